//! Rigid-body inertia: mass, centre of mass and rotational inertia.
//!
//! Stored in the form the recursive algorithms want: mass `m`, first moment
//! `h = m c` and rotational inertia `i_o` about the *frame origin*, so that the
//! 6×6 spatial inertia (twists `[ω; v]`) is `[[i_o, [h]], [[h]ᵀ, m 1]]` and
//! composites add term by term.

use crate::lie::{Se3, Twist, Wrench, skew};
use nalgebra::{Matrix3, Matrix6, Vector3, Vector6};

/// Why mass, centre of mass and rotational inertia make no rigid body: each
/// names the quantity at fault ([`InertiaError::quantity`]).
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum InertiaError {
    #[error("mass must be a finite number ≥ 0, got {0}")]
    Mass(f64),
    /// `com` says whether the centre of mass (else the inertia) is not finite.
    #[error("centre of mass and inertia must be finite numbers")]
    NotFinite { com: bool },
    /// The largest off-diagonal mismatch.
    #[error("rotational inertia must be symmetric (off-diagonal mismatch {0:e})")]
    Asymmetric(f64),
}

impl InertiaError {
    /// The quantity at fault: `"mass"`, `"com"` or `"inertia"`.
    pub fn quantity(&self) -> &'static str {
        match self {
            InertiaError::Mass(_) => "mass",
            InertiaError::NotFinite { com: true } => "com",
            InertiaError::NotFinite { com: false } | InertiaError::Asymmetric(_) => "inertia",
        }
    }
}

/// The spatial inertia of a rigid body in its own frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Inertia {
    /// Mass (kg).
    pub mass: f64,
    /// First moment `m c` (kg·m), `c` the centre of mass in the body frame.
    pub h: Vector3<f64>,
    /// Rotational inertia about the body-frame origin (kg·m²), body axes.
    pub i_o: Matrix3<f64>,
}

impl Default for Inertia {
    fn default() -> Self {
        Self::zero()
    }
}

impl Inertia {
    /// A massless body.
    pub fn zero() -> Self {
        Inertia {
            mass: 0.0,
            h: Vector3::zeros(),
            i_o: Matrix3::zeros(),
        }
    }

    /// From mass, centre of mass `com` and rotational inertia `i_com` about the
    /// centre of mass (body axes). Errors on a negative or non-finite mass or a
    /// non-symmetric / non-finite inertia.
    pub fn from_com(
        mass: f64,
        com: Vector3<f64>,
        i_com: Matrix3<f64>,
    ) -> Result<Self, InertiaError> {
        if !mass.is_finite() || mass < 0.0 {
            return Err(InertiaError::Mass(mass));
        }
        let com_finite = com.iter().all(|x| x.is_finite());
        if !com_finite || !i_com.iter().all(|x| x.is_finite()) {
            return Err(InertiaError::NotFinite { com: !com_finite });
        }
        let asym = (i_com - i_com.transpose()).abs().max();
        if asym > 1e-9 * (1.0 + i_com.abs().max()) {
            return Err(InertiaError::Asymmetric(asym));
        }
        let c = skew(&com);
        Ok(Inertia {
            mass,
            h: com * mass,
            i_o: i_com - c * c * mass,
        })
    }

    /// A point mass at `com`.
    pub fn point(mass: f64, com: Vector3<f64>) -> Result<Self, InertiaError> {
        Self::from_com(mass, com, Matrix3::zeros())
    }

    /// Centre of mass (the origin for a massless body).
    pub fn com(&self) -> Vector3<f64> {
        if self.mass > 0.0 {
            self.h / self.mass
        } else {
            Vector3::zeros()
        }
    }

    /// Rotational inertia about the centre of mass.
    pub fn inertia_com(&self) -> Matrix3<f64> {
        let c = skew(&self.com());
        self.i_o + c * c * self.mass
    }

    /// True for a massless body without rotational inertia (URDF's links
    /// between the axes of one anatomical joint): transforming it is a no-op.
    #[inline]
    pub fn is_zero(&self) -> bool {
        self.mass == 0.0 && self.h == Vector3::zeros() && self.i_o == Matrix3::zeros()
    }

    /// This inertia, given in frame `child`, expressed in the frame in which
    /// `t` places `child` (`x_parent = t x_child`).
    #[inline]
    pub fn transformed(&self, t: &Se3) -> Inertia {
        let r = &t.r;
        let rh = r * self.h;
        let p = &t.p;
        // The dynamics transforms every link's inertia on every call, so only the
        // six unique entries of the symmetric result are formed. `R I Rᵀ` is
        // `A Rᵀ` with `A = R I`; the parallel-axis part −[rh][p] − [p][rh] − m[p]²
        // written out with [a][b] = b aᵀ − (a·b) 1 is 2(p·w) 1 − p wᵀ − w pᵀ,
        // w = rh + m p / 2.
        let a = r * self.i_o;
        let w = rh + p * (0.5 * self.mass);
        let d = 2.0 * p.dot(&w);
        let e = |i: usize, j: usize| {
            a[(i, 0)] * r[(j, 0)] + a[(i, 1)] * r[(j, 1)] + a[(i, 2)] * r[(j, 2)]
                - p[i] * w[j]
                - w[i] * p[j]
        };
        let (xy, xz, yz) = (e(0, 1), e(0, 2), e(1, 2));
        let i_o = Matrix3::new(
            e(0, 0) + d,
            xy,
            xz,
            xy,
            e(1, 1) + d,
            yz,
            xz,
            yz,
            e(2, 2) + d,
        );
        Inertia {
            mass: self.mass,
            h: rh + p * self.mass,
            i_o,
        }
    }

    /// The inertia of mass `mass` whose first moment `rh` and rotational
    /// inertia (unique entries `xx, yy, zz, xy, xz, yz` of a symmetric matrix)
    /// are about an origin that sits at `p` in the frame wanted, axes already
    /// turned into it: the parallel-axis part −[rh][p] − [p][rh] − m[p]²,
    /// written out with [a][b] = b aᵀ − (a·b) 1, is 2(p·w) 1 − p wᵀ − w pᵀ with
    /// w = rh + m p / 2.
    #[inline]
    pub(crate) fn shifted(
        mass: f64,
        rh: &Vector3<f64>,
        rotated: &[f64; 6],
        p: &Vector3<f64>,
    ) -> Inertia {
        let w = rh + p * (0.5 * mass);
        let d = 2.0 * p.dot(&w);
        let e = |x: f64, i: usize, j: usize| x - p[i] * w[j] - w[i] * p[j];
        let [xx, yy, zz, xy, xz, yz] = *rotated;
        let (xy, xz, yz) = (e(xy, 0, 1), e(xz, 0, 2), e(yz, 1, 2));
        let i_o = Matrix3::new(
            e(xx, 0, 0) + d,
            xy,
            xz,
            xy,
            e(yy, 1, 1) + d,
            yz,
            xz,
            yz,
            e(zz, 2, 2) + d,
        );
        Inertia {
            mass,
            h: rh + p * mass,
            i_o,
        }
    }

    /// `G V`: the momentum of the body moving with twist `v`.
    #[inline]
    pub fn mul_twist(&self, v: &Twist) -> Wrench {
        let w = v.fixed_rows::<3>(0).into_owned();
        let lin = v.fixed_rows::<3>(3).into_owned();
        let mu = self.i_o * w + self.h.cross(&lin);
        let eta = lin * self.mass - self.h.cross(&w);
        Vector6::new(mu.x, mu.y, mu.z, eta.x, eta.y, eta.z)
    }

    /// The 6×6 spatial inertia matrix.
    pub fn matrix(&self) -> Matrix6<f64> {
        let mut g = Matrix6::zeros();
        let hx = skew(&self.h);
        g.fixed_view_mut::<3, 3>(0, 0).copy_from(&self.i_o);
        g.fixed_view_mut::<3, 3>(0, 3).copy_from(&hx);
        g.fixed_view_mut::<3, 3>(3, 0).copy_from(&hx.transpose());
        g.fixed_view_mut::<3, 3>(3, 3)
            .copy_from(&(Matrix3::identity() * self.mass));
        g
    }
}

impl std::ops::Add for Inertia {
    type Output = Inertia;
    fn add(self, o: Inertia) -> Inertia {
        Inertia {
            mass: self.mass + o.mass,
            h: self.h + o.h,
            i_o: self.i_o + o.i_o,
        }
    }
}

impl std::ops::AddAssign for Inertia {
    fn add_assign(&mut self, o: Inertia) {
        *self = *self + o;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Rotation3;

    #[test]
    fn transform_matches_the_matrix_congruence() {
        let i = Inertia::from_com(
            2.0,
            Vector3::new(0.1, -0.2, 0.3),
            Matrix3::new(0.5, 0.01, 0.02, 0.01, 0.4, 0.03, 0.02, 0.03, 0.3),
        )
        .unwrap();
        let t = Se3::new(
            Rotation3::from_euler_angles(0.4, 0.1, -0.7).into_inner(),
            Vector3::new(0.3, 0.5, -0.2),
        );
        // Parent-frame inertia = Ad_{T⁻¹}ᵀ G Ad_{T⁻¹}.
        let x = t.inverse().ad_matrix();
        let expect = x.transpose() * i.matrix() * x;
        assert!((i.transformed(&t).matrix() - expect).abs().max() < 1e-13);
        // And round trip through com form.
        let back = i.transformed(&t);
        assert!((back.mass - 2.0).abs() < 1e-15);
        assert!(
            (back.inertia_com() - t.r * i.inertia_com() * t.r.transpose())
                .abs()
                .max()
                < 1e-13
        );
    }

    #[test]
    fn bad_inertia_is_an_error() {
        assert!(Inertia::from_com(-1.0, Vector3::zeros(), Matrix3::identity()).is_err());
        assert!(Inertia::from_com(f64::NAN, Vector3::zeros(), Matrix3::identity()).is_err());
        let mut a = Matrix3::identity();
        a[(0, 1)] = 1.0;
        assert!(Inertia::from_com(1.0, Vector3::zeros(), a).is_err());
    }
}
