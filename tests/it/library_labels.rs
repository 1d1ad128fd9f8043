//! The clip library's stored contact labels (`mx::library::labels`): equal to
//! `contacts()` on every shared clip, kept through a save and a load, carried
//! onto a gap's clock as a library example's stances; and the `.mxlib`
//! versions and truncations a load refuses.

use crate::common;
use mx::ground::{self, GroundOptions};
use mx::library::{self, ClipLabels, Library, Settings, file, labels};
use mx::mocap::body_of;
use std::path::PathBuf;

fn folders() -> Vec<PathBuf> {
    let Some(d) = common::shared_dir() else {
        return vec![];
    };
    ["mocap", "inbetween"]
        .iter()
        .map(|s| d.join("data").join(s))
        .collect()
}

/// Every shared clip (both folders), as `library(dir)` reads them.
fn shared_library() -> Option<Library> {
    let mut clips = vec![];
    let mut skipped = vec![];
    for dir in folders() {
        let (c, s) = library::clips_in_folder(&dir).unwrap();
        clips.extend(c);
        skipped.extend(s);
    }
    if clips.is_empty() {
        return None;
    }
    Some(Library::build(clips, skipped, Settings::default()).unwrap())
}

/// `labels` against `contacts()` on the clip's own body, point by point and
/// frame by frame.
fn assert_labels_are_contacts(lib: &Library, what: &str) {
    let mut points = 0;
    for c in &lib.clips {
        let clip = c.motion().unwrap();
        let l = c
            .labels()
            .unwrap()
            .unwrap_or_else(|| panic!("{what}: `{}` has no labels", c.name));
        let (body, _) = body_of(&clip.skeleton, 70.0, clip.units.metres_per_unit).unwrap();
        let want = ground::contacts(&clip.mu, &body, &GroundOptions::default()).unwrap();
        assert_eq!(l.frames, want.times.len(), "{what}: {}", c.name);
        assert_eq!(l.start, want.times[0], "{what}: {}", c.name);
        assert_eq!(l.floor, want.floor, "{what}: {}", c.name);
        assert_eq!(l.points.len(), want.points.len(), "{what}: {}", c.name);
        for (p, w) in l.points.iter().zip(&want.points) {
            assert_eq!(p.name, w.name, "{what}: {}", c.name);
            assert_eq!(
                labels::flags(&p.contact, l.frames),
                w.in_contact,
                "{what}: {} {}",
                c.name,
                p.name
            );
            // the planning rule stands at the point's own lowest height,
            // never below the floor of every point
            assert!(p.stand >= l.floor - 1e-12, "{}", p.name);
            points += 1;
        }
    }
    assert!(points > 0, "{what}: no contact point labelled");
}

#[test]
fn stored_labels_equal_contacts_on_each_clip() {
    let Some(lib) = shared_library() else { return };
    assert_eq!(lib.clips.len() + lib.skipped.len(), {
        folders()
            .iter()
            .map(|d| library::bvh_files(d).unwrap().len())
            .sum::<usize>()
    });
    assert_labels_are_contacts(&lib, "built");
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("x.mxlib");
    file::save(&lib, &p).unwrap();
    let back = file::load(&p, None).unwrap();
    assert!(
        back.clips
            .iter()
            .all(|c| matches!(c.labels, library::LabelData::Section(_)))
    );
    assert_labels_are_contacts(&back, "loaded");
    // a saved library saves the same bytes again
    assert_eq!(file::to_bytes(&back).unwrap(), std::fs::read(&p).unwrap());
}

/// Every shared clip and the same clip at half its frame rate (every other
/// frame) plan the same stances at the same times, but within a speed
/// window and a frame of a lift-off or touch-down: the rule is in seconds,
/// not frames. Where a clip walks, its feet plant.
#[test]
fn planning_labels_follow_the_clip_not_its_frame_rate() {
    let mut planted = 0;
    for dir in folders() {
        for path in library::bvh_files(&dir).unwrap() {
            let file = mx::mocap::bvh::read_file(&path).unwrap();
            let at = |f: &mx::mocap::bvh::BvhFile| {
                let clip = mx::mocap::from_bvh(f, mx::mocap::bvh::Units::Auto).unwrap();
                ClipLabels::of(&clip).unwrap()
            };
            let full = at(&file);
            let nch = file.skeleton.channel_count();
            let mut half = file.clone();
            half.frame_time *= 2.0;
            half.values = file
                .values
                .chunks(nch)
                .step_by(2)
                .flatten()
                .copied()
                .collect();
            let half = at(&half);
            assert_eq!(full.points.len(), half.points.len());
            for (a, b) in full.points.iter().zip(&half.points) {
                let fa = labels::flags(&a.plan, full.frames);
                let fb = labels::flags(&b.plan, half.frames);
                let agree = (0..half.frames).filter(|&k| fa[2 * k] == fb[k]).count();
                assert!(
                    agree as f64 >= 0.85 * half.frames as f64,
                    "{} {}: {agree} of {} frames agree",
                    path.display(),
                    a.name,
                    half.frames
                );
                planted += usize::from(!a.plan.is_empty());
            }
        }
    }
    assert!(planted > 0 || common::shared_dir().is_none());
}

/// A library written by an older mx (format version 2, before contact
/// labels) or cut short anywhere is refused on load with a sentence that
/// says so, and how to make a good one.
#[test]
fn an_older_or_truncated_mxlib_is_refused_clearly() {
    let Some(dir) = common::shared_dir() else {
        return;
    };
    let one = library::bvh_files(&dir.join("data").join("mocap")).unwrap()[0].clone();
    let lib = Library::build_files(&[one], Settings::default()).unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let p = tmp.path().join("x.mxlib");
    file::save(&lib, &p).unwrap();
    let good = std::fs::read(&p).unwrap();
    let refused = |b: &[u8]| {
        std::fs::write(&p, b).unwrap();
        file::load(&p, None)
            .err()
            .map(|e| e.to_string())
            .unwrap_or_else(|| "loaded".into())
    };
    for old in [1u32, 2] {
        let mut b = good.clone();
        b[6..10].copy_from_slice(&old.to_le_bytes());
        let e = refused(&b);
        assert!(
            e.contains(&format!("version {old}")) && e.contains("rebuild") && e.contains("x.mxlib"),
            "{e}"
        );
    }
    for keep in [3, 9, 17, 40, good.len() / 3, good.len() / 2, good.len() - 1] {
        let e = refused(&good[..keep]);
        assert!(
            e.contains("damaged") && e.contains("x.mxlib"),
            "{keep} of {} bytes: {e}",
            good.len()
        );
    }
    assert_eq!(refused(&good), "loaded");
}
