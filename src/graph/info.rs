//! `mx graph info`: counts, the largest strongly connected part (the part a
//! walk can stay in forever, Kovar et al. §4.1) and histograms of the edge costs.

use super::model::{Edge, Graph};
use std::fmt::Write as _;

/// A text histogram of `values` in `bins` equal bins from min to max.
pub fn histogram(values: &[f64], bins: usize, unit: &str) -> String {
    let mut out = String::new();
    if values.is_empty() {
        out.push_str("  (none)\n");
        return out;
    }
    let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let width = if hi > lo {
        (hi - lo) / bins as f64
    } else {
        1.0
    };
    let mut counts = vec![0usize; bins];
    for &v in values {
        let b = (((v - lo) / width) as usize).min(bins - 1);
        counts[b] += 1;
    }
    let most = counts.iter().copied().max().unwrap_or(1).max(1);
    for (b, &c) in counts.iter().enumerate() {
        let from = lo + b as f64 * width;
        let bar = "#".repeat((c * 40).div_ceil(most));
        let _ = writeln!(
            out,
            "  {:>10.4} – {:<10.4}{unit:<4} {c:>6} {bar}",
            from,
            from + width
        );
    }
    out
}

/// The summary `mx graph info` prints.
pub fn summary(g: &Graph) -> String {
    let mut out = String::new();
    let loaded = g
        .library
        .clips
        .iter()
        .filter(|c| c.frames.is_some())
        .count();
    let trans: Vec<&Edge> = g
        .edges
        .iter()
        .filter(|e| matches!(e, Edge::Transition { .. }))
        .collect();
    let pairs_with: std::collections::BTreeSet<(String, String)> = trans
        .iter()
        .map(|e| {
            let (f, t) = e.ends();
            (g.nodes[f].clip.clone(), g.nodes[t].clip.clone())
        })
        .collect();
    let n = g.library.clips.len();
    let _ = writeln!(
        out,
        "clips: {n} ({loaded} loaded, {} failed) from {}",
        g.library.clip_failures.len(),
        g.library.clips_dir
    );
    let _ = writeln!(
        out,
        "pairs: {} ordered, {} with a transition, {} failed",
        n * n.saturating_sub(1),
        pairs_with.len(),
        g.pair_failures.len()
    );
    let _ = writeln!(
        out,
        "nodes (clip segments): {}; edges: {} ({} transitions, {} clip continuations)",
        g.nodes.len(),
        g.edges.len(),
        trans.len(),
        g.edges.len() - trans.len()
    );
    let comps = g.components();
    let largest = comps.first().map(|c| c.len()).unwrap_or(0);
    let clips_in: std::collections::BTreeSet<&str> = comps
        .first()
        .map(|c| c.iter().map(|&k| g.nodes[k].clip.as_str()).collect())
        .unwrap_or_default();
    let frames_in: usize = comps
        .first()
        .map(|c| c.iter().map(|&k| g.nodes[k].end - g.nodes[k].start).sum())
        .unwrap_or(0);
    let _ = writeln!(
        out,
        "largest strongly connected part: {largest} of {} nodes, {} clips, {:.1} s of clip motion ({} parts in all)",
        g.nodes.len(),
        clips_in.len(),
        frames_in as f64 * g.library.frame_time,
        comps.len()
    );
    let pick = |f: &dyn Fn(&Edge) -> Option<f64>| -> Vec<f64> {
        trans.iter().filter_map(|e| f(e)).collect()
    };
    let dist = pick(&|e| match e {
        Edge::Transition { distance, .. } => Some(*distance),
        _ => None,
    });
    let energy = pick(&|e| match e {
        Edge::Transition { energy, .. } => Some(*energy),
        _ => None,
    });
    let dur = pick(&|e| match e {
        Edge::Transition { duration, .. } => Some(*duration),
        _ => None,
    });
    let _ = writeln!(out, "transition cost: point-cloud distance (RMS, m)");
    out.push_str(&histogram(&dist, 8, "m"));
    let _ = writeln!(out, "transition torque energy ∫Στ²");
    out.push_str(&histogram(&energy, 8, ""));
    let _ = writeln!(out, "transition duration");
    out.push_str(&histogram(&dur, 4, "s"));
    for f in g.library.clip_failures.iter().take(5) {
        let _ = writeln!(out, "failed clip {}: {}", f.clip, f.error);
    }
    for f in g.pair_failures.iter().take(5) {
        let _ = writeln!(out, "failed pair {} → {}: {}", f.a, f.b, f.error);
    }
    out
}
