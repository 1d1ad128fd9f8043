//! A gap's plan as the user states it (`contact: [{point, from, to, at}, …]`,
//! or a capture's own contacts): the stances are given, not planned. A
//! stance without `at` is anchored where the motion has its point at the
//! stance's recorded end (the gap's edge it touches); one wholly inside a gap
//! needs `at`, since the motion says nothing there.

use super::plan::{GapPlan, PointPlan, Source, Stance};
use crate::lie::Se3;
use crate::model::Model;
use crate::spacetime::error::{SpError, invalid_option};
use nalgebra::Vector3;

/// One stated stance: `point` (a link's name) planted over [from, to] s,
/// at `at` (world, m) or where the motion puts it.
#[derive(Clone, Debug, PartialEq)]
pub struct GivenStance {
    pub point: String,
    pub from: f64,
    pub to: f64,
    pub at: Option<Vector3<f64>>,
}

impl GivenStance {
    /// Why the stance cannot be planned, if it cannot: times not finite or
    /// `to` before `from`, a position not finite (an error of `contact:`).
    pub fn check(&self) -> Result<(), SpError> {
        if !(self.from.is_finite() && self.to.is_finite()) || self.to < self.from {
            return Err(invalid_option(
                "contact",
                format!(
                    "{}: from {} to {}: needs finite times with from ≤ to",
                    self.point, self.from, self.to
                ),
            ));
        }
        if self.at.is_some_and(|p| !p.iter().all(|v| v.is_finite())) {
            return Err(invalid_option(
                "contact",
                format!("{}: at: needs a finite [x, y, z]", self.point),
            ));
        }
        Ok(())
    }
}

/// The plan of gap [t0, t1] from `given`: per point (`points`: (link, the
/// height it stands at)), the given stances that meet the gap, cut to it.
pub fn plan_given(
    model: &Model,
    given: &[GivenStance],
    points: &[(usize, f64)],
    (t0, t1): (f64, f64),
    configuration: &dyn Fn(f64) -> Result<Vec<f64>, SpError>,
) -> Result<GapPlan, SpError> {
    let mut poses: Vec<Se3> = vec![];
    let mut at = |link: usize, t: f64| -> Result<Vector3<f64>, SpError> {
        let q = configuration(t)?;
        model
            .forward_kinematics(&q, &mut poses)
            .map_err(SpError::Kinematics)?;
        Ok(poses[link].p)
    };
    let mut out = vec![];
    for &(link, stand) in points {
        let name = &model.link(link).name;
        let mut stances = vec![];
        for g in given
            .iter()
            .filter(|g| &g.point == name && g.to >= t0 && g.from <= t1)
        {
            let anchor = match g.at {
                Some(p) => p,
                None if g.from <= t0 => at(link, t0)?,
                None if g.to >= t1 => at(link, t1)?,
                None => {
                    return Err(SpError::Invalid(format!(
                        "contact: {name} from {} to {} s lies inside the gap [{t0}, {t1}] s, where the motion has no pose: give at: [x, y, z]",
                        g.from, g.to
                    )));
                }
            };
            stances.push(Stance::planted(g.from.max(t0), g.to.min(t1), anchor).by(Source::Given));
        }
        stances.sort_by(|a, b| a.t0.total_cmp(&b.t0));
        out.push(PointPlan {
            name: name.clone(),
            link,
            stand,
            stances,
        });
    }
    Ok(GapPlan {
        t0,
        t1,
        points: out,
    })
}
