//! "Up" and the floor: the one definition the ground measures and SP's
//! contact planning and support hold share.
//!
//! Up is against gravity, so y-up mocap bodies and z-up URDF robots both
//! work; a point's height is its position along up. The floor is a plane of
//! constant height: by default the lowest height the contact points reach
//! (`points.rs`: over a whole motion, or where it is recorded — never a
//! massless root link's origin, only contact points count).

use super::{GroundError, invalid, invalid_option};
use nalgebra::Vector3;

/// Unit vector against `gravity`; `None` for zero or non-finite gravity
/// (nothing is up: no floor, nothing stands).
pub fn up_of(gravity: &Vector3<f64>) -> Option<Vector3<f64>> {
    let n = gravity.norm();
    (n.is_finite() && n > 0.0).then(|| -gravity / n)
}

/// Unit vector against `gravity`; `Err` for zero or non-finite gravity.
pub fn up_direction(gravity: &Vector3<f64>) -> Result<Vector3<f64>, GroundError> {
    up_of(gravity).ok_or_else(|| {
        invalid_option(
            "gravity",
            format!(
                "gravity [{}, {}, {}] gives no \"up\": ground measures need a nonzero, finite gravity",
                gravity.x, gravity.y, gravity.z
            ),
        )
    })
}

/// The part of `d` across `up` (along the floor).
pub fn horizontal(d: &Vector3<f64>, up: &Vector3<f64>) -> Vector3<f64> {
    d - up * d.dot(up)
}

/// The floor: the plane of points p with `up · p = height`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FloorPlane {
    /// Unit vector against gravity.
    pub up: Vector3<f64>,
    /// Metres along `up`.
    pub height: f64,
}

impl FloorPlane {
    /// The floor at `height` under `gravity`; `Err` when gravity gives no up
    /// or the height is not finite.
    pub fn new(gravity: &Vector3<f64>, height: f64) -> Result<Self, GroundError> {
        let up = up_direction(gravity)?;
        if !height.is_finite() {
            return Err(invalid(format!(
                "floor must be a finite height (m), got {height}"
            )));
        }
        Ok(FloorPlane { up, height })
    }

    /// How far `p` is above the floor (m; negative below it).
    pub fn above(&self, p: &Vector3<f64>) -> f64 {
        self.up.dot(p) - self.height
    }

    /// `p` moved along up onto the floor.
    pub fn project(&self, p: &Vector3<f64>) -> Vector3<f64> {
        p - self.up * self.above(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn up_is_against_gravity_and_none_without_it() {
        let up = up_of(&Vector3::new(0.0, -9.81, 0.0)).unwrap();
        assert_eq!(up, Vector3::y());
        assert!(up_of(&Vector3::zeros()).is_none());
        assert!(up_of(&Vector3::new(f64::NAN, 0.0, 0.0)).is_none());
        assert!(up_direction(&Vector3::zeros()).is_err());
        let d = horizontal(&Vector3::new(1.0, 2.0, 3.0), &up);
        assert_eq!(d, Vector3::new(1.0, 0.0, 3.0));
    }

    #[test]
    fn a_plane_measures_and_projects_along_up() {
        let f = FloorPlane::new(&Vector3::new(0.0, 0.0, -9.81), 0.5).unwrap();
        let p = Vector3::new(1.0, 2.0, 0.2);
        assert!((f.above(&p) + 0.3).abs() < 1e-15);
        assert_eq!(f.project(&p), Vector3::new(1.0, 2.0, 0.5));
        assert!(FloorPlane::new(&Vector3::zeros(), 0.0).is_err());
        assert!(FloorPlane::new(&Vector3::z(), f64::INFINITY).is_err());
    }
}
