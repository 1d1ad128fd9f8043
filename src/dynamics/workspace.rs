//! Preallocated buffers for the dynamics algorithms, and the forward
//! (kinematic) sweep they share.

use crate::dynamics::DynamicsError;
use crate::dynamics::variation::Variation;
use crate::lie::{Se3, Twist, Wrench, ad};
use crate::model::joint::{AxisMotion, Derivatives, JointKinematics, MAX_JOINT_DOF};
use crate::model::{Inertia, Model};
use nalgebra::{Matrix6, Vector3, Vector6};

/// All buffers the algorithms need for one model. Build it once with
/// [`Workspace::new`]; every call then runs without heap allocation.
#[derive(Clone, Debug)]
pub struct Workspace {
    pub(crate) n_links: usize,
    pub(crate) nq: usize,
    /// Joint transform, Jacobian and Hessian per link.
    pub(crate) kin: Vec<JointKinematics>,
    /// Pose of each link in its parent: `offset · G(q)`.
    pub(crate) xt: Vec<Se3>,
    /// Body twist `V_i`.
    pub(crate) v: Vec<Twist>,
    /// Body acceleration `V̇_i` (with the gravity trick: the base accelerates at −g).
    pub(crate) a: Vec<Twist>,
    /// Net wrench transmitted by the joint of each link (after the backward sweep).
    pub(crate) f: Vec<Wrench>,
    /// `S_i q̇_i`.
    pub(crate) sv: Vec<Twist>,
    /// `Ad_{X_i⁻¹} V_parent` and `Ad_{X_i⁻¹} V̇_parent`.
    pub(crate) wv: Vec<Twist>,
    pub(crate) wa: Vec<Twist>,
    /// Velocity-product acceleration `ad(V_i, S q̇) + Ṡ q̇` (body frame after
    /// [`velocity_pass`], world frame after [`world_velocity_pass`]).
    pub(crate) c: Vec<Twist>,
    // ABA
    pub(crate) ia: Vec<Matrix6<f64>>,
    /// Offset of each link's origin from its parent's, world axes.
    pub(crate) shift: Vec<Vector3<f64>>,
    pub(crate) pa: Vec<Wrench>,
    pub(crate) u: Vec<[Twist; MAX_JOINT_DOF]>,
    pub(crate) dinv: Vec<Matrix6<f64>>,
    pub(crate) uu: Vec<[f64; MAX_JOINT_DOF]>,
    // CRBA: composite inertias per link, composite momenta `I^c J` per coordinate
    pub(crate) ic: Vec<Inertia>,
    pub(crate) ag: Vec<Wrench>,
    // adjoint: V̄, Λ, F̄ per link
    pub(crate) dv: Vec<Twist>,
    pub(crate) da: Vec<Twist>,
    pub(crate) df: Vec<Wrench>,
    // derivatives (world frame): per link twist, acceleration, force, inertia variation
    pub(crate) ov: Vec<Twist>,
    pub(crate) oa: Vec<Twist>,
    pub(crate) of: Vec<Wrench>,
    pub(crate) doy: Vec<Variation>,
    // per coordinate: world joint column J and the seeds dV/dq, dA/dq, dA/dq̇
    pub(crate) jw: Vec<Twist>,
    pub(crate) dvdq: Vec<Twist>,
    pub(crate) dadq: Vec<Twist>,
    pub(crate) dadv: Vec<Twist>,
    pub(crate) tau: Vec<f64>,
    pub(crate) scratch: JointKinematics,
    /// World poses (energies, point forces).
    pub(crate) world: Vec<Se3>,
    /// Point forces (`external.rs`): their wrenches per link (link frame)
    /// and, in the adjoint, the sums U_i of their turning terms.
    pub(crate) pf: Vec<Wrench>,
    pub(crate) pu: Vec<Vector3<f64>>,
    /// The mass matrix is computed in link frames rather than the world frame
    /// (decided once per model: `crba_frame::prefers_link_frames`).
    pub(crate) crba_in_link_frames: bool,
}

impl Workspace {
    pub fn new(model: &Model) -> Self {
        let n = model.num_links();
        Workspace {
            n_links: n,
            nq: model.nq(),
            kin: vec![JointKinematics::default(); n],
            xt: vec![Se3::identity(); n],
            v: vec![Twist::zeros(); n],
            a: vec![Twist::zeros(); n],
            f: vec![Wrench::zeros(); n],
            sv: vec![Twist::zeros(); n],
            wv: vec![Twist::zeros(); n],
            wa: vec![Twist::zeros(); n],
            c: vec![Twist::zeros(); n],
            ia: vec![Matrix6::zeros(); n],
            shift: vec![Vector3::zeros(); n],
            pa: vec![Wrench::zeros(); n],
            u: vec![[Twist::zeros(); MAX_JOINT_DOF]; n],
            dinv: vec![Matrix6::zeros(); n],
            uu: vec![[0.0; MAX_JOINT_DOF]; n],
            ic: vec![Inertia::zero(); n],
            ag: vec![Wrench::zeros(); model.nq()],
            dv: vec![Twist::zeros(); n],
            da: vec![Twist::zeros(); n],
            df: vec![Wrench::zeros(); n],
            ov: vec![Twist::zeros(); n],
            oa: vec![Twist::zeros(); n],
            of: vec![Wrench::zeros(); n],
            doy: vec![Variation::zero(); n],
            jw: vec![Twist::zeros(); model.nq()],
            dvdq: vec![Twist::zeros(); model.nq()],
            dadq: vec![Twist::zeros(); model.nq()],
            dadv: vec![Twist::zeros(); model.nq()],
            tau: vec![0.0; model.nq()],
            scratch: JointKinematics::default(),
            world: vec![Se3::identity(); n],
            pf: vec![Wrench::zeros(); n],
            pu: vec![Vector3::zeros(); n],
            crba_in_link_frames: crate::dynamics::crba_frame::prefers_link_frames(model),
        }
    }

    pub(crate) fn check(&self, model: &Model) -> Result<(), DynamicsError> {
        if self.n_links != model.num_links() || self.nq != model.nq() {
            return Err(DynamicsError::Input(format!(
                "this workspace was built for another model ({} links, {} coordinates; `{}` has {} and {}); build one with Workspace::new(&model)",
                self.n_links,
                self.nq,
                model.name,
                model.num_links(),
                model.nq()
            )));
        }
        Ok(())
    }
}

/// The base acceleration that stands for gravity: the world accelerates at −g.
#[inline]
pub(crate) fn base_acceleration(g: &Vector3<f64>) -> Twist {
    Vector6::new(0.0, 0.0, 0.0, -g.x, -g.y, -g.z)
}

/// `Σ_j s_j x_j` over a joint's columns.
#[inline]
pub(crate) fn s_mul(kin: &JointKinematics, x: &[f64]) -> Twist {
    let mut t = Twist::zeros();
    for (j, xj) in x.iter().enumerate() {
        t += kin.s[j] * *xj;
    }
    t
}

/// `Ṡ q̇ = Σ_j Σ_k ∂s_j/∂q_k q̇_k q̇_j`.
#[inline]
pub(crate) fn sdot_v(kin: &JointKinematics, v: &[f64]) -> Twist {
    let mut t = Twist::zeros();
    for (j, vj) in v.iter().enumerate() {
        for (k, vk) in v.iter().enumerate() {
            t += kin.ds[j][k] * (vj * vk);
        }
    }
    t
}

/// Forward sweep shared by the algorithms: joint kinematics, link poses, body
/// twists `V`, their parent parts `wv` and the velocity-product terms `c`.
/// The Hessian is evaluated only for joints whose Jacobian depends on q.
pub(crate) fn velocity_pass(
    model: &Model,
    ws: &mut Workspace,
    q: &[f64],
    v: &[f64],
    hessian: bool,
) {
    for (i, l) in model.links().iter().enumerate() {
        let r = l.q_index..l.q_index + l.dof;
        let sv = match &l.axis {
            // Revolute/prismatic (most URDF and BVH links): a constant column,
            // placed directly, without the generic joint call.
            Some(axis) => {
                let s = axis.twist();
                ws.kin[i].s[0] = s;
                ws.xt[i] = axis.place(&l.offset, q[l.q_index]);
                s * v[l.q_index]
            }
            None => {
                let want = if hessian && !l.constant_jacobian {
                    Derivatives::Hessian
                } else {
                    Derivatives::Jacobian
                };
                l.joint.kinematics(&q[r.clone()], want, &mut ws.kin[i]);
                ws.xt[i] = l.offset.compose(&ws.kin[i].transform);
                s_mul(&ws.kin[i], &v[r.clone()])
            }
        };
        let wv = match l.parent {
            Some(p) => ws.xt[i].inv_ad_twist(&ws.v[p]),
            None => Twist::zeros(),
        };
        let vi = wv + sv;
        let mut c = ad(&vi, &sv);
        if !l.constant_jacobian {
            c += sdot_v(&ws.kin[i], &v[r]);
        }
        ws.wv[i] = wv;
        ws.sv[i] = sv;
        ws.v[i] = vi;
        ws.c[i] = c;
    }
}

/// The world-frame forward sweep of the derivatives: world
/// poses `T_i`, joint columns `J = Ad_T S` (`jw`, per coordinate), twists `ov`
/// and velocity-product accelerations `c = v_λ × J q̇ + Ad_T (Ṡ q̇)`. The Hessian
/// is evaluated only for joints whose Jacobian depends on q.
pub(crate) fn world_velocity_pass(model: &Model, ws: &mut Workspace, q: &[f64], v: &[f64]) {
    frame_velocity_pass::<false>(model, ws, q, v);
}

/// The same sweep in link-aligned frames (the articulated-body algorithm's):
/// each link's quantities are expressed with the world's axes at the link's
/// origin, so `J = R S` and every twist is moved from the parent's origin by the
/// shift `d_i` (also stored, in `shift`). Precise on links far from the world
/// origin, where world-frame twists lose digits.
pub(crate) fn aligned_velocity_pass(model: &Model, ws: &mut Workspace, q: &[f64], v: &[f64]) {
    frame_velocity_pass::<true>(model, ws, q, v);
}

/// The forward sweep of [`world_velocity_pass`] (`ALIGNED = false`) and
/// [`aligned_velocity_pass`] (`true`); one loop, monomorphised per frame.
#[inline(always)]
fn frame_velocity_pass<const ALIGNED: bool>(
    model: &Model,
    ws: &mut Workspace,
    q: &[f64],
    v: &[f64],
) {
    for (i, l) in model.links().iter().enumerate() {
        let qi = l.q_index;
        let (vp, origin) = match l.parent {
            Some(p) => (ws.ov[p], ws.world[p].p),
            None => (Twist::zeros(), Vector3::zeros()),
        };
        // The frame the joint moves in: the parent's placement times the fixed
        // offset (most URDF offsets only translate: no rotation product then).
        let before = match (l.parent, l.offset_rotates) {
            (Some(p), true) => ws.world[p].compose(&l.offset),
            (Some(p), false) => ws.world[p].translated(&l.offset.p),
            (None, _) => l.offset,
        };
        let (t, c, vi) = match &l.axis {
            // Revolute/prismatic (most URDF links): placed through the cached
            // axis, one column, no Hessian: the generic joint call, a 3×3
            // rotation product and a full `Ad` of the column are skipped.
            Some(axis) => {
                let t = axis.place(&before, q[qi]);
                let (jm, vp) = if ALIGNED {
                    let d = t.p - origin;
                    ws.shift[i] = d;
                    let u = axis.direction_in(&t.r);
                    let jm = match axis.motion {
                        AxisMotion::Rotation => Twist::new(u.x, u.y, u.z, 0.0, 0.0, 0.0),
                        AxisMotion::Translation => Twist::new(0.0, 0.0, 0.0, u.x, u.y, u.z),
                    };
                    (jm, shift_twist(&vp, &d))
                } else {
                    (axis.twist_in(&t), vp)
                };
                ws.jw[qi] = jm;
                let vj = jm * v[qi];
                // v_i × J q̇ = v_λ × J q̇: the J q̇ × J q̇ part vanishes.
                (t, ad(&vp, &vj), vp + vj)
            }
            None => {
                let r = qi..qi + l.dof;
                let want = if l.constant_jacobian {
                    Derivatives::Jacobian
                } else {
                    Derivatives::Hessian
                };
                l.joint.kinematics(&q[r.clone()], want, &mut ws.kin[i]);
                let t = before.compose(&ws.kin[i].transform);
                // the frame the link's quantities are expressed in, and the
                // parent's twist moved into it
                let (frame, vp) = if ALIGNED {
                    let d = t.p - origin;
                    ws.shift[i] = d;
                    (Se3::from_rotation(t.r), shift_twist(&vp, &d))
                } else {
                    (t, vp)
                };
                let kin = &ws.kin[i];
                let mut vj = Twist::zeros();
                for m in 0..l.dof {
                    let jm = frame.ad_twist(&kin.s[m]);
                    ws.jw[qi + m] = jm;
                    vj += jm * v[qi + m];
                }
                let mut c = ad(&vp, &vj);
                if !l.constant_jacobian {
                    c += frame.ad_twist(&sdot_v(kin, &v[r]));
                }
                (t, c, vp + vj)
            }
        };
        ws.world[i] = t;
        ws.ov[i] = vi;
        ws.c[i] = c;
    }
}

/// A twist given at one origin, expressed at an origin `d` further (same axes).
#[inline]
pub(crate) fn shift_twist(x: &Twist, d: &Vector3<f64>) -> Twist {
    let w = Vector3::new(x[0], x[1], x[2]);
    let v = Vector3::new(x[3], x[4], x[5]) + w.cross(d);
    Twist::new(w.x, w.y, w.z, v.x, v.y, v.z)
}
