//! Dynamics built-ins: bodies (`load("robot.urdf")`), `coordinates`,
//! `inverse_dynamics`, `forward_dynamics`, `mass_matrix`, `scene`.
//! Vectors are plain lists in the body's coordinate order. A body loaded from
//! URDF uses gravity `[0, 0, −9.81]` (Pinocchio's default, z up) unless a call
//! passes `gravity: [...]`, so results match Pinocchio.

use std::sync::Arc;

use indexmap::IndexMap;
use nalgebra::{DMatrix, Vector3};

use crate::dynamics::{
    DynamicsError, ExternalForce, Forces, Integrator, JointState, LimitPenalty, Scene, Spring,
    State, Workspace, coupled_forward_dynamics, coupled_inverse_dynamics, coupled_mass_matrix,
    forward_dynamics, inverse_dynamics, mass_matrix, simulate,
};
use crate::lang::args::{ArgValue, Args};
use crate::lang::diagnostics::{MxError, MxResult};
use crate::lang::eval::Evaluator;
use crate::lang::host::errors::{dyn_error, engine_error};
use crate::lang::host::{Body, Motion};
use crate::lang::registry::Registry;
use crate::lang::topic::Topic;
use crate::lang::value::Value;

// The scene value lives in `lang::host`; this keeps the path embedders use.
pub use crate::lang::host::scene::SceneValue;
use crate::model::Model;
use crate::model::urdf::UrdfOptions;
use crate::motion::{Curve, Dof, Interval, Mu};

fn nums(v: &[f64]) -> Value {
    Value::list(v.iter().map(|x| Value::Number(*x)).collect())
}

/// The `body` argument as a body with every coordinate free (scenes).
fn body(a: &mut Args) -> MxResult<Arc<Model>> {
    let b = dyn_body(a)?;
    match b.coupling {
        None => Ok(b.model),
        Some(_) => Err(
            MxError::value(b.free_model(&format!("`{}`", a.name())).unwrap_err()).at(a.call_span()),
        ),
    }
}

/// The `body` argument, coupled coordinates included.
fn dyn_body(a: &mut Args) -> MxResult<Body> {
    let arg = a.arg("body")?;
    if let Some(b) = arg.value.as_object::<Body>() {
        return Ok(b.clone());
    }
    if let Some(s) = arg.value.as_object::<SceneValue>() {
        return Ok(Body::from_model(s.scene.model.clone()));
    }
    Err(a.type_error("body", "a body (e.g. `load(\"robot.urdf\")`)", &arg))
}

/// A list of numbers named `name`, one per coordinate of `b` in order.
fn coords(a: &mut Args, b: &Body, name: &str) -> MxResult<Vec<f64>> {
    let arg = a.arg(name)?;
    list_of(a, &arg, name, b.coordinate_names())
}

fn list_n(a: &Args, arg: &ArgValue, name: &str, m: &Model) -> MxResult<Vec<f64>> {
    list_of(a, arg, name, m.coordinate_names())
}

fn list_of(a: &Args, arg: &ArgValue, name: &str, names: &[String]) -> MxResult<Vec<f64>> {
    let Value::List(l) = &arg.value else {
        return Err(a.type_error(name, "a list of numbers", arg));
    };
    let n = names.len();
    if l.len() != n {
        return Err(MxError::value(format!(
            "`{}`: `{name}` has {} numbers but the body has {n} coordinates",
            a.name(),
            l.len()
        ))
        .at(arg.span)
        .help(format!("the coordinates, in order: {}", names.join(", "))));
    }
    l.iter()
        .enumerate()
        .map(|(i, v)| match v.as_number() {
            Some(x) if x.is_finite() => Ok(x),
            _ => Err(MxError::type_error(format!(
                "`{}`: element {i} of `{name}` (`{}`) must be a finite number",
                a.name(),
                names[i]
            ))
            .at(arg.span)),
        })
        .collect()
}

fn vec3(a: &Args, arg: &ArgValue, name: &str) -> MxResult<Vector3<f64>> {
    a.vector3(arg, name)
}

fn gravity(a: &mut Args, m: &Model) -> MxResult<Vector3<f64>> {
    match a.opt_named("gravity") {
        Some(g) => vec3(a, &g, "gravity"),
        None => Ok(m.default_gravity),
    }
}

/// A link by name, or `"world"` / `nil` for the world.
fn link_ref(
    a: &Args,
    v: Option<&Value>,
    m: &Model,
    span: crate::lang::ast::Span,
) -> MxResult<Option<usize>> {
    match v {
        None | Some(Value::Nil) => Ok(None),
        Some(Value::Str(s)) if &**s == "world" => Ok(None),
        Some(Value::Str(s)) => m.link_index(s).map(Some).ok_or_else(|| {
            MxError::value(format!("`{}`: the body has no link named `{s}`", a.name()))
                .at(span)
                .help(format!(
                    "links: {}",
                    m.links()
                        .iter()
                        .map(|l| l.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                ))
        }),
        Some(other) => Err(MxError::type_error(format!(
            "`{}`: a link is given by its name (a string) or \"world\", found {}",
            a.name(),
            other.type_name()
        ))
        .at(span)),
    }
}

fn rec_num(
    a: &Args,
    r: &IndexMap<String, Value>,
    keys: &[&str],
    span: crate::lang::ast::Span,
) -> MxResult<Option<f64>> {
    for k in keys {
        if let Some(v) = r.get(*k) {
            return match v.as_number() {
                Some(x) if x.is_finite() => Ok(Some(x)),
                _ => Err(MxError::type_error(format!(
                    "`{}`: `{k}` must be a finite number",
                    a.name()
                ))
                .at(span)),
            };
        }
    }
    Ok(None)
}

fn rec_vec3(
    a: &Args,
    r: &IndexMap<String, Value>,
    keys: &[&str],
    span: crate::lang::ast::Span,
) -> MxResult<Option<Vector3<f64>>> {
    for k in keys {
        if let Some(v) = r.get(*k) {
            return vec3(
                a,
                &ArgValue {
                    value: v.clone(),
                    span,
                    name: None,
                },
                k,
            )
            .map(Some);
        }
    }
    Ok(None)
}

fn build_scene(a: &mut Args) -> MxResult<Value> {
    let m = body(a)?;
    let mut s = Scene::new(m.clone());
    let err = |e: DynamicsError, a: &Args| dyn_error(e, a);
    if let Some(g) = a.opt_named("gravity") {
        let g = vec3(a, &g, "gravity")?;
        s = s.with_gravity(g).map_err(|e| err(e, a))?;
    }
    if let Some(d) = a.opt_named("damping") {
        let coeffs: Vec<f64> = match &d.value {
            Value::Number(x) => vec![*x],
            Value::List(_) => list_n(a, &d, "damping", &m)?,
            _ => {
                return Err(a.type_error(
                    "damping",
                    "a number or a list with one per coordinate",
                    &d,
                ));
            }
        };
        s = s.with_damping(&coeffs).map_err(|e| err(e, a))?;
    }
    if let Some(sp) = a.opt_named("springs") {
        let Value::List(l) = &sp.value else {
            return Err(a.type_error(
                "springs",
                "a list of records {a:, pa:, b:, pb:, k:, c:, rest:}",
                &sp,
            ));
        };
        for v in l.iter() {
            let Value::Record(r) = v else {
                return Err(a.type_error(
                    "springs",
                    "a list of records {a:, pa:, b:, pb:, k:, c:, rest:}",
                    &sp,
                ));
            };
            let la = link_ref(a, r.get("a").or(r.get("from")), &m, sp.span)?;
            let lb = link_ref(a, r.get("b").or(r.get("to")), &m, sp.span)?;
            let pa =
                rec_vec3(a, r, &["pa", "at_a", "point_a"], sp.span)?.unwrap_or_else(Vector3::zeros);
            let pb =
                rec_vec3(a, r, &["pb", "at_b", "point_b"], sp.span)?.unwrap_or_else(Vector3::zeros);
            let k = rec_num(a, r, &["k", "stiffness"], sp.span)?.unwrap_or(0.0);
            let c = rec_num(a, r, &["c", "damping"], sp.span)?.unwrap_or(0.0);
            // Default rest length: the distance at the zero configuration.
            let rest = match rec_num(a, r, &["rest", "rest_length"], sp.span)? {
                Some(x) => x,
                None => {
                    let q0 = vec![0.0; m.nq()];
                    let at = |l: Option<usize>, p: &Vector3<f64>| match l {
                        None => Ok(*p),
                        Some(i) => m.point_position(&q0, i, p),
                    };
                    let d = at(lb, &pb).and_then(|b| at(la, &pa).map(|a| (b - a).norm()));
                    d.map_err(|e| MxError::value(e.to_string()).at(sp.span))?
                }
            };
            s = s
                .with_spring(Spring {
                    link_a: la,
                    point_a: pa,
                    link_b: lb,
                    point_b: pb,
                    stiffness: k,
                    damping: c,
                    rest_length: rest,
                })
                .map_err(|e| err(e, a))?;
        }
    }
    if let Some(fs) = a.opt_named("forces") {
        let Value::List(l) = &fs.value else {
            return Err(a.type_error(
                "forces",
                "a list of records {link:, at:, force: [x, y, z]}",
                &fs,
            ));
        };
        for v in l.iter() {
            let Value::Record(r) = v else {
                return Err(a.type_error(
                    "forces",
                    "a list of records {link:, at:, force: [x, y, z]}",
                    &fs,
                ));
            };
            let Some(link) = link_ref(a, r.get("link"), &m, fs.span)? else {
                return Err(
                    MxError::value("a force needs `link:` naming a link of the body").at(fs.span),
                );
            };
            let point = rec_vec3(a, r, &["at", "point"], fs.span)?.unwrap_or_else(Vector3::zeros);
            let Some(force) = rec_vec3(a, r, &["force", "f"], fs.span)? else {
                return Err(
                    MxError::value("a force needs `force: [x, y, z]` (world frame, N)").at(fs.span),
                );
            };
            s = s
                .with_force(ExternalForce { link, point, force })
                .map_err(|e| err(e, a))?;
        }
    }
    if let Some(lim) = a.opt_named("limits") {
        let p = match &lim.value {
            Value::Bool(false) | Value::Nil => None,
            Value::Bool(true) => Some(LimitPenalty {
                stiffness: 1e4,
                damping: 100.0,
            }),
            Value::Record(r) => Some(LimitPenalty {
                stiffness: rec_num(a, r, &["k", "stiffness"], lim.span)?.unwrap_or(1e4),
                damping: rec_num(a, r, &["c", "damping"], lim.span)?.unwrap_or(100.0),
            }),
            _ => {
                return Err(a.type_error(
                    "limits",
                    "true or a record {stiffness:, damping:}",
                    &lim,
                ));
            }
        };
        if let Some(p) = p {
            s = s.with_limits(p).map_err(|e| err(e, a))?;
        }
    }
    if let Some(dr) = a.opt_named("driven") {
        s = with_driven(a, s, &dr, &m)?;
    }
    Ok(Value::object(SceneValue { scene: s }))
}

/// `driven: {coordinate: rate, …}`: coordinates moved at a constant rate.
fn with_driven(a: &Args, mut s: Scene, dr: &ArgValue, m: &Model) -> MxResult<Scene> {
    let Value::Record(r) = &dr.value else {
        return Err(a.type_error("driven", "a record {coordinate: rate, …}", dr));
    };
    for (k, v) in r.iter() {
        let Some(i) = m.coordinate_index(k) else {
            return Err(MxError::value(format!(
                "`{}`: the body has no coordinate `{k}`",
                a.name()
            ))
            .at(dr.span)
            .help(format!("coordinates: {}", m.coordinate_names().join(", "))));
        };
        let Some(rate) = v.as_number() else {
            return Err(MxError::type_error(format!(
                "`driven`: the rate of `{k}` must be a number"
            ))
            .at(dr.span));
        };
        s = s.with_driven(i, rate).map_err(|e| dyn_error(e, a))?;
    }
    Ok(s)
}

/// Initial coordinates from `init: {name: value, …}` or `init: {q: {…}, v: {…}}`.
fn initial_state(a: &Args, init: Option<ArgValue>, m: &Model) -> MxResult<State> {
    let mut st = State {
        q: vec![0.0; m.nq()],
        v: vec![0.0; m.nq()],
    };
    let Some(init) = init else { return Ok(st) };
    let Value::Record(r) = &init.value else {
        return Err(a.type_error(
            "init",
            "a record {coordinate: value, …} or {q: {…}, v: {…}}",
            &init,
        ));
    };
    let nested = r.keys().all(|k| k == "q" || k == "v") && !r.is_empty();
    let parts: Vec<(&IndexMap<String, Value>, bool)> = if nested {
        let mut p = Vec::new();
        for (k, v) in r.iter() {
            let Value::Record(inner) = v else {
                return Err(MxError::type_error(format!(
                    "`init.{k}` must be a record {{coordinate: value, …}}"
                ))
                .at(init.span));
            };
            p.push((&**inner, k == "v"));
        }
        p
    } else {
        vec![(&**r, false)]
    };
    for (rec, is_v) in parts {
        for (k, v) in rec.iter() {
            let Some(i) = m.coordinate_index(k) else {
                return Err(MxError::value(format!(
                    "`{}`: the body has no coordinate `{k}`",
                    a.name()
                ))
                .at(init.span)
                .help(format!("coordinates: {}", m.coordinate_names().join(", "))));
            };
            let Some(x) = v.as_number().filter(|x| x.is_finite()) else {
                return Err(
                    MxError::type_error(format!("`init`: `{k}` must be a finite number"))
                        .at(init.span),
                );
            };
            if is_v {
                st.v[i] = x;
            } else {
                st.q[i] = x;
            }
        }
    }
    Ok(st)
}

fn run_simulation(a: &mut Args, ev: &mut Evaluator) -> MxResult<Value> {
    let sarg = a.arg("scene")?;
    let scene = match (
        sarg.value.as_object::<SceneValue>(),
        sarg.value.as_object::<Body>(),
    ) {
        (Some(s), _) => s.scene.clone(),
        // A bare body is a scene with no effects at all (not even gravity).
        (None, Some(b)) => Scene::new(
            b.free_model("`simulate`")
                .map_err(|m| MxError::value(m).at(sarg.span))?,
        ),
        _ => {
            return Err(a.type_error(
                "scene",
                "a scene (`scene(body, gravity: …)`) or a body",
                &sarg,
            ));
        }
    };
    let duration = a.finite("duration")?;
    let dt = a.named_number_or("dt", 1e-3)?;
    let tol = match a.opt_named("tol") {
        Some(t) => Some(
            t.value
                .as_number()
                .ok_or_else(|| a.type_error("tol", "a number", &t))?,
        ),
        None => None,
    };
    let method = match a.opt_named("integrator") {
        Some(v) => match &v.value {
            Value::Str(s) => Integrator::from_name(s, tol)
                .map_err(|e| MxError::value(e.to_string()).at(v.span))?,
            _ => {
                return Err(a.type_error(
                    "integrator",
                    "a name: \"euler\", \"semi_implicit_euler\", \"rk4\" or \"dopri5\"",
                    &v,
                ));
            }
        },
        None => Integrator::Rk4,
    };
    let init = a.opt_named("init");
    let mut st = initial_state(a, init, &scene.model)?;
    // Driven coordinates start (and stay) at their rates.
    scene.drive_state(&mut st.v);
    let want_v = match a.opt_named("velocities") {
        Some(v) => matches!(v.value, Value::Bool(true)),
        None => false,
    };
    let steps = (duration / dt).round();
    // A progress bar on stderr for long runs (hidden when stderr is not a terminal).
    let bar = (steps * scene.model.num_links() as f64 > 2e6).then(|| {
        let b = indicatif::ProgressBar::new(1000);
        b.set_message("simulate");
        b
    });
    let mut progress = |f: f64| {
        if let Some(b) = &bar {
            b.set_position((f * 1000.0) as u64);
        }
    };
    let token = ev.ctx.cancel.clone();
    let tr = simulate(&scene, duration, dt, method, &st, &token, &mut progress);
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    let tr = tr.map_err(|e| dyn_error(e, a))?;
    if tr.t.len() < 2 {
        return Err(MxError::value(
            "`simulate`: the duration must cover at least one step (duration ≥ dt)",
        )
        .at(a.call_span()));
    }
    let tend = tr.t[tr.t.len() - 1];
    let mut mu = Mu::new();
    let mut add = |name: String, values: Vec<f64>| -> MxResult<()> {
        let c = Curve::samples(0.0, dt, values).map_err(|e| MxError::value(e.to_string()))?;
        let iv = Interval::curve(c, 0.0, tend).map_err(|e| MxError::value(e.to_string()))?;
        mu.insert(name, Dof::from(iv));
        Ok(())
    };
    for (k, name) in tr.names.iter().enumerate() {
        add(name.clone(), tr.q.iter().map(|q| q[k]).collect())?;
        if want_v {
            add(format!("{name}.v"), tr.v.iter().map(|v| v[k]).collect())?;
        }
    }
    Ok(Value::object(Motion::Mu(mu)))
}

pub fn register(reg: &mut Registry) {
    reg.topic(Topic::Dynamics);
    reg.add(
        "simulate(scene, duration, dt: 0.001, integrator: \"rk4\", tol: 1e-8, init: {}, velocities: false)",
        "Simulate a scene from `init` (coordinate values; or {q: {…}, v: {…}}) and return a motion of its \
         coordinates sampled every dt (velocities as `<name>.v` on request). Integrators: euler, \
         semi_implicit_euler, rk4, dopri5 (adaptive, `tol`). Ctrl-C cancels.",
        run_simulation,
    );
    reg.loader(
        "urdf",
        "A body from a URDF robot description (fixed base; gravity [0, 0, -9.81] by default). Option `mimic: true`: <mimic> joints follow their joint (q = multiplier·q_joint + offset) instead of being free coordinates.",
        |path, a, _ev| {
            let mimic = match a.opt_named("mimic") {
                None => false,
                Some(v) => match v.value {
                    Value::Bool(b) => b,
                    _ => return Err(a.type_error("mimic", "true or false", &v)),
                },
            };
            let (m, coupling) = Model::from_urdf_file_with(path, UrdfOptions { mimic })
                .map_err(|e| engine_error(&e))?;
            let mut b = Body::from_model(Arc::new(m));
            b.coupling = coupling.map(Arc::new);
            Ok(Value::object(b))
        },
    );
    reg.add(
        "coordinates(body)",
        "The names of the body's coordinates, in the order every dynamics list uses.",
        |a, _| {
            let b = dyn_body(a)?;
            Ok(Value::list(
                b.coordinate_names().iter().map(Value::str).collect(),
            ))
        },
    );
    reg.add(
        "inverse_dynamics(body, q, v, a, gravity: [0, 0, -9.81])",
        "Joint torques τ = M(q) a + C(q, v) v + g(q) (lists in coordinate order).",
        |a, _| {
            let b = dyn_body(a)?;
            let m = b.model.clone();
            let q = coords(a, &b, "q")?;
            let v = coords(a, &b, "v")?;
            let acc = coords(a, &b, "a")?;
            let g = gravity(a, &m)?;
            let mut ws = Workspace::new(&m);
            let mut tau = vec![0.0; q.len()];
            match &b.coupling {
                Some(c) => coupled_inverse_dynamics(
                    &m,
                    c,
                    &mut ws,
                    &JointState::new(&q, &v, &acc),
                    &g,
                    &mut tau,
                ),
                None => inverse_dynamics(&m, &mut ws, &q, &v, &acc, &g, &mut tau),
            }
            .map_err(|e| dyn_error(e, a))?;
            Ok(nums(&tau))
        },
    );
    reg.add(
        "forward_dynamics(body, q, v, tau, gravity: [0, 0, -9.81])",
        "Joint accelerations under torques tau (articulated-body algorithm).",
        |a, _| {
            let b = dyn_body(a)?;
            let m = b.model.clone();
            let q = coords(a, &b, "q")?;
            let v = coords(a, &b, "v")?;
            let tau = coords(a, &b, "tau")?;
            let g = gravity(a, &m)?;
            let mut ws = Workspace::new(&m);
            let mut qdd = vec![0.0; q.len()];
            match &b.coupling {
                Some(c) => coupled_forward_dynamics(
                    &m,
                    c,
                    &mut ws,
                    &q,
                    &v,
                    &Forces::new(&tau, &g),
                    &mut qdd,
                ),
                None => forward_dynamics(&m, &mut ws, &q, &v, &tau, &g, &mut qdd),
            }
            .map_err(|e| dyn_error(e, a))?;
            Ok(nums(&qdd))
        },
    );
    reg.add(
        "mass_matrix(body, q)",
        "The joint-space mass matrix M(q), a list of rows.",
        |a, _| {
            let b = dyn_body(a)?;
            let m = b.model.clone();
            let q = coords(a, &b, "q")?;
            let mut ws = Workspace::new(&m);
            let n = q.len();
            let mm = match &b.coupling {
                Some(c) => coupled_mass_matrix(&m, c, &mut ws, &q),
                None => {
                    let mut mm = DMatrix::zeros(n, n);
                    mass_matrix(&m, &mut ws, &q, &mut mm).map(|_| mm)
                }
            }
            .map_err(|e| dyn_error(e, a))?;
            Ok(Value::list(
                (0..n)
                    .map(|i| nums(&mm.row(i).iter().copied().collect::<Vec<_>>()))
                    .collect(),
            ))
        },
    );
    reg.add(
        "scene(body, gravity: [x, y, z], damping: d, springs: [...], forces: [...], limits: true, driven: {coordinate: rate})",
        "A body with the effects it declares; only those are computed. springs: records \
         {a: link, pa: [..], b: link|\"world\", pb: [..], k:, c:, rest:}; forces: {link:, at: [..], force: [..]}; \
         driven: coordinates moved at a constant rate whatever the forces (a motor; the clock of a deforming_surface).",
        |a, _| build_scene(a),
    );
}
