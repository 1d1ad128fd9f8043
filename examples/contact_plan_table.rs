//! The contact plan measured by itself (issue 35 item 2): on every
//! locomotion clip (name with walk/run/dash/turn, and CMU's) of
//! `$MX_SHARED/data/inbetween` and `data/mocap`, gaps of 1.0 s and 1.5 s (30
//! and 45 frames at 30 Hz) every 0.5 s, at the clip's speed and time-warped
//! to 0.8× and 1.25×: the plan from the context against the capture's own
//! contacts inside the cut (the same planning stance rule on the capture).
//!
//! Per row: lift-off/touch-down events of the capture inside the gap, those
//! the plan places within 0.25 s (and their mean |timing error|), missed and
//! spurious events; stances missed (no planned stance overlaps) and spurious
//! (overlapping no captured one); the mean horizontal distance between
//! overlapping planned and captured anchors.
//!
//! `cargo run --example contact_plan_table` (MX_SHARED defaults to ../shared).

use mx::ground::{self, FloorPlane};
use mx::mocap::{self, bvh::Units};
use mx::motion::JointSampler;
use mx::spacetime::SpError;
use mx::spacetime::contact::{Context, GapPlan, capture_plan};
use nalgebra::Vector3;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Events further apart than this (s) are not the same event.
const MATCH: f64 = 0.25;

#[derive(Default)]
struct Row {
    windows: usize,
    events: usize,
    matched: usize,
    timing: f64,
    spurious_events: usize,
    stances: usize,
    missed: usize,
    planned: usize,
    spurious: usize,
    anchor: f64,
    anchors: usize,
}

/// (time, is lift-off) of the stance ends strictly inside the gap.
fn events(g: &GapPlan, k: usize) -> Vec<(f64, bool)> {
    let eps = 1e-6;
    let mut out = vec![];
    for s in &g.points[k].stances {
        if s.t0 > g.t0 + eps {
            out.push((s.t0, false));
        }
        if s.t1 < g.t1 - eps {
            out.push((s.t1, true));
        }
    }
    out
}

fn compare(row: &mut Row, plan: &GapPlan, truth: &GapPlan, up: &Vector3<f64>) {
    row.windows += 1;
    for (k, tp) in truth.points.iter().enumerate() {
        let pp = &plan.points[k];
        // events: each captured one matched to the nearest planned one of its kind
        let (te, pe) = (events(truth, k), events(plan, k));
        let mut used = vec![false; pe.len()];
        for &(t, lift) in &te {
            row.events += 1;
            let best = pe
                .iter()
                .enumerate()
                .filter(|(i, e)| e.1 == lift && !used[*i])
                .min_by(|a, b| (a.1.0 - t).abs().total_cmp(&(b.1.0 - t).abs()));
            if let Some((i, e)) = best.filter(|(_, e)| (e.0 - t).abs() <= MATCH) {
                used[i] = true;
                row.matched += 1;
                row.timing += (e.0 - t).abs();
            }
        }
        row.spurious_events += used.iter().filter(|u| !**u).count();
        // stances and anchors
        let overlap = |a: (f64, f64), b: (f64, f64)| a.1.min(b.1) - a.0.max(b.0);
        for s in &tp.stances {
            row.stances += 1;
            let best = pp
                .stances
                .iter()
                .map(|p| (overlap((s.t0, s.t1), (p.t0, p.t1)), p))
                .filter(|(o, _)| *o >= 0.0)
                .max_by(|a, b| a.0.total_cmp(&b.0));
            match best {
                None => row.missed += 1,
                Some((_, p)) => {
                    let d = p.p0 - s.p0;
                    row.anchor += (d - up * up.dot(&d)).norm();
                    row.anchors += 1;
                }
            }
        }
        for p in &pp.stances {
            row.planned += 1;
            if !tp
                .stances
                .iter()
                .any(|s| overlap((s.t0, s.t1), (p.t0, p.t1)) >= 0.0)
            {
                row.spurious += 1;
            }
        }
    }
}

fn clips(shared: &Path) -> Vec<PathBuf> {
    let mut out = vec![];
    for d in ["data/inbetween", "data/mocap"] {
        let dir = shared.join(d);
        let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "bvh"))
            .filter(|p| {
                let n = p.file_stem().unwrap().to_string_lossy();
                ["walk", "run", "dash", "turn", "cmu_"]
                    .iter()
                    .any(|k| n.contains(k))
            })
            .collect();
        v.sort();
        out.extend(v);
    }
    out
}

fn kind(name: &str) -> &'static str {
    if name.contains("cmu_") {
        "cmu 120Hz"
    } else if name.contains("run") || name.contains("dash") {
        "run/dash"
    } else if name.contains("turn") || name.contains("left") || name.contains("right") {
        "walk-turn"
    } else {
        "walk"
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let shared = PathBuf::from(std::env::var("MX_SHARED").unwrap_or("../shared".into()));
    let mut rows: BTreeMap<(String, String, String), Row> = BTreeMap::new();
    for path in clips(&shared) {
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        let clip = mocap::load(&path, Units::Auto)?;
        let (body, _) = mocap::body_of(&clip.skeleton, 70.0, clip.units.metres_per_unit)?;
        let names = body.coordinate_names();
        let sampler = JointSampler::new(&clip.mu, names);
        let (start, stop) = clip.mu.span().ok_or("empty clip")?;
        let up = ground::up_of(&body.default_gravity).ok_or("no gravity")?;
        let points = ground::default_contact_points(&body);
        let links: Vec<usize> = points.iter().map(|p| p.link).collect();
        for warp in [1.0, 0.8, 1.25] {
            // the clip played at `warp`× its speed: t in the warped clip is t·warp in the capture
            let configuration = |t: f64| -> Result<Vec<f64>, SpError> {
                let s = start + (t - start) * warp;
                if s < start || s > stop {
                    return Ok(vec![f64::NAN; names.len()]);
                }
                sampler
                    .positions(s)
                    .map_err(|e| SpError::Invalid(e.to_string()))
            };
            let end = start + (stop - start) / warp;
            // the floor: the contact points' lowest over the clip
            let mut low = f64::INFINITY;
            let mut poses = vec![];
            let mut t = start;
            while t <= end {
                body.forward_kinematics(&configuration(t)?, &mut poses)?;
                for &l in &links {
                    low = low.min(up.dot(&poses[l].p));
                }
                t += 1.0 / 30.0;
            }
            let floor = FloorPlane { up, height: low };
            for gap in [1.0, 1.5] {
                let mut t0 = start + 0.5;
                while t0 + gap <= end - 0.5 {
                    let span = (t0, t0 + gap);
                    let ctx = Context::new(&body, &floor, &links, false, span, &configuration)?;
                    let plan = ctx.plan();
                    let kept: Vec<usize> = plan.points.iter().map(|p| p.link).collect();
                    let truth = capture_plan(&body, &floor, &kept, span, &configuration)?;
                    let key = (
                        kind(&name).to_string(),
                        format!("{:.0} frames", gap * 30.0),
                        format!("{warp}x"),
                    );
                    compare(rows.entry(key).or_default(), &plan, &truth, &up);
                    t0 += 0.5;
                }
            }
        }
        eprintln!("{name}");
    }
    println!(
        "| clips | gap | speed | windows | events | placed ≤{MATCH}s | mean |dt| (s) | spurious events | stances | missed | spurious | anchor err (m) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for ((k, g, w), r) in &rows {
        println!(
            "| {k} | {g} | {w} | {} | {} | {} ({:.0} %) | {:.3} | {} | {} | {} | {} / {} | {:.3} |",
            r.windows,
            r.events,
            r.matched,
            100.0 * r.matched as f64 / r.events.max(1) as f64,
            r.timing / r.matched.max(1) as f64,
            r.spurious_events,
            r.stances,
            r.missed,
            r.spurious,
            r.planned,
            r.anchor / r.anchors.max(1) as f64,
        );
    }
    Ok(())
}
