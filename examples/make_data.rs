//! Writes the project's own small clips to `examples/data/` (run with
//! `cargo run --example make_data`). The test `mocap_examples_data` checks
//! the committed files are exactly what this writes.

use mx::mocap::{bvh, synth};
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/data");
    std::fs::create_dir_all(&dir)?;
    for (name, clip) in [
        ("walk.bvh", synth::walk()),
        ("wave.bvh", synth::wave()),
        ("run.bvh", synth::run()),
        ("kick.bvh", synth::kick()),
        ("arm_raise.bvh", synth::arm_raise()),
    ] {
        let path = dir.join(name);
        bvh::write_file(&clip, &path)?;
        println!("wrote {} ({} frames)", path.display(), clip.frame_count());
    }
    Ok(())
}
