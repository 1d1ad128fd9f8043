//! The variation of a world inertia carried along by a twist: the one quantity
//! the derivative passes (`derivatives.rs`) keep per link, stored in the
//! [`Workspace`](super::Workspace) so those passes allocate nothing.

use crate::lie::{Twist, Wrench, skew};
use crate::model::Inertia;
use nalgebra::{Matrix3, Vector3};

/// The variation `Ẏ x = Y (x × v) + x ×* (Y v) + v ×* (Y x)` of a world inertia
/// moving with twist v: the derivative of `Y a + v ×* Y v` when x perturbs v and
/// the body is carried along. Worked out by blocks it is
/// `[[A, 0], [−2[p], 0]]` with `(k; p) = Y v`, so it adds up over a subtree
/// as one 3×3 matrix and one vector.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Variation {
    a: Matrix3<f64>,
    p: Vector3<f64>,
}

impl Variation {
    pub(crate) fn zero() -> Self {
        Variation {
            a: Matrix3::zeros(),
            p: Vector3::zeros(),
        }
    }

    /// Of inertia `y` moving with twist `v`, whose momentum is `yv = y v`.
    pub(super) fn new(y: &Inertia, v: &Twist, yv: &Wrench) -> Self {
        let w = skew(&Vector3::new(v[0], v[1], v[2]));
        let vl = Vector3::new(v[3], v[4], v[5]);
        // [h][vl] + [vl][h] = h vlᵀ + vl hᵀ − 2 (h·vl) 1
        let hv = y.h * vl.transpose();
        let sym = hv + hv.transpose() - Matrix3::from_diagonal_element(2.0 * y.h.dot(&vl));
        let k = skew(&Vector3::new(yv[0], yv[1], yv[2]));
        Variation {
            a: w * y.i_o - y.i_o * w - sym - k,
            p: Vector3::new(yv[3], yv[4], yv[5]),
        }
    }

    #[inline]
    pub(super) fn apply(&self, x: &Twist) -> Wrench {
        let w = Vector3::new(x[0], x[1], x[2]);
        let m = self.a * w;
        let n = w.cross(&self.p) * 2.0;
        Wrench::new(m.x, m.y, m.z, n.x, n.y, n.z)
    }

    /// `Ẏᵀ j` (its linear half is zero, so only the angular half is returned).
    #[inline]
    pub(super) fn transpose_apply(&self, j: &Twist) -> Vector3<f64> {
        let jw = Vector3::new(j[0], j[1], j[2]);
        let jl = Vector3::new(j[3], j[4], j[5]);
        self.a.tr_mul(&jw) + self.p.cross(&jl) * 2.0
    }

    pub(super) fn add(&mut self, o: &Variation) {
        self.a += o.a;
        self.p += o.p;
    }
}
