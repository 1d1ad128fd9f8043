//! Support limbs held by inverse kinematics over a transition (Rose §3.2.2).
//!
//! A support frame is a link whose world position stays inside a small box
//! over the end of the motion before a gap and the start of the motion after
//! it (a planted foot), or one the animator names. Detection looks at
//! [`WINDOW`] seconds on each side (6 samples per side): long enough to tell a
//! planted foot from a swinging one passing through its lowest point, short
//! enough to fit inside the stance phase of a walk (≈0.6 s). Only frames near
//! the ground count ([`GROUND_BAND`] above the body's lowest frame): a still
//! head or hand of a person standing is not carrying the body.
//!
//! Over the gap a support frame k is held on its planted path p̂_k(t), the
//! straight line from where it is at the gap's start to where it is at the
//! gap's end (the curves are fixed there, so r = 0 is reachable at both ends;
//! the two points are inside the box of each other), by minimising
//!
//! R = ∫ Σ_k ‖p_k(q(t)) − p̂_k(t)‖² dt
//!
//! over the free B-spline coefficients of the gap DOFs on the chains from the
//! held frames to the root — the same transition curves and quadrature as the
//! spacetime solve. R is a sum of squares and the unknowns are few, so
//! Gauss–Newton with Levenberg–Marquardt damping converges in a few
//! iterations. The Jacobian is analytic: a coordinate i of link L moves a point
//! p by ∂p/∂q_i = R_L(ω_i × R_Lᵀ(p − o_L) + v_i), [ω_i; v_i] = column i of the
//! joint's S(q) in L's frame. The solved DOFs then become inputs of the
//! spacetime solve of the remaining ones.

use super::error::{SpError, invalid};
use super::objective::{GapDof, TransitionSettings, composite_nodes, hermite_free_coefficients};
use super::transition::TransitionCurve;
use crate::cancel::CancelToken;
use crate::lie::Se3;
use crate::model::kinematics::point_velocity;
use crate::model::{Derivatives, JointKinematics, Model};
use nalgebra::{DMatrix, DVector, Vector3};

/// Seconds of motion looked at on each side of a gap to detect support frames.
pub const WINDOW: f64 = 0.1;
/// Samples per side in [`WINDOW`].
pub const WINDOW_SAMPLES: usize = 6;
/// A support frame lies within this height (m) of the body's lowest frame.
pub const GROUND_BAND: f64 = 0.15;
/// Levenberg–Marquardt iterations at most (it converges in a handful).
const MAX_ITERS: usize = 50;
/// Stop when the largest residual is below this (m): far below what shows.
const RESIDUAL_TOL: f64 = 1e-6;

/// One support frame held over one gap.
#[derive(Clone, Debug, PartialEq)]
pub struct HeldFrame {
    /// The link's name.
    pub frame: String,
    pub t0: f64,
    pub t1: f64,
    /// `true` when found by the box test, `false` when named.
    pub detected: bool,
    /// The gap DOFs solved by IK (every held frame of the gap shares them).
    pub dofs: Vec<String>,
    /// Largest distance (m) from its planted path over the gap with the
    /// starting (Hermite) curves, i.e. without IK.
    pub moved_before: f64,
    /// The same after IK.
    pub moved: f64,
}

/// The world position of every link (by index) at configuration q.
fn link_positions(model: &Model, q: &[f64], poses: &mut Vec<Se3>) -> Result<(), SpError> {
    model
        .forward_kinematics(q, poses)
        .map_err(|e| SpError::Evaluation(format!("forward kinematics: {e}")))
}

/// The world positions of `frames` at time t of a fully defined configuration.
fn frame_positions(
    model: &Model,
    frames: &[usize],
    configuration: &dyn Fn(f64) -> Result<Vec<f64>, SpError>,
    t: f64,
) -> Result<Vec<Vector3<f64>>, SpError> {
    let q = configuration(t)?;
    if q.iter().any(|v| !v.is_finite()) {
        return Err(SpError::Evaluation(format!(
            "support IK: the body is not fully defined at the gap end t = {t}"
        )));
    }
    let mut poses = vec![];
    link_positions(model, &q, &mut poses)?;
    Ok(frames.iter().map(|&f| poses[f].p).collect())
}

/// The link that owns coordinate c.
pub(crate) fn owner(model: &Model, c: usize) -> Option<usize> {
    model
        .links()
        .iter()
        .position(|l| c >= l.q_index && c < l.q_index + l.dof)
}

/// Candidate support frames: every link that is not an intermediate link of a
/// multi-DOF joint (those coincide with the next link).
pub(crate) fn candidates(model: &Model) -> Vec<usize> {
    crate::model::joint_points(model).0
}

/// Frames whose position stays in a cube of edge `box_size` over `q_before`
/// and `q_after` (configurations sampled on each side of the gap) and that lie
/// near the ground (see [`GROUND_BAND`]).
pub fn detect(
    model: &Model,
    configurations: &[Vec<f64>],
    gravity: &Vector3<f64>,
    box_size: f64,
) -> Result<Vec<usize>, SpError> {
    if !(box_size.is_finite() && box_size >= 0.0) {
        return Err(invalid(format!(
            "support box size {box_size} m must be finite and non-negative (default 0.02)"
        )));
    }
    let up = if gravity.norm() > 0.0 {
        -gravity / gravity.norm()
    } else {
        return Ok(vec![]); // no gravity: nothing is supported
    };
    let links = candidates(model);
    let mut lo = vec![Vector3::repeat(f64::INFINITY); links.len()];
    let mut hi = vec![Vector3::repeat(f64::NEG_INFINITY); links.len()];
    let mut lowest = f64::INFINITY;
    let mut poses = vec![];
    for q in configurations {
        link_positions(model, q, &mut poses)?;
        for (j, &l) in links.iter().enumerate() {
            let p = poses[l].p;
            lo[j] = lo[j].inf(&p);
            hi[j] = hi[j].sup(&p);
            lowest = lowest.min(p.dot(&up));
        }
    }
    if configurations.is_empty() {
        return Ok(vec![]);
    }
    Ok(links
        .iter()
        .enumerate()
        .filter(|&(j, _)| {
            let still = (hi[j] - lo[j]).iter().all(|d| *d <= box_size);
            // the frame's highest point over the windows is near the ground
            let h = 0.5 * (hi[j] + lo[j]);
            let near_ground = h.dot(&up) - lowest <= GROUND_BAND + box_size;
            still && near_ground
        })
        .map(|(_, &l)| l)
        .collect())
}

/// Links named by the user; an unknown name is an error listing the closest names.
pub fn named(model: &Model, names: &[String]) -> Result<Vec<usize>, SpError> {
    names
        .iter()
        .map(|n| {
            model.link_index(n).ok_or_else(|| {
                let mut near: Vec<(f64, &str)> = model
                    .links()
                    .iter()
                    .map(|l| {
                        (
                            strsim::normalized_damerau_levenshtein(
                                &n.to_lowercase(),
                                &l.name.to_lowercase(),
                            ),
                            l.name.as_str(),
                        )
                    })
                    .collect();
                near.sort_by(|a, b| b.0.total_cmp(&a.0));
                let list: Vec<&str> = near.iter().take(5).map(|(_, s)| *s).collect();
                invalid(format!(
                    "support: the body has no frame named '{n}'; the nearest names are {}",
                    list.join(", ")
                ))
            })
        })
        .collect()
}

/// A gap DOF's q at one node: (offset, first free index, basis values).
type NodeRow = (f64, usize, Vec<f64>);

/// The IK problem of one gap: hold `frames` on their planted paths by moving
/// the gap DOFs `dofs` (those on the frames' chains).
pub struct SupportObjective<'a> {
    model: &'a Model,
    frames: Vec<usize>,
    /// Per frame, where it is held: one plant over the whole span (Rose's
    /// support, [`SupportObjective::new`]) or a contact schedule's
    /// ([`SupportObjective::planned`]).
    plants: Vec<Vec<Plant>>,
    /// Nothing goes below it: outside its plants a frame lower than this is
    /// pulled up to it (one-sided), `None` for Rose's support.
    floor: Option<Floor>,
    t0: f64,
    t1: f64,
    dofs: Vec<GapDof>,
    curves: Vec<TransitionCurve>,
    /// Link owning each gap DOF's coordinate.
    owners: Vec<usize>,
    /// Whether frame f moves with gap DOF d.
    moves: Vec<Vec<bool>>,
    nodes: Vec<f64>,
    qweights: Vec<f64>,
    /// Every coordinate at each node (gap DOFs overwritten from x).
    base: Vec<Vec<f64>>,
    /// Per gap DOF and node: (offset, first free index, basis values) of q.
    rows: Vec<Vec<Option<NodeRow>>>,
    n_free: usize,
    /// μ² of the term μ²‖x − x_H‖² that keeps the IK near the Hermite start
    /// ([`IK_STIFFNESS`] × the gap's length).
    stiffness: f64,
    /// The Hermite start x_H.
    start: Vec<f64>,
}

/// Where a held frame must be over part of a gap: on the straight path from
/// `p0` at `t0` to `p1` at `t1` (a planted foot: `p0 == p1`).
#[derive(Clone, Debug, PartialEq)]
pub struct Plant {
    pub t0: f64,
    pub t1: f64,
    pub p0: Vector3<f64>,
    pub p1: Vector3<f64>,
}

impl Plant {
    fn covers(&self, t: f64) -> bool {
        t >= self.t0 && t <= self.t1
    }

    fn at(&self, t: f64) -> Vector3<f64> {
        let s = ((t - self.t0) / (self.t1 - self.t0)).clamp(0.0, 1.0);
        self.p0 * (1.0 - s) + self.p1 * s
    }
}

/// The floor of a contact schedule: the plane of points p with `up · p = height`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Floor {
    /// Unit vector against gravity.
    pub up: Vector3<f64>,
    pub height: f64,
}

/// How a frame is held at one node: r = P (p − target), ∂r/∂q = P ∂p/∂q.
enum Hold {
    /// On its plant: P = I.
    Planted(Vector3<f64>),
    /// Below the floor and not planted: P = up upᵀ, target on the floor.
    Floor(Vector3<f64>),
    /// Free: P = 0.
    Free,
}

/// μ² per second of gap of the IK's pull toward the Hermite curves (m² per
/// rad² of free coefficient): holding a foot inside its box must not twist a
/// knee half a radian about its long axis, which a pure drift objective
/// allows (redundant Euler channels move the foot for free).
pub const IK_STIFFNESS: f64 = 1e-3;

impl<'a> SupportObjective<'a> {
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
        o.plants = a
            .into_iter()
            .zip(b)
            .map(|(p0, p1)| {
                vec![Plant {
                    t0: o.t0,
                    t1: o.t1,
                    p0,
                    p1,
                }]
            })
            .collect();
        o.start = o.hermite_start();
        Ok(o)
    }

    /// A contact schedule's IK: frame k held on `plants[k]` (none: free) and
    /// every frame kept at or above `floor` where it is not planted.
    pub fn planned(
        model: &'a Model,
        frames: Vec<usize>,
        plants: Vec<Vec<Plant>>,
        floor: Floor,
        dofs: Vec<GapDof>,
        settings: &TransitionSettings,
        configuration: &dyn Fn(f64) -> Result<Vec<f64>, SpError>,
    ) -> Result<Self, SpError> {
        if plants.len() != frames.len() {
            return Err(invalid("support IK: one plant list per frame"));
        }
        let mut o = Self::layout(model, frames, dofs, settings, configuration)?;
        o.plants = plants;
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
        let curves = dofs
            .iter()
            .map(|d| TransitionCurve::new(d.t0, d.t1, settings.coefficients, settings.continuity))
            .collect::<Result<Vec<_>, _>>()?;
        let owners = dofs
            .iter()
            .map(|d| owner(model, d.coord).ok_or_else(|| invalid("gap coordinate without a link")))
            .collect::<Result<Vec<_>, _>>()?;
        let moves = frames
            .iter()
            .map(|&f| owners.iter().map(|&o| model.is_ancestor(o, f)).collect())
            .collect();
        let (nodes, qweights) = composite_nodes(&curves, settings.samples)?;
        let n_free = settings.coefficients;
        let mut base = Vec::with_capacity(nodes.len());
        for &t in &nodes {
            // Gap DOFs off the held chains are undefined here; they cannot move
            // the held frames, so any finite value does for the kinematics.
            let q = configuration(t)?;
            base.push(
                q.into_iter()
                    .map(|v| if v.is_finite() { v } else { 0.0 })
                    .collect(),
            );
        }
        let rows = dofs
            .iter()
            .zip(&curves)
            .map(|(d, c)| {
                let fixed = c.coefficients(&d.start, &d.end, &vec![0.0; n_free]);
                let k0 = c.first_free();
                nodes
                    .iter()
                    .map(|&t| {
                        if t < d.t0 || t > d.t1 {
                            return None;
                        }
                        let b = &c.basis_at(t)[0];
                        let off: f64 = b.iter().zip(&fixed).map(|(x, y)| x * y).sum();
                        Some((off, 0, b[k0..k0 + n_free].to_vec()))
                    })
                    .collect()
            })
            .collect();
        Ok(SupportObjective {
            model,
            frames,
            plants: vec![],
            floor: None,
            t0,
            t1,
            dofs,
            curves,
            owners,
            moves,
            nodes,
            qweights,
            base,
            rows,
            n_free,
            stiffness: 0.0,
            start: vec![],
        })
        .map(|mut o: SupportObjective<'a>| {
            o.stiffness = IK_STIFFNESS * (o.t1 - o.t0);
            o
        })
    }

    pub fn n_vars(&self) -> usize {
        self.dofs.len() * self.n_free
    }

    pub fn dofs(&self) -> &[GapDof] {
        &self.dofs
    }

    pub fn curves(&self) -> &[TransitionCurve] {
        &self.curves
    }

    /// How frame f (at world position p) is held at t.
    fn hold(&self, f: usize, t: f64, p: &Vector3<f64>) -> Hold {
        if let Some(plant) = self.plants[f].iter().find(|pl| pl.covers(t)) {
            return Hold::Planted(plant.at(t));
        }
        match self.floor {
            Some(fl) if fl.up.dot(p) < fl.height => {
                Hold::Floor(p - fl.up * (fl.up.dot(p) - fl.height))
            }
            _ => Hold::Free,
        }
    }

    /// The plants of each frame.
    pub fn plants(&self) -> &[Vec<Plant>] {
        &self.plants
    }

    /// The starting point: the Hermite curves (as the spacetime solve's).
    pub fn hermite_start(&self) -> Vec<f64> {
        hermite_free_coefficients(&self.dofs, &self.curves)
    }

    /// q at node k for free coefficients x.
    fn configuration(&self, k: usize, x: &[f64]) -> Vec<f64> {
        let mut q = self.base[k].clone();
        for (d, dof) in self.dofs.iter().enumerate() {
            if let Some((off, lo, row)) = &self.rows[d][k] {
                let xd = &x[d * self.n_free + lo..];
                q[dof.coord] = off + row.iter().zip(xd).map(|(a, b)| a * b).sum::<f64>();
            }
        }
        q
    }

    /// Residuals r_k (3 per frame) at node k and, when asked, their Jacobian
    /// with respect to the gap coordinates (3·frames × dofs).
    fn node(
        &self,
        k: usize,
        x: &[f64],
        jac: Option<&mut DMatrix<f64>>,
    ) -> Result<Vec<Vector3<f64>>, SpError> {
        let q = self.configuration(k, x);
        let mut poses = vec![];
        link_positions(self.model, &q, &mut poses)?;
        let t = self.nodes[k];
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
            jac.fill(0.0);
            let mut jk = JointKinematics::default();
            for (d, (dof, &o)) in self.dofs.iter().zip(&self.owners).enumerate() {
                if self.rows[d][k].is_none() {
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
        Ok(r)
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
        let mut jac = DMatrix::zeros(3 * self.frames.len(), self.dofs.len());
        for k in 0..self.nodes.len() {
            let want_j = grad.is_some();
            let r = self.node(k, x, want_j.then_some(&mut jac))?;
            let w = self.qweights[k];
            total += w * r.iter().map(|v| v.norm_squared()).sum::<f64>();
            if let Some(g) = grad.as_deref_mut() {
                for (d, rows) in self.rows.iter().enumerate() {
                    let Some((_, lo, row)) = &rows[k] else {
                        continue;
                    };
                    // ∂R/∂q_d at this node
                    let gd: f64 = (0..r.len())
                        .map(|f| (0..3).map(|i| r[f][i] * jac[(3 * f + i, d)]).sum::<f64>())
                        .sum::<f64>()
                        * 2.0
                        * w;
                    for (j, b) in row.iter().enumerate() {
                        g[d * self.n_free + lo + j] += gd * b;
                    }
                }
            }
        }
        if !total.is_finite() {
            return Err(SpError::Evaluation(
                "support IK: the frame positions are not finite".into(),
            ));
        }
        Ok(total)
    }

    /// Largest distance of any held frame from its planted path over the
    /// gap, at the quadrature nodes (where every other coordinate is known exactly).
    pub fn largest_drift(&self, x: &[f64]) -> Result<Vec<f64>, SpError> {
        let mut out = vec![0.0f64; self.frames.len()];
        for k in 0..self.nodes.len() {
            for (f, r) in self.node(k, x, None)?.iter().enumerate() {
                out[f] = out[f].max(r.norm());
            }
        }
        Ok(out)
    }

    /// Full coefficient vectors of every gap DOF for free coefficients x.
    pub fn coefficients(&self, x: &[f64]) -> Vec<Vec<f64>> {
        super::objective::full_coefficients(&self.dofs, &self.curves, self.n_free, x)
    }

    /// Minimise R by Levenberg–Marquardt from the Hermite start; returns x.
    pub fn solve(&self, cancel: &CancelToken) -> Result<Vec<f64>, SpError> {
        let n = self.n_vars();
        let mut x = self.hermite_start();
        if n == 0 {
            return Ok(x);
        }
        let mut lambda = 1e-6;
        let mut jac = DMatrix::zeros(3 * self.frames.len(), self.dofs.len());
        for _ in 0..MAX_ITERS {
            cancel.check()?;
            // Gauss–Newton system Σ w JᵀJ δ = −Σ w Jᵀ r over the coefficients
            let mut h = DMatrix::<f64>::zeros(n, n);
            let mut g = DVector::<f64>::zeros(n);
            let mut e = 0.0;
            let mut worst = 0.0f64;
            for k in 0..self.nodes.len() {
                let r = self.node(k, &x, Some(&mut jac))?;
                let w = self.qweights[k];
                e += w * r.iter().map(|v| v.norm_squared()).sum::<f64>();
                worst = r.iter().fold(worst, |m, v| m.max(v.norm()));
                let rv =
                    DVector::from_iterator(3 * r.len(), r.iter().flat_map(|v| v.iter().copied()));
                // columns of the coefficient Jacobian: J_q[:, d] · basis row
                let mut cols: Vec<(usize, DVector<f64>)> = vec![];
                for (d, rows) in self.rows.iter().enumerate() {
                    let Some((_, lo, row)) = &rows[k] else {
                        continue;
                    };
                    for (j, b) in row.iter().enumerate() {
                        if *b != 0.0 {
                            cols.push((d * self.n_free + lo + j, jac.column(d) * *b));
                        }
                    }
                }
                for (i, ci) in &cols {
                    g[*i] += w * ci.dot(&rv);
                    for (j, cj) in &cols {
                        h[(*i, *j)] += w * ci.dot(cj);
                    }
                }
            }
            for i in 0..n {
                e += self.stiffness * (x[i] - self.start[i]).powi(2);
                g[i] += self.stiffness * (x[i] - self.start[i]);
                h[(i, i)] += self.stiffness;
            }
            if worst <= RESIDUAL_TOL {
                break;
            }
            // damped step, raising the damping until R decreases
            let scale = (0..n).map(|i| h[(i, i)]).fold(0.0, f64::max).max(1e-300);
            let mut improved = false;
            for _ in 0..20 {
                let mut a = h.clone();
                for i in 0..n {
                    a[(i, i)] += lambda * (h[(i, i)] + 1e-9 * scale);
                }
                let Some(ch) = a.cholesky() else {
                    lambda *= 10.0;
                    continue;
                };
                let step = ch.solve(&(-&g));
                let xt: Vec<f64> = x.iter().zip(step.iter()).map(|(a, b)| a + b).collect();
                let et = self.eval(&xt, None)?;
                if et < e {
                    x = xt;
                    lambda = (lambda * 0.1).max(1e-12);
                    improved = true;
                    // converged when the step no longer changes R noticeably
                    if e - et <= 1e-12 * e {
                        return Ok(x);
                    }
                    break;
                }
                lambda *= 10.0;
            }
            if !improved {
                break;
            }
        }
        Ok(x)
    }
}
