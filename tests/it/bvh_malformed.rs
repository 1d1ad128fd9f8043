//! Reader edge cases on small hand-written files, the corpus of quirky files
//! in `tests/bvh_quirks/` (each with the warnings or the error it must give),
//! malformed input with line numbers, and mutation runs over real clips (no
//! panic, ever; every failure names its line).

use crate::common;
use crate::support::Rng;

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
            "`x` is not a number",
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
    let mut rng = Rng::from_state(0x9E3779B97F4A7C15);
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

#[test]
fn frame_counts_that_disagree_with_the_rows_are_read_with_one_warning() {
    for (declared, line, word) in [
        ("3", 21, "only 2 follow"),
        ("1", 24, "read all 2"),
        ("0", 23, "read all 2"),
        ("18446744073709551615", 21, "only 2 follow"),
    ] {
        let text = SMALL.replace("Frames:\t2", &format!("Frames:\t{declared}"));
        let (f, w) = bvh::parse_with_warnings(&text).unwrap();
        assert_eq!(f, bvh::parse(SMALL).unwrap(), "Frames: {declared}");
        assert_eq!(w.len(), 1, "{w:?}");
        assert_eq!(w[0].line, line, "{}", w[0]);
        assert!(w[0].message.contains(word), "{}", w[0]);
    }
    assert!(bvh::parse_with_warnings(SMALL).unwrap().1.is_empty());
}

/// What a corpus file's `.expect` sidecar says it must give.
#[derive(Default, Debug)]
struct Expect {
    frames: Option<usize>,
    frame_time: Option<f64>,
    /// (line, words the warning must contain), in line order.
    warnings: Vec<(usize, String)>,
    /// (line, column, words the message must contain).
    error: Option<(usize, Option<usize>, String)>,
    /// (joint, channel names in file order).
    channels: Vec<(String, Vec<String>)>,
}

fn read_expect(path: &std::path::Path) -> Expect {
    let mut e = Expect::default();
    for l in std::fs::read_to_string(path).unwrap().lines() {
        let (kind, rest) = l.split_once(' ').unwrap_or((l, ""));
        match kind {
            "frames" => e.frames = Some(rest.parse().unwrap()),
            "frame_time" => e.frame_time = Some(rest.parse().unwrap()),
            "warn" => {
                let (line, words) = rest.split_once(' ').unwrap();
                e.warnings.push((line.parse().unwrap(), words.into()));
            }
            "error" => {
                let (at, words) = rest.split_once(' ').unwrap();
                let (line, col) = match at.split_once(':') {
                    Some((l, c)) => (l.parse().unwrap(), Some(c.parse().unwrap())),
                    None => (at.parse().unwrap(), None),
                };
                e.error = Some((line, col, words.into()));
            }
            "channels" => {
                let mut w = rest.split_whitespace().map(String::from);
                let joint = w.next().unwrap();
                e.channels.push((joint, w.collect()));
            }
            other => panic!("{}: unknown expectation `{other}`", path.display()),
        }
    }
    e
}

fn quirk_files() -> Vec<std::path::PathBuf> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bvh_quirks");
    let mut v: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "bvh"))
        .collect();
    v.sort();
    v
}

#[test]
fn quirky_corpus_loads_with_the_expected_warnings_or_fails_with_the_expected_error() {
    let files = quirk_files();
    assert!(files.len() >= 12, "{} corpus files", files.len());
    let (mut loaded, mut refused, mut warned) = (0, 0, 0);
    for path in files {
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let exp = read_expect(&path.with_extension("expect"));
        let got = bvh::read_file_with_warnings(&path);
        match (&exp.error, got) {
            (Some((line, col, words)), Err(e)) => {
                refused += 1;
                let msg = e.to_string();
                assert_eq!(e.line(), Some(*line), "{name}: {msg}");
                assert_eq!(e.column(), *col, "{name}: {msg}");
                if let Some(c) = col {
                    assert!(msg.contains(&format!("line {line}, column {c}")), "{msg}");
                }
                assert!(
                    msg.contains(words.as_str()),
                    "{name}: `{words}` not in {msg}"
                );
            }
            (Some(_), Ok(_)) => panic!("{name}: loaded, but an error was expected"),
            (None, Err(e)) => panic!("{name}: {e}"),
            (None, Ok((f, warnings))) => {
                loaded += 1;
                warned += usize::from(!warnings.is_empty());
                let got: Vec<_> = warnings.iter().map(|w| w.to_string()).collect();
                assert_eq!(warnings.len(), exp.warnings.len(), "{name}: {got:#?}");
                for (w, (line, words)) in warnings.iter().zip(&exp.warnings) {
                    assert_eq!(w.line, *line, "{name}: {w}");
                    assert!(
                        w.message.contains(words.as_str()),
                        "{name}: `{words}` not in {w}"
                    );
                }
                if let Some(n) = exp.frames {
                    assert_eq!(f.frame_count(), n, "{name}");
                }
                if let Some(t) = exp.frame_time {
                    assert_eq!(f.frame_time, t, "{name}");
                }
                for (joint, chans) in &exp.channels {
                    let j = &f.skeleton.joints[f.skeleton.find(joint).unwrap()];
                    let names: Vec<_> = j.channels.iter().map(|c| c.name()).collect();
                    assert_eq!(&names, chans, "{name}: {joint}");
                }
                // Saving what was loaded round-trips exactly, and the saved file is clean.
                let text = bvh::to_string(&f).unwrap();
                let (again, w2) = bvh::parse_with_warnings(&text).unwrap();
                assert_eq!(again, f, "{name}");
                assert!(w2.is_empty(), "{name}: {w2:?}");
            }
        }
    }
    assert!(
        loaded >= 6 && refused >= 6 && warned >= 5,
        "{loaded} {refused} {warned}"
    );
}

#[test]
fn loose_formatting_reads_the_same_values_as_the_clean_file() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bvh_quirks");
    let clean = bvh::read_file(&dir.join("extra_row.bvh")).unwrap();
    for name in [
        "trailing_blanks",
        "blank_lines",
        "end_site_case",
        "fewer_rows",
    ] {
        let f = bvh::read_file(&dir.join(format!("{name}.bvh"))).unwrap();
        assert_eq!(f.values, clean.values, "{name}");
        assert_eq!(f.skeleton, clean.skeleton, "{name}");
    }
}

#[test]
fn load_prints_one_warning_line_per_tolerance_and_bvh_info_lists_them() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bvh_quirks");
    let path = dir.join("mixed_quirks.bvh");
    let script = format!(
        "let m = load({p:?})\nprint(len(dofs(m)))\nprint(bvh_info({p:?}).warnings)",
        p = path.display().to_string()
    );
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_mx"))
        .args(["eval", &format!("{{ {} }}", script.replace('\n', "; "))])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stderr}");
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), 3, "{stderr}");
    for (l, (line, what)) in
        lines
            .iter()
            .zip([(21, "read all 5"), (23, "blank"), (25, "cut short")])
    {
        assert!(l.starts_with("warning: "), "{l}");
        assert!(l.contains("mixed_quirks.bvh"), "{l}");
        assert!(
            l.contains(&format!("line {line}: ")) && l.contains(what),
            "{l}"
        );
    }
    assert!(
        stdout.contains("line 25: the last frame row is cut short"),
        "{stdout}"
    );
}

/// One of the ways real files go wrong, applied to whole lines and words.
fn mutate_like_a_tool(text: &str, rng: &mut Rng) -> (String, &'static str) {
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let motion = lines.iter().position(|l| l.trim() == "MOTION").unwrap();
    let first_row = motion + 3;
    let row = first_row + rng.below(lines.len() - first_row);
    let any = rng.below(lines.len());
    let kind = match rng.below(9) {
        0 => {
            // Truncate anywhere (a cut-short export).
            let mut s = lines.join("\n");
            let mut at = rng.below(s.len());
            while !s.is_char_boundary(at) {
                at -= 1;
            }
            s.truncate(at);
            return (s, "truncate");
        }
        1 => {
            let n = 1 + rng.below(3);
            let dup = lines[row].clone();
            for _ in 0..n {
                lines.insert(row, dup.clone());
            }
            "duplicate rows"
        }
        2 => {
            let mut w: Vec<&str> = lines[any].split_whitespace().collect();
            if !w.is_empty() {
                w.remove(rng.below(w.len()));
            }
            lines[any] = w.join(" ");
            "drop a token"
        }
        3 => {
            let words = [
                "ten", "NaN", "inf", "-inf", "1e999", "1,5", "--1", "0x10", "½",
            ];
            let mut w: Vec<String> = lines[row].split_whitespace().map(String::from).collect();
            let i = rng.below(w.len());
            w[i] = words[rng.below(words.len())].to_string();
            lines[row] = w.join(" ");
            "a word for a number"
        }
        4 => return (lines.join("\r\n") + "\r\n", "CRLF"),
        5 => {
            for l in &mut lines {
                *l = l.replace(' ', "\t");
            }
            "tabs"
        }
        6 => {
            lines.insert(row, " \t ".into());
            "blank line among rows"
        }
        7 => {
            let f = motion + 1;
            lines[f] = format!("Frames: {}", rng.below(40));
            "wrong frame count"
        }
        _ => {
            lines[motion + 2] = format!(
                "Frame Time: {}",
                ["0", "-0.01", ".0083333", "nan", "x"][rng.below(5)]
            );
            "frame time"
        }
    };
    (lines.join("\n") + "\n", kind)
}

#[test]
fn mutation_run_over_the_shared_clips_never_panics_and_every_failure_names_its_line() {
    let mut rng = Rng::from_state(0xD1B54A32D192ED03);
    let clips = common::shared_files("mocap", ".bvh");
    let start = std::time::Instant::now();
    let (mut total, mut refused, mut warned) = (0usize, 0usize, 0usize);
    let mut kinds = std::collections::BTreeMap::new();
    let per_clip = 1000usize.div_ceil(clips.len().max(1)) + 10;
    for path in &clips {
        let full = std::fs::read_to_string(path).unwrap();
        let cut = full.find("MOTION").unwrap();
        let head: String = full[cut..].lines().take(23).collect::<Vec<_>>().join("\n");
        let base = fix_frames(&format!("{}{}\n", &full[..cut], head));
        let clean = bvh::parse(&base).unwrap();
        for _ in 0..per_clip {
            let (m, kind) = mutate_like_a_tool(&base, &mut rng);
            total += 1;
            *kinds.entry(kind).or_insert(0usize) += 1;
            let t = std::time::Instant::now();
            let got = bvh::parse_with_warnings(&m);
            assert!(
                t.elapsed().as_secs_f64() < 2.0,
                "{kind}: parse took {:?}",
                t.elapsed()
            );
            match got {
                Err(e) => {
                    refused += 1;
                    let lines = m.lines().count().max(1);
                    let line = e.line().unwrap_or_else(|| panic!("{kind}: no line in {e}"));
                    assert!(
                        line >= 1 && line <= lines + 1,
                        "{kind}: line {line} of {lines}: {e}"
                    );
                    if kind == "a word for a number" && e.to_string().contains("number") {
                        assert!(e.column().is_some(), "{kind}: no column in {e}");
                    }
                }
                Ok((f, w)) => {
                    warned += usize::from(!w.is_empty());
                    assert!(w.iter().all(|w| w.line >= 1 && !w.message.is_empty()));
                    if kind == "CRLF" || kind == "tabs" {
                        assert_eq!(f, clean, "{kind} changed what was read");
                        assert!(w.is_empty(), "{kind}: {w:?}");
                    }
                    let again = bvh::parse(&bvh::to_string(&f).unwrap()).unwrap();
                    assert_eq!(again, f, "{kind}: save does not round-trip");
                }
            }
        }
    }
    if clips.is_empty() {
        return; // shared_files already failed in CI
    }
    assert!(total >= 1000, "{total} variants");
    assert!(
        refused > 50 && warned > 50,
        "{refused} refused, {warned} warned"
    );
    assert!(start.elapsed().as_secs() < 120, "{:?}", start.elapsed());
    eprintln!(
        "{total} tool-like variants of {} clips: {refused} refused with a line, {warned} read with warnings, none panicked ({kinds:?}, {:.1} s)",
        clips.len(),
        start.elapsed().as_secs_f64()
    );
}
