//! SP over a whole motion (Rose §3.2): find every interior gap of every DOF,
//! move the root kinematically, solve the remaining gap DOFs as spacetime
//! transitions (overlapping gaps together, disjoint ones in parallel), and
//! write the curves back into the motion. Also the Hermite baseline
//! (`fill(m, "hermite")`) and the torque energy of a motion.
//!
//! SP, stage by stage, over one [`Filling`] (the motion being filled, the
//! body, and the report the stages add to):
//! 0. [`checks`]: conflicts and a motion that cannot drive the body are errors;
//! 1. [`root_fill`]: the root's gaps (Rose's path, or pinned);
//! 2. [`offsets`]: constant bone offsets held;
//! 3. [`hold_supports`] (or [`hold_contacts`] with `contact:` when the body
//!    does not stand): limbs held by IK ([`held_limbs`]); when it stands
//!    ([`grounded::stands`]) nothing is held here: each group's solve plans
//!    its contacts and holds the feet itself;
//! 4. [`transitions`]: the rest solved as spacetime transitions, the prior's
//!    weights from [`prior_weights`], ∫Στ² by [`energy`]'s rule for the
//!    baseline, on the ground ([`grounded::SpGround`]) when the body stands;
//!
//! and the result is the filled motion with the [`report`].

mod checks;
mod energy;
mod filling;
#[cfg(test)]
mod fixture;
mod grounded;
mod held_limbs;
mod hold_contacts;
mod hold_supports;
mod offsets;
mod options;
mod prior_weights;
mod report;
mod root_fill;
mod transitions;

pub use checks::fill_hermite;
pub use energy::{joint_weights, torque_energy};
pub use filling::Filling;
pub use grounded::stands;
pub use hold_contacts::contact_floor;
pub use options::{
    AUTO_TIME_SCALE, DEFAULT_SMOOTHNESS, OptionDoc, Prior, ROOT_TOLERANCE_FIXED,
    ROOT_TOLERANCE_RELATIVE, RootFill, SP_OPTIONS, SpOptions, Support, root_tolerance,
};
pub use prior_weights::prior_weights;
pub use report::{FreeRoot, MAX_AIR, PinnedRoot, RootShift, SpReport, Undefined, Unplanned};

use crate::model::Model;
use crate::motion::Mu;
use crate::spacetime::contact::{Contact, ContactPlan};
use crate::spacetime::error::SpError;

/// `SP(m, body: b, …)`: the motion with every interior gap filled. Gaps at the
/// start or end stay undefined (listed in the report).
pub fn sp(m: &Mu, model: &Model, opts: &SpOptions) -> Result<(Mu, SpReport), SpError> {
    opts.check(model)?;
    checks::check_conflicts(m)?;
    checks::check_names(m, model)?;
    let gravity = opts.gravity.unwrap_or(model.default_gravity);
    let mut f = Filling::new(m, model, gravity);
    // grounded (issues 35, 42): the body has feet, gravity acts, `contact:`
    // is not "none", and there is a floor to stand on
    let standing = match grounded::stands(model, &gravity, opts)? {
        true => hold_contacts::contact_floor(m, model, &gravity, opts)?,
        false => None,
    };
    let free_root = standing.is_some() && f.root.is_floating();
    root_fill::fill_root(&mut f, opts.root, free_root)?;
    let gaps = f.gaps()?;
    // what the prior's transitions must undercut: the motion filled by Hermite curves
    let hermite_all = fill_hermite(&f.motion)?;
    let gaps = offsets::hold_constant_offsets(&mut f, gaps)?;
    let gaps = if let Some(floor) = standing {
        // the plan is made per group in the solve, which holds the feet
        f.contacts = Some(ContactPlan::new(floor));
        gaps
    } else if opts.contact != Contact::None && matches!(opts.support, Support::Auto { .. }) {
        hold_contacts::hold_contacts(&mut f, opts, gaps)?
    } else {
        hold_supports::hold_supports(&mut f, opts, gaps)?
    };
    if !gaps.is_empty() {
        transitions::solve_transitions(&mut f, opts, &hermite_all, gaps, standing)?;
    }
    Ok(f.finish())
}

#[cfg(test)]
mod tests {
    use super::fixture::{Y_UP, body, motion};
    use super::*;
    use crate::spacetime::objective::TransitionSettings;

    #[test]
    fn the_stages_fill_every_interior_gap_and_report_each() {
        let model = body();
        // root, limbs and the bone gapped together
        let m = motion(&model, &[0, 1, 2, 3, 4, 5], (0.8, 1.2));
        let opts = SpOptions {
            gravity: Some(Y_UP),
            support: Support::Off,
            prior: Prior::none(),
            settings: TransitionSettings {
                coefficients: 3,
                samples: 8,
                ..Default::default()
            },
            ..Default::default()
        };
        let (filled, report) = sp(&m, &model, &opts).unwrap();
        assert!(crate::motion::gaps(&filled).is_empty());
        assert_eq!(report.pinned.len(), 1); // one recording: pinned
        assert_eq!(report.constant.len(), 1); // the bone
        assert_eq!(report.groups.len(), 1);
        let g = &report.groups[0];
        assert_eq!(g.names, vec!["hip".to_string(), "knee".to_string()]);
        assert!(g.energy <= g.initial_energy, "{g:?}");
        assert_eq!(g.solves, 1);
        // no gap, nothing to do
        let (same, r) = sp(&filled, &model, &opts).unwrap();
        assert_eq!(same, filled);
        assert!(r.groups.is_empty() && r.to_string().starts_with("SP: no interior gaps"));
    }
}
