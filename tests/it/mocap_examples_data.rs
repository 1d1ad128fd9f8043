//! The clips in `examples/data/` are the project's own, made by
//! `cargo run --example make_data`; they must equal what the generator makes
//! now and load like any BVH.

use mx::mocap::{bvh, synth};
use std::path::PathBuf;

#[test]
fn committed_example_clips_match_the_generator() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/data");
    for (name, clip) in [
        ("walk.bvh", synth::walk()),
        ("wave.bvh", synth::wave()),
        ("run.bvh", synth::run()),
        ("kick.bvh", synth::kick()),
        ("arm_raise.bvh", synth::arm_raise()),
    ] {
        let path = dir.join(name);
        let on_disk = std::fs::read_to_string(&path).unwrap_or_else(|e| {
            panic!(
                "{}: {e}; run `cargo run --example make_data`",
                path.display()
            )
        });
        assert_eq!(
            on_disk,
            bvh::to_string(&clip).unwrap(),
            "{name} is stale: run `cargo run --example make_data`"
        );
        let read = bvh::read_file(&path).unwrap();
        assert_eq!(read, clip);
        assert_eq!(bvh::detect_units(&read.skeleton).metres_per_unit, 0.01);
    }
}
