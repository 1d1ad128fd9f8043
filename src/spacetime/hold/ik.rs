//! The hold IK of one gap: the residual R of the held frames, its gradient
//! and Jacobian, on the gap layout the torque objective uses.

use super::super::error::{SpError, invalid};
use super::super::objective::{GapDof, GapLayout, TransitionSettings};
use super::super::transition::TransitionCurve;
use super::{frame_positions, link_positions, owner};
use crate::ground::FloorPlane;
use crate::model::kinematics::point_velocity;
use crate::model::{Derivatives, JointKinematics, Model};
use crate::spacetime::contact::Stance;
use nalgebra::{DMatrix, Vector3};

/// μ² per second of gap of the IK's pull toward the Hermite curves (m² per
/// rad² of free coefficient): holding a foot inside its box must not twist a
/// knee half a radian about its long axis, which a pure drift objective
/// allows (redundant Euler channels move the foot for free).
pub const IK_STIFFNESS: f64 = 1e-3;

/// The IK problem of one gap: hold `frames` on their planted paths by moving
/// the gap DOFs `dofs` (those on the frames' chains).
pub struct HoldObjective<'a> {
    pub(super) model: &'a Model,
    pub(super) frames: Vec<usize>,
    /// Per frame, where it is held: one stance over the whole span (Rose's
    /// support, [`HoldObjective::new`]) or a contact plan's
    /// ([`HoldObjective::planned`]).
    stances: Vec<Vec<Stance>>,
    /// Nothing goes below it: outside its stances a frame lower than this is
    /// pulled up to it (one-sided), `None` for Rose's support.
    floor: Option<FloorPlane>,
    t0: f64,
    t1: f64,
    /// The gap DOFs, their curves, the nodes and the basis rows (the torque
    /// objective's layout; the IK reads the q rows).
    pub(super) layout: GapLayout,
    /// Link owning each gap DOF's coordinate.
    owners: Vec<usize>,
    /// Whether frame f moves with gap DOF d.
    moves: Vec<Vec<bool>>,
    /// Every coordinate at each node (gap DOFs overwritten from x).
    base: Vec<Vec<f64>>,
    /// μ² of the term μ²‖x − x_H‖² that keeps the IK near the Hermite start
    /// ([`IK_STIFFNESS`] × the gap's length).
    pub(super) stiffness: f64,
    /// The Hermite start x_H.
    pub(super) start: Vec<f64>,
}

/// How a frame is held at one node: r = P (p − target), ∂r/∂q = P ∂p/∂q.
enum Hold {
    /// On its stance: P = I.
    Planted(Vector3<f64>),
    /// Below the floor and not planted: P = up upᵀ, target on the floor.
    Floor(Vector3<f64>),
    /// Free: P = 0.
    Free,
}

impl<'a> HoldObjective<'a> {
    /// Rose's support: each frame held over the whole span on the straight
    /// path between where it is at the span's ends. `configuration(t)` gives
    /// every coordinate at t (gap DOFs may be NaN inside their gaps); `dofs`
    /// are the IK unknowns.
    pub fn new(
        model: &'a Model,
        frames: Vec<usize>,
        dofs: Vec<GapDof>,
        settings: &TransitionSettings,
        configuration: &dyn Fn(f64) -> Result<Vec<f64>, SpError>,
    ) -> Result<Self, SpError> {
        let mut o = Self::layout(model, frames, dofs, settings, configuration)?;
        // planted positions: where the frames are at the span's ends
        let (a, b) = (
            frame_positions(model, &o.frames, configuration, o.t0)?,
            frame_positions(model, &o.frames, configuration, o.t1)?,
        );
        o.stances = a
            .into_iter()
            .zip(b)
            .map(|(p0, p1)| {
                vec![Stance {
                    t0: o.t0,
                    t1: o.t1,
                    p0,
                    p1,
                    source: crate::spacetime::contact::Source::Context,
                    solved: None,
                }]
            })
            .collect();
        o.start = o.hermite_start();
        Ok(o)
    }

    /// A contact plan's IK: frame k held on `stances[k]` (none: free) and
    /// every frame kept at or above `floor` where it is not planted.
    pub fn planned(
        model: &'a Model,
        frames: Vec<usize>,
        stances: Vec<Vec<Stance>>,
        floor: FloorPlane,
        dofs: Vec<GapDof>,
        settings: &TransitionSettings,
        configuration: &dyn Fn(f64) -> Result<Vec<f64>, SpError>,
    ) -> Result<Self, SpError> {
        if stances.len() != frames.len() {
            return Err(invalid("support IK: one stance list per frame"));
        }
        let mut o = Self::layout(model, frames, dofs, settings, configuration)?;
        o.stances = stances;
        o.floor = Some(floor);
        o.start = o.hermite_start();
        Ok(o)
    }

    /// Everything but where the frames are held.
    fn layout(
        model: &'a Model,
        frames: Vec<usize>,
        dofs: Vec<GapDof>,
        settings: &TransitionSettings,
        configuration: &dyn Fn(f64) -> Result<Vec<f64>, SpError>,
    ) -> Result<Self, SpError> {
        if dofs.is_empty() || frames.is_empty() {
            return Err(invalid(
                "support IK needs at least one frame and one gap DOF",
            ));
        }
        let t0 = dofs.iter().map(|d| d.t0).fold(f64::INFINITY, f64::min);
        let t1 = dofs.iter().map(|d| d.t1).fold(f64::NEG_INFINITY, f64::max);
        let layout = GapLayout::new(dofs, settings)?;
        let owners = layout
            .dofs
            .iter()
            .map(|d| owner(model, d.coord).ok_or_else(|| invalid("gap coordinate without a link")))
            .collect::<Result<Vec<_>, _>>()?;
        let moves = frames
            .iter()
            .map(|&f| owners.iter().map(|&o| model.is_ancestor(o, f)).collect())
            .collect();
        let mut base = Vec::with_capacity(layout.nodes.len());
        for &t in &layout.nodes {
            // Gap DOFs off the held chains are undefined here; they cannot move
            // the held frames, so any finite value does for the kinematics.
            let q = configuration(t)?;
            base.push(
                q.into_iter()
                    .map(|v| if v.is_finite() { v } else { 0.0 })
                    .collect(),
            );
        }
        Ok(HoldObjective {
            model,
            frames,
            stances: vec![],
            floor: None,
            t0,
            t1,
            layout,
            owners,
            moves,
            base,
            stiffness: IK_STIFFNESS * (t1 - t0),
            start: vec![],
        })
    }

    pub fn n_vars(&self) -> usize {
        self.layout.n_vars()
    }

    pub fn dofs(&self) -> &[GapDof] {
        self.layout.dofs()
    }

    pub fn curves(&self) -> &[TransitionCurve] {
        self.layout.curves()
    }

    /// The gap layout the IK is solved on (the torque objective's).
    pub fn gap_layout(&self) -> &GapLayout {
        &self.layout
    }

    /// How frame f (at world position p) is held at t.
    fn hold(&self, f: usize, t: f64, p: &Vector3<f64>) -> Hold {
        if let Some(stance) = self.stances[f].iter().find(|pl| pl.covers(t)) {
            return Hold::Planted(stance.at(t));
        }
        match self.floor {
            Some(fl) if fl.up.dot(p) < fl.height => {
                Hold::Floor(p - fl.up * (fl.up.dot(p) - fl.height))
            }
            _ => Hold::Free,
        }
    }

    /// The stances of each frame.
    pub fn stances(&self) -> &[Vec<Stance>] {
        &self.stances
    }

    /// The starting point: the Hermite curves (as the spacetime solve's).
    pub fn hermite_start(&self) -> Vec<f64> {
        self.layout.hermite_start()
    }

    /// q at node k for free coefficients x.
    fn configuration(&self, k: usize, x: &[f64]) -> Vec<f64> {
        let mut q = self.base[k].clone();
        for (d, dof) in self.layout.dofs.iter().enumerate() {
            if let Some(r) = self.layout.rows(d, k) {
                q[dof.coord] = r.value(0, self.layout.of_dof(d, x));
            }
        }
        q
    }

    /// Residuals r_k (3 per frame) at node k and, when asked, their Jacobian
    /// with respect to the gap coordinates (3·frames × dofs).
    pub(super) fn node(
        &self,
        k: usize,
        x: &[f64],
        jac: Option<&mut DMatrix<f64>>,
    ) -> Result<Vec<Vector3<f64>>, SpError> {
        let q = self.configuration(k, x);
        let mut poses = vec![];
        link_positions(self.model, &q, &mut poses)?;
        let t = self.layout.nodes[k];
        let holds: Vec<Hold> = self
            .frames
            .iter()
            .enumerate()
            .map(|(f, &l)| self.hold(f, t, &poses[l].p))
            .collect();
        let r = self
            .frames
            .iter()
            .zip(&holds)
            .map(|(&l, h)| match h {
                Hold::Planted(target) | Hold::Floor(target) => poses[l].p - target,
                Hold::Free => Vector3::zeros(),
            })
            .collect();
        if let Some(jac) = jac {
            self.jacobian(k, &q, &poses, &holds, jac);
        }
        Ok(r)
    }

    /// ∂r/∂q at node k (configuration `q`, link poses `poses`) into `jac`.
    fn jacobian(
        &self,
        k: usize,
        q: &[f64],
        poses: &[crate::lie::Se3],
        holds: &[Hold],
        jac: &mut DMatrix<f64>,
    ) {
        jac.fill(0.0);
        let mut jk = JointKinematics::default();
        for (d, (dof, &o)) in self.layout.dofs.iter().zip(&self.owners).enumerate() {
            if self.layout.rows(d, k).is_none() {
                continue;
            }
            let link = self.model.link(o);
            link.joint.kinematics(
                &q[link.q_index..link.q_index + link.dof],
                Derivatives::Jacobian,
                &mut jk,
            );
            let s = jk.s[dof.coord - link.q_index];
            let pose = &poses[o];
            for (f, &fl) in self.frames.iter().enumerate() {
                if !self.moves[f][d] {
                    continue;
                }
                let dp = match &holds[f] {
                    Hold::Planted(_) => point_velocity(pose, &s, &poses[fl].p),
                    Hold::Floor(_) => {
                        let up = self.floor.map_or(Vector3::zeros(), |fl| fl.up);
                        up * up.dot(&point_velocity(pose, &s, &poses[fl].p))
                    }
                    Hold::Free => Vector3::zeros(),
                };
                for i in 0..3 {
                    jac[(3 * f + i, d)] = dp[i];
                }
            }
        }
    }

    /// R(x) = ∫ Σ_k ‖p_k − p̂_k‖² dt + μ²‖x − x_H‖², and ∂R/∂x into `grad` when given.
    pub fn eval(&self, x: &[f64], mut grad: Option<&mut [f64]>) -> Result<f64, SpError> {
        let mut total = 0.0;
        if let Some(g) = grad.as_deref_mut() {
            g.fill(0.0);
        }
        for (i, (xi, si)) in x.iter().zip(&self.start).enumerate() {
            total += self.stiffness * (xi - si) * (xi - si);
            if let Some(g) = grad.as_deref_mut() {
                g[i] += 2.0 * self.stiffness * (xi - si);
            }
        }
        let n_free = self.layout.n_free;
        let mut jac = DMatrix::zeros(3 * self.frames.len(), self.layout.dofs.len());
        for k in 0..self.layout.nodes.len() {
            let want_j = grad.is_some();
            let r = self.node(k, x, want_j.then_some(&mut jac))?;
            let w = self.layout.qweights[k];
            total += w * r.iter().map(|v| v.norm_squared()).sum::<f64>();
            if let Some(g) = grad.as_deref_mut() {
                for d in 0..self.layout.dofs.len() {
                    let Some(rows) = self.layout.rows(d, k) else {
                        continue;
                    };
                    // ∂R/∂q_d at this node
                    let gd: f64 = (0..r.len())
                        .map(|f| (0..3).map(|i| r[f][i] * jac[(3 * f + i, d)]).sum::<f64>())
                        .sum::<f64>()
                        * 2.0
                        * w;
                    for (j, b) in rows.rows[0].iter().enumerate() {
                        g[d * n_free + j] += gd * b;
                    }
                }
            }
        }
        if !total.is_finite() {
            return Err(SpError::Numerical(
                "support IK: the frame positions are not finite".into(),
            ));
        }
        Ok(total)
    }

    /// Largest distance of any held frame from its planted path over the
    /// gap, at the quadrature nodes (where every other coordinate is known exactly).
    pub fn largest_drift(&self, x: &[f64]) -> Result<Vec<f64>, SpError> {
        let mut out = vec![0.0f64; self.frames.len()];
        for k in 0..self.layout.nodes.len() {
            for (f, r) in self.node(k, x, None)?.iter().enumerate() {
                out[f] = out[f].max(r.norm());
            }
        }
        Ok(out)
    }

    /// Full coefficient vectors of every gap DOF for free coefficients x.
    pub fn coefficients(&self, x: &[f64]) -> Vec<Vec<f64>> {
        self.layout.coefficients(x)
    }
}
