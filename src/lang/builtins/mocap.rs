//! Motion-capture built-ins: the `.bvh` format of `load`/`save`, `bvh_info`,
//! `body_of`, `human`, `fit`, `positions`, `plot` (`view` is `view.rs`). The work is done by
//! `crate::mocap` and `crate::io::{plot, viewer}`; this file converts values
//! and errors.
//!
//! A motion unit holds no skeleton: `save(m, "x.bvh")` and `body_of(m)` use
//! the most recently loaded clip's skeleton that names all of `m`'s DOFs
//! (`crate::mocap::registry`), or the one of a body given as `body:`.

use std::sync::Arc;

use indexmap::IndexMap;

use crate::lang::args::{ArgValue, Args, describe};
use crate::lang::ast::Span;
use crate::lang::diagnostics::{ErrorKind, MxError, MxResult};
use crate::lang::eval::Evaluator;
use crate::lang::host::errors::{diagnostic, error_at, file_error};
use crate::lang::host::motion::{ClipSource, LoadedClips, Provenance, provenance};
use crate::lang::host::{Body, Motion};
use crate::lang::registry::Registry;
use crate::lang::topic::Topic;
use crate::lang::value::Value;
use crate::mocap::bvh::Units;
use crate::mocap::{self, Missing, MocapError, to_motion};
use crate::motion::{Curve, Dof, Interval, Mu};

/// A mocap error at `span`, with the engine's kind and advice.
fn mocap_error(e: MocapError, span: Span) -> MxError {
    error_at(&e, span)
}

fn mu_of(a: &Args, name: &str, arg: &ArgValue) -> MxResult<Mu> {
    a.mu_of(name, arg)
}

fn body_of_arg(a: &Args, name: &str, arg: &ArgValue) -> MxResult<Body> {
    a.free_body_of(name, arg, "a body, e.g. body_of(clip, mass: 70)")
}

/// The clip `value` (whose motion unit is `mu`) came from: its own
/// provenance when that names every DOF, else the most recent clip this
/// interpreter loaded that does.
fn clip_of(value: &Value, mu: &Mu, ev: &Evaluator) -> Option<Arc<ClipSource>> {
    provenance(value)
        .and_then(|p| p.clip.clone())
        .filter(|c| c.covers(mu))
        .or_else(|| ev.ctx.session.get::<LoadedClips>().find_for(mu))
}

/// The optional `unit:` argument (metres per file unit).
fn units_arg(a: &mut Args) -> MxResult<Units> {
    match a.opt_named("unit") {
        None => Ok(Units::Auto),
        Some(v) => match v.value {
            Value::Number(s) if s.is_finite() && s > 0.0 => Ok(Units::MetresPerUnit(s)),
            _ => Err(a.type_error(
                "unit",
                "a positive number of metres per file unit (0.01 for centimetres)",
                &v,
            )),
        },
    }
}

fn no_skeleton(span: Span) -> MxError {
    MxError::new(
        ErrorKind::Value,
        "no loaded clip's skeleton names all of this motion's DOFs",
    )
    .at(span)
    .help("load the .bvh the motion came from first, or pass `body: body_of(clip)`")
}

/// The motion-capture built-ins, by topic.
pub fn register(reg: &mut Registry) {
    clips(reg);
    bodies(reg);
    pictures(reg);
}

/// BVH clips: the `.bvh` format and `bvh_info`.
fn clips(reg: &mut Registry) {
    reg.topic(Topic::Files);
    gltf_files(reg);
    reg.loader(
        "bvh",
        "BVH motion capture: an Mu with DOFs `Joint.channel` (radians, metres; cubic between frames). Option `unit:` metres per file unit (default: detected; see bvh_info).",
        |path, a, ev| {
            let units = units_arg(a)?;
            let clip = to_motion::load(path, units).map_err(|e| diagnostic(&e, a, a.call_span()))?;
            // One line per kind of looseness, on stderr: stdout carries only `print` output.
            for w in &clip.warnings {
                eprintln!("warning: {}: {w}", path.display());
            }
            let source = Arc::new(ClipSource {
                skeleton: Arc::new(clip.skeleton),
                metres_per_unit: clip.units.metres_per_unit,
                frame_time: clip.frame_time,
                path: path.display().to_string(),
            });
            ev.ctx.session.get::<LoadedClips>().remember(source.clone());
            Ok(Motion::Mu(clip.mu).with_provenance(Provenance {
                clip: Some(source),
                ..Provenance::default()
            }))
        },
    );
    reg.saver(
        "bvh",
        "BVH: skeleton and motion, sampled at the clip's frame rate (or `rate:`); `body:` chooses the skeleton.",
        |v, path, a, ev| {
            let span = a.call_span();
            let Some(Motion::Mu(m)) = v.as_object::<Motion>() else {
                return Err(a.error(ErrorKind::Type, format!("BVH holds a motion unit (Mu), not {}", describe(v))));
            };
            let body = match a.opt_named("body") {
                Some(b) => Some(body_of_arg(a, "body", &b)?),
                None => None,
            };
            let rate = match a.opt_named("rate") {
                Some(r) => match r.value {
                    Value::Number(x) if x.is_finite() && x > 0.0 => Some(x),
                    _ => return Err(a.type_error("rate", "a positive number of frames per second", &r)),
                },
                None => None,
            };
            let (skeleton, scale, dt) = match body.and_then(|b| b.skeleton) {
                Some((s, scale)) => (s, scale, None),
                None => {
                    let k = clip_of(v, m, ev).ok_or_else(|| no_skeleton(span))?;
                    (k.skeleton.clone(), k.metres_per_unit, Some(k.frame_time))
                }
            };
            let dt = rate.map(|r| 1.0 / r).or(dt).or_else(|| to_motion::sample_period(m)).unwrap_or(1.0 / 30.0);
            // Written atomically: a failed save leaves an existing file as it was.
            let (file, _) = to_motion::to_bvh(m, &skeleton, scale, dt).map_err(|e| mocap_error(e, span))?;
            let text = mocap::bvh::to_string(&file).map_err(|e| mocap_error(e.into(), span))?;
            crate::io::atomic::write_atomic(path, text.as_bytes()).map_err(|e| file_error(e, span))
        },
    );
    reg.add(
        "bvh_info(path, unit: auto)",
        "What load(path) would read: a record {frames, frame_time, joints, dofs, metres_per_unit, units, reason, wraps, warnings} (warnings: what the reader tolerated, one `line N: …` string each).",
        |a, ev| {
            let arg = a.arg("path")?;
            let Value::Str(p) = &arg.value else { return Err(a.type_error("path", "a file name string", &arg)) };
            let path = ev.resolve_path(p, arg.span)?;
            let units = units_arg(a)?;
            let clip = to_motion::load(&path, units).map_err(|e| diagnostic(&e, a, arg.span))?;
            let mut r = IndexMap::new();
            r.insert("frames".into(), Value::Number(clip.frames as f64));
            r.insert("frame_time".into(), Value::Number(clip.frame_time));
            r.insert("joints".into(), Value::Number(clip.skeleton.joints.len() as f64));
            r.insert("dofs".into(), Value::Number(clip.mu.len() as f64));
            r.insert("metres_per_unit".into(), Value::Number(clip.units.metres_per_unit));
            r.insert("units".into(), Value::str(&clip.units.name));
            r.insert("reason".into(), Value::str(&clip.units.reason));
            r.insert("wraps".into(), Value::Number(clip.wraps_removed as f64));
            r.insert("warnings".into(), Value::list(clip.warnings.iter().map(|w| Value::str(w.to_string())).collect()));
            Ok(Value::record(r))
        },
    );
}

fn gltf_error(e: crate::io::gltf::GltfError, span: Span) -> MxError {
    error_at(&e, span)
}

/// The motions of a `save(…, "x.glb")`: one Mu, or a non-empty list of them.
fn motions_to_save(v: &Value, a: &Args) -> MxResult<Vec<Mu>> {
    let bad = || {
        a.error(
            ErrorKind::Type,
            format!(
                "glTF holds a motion unit (Mu) or a list of them, not {}",
                describe(v)
            ),
        )
    };
    match v {
        Value::List(items) if !items.is_empty() => items
            .iter()
            .map(|x| match x.as_object::<Motion>() {
                Some(Motion::Mu(m)) => Ok(m.clone()),
                _ => Err(bad()),
            })
            .collect(),
        _ => match v.as_object::<Motion>() {
            Some(Motion::Mu(m)) => Ok(vec![m.clone()]),
            _ => Err(bad()),
        },
    }
}

/// glTF 2.0: `.glb` and `.gltf` (`crate::io::gltf`).
fn gltf_files(reg: &mut Registry) {
    for ext in ["glb", "gltf"] {
        reg.loader(
            ext,
            "glTF 2.0 skeleton animation: an Mu with DOFs `Joint.Zrotation/Xrotation/Yrotation` (Z·X·Y Euler, radians) per joint of the skin and \
             `Joint.X/Y/Zposition` (metres) at the root and wherever a joint's translation is animated; frames on the keys' grid from t = 0. \
             `body_of(m)` gives its body (the saved one, masses and inertias, when mx wrote the file). Option `animation:` a name or an index (0 first; default the first). \
             `forces: true` reads instead the contact forces the animation carries (saved with `forces:`): the motion `ground_forces` gave, on the animation's frames from t = 0 \
             (`POINT.Fx/Fy/Fz`, `residual.Fx/…/Mz`, `residual.percent_bw`; N and N·m in the file's axes, the saved body's), number for number; an error when it carries none. \
             Meshes, scale and morph channels are ignored with a note.",
            load_gltf,
        );
        reg.saver(
            ext,
            "glTF 2.0 (.glb binary; .gltf one JSON file, its buffer embedded as base64): the body's joints as a skinned node hierarchy (y-up metres, names kept), \
             each motion an animation of LINEAR rotation (quaternion) channels and the root's translation, keyed on its frames from 0 s; \
             each joint's mass, centre of mass and inertia in its node's `extras.mx`. \
             `save(m, \"x.glb\", body: b)`; several motions of one body: `save([a, b], \"x.glb\", body: b, names: [\"a\", \"b\"])`. \
             `body:` defaults to the body of the clip m came from; `rate:` frames per second (default: the motion's own). \
             `forces: ground_forces(m, b)` (or `forces: true`, which computes it with its defaults on the saved body and rate) also writes the contact forces per frame, \
             on the animation's frames, to the animation's `extras.mx.forces`: the points' names and nodes, frames × points × 3 forces (N), the residual force (N), \
             moment (N·m about the centre of mass) and % body weight, the frame times and the body's up, in the file's axes (y-up for a body from BVH). \
             Several motions: a list, one per motion (`true`, `false` or a forces motion). Without `forces:` no dynamics runs. \
             `load(\"x.glb\", forces: true)` reads them back.",
            save_gltf,
        );
    }
}

/// `load("x.glb", animation: …, forces: …)`: the animation as a clip, or the contact forces it carries.
fn load_gltf(path: &std::path::Path, a: &mut Args, ev: &mut Evaluator) -> MxResult<Value> {
    let which = match a.opt_named("animation") {
        None => crate::io::gltf::Which::First,
        Some(v) => match &v.value {
            Value::Str(s) => crate::io::gltf::Which::Name(s.to_string()),
            Value::Number(k) if *k >= 0.0 && k.fract() == 0.0 => {
                crate::io::gltf::Which::Index(*k as usize)
            }
            _ => {
                return Err(a.type_error(
                    "animation",
                    "an animation's name or its index (0 first)",
                    &v,
                ));
            }
        },
    };
    let forces = match a.opt_named("forces") {
        None => false,
        Some(v) => match v.value {
            Value::Bool(b) => b,
            _ => {
                return Err(a.type_error(
                    "forces",
                    "true (read the contact forces the animation carries) or false",
                    &v,
                ));
            }
        },
    };
    if forces {
        let span = a.call_span();
        let saved = crate::io::gltf::load_forces(path, which).map_err(|e| gltf_error(e, span))?;
        let mu = saved.series.to_motion().map_err(|e| error_at(&e, span))?;
        return Ok(Value::object(Motion::Mu(mu)));
    }
    let loaded = crate::io::gltf::load(path, which).map_err(|e| gltf_error(e, a.call_span()))?;
    // Notes on stderr: stdout carries only `print` output.
    for n in &loaded.notes {
        eprintln!("note: {}: {n}", path.display());
    }
    let clip = loaded.clip;
    let source = Arc::new(ClipSource {
        path: path.display().to_string(),
        skeleton: Arc::new(clip.skeleton),
        metres_per_unit: clip.units.metres_per_unit,
        frame_time: clip.frame_time,
    });
    ev.ctx.session.get::<LoadedClips>().remember(source.clone());
    Ok(Motion::Mu(clip.mu).with_provenance(Provenance {
        clip: Some(source),
        ..Provenance::default()
    }))
}

/// `save(m, "x.glb", body: …, rate: …, names: […], forces: …)`.
fn save_gltf(v: &Value, path: &std::path::Path, a: &mut Args, ev: &mut Evaluator) -> MxResult<()> {
    let span = a.call_span();
    let motions = motions_to_save(v, a)?;
    let body = match a.opt_named("body") {
        Some(b) => body_of_arg(a, "body", &b)?.model.clone(),
        None => {
            let k = clip_of(v, &motions[0], ev).ok_or_else(|| no_skeleton(span))?;
            let mass = k.skeleton.stated_mass().unwrap_or(70.0);
            let (model, _) =
                mocap::body_of::body_of_motion(&k.skeleton, &motions[0], mass, k.metres_per_unit)
                    .map_err(|e| mocap_error(e, span))?;
            Arc::new(model)
        }
    };
    let rate = match a.opt_named("rate") {
        Some(r) => match r.value {
            Value::Number(x) if x.is_finite() && x > 0.0 => Some(x),
            _ => return Err(a.type_error("rate", "a positive number of frames per second", &r)),
        },
        None => None,
    };
    let names: Vec<String> = match a.opt_named("names") {
        None if motions.len() == 1 => vec![
            path.file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "motion".into()),
        ],
        None => (1..=motions.len()).map(|k| format!("motion {k}")).collect(),
        Some(l) => {
            let bad = |a: &Args| {
                a.type_error(
                    "names",
                    &format!("a list of {} strings, one per motion", motions.len()),
                    &l,
                )
            };
            let Value::List(items) = &l.value else {
                return Err(bad(a));
            };
            if items.len() != motions.len() {
                return Err(bad(a));
            }
            items
                .iter()
                .map(|v| match v {
                    Value::Str(s) => Ok(s.to_string()),
                    _ => Err(bad(a)),
                })
                .collect::<MxResult<_>>()?
        }
    };
    let forces = forces_to_save(a, &motions, &body, rate)?;
    let forces: Vec<Option<&crate::ground::ForceSeries>> =
        forces.iter().map(Option::as_ref).collect();
    let clips: Vec<crate::io::gltf::Clip> = names
        .iter()
        .zip(&motions)
        .map(|(name, motion)| crate::io::gltf::Clip { name, motion })
        .collect();
    crate::io::gltf::save_with_forces(&body, &clips, &forces, rate, path)
        .map_err(|e| gltf_error(e, span))
}

/// The `forces:` of a glTF save, one entry per motion: `true` computes
/// `ground_forces` (its defaults, on `body`, at the saved `rate`, so on the
/// animation's frames); a forces motion is read at the animation's frames;
/// `false` or nil, none; a list gives one of these per motion. No `forces:`:
/// none, and no dynamics runs.
fn forces_to_save(
    a: &mut Args,
    motions: &[Mu],
    body: &crate::model::Model,
    rate: Option<f64>,
) -> MxResult<Vec<Option<crate::ground::ForceSeries>>> {
    let Some(arg) = a.opt_named("forces") else {
        return Ok(vec![]);
    };
    let what = "true (compute ground_forces(m, body)), false, what ground_forces(m, body) returns, or a list of these, one per motion";
    let items: Vec<Value> = match &arg.value {
        Value::List(items) if items.len() == motions.len() => items.to_vec(),
        Value::List(_) => {
            return Err(a.type_error(
                "forces",
                &format!("a list of {} entries, one per motion", motions.len()),
                &arg,
            ));
        }
        Value::Bool(_) | Value::Nil => vec![arg.value.clone(); motions.len()],
        v if motions.len() == 1 => vec![v.clone()],
        _ => {
            return Err(a.type_error(
                "forces",
                &format!("a list of {} entries, one per motion", motions.len()),
                &arg,
            ));
        }
    };
    let at = |e: &dyn crate::lang::host::errors::EngineError| error_at(e, arg.span);
    items
        .iter()
        .zip(motions)
        .map(|(item, m)| match item {
            Value::Bool(false) | Value::Nil => Ok(None),
            Value::Bool(true) => {
                let o = crate::ground::GroundOptions {
                    rate,
                    ..Default::default()
                };
                let g = crate::ground::ground_forces(m, body, &o, 0.8).map_err(|e| at(&e))?;
                Ok(Some(g.series()))
            }
            v => match v.as_object::<Motion>() {
                Some(Motion::Mu(f)) => {
                    let times = mocap::frame_times(m, rate).map_err(|e| at(&e))?;
                    let r = rate
                        .or_else(|| to_motion::sample_period(m).map(|dt| 1.0 / dt))
                        .unwrap_or(30.0);
                    crate::ground::ForceSeries::from_motion(f, &times, 1.0 / r)
                        .map(Some)
                        .map_err(|e| at(&e))
                }
                _ => Err(a.type_error("forces", what, &arg)),
            },
        })
        .collect()
}

/// Bodies from clips: `body_of`, `human`, `fit`, `positions`.
fn bodies(reg: &mut Registry) {
    reg.topic(Topic::Dynamics);
    reg.add(
        "body_of(clip, mass: 70)",
        "A body whose coordinates are exactly the clip's DOFs (revolute per rotation channel, prismatic per position channel), de Leva (1996) segments scaled by bone lengths and `mass` (kg). \
         Gravity points from the hips to the feet (joints named Foot, Toe, Ankle, Heel), snapped to an axis: y for the usual BVH skeleton, z for a z-up one; read from the rest pose, or from the clip's frames where the rest pose does not stand; y for a skeleton without feet. \
         A glTF file mx wrote carries its body's masses and inertias: body_of gives that body back (`mass:` scales it; its default is then the saved total).",
        |a, ev| {
            let arg = a.arg("clip")?;
            let m = mu_of(a, "clip", &arg)?;
            let k = clip_of(&arg.value, &m, ev).ok_or_else(|| no_skeleton(arg.span))?;
            let mass = a.number_or("mass", k.skeleton.stated_mass().unwrap_or(70.0))?;
            let (model, _) = mocap::body_of::body_of_motion(&k.skeleton, &m, mass, k.metres_per_unit).map_err(|e| diagnostic(&e, a, a.call_span()))?;
            Ok(Value::object(Body {
                model: Arc::new(model),
                skeleton: Some((k.skeleton.clone(), k.metres_per_unit)),
                human: None,
                coupling: None,
                osim: None,
            }))
        },
    );
    reg.add(
        "human(clip, mass: 70)",
        "The 44-DOF anatomical model (6 root + 38 joint DOFs: hinge knees/elbows, 2-DOF ankles/wrists, 3-DOF hips/shoulders/spine/neck) with limb lengths from the clip's skeleton.",
        |a, ev| {
            let arg = a.arg("clip")?;
            let m = mu_of(a, "clip", &arg)?;
            let mass = a.number_or("mass", 70.0)?;
            let k = clip_of(&arg.value, &m, ev).ok_or_else(|| no_skeleton(arg.span))?;
            let h = mocap::human::human(&k.skeleton, k.metres_per_unit, mass).map_err(|e| diagnostic(&e, a, a.call_span()))?;
            Ok(Value::object(Body {
                model: Arc::new(h.model.clone()),
                skeleton: Some((k.skeleton.clone(), k.metres_per_unit)),
                human: Some(Arc::new(h)),
                coupling: None,
                osim: None,
            }))
        },
    );
    reg.add(
        "fit(clip, model, angle_weight: 0.1)",
        "Convert a clip to the human model by per-frame least squares on joint positions and segment orientations (angle_weight: metres one radian counts as; 0 = positions only); notes the errors on stderr (positions RMS/max in cm, orientations RMS/max in degrees) and returns the model's motion.",
        |a, ev| {
            let carg = a.arg("clip")?;
            let m = mu_of(a, "clip", &carg)?;
            let barg = a.arg("model")?;
            let body = body_of_arg(a, "model", &barg)?;
            let span = a.call_span();
            let Some(h) = body.human.clone() else {
                return Err(MxError::new(ErrorKind::Type, "fit needs the model made by human(clip)").at(barg.span));
            };
            let k = clip_of(&carg.value, &m, ev).ok_or_else(|| no_skeleton(carg.span))?;
            let dt = to_motion::sample_period(&m).unwrap_or(k.frame_time);
            let (file, _) = to_motion::to_bvh(&m, &k.skeleton, k.metres_per_unit, dt).map_err(|e| mocap_error(e, span))?;
            let options = mocap::human::FitOptions { angle_weight: a.number_or("angle_weight", mocap::human::FitOptions::default().angle_weight)? };
            let (mu, rep) = mocap::human::fit(&file, k.metres_per_unit, &h, options, Some(&ev.ctx.cancel)).map_err(|e| diagnostic(&e, a, span))?;
            // A note, not a result: stderr, so stdout carries only `print` output.
            eprintln!("fit: {} frames, {rep}", file.frame_count());
            Ok(Value::object(Motion::Mu(mu)))
        },
    );
    reg.add(
        "positions(m, body)",
        "World positions of the body's joints over time as an Mu with DOFs `Joint.x`, `Joint.y`, `Joint.z` (metres), sampled at the motion's frame rate.",
        |a, _| {
            let marg = a.arg("m")?;
            let m = mu_of(a, "m", &marg)?;
            let barg = a.arg("body")?;
            let body = body_of_arg(a, "body", &barg)?;
            let span = a.call_span();
            let p = mocap::positions(&m, &body.model, None, Missing::Error).map_err(|e| mocap_error(e, span))?;
            positions_mu(&p).map_err(|e| mocap_error(e, span)).map(|mu| Value::object(Motion::Mu(mu)))
        },
    );
}

/// Pictures of motions: `plot`, `view`.
fn pictures(reg: &mut Registry) {
    reg.topic(Topic::Files);
    reg.add(
        "plot(m, path)",
        "Draw every DOF of m over time to an SVG file (use m.only(…) or only(m, …) to choose), gaps grey, conflicts red.",
        |a, ev| {
            let marg = a.arg("m")?;
            let m = match marg.value.as_object::<Motion>() {
                Some(Motion::Mu(m)) => m.clone(),
                Some(other) => {
                    let d = other.as_dof().unwrap_or_default();
                    Mu::from_iter([("value".to_string(), d)])
                }
                None => return Err(a.type_error("m", "a motion (Interval, Dof or Mu)", &marg)),
            };
            let parg = a.arg("path")?;
            let Value::Str(p) = &parg.value else { return Err(a.type_error("path", "an .svg file name", &parg)) };
            let path = ev.resolve_path(p, parg.span)?;
            super::core::create_parent_folder(&path, parg.span)?;
            let rate = to_motion::sample_period(&m).map(|d| 1.0 / d).unwrap_or(60.0).min(240.0);
            crate::io::plot::plot_motion(&m, &[], rate, &path)
                .map_err(|e| MxError::new(ErrorKind::Io, e.to_string()).at(parg.span))?;
            Ok(Value::Nil)
        },
    );
}

/// Joint positions as an Mu: `Joint.x/.y/.z`, sampled curves over the times.
fn positions_mu(p: &mocap::Positions) -> Result<Mu, MocapError> {
    let t0 = p.times.first().copied().unwrap_or(0.0);
    let n = p.times.len();
    let dt = if n > 1 { p.times[1] - p.times[0] } else { 1.0 };
    let stop = if n > 1 { p.times[n - 1] } else { t0 + dt };
    let mut mu = Mu::new();
    for (j, name) in p.names.iter().enumerate() {
        for (axis, suffix) in ["x", "y", "z"].iter().enumerate() {
            let vals: Vec<f64> = p.points.iter().map(|fr| fr[j][axis]).collect();
            let curve = if n > 1 {
                Curve::samples(t0, dt, vals)?
            } else {
                Curve::constant(vals[0])?
            };
            mu.insert(
                format!("{name}.{suffix}"),
                Dof::new(vec![Interval::curve(curve, t0, stop)?])?,
            );
        }
    }
    Ok(mu)
}
