//! The in-betweening summary as the tables issues 35 and 36 read: accuracy
//! and ground side by side, one row per method (with SP's time and
//! evaluations), and the leave-one-out library rows against slerp, Hermite
//! and the motion's own example on the same windows.

use super::goals::short;
use super::inbetween::{Method, SP_DEFAULTS, SP_LIBRARY, SP_LIBRARY_SELF, Summary};

fn same<'a>(rows: &'a [Summary], r: &Summary, method: &str) -> Option<&'a Summary> {
    rows.iter()
        .find(|h| h.root == r.root && h.gap == r.gap && h.method == method)
}

/// a ÷ b in 3 digits, "–" without b.
fn over(a: f64, b: Option<f64>) -> String {
    b.filter(|b| *b > 0.0).map_or("–".into(), |b| short(a / b))
}

/// A share (0–1) as a percentage, "–" without one.
fn percent(v: Option<f64>) -> String {
    v.map_or("–".into(), |v| format!("{:.0} %", 100.0 * v))
}

/// One row per (root, gap, method), whatever methods ran: L2P and its ratio
/// to Hermite's, L2Q, NPSS; skate within 2 cm of the floor and its ratio to
/// the capture's, depth below the floor (mean, worst window), ground
/// residual (mean, its excess over the capture's, worst frame); the contact
/// plan against the capture's (stance edges within 0.1 s, frames that
/// agree; "–" for a method that plans none); blow-ups, solves not
/// converged, evaluations and seconds per solve.
pub fn accuracy_and_ground(rows: &[Summary]) -> String {
    let mut s = String::from(
        "| root | gap | method | windows | L2P cm | ×Hermite | L2Q | NPSS | skate cm/s | ×capture | below floor cm (worst) | residual % BW | − capture | worst frame % BW | plan edges ≤ 0.1 s | plan frames | blow-ups | not converged | evals | s/solve |\n\
         |---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        let h = same(rows, r, Method::Hermite.label()).map(|h| h.l2p);
        let cap = same(rows, r, Method::Capture.label());
        s.push_str(&format!(
            "| {} | {} | {} | {} | {:.2} | {} | {:.3} | {:.4} | {:.1} | {} | {:.2} ({:.2}) | {:.1} | {} | {:.1} | {} | {} | {} | {} | {:.0} | {:.3} |\n",
            r.root.label(),
            r.gap,
            r.method,
            r.windows,
            r.l2p,
            over(r.l2p, h),
            r.l2q,
            r.npss,
            r.skate,
            over(r.skate, cap.map(|c| c.skate)),
            r.penetration,
            r.penetration_worst,
            r.residual,
            cap.map_or("–".into(), |c| format!("{:+.1}", r.residual - c.residual)),
            r.residual_worst,
            percent(r.plan.and_then(|p| p.edges())),
            percent(r.plan.and_then(|p| p.agreement())),
            r.blowups,
            r.not_converged,
            r.evaluations,
            r.seconds
        ));
    }
    s
}

/// Per (root, gap) where a leave-one-out row ran: L2P of slerp, Hermite,
/// SP with its own example (`SP defaults`), the library alone and
/// `[lib, "self"]`, and the library rows' ratios to slerp and Hermite.
pub fn library(rows: &[Summary]) -> String {
    let mut s = String::from(
        "| root | gap | windows | slerp | Hermite | \"self\" (SP defaults) | lib | [lib, \"self\"] | lib ÷ slerp | lib ÷ Hermite | [lib, \"self\"] ÷ slerp | [lib, \"self\"] ÷ Hermite |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    let l2p = |m: Option<&Summary>| m.map(|m| m.l2p);
    let cell = |v: Option<f64>| v.map_or("–".into(), |v| format!("{v:.2}"));
    for r in rows.iter().filter(|r| r.method == Method::Hermite.label()) {
        let (lib, both) = (same(rows, r, SP_LIBRARY), same(rows, r, SP_LIBRARY_SELF));
        if lib.is_none() && both.is_none() {
            continue;
        }
        let slerp = l2p(same(rows, r, Method::Slerp.label()));
        let ratio =
            |m: Option<&Summary>, b: Option<f64>| m.map_or("–".into(), |m| over(m.l2p, b));
        s.push_str(&format!(
            "| {} | {} | {} | {} | {:.2} | {} | {} | {} | {} | {} | {} | {} |\n",
            r.root.label(),
            r.gap,
            r.windows,
            cell(slerp),
            r.l2p,
            cell(l2p(same(rows, r, SP_DEFAULTS))),
            cell(l2p(lib)),
            cell(l2p(both)),
            ratio(lib, slerp),
            ratio(lib, Some(r.l2p)),
            ratio(both, slerp),
            ratio(both, Some(r.l2p)),
        ));
    }
    s
}
