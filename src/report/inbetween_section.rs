//! `mx report`'s in-betweening section: the protocol's table over the shared
//! clips, accuracy beside the ground measures and the contact plan
//! (`inbetween_tables`), the goals of issues 35 and 36 (`goals`), a figure
//! of L2P against gap length, and per root setting and gap a figure of the
//! per-frame ground measures of one typical window (`inbetween_figures`).
//! Above `inbetween`, `goals`, `inbetween_tables` and `inbetween_figures`,
//! which read its rows.

use super::doc::Doc;
use super::inbetween::*;
use std::fmt::Write as _;
use std::path::Path;

/// `mx report`'s in-betweening section: the table of [`summarise`] over the
/// shared clips (every other clip, one window per clip and gap; one clip and
/// two gaps in smoke mode), the ground and plan tables, the goals and the figures.
pub(super) fn section(d: &mut Doc, shared: Option<&Path>, smoke: bool, tick: &(dyn Fn() + Sync)) {
    let Some((cases, p)) = cases_and_protocol(d, shared, smoke) else {
        return;
    };
    let results = match run(&cases, &p, &methods(), |_| tick()) {
        Ok(r) => r,
        Err(e) => return d.pending("in-betweening", &e.to_string()),
    };
    let rows = summarise(&results);
    protocol_table(d, &cases, &p, &rows);
    let loco = summarise_locomotion(&results);
    ground_tables(d, &rows, &loco);
    goal_tables(d, &rows, &loco);
    gap_figures(d, &cases, &p, &results);
}

/// The clips and the protocol the section runs: every other clip of
/// `data/inbetween`, one window per clip and gap (one clip, two gaps in
/// smoke mode); `None`, with the section marked pending, without them.
fn cases_and_protocol(
    d: &mut Doc,
    shared: Option<&Path>,
    smoke: bool,
) -> Option<(Vec<Case>, Protocol)> {
    let Some(dir) = shared.map(|s| s.join("data").join("inbetween")) else {
        d.pending("in-betweening", "needs `$MX_SHARED/data/inbetween`");
        return None;
    };
    let mut cases = match Case::load_dir(&dir) {
        Ok(c) if !c.is_empty() => c,
        Ok(_) => {
            d.pending("in-betweening", "no clips in data/inbetween");
            return None;
        }
        Err(e) => {
            d.pending("in-betweening", &e.to_string());
            return None;
        }
    };
    let p = if smoke {
        cases.truncate(1);
        Protocol {
            gaps: vec![15, 30],
            windows_per_clip: Some(1),
            ..Protocol::default()
        }
    } else {
        // every other clip, one window per clip and gap: minutes, not the bench's hour
        cases = cases.into_iter().step_by(2).collect();
        Protocol {
            gaps: vec![15, 30, 45],
            windows_per_clip: Some(1),
            ..Protocol::default()
        }
    };
    Some((cases, p))
}

/// What the section measured and how, the figure of L2P against gap length
/// with the root given, and the protocol's table.
fn protocol_table(d: &mut Doc, cases: &[Case], p: &Protocol, rows: &[Summary]) {
    let _ = writeln!(
        d.md,
        "Cut a gap out of a real clip, fill it, compare with what the person did (the protocol of \
         `data/inbetween/README.md`, after Harvey et al. 2020): {} clips (every other one of the folder), at most {} window per clip and gap \
         (`cargo bench --bench inbetween` runs every window), {} context frames, root given (its channels kept) \
         and the natural cut (every DOF cut, the frames after the gap where they were captured; SP at its own \
         `root:` default, today's SP with `root: \"pinned\"`). \
         L2P: mean joint-position error over the gap (cm); ×Hermite: its ratio to `fill(m, \"hermite\")` on the \
         same windows; worst: the largest joint error and where; L2Q: Harvey et al.'s mean over frames of \
         the L2 distance of the stacked world orientations (unit quaternions, sign-aligned); NPSS: normalised power \
         spectrum similarity of those orientations over the gap (Gopalakrishnan et al. 2019; 0: the same \
         frequencies); skate: horizontal speed of a contact point within 2 cm of the floor (cm/s, `foot_skate`'s); \
         bone Δ: largest bone-length change (m); \
         blow-ups: windows whose worst error exceeds 1.5 × Hermite's + 5 cm. SP's default objective is \
         ∫Στ² plus an inertia-weighted tension prior, lowered until the transition costs less torque than \
         Hermite (see `spacetime::sp::prior_weights`); `objective: \"torque\"` is Rose's objective alone. \
         Every score is `compare(m, capture, body)`'s, from the same code (`crate::score`).\n",
        cases.len(),
        p.windows_per_clip.unwrap_or(0),
        p.context
    );
    let labels: Vec<String> = methods().iter().map(|m| m.label().to_string()).collect();
    let series = labels
        .iter()
        .map(|m| super::plot::Series {
            label: m.clone(),
            points: rows
                .iter()
                .filter(|r| r.root == RootMode::Given && &r.method == m)
                .map(|r| (r.gap as f64, r.l2p))
                .collect(),
            default_at: None,
        })
        .collect();
    d.figure(&super::plot::Figure {
        file: "inbetween_l2p.svg".into(),
        title: "In-betweening against capture (root given): L2P against gap length".into(),
        x_label: "gap (frames at 30 fps)".into(),
        y_label: "mean joint-position error L2P (cm)".into(),
        series,
    });
    d.header(&[
        "root",
        "gap",
        "method",
        "windows",
        "L2P cm",
        "×Hermite",
        "worst cm",
        "L2Q",
        "NPSS",
        "skate cm/s",
        "bone Δ m",
        "∫Στ²",
        "< Hermite ∫Στ²",
        "blow-ups",
        "not converged",
        "evaluations",
        "s/solve",
    ]);
    for r in rows {
        protocol_row(d, rows, r);
    }
}

fn protocol_row(d: &mut Doc, rows: &[Summary], r: &Summary) {
    let h = rows
        .iter()
        .find(|h| h.root == r.root && h.gap == r.gap && h.method == Method::Hermite.label())
        .map_or(f64::NAN, |h| h.l2p);
    let cells = [
        r.root.label().to_string(),
        r.gap.to_string(),
        r.method.clone(),
        r.windows.to_string(),
        d.n(r.l2p),
        d.n(r.l2p / h),
        format!("{} ({})", d.n(r.worst), r.worst_at),
        d.n(r.l2q),
        d.n(r.npss),
        d.n(r.skate),
        d.n(r.bone),
        d.n(r.energy),
        format!("{}/{}", r.cheaper_than_hermite, r.windows),
        r.blowups.to_string(),
        r.not_converged.to_string(),
        d.n(r.evaluations),
        d.n(r.seconds),
    ];
    d.row(&cells);
}

/// Accuracy beside the ground measures and the contact plan, all clips and locomotion.
fn ground_tables(d: &mut Doc, rows: &[Summary], loco: &[Summary]) {
    let _ = writeln!(
        d.md,
        "\nAccuracy and standing on the ground, one row per method (`data/inbetween/README.md`'s ground \
         measures by `ground`'s rules, over each gap and the step on either side, against the floor of the whole \
         captured clip): skate: horizontal speed of a contact point (an ankle or toe joint, found by name: Foot, Toe, \
         Ankle, Heel) within 2 cm of the floor (cm/s), and its ratio to the capture's on the same windows; below floor: \
         the deepest contact point under it (cm; mean, and worst window); ground residual: the force the floating base \
         needs that no friction-cone (μ {FRICTION}) forces at the contact points within 2 cm can supply (% of body \
         weight; mean, its excess over the capture's, and worst frame); plan: where SP planned contacts, its plan \
         against the capture's contacts read by the same planning rule — edges: the share of stance starts and ends \
         within 0.1 s of the capture's (matched one to one, 2·matched ÷ (planned + captured)), frames: the share of \
         (contact point, frame) pairs standing in both or in neither — pooled over the windows; SP's evaluations and \
         seconds per solve. The capture row is the reference; SP with the capture's contacts (`contact: contacts(c, b)`, \
         each stance's `at:` where the capture stood) is the upper bound of any plan. `today's SP` is SP with the \
         options that reproduce it before grounded SP (`contact: \"none\"`, `root: \"pinned\"`, the old prior); where \
         its options equal the defaults it is the same solve. All clips, then the locomotion clips (walk, run, dash, \
         turn) alone.\n"
    );
    for (title, rows) in [("all clips", rows), ("locomotion", loco)] {
        let _ = writeln!(
            d.md,
            "\n{title}:\n\n{}",
            super::inbetween_tables::accuracy_and_ground(rows)
        );
    }
}

/// The goals of issues 35 and 36 on these windows.
fn goal_tables(d: &mut Doc, rows: &[Summary], loco: &[Summary]) {
    let _ = writeln!(
        d.md,
        "\nThe goals of issue 35 (SP at its defaults: skate ≤ {} × the capture's, no foot point more than \
         {} cm below the floor, residual ≤ the capture's + {} % BW, natural-cut L2P ≤ {} × Hermite's, root-given \
         L2P ÷ Hermite's no worse than today's SP's, no blow-up, every solve converged, bones kept, ≤ {} × \
         today's SP's time) and of issue 36 (leave-one-out library rows, where they ran: `cargo bench --bench \
         inbetween` with `MX_INBETWEEN_LIBRARY=1`), measured on these windows: PASS, or MISS by how much \
         above the bound.\n",
        super::goals::SKATE_RATIO,
        super::goals::DEPTH_CM,
        super::goals::RESIDUAL_EXCESS,
        super::goals::NATURAL_CUT_VS_HERMITE,
        super::goals::TIME_RATIO,
    );
    for (title, rows) in [("all clips", rows), ("locomotion", loco)] {
        let _ = writeln!(
            d.md,
            "\ngoals, {title}:\n\n{}",
            super::goals::table(&super::goals::goals(rows))
        );
    }
}

/// Per root setting and gap length, the per-frame ground measures of one
/// typical window ([`super::inbetween_figures`]).
fn gap_figures(d: &mut Doc, cases: &[Case], p: &Protocol, results: &[WindowResult]) {
    let _ = writeln!(
        d.md,
        "\nPer gap, frame by frame: for each root setting and gap length, the locomotion window whose SP L2P is the \
         median of its kind, filled again by SP at its defaults and by Hermite, beside the capture: skate (the \
         fastest contact point within 2 cm of the floor over the step into each frame, cm/s), depth (the lowest \
         contact point below the floor, cm) and the ground residual (% of body weight), over the window's context \
         and gap, the gap shaded. The numbers are the ones the tables average.\n"
    );
    for &root in &p.roots {
        for &gap in &p.gaps {
            let Some(w) = super::inbetween_figures::typical_window(results, root, gap) else {
                continue;
            };
            let Some(case) = cases.iter().find(|c| c.name == w.clip) else {
                continue;
            };
            match super::inbetween_figures::figure(case, p, w) {
                Ok(f) => d.ground_figure(&f),
                Err(e) => d.pending(
                    &format!("in-betweening figure {} {gap}", root.label()),
                    &e.to_string(),
                ),
            }
        }
    }
}
