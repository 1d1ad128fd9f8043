//! Split the gaps of a motion into independent transition problems: gaps of
//! different DOFs that overlap in time are coupled through the dynamics and
//! are solved together; disjoint groups are independent and run in parallel.

use super::error::SpError;
use super::objective::{GapDof, Inputs, Objective, TransitionSettings};
use super::progress::ProgressEvent;
use super::solve::{GroupSolution, SolveOptions, solve_group};
use super::torque::TorqueModel;
use rayon::prelude::*;

/// Groups of gaps whose open spans overlap (transitively), ordered by start time.
/// Gaps that only touch at a point are independent.
pub fn group_overlapping(mut gaps: Vec<GapDof>) -> Vec<Vec<GapDof>> {
    gaps.sort_by(|a, b| a.t0.total_cmp(&b.t0).then(a.coord.cmp(&b.coord)));
    let mut groups: Vec<(f64, Vec<GapDof>)> = vec![];
    for g in gaps {
        match groups.last_mut() {
            Some((end, members)) if g.t0 < *end => {
                *end = end.max(g.t1);
                members.push(g);
            }
            _ => groups.push((g.t1, vec![g])),
        }
    }
    groups.into_iter().map(|(_, m)| m).collect()
}

/// Solve every group (in parallel); results in the order of [`group_overlapping`].
pub fn solve_all<M: TorqueModel>(
    model: &M,
    gaps: Vec<GapDof>,
    settings: &TransitionSettings,
    weights: &[f64],
    inputs: &Inputs<'_>,
    opts: &SolveOptions,
) -> Result<Vec<GroupSolution>, SpError> {
    let groups = group_overlapping(gaps);
    opts.progress.report(ProgressEvent::Groups(groups.len()));
    groups
        .into_par_iter()
        .map(|dofs| {
            let obj = Objective::new(model, dofs, settings, weights.to_vec(), inputs)?;
            let solution = solve_group(&obj, opts);
            opts.progress.report(ProgressEvent::GroupDone);
            solution
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spacetime::planar2::TwoLinkArm;
    use crate::spacetime::transition::EndState;

    fn gap(coord: usize, t0: f64, t1: f64) -> GapDof {
        GapDof {
            coord,
            t0,
            t1,
            start: EndState::default(),
            end: EndState {
                q: 1.0,
                v: 0.0,
                a: 0.0,
            },
        }
    }

    #[test]
    fn overlapping_gaps_group_and_touching_ones_do_not() {
        let g = group_overlapping(vec![
            gap(1, 2.0, 3.0),
            gap(0, 0.0, 1.0),
            gap(1, 0.5, 1.5),
            gap(0, 1.5, 2.0),
        ]);
        let spans: Vec<Vec<(usize, f64)>> = g
            .iter()
            .map(|m| m.iter().map(|d| (d.coord, d.t0)).collect())
            .collect();
        assert_eq!(
            spans,
            vec![vec![(0, 0.0), (1, 0.5)], vec![(0, 1.5)], vec![(1, 2.0)]]
        );
    }

    #[test]
    fn disjoint_groups_solve_independently_and_equal_solo_solves() {
        let arm = TwoLinkArm::default();
        let inputs = |t: f64, q: &mut [f64], v: &mut [f64], a: &mut [f64]| {
            q[0] = t;
            v[0] = 1.0;
            a[0] = 0.0;
            q[1] = 0.3;
            v[1] = 0.0;
            a[1] = 0.0;
            Ok(())
        };
        let s = TransitionSettings::default();
        let o = SolveOptions::default();
        let all = solve_all(
            &arm,
            vec![gap(1, 0.0, 0.5), gap(1, 2.0, 2.7)],
            &s,
            &[1.0, 1.0],
            &inputs,
            &o,
        )
        .unwrap();
        assert_eq!(all.len(), 2);
        let solo = solve_all(&arm, vec![gap(1, 2.0, 2.7)], &s, &[1.0, 1.0], &inputs, &o).unwrap();
        assert_eq!(all[1].report.energy, solo[0].report.energy);
        assert!(
            all.iter()
                .all(|g| g.report.energy <= g.report.initial_energy)
        );
    }

    #[test]
    fn input_errors_propagate() {
        let arm = TwoLinkArm::default();
        let inputs = |t: f64, _: &mut [f64], _: &mut [f64], _: &mut [f64]| {
            Err(SpError::Evaluation(format!("undefined at {t}")))
        };
        let r = solve_all(
            &arm,
            vec![gap(1, 0.0, 0.5)],
            &TransitionSettings::default(),
            &[1.0; 2],
            &inputs,
            &SolveOptions::default(),
        );
        assert!(matches!(r, Err(SpError::Evaluation(_))));
    }
}
