//! Which of the two CRBA passes a model gets: the world-frame one (`crba.rs`)
//! or the link-frame one (`crba_local.rs`). Kept apart from both so that the
//! workspace, which both use, can decide once per model without a loop.

use crate::model::Model;

/// Which pass computes the mass matrix: both give the same matrix (to
/// rounding); they differ in the work they do on a given tree.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CrbaFrame {
    /// Composite inertias in the world frame (`crba.rs`): any link order.
    World,
    /// Composite inertias carried link to link (`crba_local.rs`): depth-first
    /// models only; others take the world-frame pass.
    Link,
}

/// The pass [`mass_matrix`](crate::dynamics::mass_matrix) takes on `model`
/// (a workspace decides it once, when it is built).
pub fn crba_frame_for(model: &Model) -> CrbaFrame {
    if prefers_link_frames(model) {
        CrbaFrame::Link
    } else {
        CrbaFrame::World
    }
}

/// Whether the link-frame CRBA (`crba_local.rs`) does less work than the
/// world-frame one on `model`, by a count of multiplications per call: in link
/// frames each link carries its composite inertia up (about 35 on the fast
/// path, 75 otherwise) and each of its subtree's momenta (14 or 24 per column);
/// in the world frame each link with mass is placed and its inertia turned
/// (about 95), each own column gets its momentum (24), and each entry is a dot
/// product (6). Only depth-first models qualify (the link-frame pass reads
/// subtree coordinate ranges). Decided once per workspace.
///
/// Checked against time, not only counts (#37): `cargo bench --bench dynamics`
/// times both passes interleaved on the reference URDFs, on any URDF named in
/// `MX_BENCH_URDFS` and on the random trees of `report::trees` (chains,
/// humanoid-like and random trees of 6–60 coordinates, mixed joints), and
/// prints which pass this rule picks beside the world/link time ratio. The
/// count favours the link frames on short or bushy trees and the world frame
/// on long chains (where carrying every subtree momentum up each link costs
/// more than a dot product per entry), and that is what the times show.
pub(super) fn prefers_link_frames(model: &Model) -> bool {
    if model.num_links() == 0 || model.subtree_coordinates(0).is_none() {
        return false;
    }
    let (mut local, mut world) = (0usize, 0usize);
    for (i, l) in model.links().iter().enumerate() {
        let sub = model.subtree_coordinates(i).map_or(0, |r| r.len());
        let fast = !l.offset_rotates
            && l.axis.is_some_and(|a| {
                a.motion == crate::model::joint::AxisMotion::Rotation && a.principal().is_some()
            });
        let (act, carry) = if fast { (35, 14) } else { (75, 24) };
        let massive = !l.inertia.is_zero();
        if l.parent.is_some() {
            local += (if massive || sub > 0 { act } else { 0 }) + sub * carry;
        }
        world += 20 + (if massive { 75 } else { 0 }) + l.dof * (24 + 6 * sub);
    }
    local < world
}
