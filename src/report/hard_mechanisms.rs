//! Hard cases of the spline-joint mechanisms (issue #4): the paper's explicit
//! Euler at 100 ms on beads sliding round closed wires of a spinning frame,
//! and an n-DOF spline joint driven past the end of its parameter range.

use super::hard_case::{HardCase, case};
use crate::cancel::CancelToken;
use crate::dynamics::{Integrator, LimitPenalty, Scene, State, simulate};
use crate::lie::{Se3, exp_so3};
use crate::model::joints::{EulerOrder, FrameGrid, Revolute, SplineLoopJoint, SplineSurfaceJoint};
use crate::model::{Inertia, Model};
use crate::report::error::{ReportError, ZERO_AXIS};
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::TAU;
use std::sync::Arc;

/// Control frames round a flower of `petals` petals in the x–y plane, x along the wire.
fn flower(petals: f64, r: f64) -> Vec<Se3> {
    let p = |s: f64| {
        let rr = r * (1.0 + 0.3 * (petals * s).cos());
        Vector3::new(rr * s.sin(), -rr * s.cos(), 0.0)
    };
    (0..48)
        .map(|i| {
            let s = TAU * i as f64 / 48.0;
            let t = p(s + 1e-3) - p(s - 1e-3);
            Se3::new(exp_so3(&Vector3::new(0.0, 0.0, t.y.atan2(t.x))), p(s))
        })
        .collect()
}

/// Three beads on flower wires of a frame spinning at 1.5 rad/s (driven), light
/// viscous friction, explicit Euler at 100 ms for 30 s: speeds stay bounded.
pub fn beads_euler_100ms() -> HardCase {
    let name = "beads on spinning closed spline wires, explicit Euler at 100 ms (30 s)";
    let r = (|| -> Result<HardCase, ReportError> {
        let mut m = Model::new("beads");
        let frame = Inertia::from_com(
            2.0,
            Vector3::zeros(),
            Matrix3::from_diagonal(&Vector3::new(0.3, 0.5, 0.3)),
        )?;
        m.add_link(
            "wire",
            None,
            "wire",
            Arc::new(Revolute::new(Vector3::y()).ok_or(ZERO_AXIS)?),
            Se3::identity(),
            frame,
        )?;
        for (k, (petals, r, z)) in [(4.0, 0.5, -0.2), (5.0, 0.6, 0.0), (6.0, 0.5, 0.2)]
            .into_iter()
            .enumerate()
        {
            let j = SplineLoopJoint::new(flower(petals, r), TAU)?;
            let bead = Inertia::from_com(0.05, Vector3::zeros(), Matrix3::identity() * 2e-6)?;
            let n = format!("bead{k}");
            m.add_link(
                &n,
                Some(0),
                &n,
                Arc::new(j),
                Se3::from_translation(Vector3::new(0.0, 0.0, z)),
                bead,
            )?;
        }
        let scene = Scene::new(Arc::new(m))
            .with_gravity(Vector3::new(0.0, -9.81, 0.0))
            .and_then(|s| s.with_damping(&[0.1]))
            .and_then(|s| s.with_driven(0, 1.5))?;
        let mut init = State {
            q: vec![0.0, 0.3, 1.0, -0.5],
            v: vec![0.0; 4],
        };
        scene.drive_state(&mut init.v);
        let tr = simulate(
            &scene,
            30.0,
            0.1,
            Integrator::Euler,
            &init,
            &CancelToken::new(),
            &mut |_| {},
        )?;
        let fastest =
            tr.v.iter()
                .flat_map(|v| v[1..].iter().map(|x| x.abs()))
                .fold(0.0, f64::max);
        let spin_err = (tr.q.last().ok_or(ReportError::Empty {
            what: "the bead's trajectory",
        })?[0]
            - 45.0)
            .abs();
        Ok(case(
            name,
            "dynamics",
            format!("fastest bead {fastest:.2} rad/s, frame angle error {spin_err:.1e} rad"),
            fastest / 10.0 + spin_err,
            1.0,
        ))
    })();
    r.unwrap_or_else(|e| case(name, "dynamics", format!("setup failed: {e}"), 1.0, 0.5))
}

/// A ball thrown along a straight spline rail (u ∈ [0, 1]) towards its end:
/// the limit penalty must turn it back before it leaves the range by 5 %.
pub fn spline_surface_range_end() -> HardCase {
    let name = "spline surface joint driven past its range end (limits hold it)";
    let r = (|| -> Result<HardCase, ReportError> {
        let grid = FrameGrid {
            dims: vec![5],
            ranges: vec![(0.0, 1.0)],
            frames: (0..5)
                .map(|i| Se3::from_translation(Vector3::new(i as f64 / 4.0, 0.0, 0.0)))
                .collect(),
            names: vec!["u".into()],
            unlimited: vec![false],
        };
        let j = SplineSurfaceJoint::from_grid(&grid, EulerOrder::ZYX)?;
        let mut m = Model::new("rail");
        m.add_link(
            "ball",
            None,
            "ball",
            Arc::new(j),
            Se3::identity(),
            Inertia::point(1.0, Vector3::zeros())?,
        )?;
        let scene = Scene::new(Arc::new(m)).with_limits(LimitPenalty {
            stiffness: 1e4,
            damping: 200.0,
        })?;
        let init = State {
            q: vec![0.9],
            v: vec![1.0],
        };
        let tr = simulate(
            &scene,
            2.0,
            1e-3,
            Integrator::Rk4,
            &init,
            &CancelToken::new(),
            &mut |_| {},
        )?;
        let worst =
            tr.q.iter()
                .map(|q| (q[0] - 1.0).max(-q[0]).max(0.0))
                .fold(0.0, f64::max);
        Ok(case(
            name,
            "dynamics",
            format!("furthest {worst:.2e} beyond the range"),
            worst,
            0.05,
        ))
    })();
    r.unwrap_or_else(|e| case(name, "dynamics", format!("setup failed: {e}"), 1.0, 0.5))
}
