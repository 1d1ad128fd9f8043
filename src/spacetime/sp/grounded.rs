//! Whether SP stands the body on the ground (issue 35): the rule the
//! pipeline's grounded stages ask ([`super::root_fill`] leaving the cut
//! root open, [`super::transitions`] solving with the ground's terms and
//! forces, [`crate::spacetime::solve::grounded`]).
//!
//! The body stands when all of these hold, and otherwise SP is Rose's
//! (today's numbers, bit for bit):
//! - `contact:` is not `"none"` (the opt-out);
//! - gravity acts (something is up: [`crate::ground::up_of`]);
//! - the body has contact points: the ones `contact:` names, or `ground`'s
//!   default ones (its ankle/toe/foot/heel joints). An arm, a pendulum or
//!   Rose's Fig. 10 arm have none, so SP on them never changes.

use super::hold_contacts::contact_links;
use super::options::SpOptions;
use crate::ground::up_of;
use crate::model::Model;
use crate::spacetime::contact::Contact;
use crate::spacetime::error::SpError;
use nalgebra::Vector3;

/// Whether SP with `opts` stands `model` on the ground under `gravity`
/// (see the module docs). Errors only for a `contact:` naming a link the
/// body lacks.
pub fn stands(model: &Model, gravity: &Vector3<f64>, opts: &SpOptions) -> Result<bool, SpError> {
    if opts.contact == Contact::None || up_of(gravity).is_none() {
        return Ok(false);
    }
    let (links, _) = contact_links(model, &opts.contact)?;
    Ok(!links.is_empty())
}

#[cfg(test)]
mod tests {
    use super::super::fixture::{Y_UP, body};
    use super::*;
    use crate::lie::Se3;
    use crate::model::Inertia;
    use crate::model::joints::Revolute;
    use std::sync::Arc;

    fn with(contact: Contact) -> SpOptions {
        SpOptions {
            contact,
            ..Default::default()
        }
    }

    #[test]
    fn a_body_with_feet_stands_under_gravity_unless_asked_not_to() {
        let b = body();
        assert!(stands(&b, &Y_UP, &with(Contact::Auto)).unwrap());
        assert!(stands(&b, &Y_UP, &with(Contact::Named(vec!["foot".into()]))).unwrap());
        assert!(!stands(&b, &Y_UP, &with(Contact::None)).unwrap());
        assert!(!stands(&b, &Vector3::zeros(), &with(Contact::Auto)).unwrap());
        let named = with(Contact::Named(vec!["hoof".into()]));
        assert!(stands(&b, &Y_UP, &named).is_err());
    }

    #[test]
    fn a_body_without_feet_never_stands() {
        let mut arm = Model::new("arm");
        let mass = Inertia::point(2.0, Vector3::new(0.0, -0.3, 0.0)).unwrap();
        let hinge = Arc::new(Revolute::new(Vector3::z()).unwrap());
        let upper = arm
            .add_link("upper_arm", None, "shoulder", hinge.clone(), Se3::identity(), mass)
            .unwrap();
        let below = Se3::from_translation(Vector3::new(0.0, -0.3, 0.0));
        arm.add_link("forearm", Some(upper), "elbow", hinge, below, mass)
            .unwrap();
        assert!(!stands(&arm, &Y_UP, &with(Contact::Auto)).unwrap());
    }
}
