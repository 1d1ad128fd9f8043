//! Scenes: a model plus the effects it declares. Only declared effects are
//! computed: a scene without springs never evaluates point kinematics, one
//! without gravity passes a zero vector, and so on.

use crate::dynamics::aba::aba_core;
use crate::dynamics::driven::{Driven, DrivenBuffers, driven_accelerations};
use crate::dynamics::state::Forces;
use crate::dynamics::workspace::Workspace;
use crate::dynamics::{DynamicsError, kinetic_energy, potential_energy};
use crate::lie::{Se3, Twist, Wrench};
use crate::model::Model;
use crate::model::joint::Derivatives;
use nalgebra::{Vector3, Vector6};
use std::sync::Arc;

/// A damped spring between a point on one link and a point on another (or the
/// world): force `k (|d| − rest) + c d/dt|d|` along the line between the points.
#[derive(Clone, Debug, PartialEq)]
pub struct Spring {
    /// Link of the first end (`None`: fixed in the world).
    pub link_a: Option<usize>,
    /// The first end in `link_a`'s frame (world frame when `link_a` is `None`).
    pub point_a: Vector3<f64>,
    pub link_b: Option<usize>,
    pub point_b: Vector3<f64>,
    pub stiffness: f64,
    pub damping: f64,
    pub rest_length: f64,
}

/// A constant force (world frame) applied at a point of a link (link frame).
#[derive(Clone, Debug, PartialEq)]
pub struct ExternalForce {
    pub link: usize,
    pub point: Vector3<f64>,
    pub force: Vector3<f64>,
}

/// Penalty that pushes coordinates back inside their joint limits:
/// `τ = k (limit − q) − c q̇` while outside.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LimitPenalty {
    pub stiffness: f64,
    pub damping: f64,
}

/// A model and the effects that act on it.
#[derive(Clone, Debug)]
pub struct Scene {
    pub model: Arc<Model>,
    pub gravity: Option<Vector3<f64>>,
    /// Viscous joint damping per coordinate (`τ = −d q̇`).
    pub damping: Option<Vec<f64>>,
    pub springs: Vec<Spring>,
    pub forces: Vec<ExternalForce>,
    pub limits: Option<LimitPenalty>,
    /// Coordinates moved at a constant rate whatever the forces (see `driven.rs`).
    pub driven: Vec<Driven>,
    limit_values: Vec<(f64, f64)>,
}

/// Buffers for [`Scene::accelerations`]; build once per scene.
#[derive(Clone, Debug)]
pub struct SceneWorkspace {
    pub(crate) ws: Workspace,
    tau: Vec<f64>,
    fext: Vec<Wrench>,
    poses: Vec<Se3>,
    twists: Vec<Twist>,
    driven: Option<DrivenBuffers>,
}

impl SceneWorkspace {
    pub fn new(scene: &Scene) -> Self {
        let n = scene.model.num_links();
        SceneWorkspace {
            ws: Workspace::new(&scene.model),
            tau: vec![0.0; scene.model.nq()],
            fext: vec![Wrench::zeros(); n],
            poses: vec![Se3::identity(); n],
            twists: vec![Twist::zeros(); n],
            driven: (!scene.driven.is_empty())
                .then(|| DrivenBuffers::new(&scene.model, &scene.driven)),
        }
    }
}

fn finite3(v: &Vector3<f64>) -> bool {
    v.iter().all(|x| x.is_finite())
}

impl Scene {
    /// A scene with no effects at all (not even gravity).
    pub fn new(model: Arc<Model>) -> Self {
        let limit_values = model
            .links()
            .iter()
            .flat_map(|l| {
                l.joint
                    .limits()
                    .into_iter()
                    .take(l.dof)
                    .map(|x| (x.lower, x.upper))
            })
            .collect();
        Scene {
            model,
            gravity: None,
            damping: None,
            springs: vec![],
            forces: vec![],
            limits: None,
            driven: vec![],
            limit_values,
        }
    }

    pub fn with_gravity(mut self, g: Vector3<f64>) -> Result<Self, DynamicsError> {
        if !finite3(&g) {
            return Err(DynamicsError::Input(
                "gravity must be a finite vector".into(),
            ));
        }
        self.gravity = Some(g);
        Ok(self)
    }

    /// Joint damping: one coefficient for every coordinate, or one per coordinate.
    pub fn with_damping(mut self, d: &[f64]) -> Result<Self, DynamicsError> {
        let n = self.model.nq();
        let d = match d.len() {
            1 => vec![d[0]; n],
            k if k == n => d.to_vec(),
            k => {
                return Err(DynamicsError::Input(format!(
                    "damping: give one coefficient or one per coordinate ({n}), not {k}"
                )));
            }
        };
        if d.iter().any(|x| !x.is_finite() || *x < 0.0) {
            return Err(DynamicsError::Input(
                "damping coefficients must be finite and ≥ 0".into(),
            ));
        }
        self.damping = Some(d);
        Ok(self)
    }

    pub fn with_spring(mut self, s: Spring) -> Result<Self, DynamicsError> {
        for l in [s.link_a, s.link_b].into_iter().flatten() {
            if l >= self.model.num_links() {
                return Err(DynamicsError::Input(format!(
                    "spring: link index {l} out of range (the model has {} links)",
                    self.model.num_links()
                )));
            }
        }
        let ok = [s.stiffness, s.damping, s.rest_length]
            .iter()
            .all(|x| x.is_finite() && *x >= 0.0);
        if !ok || !finite3(&s.point_a) || !finite3(&s.point_b) {
            return Err(DynamicsError::Input(
                "spring: stiffness, damping and rest length must be finite and ≥ 0, points finite"
                    .into(),
            ));
        }
        self.springs.push(s);
        Ok(self)
    }

    pub fn with_force(mut self, f: ExternalForce) -> Result<Self, DynamicsError> {
        if f.link >= self.model.num_links() {
            return Err(DynamicsError::Input(format!(
                "force: link index {} out of range (the model has {} links)",
                f.link,
                self.model.num_links()
            )));
        }
        if !finite3(&f.point) || !finite3(&f.force) {
            return Err(DynamicsError::Input(
                "force: point and force must be finite".into(),
            ));
        }
        self.forces.push(f);
        Ok(self)
    }

    pub fn with_limits(mut self, p: LimitPenalty) -> Result<Self, DynamicsError> {
        if !(p.stiffness.is_finite()
            && p.stiffness >= 0.0
            && p.damping.is_finite()
            && p.damping >= 0.0)
        {
            return Err(DynamicsError::Input(
                "limit penalty: stiffness and damping must be finite and ≥ 0".into(),
            ));
        }
        self.limits = Some(p);
        Ok(self)
    }

    /// Drives a coordinate at a constant `rate` (its velocity, set in the
    /// initial state by [`Scene::drive_state`]): it moves whatever the forces.
    pub fn with_driven(mut self, coordinate: usize, rate: f64) -> Result<Self, DynamicsError> {
        let n = self.model.nq();
        if coordinate >= n {
            return Err(DynamicsError::Input(format!(
                "driven coordinate index {coordinate} out of range (the model has {n})"
            )));
        }
        if !rate.is_finite() {
            return Err(DynamicsError::Input("a driven rate must be finite".into()));
        }
        if self.driven.iter().any(|d| d.coordinate == coordinate) {
            return Err(DynamicsError::Input(format!(
                "coordinate `{}` is driven twice",
                self.model.coordinate_names()[coordinate]
            )));
        }
        if self.driven.len() + 1 >= n {
            return Err(DynamicsError::Input(
                "every coordinate would be driven: leave at least one free".into(),
            ));
        }
        self.driven.push(Driven { coordinate, rate });
        Ok(self)
    }

    /// Sets the velocities of the driven coordinates to their rates.
    pub fn drive_state(&self, v: &mut [f64]) {
        for d in &self.driven {
            if let Some(x) = v.get_mut(d.coordinate) {
                *x = d.rate;
            }
        }
    }

    /// The final solve: O(n) articulated-body forward dynamics, or with driven
    /// coordinates the constrained solve of `driven.rs`.
    fn solve(
        &self,
        sw_ws: &mut Workspace,
        driven: &mut Option<DrivenBuffers>,
        q: &[f64],
        v: &[f64],
        forces: &Forces,
        qdd: &mut [f64],
    ) -> Result<(), DynamicsError> {
        let m = &*self.model;
        if self.driven.is_empty() {
            return aba_core(m, sw_ws, q, v, forces, qdd);
        }
        let buf = driven.get_or_insert_with(|| DrivenBuffers::new(m, &self.driven));
        driven_accelerations(m, sw_ws, buf, q, v, forces, qdd)
    }

    pub fn nq(&self) -> usize {
        self.model.nq()
    }

    fn gravity_or_zero(&self) -> Vector3<f64> {
        self.gravity.unwrap_or_else(Vector3::zeros)
    }

    /// World poses and body twists of all links (only needed by springs and forces).
    fn point_kinematics(&self, sw: &mut SceneWorkspace, q: &[f64], v: &[f64]) {
        let m = &*self.model;
        for (i, l) in m.links().iter().enumerate() {
            let r = l.q_index..l.q_index + l.dof;
            let kin = &mut sw.ws.scratch;
            l.joint
                .kinematics(&q[r.clone()], Derivatives::Jacobian, kin);
            let x = l.offset.compose(&kin.transform);
            let mut sv = Twist::zeros();
            for (j, vj) in v[r].iter().enumerate() {
                sv += kin.s[j] * *vj;
            }
            let (pose, tw) = match l.parent {
                Some(p) => (sw.poses[p].compose(&x), x.inv_ad_twist(&sw.twists[p]) + sv),
                None => (x, sv),
            };
            sw.poses[i] = pose;
            sw.twists[i] = tw;
        }
    }

    /// World position and velocity of a point attached to a link (or the world).
    fn point_state(
        sw: &SceneWorkspace,
        link: Option<usize>,
        p: &Vector3<f64>,
    ) -> (Vector3<f64>, Vector3<f64>) {
        match link {
            None => (*p, Vector3::zeros()),
            Some(i) => {
                let t = &sw.poses[i];
                let tw = &sw.twists[i];
                let w = tw.fixed_rows::<3>(0).into_owned();
                let vl = tw.fixed_rows::<3>(3).into_owned();
                (t.act_point(p), t.r * (vl + w.cross(p)))
            }
        }
    }

    /// Adds a world-frame force at a link point to that link's external wrench.
    fn add_force(sw: &mut SceneWorkspace, link: usize, p: &Vector3<f64>, f: &Vector3<f64>) {
        let fl = sw.poses[link].r.transpose() * f;
        let mu = p.cross(&fl);
        sw.fext[link] += Vector6::new(mu.x, mu.y, mu.z, fl.x, fl.y, fl.z);
    }

    /// `q̈` under the declared effects, with extra applied joint torques `tau_applied`
    /// (empty slice for none).
    pub fn accelerations(
        &self,
        sw: &mut SceneWorkspace,
        q: &[f64],
        v: &[f64],
        tau_applied: &[f64],
        qdd: &mut [f64],
    ) -> Result<(), DynamicsError> {
        let m = &*self.model;
        sw.ws.check(m)?;
        m.check_vec("q", q, m.nq())?;
        m.check_vec("v", v, m.nq())?;
        if !tau_applied.is_empty() {
            m.check_vec("tau", tau_applied, m.nq())?;
            sw.tau.copy_from_slice(tau_applied);
        } else {
            sw.tau.iter_mut().for_each(|x| *x = 0.0);
        }
        if qdd.len() != m.nq() {
            return Err(DynamicsError::Input(format!(
                "qdd must have {} entries",
                m.nq()
            )));
        }
        if let Some(d) = &self.damping {
            for k in 0..d.len() {
                sw.tau[k] -= d[k] * v[k];
            }
        }
        if let Some(p) = &self.limits {
            for (k, &(lo, hi)) in self.limit_values.iter().enumerate() {
                if q[k] < lo {
                    sw.tau[k] += p.stiffness * (lo - q[k]) - p.damping * v[k].min(0.0);
                } else if q[k] > hi {
                    sw.tau[k] += p.stiffness * (hi - q[k]) - p.damping * v[k].max(0.0);
                }
            }
        }
        let g = self.gravity_or_zero();
        let tau = std::mem::take(&mut sw.tau);
        let r = if self.springs.is_empty() && self.forces.is_empty() {
            self.solve(
                &mut sw.ws,
                &mut sw.driven,
                q,
                v,
                &Forces::new(&tau, &g),
                qdd,
            )
        } else {
            sw.fext.iter_mut().for_each(|f| *f = Wrench::zeros());
            self.point_kinematics(sw, q, v);
            for s in &self.springs {
                let (pa, va) = Self::point_state(sw, s.link_a, &s.point_a);
                let (pb, vb) = Self::point_state(sw, s.link_b, &s.point_b);
                let d = pb - pa;
                let len = d.norm();
                // A zero-length spring has no direction: it exerts no force.
                if len > 1e-12 {
                    let u = d / len;
                    let mag = s.stiffness * (len - s.rest_length) + s.damping * u.dot(&(vb - va));
                    let f = u * mag; // pulls a toward b when stretched
                    if let Some(la) = s.link_a {
                        Self::add_force(sw, la, &s.point_a, &f);
                    }
                    if let Some(lb) = s.link_b {
                        Self::add_force(sw, lb, &s.point_b, &(-f));
                    }
                }
            }
            for f in &self.forces {
                // World-frame force: the link frame needs the current pose.
                Self::add_force(sw, f.link, &f.point, &f.force);
            }
            let fext = std::mem::take(&mut sw.fext);
            let r = self.solve(
                &mut sw.ws,
                &mut sw.driven,
                q,
                v,
                &Forces::new(&tau, &g).with_wrenches(&fext),
                qdd,
            );
            sw.fext = fext;
            r
        };
        sw.tau = tau;
        r
    }

    /// Total mechanical energy: kinetic + gravity + spring potential.
    pub fn energy(
        &self,
        sw: &mut SceneWorkspace,
        q: &[f64],
        v: &[f64],
    ) -> Result<f64, DynamicsError> {
        let m = &*self.model;
        let mut e = kinetic_energy(m, &mut sw.ws, q, v)?;
        if let Some(g) = &self.gravity {
            e += potential_energy(m, &mut sw.ws, q, g)?;
        }
        if !self.springs.is_empty() {
            self.point_kinematics(sw, q, v);
            for s in &self.springs {
                let (pa, _) = Self::point_state(sw, s.link_a, &s.point_a);
                let (pb, _) = Self::point_state(sw, s.link_b, &s.point_b);
                let x = (pb - pa).norm() - s.rest_length;
                e += 0.5 * s.stiffness * x * x;
            }
        }
        Ok(e)
    }
}
