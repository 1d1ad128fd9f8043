//! SO(3) and SE(3): the rigid-body group, its Lie algebra and their actions.
//!
//! Conventions (spline-joint paper §3): a twist is `[ω; v]`, a wrench `[μ; η]`,
//! both 6-vectors; velocities are body-frame. `T = (R, p)` maps child
//! coordinates to parent coordinates: `x_parent = R x_child + p`.

use nalgebra::{Matrix3, Matrix4, Matrix6, Vector3, Vector6};

pub mod se3exp;
pub mod series;
pub mod so3;

pub use se3exp::{ad_bracket_matrix, exp_se3, log_se3};
pub use so3::{
    exp_so3, left_jacobian_inv_so3, left_jacobian_so3, log_so3, quat_from_matrix,
    right_jacobian_so3, rotation_angle,
};

/// A twist `[ω; v]` (angular part first).
pub type Twist = Vector6<f64>;
/// A wrench `[μ; η]` (moment first), dual to a twist.
pub type Wrench = Vector6<f64>;

/// The 3×3 skew-symmetric matrix `[w]` with `[w] x = w × x`.
#[inline]
pub fn skew(w: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -w.z, w.y, w.z, 0.0, -w.x, -w.y, w.x, 0.0)
}

/// A rigid transform: rotation `r` and translation `p`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Se3 {
    pub r: Matrix3<f64>,
    pub p: Vector3<f64>,
}

impl Default for Se3 {
    fn default() -> Self {
        Self::identity()
    }
}

impl Se3 {
    #[inline]
    pub fn identity() -> Self {
        Se3 {
            r: Matrix3::identity(),
            p: Vector3::zeros(),
        }
    }

    #[inline]
    pub fn new(r: Matrix3<f64>, p: Vector3<f64>) -> Self {
        Se3 { r, p }
    }

    #[inline]
    pub fn from_translation(p: Vector3<f64>) -> Self {
        Se3 {
            r: Matrix3::identity(),
            p,
        }
    }

    #[inline]
    pub fn from_rotation(r: Matrix3<f64>) -> Self {
        Se3 {
            r,
            p: Vector3::zeros(),
        }
    }

    /// `self * other`.
    #[inline]
    pub fn compose(&self, other: &Se3) -> Se3 {
        Se3 {
            r: self.r * other.r,
            p: self.r * other.p + self.p,
        }
    }

    /// `self ∘ (1, p)`: composing with a pure translation needs no rotation product.
    #[inline]
    pub fn translated(&self, p: &Vector3<f64>) -> Se3 {
        Se3 {
            r: self.r,
            p: self.r * p + self.p,
        }
    }

    /// The inverse transform `(Rᵀ, −Rᵀp)`.
    #[inline]
    pub fn inverse(&self) -> Se3 {
        let rt = self.r.transpose();
        Se3 {
            r: rt,
            p: -(rt * self.p),
        }
    }

    /// `self⁻¹ * other` without forming the inverse.
    #[inline]
    pub fn inv_compose(&self, other: &Se3) -> Se3 {
        let rt = self.r.transpose();
        Se3 {
            r: rt * other.r,
            p: rt * (other.p - self.p),
        }
    }

    /// Maps a point from child to parent coordinates.
    #[inline]
    pub fn act_point(&self, x: &Vector3<f64>) -> Vector3<f64> {
        self.r * x + self.p
    }

    /// Maps a free vector (direction) from child to parent coordinates.
    #[inline]
    pub fn act_vector(&self, x: &Vector3<f64>) -> Vector3<f64> {
        self.r * x
    }

    /// `Ad_T s`: the twist `s`, given in the child frame, expressed in the parent frame.
    #[inline]
    pub fn ad_twist(&self, s: &Twist) -> Twist {
        let w = self.r * s.fixed_rows::<3>(0);
        let v = self.r * s.fixed_rows::<3>(3) + self.p.cross(&w);
        Vector6::new(w.x, w.y, w.z, v.x, v.y, v.z)
    }

    /// `Ad_T⁻¹ s`: the twist `s`, given in the parent frame, expressed in the child frame.
    #[inline]
    pub fn inv_ad_twist(&self, s: &Twist) -> Twist {
        let w0 = s.fixed_rows::<3>(0).into_owned();
        let v0 = s.fixed_rows::<3>(3).into_owned();
        let rt = self.r.transpose();
        let w = rt * w0;
        let v = rt * (v0 - self.p.cross(&w0));
        Vector6::new(w.x, w.y, w.z, v.x, v.y, v.z)
    }

    /// `Ad*_{T⁻¹} f`: a wrench given in the child frame, expressed in the parent frame
    /// (the transpose of [`Se3::inv_ad_twist`], so power is preserved).
    #[inline]
    pub fn ad_wrench(&self, f: &Wrench) -> Wrench {
        let m0 = f.fixed_rows::<3>(0).into_owned();
        let n0 = f.fixed_rows::<3>(3).into_owned();
        let n = self.r * n0;
        let m = self.r * m0 + self.p.cross(&n);
        Vector6::new(m.x, m.y, m.z, n.x, n.y, n.z)
    }

    /// `Ad*_T f`: a wrench given in the parent frame, expressed in the child frame
    /// (the transpose of [`Se3::ad_twist`]).
    #[inline]
    pub fn inv_ad_wrench(&self, f: &Wrench) -> Wrench {
        let m0 = f.fixed_rows::<3>(0).into_owned();
        let n0 = f.fixed_rows::<3>(3).into_owned();
        let rt = self.r.transpose();
        let n = rt * n0;
        let m = rt * (m0 - self.p.cross(&n0));
        Vector6::new(m.x, m.y, m.z, n.x, n.y, n.z)
    }

    /// The 6×6 matrix of `Ad_T` acting on twists.
    pub fn ad_matrix(&self) -> Matrix6<f64> {
        let mut m = Matrix6::zeros();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&self.r);
        m.fixed_view_mut::<3, 3>(3, 3).copy_from(&self.r);
        m.fixed_view_mut::<3, 3>(3, 0)
            .copy_from(&(skew(&self.p) * self.r));
        m
    }

    /// The homogeneous 4×4 matrix.
    pub fn to_matrix(&self) -> Matrix4<f64> {
        let mut m = Matrix4::identity();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&self.r);
        m.fixed_view_mut::<3, 1>(0, 3).copy_from(&self.p);
        m
    }

    /// From a homogeneous 4×4 matrix (the last row is not checked).
    pub fn from_matrix(m: &Matrix4<f64>) -> Se3 {
        Se3 {
            r: m.fixed_view::<3, 3>(0, 0).into_owned(),
            p: m.fixed_view::<3, 1>(0, 3).into_owned(),
        }
    }
}

impl std::ops::Mul for Se3 {
    type Output = Se3;
    #[inline]
    fn mul(self, rhs: Se3) -> Se3 {
        self.compose(&rhs)
    }
}

/// `ad_a b = [a, b]`, the Lie bracket of two twists.
#[inline]
pub fn ad(a: &Twist, b: &Twist) -> Twist {
    let wa = a.fixed_rows::<3>(0);
    let va = a.fixed_rows::<3>(3);
    let wb = b.fixed_rows::<3>(0);
    let vb = b.fixed_rows::<3>(3);
    let w = wa.cross(&wb);
    let v = wa.cross(&vb) - wb.cross(&va);
    Vector6::new(w.x, w.y, w.z, v.x, v.y, v.z)
}

/// `ad*_a f = (ad_a)ᵀ f`, the dual of [`ad`] acting on a wrench.
#[inline]
pub fn ad_dual(a: &Twist, f: &Wrench) -> Wrench {
    let wa = a.fixed_rows::<3>(0);
    let va = a.fixed_rows::<3>(3);
    let m = f.fixed_rows::<3>(0);
    let n = f.fixed_rows::<3>(3);
    // (ad_a)ᵀ = [[-[wa], -[va]], [0, -[wa]]]ᵀ applied to [m; n]
    let mm = m.cross(&wa) + n.cross(&va);
    let nn = n.cross(&wa);
    Vector6::new(mm.x, mm.y, mm.z, nn.x, nn.y, nn.z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Rotation3;

    fn sample() -> Se3 {
        let r = Rotation3::from_euler_angles(0.3, -1.1, 2.0).into_inner();
        Se3::new(r, Vector3::new(0.4, -0.2, 1.5))
    }

    #[test]
    fn adjoint_actions_are_consistent_with_the_matrix() {
        let t = sample();
        let s = Vector6::new(0.1, 0.2, -0.3, 1.0, -2.0, 0.5);
        let m = t.ad_matrix();
        assert!((t.ad_twist(&s) - m * s).norm() < 1e-14);
        assert!((t.inv_ad_twist(&t.ad_twist(&s)) - s).norm() < 1e-14);
        // wrench maps are the transposes, so power f·s is invariant.
        let f = Vector6::new(0.7, -0.1, 0.2, 0.3, 0.9, -1.2);
        assert!((t.inv_ad_wrench(&f) - m.transpose() * f).norm() < 1e-13);
        assert!((t.ad_wrench(&t.inv_ad_wrench(&f)) - f).norm() < 1e-13);
        assert!((t.ad_wrench(&f).dot(&t.ad_twist(&s)) - f.dot(&s)).abs() < 1e-13);
    }

    #[test]
    fn ad_dual_is_the_transpose_of_ad() {
        let a = Vector6::new(0.3, -0.4, 0.5, 1.0, 0.2, -0.7);
        let b = Vector6::new(-0.2, 0.1, 0.9, 0.4, -1.1, 0.3);
        let f = Vector6::new(0.5, 0.6, -0.7, 0.8, -0.9, 1.0);
        assert!((ad_dual(&a, &f).dot(&b) - f.dot(&ad(&a, &b))).abs() < 1e-14);
    }
}
