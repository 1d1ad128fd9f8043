//! The n-DOF spline joint built from a grid of control frames (paper §5.2):
//! each control frame Ǧ_{i…} of an n-dimensional grid is written in the
//! joint's six coordinates — translation x, y, z, then three Euler angles in a
//! chosen order — and those numbers are the coefficients of the six
//! tensor-product B-splines φ_j of eq. 25. A 2-D grid is a spline surface joint
//! (the scapulothoracic joint, a ball on a surface); a 3-D grid whose last axis
//! is time is a deforming surface (see `dynamics/driven.rs` for how time is
//! driven).
//!
//! Like any B-spline the joint approximates its control frames (it passes
//! through the corner frames of a clamped grid). The Euler angles make the
//! rotation singular where the middle angle reaches ±π/2 (Tait–Bryan orders):
//! frames closer than [`MIN_GIMBAL_DISTANCE`] to it are refused, with advice
//! to choose another `order`.

use super::error::{JointSpecError, jerr};
use super::spherical::EulerOrder;
use super::spline_ndof::SplineJoint;
use crate::lie::{Se3, Twist};
use crate::model::joint::{Derivatives, Joint, JointKinematics, Limit, MAX_JOINT_DOF};
use crate::spline::{BSplineBasis, TensorSpline};
use nalgebra::Matrix3;
use std::f64::consts::{FRAC_PI_2, PI};

/// Control frames may come no closer than this (rad) to gimbal lock.
pub const MIN_GIMBAL_DISTANCE: f64 = 5.0 * PI / 180.0;

/// A spline joint whose functions come from a grid of control frames; the
/// coordinates are limited to the grid's parameter ranges (a scene with
/// `limits` keeps them inside).
#[derive(Clone, Debug)]
pub struct SplineSurfaceJoint {
    inner: SplineJoint,
    limits: Vec<Limit>,
    suffixes: Vec<String>,
}

/// What a frame grid is laid out as: `dims[d]` frames along coordinate d over
/// `ranges[d]`, frames in row-major order (the last coordinate varies fastest).
#[derive(Clone, Debug)]
pub struct FrameGrid {
    pub dims: Vec<usize>,
    pub ranges: Vec<(f64, f64)>,
    pub frames: Vec<Se3>,
    /// Names of the coordinates (for the body's coordinate names), e.g. ["u", "v"].
    pub names: Vec<String>,
    /// Coordinates left without limits (a driven clock coordinate).
    pub unlimited: Vec<bool>,
}

impl SplineSurfaceJoint {
    /// Rotations as R = R_a(α) R_b(β) R_c(γ) for the Tait–Bryan `order` (three distinct axes).
    pub fn from_grid(grid: &FrameGrid, order: EulerOrder) -> Result<Self, JointSpecError> {
        let n = grid.dims.len();
        if n == 0 || n > MAX_JOINT_DOF {
            return jerr(format!(
                "a spline surface joint needs a grid of 1 to {MAX_JOINT_DOF} dimensions, got {n}"
            ));
        }
        if grid.ranges.len() != n || grid.names.len() != n || grid.unlimited.len() != n {
            return jerr("frame grid: one range, name and limit flag per dimension");
        }
        let [i, j, k] = order.0;
        if i == k {
            return jerr(format!(
                "Euler order \"{}\": a spline surface joint needs three different axes (e.g. \"zyx\", \"xyz\")",
                order.name()
            ));
        }
        if let Some(d) = grid.dims.iter().position(|&m| m < 2) {
            return jerr(format!(
                "the frame grid has {} frame(s) along coordinate {d}; give at least 2",
                grid.dims[d]
            ));
        }
        let total: usize = grid.dims.iter().product();
        if grid.frames.len() != total {
            return jerr(format!(
                "the frame grid should hold {total} frames, got {}",
                grid.frames.len()
            ));
        }
        for (d, &(a, b)) in grid.ranges.iter().enumerate() {
            if !(a.is_finite() && b.is_finite() && b > a) {
                return jerr(format!(
                    "coordinate {d}: the range [{a}, {b}] must be finite and increasing"
                ));
            }
        }
        let strides: Vec<usize> = (0..n)
            .map(|d| grid.dims[d + 1..].iter().product())
            .collect();
        let mut coeffs = vec![vec![0.0; total]; 6];
        for (flat, f) in grid.frames.iter().enumerate() {
            if !f.r.iter().chain(f.p.iter()).all(|x| x.is_finite()) {
                return jerr(format!("control frame {flat} is not finite"));
            }
            let [alpha, beta, gamma] = tait_bryan(&f.r, order);
            if FRAC_PI_2 - beta.abs() < MIN_GIMBAL_DISTANCE {
                return jerr(format!(
                    "control frame {flat} is {:.1}° from gimbal lock of the Euler order \"{}\"; choose an order whose middle axis stays away from the frames' rotations",
                    (FRAC_PI_2 - beta.abs()).to_degrees(),
                    order.name()
                ));
            }
            // Unwrap the first and last angles to the nearest grid neighbour
            // already visited, so the splines do not jump by 2π.
            let neighbour = (0..n)
                .rev()
                .find(|&d| !(flat / strides[d]).is_multiple_of(grid.dims[d]))
                .map(|d| flat - strides[d]);
            let (alpha, gamma) = match neighbour {
                Some(p) => (
                    unwrap_to(alpha, coeffs[3][p]),
                    unwrap_to(gamma, coeffs[5][p]),
                ),
                None => (alpha, gamma),
            };
            for (c, coeff) in coeffs.iter_mut().enumerate().take(3) {
                coeff[flat] = f.p[c];
            }
            coeffs[3][flat] = alpha;
            coeffs[4][flat] = beta;
            coeffs[5][flat] = gamma;
        }
        let bases = (0..n)
            .map(|d| {
                let (a, b) = grid.ranges[d];
                BSplineBasis::clamped_uniform(3.min(grid.dims[d] - 1), grid.dims[d], a, b)
            })
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| JointSpecError(format!("spline surface basis: {e}")))?;
        let phis = coeffs
            .into_iter()
            .map(|c| TensorSpline::new(bases.clone(), c))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| JointSpecError(format!("spline surface: {e}")))?;
        let mut twists = [Twist::zeros(); 6];
        for (c, tw) in twists.iter_mut().enumerate().take(3) {
            tw[3 + c] = 1.0;
        }
        for (r, &axis) in [i, j, k].iter().enumerate() {
            twists[3 + r][axis] = 1.0;
        }
        let inner = SplineJoint::new(Se3::identity(), twists, phis)?;
        let limits = (0..n)
            .map(|d| {
                if grid.unlimited[d] {
                    Limit::NONE
                } else {
                    let (lower, upper) = grid.ranges[d];
                    Limit { lower, upper }
                }
            })
            .collect();
        Ok(SplineSurfaceJoint {
            inner,
            limits,
            suffixes: grid.names.clone(),
        })
    }

    pub fn spline(&self) -> &SplineJoint {
        &self.inner
    }
}

/// Angles (α, β, γ) with R = R_i(α) R_j(β) R_k(γ), i, j, k distinct, β ∈ [−π/2, π/2].
pub fn tait_bryan(r: &Matrix3<f64>, order: EulerOrder) -> [f64; 3] {
    let [i, j, k] = order.0;
    // +1 for cyclic orders (xyz, yzx, zxy), −1 for the others.
    let eps = if (j + 3 - i) % 3 == 1 { 1.0 } else { -1.0 };
    let beta = (eps * r[(i, k)]).clamp(-1.0, 1.0).asin();
    let alpha = (-eps * r[(j, k)]).atan2(r[(k, k)]);
    let gamma = (-eps * r[(i, j)]).atan2(r[(i, i)]);
    [alpha, beta, gamma]
}

fn unwrap_to(x: f64, reference: f64) -> f64 {
    x + ((reference - x) / (2.0 * PI)).round() * 2.0 * PI
}

impl Joint for SplineSurfaceJoint {
    fn kind(&self) -> &'static str {
        "spline_surface"
    }
    fn dof(&self) -> usize {
        self.inner.dof()
    }
    fn coordinate_suffixes(&self) -> Vec<String> {
        self.suffixes.clone()
    }
    fn kinematics(&self, q: &[f64], want: Derivatives, out: &mut JointKinematics) {
        self.inner.kinematics(q, want, out)
    }
    fn sdot_v_dq(&self, q: &[f64], v: &[f64], out: &mut [Twist; MAX_JOINT_DOF]) -> bool {
        self.inner.sdot_v_dq(q, v, out)
    }
    fn limits(&self) -> Vec<Limit> {
        self.limits.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lie::so3::exp_so3;
    use nalgebra::Vector3;

    #[test]
    fn tait_bryan_inverts_every_order() {
        for o in ["xyz", "zyx", "zxy", "yxz", "xzy", "yzx"] {
            let order = EulerOrder::parse(o).unwrap();
            let q = [0.7, -0.4, 2.5];
            let ax = |a: usize, t: f64| exp_so3(&(EulerOrder::axis(a) * t));
            let r = ax(order.0[0], q[0]) * ax(order.0[1], q[1]) * ax(order.0[2], q[2]);
            let got = tait_bryan(&r, order);
            for (g, w) in got.iter().zip(q) {
                assert!((g - w).abs() < 1e-12, "{o}: {got:?} vs {q:?}");
            }
        }
    }

    #[test]
    fn corner_frames_are_interpolated() {
        let mut frames = vec![];
        for a in 0..4 {
            for b in 0..3 {
                let r = exp_so3(&Vector3::new(0.1 * a as f64, 0.2 * b as f64, 0.3));
                frames.push(Se3::new(r, Vector3::new(a as f64, b as f64, 0.5)));
            }
        }
        let grid = FrameGrid {
            dims: vec![4, 3],
            ranges: vec![(0.0, 1.0), (-1.0, 1.0)],
            frames: frames.clone(),
            names: vec!["u".into(), "v".into()],
            unlimited: vec![false, false],
        };
        let j = SplineSurfaceJoint::from_grid(&grid, EulerOrder::ZYX).unwrap();
        let mut k = JointKinematics::default();
        for (q, f) in [([0.0, -1.0], frames[0]), ([1.0, 1.0], frames[11])] {
            j.kinematics(&q, Derivatives::Transform, &mut k);
            assert!((k.transform.p - f.p).norm() < 1e-12);
            assert!((k.transform.r - f.r).norm() < 1e-12);
        }
        assert_eq!(
            j.limits()[1],
            Limit {
                lower: -1.0,
                upper: 1.0
            }
        );
    }

    #[test]
    fn gimbal_lock_is_refused() {
        let r = exp_so3(&Vector3::new(0.0, FRAC_PI_2, 0.0));
        let grid = FrameGrid {
            dims: vec![2],
            ranges: vec![(0.0, 1.0)],
            frames: vec![Se3::from_rotation(r), Se3::identity()],
            names: vec!["u".into()],
            unlimited: vec![false],
        };
        let e = SplineSurfaceJoint::from_grid(&grid, EulerOrder::ZYX).unwrap_err();
        assert!(e.0.contains("gimbal lock"), "{e}");
    }
}
