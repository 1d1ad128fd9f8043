//! Checks on simulated mechanisms: the mechanical energy of a scene and the
//! world position of a point on a link, at given coordinates.

use nalgebra::Vector3;

use crate::dynamics::SceneWorkspace;
use crate::lang::args::{ArgValue, Args};
use crate::lang::diagnostics::{MxError, MxResult};
use crate::lang::host::errors::dyn_error;
use crate::lang::host::{Body, SceneValue};
use crate::lang::registry::Registry;
use crate::lang::topic::Topic;
use crate::lang::value::Value;
use crate::model::Model;

fn numbers(a: &Args, name: &str, arg: &ArgValue, n: usize, m: &Model) -> MxResult<Vec<f64>> {
    let v = arg.value.as_list().and_then(|l| {
        l.iter()
            .map(|x| x.as_number().filter(|x| x.is_finite()))
            .collect::<Option<Vec<f64>>>()
    });
    match v {
        Some(v) if v.len() == n => Ok(v),
        _ => Err(a
            .type_error(name, &format!("a list of {n} finite numbers"), arg)
            .help(format!(
                "coordinates, in order: {}",
                m.coordinate_names().join(", ")
            ))),
    }
}

fn energy(a: &mut Args) -> MxResult<Value> {
    let s = a.object::<SceneValue>("scene", "a scene (scene(body, …))")?;
    let scene = &s.scene;
    let n = scene.model.nq();
    let qa = a.arg("q")?;
    let q = numbers(a, "q", &qa, n, &scene.model)?;
    let va = a.arg("v")?;
    let v = numbers(a, "v", &va, n, &scene.model)?;
    let mut sw = SceneWorkspace::new(scene);
    let e = scene.energy(&mut sw, &q, &v).map_err(|e| dyn_error(e, a))?;
    Ok(Value::Number(e))
}

fn point(a: &mut Args) -> MxResult<Value> {
    let b = a.object::<Body>("body", "a body")?;
    let m = b.model.clone();
    let larg = a.arg("link")?;
    let Value::Str(name) = &larg.value else {
        return Err(a.type_error("link", "a link name", &larg));
    };
    let Some(link) = m.link_index(name) else {
        return Err(
            MxError::value(format!("`point`: the body has no link named `{name}`"))
                .at(larg.span)
                .help(format!(
                    "links: {}",
                    m.links()
                        .iter()
                        .map(|l| l.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                )),
        );
    };
    let qa = a.arg("q")?;
    let q = numbers(a, "q", &qa, m.nq(), &m)?;
    let at = match a.opt_named("at") {
        Some(p) => {
            let v = numbers(a, "at", &p, 3, &m)?;
            Vector3::new(v[0], v[1], v[2])
        }
        None => Vector3::zeros(),
    };
    let p = m
        .point_position(&q, link, &at)
        .map_err(|e| MxError::value(e.to_string()).at(a.call_span()))?;
    Ok(Value::list(vec![
        Value::Number(p.x),
        Value::Number(p.y),
        Value::Number(p.z),
    ]))
}

pub fn register(reg: &mut Registry) {
    reg.topic(Topic::Dynamics);
    reg.add(
        "energy(scene, q, v)",
        "The scene's mechanical energy at coordinates q and velocities v: kinetic + gravity + spring potential (J). \
         Constant along an exact motion of a conservative scene, so its drift measures an integrator's error.",
        |a, _| energy(a),
    );
    reg.add(
        "point(body, link, q, at: [0, 0, 0])",
        "World position of the point `at` (link frame) of `link` at coordinates q.",
        |a, _| point(a),
    );
}
