//! Split the gaps of a motion into independent transition problems: gaps of
//! different DOFs that overlap in time are coupled through the dynamics and
//! are solved together; disjoint groups are independent and run in parallel.

use super::group::solve_group;
use super::problem::Problem;
use super::report::GroupSolution;
use crate::spacetime::error::SpError;
use crate::spacetime::objective::GapDof;
use crate::spacetime::progress::ProgressEvent;
use crate::spacetime::torque::TorqueModel;
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
    problem: &Problem<'_, M>,
    gaps: Vec<GapDof>,
) -> Result<Vec<GroupSolution>, SpError> {
    let groups = group_overlapping(gaps);
    let progress = &problem.opts.progress;
    progress.report(ProgressEvent::Groups(groups.len()));
    groups
        .into_par_iter()
        .map(|dofs| {
            let solution = solve_group(problem, dofs);
            progress.report(ProgressEvent::GroupDone);
            solution
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spacetime::objective::TransitionSettings;
    use crate::spacetime::planar2::TwoLinkArm;
    use crate::spacetime::progress::Progress;
    use crate::spacetime::solve::SolveOptions;
    use crate::spacetime::transition::EndState;
    use std::sync::{Arc, Mutex};

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
        let problem = Problem {
            model: &arm,
            settings: &s,
            weights: &[1.0, 1.0],
            prior: None,
            inputs: &inputs,
            opts: &o,
            names: &[],
            ground: None,
        };
        let all = solve_all(&problem, vec![gap(1, 0.0, 0.5), gap(1, 2.0, 2.7)]).unwrap();
        assert_eq!(all.len(), 2);
        let solo = solve_all(&problem, vec![gap(1, 2.0, 2.7)]).unwrap();
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
            Err(SpError::Numerical(format!("undefined at {t}")))
        };
        let problem = Problem {
            model: &arm,
            settings: &TransitionSettings::default(),
            weights: &[1.0; 2],
            prior: None,
            inputs: &inputs,
            opts: &SolveOptions::default(),
            names: &[],
            ground: None,
        };
        let r = solve_all(&problem, vec![gap(1, 0.0, 0.5)]);
        assert!(matches!(r, Err(SpError::Numerical(_))));
    }

    #[test]
    fn progress_tells_groups_steps_iterations_and_evaluations_and_reports_are_named() {
        let arm = TwoLinkArm::default();
        let inputs = |t: f64, q: &mut [f64], v: &mut [f64], a: &mut [f64]| {
            (q[0], v[0], a[0]) = (t, 1.0, 0.0);
            (q[1], v[1], a[1]) = (0.3, 0.0, 0.0);
            Ok(())
        };
        let seen = Arc::new(Mutex::new(vec![]));
        let log = seen.clone();
        let o = SolveOptions {
            progress: Progress::new(move |e| log.lock().unwrap().push(e)),
            ..Default::default()
        };
        let names = ["shoulder".to_string(), "elbow".to_string()];
        let problem = Problem {
            model: &arm,
            settings: &TransitionSettings::default(),
            weights: &[1.0; 2],
            prior: None,
            inputs: &inputs,
            opts: &o,
            names: &names,
            ground: None,
        };
        let all = solve_all(&problem, vec![gap(1, 0.0, 0.5)]).unwrap();
        assert_eq!(all[0].report.names, vec!["elbow".to_string()]);
        let seen = seen.lock().unwrap();
        assert_eq!(seen.first(), Some(&ProgressEvent::Groups(1)));
        assert_eq!(seen.last(), Some(&ProgressEvent::GroupDone));
        assert!(seen.contains(&ProgressEvent::Step { step: 1, steps: 1 }));
        let iterations: Vec<u64> = seen
            .iter()
            .filter_map(|e| match e {
                ProgressEvent::Iteration { iteration, max } => {
                    assert_eq!(*max, 300);
                    Some(*iteration)
                }
                _ => None,
            })
            .collect();
        // one event per iteration, counted from 1, in order
        let r = &all[0].report;
        assert!(r.iterations > 0, "{r:?}");
        assert_eq!(
            iterations,
            (1..=iterations.len() as u64).collect::<Vec<_>>()
        );
        let evaluations = seen
            .iter()
            .filter(|e| **e == ProgressEvent::Evaluation)
            .count();
        assert_eq!(evaluations as u64, r.evaluations);
    }
}
