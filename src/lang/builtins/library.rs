//! Clip libraries: `library`, `match` and the `.mxlib` format.

use std::sync::Arc;

use crate::lang::args::{ArgValue, Args};
use crate::lang::diagnostics::{ErrorKind, MxError, MxResult};
use crate::lang::eval::Evaluator;
use crate::lang::host::errors::diagnostic;
use crate::lang::host::motion::skeleton_of as clip_of;
use crate::lang::host::sp_report::{num, record};
use crate::lang::host::{LibraryValue, Motion};
use crate::lang::registry::Registry;
use crate::lang::topic::Topic;
use crate::lang::value::Value;
use crate::library::{self, ClipInput, Library, LibraryError, Settings, Skipped, file};
use crate::mocap::to_motion;

/// A library error at the option it names (`rate`, `warps`), else at the call.
fn lib_error(e: LibraryError, a: &Args) -> MxError {
    diagnostic(&e, a, a.call_span())
}

/// `rate:` and `warps:`, if either is given.
fn settings_arg(a: &mut Args) -> MxResult<Option<Settings>> {
    let mut s = Settings::default();
    let mut given = false;
    if let Some(r) = a.opt_named("rate") {
        s.rate = r
            .value
            .as_number()
            .ok_or_else(|| a.type_error("rate", "a number of frames per second", &r))?;
        given = true;
    }
    if let Some(w) = a.opt_named("warps") {
        let list = w.value.as_list().and_then(|l| {
            l.iter()
                .map(|v| v.as_number())
                .collect::<Option<Vec<f64>>>()
        });
        s.warps = list.ok_or_else(|| a.type_error("warps", "a list of numbers", &w))?;
        given = true;
    }
    if given {
        s.check().map_err(|e| lib_error(e, a))?;
    }
    Ok(given.then_some(s))
}

/// One element of `library([…])`: a motion (its skeleton from its clip) or
/// a path to a `.bvh` file.
fn clip_input(
    name: String,
    v: &Value,
    a: &Args,
    span_arg: &ArgValue,
    ev: &Evaluator,
) -> MxResult<Result<ClipInput, Skipped>> {
    let skip = |reason: String| {
        Ok(Err(Skipped {
            clip: name.clone(),
            reason,
        }))
    };
    if let Some(path) = v.as_str() {
        let p = ev.resolve_path(path, span_arg.span)?;
        return Ok(library::read_clip(&p));
    }
    let Some(Motion::Mu(mu)) = v.as_object::<Motion>() else {
        return Err(a.type_error(
            "clips",
            "a folder path, or a list (or record) of motions or .bvh paths",
            span_arg,
        ));
    };
    let Some(clip) = clip_of(v, mu, ev) else {
        return skip("no loaded clip's skeleton names all its DOFs".into());
    };
    match to_motion::to_bvh(mu, &clip.skeleton, clip.metres_per_unit, clip.frame_time) {
        Ok((file, _)) => Ok(Ok(ClipInput {
            name,
            file,
            metres_per_unit: clip.metres_per_unit,
            source: None,
        })),
        Err(e) => skip(e.to_string()),
    }
}

fn build(a: &mut Args, ev: &mut Evaluator) -> MxResult<Value> {
    let arg = a.arg("clips")?;
    let settings = settings_arg(a)?.unwrap_or_default();
    let (clips, skipped) = match &arg.value {
        Value::Str(_) => {
            let path = ev.resolve_path(arg.value.as_str().unwrap_or(""), arg.span)?;
            if path.is_dir() {
                // read, indexed and let go file by file: the library keeps features
                let paths = library::bvh_files(&path).map_err(|e| lib_error(e, a))?;
                let lib = Library::build_files(&paths, settings).map_err(|e| lib_error(e, a))?;
                return Ok(library_value(lib));
            } else {
                let one = clip_input(String::new(), &arg.value, a, &arg, ev)?;
                match one {
                    Ok(c) => (vec![c], vec![]),
                    Err(s) => (vec![], vec![s]),
                }
            }
        }
        Value::List(items) => {
            let mut out = (vec![], vec![]);
            for (i, v) in items.iter().enumerate() {
                match clip_input(format!("clip{}", i + 1), v, a, &arg, ev)? {
                    Ok(c) => out.0.push(c),
                    Err(s) => out.1.push(s),
                }
            }
            out
        }
        Value::Record(r) => {
            let mut out = (vec![], vec![]);
            for (k, v) in r.iter() {
                match clip_input(k.clone(), v, a, &arg, ev)? {
                    Ok(c) => out.0.push(c),
                    Err(s) => out.1.push(s),
                }
            }
            out
        }
        _ => {
            return Err(a.type_error(
                "clips",
                "a folder path, or a list (or record) of motions or .bvh paths",
                &arg,
            ));
        }
    };
    let lib = Library::build(clips, skipped, settings).map_err(|e| lib_error(e, a))?;
    Ok(library_value(lib))
}

fn library_value(lib: Library) -> Value {
    // reported, not dropped: on stderr now and in `lib.skipped`
    for s in &lib.skipped {
        eprintln!("warning: library: clip `{}` skipped: {}", s.clip, s.reason);
    }
    Value::object(LibraryValue(Arc::new(lib)))
}

fn matches(a: &mut Args, ev: &mut Evaluator) -> MxResult<Value> {
    let lib = a.object::<LibraryValue>("lib", "a clip library, e.g. library(\"clips/\")")?;
    let (m, marg) = a.mu("m")?;
    let t0 = a.number("t0")?;
    let t1 = a.number("t1")?;
    let k = a.named_number_or("k", 5.0)?;
    if !(1.0..=1e4).contains(&k) {
        return Err(a.error(
            ErrorKind::Value,
            format!("`k` must be a whole number from 1 to 10000, found {k}"),
        ));
    }
    let clip = clip_of(&marg.value, &m, ev).ok_or_else(|| {
        MxError::new(
            ErrorKind::Value,
            "no loaded clip's skeleton names all of this motion's DOFs: a match needs the skeleton m drives",
        )
        .at(marg.span)
        .help("load the .bvh the motion came from first")
    })?;
    let lib = &lib.0;
    let q = lib
        .query(&m, &clip.skeleton, clip.metres_per_unit, t0, t1)
        .map_err(|e| lib_error(e, a))?;
    let found = lib.match_gap(&q, k as usize);
    Ok(Value::list(
        found
            .iter()
            .map(|x| {
                record(vec![
                    ("clip", Value::str(&x.name)),
                    ("time", num(x.time)),
                    ("duration", num(x.duration)),
                    ("warp", num(x.warp)),
                    ("mismatch", num(x.mismatch)),
                ])
            })
            .collect(),
    ))
}

/// The clip library built-ins.
pub fn register(reg: &mut Registry) {
    reg.topic(Topic::Spacetime);
    reg.add(
        "library(clips, rate: 30, warps: [1])",
        "A clip library: a motion-matching index over every frame of every clip, for SP's `example: lib` and `match`. \
         `clips`: a folder (every .bvh file in it a clip, named after the file), or a list of motions (named clip1, clip2, …) \
         or .bvh paths, or a record {name: motion}. Each frame is described by its feet and hands relative to the pelvis, \
         the feet's and pelvis's velocity, and where the pelvis was and will be a third of a second away, in the body's heading frame. \
         Clips on other skeletons work when their joints are named alike (Left…/…_L, foot/ankle, hand/wrist); \
         a clip that cannot be matched is skipped with the reason (on stderr and in `lib.skipped`). \
         `rate:` the grid the clips are sampled on (Hz); `warps:` the time warps a stretch may take (clip time per gap time). \
         Fields: clips, skipped, frames, rate, warps. Keep a built index with save(lib, \"x.mxlib\").",
        build,
    );
    reg.add(
        "match(lib, m, t0, t1, k: 5)",
        "The k library stretches that best fill the gap [t0, t1] of m, best first: those whose frames arrive as m does before t0 \
         and leave as m does after t1 (m must be defined a third of a second before and after). \
         Each is a record {clip, time (s, where the stretch starts in the clip), duration (s), warp, mismatch \
         (mean squared normalised feature difference: 0 is exact)}. Stretches of one clip within a third of a second of a better one are left out.",
        matches,
    );
    reg.topic(Topic::Files);
    reg.loader(
        "mxlib",
        "A clip library saved by save(lib, \"x.mxlib\"): versioned and checksummed, with the clips inside. \
         Refused with the reason when damaged, of another format version, stale (a clip file changed since), \
         or built with other settings than `rate:`/`warps:` given here.",
        |path, a, _ev| {
            let expect = settings_arg(a)?;
            let lib = file::load(path, expect.as_ref()).map_err(|e| {
                MxError::new(ErrorKind::Io, e.to_string())
                    .at(a.call_span())
                    .help("rebuild it with library(…) and save it again")
            })?;
            Ok(Value::object(LibraryValue(Arc::new(lib))))
        },
    );
    reg.saver(
        "mxlib",
        "A clip library (written atomically: a killed or failed save leaves the old file).",
        |v, path, a, _ev| {
            let Some(lib) = v.as_object::<LibraryValue>() else {
                return Err(a.error(
                    ErrorKind::Type,
                    format!(
                        "a .mxlib file holds a clip library, not {}",
                        crate::lang::args::describe(v)
                    ),
                ));
            };
            file::save(&lib.0, path).map_err(|e| lib_error(e, a))
        },
    );
}
