//! The windows' results summarised per (root setting, gap, method), each
//! method compared window by window with Hermite; the protocol's table and
//! every window as CSV.

use super::methods::Method;
use super::protocol::{RootMode, is_locomotion};
use super::window::WindowResult;
use crate::score::PlanAccuracy;
use crate::score::metrics::NpssSum;

/// One row of the summary: a method at one gap length and root setting.
#[derive(Clone, Debug)]
pub struct Summary {
    pub root: RootMode,
    pub gap: usize,
    pub method: String,
    pub windows: usize,
    pub l2p: f64,
    pub worst: f64,
    pub worst_at: String,
    pub l2q: f64,
    /// NPSS pooled over the windows as LaFAN1's batch is (each window's
    /// dimensions weighted by the capture's power).
    pub npss: f64,
    pub bone: f64,
    pub energy: f64,
    /// Ground measures: mean skate (cm/s), mean and worst penetration (cm),
    /// mean residual and its worst frame over the windows (% of body weight).
    pub skate: f64,
    pub penetration: f64,
    pub penetration_worst: f64,
    pub residual: f64,
    pub residual_worst: f64,
    /// The contact plan against the capture's contacts, pooled over the
    /// windows where the method planned (`None`: it never did).
    pub plan: Option<PlanAccuracy>,
    /// Windows where this method is closer to the capture than Hermite (L2P).
    pub beats_hermite: usize,
    /// Windows whose ∫Στ² is below Hermite's.
    pub cheaper_than_hermite: usize,
    /// Windows whose worst joint error exceeds 1.5 × Hermite's worst + 5 cm.
    pub blowups: usize,
    pub not_converged: usize,
    pub iterations: f64,
    pub evaluations: f64,
    pub seconds: f64,
}

/// Windows against Hermite's on the same window: (closer, cheaper, blow-ups).
fn against_hermite(results: &[WindowResult], rows: &[&WindowResult]) -> (usize, usize, usize) {
    let hermite_of = |r: &WindowResult| {
        results.iter().find(|h| {
            h.method == Method::Hermite.label()
                && h.clip == r.clip
                && h.start == r.start
                && h.gap == r.gap
                && h.root == r.root
        })
    };
    let (mut beats, mut cheaper, mut blowups) = (0, 0, 0);
    for r in rows {
        if let Some(h) = hermite_of(r) {
            beats += usize::from(r.l2p < h.l2p);
            cheaper += usize::from(r.energy < h.energy);
            blowups += usize::from(r.worst > 1.5 * h.worst + 5.0);
        }
    }
    (beats, cheaper, blowups)
}

/// One row of [`summarise`] over `rows`, the windows of one (root, gap, method).
fn summary_of(
    key: (RootMode, usize, String),
    rows: &[&WindowResult],
    results: &[WindowResult],
) -> Summary {
    let (root, gap, method) = key;
    let n = rows.len().max(1) as f64;
    let mean = |f: &dyn Fn(&WindowResult) -> f64| rows.iter().map(|r| f(r)).sum::<f64>() / n;
    let most = |f: &dyn Fn(&WindowResult) -> f64| rows.iter().map(|r| f(r)).fold(0.0, f64::max);
    let w = rows.iter().max_by(|a, b| a.worst.total_cmp(&b.worst));
    let (beats, cheaper, blowups) = against_hermite(results, rows);
    let mut pooled = NpssSum::default();
    for r in rows {
        pooled.add(NpssSum {
            weighted: r.npss * r.npss_weight,
            weight: r.npss_weight,
        });
    }
    Summary {
        root,
        gap,
        method,
        windows: rows.len(),
        l2p: mean(&|r| r.l2p),
        worst: w.map_or(0.0, |r| r.worst),
        worst_at: w.map_or(String::new(), |r| {
            format!("{} {} @{}", r.clip, r.worst_joint, r.worst_frame)
        }),
        l2q: mean(&|r| r.l2q),
        npss: pooled.value(),
        bone: most(&|r| r.bone),
        energy: mean(&|r| r.energy),
        skate: mean(&|r| r.skate),
        penetration: mean(&|r| r.penetration),
        penetration_worst: most(&|r| r.penetration),
        residual: mean(&|r| r.residual),
        residual_worst: most(&|r| r.residual_worst),
        plan: rows.iter().filter_map(|r| r.plan).reduce(|mut a, b| {
            a.add(&b);
            a
        }),
        beats_hermite: beats,
        cheaper_than_hermite: cheaper,
        blowups,
        not_converged: rows.iter().filter(|r| r.converged == Some(false)).count(),
        iterations: mean(&|r| r.iterations as f64),
        evaluations: mean(&|r| r.evaluations as f64),
        seconds: mean(&|r| r.seconds),
    }
}

/// Means per (root, gap, method), each method compared window by window with Hermite.
pub fn summarise(results: &[WindowResult]) -> Vec<Summary> {
    let mut keys: Vec<(RootMode, usize, String)> = vec![];
    for r in results {
        let k = (r.root, r.gap, r.method.clone());
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    keys.into_iter()
        .map(|(root, gap, method)| {
            let rows: Vec<&WindowResult> = results
                .iter()
                .filter(|r| r.root == root && r.gap == gap && r.method == method)
                .collect();
            summary_of((root, gap, method), &rows, results)
        })
        .collect()
}

/// [`summarise`] over the locomotion clips only ([`is_locomotion`]).
pub fn summarise_locomotion(results: &[WindowResult]) -> Vec<Summary> {
    let loco: Vec<WindowResult> = results
        .iter()
        .filter(|r| is_locomotion(&r.clip))
        .cloned()
        .collect();
    summarise(&loco)
}

/// The summary as a Markdown table.
pub fn table(rows: &[Summary]) -> String {
    let mut s = String::from(
        "| root | gap | method | windows | L2P cm | ×Hermite | worst cm (where) | L2Q | NPSS | skate cm/s | bone Δ m | ∫Στ² | < Hermite L2P | < Hermite ∫Στ² | blow-ups | not converged | iters | evals | s/solve |\n\
         |---|---:|---|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        let h = rows
            .iter()
            .find(|h| h.root == r.root && h.gap == r.gap && h.method == Method::Hermite.label())
            .map_or(f64::NAN, |h| h.l2p);
        s.push_str(&format!(
            "| {} | {} | {} | {} | {:.2} | {:.2} | {:.1} ({}) | {:.3} | {:.4} | {:.1} | {:.1e} | {:.4e} | {}/{} | {}/{} | {} | {} | {:.0} | {:.0} | {:.3} |\n",
            r.root.label(),
            r.gap,
            r.method,
            r.windows,
            r.l2p,
            r.l2p / h,
            r.worst,
            r.worst_at,
            r.l2q,
            r.npss,
            r.skate,
            r.bone,
            r.energy,
            r.beats_hermite,
            r.windows,
            r.cheaper_than_hermite,
            r.windows,
            r.blowups,
            r.not_converged,
            r.iterations,
            r.evaluations,
            r.seconds
        ));
    }
    s
}

/// Every window's result as CSV rows (with a header), for plots and digging;
/// the plan's shares are empty where the method planned none.
pub fn csv(results: &[WindowResult]) -> String {
    let mut s = String::from(
        "clip,start,gap,root,method,l2p_cm,worst_cm,worst_joint,worst_frame,l2q,npss,npss_weight,skate_cm_s,bone_m,energy,penetration_cm,residual_pct_bw,residual_worst_pct_bw,plan_edges,plan_frames,iterations,evaluations,converged,seconds\n",
    );
    let share = |v: Option<f64>| v.map_or(String::new(), |v| v.to_string());
    for r in results {
        s.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
            r.clip,
            r.start,
            r.gap,
            r.root.label(),
            r.method,
            r.l2p,
            r.worst,
            r.worst_joint,
            r.worst_frame,
            r.l2q,
            r.npss,
            r.npss_weight,
            r.skate,
            r.bone,
            r.energy,
            r.penetration,
            r.residual,
            r.residual_worst,
            share(r.plan.and_then(|p| p.edges())),
            share(r.plan.and_then(|p| p.agreement())),
            r.iterations,
            r.evaluations,
            r.converged.map_or("", |c| if c { "yes" } else { "no" }),
            r.seconds
        ));
    }
    s
}
