//! In-betweening against captured motion (`mx::report::inbetween`; the
//! protocol of `$MX_SHARED/data/inbetween/README.md`): windows every 40
//! frames, 10 context frames, gaps of 5/15/30/45 frames, root given and root
//! filled; SP at its defaults and at every setting tried, `fill(m, "hermite")`
//! and `fill(m, "slerp")` side by side on the same windows, in one run.
//!
//! Run: `cargo bench --bench inbetween`. Environment:
//! - `MX_INBETWEEN_WINDOWS=K`: at most K windows per clip and gap (default: all);
//! - `MX_INBETWEEN_DIR=PATH`: another folder of BVH clips (same protocol);
//! - `MX_INBETWEEN_METHODS=a,b`: only these method labels (plus Hermite);
//! - `MX_INBETWEEN_GAPS=15,30`, `MX_INBETWEEN_ROOTS=given|filled`;
//! - `MX_INBETWEEN_CSV=PATH`: every window's result as CSV;
//! - `MX_INBETWEEN_LIBRARY=1`: also SP following a clip library held out
//!   from the window's own file (`example: lib` and `[lib, "self"]`, lib every
//!   clip of the folder but the window's; built once per file);
//!
//! Beside the main table it prints the ground measures (skate within 2 cm of
//! the capture's floor, penetration, ground residual; the capture as the
//! reference row), for all clips and for the locomotion clips alone.
//! - `MX_INBETWEEN_VIEW=PATH`: where the HTML page of the worst SP window goes
//!   (capture, SP and Hermite overlaid; default `target/inbetween_worst.html`).

mod common;
use common::shared;

use mx::report::inbetween::{self, Case, Method, Protocol, RootMode};
use mx::report::leave_one_out::LeaveOneOut;
use std::path::PathBuf;

fn main() {
    let dir = std::env::var_os("MX_INBETWEEN_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| shared().join("data").join("inbetween"));
    let cases = match Case::load_dir(&dir) {
        Ok(c) if !c.is_empty() => c,
        Ok(_) => panic!("no .bvh clips in {}", dir.display()),
        Err(e) => panic!("{e}"),
    };
    let mut p = Protocol {
        windows_per_clip: std::env::var("MX_INBETWEEN_WINDOWS")
            .ok()
            .and_then(|s| s.parse().ok()),
        ..Protocol::default()
    };
    if let Ok(g) = std::env::var("MX_INBETWEEN_GAPS") {
        p.gaps = g.split(',').filter_map(|s| s.trim().parse().ok()).collect();
    }
    if let Ok(r) = std::env::var("MX_INBETWEEN_ROOTS") {
        p.roots = r
            .split(',')
            .filter_map(|s| match s.trim() {
                "given" => Some(RootMode::Given),
                "filled" => Some(RootMode::Filled),
                _ => None,
            })
            .collect();
    }
    let mut methods = inbetween::methods();
    if std::env::var("MX_INBETWEEN_LIBRARY").is_ok_and(|v| v == "1") {
        let loo = LeaveOneOut::new(&dir, mx::library::Settings::default())
            .unwrap_or_else(|e| panic!("{e}"));
        eprintln!(
            "leave-one-out libraries of {} clips less the window's own",
            loo.len()
        );
        methods.extend(inbetween::library_methods(std::sync::Arc::new(loo)));
    }
    // extra SP settings to try: `MX_INBETWEEN_SP="label:smoothness:time_constant:coefficients[:nosupport];…"`
    if let Ok(extra) = std::env::var("MX_INBETWEEN_SP") {
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
    if let Ok(only) = std::env::var("MX_INBETWEEN_METHODS") {
        let keep: Vec<&str> = only.split(',').map(str::trim).collect();
        methods.retain(|m| matches!(m, Method::Hermite) || keep.contains(&m.label()));
    }
    let windows: usize = p
        .gaps
        .iter()
        .map(|&g| cases.iter().map(|c| c.windows(&p, g).len()).sum::<usize>())
        .sum::<usize>()
        * p.roots.len();
    eprintln!(
        "{} clips from {}, {} windows × {} methods",
        cases.len(),
        dir.display(),
        windows,
        methods.len()
    );
    let mut done = 0;
    let results = inbetween::run(&cases, &p, &methods, |r| {
        done += 1;
        if done % 50 == 0 {
            eprintln!(
                "  {done} fills ({} {} gap {} {})",
                r.clip, r.start, r.gap, r.method
            );
        }
    })
    .unwrap_or_else(|e| panic!("{e}"));
    println!("{}", inbetween::table(&inbetween::summarise(&results)));
    // standing on the ground: skate, penetration, residual beside L2P, capture the reference;
    // all clips, then the locomotion clips (walk*, run*, dash*) alone
    println!(
        "\nground, all clips:\n{}",
        inbetween::ground_table(&inbetween::summarise(&results))
    );
    println!(
        "\nground, locomotion (walk*, run*, dash*):\n{}",
        inbetween::ground_table(&inbetween::summarise_locomotion(&results))
    );
    // the worst SP window (largest worst-joint error, root given) as one page:
    // the capture, SP and the Hermite fill overlaid on one clock
    let sp_label = "SP defaults";
    if let Some(w) = results
        .iter()
        .filter(|r| r.method == sp_label && r.root == RootMode::Given)
        .max_by(|a, b| a.worst.total_cmp(&b.worst))
    {
        let case = cases
            .iter()
            .find(|c| c.name == w.clip)
            .expect("the clip of a result");
        let sp = methods
            .iter()
            .find(|m| m.label() == sp_label)
            .expect("SP defaults runs");
        let fill = |m: &Method| {
            inbetween::fill_window(case, &p, w.start, w.gap, w.root, m)
                .map(|f| f.motion)
                .map_err(|e| e.to_string())
        };
        let (sp_m, h_m) = (
            fill(sp).unwrap_or_else(|e| panic!("{e}")),
            fill(&Method::Hermite).unwrap_or_else(|e| panic!("{e}")),
        );
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
    if let Some(path) = std::env::var_os("MX_INBETWEEN_CSV") {
        mx::atomic_file::write(
            std::path::Path::new(&path),
            inbetween::csv(&results).as_bytes(),
        )
        .unwrap_or_else(|e| panic!("{e}"));
    }
}
