//! The ConstraintSet (CoordinateCouplerConstraints, read as coupled
//! coordinates) and the count of what mx does not simulate (forces, muscles,
//! contact, markers, controllers, probes, geometry): reported, never an error.

use roxmltree::Node;

use super::xml::{Ctx, child, elements, err, name_of, objects, text};
use super::{Coupler, OsimReport};
use crate::model::files::osim_joint::function_from_xml;
use crate::model::tree::{Model, ModelError};

pub(super) fn read_constraints(
    cx: &Ctx,
    m: Node,
    model: &Model,
    report: &mut OsimReport,
) -> Result<(), ModelError> {
    for c in objects(child(m, "ConstraintSet")) {
        let t = c.tag_name().name();
        let cname = name_of(c);
        let enforced = text(c, "isEnforced")
            .or_else(|| text(c, "isDisabled").map(|d| if d == "true" { "false" } else { "true" }))
            .is_none_or(|v| v != "false");
        if !enforced {
            report.warnings.push(format!(
                "constraint '{cname}' ({}) is not enforced; ignored",
                cx.at(c)
            ));
            continue;
        }
        if t != "CoordinateCouplerConstraint" {
            return err(format!(
                "constraint '{cname}' ({}) is a {t}, which changes the kinematics and which mx does not read; mx reads CoordinateCouplerConstraint",
                cx.at(c)
            ));
        }
        let what = format!("CoordinateCouplerConstraint '{cname}' ({})", cx.at(c));
        let ind: Vec<&str> = text(c, "independent_coordinate_names")
            .unwrap_or("")
            .split_whitespace()
            .collect();
        let dep = text(c, "dependent_coordinate_name")
            .unwrap_or("")
            .to_string();
        let [ind] = ind.as_slice() else {
            return err(format!(
                "{what} couples {} independent coordinates; mx reads couplers of one",
                ind.len()
            ));
        };
        for n in [*ind, dep.as_str()] {
            if model.coordinate_index(n).is_none() {
                return err(format!(
                    "{what} names coordinate '{n}', which the model does not have"
                ));
            }
        }
        let f = child(c, "coupled_coordinates_function")
            .and_then(|f| elements(f).next())
            .ok_or_else(|| {
                ModelError::Invalid(format!("{what} has no <coupled_coordinates_function>"))
            })?;
        let function = function_from_xml(f)
            .map_err(|m| ModelError::Invalid(format!("{what}, {}: {}", cx.at(f), m.0)))?;
        report.couplers.push(Coupler {
            name: cname,
            dependent: dep,
            independent: ind.to_string(),
            function,
        });
    }

    Ok(())
}

/// Counts what mx does not simulate (forces, markers, geometry, …) into the report.
pub(super) fn count_ignored(m: Node, report: &mut OsimReport) {
    let mut count = |what: &str, kind: &str| match report
        .ignored
        .iter_mut()
        .find(|(w, k, _)| w == what && k == kind)
    {
        Some(e) => e.2 += 1,
        None => report.ignored.push((what.into(), kind.into(), 1)),
    };
    for f in objects(child(m, "ForceSet")) {
        let k = f.tag_name().name();
        let what = if k.ends_with("Muscle") || k.contains("Muscle") {
            "muscles"
        } else if k.ends_with("Actuator") {
            "actuators"
        } else if k.contains("Contact") || k.contains("HuntCrossley") || k.contains("Elastic") {
            "contact forces"
        } else {
            "forces"
        };
        count(what, k);
    }
    for (set, what) in [
        ("MarkerSet", "markers"),
        ("ContactGeometrySet", "contact geometry"),
        ("ControllerSet", "controllers"),
        ("ProbeSet", "probes"),
    ] {
        for x in objects(child(m, set)) {
            count(what, x.tag_name().name());
        }
    }
    for g in m.descendants().filter(|n| {
        n.is_element()
            && n.parent()
                .is_some_and(|p| p.has_tag_name("attached_geometry"))
    }) {
        count("geometry", g.tag_name().name());
    }
    for w in m.descendants().filter(|n| {
        n.parent().is_some_and(|p| p.has_tag_name("objects"))
            && n.ancestors().any(|a| a.has_tag_name("WrapObjectSet"))
    }) {
        count("wrap objects", w.tag_name().name());
    }
}
