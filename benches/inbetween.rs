//! In-betweening against captured motion (`mx::report::inbetween`; the
//! protocol of `$MX_SHARED/data/inbetween/README.md`): windows every 40
//! frames, 10 context frames, gaps of 15/30/45 frames at 30 fps, root given
//! and the natural cut (every DOF cut, the frames after the gap where they
//! were captured); the interpolations, the capture itself (the reference
//! row), SP at its defaults, SP as it was before grounded SP ("today's SP":
//! `report::inbetween::todays_sp`), SP with `contact: "auto"` and SP with the
//! capture's own contacts (`contact: contacts(c, b)`, each `at:` from the
//! capture: the upper bound of any contact plan), side by side on the same
//! windows, in one run. Every score is `compare(…)`'s (`mx::score`). Then:
//! accuracy beside the ground measures and the contact plan's accuracy
//! against the capture's contacts (stance edges within 0.1 s, frames that
//! agree; all clips, then locomotion: walk/run/dash/turn), the goals of
//! issues 35 and 36 with PASS or MISS and by how much, and the leave-one-out
//! library rows. Rows are generic: a method pushed onto the list (an SP
//! setting per plan source, say) gets every column.
//!
//! Run: `cargo bench --bench inbetween`. Fast modes for development, all by
//! environment (combine them):
//! - `MX_INBETWEEN_CLIPS=walk*,run*`: only clips whose file name (without
//!   `.bvh`) matches one of these globs;
//! - `MX_INBETWEEN_LOCOMOTION=1`: only locomotion clips (walk, run, dash, turn);
//! - `MX_INBETWEEN_WINDOWS=K`: at most K windows per clip and gap (spread
//!   evenly; default all);
//! - `MX_INBETWEEN_GAPS=15,30,45` (default), e.g. `30` alone or `5,15`;
//! - `MX_INBETWEEN_ROOTS=given,filled` (default both; `filled` is the natural cut);
//! - `MX_INBETWEEN_METHODS=defaults,today,capture`: only methods whose label
//!   contains one of these (case-insensitive); Hermite always runs (every
//!   ratio is to it). The goals need `capture`, `slerp`, `defaults`, `today`;
//! - `MX_INBETWEEN_KNOBS=1`: also a row per knob of SP's objective;
//! - `MX_INBETWEEN_SP="label:smoothness:time_constant:coefficients[:nosupport];…"`:
//!   extra SP settings;
//! - `MX_INBETWEEN_GROUND="label:key=value,key=value;…"`: extra grounded SP
//!   rows (`contact: "auto"`) with the ground's settings changed
//!   (`GroundSettings`: `base=1e5/1e6/1e7`, `replans=1`, `prior=1e-5`,
//!   `example=1e-5`, `given=1e-3` (both scales, root given), `stance=1e10`, `floor=1e9`, `clearance=1e9`,
//!   `friction=0.8`, `window=25` (stall window), `bymismatch=1`, `plan=auto|context|example|steps`, and `anchor=0|1`,
//!   `coefficients=5`);
//! - `RAYON_NUM_THREADS=N`: windows run in parallel (each window's methods
//!   one after the other on one thread, so their times compare); the
//!   results do not depend on N. Rows whose SP options are identical are
//!   solved once per window (on main before grounded SP, "SP defaults" and
//!   "today's SP" are one solve).
//!
//! Held-out runs:
//! - `MX_INBETWEEN_DIR=PATH[:PATH…]`: the clips of these folders instead of
//!   `data/inbetween` (e.g. `$MX_SHARED/data/mocap`). Clips captured at
//!   another rate (CMU's 120 Hz) are **resampled to 30 fps** on load (their
//!   every fourth frame), so windows and gaps are the same frames and seconds
//!   on every clip. Foot joints are found by name (`ground`: Foot, Toe,
//!   Ankle, Heel: `Foot_L`/`Toes_L`, CMU's `LeftFoot`/`LeftToeBase`).
//! - `MX_INBETWEEN_VARIANTS=0.8,1.25,mirror`: also clips made from each
//!   loaded clip: played 0.8× and 1.25× as fast, and mirrored left for right
//!   (clips no one tuned on); `MX_INBETWEEN_ORIGINALS=0` drops the originals.
//!
//! Libraries (issue 36):
//! - `MX_INBETWEEN_LIBRARY=1`: also SP following a clip library held out
//!   from the window's own file (`example: lib` and `[lib, "self"]`, lib
//!   every clip of the library folders but the window's source file; built
//!   once per file); `MX_INBETWEEN_LIBRARY_DIRS=PATH[:PATH…]`: the library's
//!   folders (default: the clip folders).
//!
//! Output: `MX_INBETWEEN_CSV=PATH`: every window's result as CSV;
//! `MX_INBETWEEN_VIEW=PATH`: the HTML page of the worst SP window (capture, SP
//! and Hermite overlaid; default `target/inbetween_worst.html`).

mod common;
use common::shared;

use mx::report::heldout::{self, ClipFilter};
use mx::report::inbetween::{self, Case, Method, Protocol, RootMode};
use mx::report::leave_one_out::LeaveOneOut;
use mx::report::{goals, inbetween_tables};
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

fn var(name: &str) -> Option<String> {
    std::env::var(name).ok().filter(|v| !v.trim().is_empty())
}

fn flag(name: &str) -> bool {
    var(name).is_some_and(|v| v != "0")
}

fn dirs(name: &str) -> Option<Vec<PathBuf>> {
    std::env::var_os(name)
        .filter(|v| !v.is_empty())
        .map(|v| std::env::split_paths(&v).collect())
}

/// A comma-separated list of numbers; a bad entry stops the run naming it.
fn numbers<T: std::str::FromStr>(name: &str, v: &str) -> Vec<T> {
    v.split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| {
            s.parse()
                .unwrap_or_else(|_| panic!("{name}: `{s}` is not a number"))
        })
        .collect()
}

fn main() {
    let dirs_ =
        dirs("MX_INBETWEEN_DIR").unwrap_or_else(|| vec![shared().join("data").join("inbetween")]);
    let filter = ClipFilter::parse(
        &var("MX_INBETWEEN_CLIPS").unwrap_or_default(),
        flag("MX_INBETWEEN_LOCOMOTION"),
    )
    .unwrap_or_else(|e| panic!("MX_INBETWEEN_CLIPS: {e}"));
    let paths = heldout::clip_paths(&dirs_, &filter).unwrap_or_else(|e| panic!("{e}"));
    if paths.is_empty() {
        panic!(
            "no clip of {:?} passes MX_INBETWEEN_CLIPS / MX_INBETWEEN_LOCOMOTION",
            dirs_
        );
    }
    let mut cases = heldout::load(&paths).unwrap_or_else(|e| panic!("{e}"));
    if let Some(v) = var("MX_INBETWEEN_VARIANTS") {
        let parts: Vec<&str> = v.split(',').map(str::trim).collect();
        let mirror = parts.contains(&"mirror");
        let speeds: Vec<f64> = numbers(
            "MX_INBETWEEN_VARIANTS",
            &parts
                .iter()
                .filter(|p| **p != "mirror")
                .copied()
                .collect::<Vec<_>>()
                .join(","),
        );
        let made = heldout::variants(&cases, &speeds, mirror).unwrap_or_else(|e| panic!("{e}"));
        if var("MX_INBETWEEN_ORIGINALS").as_deref() == Some("0") {
            cases = made;
        } else {
            cases.extend(made);
        }
    }
    let mut p = Protocol {
        gaps: vec![15, 30, 45],
        windows_per_clip: var("MX_INBETWEEN_WINDOWS").map(|s| {
            s.parse()
                .unwrap_or_else(|_| panic!("MX_INBETWEEN_WINDOWS: `{s}` is not a count"))
        }),
        ..Protocol::default()
    };
    if let Some(g) = var("MX_INBETWEEN_GAPS") {
        p.gaps = numbers("MX_INBETWEEN_GAPS", &g);
    }
    if let Some(r) = var("MX_INBETWEEN_ROOTS") {
        p.roots = r
            .split(',')
            .map(|s| match s.trim() {
                "given" => RootMode::Given,
                "filled" | "natural" | "cut" => RootMode::Filled,
                other => panic!("MX_INBETWEEN_ROOTS: `{other}` is not given or filled"),
            })
            .collect();
    }
    let mut methods = inbetween::methods();
    if flag("MX_INBETWEEN_KNOBS") {
        methods.extend(inbetween::knob_methods());
    }
    if flag("MX_INBETWEEN_LIBRARY") {
        let lib_dirs = dirs("MX_INBETWEEN_LIBRARY_DIRS").unwrap_or_else(|| dirs_.clone());
        let refs: Vec<&std::path::Path> = lib_dirs.iter().map(|d| d.as_path()).collect();
        let loo = LeaveOneOut::of_folders(&refs, mx::library::Settings::default())
            .unwrap_or_else(|e| panic!("{e}"));
        eprintln!(
            "leave-one-out libraries of {} clips less the window's own source file",
            loo.len()
        );
        methods.extend(inbetween::library_methods(std::sync::Arc::new(loo)));
    }
    if let Some(extra) = var("MX_INBETWEEN_SP") {
        for spec in extra.split(';').filter(|s| !s.trim().is_empty()) {
            let f: Vec<&str> = spec.split(':').collect();
            let num = |i: usize, d: f64| f.get(i).and_then(|s| s.parse().ok()).unwrap_or(d);
            let mut o = mx::spacetime::SpOptions::default();
            o.prior.smoothness = num(1, o.prior.smoothness);
            if o.prior.smoothness == 0.0 {
                o.prior = mx::spacetime::Prior::none();
            }
            o.prior.time_constant = f.get(2).and_then(|s| s.parse().ok());
            o.settings.coefficients = num(3, o.settings.coefficients as f64) as usize;
            if f.get(4) == Some(&"nosupport") {
                o.support = mx::spacetime::Support::Off;
            }
            methods.push(Method::Sp(f[0].to_string(), Box::new(o)));
        }
    }
    if let Some(extra) = var("MX_INBETWEEN_GROUND") {
        for spec in extra.split(';').filter(|s| !s.trim().is_empty()) {
            let (label, kvs) = spec.split_once(':').unwrap_or((spec, ""));
            methods.push(Method::Sp(
                label.trim().to_string(),
                Box::new(ground_row(kvs)),
            ));
        }
    }
    if let Some(only) = var("MX_INBETWEEN_METHODS") {
        let keep: Vec<String> = only
            .split(',')
            .map(|s| s.trim().to_lowercase())
            .filter(|s| !s.is_empty())
            .collect();
        methods.retain(|m| {
            matches!(m, Method::Hermite)
                || keep
                    .iter()
                    .any(|k| m.label().to_lowercase().contains(k.as_str()))
        });
    }
    let windows: usize = p
        .gaps
        .iter()
        .map(|&g| cases.iter().map(|c| c.windows(&p, g).len()).sum::<usize>())
        .sum::<usize>()
        * p.roots.len();
    eprintln!(
        "{} clips from {:?} at {} fps, {} windows × {} methods ({} threads)",
        cases.len(),
        dirs_,
        inbetween::PROTOCOL_RATE,
        windows,
        methods.len(),
        rayon::current_num_threads()
    );
    let done = AtomicUsize::new(0);
    let total = windows * methods.len();
    let results = inbetween::run(&cases, &p, &methods, |r| {
        let n = done.fetch_add(1, Ordering::Relaxed) + 1;
        if n.is_multiple_of(50) {
            eprintln!(
                "  {n}/{total} fills ({} {} gap {} {})",
                r.clip, r.start, r.gap, r.method
            );
        }
    })
    .unwrap_or_else(|e| panic!("{e}"));
    let all = inbetween::summarise(&results);
    let loco = inbetween::summarise_locomotion(&results);
    println!("{}", inbetween::table(&all));
    println!(
        "\naccuracy and ground, all clips ({} clips):\n{}",
        cases.len(),
        inbetween_tables::accuracy_and_ground(&all)
    );
    println!(
        "\naccuracy and ground, locomotion (walk, run, dash, turn: {} clips):\n{}",
        cases
            .iter()
            .filter(|c| inbetween::is_locomotion(&c.name))
            .count(),
        inbetween_tables::accuracy_and_ground(&loco)
    );
    println!("\ngoals, all clips:\n{}", goals::table(&goals::goals(&all)));
    println!(
        "\ngoals, locomotion:\n{}",
        goals::table(&goals::goals(&loco))
    );
    let lib = inbetween_tables::library(&all);
    if lib.lines().count() > 2 {
        println!("\nleave-one-out library, all clips (L2P cm):\n{lib}");
        println!(
            "\nleave-one-out library, locomotion (L2P cm):\n{}",
            inbetween_tables::library(&loco)
        );
    }
    if let Some(path) = std::env::var_os("MX_INBETWEEN_CSV") {
        mx::atomic_file::write(
            std::path::Path::new(&path),
            inbetween::csv(&results).as_bytes(),
        )
        .unwrap_or_else(|e| panic!("{e}"));
    }
    view_worst(&cases, &p, &methods, &results);
}

/// A grounded row's options: `contact: "auto"` stated (a given root stands
/// too) with `kvs`
/// (`key=value,…`, see the module docs) changed; a bad key or value stops
/// the run naming it.
fn ground_row(kvs: &str) -> mx::spacetime::SpOptions {
    let mut o = mx::spacetime::SpOptions {
        contact: mx::spacetime::Contact::Auto,
        ..Default::default()
    };
    o.ground.stand_root_given = true;
    for kv in kvs.split(',').filter(|s| !s.trim().is_empty()) {
        let (k, v) = kv
            .split_once('=')
            .unwrap_or_else(|| panic!("MX_INBETWEEN_GROUND: `{kv}` is not key=value"));
        let num = |v: &str| -> f64 {
            v.trim()
                .parse()
                .unwrap_or_else(|_| panic!("MX_INBETWEEN_GROUND: {k}: `{v}` is not a number"))
        };
        let g = &mut o.ground;
        match k.trim() {
            "base" => g.base = v.split('/').filter(|s| !s.is_empty()).map(num).collect(),
            "replans" => g.replans = num(v) as usize,
            "prior" => g.prior_scale = num(v),
            "example" => g.example = num(v),
            "given" => g.root_given = (num(v), num(v)),
            "window" => g.stall_window = Some(num(v) as u64),
            "bymismatch" => g.by_mismatch = num(v) != 0.0,
            "stance" => g.stance = num(v),
            "floor" => g.floor = num(v),
            "clearance" => g.clearance = num(v),
            "friction" => g.friction = num(v),
            "anchor" => o.prior.anchor = num(v) != 0.0,
            "plan" => {
                g.plan = match v.trim() {
                    "auto" => mx::spacetime::solve::PlanSource::Auto,
                    "context" => mx::spacetime::solve::PlanSource::Context,
                    "example" => mx::spacetime::solve::PlanSource::Example,
                    "steps" => mx::spacetime::solve::PlanSource::Steps,
                    other => panic!("MX_INBETWEEN_GROUND: plan: `{other}`"),
                }
            }
            "coefficients" => o.settings.coefficients = num(v) as usize,
            other => panic!("MX_INBETWEEN_GROUND: unknown key `{other}`"),
        }
    }
    o
}

/// The worst SP window (largest worst-joint error, root given) as one page:
/// the capture, SP and the Hermite fill overlaid on one clock.
fn view_worst(
    cases: &[Case],
    p: &Protocol,
    methods: &[Method],
    results: &[inbetween::WindowResult],
) {
    let sp_label = inbetween::SP_DEFAULTS;
    let Some(w) = results
        .iter()
        .filter(|r| r.method == sp_label && r.root == RootMode::Given)
        .max_by(|a, b| a.worst.total_cmp(&b.worst))
    else {
        return;
    };
    let case = cases
        .iter()
        .find(|c| c.name == w.clip)
        .expect("the clip of a result");
    let Some(sp) = methods.iter().find(|m| m.label() == sp_label) else {
        return;
    };
    let fill = |m: &Method| match inbetween::fill_window(case, p, w.start, w.gap, w.root, m) {
        Ok(f) => f.motion,
        Err(e) => panic!("{e}"),
    };
    let (sp_m, h_m) = (fill(sp), fill(&Method::Hermite));
    let path = std::env::var_os("MX_INBETWEEN_VIEW")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(env!("CARGO_MANIFEST_DIR"))
                .join("target")
                .join("inbetween_worst.html")
        });
    let title = format!(
        "{} frame {} gap {} ({}): capture, SP, Hermite",
        w.clip,
        w.start,
        w.gap,
        w.root.label()
    );
    match mx::io::viewer::write_overlay(
        &path,
        &case.body,
        &[("capture", &case.capture), ("SP", &sp_m), ("hermite", &h_m)],
        &title,
    ) {
        Ok(()) => eprintln!("worst SP window: {title} → {}", path.display()),
        Err(e) => eprintln!("could not write {}: {e}", path.display()),
    }
}
