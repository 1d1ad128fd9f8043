//! `examples/osim_sp.mx`: SP on the gait2392 body between two poses of a
//! synthesised `.mot` gait, scored as the in-betweening protocol scores
//! transitions (effort ∫Στ² dt, L2P over the gap) beside the Hermite fill.

use crate::common;

use mx::Interpreter;

fn num(mx: &mut Interpreter, name: &str) -> f64 {
    mx.eval_str(name)
        .unwrap()
        .as_number()
        .unwrap_or_else(|| panic!("{name} is not a number"))
}

#[test]
fn sp_on_a_mot_gait_of_gait2392_matches_hermite_on_effort() {
    let Some(model) = common::shared_files("opensim", ".osim")
        .into_iter()
        .find(|p| p.ends_with("gait2392_thelen2003muscle.osim"))
    else {
        return; // shared_files already failed under CI when the folder is missing
    };
    let dir = tempfile::tempdir().unwrap();
    let example = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/osim_sp.mx");
    let src = std::fs::read_to_string(&example).unwrap();
    // the shared folder the test found (the example reads $MX_SHARED)
    let shared = model.parent().unwrap().parent().unwrap().parent().unwrap();
    let line = "let shared = if env(\"MX_SHARED\") == nil { \"../../shared\" } else { env(\"MX_SHARED\") }";
    assert!(
        src.contains(line),
        "the example's shared-folder line changed"
    );
    let src = src
        .replace(
            line,
            &format!("let shared = {:?}", shared.display().to_string()),
        )
        .replace("\"out/", &format!("\"{}/", dir.path().display()));
    let mut mx = Interpreter::new();
    mx.eval_str(&src).unwrap();
    assert!(dir.path().join("osim_gait.mot").is_file());
    assert!(dir.path().join("osim_sp.mot").is_file());
    let (e_sp, e_h) = (num(&mut mx, "effort_sp"), num(&mut mx, "effort_hermite"));
    let (l_sp, l_h) = (num(&mut mx, "l2p_sp"), num(&mut mx, "l2p_hermite"));
    eprintln!("effort SP {e_sp:.4} Hermite {e_h:.4}; L2P SP {l_sp:.5} m Hermite {l_h:.5} m");
    for v in [e_sp, e_h, l_sp, l_h] {
        assert!(v.is_finite() && v >= 0.0, "{v}");
    }
    // SP's continuation stops at the smallest prior; "matches" is within 0.5 %
    assert!(e_sp <= 1.005 * e_h, "SP {e_sp} vs Hermite {e_h}");
    // the fill stays near the gait it replaces (a few mm, not a different motion)
    assert!(l_sp < 0.02 && l_h < 0.02, "L2P {l_sp} / {l_h}");
}
