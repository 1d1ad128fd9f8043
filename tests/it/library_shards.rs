//! `mx library build/merge`: a folder indexed in shards and merged is the
//! same `.mxlib`, byte for byte, as one built whole in one process and as
//! the library built in memory (`--shard i/n`, Slurm's array variables, GNU
//! parallel); a merge refuses missing shards; bad input is a clear error.

use crate::common;
use crate::support::graph::{have, in_ci, mx_bin};
use mx::library::{self, Library, Settings, file};
use std::path::Path;
use std::process::Command;

fn build(clips: &Path, out: &Path, extra: &[&str]) -> Command {
    let mut c = Command::new(mx_bin());
    c.args(["library", "build"])
        .arg(clips)
        .arg("--out")
        .arg(out)
        .arg("--quiet")
        .args(extra)
        .env_remove("SLURM_ARRAY_TASK_ID")
        .env_remove("SLURM_ARRAY_TASK_COUNT")
        .env_remove("SLURM_ARRAY_TASK_MIN");
    c
}

fn ok(mut c: Command) -> String {
    let o = c.output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "{err}");
    err
}

fn merge(out: &Path) -> std::process::Output {
    Command::new(mx_bin())
        .args(["library", "merge"])
        .arg(out)
        .output()
        .unwrap()
}

/// The shared clips of data/mocap (never copied).
fn clips() -> Option<std::path::PathBuf> {
    common::shared_dir().map(|d| d.join("data").join("mocap"))
}

#[test]
fn shards_merged_are_the_library_built_whole() {
    let Some(clips) = clips() else { return };
    let out = tempfile::tempdir().unwrap();
    let whole = out.path().join("whole.mxlib");
    ok(build(&clips, &whole, &[]));
    // the same bytes as the library built in memory and saved
    let paths = library::bvh_files(&clips).unwrap();
    let lib = Library::build_files(&paths, Settings::default()).unwrap();
    assert_eq!(
        file::to_bytes(&lib).unwrap(),
        std::fs::read(&whole).unwrap()
    );
    // three shards, two at once and one from Slurm's array variables
    let x = out.path().join("x.mxlib");
    let mut kids: Vec<_> = ["0/3", "2/3"]
        .iter()
        .map(|s| {
            build(&clips, &x, &["--shard", s, "--threads", "1"])
                .spawn()
                .unwrap()
        })
        .collect();
    for k in &mut kids {
        assert!(k.wait().unwrap().success());
    }
    let o = merge(&x);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("shard 1/3"), "{err}");
    let mut slurm = build(&clips, &x, &[]);
    slurm
        .env("SLURM_ARRAY_TASK_ID", "1")
        .env("SLURM_ARRAY_TASK_COUNT", "3");
    let said = ok(slurm);
    assert!(said.contains("shard 1/3"), "{said}");
    assert!(merge(&x).status.success());
    assert_eq!(std::fs::read(&x).unwrap(), std::fs::read(&whole).unwrap());
    // what it holds answers as the library in memory does
    let back = file::load(&x, Some(&Settings::default())).unwrap();
    assert_eq!(back.clips.len(), lib.clips.len());
    let c = &lib.clips[lib.clips.len() / 2];
    let clip = c.motion().unwrap();
    let t0 = c.start + (c.frames / 2) as f64 / 30.0;
    let q = |l: &Library| {
        l.query(
            &clip.mu,
            &clip.skeleton,
            clip.units.metres_per_unit,
            t0,
            t0 + 0.5,
        )
        .unwrap()
    };
    assert_eq!(back.match_gap(&q(&back), 5), lib.match_gap(&q(&lib), 5));
    assert_eq!(
        back.clips[lib.clips.len() / 2].motion().unwrap().mu,
        clip.mu,
        "the clip read back from the file"
    );
}

#[test]
fn gnu_parallel_runs_the_library_shards() {
    let Some(clips) = clips() else { return };
    if !have("parallel") {
        assert!(
            !in_ci(),
            "GNU parallel is missing in CI: scripts/test installs it (apt-get install parallel)"
        );
        eprintln!("SKIPPED: GNU parallel is not installed (apt-get install parallel)");
        return;
    }
    let out = tempfile::tempdir().unwrap();
    let whole = out.path().join("whole.mxlib");
    ok(build(&clips, &whole, &[]));
    let x = out.path().join("x.mxlib");
    let mut cmd = Command::new("parallel");
    cmd.args(["--halt", "now,fail=1", "-j", "2"])
        .arg(mx_bin())
        .args(["library", "build"])
        .arg(&clips)
        .arg("--out")
        .arg(&x)
        .args([
            "--quiet",
            "--threads",
            "1",
            "--shard",
            "{}/2",
            ":::",
            "0",
            "1",
        ])
        .env_remove("SLURM_ARRAY_TASK_ID")
        .env_remove("SLURM_ARRAY_TASK_COUNT");
    assert!(cmd.status().unwrap().success());
    assert!(merge(&x).status.success());
    assert_eq!(std::fs::read(&x).unwrap(), std::fs::read(&whole).unwrap());
}

#[test]
fn bad_library_builds_get_a_clear_error() {
    let Some(clips) = clips() else { return };
    let out = tempfile::tempdir().unwrap();
    let x = out.path().join("x.mxlib");
    let bad = |c: Command, says: &str| {
        let mut c = c;
        let o = c.output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains(says), "{says}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    };
    bad(build(&clips, &x, &["--shard", "4/3"]), "bad shard `4/3`");
    bad(build(&clips, &x, &["--rate", "0"]), "rate must be");
    bad(build(&clips, &x, &["--threads", "0"]), "--threads");
    let empty = tempfile::tempdir().unwrap();
    bad(build(empty.path(), &x, &[]), "no .bvh clips");
    let mut slurm = build(&clips, &x, &[]);
    slurm.env("SLURM_ARRAY_TASK_ID", "1");
    bad(slurm, "SLURM_ARRAY_TASK_COUNT");
    let o = merge(&x);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("no shard parts"),
        "{err}"
    );
    // parts of two different builds
    ok(build(&clips, &x, &["--shard", "0/2"]));
    ok(build(&clips, &x, &["--shard", "1/3"]));
    let o = merge(&x);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("different builds"),
        "{err}"
    );
}
