//! Every BVH in $MX_SHARED/data/mocap loads, round-trips, unwraps and has the
//! body dimensions SOURCES.md reports.

use crate::common;

use mx::mocap::bvh::{self, Channel, Units};

#[test]
fn every_shared_clip_loads_and_round_trips() {
    for path in common::shared_files("mocap", ".bvh") {
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let f = bvh::read_file(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        let text = std::fs::read_to_string(&path).unwrap();
        // The rows of numbers after `Frame Time:`, not the `Frames:` header:
        // the reader accepts a file whose header miscounts (with a warning).
        let rows = text
            .lines()
            .skip_while(|l| !l.trim_start().starts_with("Frame Time:"))
            .skip(1)
            .filter(|l| !l.trim().is_empty())
            .count();
        assert!(rows > 0, "{name}: no motion rows");
        assert_eq!(f.frame_count(), rows, "{name}");
        assert!(f.frame_time > 0.0);
        // Write and read back: exact.
        let again = bvh::parse(&bvh::to_string(&f).unwrap()).unwrap();
        assert_eq!(again, f, "{name}: round trip");
        // Units: Bandai centimetres, CMU ASF units.
        let u = bvh::detect_units(&f.skeleton);
        let want = if name.starts_with("cmu") {
            bvh::CMU_UNIT
        } else {
            0.01
        };
        assert_eq!(u.metres_per_unit, want, "{name}: {}", u.reason);
        eprintln!("{name}: {} frames, {}", f.frame_count(), u.reason);
    }
}

#[test]
fn unwrapping_makes_rotations_continuous_and_keeps_values_mod_360() {
    for path in common::shared_files("mocap", ".bvh") {
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let raw = bvh::read_file(&path).unwrap();
        let mut f = raw.clone();
        let wraps = f.unwrap_rotations();
        let kinds: Vec<Channel> = f
            .skeleton
            .joints
            .iter()
            .flat_map(|j| j.channels.clone())
            .collect();
        for (c, k) in kinds.iter().enumerate() {
            if !k.is_rotation() {
                assert_eq!(f.column(c), raw.column(c));
                continue;
            }
            let u = f.column(c);
            let r = raw.column(c);
            for w in u.windows(2) {
                assert!((w[1] - w[0]).abs() <= 180.0, "{name} channel {c}");
            }
            for (a, b) in u.iter().zip(&r) {
                let m = (a - b) / 360.0;
                assert!((m - m.round()).abs() < 1e-9, "{name}: {a} vs {b}");
            }
        }
        // SOURCES.md counts frame-to-frame jumps over 90°: 54 in the walk, all
        // wraps; 408 in the dance, of which 366 exceed 180° (wraps) and 42 are
        // 90–180° swings near the ZXY gimbal singularity (not wraps).
        if name == "bandai1_dance-short_normal_001.bvh" {
            assert_eq!(wraps, 366, "{name}");
        }
        if name == "bandai1_walk_normal_001.bvh" {
            assert_eq!(wraps, 54, "{name}");
        }
        eprintln!("{name}: {wraps} wraps removed");
    }
}

#[test]
fn bandai_standing_heights_match_sources() {
    let Some(dir) = common::shared_dir() else {
        return;
    };
    let path = dir.join("data/mocap/bandai1_bye_sad_001.bvh");
    let f = bvh::read_file(&path).unwrap();
    let s = bvh::resolve_units(Units::Auto, &f.skeleton)
        .unwrap()
        .metres_per_unit;
    let hips = f.skeleton.find("Hips").unwrap();
    let head = f.skeleton.find("Head").unwrap();
    let p = bvh::fk::world_positions(&f, 0, s);
    // SOURCES.md: hips about 0.93 m, head joint about 1.40 m (y up).
    assert!((p[hips].y - 0.93).abs() < 0.06, "hips at {}", p[hips].y);
    assert!((p[head].y - 1.40).abs() < 0.08, "head at {}", p[head].y);
}

#[test]
fn cmu_hip_height_with_cmu_units() {
    let Some(dir) = common::shared_dir() else {
        return;
    };
    let f = bvh::read_file(&dir.join("data/mocap/cmu_131_01_start_walk_stop.bvh")).unwrap();
    let u = bvh::detect_units(&f.skeleton);
    let p = bvh::fk::world_positions(&f, 0, u.metres_per_unit);
    // SOURCES.md: hips about 0.91–1.01 m high with 0.056444 m/unit.
    assert!(p[0].y > 0.85 && p[0].y < 1.05, "hips at {}", p[0].y);
}
