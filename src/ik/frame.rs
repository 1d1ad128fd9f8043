//! One frame of IK: the coordinates that move the goal links, found by
//! damped least squares.
//!
//! Minimises ½‖r(q)‖² with, per goal g of weight w_g,
//!   r_g = w_g (p_g(q) − p̂_g)                       (3 rows, metres)
//!   r_g' = w_g c log(R̂_gᵀ R_g(q))                 (3 rows, only with an orientation)
//! where c (metres per radian, [`Settings::orientation_weight`]) makes an
//! angle comparable with a distance. The Jacobian is analytic: a coordinate
//! moves a point by `model::kinematics::point_velocity` and turns a link by
//! `angular_velocity` (the joint's own S(q), so spline, function-based and
//! every other joint of the library are handled alike).
//!
//! Levenberg–Marquardt with Nielsen's damping update: the step solves
//! (JᵀJ + μI) δ = −Jᵀr; μ shrinks by up to 3× after a step the linear model
//! predicted well and doubles (then quadruples, …) after a rejected one, so
//! reachable goals converge quadratically once close while far ones still
//! take safe steps. μI rather than μ·diag(JᵀJ): redundant chains have zero
//! or tiny columns, and a plain μ keeps those coordinates still instead of
//! letting them jump. Joint limits are bounds: a step is projected onto the
//! box, and a coordinate at a bound whose gradient pushes it outward is held
//! for that step (so the others still get a full Gauss–Newton step).
//!
//! An unreachable goal ends at the nearest point the method finds (a local
//! minimum of the residual); the result says how far it is.

use crate::lie::Se3;
use crate::lie::{left_jacobian_inv_so3, log_so3};
use crate::model::kinematics::{angular_velocity, point_velocity};
use crate::model::{Derivatives, JointKinematics, Model, ModelError};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

/// Where one link should be.
#[derive(Clone, Debug, PartialEq)]
pub struct Goal {
    /// Link index in the model.
    pub link: usize,
    /// World position of the link's origin (m).
    pub position: Vector3<f64>,
    /// World orientation of the link's frame, when it matters.
    pub orientation: Option<Matrix3<f64>>,
    /// Relative weight (> 0) of this goal's residual.
    pub weight: f64,
}

/// When to stop.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// A goal is met when its position is within this (m) and its
    /// orientation within this (rad).
    pub tolerance: f64,
    /// Iterations (Jacobian evaluations) per frame at most.
    pub max_iterations: usize,
    /// Metres one radian of orientation error counts as.
    pub orientation_weight: f64,
}

impl Default for Settings {
    /// 1e-6 m (a micrometre: far below what any capture resolves), 50
    /// iterations (a warm-started reachable frame takes 2–5), 0.1 m/rad.
    fn default() -> Self {
        Settings {
            tolerance: 1e-6,
            max_iterations: 50,
            orientation_weight: 0.1,
        }
    }
}

/// How one frame went.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameResult {
    /// Jacobian evaluations (steps tried from a new point).
    pub iterations: usize,
    /// Distance (m) of each goal's link from its target position.
    pub position_error: Vec<f64>,
    /// Angle (rad) between each goal's link frame and its target (0 when
    /// it has none).
    pub orientation_error: Vec<f64>,
    /// Every goal met within the tolerance.
    pub converged: bool,
}

/// The coordinates that may move and what they move, set up once for a
/// sequence of frames with the same goal links.
pub struct Solver<'a> {
    model: &'a Model,
    /// Goal link indices, in the order goals are given to [`Solver::solve`].
    links: Vec<usize>,
    /// Free coordinates (indices into q).
    free: Vec<usize>,
    /// Link owning each free coordinate.
    owners: Vec<usize>,
    /// `moves[g][j]`: free coordinate j moves goal link g.
    moves: Vec<Vec<bool>>,
    lower: Vec<f64>,
    upper: Vec<f64>,
    poses: Vec<Se3>,
}

impl<'a> Solver<'a> {
    /// `links`: the goal links; `allowed[c]`: coordinate c may move. The
    /// free coordinates are the allowed ones on some goal link's chain.
    pub fn new(model: &'a Model, links: &[usize], allowed: &[bool]) -> Result<Self, ModelError> {
        if allowed.len() != model.nq() {
            return Err(ModelError::Invalid(format!(
                "ik: {} allowed flags for {} coordinates",
                allowed.len(),
                model.nq()
            )));
        }
        if let Some(&l) = links.iter().find(|&&l| l >= model.num_links()) {
            return Err(ModelError::Invalid(format!(
                "ik: link index {l} out of range (the model has {} links)",
                model.num_links()
            )));
        }
        let (mut free, mut owners, mut lower, mut upper) = (vec![], vec![], vec![], vec![]);
        for (li, link) in model.links().iter().enumerate() {
            for k in 0..link.dof {
                let c = link.q_index + k;
                if allowed[c] && links.iter().any(|&g| model.is_ancestor(li, g)) {
                    free.push(c);
                    owners.push(li);
                    let lim = link
                        .limits
                        .get(k)
                        .copied()
                        .unwrap_or(crate::model::Limit::NONE);
                    lower.push(lim.lower);
                    upper.push(lim.upper);
                }
            }
        }
        let moves = links
            .iter()
            .map(|&g| owners.iter().map(|&o| model.is_ancestor(o, g)).collect())
            .collect();
        Ok(Solver {
            model,
            links: links.to_vec(),
            free,
            owners,
            moves,
            lower,
            upper,
            poses: Vec::with_capacity(model.num_links()),
        })
    }

    /// The coordinates this solver moves (indices into q).
    pub fn free(&self) -> &[usize] {
        &self.free
    }

    /// Residuals at q (and the Jacobian over the free coordinates when
    /// asked), with the unweighted errors per goal.
    fn residuals(
        &mut self,
        q: &[f64],
        goals: &[Goal],
        settings: &Settings,
        jac: Option<&mut DMatrix<f64>>,
        r: &mut DVector<f64>,
        errors: &mut (Vec<f64>, Vec<f64>),
    ) -> Result<(), ModelError> {
        self.model.forward_kinematics(q, &mut self.poses)?;
        let c = settings.orientation_weight;
        let mut row = 0;
        let mut rows_of = Vec::with_capacity(goals.len());
        errors.0.clear();
        errors.1.clear();
        for g in goals {
            let pose = &self.poses[g.link];
            let dp = pose.p - g.position;
            errors.0.push(dp.norm());
            r.fixed_rows_mut::<3>(row).copy_from(&(dp * g.weight));
            let mut e_rot = None;
            if let Some(rt) = &g.orientation {
                let e = log_so3(&(rt.transpose() * pose.r));
                errors.1.push(e.norm());
                r.fixed_rows_mut::<3>(row + 3)
                    .copy_from(&(e * (g.weight * c)));
                e_rot = Some(e);
            } else {
                errors.1.push(0.0);
            }
            rows_of.push((row, e_rot));
            row += if g.orientation.is_some() { 6 } else { 3 };
        }
        let Some(jac) = jac else { return Ok(()) };
        jac.fill(0.0);
        let mut jk = JointKinematics::default();
        let mut last_owner = usize::MAX;
        for (j, (&coord, &o)) in self.free.iter().zip(&self.owners).enumerate() {
            let link = self.model.link(o);
            if o != last_owner {
                link.joint.kinematics(
                    &q[link.q_index..link.q_index + link.dof],
                    Derivatives::Jacobian,
                    &mut jk,
                );
                last_owner = o;
            }
            let s = jk.s[coord - link.q_index];
            let pose = &self.poses[o];
            for (gi, g) in goals.iter().enumerate() {
                if !self.moves[gi][j] {
                    continue;
                }
                let (row, e_rot) = &rows_of[gi];
                let dp = point_velocity(pose, &s, &self.poses[g.link].p) * g.weight;
                jac.fixed_view_mut::<3, 1>(*row, j).copy_from(&dp);
                if let Some(e) = e_rot {
                    // e = log(R̂ᵀR): de = J_r⁻¹(e) Rᵀ ω, and J_r(e) = J_l(−e)
                    let w = angular_velocity(pose, &s);
                    let rl = self.poses[g.link].r;
                    let de = left_jacobian_inv_so3(&(-e)) * rl.transpose() * w * (g.weight * c);
                    jac.fixed_view_mut::<3, 1>(row + 3, j).copy_from(&de);
                }
            }
        }
        Ok(())
    }

    /// Moves the free coordinates of `q` (the starting point, updated in
    /// place) toward the goals. The goals' links must be the solver's, in
    /// order.
    pub fn solve(
        &mut self,
        q: &mut [f64],
        goals: &[Goal],
        settings: &Settings,
    ) -> Result<FrameResult, ModelError> {
        if goals.len() != self.links.len()
            || goals.iter().zip(&self.links).any(|(g, &l)| g.link != l)
        {
            return Err(ModelError::Invalid(
                "ik: the goals' links differ from the solver's".into(),
            ));
        }
        let m: usize = goals
            .iter()
            .map(|g| if g.orientation.is_some() { 6 } else { 3 })
            .sum();
        let n = self.free.len();
        for (j, &c) in self.free.iter().enumerate() {
            q[c] = q[c].clamp(self.lower[j], self.upper[j]);
        }
        let mut r = DVector::zeros(m);
        let mut rt = DVector::zeros(m);
        let mut jac = DMatrix::zeros(m, n);
        let mut errors = (vec![], vec![]);
        let mut trial_errors = (vec![], vec![]);
        self.residuals(q, goals, settings, Some(&mut jac), &mut r, &mut errors)?;
        let met =
            |e: &(Vec<f64>, Vec<f64>)| e.0.iter().chain(&e.1).all(|&x| x <= settings.tolerance);
        let mut cost = 0.5 * r.norm_squared();
        let mut iterations = 1;
        let mut mu = -1.0;
        let mut nu = 2.0;
        let mut trial = q.to_vec();
        while !met(&errors) && iterations < settings.max_iterations.max(1) && n > 0 {
            let a = jac.transpose() * &jac;
            let g = jac.transpose() * &r;
            if mu < 0.0 {
                let dmax = (0..n).map(|i| a[(i, i)]).fold(0.0, f64::max);
                mu = 1e-3 * dmax.max(1e-12);
            }
            // coordinates at a bound that the gradient pushes outward stay put
            let held: Vec<bool> = (0..n)
                .map(|j| {
                    let x = q[self.free[j]];
                    (x <= self.lower[j] && g[j] > 0.0) || (x >= self.upper[j] && g[j] < 0.0)
                })
                .collect();
            let idx: Vec<usize> = (0..n).filter(|&j| !held[j]).collect();
            if idx.is_empty() || idx.iter().all(|&j| g[j] == 0.0) {
                break; // a stationary point within the limits: as close as it gets
            }
            let k = idx.len();
            let mut am = DMatrix::from_fn(k, k, |i, j| a[(idx[i], idx[j])]);
            for i in 0..k {
                am[(i, i)] += mu;
            }
            let gv = DVector::from_fn(k, |i, _| -g[idx[i]]);
            let Some(ch) = am.cholesky() else {
                mu *= nu;
                nu *= 2.0;
                continue;
            };
            let step = ch.solve(&gv);
            trial.copy_from_slice(q);
            for (i, &j) in idx.iter().enumerate() {
                let c = self.free[j];
                trial[c] = (q[c] + step[i]).clamp(self.lower[j], self.upper[j]);
            }
            // the step actually taken (after projection) and its predicted gain
            let d = DVector::from_fn(n, |j, _| trial[self.free[j]] - q[self.free[j]]);
            let dnorm = d.norm();
            let xnorm: f64 = self.free.iter().map(|&c| q[c] * q[c]).sum::<f64>().sqrt();
            if dnorm <= 1e-14 * (1.0 + xnorm) {
                break; // no step left to take
            }
            let predicted = -(g.dot(&d) + 0.5 * (d.transpose() * &a * &d)[(0, 0)]);
            self.residuals(&trial, goals, settings, None, &mut rt, &mut trial_errors)?;
            let trial_cost = 0.5 * rt.norm_squared();
            let rho = if predicted > 0.0 {
                (cost - trial_cost) / predicted
            } else {
                -1.0
            };
            if rho > 0.0 && trial_cost < cost {
                q.copy_from_slice(&trial);
                let gain = cost - trial_cost;
                cost = trial_cost;
                mu *= (1.0 - (2.0 * rho - 1.0).powi(3)).max(1.0 / 3.0);
                nu = 2.0;
                self.residuals(q, goals, settings, Some(&mut jac), &mut r, &mut errors)?;
                iterations += 1;
                if gain <= 1e-15 * cost.max(1e-300) && !met(&errors) {
                    break; // no longer improving: the nearest point it finds
                }
            } else {
                mu *= nu;
                nu *= 2.0;
                if !mu.is_finite() || mu > 1e30 {
                    break;
                }
            }
        }
        let converged = met(&errors);
        Ok(FrameResult {
            iterations,
            position_error: errors.0,
            orientation_error: errors.1,
            converged,
        })
    }

    /// The Jacobian of the weighted residuals over the free coordinates at q
    /// (rows as in the module comment), for checking against differences.
    pub fn jacobian(
        &mut self,
        q: &[f64],
        goals: &[Goal],
        settings: &Settings,
    ) -> Result<(DVector<f64>, DMatrix<f64>), ModelError> {
        let m: usize = goals
            .iter()
            .map(|g| if g.orientation.is_some() { 6 } else { 3 })
            .sum();
        let mut r = DVector::zeros(m);
        let mut jac = DMatrix::zeros(m, self.free.len());
        let mut e = (vec![], vec![]);
        self.residuals(q, goals, settings, Some(&mut jac), &mut r, &mut e)?;
        Ok((r, jac))
    }
}
