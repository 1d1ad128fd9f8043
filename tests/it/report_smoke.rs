//! `mx report --smoke` into a temporary folder: every figure and table is
//! produced, every number in it is finite, and no section is pending.

use crate::common;

use mx::report::{Options, generate};

#[test]
fn smoke_report_produces_every_figure_with_finite_numbers() {
    let Some(shared) = common::shared_dir() else {
        return;
    };
    let dir = tempfile::tempdir().expect("tempdir");
    let mut opts = Options::new(dir.path().to_path_buf(), true);
    opts.shared = Some(shared);
    opts.progress = false;
    let s = generate(&opts).expect("report runs");
    assert!(s.pending.is_empty(), "pending sections: {:?}", s.pending);
    let want = [
        "spacetime_energy.svg",
        "spacetime_continuity.svg",
        "integrators_error.svg",
        "integrators_energy.svg",
        "fit_frames.svg",
        "fit_smoothing.svg",
        "mocap_bspline.svg",
        "mocap_sampling.svg",
        "cyclify.svg",
        "inbetween_l2p.svg",
    ];
    for f in want {
        let p = dir.path().join(f);
        let svg = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{f}: {e}"));
        assert!(
            svg.contains("<svg") && svg.contains("<circle"),
            "{f} has no points"
        );
    }
    // the named figures and the per-gap in-betweening ones beside them
    assert!(s.figures.len() >= want.len(), "{:?}", s.figures);
    let md = std::fs::read_to_string(&s.markdown).expect("accuracy.md");
    for section in [
        "## Spacetime",
        "## In-betweening",
        "## Integrators",
        "## Spline-joint",
        "## Mocap",
        "## Cyclification",
        "## Inverse kinematics",
        "## Hard cases",
        "## Performance",
    ] {
        assert!(md.contains(section), "missing {section}");
    }
    for f in want {
        assert!(md.contains(&format!("]({f})")), "{f} not linked");
    }
    assert!(!s.numbers.is_empty());
    assert!(
        s.numbers.iter().all(|x| x.is_finite()),
        "non-finite number in the report"
    );
    for bad in ["NaN", "inf"] {
        assert!(
            !md.split(|c: char| !c.is_alphanumeric()).any(|w| w == bad),
            "`{bad}` in the report"
        );
    }
    assert_eq!(s.hard_cases.len(), mx::report::hard_cases::all().len());
    assert!(md.contains("| yes |"));
}
