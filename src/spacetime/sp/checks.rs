//! What SP refuses before it starts (conflicts, a motion that cannot drive
//! the body), the Hermite baseline `fill(m, "hermite")`, and motion errors
//! worded as SP's.

use crate::model::Model;
use crate::motion::{Mu, conflicts};
use crate::spacetime::error::{SpError, invalid};

pub(super) fn motion_err(e: crate::motion::MotionError) -> SpError {
    SpError::Motion(e)
}

/// Error on any conflict (SP needs one value per DOF where it is defined).
pub(super) fn check_conflicts(m: &Mu) -> Result<(), SpError> {
    if let Some(c) = conflicts(m).first() {
        return Err(SpError::Conflict {
            dof: c.dof.clone(),
            t0: c.start,
            t1: c.stop,
        });
    }
    Ok(())
}

/// Checks that the motion can drive the body: every DOF with a gap is a body
/// coordinate, and every body coordinate is in the motion.
pub(super) fn check_names(m: &Mu, model: &Model) -> Result<(), SpError> {
    let names = model.coordinate_names();
    let missing: Vec<&String> = names.iter().filter(|n| m.get(n).is_none()).collect();
    if !missing.is_empty() {
        return Err(invalid(format!(
            "the motion has no DOF for {} of the body's coordinates ({}{}); the body must be the one the motion was made for \
             (e.g. human(walk) for a clip) — torques need every coordinate",
            missing.len(),
            missing
                .iter()
                .take(5)
                .map(|s| s.as_str())
                .collect::<Vec<_>>()
                .join(", "),
            if missing.len() > 5 { ", …" } else { "" }
        )));
    }
    for (name, d) in &m.dofs {
        if !d.gaps().is_empty() && model.coordinate_index(name).is_none() {
            return Err(invalid(format!(
                "DOF '{name}' has a gap but the body has no coordinate of that name, so SP cannot compute its torques; \
                 fill it another way (fill(m, \"hermite\")) or use the body the motion was made for"
            )));
        }
    }
    Ok(())
}

/// `fill(m, "hermite")`: every interior gap of every DOF becomes the cubic
/// Hermite curve between the end values and velocities
/// ([`crate::motion::fill_hermite`]). Conflicts are an error, worded for SP.
pub fn fill_hermite(m: &Mu) -> Result<Mu, SpError> {
    check_conflicts(m)?;
    crate::motion::fill_hermite(m).map_err(motion_err)
}

#[cfg(test)]
mod tests {
    use super::super::fixture::{body, motion};
    use super::*;
    use crate::motion::{Dof, Interval};

    #[test]
    fn conflicts_missing_coordinates_and_foreign_gaps_are_errors() {
        let model = body();
        let m = motion(&model, &[3], (0.8, 1.2));
        assert!(check_conflicts(&m).is_ok() && check_names(&m, &model).is_ok());
        let mut twice = m.clone();
        let hip = twice
            .get("hip")
            .unwrap()
            .plus(&Dof::from(Interval::constant(0.0, 0.1, 0.2).unwrap()));
        twice.insert("hip", hip);
        let e = check_conflicts(&twice).unwrap_err();
        assert!(
            matches!(&e, SpError::Conflict { dof, t0, t1 } if dof == "hip" && *t0 == 0.1 && *t1 == 0.2),
            "{e:?}"
        );
        let e = e.to_string();
        assert!(e.contains("'hip'") && e.contains("conflict"), "{e}");
        let mut missing = m.clone();
        missing.dofs.shift_remove("knee");
        let e = check_names(&missing, &model).unwrap_err().to_string();
        assert!(e.contains("knee"), "{e}");
        let mut foreign = m.clone();
        let gapped = Dof::new(vec![
            Interval::constant(0.0, 0.0, 0.5).unwrap(),
            Interval::constant(0.0, 0.7, 2.0).unwrap(),
        ])
        .unwrap();
        foreign.insert("tail", gapped);
        let e = check_names(&foreign, &model).unwrap_err().to_string();
        assert!(e.contains("'tail'"), "{e}");
    }

    /// SP and torque_energy say which error it is, not only its text.
    #[test]
    fn sp_and_torque_energy_raise_typed_errors() {
        use crate::spacetime::Need;
        use crate::spacetime::sp::{SpOptions, Support, sp, torque_energy};
        let model = body();
        let opts = SpOptions {
            support: Support::Off,
            ..Default::default()
        };
        let mut twice = motion(&model, &[3], (0.8, 1.2));
        let knee = twice
            .get("knee")
            .unwrap()
            .plus(&Dof::from(Interval::constant(0.0, 0.1, 0.2).unwrap()));
        twice.insert("knee", knee);
        match sp(&twice, &model, &opts) {
            Err(SpError::Conflict { dof, t0, t1 }) => {
                assert_eq!((dof.as_str(), t0, t1), ("knee", 0.1, 0.2))
            }
            other => panic!("expected a conflict, got {other:?}"),
        }
        let gapped = motion(&model, &[3], (0.8, 1.2));
        match torque_energy(&gapped, &model, None) {
            Err(SpError::Undefined { dof, t, need }) => {
                assert_eq!((dof.as_str(), &need), ("hip", &Need::TorqueEnergy));
                assert!(t > 0.8 && t < 1.2, "{t}");
            }
            other => panic!("expected an undefined DOF, got {other:?}"),
        }
        // the knee starts at 1.0, inside the hip's gap: its transition cannot
        // compute the body's torques there
        let mut late = gapped.clone();
        late.insert(
            "knee",
            Dof::from(Interval::constant(0.3, 1.0, 2.0).unwrap()),
        );
        match sp(&late, &model, &opts) {
            Err(SpError::Undefined { dof, t, need }) => {
                assert_eq!(dof, "knee");
                assert!(t < 1.0, "{t}");
                assert!(matches!(need, Need::Transition(_)), "{need:?}");
            }
            other => panic!("expected an undefined DOF, got {other:?}"),
        }
    }
}
