//! One state's kinematics and inverse dynamics, computed on first request
//! and kept while the state stays the same, so that several consumers of one
//! state — the spacetime objective's terms at one quadrature node — share one
//! forward pass instead of running one each (IDTO's per-time-step cache,
//! invalidated when q changes, is the model).
//!
//! The passes, in the order they build on each other:
//! - kinematics at (q, q̇): joint transforms, Jacobians and Hessians, link
//!   twists (the RNEA's velocity pass), and on request the links' world
//!   poses and the Jacobian of a link's origin;
//! - the RNEA's force sweeps at q̈ under gravity and world forces at link
//!   points ([`PointForce`]): τ and the root's wrench;
//! - reverse sweeps seeded on τ and on the root's wrench after them, as many
//!   as asked ([`StateCache::reverse`]).
//!
//! Every request names the state it wants ([`Loaded`]); the cache compares it
//! bit for bit with the one it holds and reruns only the passes whose inputs
//! differ, so a stale pass is never read and no caller has to say when the
//! state changed. The operations are those of `rnea_points` and the adjoint,
//! in the same order: τ and every gradient are the same to the bit as
//! [`crate::dynamics::inverse_dynamics_at_points`] and
//! [`crate::dynamics::InverseDynamicsPass`] give.

use crate::dynamics::DynamicsError;
use crate::dynamics::adjoint::reverse_sweep;
use crate::dynamics::external::{
    PointForce, add_turning_gradient, check_points, link_wrenches, world_poses,
};
use crate::dynamics::rnea::{check_inputs, check_out, rnea_sweeps};
use crate::dynamics::state::{JointState, StateGradient};
use crate::dynamics::workspace::{Workspace, velocity_pass};
use crate::lie::{Se3, Twist, Wrench};
use crate::model::Model;
use crate::model::kinematics::point_velocity;
use nalgebra::Vector3;

/// A state of the body and what acts on it besides its joints: gravity and
/// world forces at link points.
#[derive(Clone, Copy, Debug)]
pub struct Loaded<'a> {
    pub x: JointState<'a>,
    pub gravity: &'a Vector3<f64>,
    pub forces: &'a [PointForce],
}

/// A link origin's world Jacobian: (coordinate, ∂p/∂q_c), leaf to root.
type Columns = Vec<(usize, Vector3<f64>)>;

/// The passes of one state (see the module doc). Build it once per model and
/// thread; it allocates only when a state has more forces than any before.
#[derive(Clone, Debug)]
pub struct StateCache {
    ws: Workspace,
    tau: Vec<f64>,
    /// The (q, q̇) the kinematic pass holds, if it holds one.
    q: Vec<f64>,
    v: Vec<f64>,
    posed: bool,
    /// Whether `ws.world` holds that pass's world poses.
    world: bool,
    /// The q̈, gravity and forces the force sweeps hold, if they hold any.
    a: Vec<f64>,
    gravity: Vector3<f64>,
    forces: Vec<PointForce>,
    solved: bool,
    /// Counts the kinematic passes; per link, the pass its origin's
    /// Jacobian columns were taken at, and them.
    pass: u64,
    columns: Vec<(u64, Columns)>,
    /// A zero seed on τ.
    zero: Vec<f64>,
}

/// Whether two slices hold the same numbers to the bit.
fn same(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

fn same_forces(a: &[PointForce], b: &[PointForce]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(f, g)| {
            f.link == g.link
                && same(f.point.as_slice(), g.point.as_slice())
                && same(f.force.as_slice(), g.force.as_slice())
                && same(f.moment.as_slice(), g.moment.as_slice())
        })
}

impl StateCache {
    pub fn new(model: &Model) -> Self {
        let n = model.nq();
        StateCache {
            ws: Workspace::new(model),
            tau: vec![0.0; n],
            q: vec![0.0; n],
            v: vec![0.0; n],
            posed: false,
            world: false,
            a: vec![0.0; n],
            gravity: Vector3::zeros(),
            forces: vec![],
            solved: false,
            pass: 0,
            columns: vec![(0, vec![]); model.num_links()],
            zero: vec![0.0; n],
        }
    }

    /// The kinematic pass at (q, q̇), run unless it holds that one.
    fn kinematics(&mut self, model: &Model, x: &JointState) -> Result<(), DynamicsError> {
        if self.posed && same(&self.q, x.q) && same(&self.v, x.v) {
            return Ok(());
        }
        check_inputs(
            model,
            &self.ws,
            &[("q", x.q), ("v", x.v)],
            &Vector3::zeros(),
        )?;
        self.posed = false;
        self.solved = false;
        self.world = false;
        velocity_pass(model, &mut self.ws, x.q, x.v, true);
        self.q.copy_from_slice(x.q);
        self.v.copy_from_slice(x.v);
        self.pass += 1;
        self.posed = true;
        Ok(())
    }

    fn world_poses(&mut self, model: &Model) {
        if !self.world {
            world_poses(model, &mut self.ws);
            self.world = true;
        }
    }

    /// The links' world poses at `x.q` (q̇ is read too: the pass that
    /// places the links is the RNEA's, which also moves them).
    pub fn poses(&mut self, model: &Model, x: &JointState) -> Result<&[Se3], DynamicsError> {
        self.kinematics(model, x)?;
        self.world_poses(model);
        Ok(&self.ws.world)
    }

    /// (c, ∂p/∂q_c) at `x.q` for every coordinate c that moves the origin p
    /// of `link` (its own joint's and its ancestors'), leaf to root: the
    /// columns of the origin's world Jacobian, each joint's read from the
    /// kinematic pass.
    pub fn point_jacobian(
        &mut self,
        model: &Model,
        x: &JointState,
        link: usize,
    ) -> Result<&[(usize, Vector3<f64>)], DynamicsError> {
        if link >= model.num_links() {
            return Err(DynamicsError::Input(format!(
                "link {link} is outside the model's {} links",
                model.num_links()
            )));
        }
        self.kinematics(model, x)?;
        self.world_poses(model);
        let (at, cols) = &mut self.columns[link];
        if *at != self.pass {
            cols.clear();
            let p = self.ws.world[link].p;
            let mut l = Some(link);
            while let Some(i) = l {
                let lk = model.link(i);
                for m in 0..lk.dof {
                    let col = point_velocity(&self.ws.world[i], &self.ws.kin[i].s[m], &p);
                    cols.push((lk.q_index + m, col));
                }
                l = lk.parent;
            }
            *at = self.pass;
        }
        Ok(&self.columns[link].1)
    }

    /// The RNEA at `s`, run unless the cache holds it (see the module doc).
    fn dynamics(&mut self, model: &Model, s: &Loaded) -> Result<(), DynamicsError> {
        self.kinematics(model, &s.x)?;
        if self.solved
            && same(&self.a, s.x.a)
            && same(self.gravity.as_slice(), s.gravity.as_slice())
            && same_forces(&self.forces, s.forces)
        {
            return Ok(());
        }
        check_inputs(model, &self.ws, &[("a", s.x.a)], s.gravity)?;
        check_points(model, s.forces)?;
        self.solved = false;
        let fext = if s.forces.is_empty() {
            None
        } else {
            self.world_poses(model);
            link_wrenches(model, &mut self.ws, s.forces);
            Some(std::mem::take(&mut self.ws.pf))
        };
        rnea_sweeps(
            model,
            &mut self.ws,
            s.x.a,
            s.gravity,
            fext.as_deref(),
            &mut self.tau,
        );
        if let Some(pf) = fext {
            self.ws.pf = pf;
        }
        self.a.copy_from_slice(s.x.a);
        self.gravity = *s.gravity;
        self.forces.clear();
        self.forces.extend_from_slice(s.forces);
        self.solved = true;
        Ok(())
    }

    /// τ at `s`: inverse dynamics with its forces acting,
    /// τ = ID − Σ J_cᵀ [m_c; f_c].
    pub fn tau(&mut self, model: &Model, s: &Loaded) -> Result<&[f64], DynamicsError> {
        self.dynamics(model, s)?;
        Ok(&self.tau)
    }

    /// The wrench the world applies through the root joints at `s` (moment
    /// about the world origin, force; world axes), as
    /// [`crate::dynamics::root_wrench`].
    pub fn root_wrench(&mut self, model: &Model, s: &Loaded) -> Result<Wrench, DynamicsError> {
        self.dynamics(model, s)?;
        Ok(crate::dynamics::root_wrench(model, &self.ws))
    }

    /// Writes into `grad` the gradient with respect to q, q̇, q̈ of
    /// `tau_bar · τ + root_bar · w_root` at `s` (none: a zero seed), the
    /// forces held fixed in the world: one reverse sweep after the held (or
    /// a new) RNEA, as [`crate::dynamics::InverseDynamicsPass::reverse`].
    pub fn reverse(
        &mut self,
        model: &Model,
        s: &Loaded,
        tau_bar: Option<&[f64]>,
        root_bar: Option<&Twist>,
        grad: StateGradient,
    ) -> Result<(), DynamicsError> {
        self.dynamics(model, s)?;
        let StateGradient { q, v, a } = grad;
        for (name, g) in [("gq", &*q), ("gv", &*v), ("ga", &*a)] {
            check_out(model, name, g)?;
        }
        // non-finite seeds give a non-finite gradient, as the adjoint's do
        let tbar = tau_bar.unwrap_or(&self.zero);
        check_out(model, "tau_bar", tbar)?;
        reverse_sweep(
            model,
            &mut self.ws,
            &s.x,
            tbar,
            root_bar,
            [&mut *q, &mut *v, &mut *a],
        );
        if !s.forces.is_empty() {
            add_turning_gradient(model, &mut self.ws, s.forces, q);
        }
        Ok(())
    }
}
