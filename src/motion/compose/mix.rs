//! The pose mixer the blending operators share: inputs split into groups
//! (a joint's Euler channels, or one scalar DOF) and mixed frame by frame
//! through a [`Mixer`].

use nalgebra::UnitQuaternion;

use super::super::dof::Dof;
use super::super::error::MotionError;
use super::super::interval::Interval;
use super::super::mu::Mu;
use super::super::rotation::{self, EulerJoint};
use super::{common_spans, err, grid, sampled};

/// A group of DOFs mixed together: a joint's three Euler channels or one scalar.
pub(super) enum Group {
    Rot(EulerJoint),
    Scalar(String),
}

impl Group {
    fn names(&self) -> Vec<&str> {
        match self {
            Group::Rot(j) => j.dofs.iter().map(String::as_str).collect(),
            Group::Scalar(n) => vec![n.as_str()],
        }
    }
}

/// The groups of `names`: Euler joints first found, then the other DOFs.
pub(super) fn groups(names: &[&str]) -> Vec<Group> {
    let joints = rotation::euler_joints(names.iter().copied());
    let in_joint = |n: &str| joints.iter().any(|j| j.dofs.iter().any(|d| d == n));
    let scalars: Vec<Group> = names
        .iter()
        .copied()
        .filter(|n| !in_joint(n))
        .map(|n| Group::Scalar(n.to_string()))
        .collect();
    joints.into_iter().map(Group::Rot).chain(scalars).collect()
}

/// How a pose-mixing operator combines its inputs at one time.
pub(super) trait Mixer {
    /// Weights of the inputs for predicting the next frame's Euler angles.
    fn weights(&self, t: f64) -> Result<Vec<f64>, MotionError>;
    /// The mixed rotation of group `g` from the inputs' rotations.
    fn rot(
        &self,
        g: usize,
        t: f64,
        qs: &[UnitQuaternion<f64>],
    ) -> Result<UnitQuaternion<f64>, MotionError>;
    /// The input whose pose the mix is at `t` exactly (a blend at w = 0 or 1),
    /// so its Euler channels are copied rather than recomputed.
    fn pick(&self, _t: f64) -> Result<Option<usize>, MotionError> {
        Ok(None)
    }
    /// The mixed value of scalar group `g` from the inputs' values.
    fn scalar(&self, g: usize, t: f64, xs: &[f64]) -> Result<f64, MotionError>;
    /// The input the mix is, exactly, wherever it is evaluated (a blend at a
    /// constant w of 0 or 1, or of inputs that are the same curves
    /// (`same`); a layer at w = 0): its curves are copied, not resampled.
    fn whole(&self, _same: bool) -> Option<usize> {
        None
    }
}

/// Mix `inputs` group by group where all of a group's DOFs are defined in
/// every input; elsewhere each DOF is `keep`'s.
pub(super) fn mix(
    inputs: &[&Mu],
    keep: &Mu,
    mixer: &dyn Mixer,
    dt: f64,
) -> Result<Mu, MotionError> {
    let names: Vec<&str> = inputs[0]
        .names()
        .filter(|n| inputs.iter().all(|m| m.get(n).is_some()))
        .collect();
    let gs = groups(&names);
    let mut mixed: indexmap::IndexMap<String, Vec<Interval>> = indexmap::IndexMap::new();
    for (gi, g) in gs.iter().enumerate() {
        let names = g.names();
        let dofs: Vec<&Dof> = inputs
            .iter()
            .flat_map(|m| names.iter().map(move |n| &m.dofs[*n]))
            .collect();
        let same = inputs[1..]
            .iter()
            .all(|m| names.iter().all(|n| m.dofs[*n] == inputs[0].dofs[*n]));
        for (s, e) in common_spans(&dofs) {
            // Copied where the mix is one input: resampled, it is not that
            // input. The grid is off the input's frames (CMU's 0.0083333 s
            // frame time over [2, 4] s gives 241 steps of 8.299 ms) and the
            // spline through the resampled values has its own ends, so
            // `blend(c, c, 0.5)` on CMU 01_01 clipped to [2, 4] s moved 74 of
            // 96 DOFs at t = 1.1 s, by up to 5.5e-4 rad (measured).
            if let Some(k) = mixer.whole(same) {
                // the weights are still checked at every frame (a weight
                // function leaving [0, 1] is an error even here)
                for &t in &grid(s, e, dt) {
                    mixer.weights(t)?;
                }
                for n in &names {
                    let part = inputs[k].dofs[*n].window(s, e);
                    mixed
                        .entry(n.to_string())
                        .or_default()
                        .extend(part.intervals);
                }
                continue;
            }
            let times = grid(s, e, dt);
            // values[input][channel][frame]
            let mut vals = vec![vec![vec![]; names.len()]; inputs.len()];
            for (k, m) in inputs.iter().enumerate() {
                for (c, n) in names.iter().enumerate() {
                    let v = m.dofs[*n].sample_values_sorted(n, &times)?;
                    vals[k][c] = v
                        .into_iter()
                        .zip(&times)
                        .map(|(x, &t)| {
                            x.ok_or(MotionError::Undefined {
                                dof: n.to_string(),
                                t,
                            })
                        })
                        .collect::<Result<_, _>>()?;
                }
            }
            let mut out = vec![Vec::with_capacity(times.len()); names.len()];
            match g {
                Group::Scalar(_) => {
                    for (f, &t) in times.iter().enumerate() {
                        let xs: Vec<f64> = vals.iter().map(|v| v[0][f]).collect();
                        out[0].push(mixer.scalar(gi, t, &xs)?);
                    }
                }
                Group::Rot(j) => {
                    let mut prev: Option<[f64; 3]> = None;
                    let mut prev_q: Vec<UnitQuaternion<f64>> = vec![];
                    for (f, &t) in times.iter().enumerate() {
                        let eul: Vec<[f64; 3]> =
                            vals.iter().map(|v| [v[0][f], v[1][f], v[2][f]]).collect();
                        // each input's quaternion sign-aligned along time (the
                        // first frame's to the first input's), so mixes of
                        // them are continuous in time
                        let q0 = rotation::from_euler(j.axes, eul[0]);
                        let qs: Vec<_> = eul
                            .iter()
                            .enumerate()
                            .map(|(k, e)| {
                                let q = rotation::from_euler(j.axes, *e);
                                rotation::align_sign(prev_q.get(k).unwrap_or(&q0), &q)
                            })
                            .collect();
                        prev_q = qs.clone();
                        if let Some(k) = mixer.pick(t)? {
                            for c in 0..3 {
                                out[c].push(eul[k][c]);
                            }
                            prev = Some(eul[k]);
                            continue;
                        }
                        let q = mixer.rot(gi, t, &qs)?;
                        let w = mixer.weights(t)?;
                        let near: [f64; 3] = std::array::from_fn(|c| match prev {
                            None => eul.iter().zip(&w).map(|(e, w)| w * e[c]).sum(),
                            Some(p) => {
                                p[c] + vals
                                    .iter()
                                    .zip(&w)
                                    .map(|(v, w)| w * (v[c][f] - v[c][f - 1]))
                                    .sum::<f64>()
                            }
                        });
                        let e = rotation::to_euler_near(j.axes, &q, near);
                        for c in 0..3 {
                            out[c].push(e[c]);
                        }
                        prev = Some(e);
                    }
                }
            }
            for (c, n) in names.iter().enumerate() {
                let i = sampled(&times, std::mem::take(&mut out[c]))?;
                mixed.entry(n.to_string()).or_default().push(i);
            }
        }
    }
    let mut result = Mu::new();
    for (name, dof) in &keep.dofs {
        let out = match mixed.get(name) {
            Some(ivs) => {
                let region = Dof {
                    intervals: ivs
                        .iter()
                        .map(|i| Interval::constant(0.0, i.start, i.stop))
                        .collect::<Result<_, _>>()?,
                };
                dof.minus(&region).plus(&Dof::new(ivs.clone())?)
            }
            None => dof.clone(),
        };
        result.insert(name.clone(), out);
    }
    Ok(result)
}
/// The values of every group of `names` in `m` at `t` (Euler triples or one value).
pub(super) fn group_values(
    m: &Mu,
    gs: &[Group],
    t: f64,
    op: &'static str,
) -> Result<Vec<Vec<f64>>, MotionError> {
    gs.iter()
        .map(|g| {
            g.names()
                .iter()
                .map(|n| {
                    m.get(n)
                        .map(|d| d.sample(n, t))
                        .transpose()?
                        .flatten()
                        .map(|v| v[0])
                        .ok_or_else(|| {
                            err(
                                op,
                                format!("the reference pose has no value for `{n}` at t = {t}"),
                            )
                        })
                })
                .collect()
        })
        .collect()
}

/// The Euler axes of each rotation group (`None` for scalars).
pub(super) fn group_axes(gs: &[Group]) -> Vec<Option<[usize; 3]>> {
    gs.iter()
        .map(|g| match g {
            Group::Rot(j) => Some(j.axes),
            Group::Scalar(_) => None,
        })
        .collect()
}
