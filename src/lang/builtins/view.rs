//! `view`: the self-contained HTML viewer of motions on a body, with its
//! ground layers. The work is done by `crate::io::viewer` (and its
//! `ground` module); this file reads the options, finds what SP attached to
//! each motion (its filled gaps and contact plan) and converts errors.

use std::sync::Arc;

use crate::io::viewer::ground::{GroundRequest, Layer};
use crate::lang::args::{ArgValue, Args};
use crate::lang::diagnostics::{ErrorKind, MxError, MxResult};
use crate::lang::host::sp_report::report_of;
use crate::lang::host::{Body, Motion};
use crate::lang::registry::Registry;
use crate::lang::topic::Topic;
use crate::lang::value::Value;
use crate::motion::Mu;

fn mu_of(a: &Args, name: &str, arg: &ArgValue) -> MxResult<Mu> {
    a.mu_of(name, arg)
}

fn body_of_arg(a: &Args, name: &str, arg: &ArgValue) -> MxResult<Body> {
    a.free_body_of(name, arg, "a body, e.g. body_of(clip, mass: 70)")
}

pub fn register(reg: &mut Registry) {
    reg.topic(Topic::Files);
    reg.add(
        "view(m, body, path, labels: [...], curves: [...], ground: true, floor: \"auto\")",
        "Write a self-contained HTML viewer of m played on body (3D figure, play/pause, slider, orbit; camera presets front/side/top, \
         keys 1/2/3; DOF curves below) over m's own span. The page's address keeps the view and time (`view.html#view=side&t=2.5`). \
         m may be a list of motions of one body: they share the stage and one clock, each in its own colour, named in a legend by `labels` \
         (default \"motion 1\", …). `curves` chooses the curves: DOF names, joint names (all their DOFs) or globs (`\"*Knee.Xrotation\"`); \
         by default the DOFs that move most, fingers, thumbs and toes left out. Undefined stretches are gaps in the curves and hold the \
         last pose, marked undefined; the gaps an SP result filled are shaded. \
         `ground` (on by default for a body with feet under gravity; `false` turns it off, a list such as `[\"plan\", \"forces\"]` chooses): \
         the floor as a plane at the first motion's floor (or `floor`, m), anything below it drawn under it; footprints (an SP result's contact plan, \
         coloured by what planned each stance, else the motion's own contacts); a strip under the curves, one row per contact point, with bars where \
         the point is in contact and where the plan stands it; `\"forces\"` and `\"residual\"` (not on by default: they run inverse dynamics) draw \
         `ground_forces`' contact forces as arrows scaled by body weight and its residual at the centre of mass. Keys g/p/c/f/r toggle \
         floor, plan, contacts, forces and residual; h holds the camera still; the address keeps layers, camera, zoom and follow \
         (`#ground=forces,plan&follow=off&zoom=1.5`).",
        |a, ev| {
            let marg = a.arg("m")?;
            let mus: Vec<Mu> = match &marg.value {
                Value::List(items) => {
                    if items.is_empty() {
                        return Err(a.type_error("m", "a motion unit (Mu) or a non-empty list of them", &marg));
                    }
                    items
                        .iter()
                        .map(|v| match v.as_object::<Motion>() {
                            Some(Motion::Mu(m)) => Ok(m.clone()),
                            _ => Err(a.type_error("m", "a list of motion units (Mu)", &marg)),
                        })
                        .collect::<MxResult<_>>()?
                }
                _ => vec![mu_of(a, "m", &marg)?],
            };
            let barg = a.arg("body")?;
            let body = body_of_arg(a, "body", &barg)?;
            let parg = a.arg("path")?;
            let Value::Str(p) = &parg.value else { return Err(a.type_error("path", "an .html file name", &parg)) };
            let path = ev.resolve_path(p, parg.span)?;
            let title = path.file_stem().map(|s| s.to_string_lossy().to_string()).unwrap_or_default();
            let labels: Vec<String> = match a.opt_named("labels") {
                None if mus.len() == 1 => vec![title.clone()],
                None => (1..=mus.len()).map(|k| format!("motion {k}")).collect(),
                Some(l) => {
                    let bad = |a: &Args| a.type_error("labels", &format!("a list of {} strings, one per motion", mus.len()), &l);
                    let Value::List(items) = &l.value else { return Err(bad(a)) };
                    if items.len() != mus.len() {
                        return Err(bad(a));
                    }
                    items.iter().map(|v| match v { Value::Str(s) => Ok(s.to_string()), _ => Err(bad(a)) }).collect::<MxResult<_>>()?
                }
            };
            let chosen = view_curves(a, &mus)?;
            let chosen: Vec<&str> = chosen.iter().map(String::as_str).collect();
            let tracks: Vec<(&str, &Mu)> = labels.iter().map(String::as_str).zip(mus.iter()).collect();
            let mut data = crate::io::viewer::overlay(&body.model, &tracks, &title, &chosen)
                .map_err(|e| MxError::new(ErrorKind::Value, e.to_string()).at(a.call_span()))?;
            // the gaps each SP result filled, shaded on its curves
            let values: Vec<&Value> = match &marg.value {
                Value::List(items) => items.iter().collect(),
                v => vec![v],
            };
            for (track, v) in data.tracks.iter_mut().zip(values.iter().copied()) {
                track.filled = report_of(v).map(|r| filled_spans(&r)).unwrap_or_default();
            }
            let request = ground_request(a)?;
            let plans: Vec<Option<Arc<crate::spacetime::SpReport>>> = values.iter().map(|v| report_of(v)).collect();
            if let Some(request) = request {
                let plans: Vec<_> = plans.iter().map(|r| r.as_ref().and_then(|r| r.contacts.as_ref())).collect();
                data.ground = crate::io::viewer::ground::ground_layer(&body.model, &tracks, &data, &plans, &request)
                    .map_err(|e| MxError::new(ErrorKind::Value, e.to_string()).at(a.call_span()))?;
                if data.ground.is_none() && a.has_named("ground") {
                    let span = a.span_of("ground").unwrap_or(a.call_span());
                    return Err(MxError::new(ErrorKind::Value, "the body has no ground to show: no foot contact points (no joint named like Foot, Toe, Ankle, Heel or calcn) or no gravity")
                        .at(span)
                        .help("leave `ground` out, or give a body with feet"));
                }
            }
            super::core::create_parent_folder(&path, parg.span)?;
            crate::io::viewer::write_html(&data, &path).map_err(|e| MxError::new(ErrorKind::Io, e.to_string()).at(parg.span))?;
            Ok(Value::Nil)
        },
    );
}

/// `ground:` and `floor:`: `None` when the ground is off (`ground: false`),
/// else the layers asked for (default: those that run no dynamics).
fn ground_request(a: &mut Args) -> MxResult<Option<GroundRequest>> {
    let mut request = GroundRequest::default();
    if let Some(g) = a.opt_named("ground") {
        let bad = |a: &Args| {
            a.type_error(
                "ground",
                "true, false or a list of layers (\"floor\", \"plan\", \"contacts\", \"forces\", \"residual\")",
                &g,
            )
        };
        match &g.value {
            Value::Bool(false) => return Ok(None),
            Value::Bool(true) => {}
            Value::List(items) => {
                let mut layers = vec![];
                for v in items.iter() {
                    let Value::Str(s) = v else { return Err(bad(a)) };
                    let Some(layer) = Layer::parse(s) else {
                        return Err(MxError::new(ErrorKind::Value, format!("no ground layer `{s}`"))
                            .at(g.span)
                            .help("the layers are \"floor\", \"plan\", \"contacts\", \"forces\" and \"residual\""));
                    };
                    if !layers.contains(&layer) {
                        layers.push(layer);
                    }
                }
                request.layers = layers;
            }
            _ => return Err(bad(a)),
        }
    }
    if let Some(f) = a.opt_named("floor") {
        request.floor = match &f.value {
            Value::Str(s) if &**s == "auto" => None,
            Value::Number(x) if x.is_finite() => Some(*x),
            _ => {
                return Err(a.type_error(
                    "floor",
                    "a height in metres, or \"auto\" (the first motion's floor)",
                    &f,
                ));
            }
        };
    }
    Ok(Some(request))
}

/// The DOFs `view`'s `curves:` asks for (names, joint names, globs; see
/// `io::viewer::curves::select`) among the motions' DOFs; empty when not
/// given (the viewer's default choice).
fn view_curves(a: &mut Args, mus: &[Mu]) -> MxResult<Vec<String>> {
    let Some(c) = a.opt_named("curves") else {
        return Ok(vec![]);
    };
    let bad = |a: &Args| {
        a.type_error(
            "curves",
            "a list of DOF names, joint names or globs (strings)",
            &c,
        )
    };
    let Value::List(items) = &c.value else {
        return Err(bad(a));
    };
    let patterns: Vec<&str> = items
        .iter()
        .map(|v| match v {
            Value::Str(s) => Ok(&**s),
            _ => Err(bad(a)),
        })
        .collect::<MxResult<_>>()?;
    let mut names: Vec<&str> = Vec::new();
    for m in mus {
        for n in m.dofs.keys() {
            if !names.contains(&n.as_str()) {
                names.push(n);
            }
        }
    }
    crate::io::viewer::curves::select(&names, &patterns)
        .map(|v| v.into_iter().map(str::to_string).collect())
        .map_err(|u| {
            let p = &u.pattern;
            let e = MxError::new(ErrorKind::Value, u.to_string()).at(c.span).label("matches nothing");
            let joints = names.iter().map(|n| crate::io::viewer::curves::joint_of(n));
            match crate::lang::diagnostics::did_you_mean(p, names.iter().copied().chain(joints)) {
                Some(s) => e.help(format!("did you mean `{s}`? (`*` and `?` are wildcards)")),
                None => e.help("give DOF names (`\"Hips.Xrotation\"`), joint names (`\"LeftKnee\"`) or globs (`\"*Knee*\"`); `dofs(m)` lists them"),
            }
        })
}

/// The spans an SP result filled: each solved gap group's, and the DOFs
/// SP filled by Hermite or held constant, merged where they overlap.
fn filled_spans(r: &crate::spacetime::SpReport) -> Vec<[f64; 2]> {
    let mut spans: Vec<[f64; 2]> = r
        .groups
        .iter()
        .map(|g| [g.t0, g.t1])
        .chain(
            r.hermite
                .iter()
                .chain(&r.constant)
                .map(|u| [u.start, u.stop]),
        )
        .filter(|[a, b]| a.is_finite() && b.is_finite() && a <= b)
        .collect();
    spans.sort_by(|x, y| x[0].total_cmp(&y[0]));
    let mut merged: Vec<[f64; 2]> = Vec::new();
    for s in spans {
        match merged.last_mut() {
            Some(last) if s[0] <= last[1] => last[1] = last[1].max(s[1]),
            _ => merged.push(s),
        }
    }
    merged
}
