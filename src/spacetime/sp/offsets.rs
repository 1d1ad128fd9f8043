//! Stage 2, bone offsets: translation DOFs constant on both sides of their
//! gap are held at that constant, not optimised.

use super::filling::{Filling, hermite_curve};
use super::report::Undefined;
use crate::model::Model;
use crate::spacetime::error::SpError;
use crate::spacetime::objective::GapDof;
use crate::spacetime::transition::EndState;

/// Whether model coordinate `c` is the coordinate of a 1-DOF sliding joint.
pub(super) fn is_translation(model: &Model, c: usize) -> bool {
    model.coordinate_motion(c) == Some(crate::model::joint::AxisMotion::Translation)
}

/// How far (m) a translation may vary across a gap and still count as a
/// constant bone offset: Bandai's position channels carry the offset with
/// rounding noise of ~1e-8 m.
const OFFSET_TOLERANCE: f64 = 1e-6;

/// Translation DOFs whose two sides hold one value (a BVH joint's position
/// channels, which are its bone offset, up to rounding noise): the gap is the
/// cubic Hermite curve between the sides, which stays within
/// [`OFFSET_TOLERANCE`] of that value. Optimising them would let bones
/// stretch, which no torque forbids. Returns the gaps left to solve.
pub(super) fn hold_constant_offsets(
    f: &mut Filling<'_>,
    gaps: Vec<GapDof>,
) -> Result<Vec<GapDof>, SpError> {
    let names = f.names;
    let mut left = vec![];
    for g in gaps {
        let span = g.t1 - g.t0;
        let still = |s: &EndState| {
            s.v.abs() * span <= OFFSET_TOLERANCE && s.a.abs() * span * span <= OFFSET_TOLERANCE
        };
        let same = (g.start.q - g.end.q).abs() <= OFFSET_TOLERANCE;
        if is_translation(f.model, g.coord) && same && still(&g.start) && still(&g.end) {
            let curve = hermite_curve(g.t0, g.t1, &g.start, &g.end)?;
            f.write(&names[g.coord], curve, g.t0, g.t1)?;
            f.report.constant.push(Undefined {
                dof: names[g.coord].clone(),
                start: g.t0,
                stop: g.t1,
            });
        } else {
            left.push(g);
        }
    }
    Ok(left)
}
#[cfg(test)]
mod tests {
    use super::super::fixture::{Y_UP, body, motion};
    use super::*;

    #[test]
    fn a_constant_bone_offset_is_held_and_a_moving_joint_left_to_solve() {
        let model = body();
        let m = motion(&model, &[3, 5], (0.8, 1.2));
        let mut f = Filling::new(&m, &model, Y_UP);
        assert!(is_translation(&model, 5) && !is_translation(&model, 3));
        let gaps = f.gaps().unwrap();
        let left = hold_constant_offsets(&mut f, gaps).unwrap();
        assert_eq!(left.iter().map(|g| g.coord).collect::<Vec<_>>(), vec![3]);
        assert_eq!(f.report.constant.len(), 1);
        assert_eq!(f.report.constant[0].dof, "bone");
        let bone = f.motion.sample_value("bone", 1.0).unwrap().unwrap();
        assert!((bone - 0.25).abs() <= OFFSET_TOLERANCE, "{bone}");
    }
}
