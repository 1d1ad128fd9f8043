//! Every numerically delicate case of `mx::report::hard_cases::all()` must
//! pass: the same registry prints the hard-case table of `docs/accuracy.md`.

#[test]
fn every_hard_case_passes_with_a_finite_measured_error() {
    let cases = mx::report::hard_cases::all();
    assert!(
        cases.len() >= 15,
        "the registry lost cases: {}",
        cases.len()
    );
    let mut failed = Vec::new();
    for c in &cases {
        eprintln!(
            "{:<55} worst {:>10.2e} ≤ {:>8.1e}  {}",
            c.name, c.worst_error, c.bound, c.returned
        );
        assert!(c.worst_error.is_finite(), "{}: non-finite error", c.name);
        if !c.passed {
            failed.push(format!(
                "{}: {} (worst {:e} > {:e})",
                c.name, c.returned, c.worst_error, c.bound
            ));
        }
    }
    assert!(
        failed.is_empty(),
        "failing hard cases:\n{}",
        failed.join("\n")
    );
}

#[test]
fn a_broken_case_would_fail() {
    // The verdict depends on the measurement: a bound below the measured error fails.
    let c = mx::report::hard_cases::long_chain();
    assert!(
        c.worst_error > 0.0,
        "a residual of exactly 0 would make the bound untestable"
    );
    assert!(c.worst_error < c.bound);
}
