//! Root motion over a transition (Rose §3.2.1): the root is kinematic.
//!
//! The floor is the x–z plane (y up). Horizontally the root velocity is
//! interpolated linearly from v₁ (end of the first motion, t₁) to v₂ (start of
//! the second, t₂) and integrated from p(t₁):
//!
//!   p(t) = p(t₁) + v₁ (t − t₁) + (v₂ − v₁) (t − t₁)² / (2T),   T = t₂ − t₁,
//!
//! a C¹ path that ends where the integration takes it, generally not where the
//! second motion starts; the caller translates the second motion in x–z by
//! [`RootTransition::shift`] so the two join up (a walk followed by a run
//! recorded elsewhere in the room). Vertically the paper interpolates y
//! linearly; we use the cubic Hermite curve between the same end heights and
//! vertical velocities, which keeps y C¹ like x–z (and is linear when both end
//! velocities equal the secant slope).

use super::error::{SpError, invalid};
use super::hermite;
use super::transition::EndState;

/// The root's horizontal and vertical states at both ends of a gap.
#[derive(Clone, Debug, PartialEq)]
pub struct RootTransition {
    pub t1: f64,
    pub t2: f64,
    /// x, z at t₁ and their velocities at t₁ and t₂.
    pub p1: [f64; 2],
    pub v1: [f64; 2],
    pub v2: [f64; 2],
    /// y at both ends (position and velocity).
    pub y1: EndState,
    pub y2: EndState,
}

impl RootTransition {
    pub fn new(
        t1: f64,
        t2: f64,
        p1: [f64; 2],
        v1: [f64; 2],
        v2: [f64; 2],
        y1: EndState,
        y2: EndState,
    ) -> Result<Self, SpError> {
        if !(t1.is_finite() && t2.is_finite()) || t2 <= t1 {
            return Err(invalid(format!(
                "root transition span [{t1}, {t2}] must have positive finite length"
            )));
        }
        let all = [
            p1[0], p1[1], v1[0], v1[1], v2[0], v2[1], y1.q, y1.v, y2.q, y2.v,
        ];
        if all.iter().any(|v| !v.is_finite()) {
            return Err(invalid(
                "the root's end states around the gap are not finite",
            ));
        }
        Ok(RootTransition {
            t1,
            t2,
            p1,
            v1,
            v2,
            y1,
            y2,
        })
    }

    /// Horizontal [x, z] position, velocity and acceleration at t (clamped into the gap).
    pub fn xz(&self, t: f64) -> [[f64; 2]; 3] {
        let tt = self.t2 - self.t1;
        let s = (t.clamp(self.t1, self.t2)) - self.t1;
        let mut out = [[0.0; 2]; 3];
        #[allow(clippy::needless_range_loop)] // i indexes four arrays at once
        for i in 0..2 {
            let dv = self.v2[i] - self.v1[i];
            out[0][i] = self.p1[i] + self.v1[i] * s + dv * s * s / (2.0 * tt);
            out[1][i] = self.v1[i] + dv * s / tt;
            out[2][i] = dv / tt;
        }
        out
    }

    /// y, ẏ, ÿ at t.
    pub fn y(&self, t: f64) -> [f64; 3] {
        hermite::cubic(self.t1, self.t2, &self.y1, &self.y2, t)
    }

    /// Where the integrated path ends: p(t₂) = p(t₁) + T (v₁ + v₂)/2.
    pub fn end_xz(&self) -> [f64; 2] {
        self.xz(self.t2)[0]
    }

    /// The x–z translation to apply to the motion after the gap so that it
    /// starts at p(t₂), given where it starts now.
    pub fn shift(&self, second_start_xz: [f64; 2]) -> [f64; 2] {
        let e = self.end_xz();
        [e[0] - second_start_xz[0], e[1] - second_start_xz[1]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rt(v1: [f64; 2], v2: [f64; 2]) -> RootTransition {
        RootTransition::new(
            1.0,
            1.6,
            [0.5, -2.0],
            v1,
            v2,
            EndState {
                q: 0.9,
                v: 0.1,
                a: 0.0,
            },
            EndState {
                q: 0.95,
                v: -0.2,
                a: 0.0,
            },
        )
        .unwrap()
    }

    #[test]
    fn matches_velocities_and_integrates_the_linear_velocity() {
        let r = rt([1.2, 0.1], [3.0, -0.4]);
        let s = r.xz(1.0);
        assert_eq!(s[0], [0.5, -2.0]);
        assert_eq!(s[1], [1.2, 0.1]);
        let e = r.xz(1.6);
        assert!((e[1][0] - 3.0).abs() < 1e-14 && (e[1][1] + 0.4).abs() < 1e-14);
        // trapezoid of a linear velocity is exact
        let end = r.end_xz();
        assert!((end[0] - (0.5 + 0.6 * (1.2 + 3.0) / 2.0)).abs() < 1e-14);
        assert!((end[1] - (-2.0 + 0.6 * (0.1 - 0.4) / 2.0)).abs() < 1e-14);
        // derivative consistency
        let h = 1e-6;
        let d = (r.xz(1.3 + h)[0][0] - r.xz(1.3 - h)[0][0]) / (2.0 * h);
        assert!((d - r.xz(1.3)[1][0]).abs() < 1e-8);
    }

    #[test]
    fn shift_moves_the_second_motion_onto_the_path() {
        let r = rt([1.0, 0.0], [1.0, 0.0]);
        // the run was recorded 3 m away
        let sh = r.shift([3.6, 1.0]);
        assert!((sh[0] - (1.1 - 3.6)).abs() < 1e-14 && (sh[1] - (-2.0 - 1.0)).abs() < 1e-14);
    }

    #[test]
    fn y_is_c1_at_both_ends() {
        let r = rt([0.0; 2], [0.0; 2]);
        let a = r.y(1.0);
        let b = r.y(1.6);
        assert!((a[0] - 0.9).abs() < 1e-15 && (a[1] - 0.1).abs() < 1e-12);
        assert!((b[0] - 0.95).abs() < 1e-15 && (b[1] + 0.2).abs() < 1e-12);
    }

    #[test]
    fn degenerate_spans_are_errors() {
        let y = EndState::default();
        assert!(RootTransition::new(1.0, 1.0, [0.0; 2], [0.0; 2], [0.0; 2], y, y).is_err());
        assert!(RootTransition::new(1.0, 0.0, [0.0; 2], [0.0; 2], [0.0; 2], y, y).is_err());
        assert!(RootTransition::new(0.0, 1.0, [f64::NAN, 0.0], [0.0; 2], [0.0; 2], y, y).is_err());
    }
}

/// Which coordinates of a body are its root (Rose §3.2.1: positioned
/// kinematically, not by torques), and which of them translate horizontally
/// or vertically.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct RootCoords {
    /// Every root coordinate (its virtual forces are excluded from torque sums).
    pub all: Vec<usize>,
    /// Translations along horizontal world axes (the floor plane).
    pub horizontal: Vec<usize>,
    /// Translation along the vertical.
    pub vertical: Vec<usize>,
    /// Root rotations (interpolated by the cubic Hermite curve over a gap).
    pub rotations: Vec<usize>,
    /// Coordinates of massless links above the moving root that stay constant
    /// in the motion (the Bandai skeletons' all-zero `joint_Root`): they place
    /// the body rather than move it. They are in `all` (the world's force on
    /// the body passes through them unchanged, so counting them would count
    /// the root's virtual forces) and a gap in them is bridged by Hermite.
    pub fixed: Vec<usize>,
}

impl RootCoords {
    /// The root of `model`: the chain of links from the world while they are
    /// massless and have one child, up to and including the first link with
    /// mass (a 6-DOF free joint, or BVH/URDF roots written as three slides and
    /// three hinges). Translational coordinates are classified against
    /// `up = −gravity` at q = 0; a translation neither horizontal nor vertical
    /// (a tilted slide) is treated like a rotation.
    pub fn detect(model: &crate::model::Model, gravity: &nalgebra::Vector3<f64>) -> RootCoords {
        Self::detect_with(model, gravity, |_| false)
    }

    /// The root of `model` as it moves in `motion`: as [`detect`](Self::detect),
    /// but leading massless single-child links whose coordinates are all
    /// constant in `motion` are skipped (listed in `fixed`), and the root is
    /// the chain from the first link that moves. A skeleton whose top joint is
    /// a constant placeholder (Bandai's `joint_Root`, six zero channels above
    /// the moving `Hips`) so gets `Hips` as its root, as a skeleton without
    /// the placeholder would. If nothing on that chain moves (a motion that
    /// stands still) nothing is skipped. Coordinates the motion does not name,
    /// or whose curves are not provably constant, count as moving.
    pub fn detect_in(
        model: &crate::model::Model,
        gravity: &nalgebra::Vector3<f64>,
        motion: &crate::motion::Mu,
    ) -> RootCoords {
        let names = model.coordinate_names();
        Self::detect_with(model, gravity, |c| {
            motion
                .get(&names[c])
                .is_some_and(|d| is_constant(d, &names[c]))
        })
    }

    fn detect_with(
        model: &crate::model::Model,
        gravity: &nalgebra::Vector3<f64>,
        constant: impl Fn(usize) -> bool,
    ) -> RootCoords {
        use crate::model::{Derivatives, JointKinematics};
        let mut out = RootCoords::default();
        if model.num_links() == 0 || model.link(0).parent.is_some() {
            return out;
        }
        let up = if gravity.norm() > 0.0 {
            -gravity / gravity.norm()
        } else {
            nalgebra::Vector3::z()
        };
        let q0 = vec![0.0; model.nq()];
        let mut poses = vec![];
        if model.forward_kinematics(&q0, &mut poses).is_err() {
            return out;
        }
        let start = moving_root_link(model, &constant);
        let mut link = 0;
        while link != start {
            let l = model.link(link);
            out.all.extend(l.q_index..l.q_index + l.dof);
            out.fixed.extend(l.q_index..l.q_index + l.dof);
            link = model.children(link)[0];
        }
        let mut jk = JointKinematics::default();
        loop {
            let l = model.link(link);
            l.joint.kinematics(
                &q0[l.q_index..l.q_index + l.dof],
                Derivatives::Jacobian,
                &mut jk,
            );
            for j in 0..l.dof {
                let c = l.q_index + j;
                out.all.push(c);
                let s = jk.s[j];
                let w = nalgebra::Vector3::new(s[0], s[1], s[2]);
                let v = nalgebra::Vector3::new(s[3], s[4], s[5]);
                if w.norm() < 1e-12 && v.norm() > 0.0 {
                    let axis = poses[link].r * v / v.norm();
                    let d = axis.dot(&up).abs();
                    if d > 1.0 - 1e-9 {
                        out.vertical.push(c);
                    } else if d < 1e-9 {
                        out.horizontal.push(c);
                    } else {
                        out.rotations.push(c);
                    }
                } else {
                    out.rotations.push(c);
                }
            }
            let children = model.children(link);
            if l.inertia.mass > 0.0 || children.len() != 1 {
                break;
            }
            link = children[0];
        }
        out
    }
}

/// The first link from the world, down the chain of massless single-child
/// links, that has a coordinate not `constant`; the world's first link (0)
/// when there is none (nothing to skip).
fn moving_root_link(model: &crate::model::Model, constant: &impl Fn(usize) -> bool) -> usize {
    let mut link = 0;
    loop {
        let l = model.link(link);
        if (l.q_index..l.q_index + l.dof).any(|c| !constant(c)) {
            return link;
        }
        let children = model.children(link);
        if l.inertia.mass > 0.0 || children.len() != 1 {
            return 0;
        }
        link = children[0];
    }
}

/// Whether `dof` holds one value wherever it is defined: every curve is
/// constant by construction (a constant, equal samples, a flat Hermite or
/// spline) and every interval starts at the same value. Curves given as
/// functions cannot be inspected and count as moving.
fn is_constant(dof: &crate::motion::Dof, name: &str) -> bool {
    use crate::motion::Curve;
    let flat = |v: &[f64]| v.iter().all(|x| *x == v[0]);
    let curves_flat = dof
        .intervals
        .iter()
        .flat_map(|i| &i.funcs)
        .all(|f| match f.curve.as_ref() {
            Curve::Constant(_) => true,
            Curve::Samples(s) => flat(s.values()),
            Curve::Hermite(h) => h.q0 == h.q1 && h.v0 == 0.0 && h.v1 == 0.0,
            Curve::Spline(c) => flat(&c.coeffs),
            Curve::Function(_) => false,
        });
    if !curves_flat {
        return false;
    }
    let mut first = None;
    for iv in &dof.intervals {
        let Ok(Some(v)) = dof.sample_value(name, iv.start) else {
            return false; // conflicting or undefined: not provably constant
        };
        match first {
            None => first = Some(v),
            Some(f) if (v - f).abs() <= 1e-12 * f64::max(1.0, f.abs()) => {}
            Some(_) => return false,
        }
    }
    true
}

#[cfg(test)]
mod detect_tests {
    use super::*;
    use crate::lie::Se3;
    use crate::model::joints::{Prismatic, Revolute};
    use crate::model::{Inertia, Model};
    use nalgebra::Vector3;
    use std::sync::Arc;

    #[test]
    fn slides_and_hinges_to_the_first_massive_link() {
        let mut m = Model::new("t");
        let z = Inertia::zero();
        let mut p = None;
        for (i, ax) in [Vector3::x(), Vector3::y(), Vector3::z()]
            .into_iter()
            .enumerate()
        {
            p = Some(
                m.add_link(
                    &format!("s{i}"),
                    p,
                    &format!("t{i}"),
                    Arc::new(Prismatic::new(ax).unwrap()),
                    Se3::identity(),
                    z,
                )
                .unwrap(),
            );
        }
        let pelvis = Inertia::point(10.0, Vector3::zeros()).unwrap();
        let r = m
            .add_link(
                "pelvis",
                p,
                "rz",
                Arc::new(Revolute::new(Vector3::z()).unwrap()),
                Se3::identity(),
                pelvis,
            )
            .unwrap();
        m.add_link(
            "thigh",
            Some(r),
            "hip",
            Arc::new(Revolute::new(Vector3::x()).unwrap()),
            Se3::identity(),
            pelvis,
        )
        .unwrap();
        let rc = RootCoords::detect(&m, &Vector3::new(0.0, -9.8, 0.0)); // y up
        assert_eq!(rc.all, vec![0, 1, 2, 3]);
        assert_eq!(rc.horizontal, vec![0, 2]);
        assert_eq!(rc.vertical, vec![1]);
        assert_eq!(rc.rotations, vec![3]);
    }
}

#[cfg(test)]
mod detect_in_tests {
    use super::*;
    use crate::lie::Se3;
    use crate::model::joints::{Prismatic, Revolute};
    use crate::model::{Inertia, Model};
    use crate::motion::{Curve, Dof, Interval, Mu};
    use nalgebra::Vector3;
    use std::sync::Arc;

    /// A placeholder slide (`place`) above a moving slide pair (`x`, `y`) and
    /// a massive hinge, as Bandai's `joint_Root` sits above `Hips`.
    fn model() -> Model {
        let mut m = Model::new("t");
        let z = Inertia::zero();
        let slide = |ax| Arc::new(Prismatic::new(ax).unwrap());
        let p = m
            .add_link(
                "place",
                None,
                "place",
                slide(Vector3::x()),
                Se3::identity(),
                z,
            )
            .unwrap();
        let p = m
            .add_link("sx", Some(p), "x", slide(Vector3::x()), Se3::identity(), z)
            .unwrap();
        let p = m
            .add_link("sy", Some(p), "y", slide(Vector3::y()), Se3::identity(), z)
            .unwrap();
        let mass = Inertia::point(10.0, Vector3::zeros()).unwrap();
        let r = m
            .add_link(
                "pelvis",
                Some(p),
                "rz",
                Arc::new(Revolute::new(Vector3::z()).unwrap()),
                Se3::identity(),
                mass,
            )
            .unwrap();
        m.add_link(
            "thigh",
            Some(r),
            "hip",
            Arc::new(Revolute::new(Vector3::x()).unwrap()),
            Se3::identity(),
            mass,
        )
        .unwrap();
        m
    }

    fn motion(values: &[(&str, Vec<f64>)]) -> Mu {
        let mut mu = Mu::new();
        for (n, v) in values {
            let stop = 0.1 * (v.len() - 1) as f64;
            let c = Curve::samples(0.0, 0.1, v.clone()).unwrap();
            mu.insert(
                n.to_string(),
                Dof::new(vec![Interval::curve(c, 0.0, stop).unwrap()]).unwrap(),
            );
        }
        mu
    }

    const Y_UP: Vector3<f64> = Vector3::new(0.0, -9.8, 0.0);

    #[test]
    fn a_constant_placeholder_above_the_moving_root_is_skipped() {
        let m = model();
        let mu = motion(&[
            ("place", vec![0.0; 4]),
            ("x", vec![0.0, 0.1, 0.3, 0.6]),
            ("y", vec![0.9; 4]),
            ("rz", vec![0.0, 0.1, 0.0, 0.1]),
            ("hip", vec![0.2, 0.1, 0.0, 0.1]),
        ]);
        let rc = RootCoords::detect_in(&m, &Y_UP, &mu);
        assert_eq!(rc.fixed, vec![0]);
        assert_eq!(rc.all, vec![0, 1, 2, 3]);
        assert_eq!(rc.horizontal, vec![1]);
        assert_eq!(rc.vertical, vec![2]);
        assert_eq!(rc.rotations, vec![3]);
        // structure alone takes the placeholder as the root's first slide
        let plain = RootCoords::detect(&m, &Y_UP);
        assert_eq!(plain.horizontal, vec![0, 1]);
        assert!(plain.fixed.is_empty());
    }

    #[test]
    fn a_moving_placeholder_or_a_still_body_skips_nothing() {
        let m = model();
        let plain = RootCoords::detect(&m, &Y_UP);
        let moving = motion(&[("place", vec![0.0, 0.0, 0.5, 0.0]), ("x", vec![0.0; 4])]);
        assert_eq!(RootCoords::detect_in(&m, &Y_UP, &moving), plain);
        // nothing on the root chain moves: the structural root stands
        let still = motion(&[
            ("place", vec![0.0; 4]),
            ("x", vec![1.0; 4]),
            ("y", vec![0.9; 4]),
            ("rz", vec![0.3; 4]),
        ]);
        assert_eq!(RootCoords::detect_in(&m, &Y_UP, &still), plain);
        // a DOF the motion lacks counts as moving
        assert_eq!(RootCoords::detect_in(&m, &Y_UP, &Mu::new()), plain);
    }
}
