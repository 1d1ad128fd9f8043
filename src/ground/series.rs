//! `ground_forces`' numbers on a frame grid, and the motion that holds them:
//! one DOF per number, `POINT.Fx/Fy/Fz` per contact point, then
//! `residual.Fx/Fy/Fz`, `residual.Mx/My/Mz` and `residual.percent_bw`. The
//! language's `ground_forces` is that motion; a file that carries the forces
//! (glTF's `extras`) writes a [`ForceSeries`] and gives one back, so what is
//! loaded is the motion `ground_forces` gave, number for number.

use super::{GroundError, invalid};
use crate::motion::{Curve, Dof, Interval, Mu, sample_period};
use nalgebra::Vector3;

/// The residual's DOFs, in the order [`ForceSeries::to_motion`] writes them.
const RESIDUAL: [&str; 7] = [
    "residual.Fx",
    "residual.Fy",
    "residual.Fz",
    "residual.Mx",
    "residual.My",
    "residual.Mz",
    "residual.percent_bw",
];

const AXES: [&str; 3] = ["x", "y", "z"];

/// Per frame, the contact force at each point and what no contact force
/// supplies (world axes: N, and N·m about the centre of mass).
#[derive(Clone, Debug, PartialEq)]
pub struct ForceSeries {
    pub times: Vec<f64>,
    /// Seconds between frames.
    pub frame_time: f64,
    /// The contact points' link names.
    pub points: Vec<String>,
    /// `forces[k][j]`: the force on the body at point `j`, frame `k` (N).
    pub forces: Vec<Vec<Vector3<f64>>>,
    pub residual_force: Vec<Vector3<f64>>,
    pub residual_moment: Vec<Vector3<f64>>,
    /// The residual force as % of body weight.
    pub percent_bw: Vec<f64>,
}

impl ForceSeries {
    /// As a motion on the frames' clock (see the module doc): sampled
    /// curves, so `plot`, `save(…, "x.csv")` and the algebra take it, and a
    /// sample is read back exactly at its frame's time.
    pub fn to_motion(&self) -> Result<Mu, GroundError> {
        let n = self.times.len();
        if n == 0 {
            return Err(invalid("no frames of forces to make a motion of"));
        }
        let t0 = self.times[0];
        let stop = if n > 1 {
            self.times[n - 1]
        } else {
            t0 + self.frame_time
        };
        let mut mu = Mu::new();
        let mut add = |name: String, vals: Vec<f64>| -> Result<(), GroundError> {
            let curve = if n > 1 {
                Curve::samples(t0, self.frame_time, vals)?
            } else {
                Curve::constant(vals[0])?
            };
            mu.insert(name, Dof::new(vec![Interval::curve(curve, t0, stop)?])?);
            Ok(())
        };
        for (j, p) in self.points.iter().enumerate() {
            for (c, a) in AXES.iter().enumerate() {
                add(
                    format!("{p}.F{a}"),
                    self.forces.iter().map(|fr| fr[j][c]).collect(),
                )?;
            }
        }
        let [fx, fy, fz, mx, my, mz, pct] = RESIDUAL.map(String::from);
        for (c, name) in [fx, fy, fz].into_iter().enumerate() {
            add(name, self.residual_force.iter().map(|f| f[c]).collect())?;
        }
        for (c, name) in [mx, my, mz].into_iter().enumerate() {
            add(name, self.residual_moment.iter().map(|m| m[c]).collect())?;
        }
        add(pct, self.percent_bw.clone())?;
        Ok(mu)
    }

    /// The numbers of a motion of [`Self::to_motion`]'s form (what the
    /// language's `ground_forces` returns) at `times`, `frame_time` apart.
    /// `Err` naming what is amiss: a DOF of another form, a point without
    /// its three components, the residual's DOFs missing, samples
    /// `frame_time` does not space, or a DOF undefined at one of the times.
    pub fn from_motion(m: &Mu, times: &[f64], frame_time: f64) -> Result<ForceSeries, GroundError> {
        let points = point_names(m)?;
        // forces between their frames are a spline's, not a solve's: refuse them
        if let Some(dt) = sample_period(m)
            && (dt - frame_time).abs() > 1e-9 * frame_time
        {
            return Err(invalid(format!(
                "the forces are sampled {} Hz, the frames to save {} Hz: compute them at the rate saved",
                1.0 / dt,
                1.0 / frame_time
            )));
        }
        let column = |name: &str| -> Result<Vec<f64>, GroundError> {
            let dof = m.get(name).ok_or_else(|| {
                invalid(format!(
                    "the forces have no DOF `{name}`: pass what ground_forces(m, body) returns"
                ))
            })?;
            let values = dof.sample_values_sorted(name, times)?;
            values
                .iter()
                .zip(times)
                .map(|(v, t)| {
                    v.ok_or_else(|| {
                        invalid(format!(
                            "the forces' `{name}` is not defined at {t} s: they must cover every frame of the motion they go with"
                        ))
                    })
                })
                .collect()
        };
        let vectors = |names: [String; 3]| -> Result<Vec<Vector3<f64>>, GroundError> {
            let [x, y, z] = [column(&names[0])?, column(&names[1])?, column(&names[2])?];
            Ok((0..times.len())
                .map(|k| Vector3::new(x[k], y[k], z[k]))
                .collect())
        };
        let mut per_point = Vec::with_capacity(points.len());
        for p in &points {
            per_point.push(vectors(AXES.map(|a| format!("{p}.F{a}")))?);
        }
        let forces = (0..times.len())
            .map(|k| per_point.iter().map(|f| f[k]).collect())
            .collect();
        let [fx, fy, fz, mx, my, mz, pct] = RESIDUAL.map(String::from);
        Ok(ForceSeries {
            times: times.to_vec(),
            frame_time,
            points,
            forces,
            residual_force: vectors([fx, fy, fz])?,
            residual_moment: vectors([mx, my, mz])?,
            percent_bw: column(&pct)?,
        })
    }
}

/// The contact points a forces motion names, in its order; `Err` on a DOF
/// that is neither a point's force component nor the residual's.
fn point_names(m: &Mu) -> Result<Vec<String>, GroundError> {
    let mut points: Vec<String> = vec![];
    for name in m.names() {
        if RESIDUAL.contains(&name) {
            continue;
        }
        let point = [".Fx", ".Fy", ".Fz"]
            .iter()
            .find_map(|s| name.strip_suffix(s))
            .filter(|p| !p.is_empty() && *p != "residual");
        let Some(point) = point else {
            return Err(invalid(format!(
                "the forces have a DOF `{name}`, which is no contact force: pass what ground_forces(m, body) returns \
                 (`POINT.Fx/Fy/Fz` and `residual.*`)"
            )));
        };
        if !points.iter().any(|p| p == point) {
            points.push(point.to_string());
        }
    }
    if points.is_empty() {
        return Err(invalid(
            "the forces name no contact point (`POINT.Fx/Fy/Fz`): pass what ground_forces(m, body) returns",
        ));
    }
    Ok(points)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn series(frames: usize) -> ForceSeries {
        let v = |k: usize, s: f64| Vector3::new(s * k as f64, -0.5 * s, 1.0 / (k as f64 + s));
        ForceSeries {
            times: (0..frames).map(|k| 0.5 + k as f64 / 30.0).collect(),
            frame_time: 1.0 / 30.0,
            points: vec!["Left.Foot".into(), "RightToe".into()],
            forces: (0..frames).map(|k| vec![v(k, 1.0), v(k, 3.0)]).collect(),
            residual_force: (0..frames).map(|k| v(k, 7.0)).collect(),
            residual_moment: (0..frames).map(|k| v(k, 0.1)).collect(),
            percent_bw: (0..frames).map(|k| 0.3 * k as f64).collect(),
        }
    }

    #[test]
    fn a_series_comes_back_from_its_motion_exactly() {
        for frames in [1, 2, 3, 40] {
            let s = series(frames);
            let m = s.to_motion().unwrap();
            assert_eq!(m.len(), 2 * 3 + 7);
            let back = ForceSeries::from_motion(&m, &s.times, s.frame_time).unwrap();
            assert_eq!(back, s, "{frames} frames");
        }
    }

    #[test]
    fn a_motion_of_another_form_is_an_error_naming_what_is_amiss() {
        let m = series(5).to_motion().unwrap();
        let times = series(5).times;
        let mut other = m.clone();
        other.insert("Hips.Xrotation", m.get("residual.Fx").unwrap().clone());
        let e = ForceSeries::from_motion(&other, &times, 1.0 / 30.0).unwrap_err();
        assert!(e.to_string().contains("`Hips.Xrotation`"), "{e}");
        let mut lacking = Mu::new();
        for n in m.names().filter(|n| *n != "RightToe.Fy") {
            lacking.insert(n, m.get(n).unwrap().clone());
        }
        let e = ForceSeries::from_motion(&lacking, &times, 1.0 / 30.0).unwrap_err();
        assert!(e.to_string().contains("`RightToe.Fy`"), "{e}");
        let e = ForceSeries::from_motion(&m, &times, 1.0 / 60.0).unwrap_err();
        assert!(e.to_string().contains("sampled 30"), "{e}");
        let late: Vec<f64> = times.iter().map(|t| t + 1.0).collect();
        let e = ForceSeries::from_motion(&m, &late, 1.0 / 30.0).unwrap_err();
        assert!(e.to_string().contains("not defined"), "{e}");
        let e = ForceSeries::from_motion(&Mu::new(), &times, 1.0 / 30.0).unwrap_err();
        assert!(e.to_string().contains("no contact point"), "{e}");
    }
}
