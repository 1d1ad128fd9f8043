//! Reader edge cases on small hand-written files, malformed input with line
//! numbers, and a fuzz run over mutated real clips (no panic, ever).

mod common;

use mx::mocap::bvh::{self, Channel};

const SMALL: &str = "HIERARCHY\nROOT Hips\n{\n\tOFFSET 0 0 0\n\tCHANNELS 6 Xposition Yposition Zposition Yrotation Xrotation Zrotation\n\tJOINT Chest\n\t{\n\t\tOFFSET 0 10 0\n\t\tJOINT Neck\n\t\t{\n\t\t\tOFFSET 0 5e1 -0\n\t\t\tCHANNELS 3 Zposition Xrotation Zrotation\n\t\t\tEnd Site\n\t\t\t{\n\t\t\t\tOFFSET 0 1.5E+00 0\n\t\t\t}\n\t\t}\n\t}\n}\nMOTION\nFrames:\t2\nFrame Time:\t0.04\n1 2 3 10 20 30 4 5 6\n-1 -2 -3 -10 -20 -30 -4 5.5e-1 6\n";

#[test]
fn reads_zero_and_odd_channel_orders_end_sites_exponents() {
    let f = bvh::parse(SMALL).unwrap();
    let sk = &f.skeleton;
    assert_eq!(sk.joints.len(), 3);
    assert_eq!(sk.joints[1].channels.len(), 0, "Chest has no CHANNELS line");
    assert_eq!(
        sk.joints[2].channels,
        vec![Channel::Zposition, Channel::Xrotation, Channel::Zrotation]
    );
    assert_eq!(sk.joints[2].offset.y, 50.0);
    assert_eq!(sk.joints[2].end_sites[0].y, 1.5);
    assert_eq!(sk.channel_names()[3], "Hips.Yrotation");
    assert_eq!(f.frame_count(), 2);
    assert_eq!(f.frame(1)[7], 0.55);
    assert_eq!(f.frame_time, 0.04);
    // Neck's Zposition (4 in frame 0) replaces its OFFSET z; x, y stay.
    let p = bvh::fk::world_transforms(&f, 0, 1.0);
    let neck_local = p[1].inverse().compose(&p[2]);
    assert!((neck_local.p - nalgebra::Vector3::new(0.0, 50.0, 4.0)).norm() < 1e-12);
    // Writing it back reads identically.
    assert_eq!(bvh::parse(&bvh::to_string(&f).unwrap()).unwrap(), f);
}

#[test]
fn crlf_and_glued_braces_read_the_same() {
    let crlf = SMALL.replace('\n', "\r\n");
    assert_eq!(bvh::parse(&crlf).unwrap(), bvh::parse(SMALL).unwrap());
    let glued = SMALL
        .replace("ROOT Hips\n{", "ROOT Hips{")
        .replace("\t\t}\n\t}\n}", "\t\t}}}");
    assert_eq!(bvh::parse(&glued).unwrap(), bvh::parse(SMALL).unwrap());
}

/// (mutation, expected line, a word the message must contain)
fn bad_cases() -> Vec<(String, usize, &'static str)> {
    vec![
        (String::new(), 1, "empty"),
        (SMALL.replace("HIERARCHY", "HIERARCHX"), 1, "HIERARCHY"),
        (
            SMALL[..SMALL.find("MOTION").unwrap()].to_string(),
            19,
            "MOTION",
        ),
        (
            SMALL.replace("CHANNELS 3 Zposition", "CHANNELS 4 Zposition"),
            13,
            "channel",
        ),
        (
            SMALL.replace("CHANNELS 6", "CHANNELS 99999999999"),
            5,
            "at most 6",
        ),
        (SMALL.replace("CHANNELS 6", "CHANNELS 7"), 5, "at most 6"),
        (
            SMALL.replace("OFFSET 0 10 0", "OFFSET 0 ten 0"),
            8,
            "number",
        ),
        (
            SMALL.replace("1 2 3 10", "1 2 x 10"),
            23,
            "not a finite number",
        ),
        (
            SMALL.replace("1 2 3 10", "1 2 nan 10"),
            23,
            "not a finite number",
        ),
        (SMALL.replace("1 2 3 10 20", "1 2 3 10"), 23, "8 values"),
        (
            SMALL.replace("-4 5.5e-1 6", "-4 5.5e-1 6 7"),
            24,
            "more than 9",
        ),
        (SMALL.replace("Frames:\t2", "Frames:\t3"), 24, "truncated"),
        (
            SMALL.replace("Frames:\t2", "Frames:\t1"),
            24,
            "more frame rows",
        ),
        (
            SMALL.replace("Frames:\t2", "Frames:\t18446744073709551615"),
            24,
            "truncated",
        ),
        (
            SMALL.replace("Frames:\t2", "Frames:\t-2"),
            21,
            "frame count",
        ),
        (
            SMALL.replace("Frame Time:\t0.04", "Frame Time:\t0"),
            22,
            "positive",
        ),
        (SMALL.replace("Frame Time:\t0.04\n", ""), 22, "Frame Time"),
        (
            SMALL.replace("\t\t\t}\n\t\t}\n\t}\n}\n", "\t\t\t}\n\t\t}\n\t}\n"),
            19,
            "unclosed",
        ),
        (SMALL.replace("JOINT Neck", "JOINT Chest"), 9, "twice"),
        (
            SMALL.replace("Xrotation Zrotation\n", "Xrotation Xrotation\n"),
            5,
            "repeated",
        ),
        (SMALL.replace("JOINT Chest", "BONE Chest"), 6, "unexpected"),
    ]
}

#[test]
fn malformed_input_reports_the_line() {
    for (text, line, word) in bad_cases() {
        match bvh::parse(&text) {
            Ok(_) => panic!("accepted malformed input expecting `{word}`:\n{text}"),
            Err(e) => {
                let msg = e.to_string();
                assert_eq!(e.line(), Some(line), "{msg}");
                assert!(
                    msg.to_lowercase().contains(&word.to_lowercase()),
                    "`{word}` not in: {msg}"
                );
            }
        }
    }
}

#[test]
fn missing_file_is_an_io_error() {
    let e = bvh::read_file(std::path::Path::new("/no/such/file.bvh")).unwrap_err();
    assert!(e.to_string().contains("/no/such/file.bvh"));
}

/// A small deterministic generator (xorshift64*), so failures reproduce.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545F4914F6CDD1D)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

fn mutate(text: &str, rng: &mut Rng) -> String {
    let mut s: Vec<u8> = text.as_bytes().to_vec();
    for _ in 0..1 + rng.below(4) {
        let n = s.len().max(1);
        let at = rng.below(n).min(s.len());
        match rng.below(8) {
            0 => s.truncate(at),
            1 => {
                let end = (at + rng.below(200)).min(s.len());
                s.drain(at..end);
            }
            2 => {
                let junk: &[&[u8]] = &[
                    b"{",
                    b"}",
                    b"-",
                    b"e",
                    b"1e400",
                    b"nan",
                    b"\n",
                    b"\t",
                    b"JOINT X\n{",
                    b"End Site",
                    b"CHANNELS 6",
                    b"99999999999999999999",
                    b"\0",
                    b"\xff",
                ];
                let j = junk[rng.below(junk.len())];
                s.splice(at..at, j.iter().copied());
            }
            3 => {
                if at < s.len() {
                    s[at] = rng.below(256) as u8;
                }
            }
            4 => {
                // Duplicate a slice (extra rows, repeated joints).
                let end = (at + rng.below(400)).min(s.len());
                let dup = s[at..end].to_vec();
                s.splice(at..at, dup);
            }
            5 => {
                if let Some(p) = s.iter().position(|&b| b == b'\n') {
                    s.insert(p, b'\r');
                }
            }
            6 => {
                // Change a digit.
                if let Some(p) = s[at..].iter().position(|b| b.is_ascii_digit()) {
                    s[at + p] = b'0' + rng.below(10) as u8;
                }
            }
            _ => {
                let end = (at + rng.below(20)).min(s.len());
                s[at..end].reverse();
            }
        }
    }
    String::from_utf8_lossy(&s).into_owned()
}

#[test]
fn fuzz_mutated_real_clips_never_panic() {
    let mut rng = Rng(0x9E3779B97F4A7C15);
    let mut errors = 0;
    let mut total = 0;
    for path in common::shared_files("mocap", ".bvh") {
        let full = std::fs::read_to_string(&path).unwrap();
        // Keep the fuzz fast: the hierarchy plus a few frames.
        let cut = full.find("MOTION").unwrap();
        let head: String = full[cut..].lines().take(12).collect::<Vec<_>>().join("\n");
        let base = format!("{}{}\n", &full[..cut], head).replace("Frames:\t", "Frames: ");
        let base = fix_frames(&base);
        assert!(bvh::parse(&base).is_ok(), "{}", path.display());
        for _ in 0..150 {
            let m = mutate(&base, &mut rng);
            total += 1;
            if let Err(e) = bvh::parse(&m) {
                errors += 1;
                let lines = m.lines().count().max(1);
                let line = e.line().expect("parse errors carry a line");
                assert!(
                    line >= 1 && line <= lines + 1,
                    "line {line} of {lines}: {e}"
                );
            }
        }
    }
    eprintln!("{errors}/{total} mutated files rejected with a line number, none panicked");
}

/// Sets `Frames:` to the number of rows kept.
fn fix_frames(s: &str) -> String {
    let rows = s
        .split("MOTION")
        .nth(1)
        .map(|m| m.lines().filter(|l| !l.trim().is_empty()).count() - 2)
        .unwrap_or(0);
    let mut out = String::new();
    for l in s.lines() {
        if l.trim_start().starts_with("Frames:") {
            out.push_str(&format!("Frames: {rows}\n"));
        } else {
            out.push_str(l);
            out.push('\n');
        }
    }
    out
}
