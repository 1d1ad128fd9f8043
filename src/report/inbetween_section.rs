//! `mx report`'s in-betweening section: the protocol's table over the shared
//! clips, accuracy beside the ground measures (`inbetween_tables`), the goals
//! of issues 35 and 36 (`goals`) and a figure of L2P against gap length. Above
//! `inbetween`, `goals` and `inbetween_tables`, which read its rows.

use super::inbetween::*;
use std::path::Path;

/// `mx report`'s in-betweening section: the table of [`summarise`] over the
/// shared clips (every other clip, one window per clip and gap; one clip and
/// two gaps in smoke mode) and a figure of L2P against gap length with the root given.
pub(super) fn section(
    d: &mut super::doc::Doc,
    shared: Option<&Path>,
    smoke: bool,
    tick: &(dyn Fn() + Sync),
) {
    use std::fmt::Write as _;
    let Some(dir) = shared.map(|s| s.join("data").join("inbetween")) else {
        d.pending("in-betweening", "needs `$MX_SHARED/data/inbetween`");
        return;
    };
    let mut cases = match Case::load_dir(&dir) {
        Ok(c) if !c.is_empty() => c,
        Ok(_) => return d.pending("in-betweening", "no clips in data/inbetween"),
        Err(e) => return d.pending("in-betweening", &e.to_string()),
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
    let results = match run(&cases, &p, &methods(), |_| tick()) {
        Ok(r) => r,
        Err(e) => return d.pending("in-betweening", &e.to_string()),
    };
    let rows = summarise(&results);
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
         frequencies); skate: foot speed near the ground (cm/s); bone Δ: largest bone-length change (m); \
         blow-ups: windows whose worst error exceeds 1.5 × Hermite's + 5 cm. SP's default objective is \
         ∫Στ² plus an inertia-weighted tension prior, lowered until the transition costs less torque than \
         Hermite (see `spacetime::sp::prior_weights`); `objective: \"torque\"` is Rose's objective alone.\n",
        cases.len(),
        p.windows_per_clip.unwrap_or(0),
        p.context
    );
    let methods: Vec<String> = methods().iter().map(|m| m.label().to_string()).collect();
    let series = methods
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
    for r in &rows {
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
    let loco = summarise_locomotion(&results);
    let _ = writeln!(
        d.md,
        "\nAccuracy and standing on the ground, one row per method (`data/inbetween/README.md`'s ground \
         measures, `crate::ground`, over each gap and the step on either side, against the floor of the whole \
         captured clip): skate: horizontal speed of a foot joint (found by name: Foot, Toe, Ankle, Heel) within \
         2 cm of the floor (cm/s), and its ratio to the capture's on the same windows; below floor: the deepest \
         foot joint under it (cm; mean, and worst window); ground residual: the force the floating base needs \
         that no friction-cone (μ {FRICTION}) forces at the foot joints within 2 cm can supply (% of body \
         weight; mean, its excess over the capture's, and worst frame); SP's evaluations and seconds per solve. \
         The capture row is the reference. `today's SP` is SP with the options that reproduce it before grounded \
         SP (`contact: \"none\"`, `root: \"pinned\"`, the old prior); where its options equal the defaults it \
         is the same solve. All clips, then the locomotion clips (walk, run, dash, turn) alone.\n"
    );
    for (title, rows) in [("all clips", &rows), ("locomotion", &loco)] {
        let _ = writeln!(
            d.md,
            "\n{title}:\n\n{}",
            super::inbetween_tables::accuracy_and_ground(rows)
        );
    }
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
    for (title, rows) in [("all clips", &rows), ("locomotion", &loco)] {
        let _ = writeln!(
            d.md,
            "\ngoals, {title}:\n\n{}",
            super::goals::table(&super::goals::goals(rows))
        );
    }
}
