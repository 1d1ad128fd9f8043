//! What both ways of holding limbs ([`super::hold_supports`],
//! [`super::hold_contacts`]) share: which gap DOFs move a frame, a group's
//! span, and writing a solved hold IK back.

use super::filling::Filling;
use crate::model::{Model, RootCoords};
use crate::motion::Curve;
use crate::spacetime::error::SpError;
use crate::spacetime::hold::{self, HeldFrame, HoldObjective};
use crate::spacetime::objective::GapDof;

/// Whether gap coordinate `c` moves frame `f` by a joint of the limb (it is
/// on the chain from the frame to the root, and not the root's own: a foot's
/// IK must not carry the body by moving the root, which grounded SP solves
/// with the dynamics and Rose's root fill places beforehand).
pub fn moves(model: &Model, root: &RootCoords, f: usize, c: usize) -> bool {
    !root.all.contains(&c) && hold::owner(model, c).is_some_and(|o| model.is_ancestor(o, f))
}

/// The span of a group of gaps.
pub fn span(group: &[GapDof]) -> (f64, f64) {
    let t0 = group.iter().map(|d| d.t0).fold(f64::INFINITY, f64::min);
    let t1 = group.iter().map(|d| d.t1).fold(f64::NEG_INFINITY, f64::max);
    (t0, t1)
}

/// Writes a solved hold IK back into the motion (its chain's curves over
/// the gap) and records each held frame in the report, with how far it moved
/// under the Hermite curves and under IK.
pub fn write_hold_solve(
    f: &mut Filling<'_>,
    obj: &HoldObjective<'_>,
    x: &[f64],
    frames: &[usize],
    (t0, t1): (f64, f64),
    detected: bool,
) -> Result<(), SpError> {
    let names = f.names;
    let before = obj.largest_drift(&obj.hermite_start())?;
    let after = obj.largest_drift(x)?;
    let dof_names: Vec<String> = obj.dofs().iter().map(|d| names[d.coord].clone()).collect();
    for (i, &fr) in frames.iter().enumerate() {
        f.report.support.push(HeldFrame {
            frame: f.model.link(fr).name.clone(),
            t0,
            t1,
            detected,
            dofs: dof_names.clone(),
            moved_before: before[i],
            moved: after[i],
        });
    }
    for ((gap, coefs), curve) in obj.dofs().iter().zip(obj.coefficients(x)).zip(obj.curves()) {
        let c = curve.to_curve(coefs)?;
        f.write(&names[gap.coord], Curve::Spline(c), gap.t0, gap.t1)?;
    }
    Ok(())
}
