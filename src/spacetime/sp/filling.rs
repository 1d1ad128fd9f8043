//! The motion being filled: SP's stages read its end states and sampled
//! poses and write their curves back through one [`Filling`], which also
//! carries the contact plan (when one is made) and the report they add to.

use super::checks::motion_err;
use super::report::{SpReport, Undefined};
use crate::model::{Model, RootCoords};
use crate::motion::{Curve, Dof, HermiteCurve, Interval, JointSampler, Mu};
use crate::spacetime::contact::ContactPlan;
use crate::spacetime::error::{SpError, invalid};
use crate::spacetime::objective::GapDof;
use crate::spacetime::transition::EndState;
use nalgebra::Vector3;

/// The motion as the stages fill it, the body it drives and the report so far.
pub struct Filling<'a> {
    /// The motion: the input, with each stage's curves written into its gaps.
    pub motion: Mu,
    /// The input as given: its defined part is what was recorded (the
    /// contact plan's floor is read from it).
    pub recorded: &'a Mu,
    pub model: &'a Model,
    /// The body's coordinate names (the order of every state and gap's `coord`).
    pub names: &'a [String],
    pub gravity: Vector3<f64>,
    /// The root's coordinates as the motion moves them
    /// ([`crate::ground::moving_root`]).
    pub root: RootCoords,
    /// Where and when contact points stand in each gap (`contact:`); `None`
    /// without a plan. The report lists it.
    pub contacts: Option<ContactPlan>,
    pub report: SpReport,
}

impl<'a> Filling<'a> {
    /// The motion `m` to be filled on `model` under `gravity`; the report
    /// starts with the DOFs undefined at the motion's start or end, which no
    /// stage fills.
    pub fn new(m: &'a Mu, model: &'a Model, gravity: Vector3<f64>) -> Self {
        Filling {
            report: SpReport {
                undefined: undefined_ends(m),
                ..Default::default()
            },
            motion: m.clone(),
            recorded: m,
            model,
            names: model.coordinate_names(),
            gravity,
            root: crate::ground::moving_root(model, &gravity, m),
            contacts: None,
        }
    }

    /// [q, q̇, q̈] of DOF `name` at a gap end (the neighbouring interval's value).
    pub fn end_state(&self, name: &str, t: f64) -> Result<EndState, SpError> {
        match self.motion.sample(name, t).map_err(motion_err)? {
            Some([q, v, a]) => Ok(EndState { q, v, a }),
            None => Err(SpError::Undefined {
                dof: name.to_string(),
                t,
                need: crate::spacetime::Need::GapEnd,
            }),
        }
    }

    /// The body's coordinates read from the motion as it is now.
    pub fn sampler(&self) -> JointSampler<'_> {
        JointSampler::new(&self.motion, self.names)
    }

    /// Every interior gap of every body coordinate, with its end states.
    pub fn gaps(&self) -> Result<Vec<GapDof>, SpError> {
        let mut gaps = vec![];
        for (c, name) in self.names.iter().enumerate() {
            let Some(dof) = self.motion.get(name) else {
                continue;
            };
            for (t0, t1) in dof.gaps() {
                gaps.push(GapDof {
                    coord: c,
                    t0,
                    t1,
                    start: self.end_state(name, t0)?,
                    end: self.end_state(name, t1)?,
                });
            }
        }
        Ok(gaps)
    }

    /// DOF `name` of the motion, to change in place.
    pub fn dof_mut(&mut self, name: &str) -> Result<&mut Dof, SpError> {
        self.motion
            .dofs
            .get_mut(name)
            .ok_or_else(|| invalid(format!("SP lost the DOF {name} while filling its gap")))
    }

    /// Writes `curve` into DOF `name`'s gap [t0, t1].
    pub fn write(&mut self, name: &str, curve: Curve, t0: f64, t1: f64) -> Result<(), SpError> {
        let iv = Interval::curve(curve, t0, t1).map_err(motion_err)?;
        let dof = self.dof_mut(name)?;
        *dof = dof.plus(&Dof::from(iv));
        Ok(())
    }

    /// The filled motion and the report (with the contact plan).
    pub fn finish(self) -> (Mu, SpReport) {
        let mut report = self.report;
        report.contacts = self.contacts;
        (self.motion, report)
    }
}

/// The cubic Hermite curve between two end states.
pub(super) fn hermite_curve(
    t0: f64,
    t1: f64,
    a: &EndState,
    b: &EndState,
) -> Result<Curve, SpError> {
    Ok(Curve::Hermite(
        HermiteCurve::new(t0, a.q, a.v, t1, b.q, b.v).map_err(motion_err)?,
    ))
}

/// DOFs undefined at the start or end of the motion's span.
pub(super) fn undefined_ends(m: &Mu) -> Vec<Undefined> {
    let Some((s, e)) = m.span() else {
        return vec![];
    };
    let mut out = vec![];
    for (name, d) in &m.dofs {
        match d.span() {
            None => out.push(Undefined {
                dof: name.clone(),
                start: s,
                stop: e,
            }),
            Some((a, b)) => {
                if a - s > crate::motion::time_tol(s) {
                    out.push(Undefined {
                        dof: name.clone(),
                        start: s,
                        stop: a,
                    });
                }
                if e - b > crate::motion::time_tol(b) {
                    out.push(Undefined {
                        dof: name.clone(),
                        start: b,
                        stop: e,
                    });
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::fixture::{Y_UP, body, motion};
    use super::*;

    #[test]
    fn gaps_have_their_end_states_and_ends_are_not_gaps() {
        let model = body();
        let mut m = motion(&model, &[3], (0.8, 1.2));
        // the knee starts late: undefined at the start, not a gap
        let knee = Dof::from(Interval::constant(0.0, 0.0, 0.5).unwrap());
        let trimmed = m.get("knee").unwrap().minus(&knee);
        m.insert("knee", trimmed);
        let f = Filling::new(&m, &model, Y_UP);
        let g = f.gaps().unwrap();
        assert_eq!(g.len(), 1);
        assert_eq!((g[0].coord, g[0].t0, g[0].t1), (3, 0.8, 1.2));
        let hip = |t: f64| m.sample("hip", t).unwrap().unwrap();
        assert_eq!([g[0].start.q, g[0].start.v, g[0].start.a], hip(0.8));
        assert_eq!([g[0].end.q, g[0].end.v, g[0].end.a], hip(1.2));
        let u = &f.report.undefined;
        assert_eq!(u.len(), 1);
        assert_eq!(
            (u[0].dof.as_str(), u[0].start, u[0].stop),
            ("knee", 0.0, 0.5)
        );
        assert!(f.end_state("hip", 1.0).is_err());
    }

    #[test]
    fn a_curve_written_back_fills_the_gap() {
        let model = body();
        let m = motion(&model, &[3], (0.8, 1.2));
        let mut f = Filling::new(&m, &model, Y_UP);
        let g = f.gaps().unwrap().remove(0);
        assert!(f.sampler().positions(1.0).unwrap()[3].is_nan());
        let c = hermite_curve(g.t0, g.t1, &g.start, &g.end).unwrap();
        f.write("hip", c, g.t0, g.t1).unwrap();
        assert!(f.gaps().unwrap().is_empty());
        assert!(f.sampler().positions(1.0).unwrap()[3].is_finite());
        assert!(f.dof_mut("nope").is_err());
        let (filled, report) = f.finish();
        assert!(filled.get("hip").unwrap().gaps().is_empty());
        assert!(report.undefined.is_empty());
    }
}
