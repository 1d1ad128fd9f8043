//! How close a motion comes to a reference over a gap's frames, from forward
//! kinematics of both on the same body: L2P (the mean over frames and joints
//! of the world-position error, cm, with the worst joint and frame), and L2Q
//! and NPSS of the world joint orientations as Harvey et al. 2020 report them
//! ([`super::metrics`]). The joints are the body's reported joint points
//! (`model::topology::joint_points`), the ones `positions(m, b)` gives.

use super::error::{ScoreError, Which};
use super::metrics;
use crate::lie::Se3;
use crate::model::Model;
use crate::model::topology::joint_points;
use crate::motion::Mu;
use nalgebra::{Rotation3, UnitQuaternion};

/// Accuracy of a motion against its reference over a gap.
#[derive(Clone, Debug, PartialEq)]
pub struct Accuracy {
    /// Mean joint-position error over the gap's frames (cm).
    pub l2p: f64,
    /// The worst joint-position error (cm), its joint and its frame (an
    /// index into the frames scored).
    pub worst: f64,
    pub worst_joint: String,
    pub worst_frame: usize,
    /// Per frame, the L2 norm of the stacked world orientations' difference
    /// (unit quaternions, sign-aligned); the mean over the frames.
    pub l2q: f64,
    /// NPSS over the frames, and the reference's total power it is weighted
    /// by when gaps are pooled ([`metrics::NpssSum`]).
    pub npss: f64,
    pub npss_weight: f64,
}

/// The world poses of the body's joint points at each frame, of a motion and
/// of its reference: what the accuracy measures read (and the benchmark's
/// bone lengths).
pub struct JointPoses {
    /// The joint points' links, names, and parents among them (indices into `links`).
    pub links: Vec<usize>,
    pub names: Vec<String>,
    pub parents: Vec<Option<usize>>,
    /// `filled[i][j]`: joint `j` at frame `i`; likewise `reference`.
    pub filled: Vec<Vec<Se3>>,
    pub reference: Vec<Vec<Se3>>,
}

/// The world poses of `links` in `m` at `t`; `buf` holds every link's.
fn poses_at(
    body: &Model,
    (m, which): (&Mu, Which),
    t: f64,
    links: &[usize],
    buf: &mut Vec<Se3>,
) -> Result<Vec<Se3>, ScoreError> {
    let names = body.coordinate_names();
    let mut q = vec![0.0; names.len()];
    for (k, n) in names.iter().enumerate() {
        q[k] = m
            .sample(n, t)
            .map_err(ScoreError::motion(which))?
            .map(|s| s[0])
            .ok_or_else(|| ScoreError::Undefined {
                which,
                dof: n.clone(),
                t,
            })?;
    }
    body.forward_kinematics(&q, buf)?;
    Ok(links.iter().map(|&l| buf[l]).collect())
}

/// The joint poses of `filled` and `reference` on `body` at `times`.
pub fn joint_poses(
    body: &Model,
    filled: &Mu,
    reference: &Mu,
    times: &[f64],
) -> Result<JointPoses, ScoreError> {
    let (links, parents) = joint_points(body);
    let names = links.iter().map(|&l| body.link(l).name.clone()).collect();
    let mut buf = vec![];
    let (mut fil, mut refs) = (vec![], vec![]);
    for &t in times {
        refs.push(poses_at(
            body,
            (reference, Which::Reference),
            t,
            &links,
            &mut buf,
        )?);
        fil.push(poses_at(
            body,
            (filled, Which::Filled),
            t,
            &links,
            &mut buf,
        )?);
    }
    Ok(JointPoses {
        links,
        names,
        parents,
        filled: fil,
        reference: refs,
    })
}

fn quaternion(x: &Se3) -> UnitQuaternion<f64> {
    UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(x.r))
}

impl JointPoses {
    /// Frames held.
    pub fn frames(&self) -> usize {
        self.filled.len()
    }

    /// World orientations, `[joint][frame]`.
    fn orientations(&self, all: &[Vec<Se3>]) -> Vec<Vec<UnitQuaternion<f64>>> {
        (0..self.links.len())
            .map(|j| all.iter().map(|f| quaternion(&f[j])).collect())
            .collect()
    }

    /// L2P, its worst joint and frame, L2Q and NPSS over every frame held.
    pub fn accuracy(&self) -> Accuracy {
        let n = self.frames();
        let (fq, rq) = (
            self.orientations(&self.filled),
            self.orientations(&self.reference),
        );
        let l2q = (0..n)
            .map(|i| {
                let f: Vec<_> = fq.iter().map(|j| j[i]).collect();
                let r: Vec<_> = rq.iter().map(|j| j[i]).collect();
                metrics::l2q_frame(&f, &r)
            })
            .sum::<f64>()
            / n.max(1) as f64;
        let series = |q: &[Vec<UnitQuaternion<f64>>]| -> Vec<Vec<f64>> {
            q.iter()
                .flat_map(|j| metrics::continuous_series(j))
                .collect()
        };
        let npss = metrics::npss(&series(&fq), &series(&rq));
        let (mut sum, mut count) = (0.0, 0usize);
        let (mut worst, mut worst_joint, mut worst_frame) = (0.0, String::new(), 0);
        for (i, (f, r)) in self.filled.iter().zip(&self.reference).enumerate() {
            for j in 0..self.links.len() {
                let e = (f[j].p - r[j].p).norm() * 100.0;
                sum += e;
                if e > worst {
                    worst = e;
                    worst_joint = self.names[j].clone();
                    worst_frame = i;
                }
                count += 1;
            }
        }
        Accuracy {
            l2p: sum / count.max(1) as f64,
            worst,
            worst_joint,
            worst_frame,
            l2q,
            npss: npss.value(),
            npss_weight: npss.weight,
        }
    }
}

/// L2P, L2Q and NPSS of `filled` against `reference` on `body` at `times`.
pub fn accuracy(
    body: &Model,
    filled: &Mu,
    reference: &Mu,
    times: &[f64],
) -> Result<Accuracy, ScoreError> {
    Ok(joint_poses(body, filled, reference, times)?.accuracy())
}
