//! The placement of a link whose joint turns about a coordinate axis behind an
//! offset that only translates (most URDF links): `X = (Rot_k(θ), p)`. Moving a
//! wrench or an inertia across such a placement touches only the two
//! coordinates the turn mixes, so the link-frame CRBA takes it instead of a
//! general `Se3`: 14 multiplications per wrench instead of 24, about 35 per
//! inertia instead of 75. (Tried in the RNEA too: with the axis a run-time
//! index it cost 3 % more instructions there, 40.5k -> 41.7k on human44.)

use crate::lie::Wrench;
use crate::model::Inertia;
use crate::model::joint::AxisMotion;
use crate::model::tree::Link;
use nalgebra::{Matrix3, Vector3};

/// `X = (Rot_k(θ), p)` with `sin θ`, `cos θ`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct AxisTurn {
    k: usize,
    s: f64,
    c: f64,
    p: Vector3<f64>,
}

impl AxisTurn {
    /// The turn placing link `l` at coordinate `q`, when its joint turns about
    /// `±e_k` and its offset only translates (θ = ±q, as `JointAxis::place`).
    #[inline]
    pub(crate) fn of(l: &Link, q: f64) -> Option<(AxisTurn, f64)> {
        let axis = l.axis.as_ref()?;
        if l.offset_rotates || axis.motion != AxisMotion::Rotation {
            return None;
        }
        let (k, sign) = axis.principal()?;
        let (s, c) = (sign * q).sin_cos();
        Some((
            AxisTurn {
                k,
                s,
                c,
                p: l.offset.p,
            },
            sign,
        ))
    }

    /// The axis index `k`.
    #[inline(always)]
    pub(crate) fn axis(&self) -> usize {
        self.k
    }

    /// `Ad*_X⁻¹ f` for every wrench of `fs`: wrenches given in the link frame,
    /// in the parent frame. The axis is matched once, outside the loop.
    #[inline]
    pub(crate) fn ad_wrenches(&self, fs: &mut [Wrench]) {
        match self.k {
            0 => self.ad_wrenches_k::<0>(fs),
            1 => self.ad_wrenches_k::<1>(fs),
            _ => self.ad_wrenches_k::<2>(fs),
        }
    }

    /// An inertia given in the link frame, expressed in the parent frame.
    #[inline]
    pub(crate) fn inertia_to_parent(&self, y: &Inertia) -> Inertia {
        match self.k {
            0 => self.inertia_to_parent_k::<0>(y),
            1 => self.inertia_to_parent_k::<1>(y),
            _ => self.inertia_to_parent_k::<2>(y),
        }
    }

    // The axis is a constant of each function below, so every index is known
    // at compile time and the vectors stay in registers. With `k` a run-time
    // index (and the placement matched per wrench) the link-frame CRBA took
    // twice the time at 10 % more instructions (#37). Measured in one process
    // (bench `dynamics`, µs per call, before → after): TALOS (44 coordinates)
    // 6.68 → 3.47, a 36-coordinate human 5.42 → 2.66, a 60-link chain 27.7 →
    // 11.4; instructions 58.5k → 52.4k on TALOS. Cachegrind found no cause in
    // memory (a few hundred L1 misses per call, no LL misses, in both) nor in
    // branches (155 → 183 mispredicts per call: more after, yet faster); what
    // is left is a stall no count shows. Our reading, not observed directly
    // (this VM has no cycle counters): the two coordinates a turn mixes went
    // to the stack one element at a time and were read back as whole vectors,
    // which cannot forward from two narrower stores, so each load waited for
    // the stores to retire, on every wrench of every subtree.
    /// `Rot_k(θ) x`.
    #[inline(always)]
    fn rotate<const K: usize>(&self, x: &Vector3<f64>) -> Vector3<f64> {
        let (a, b) = ((K + 1) % 3, (K + 2) % 3);
        let mut y = *x;
        y[a] = self.c * x[a] - self.s * x[b];
        y[b] = self.s * x[a] + self.c * x[b];
        y
    }

    #[inline(always)]
    fn ad_wrench_k<const K: usize>(&self, f: &Wrench) -> Wrench {
        let m0 = Vector3::new(f[0], f[1], f[2]);
        let n0 = Vector3::new(f[3], f[4], f[5]);
        let n = self.rotate::<K>(&n0);
        let m = self.rotate::<K>(&m0) + self.p.cross(&n);
        Wrench::new(m.x, m.y, m.z, n.x, n.y, n.z)
    }

    fn ad_wrenches_k<const K: usize>(&self, fs: &mut [Wrench]) {
        for f in fs {
            *f = self.ad_wrench_k::<K>(f);
        }
    }

    fn inertia_to_parent_k<const K: usize>(&self, y: &Inertia) -> Inertia {
        let (k, a, b) = (K, (K + 1) % 3, (K + 2) % 3);
        let (s, c) = (self.s, self.c);
        let i = &y.i_o;
        // R I Rᵀ for a turn in the (a, b) plane: the k row turns as a vector,
        // the (a, b) block as a 2×2 congruence.
        let (cc, ss, cs) = (c * c, s * s, c * s);
        let (iaa, ibb, iab) = (i[(a, a)], i[(b, b)], i[(a, b)]);
        let two_cs_ab = 2.0 * cs * iab;
        let mut r = Matrix3::zeros();
        let mut set = |u: usize, v: usize, x: f64| {
            r[(u, v)] = x;
            r[(v, u)] = x;
        };
        set(k, k, i[(k, k)]);
        set(k, a, c * i[(k, a)] - s * i[(k, b)]);
        set(k, b, s * i[(k, a)] + c * i[(k, b)]);
        set(a, a, cc * iaa - two_cs_ab + ss * ibb);
        set(b, b, ss * iaa + two_cs_ab + cc * ibb);
        set(a, b, cs * (iaa - ibb) + (cc - ss) * iab);
        let rotated = [
            r[(0, 0)],
            r[(1, 1)],
            r[(2, 2)],
            r[(0, 1)],
            r[(0, 2)],
            r[(1, 2)],
        ];
        Inertia::shifted(y.mass, &self.rotate::<K>(&y.h), &rotated, &self.p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lie::Se3;
    use crate::model::joints::Revolute;
    use crate::model::{Joint, Model};
    use std::sync::Arc;

    /// Every operation agrees with the general `Se3` one, for each axis and sign.
    #[test]
    fn turns_match_general_placements() {
        let y = Inertia::from_com(
            1.7,
            Vector3::new(0.1, -0.3, 0.2),
            Matrix3::new(0.3, 0.02, -0.01, 0.02, 0.25, 0.04, -0.01, 0.04, 0.2),
        )
        .unwrap();
        let x = Wrench::new(0.3, -1.2, 0.7, 2.0, -0.4, 0.9);
        for (n, axis) in [
            Vector3::x(),
            -Vector3::x(),
            Vector3::y(),
            -Vector3::y(),
            Vector3::z(),
            -Vector3::z(),
        ]
        .into_iter()
        .enumerate()
        {
            let joint: Arc<dyn Joint> = Arc::new(Revolute::new(axis).unwrap());
            let mut m = Model::new("turn");
            let offset = Se3::from_translation(Vector3::new(0.2, -0.5, 0.3));
            m.add_link("l", None, "j", joint.clone(), offset, y)
                .unwrap();
            let l = m.link(0);
            let q = 0.4 + 0.5 * n as f64;
            let (turn, _) = AxisTurn::of(l, q).unwrap();
            let general = l.axis.unwrap().place(&offset, q);
            let mut moved = [x];
            turn.ad_wrenches(&mut moved);
            assert!((moved[0] - general.ad_wrench(&x)).abs().max() < 1e-14);
            let (a, b) = (turn.inertia_to_parent(&y), y.transformed(&general));
            assert!((a.matrix() - b.matrix()).abs().max() < 1e-14, "{axis:?}");
        }
    }
}
