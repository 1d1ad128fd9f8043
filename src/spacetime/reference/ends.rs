//! The aligned example against the motion at the gap's ends: its Euler
//! channels put on the motion's own branch, and which of them are close
//! enough there to follow (`lay.rs` lays the ones that are).

use super::lay::{Lay, MAX_END_OFFSET, PAD};
use super::pose::PoseMetric;
use super::{MAX_END_DIFFERENCE, gap_coords};
use crate::motion::rotation::{euler_joints, from_euler, to_euler_near};
use crate::spacetime::objective::GapDof;

impl Lay<'_> {
    /// Each Euler joint's example angles re-expressed, sample by sample, as
    /// the Euler triple nearest the previous one, from the motion's own
    /// angles at the gap's start: the same rotations, on the branch the
    /// motion is on. A joint near gimbal lock in its channels' chart (a
    /// z-up skeleton's spine) otherwise differs from the motion by ±2 rad
    /// in two channels while its rotation is 0.05 rad away, and the
    /// per-channel blend to the end states would swing through poses
    /// neither side has.
    pub(super) fn on_the_motions_branch(
        &self,
        series: &mut [(usize, f64, Vec<f64>)],
        gaps: &[GapDof],
    ) {
        let names = series.iter().map(|(c, _, _)| self.names[*c].as_str());
        for joint in euler_joints(names) {
            let at: Option<Vec<usize>> = joint
                .dofs
                .iter()
                .map(|d| series.iter().position(|(c, _, _)| self.names[*c] == *d))
                .collect();
            let Some(at) = at else { continue };
            let (from, n) = (series[at[0]].1, series[at[0]].2.len());
            if at
                .iter()
                .any(|&i| series[i].1 != from || series[i].2.len() != n)
                || n <= PAD
            {
                continue;
            }
            let start: Option<Vec<f64>> = at
                .iter()
                .map(|&i| {
                    gaps.iter()
                        .find(|g| g.coord == series[i].0)
                        .map(|g| g.start.q)
                })
                .collect();
            let Some(start) = start else { continue };
            let near0 = [start[0], start[1], start[2]];
            let mut near = near0;
            for k in (PAD..n).chain((0..PAD).rev()) {
                if k + 1 == PAD {
                    near = near0;
                }
                let e = [series[at[0]].2[k], series[at[1]].2[k], series[at[2]].2[k]];
                near = to_euler_near(joint.axes, &from_euler(joint.axes, e), near);
                for (j, &i) in at.iter().enumerate() {
                    series[i].2[k] = near[j];
                }
            }
        }
    }

    /// Per gap of `gaps`, whether its aligned example (`ends`: per coordinate,
    /// value and derivatives at its gap's start and end) is close enough to
    /// the motion at both ends to follow: a joint's angles as one rotation
    /// within [`MAX_END_DIFFERENCE`] per channel (`pose.rs`), and each
    /// channel, on the motion's own branch (`on_the_motions_branch`),
    /// within it too, as the blend below is per channel (a joint near
    /// gimbal lock in its chart is close as a rotation with two channels
    /// ±2 rad off, which no per-channel ramp blends); translations each
    /// within [`MAX_END_OFFSET`].
    pub(super) fn close_at_ends(
        &self,
        gaps: &[GapDof],
        ends: &[(usize, [f64; 3], [f64; 3])],
    ) -> Vec<bool> {
        let coords = gap_coords(gaps);
        let metric = PoseMetric::new(self.names, &coords, self.rotation, self.joints);
        let at = |c: usize| ends.iter().find(|e| e.0 == c);
        let gap = |c: usize| gaps.iter().find(|g| g.coord == c);
        let mine = |end: usize| {
            metric.pose(|i| gap(coords[i]).map_or(f64::NAN, |g| [g.start.q, g.end.q][end]))
        };
        let theirs = |end: usize| {
            metric.pose(|i| at(coords[i]).map_or(f64::NAN, |(_, a, b)| [a[0], b[0]][end]))
        };
        let angles: Vec<Vec<f64>> = (0..2)
            .map(|e| metric.angles(&theirs(e), &mine(e)))
            .collect();
        gaps.iter()
            .map(|g| {
                at(g.coord).is_some_and(|(_, a, b)| {
                    // raw differences: the laid curve meets the motion's own values
                    let (d0, d1) = (g.start.q - a[0], g.end.q - b[0]);
                    if (self.rotation)(g.coord) {
                        let i = coords.binary_search(&g.coord).expect("a gap's coordinate");
                        metric.close(i, &angles, MAX_END_DIFFERENCE)
                            && d0.abs().max(d1.abs()) <= MAX_END_DIFFERENCE
                    } else {
                        d0.abs() <= MAX_END_OFFSET && d1.abs() <= MAX_END_OFFSET
                    }
                })
            })
            .collect()
    }
}
