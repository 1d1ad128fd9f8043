//! What SP's example reads of a library clip (issue 43 item 2): the matched
//! stretch parsed alone is the whole take's curve over it, wherever the
//! clip is kept; and a saved library is smaller than the clips it indexes
//! (item 3).

use crate::common;
use mx::library::{self, ClipInput, Library, Settings, file};
use mx::mocap::Clip;

/// The largest difference between `part`'s samples and `whole`'s over clip
/// times [a, b] (every DOF, on a 240 Hz grid), and the DOF and time of it.
fn largest_difference(part: &Clip, whole: &Clip, (a, b): (f64, f64)) -> (f64, String, f64) {
    let mut worst = (0.0, String::new(), a);
    let n = ((b - a) * 240.0).round() as usize;
    for name in whole.mu.names() {
        for k in 0..=n {
            let t = a + (b - a) * k as f64 / n as f64;
            let x = part.mu.sample_value(name, t).unwrap();
            let y = whole.mu.sample_value(name, t).unwrap();
            let d = match (x, y) {
                (Some(x), Some(y)) => (x - y).abs(),
                _ => f64::INFINITY,
            };
            // angles may differ by whole turns (each read unwraps from its own first frame)
            let turns = (d / std::f64::consts::TAU).round() * std::f64::consts::TAU;
            let d = if d.is_finite() { (d - turns).abs() } else { d };
            if d > worst.0 {
                worst = (d, name.to_string(), t);
            }
        }
    }
    worst
}

/// Stretches at the start, the middle and the end of every clip (the
/// clamped ends as the whole take's), for a library built from files, saved
/// and loaded (the clips deflated in the file) and made in memory.
fn assert_stretches_are_the_whole(lib: &Library, what: &str) {
    for c in &lib.clips {
        let whole = c.motion().unwrap();
        let (lo, hi) = whole.mu.span().unwrap();
        let len = (hi - lo).min(1.4);
        for (a, b) in [
            (lo - 0.2, lo + len / 2.0),
            ((lo + hi) / 2.0 - len / 2.0, (lo + hi) / 2.0 + len / 2.0),
            (hi - len / 2.0, hi + 0.2),
        ] {
            let part = c.stretch(a, b).unwrap();
            let (pa, pb) = part.mu.span().unwrap();
            let inside = (a.max(lo), b.min(hi));
            assert!(
                pa <= inside.0 + 1e-12 && pb >= inside.1 - 1e-12,
                "{what} `{}`",
                c.name
            );
            // the frames asked for and 8 either side, not the whole take
            let most = ((inside.1 - inside.0) / whole.frame_time).ceil() as usize + 2 * 8 + 2;
            assert!(
                part.frames <= most,
                "{what} `{}`: {} frames read for {most}",
                c.name,
                part.frames
            );
            let (d, dof, t) = largest_difference(&part, &whole, inside);
            assert!(
                d < 1e-5,
                "{what} `{}` [{a:.3}, {b:.3}]: {dof} differs by {d:e} at {t:.4} s",
                c.name
            );
        }
    }
}

#[test]
fn a_stretch_read_alone_is_the_whole_takes_curve_over_it() {
    let files = common::shared_files("mocap", ".bvh");
    if files.is_empty() {
        return;
    }
    let lib = Library::build_files(&files, Settings::default()).unwrap();
    assert_stretches_are_the_whole(&lib, "built from files");
    let tmp = tempfile::tempdir().unwrap();
    let p = tmp.path().join("x.mxlib");
    file::save(&lib, &p).unwrap();
    let back = file::load(&p, None).unwrap();
    assert_stretches_are_the_whole(&back, "loaded");
    let one = library::read_clip(&files[0]).unwrap();
    let mem = ClipInput {
        source: None,
        ..one
    };
    let lib = Library::build(vec![mem], vec![], Settings::default()).unwrap();
    assert_stretches_are_the_whole(&lib, "made in memory");
}

/// A file with Windows line ends and blank lines among its rows reads the
/// same stretch as the clean file: the stretch reader skips what the BVH
/// reader skips.
#[test]
fn a_stretch_of_a_loose_file_is_the_clean_files() {
    let Some(p) = common::shared_files("mocap", ".bvh").into_iter().next() else {
        return;
    };
    let text = std::fs::read_to_string(&p).unwrap();
    let motion = text.find("MOTION").unwrap();
    let mut loose = text[..motion].replace('\n', "\r\n");
    for (k, line) in text[motion..].lines().enumerate() {
        loose.push_str(line);
        loose.push_str(if k % 7 == 5 { "\r\n\r\n" } else { "\r\n" });
    }
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("clean.bvh"), &text).unwrap();
    std::fs::write(dir.path().join("loose.bvh"), &loose).unwrap();
    let (clips, skipped) = library::clips_in_folder(dir.path()).unwrap();
    let lib = Library::build(clips, skipped, Settings::default()).unwrap();
    let whole = lib.clips[0].motion().unwrap();
    let (lo, hi) = whole.mu.span().unwrap();
    let (a, b) = (lo + (hi - lo) * 0.4, lo + (hi - lo) * 0.6);
    let clean = lib.clips[0].stretch(a, b).unwrap();
    let of_loose = lib.clips[1].stretch(a, b).unwrap();
    assert_eq!(of_loose.frames, clean.frames);
    let (d, dof, t) = largest_difference(&of_loose, &clean, (a, b));
    assert!(d == 0.0, "{dof} differs by {d:e} at {t}");
}

/// A saved library is no larger than the `.bvh` files it indexes (each
/// shared folder, and both together): the clips are deflated inside it.
#[test]
fn a_saved_library_is_smaller_than_its_clips() {
    let tmp = tempfile::tempdir().unwrap();
    let mut all = vec![];
    for sub in ["mocap", "inbetween"] {
        let files = common::shared_files(sub, ".bvh");
        all.extend(files.iter().cloned());
        let mut cases = vec![files];
        if sub == "inbetween" {
            cases.push(all.clone());
        }
        for files in cases {
            if files.is_empty() {
                continue;
            }
            let bvh: u64 = files
                .iter()
                .map(|f| std::fs::metadata(f).unwrap().len())
                .sum();
            let lib = Library::build_files(&files, Settings::default()).unwrap();
            let p = tmp.path().join("x.mxlib");
            file::save(&lib, &p).unwrap();
            let size = std::fs::metadata(&p).unwrap().len();
            assert!(
                size <= bvh,
                "{sub} ({} clips): .mxlib {size} bytes, its .bvh files {bvh}",
                files.len()
            );
        }
    }
}
