//! The BVH reader: HIERARCHY (any channel order, 0–6 channels per joint, End
//! Sites, several roots), MOTION header and the frame table. CRLF, tabs, `-0`
//! and exponents are accepted. Every malformed input is a [`BvhError`] naming
//! the line; nothing panics and nothing allocates more than the text can hold.

use super::{BvhError, BvhFile, BvhJoint, Channel, Skeleton};
use nalgebra::Vector3;
use std::path::Path;

/// Reads and parses a BVH file.
pub fn read_file(path: &Path) -> Result<BvhFile, BvhError> {
    let bytes = std::fs::read(path).map_err(|source| BvhError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let text = String::from_utf8_lossy(&bytes);
    parse(&text)
}

/// One whitespace-separated word with its 1-based line number. Braces are
/// always words of their own, even when glued to a name (`Hips{`).
#[derive(Clone, Copy, Debug)]
struct Tok<'a> {
    line: usize,
    text: &'a str,
}

/// Splits one line into words, cutting braces out as separate words.
fn words<'a>(line_no: usize, line: &'a str, out: &mut Vec<Tok<'a>>) {
    for w in line.split_whitespace() {
        let mut rest = w;
        while !rest.is_empty() {
            match rest.find(['{', '}']) {
                Some(0) => {
                    out.push(Tok {
                        line: line_no,
                        text: &rest[..1],
                    });
                    rest = &rest[1..];
                }
                Some(i) => {
                    out.push(Tok {
                        line: line_no,
                        text: &rest[..i],
                    });
                    rest = &rest[i..];
                }
                None => {
                    out.push(Tok {
                        line: line_no,
                        text: rest,
                    });
                    rest = "";
                }
            }
        }
    }
}

struct Cursor<'a> {
    toks: Vec<Tok<'a>>,
    pos: usize,
    /// Line to blame when the tokens run out.
    end_line: usize,
}

impl<'a> Cursor<'a> {
    fn peek(&self) -> Option<Tok<'a>> {
        self.toks.get(self.pos).copied()
    }
    fn next(&mut self, what: &str) -> Result<Tok<'a>, BvhError> {
        let t = self.toks.get(self.pos).copied().ok_or_else(|| {
            BvhError::at(self.end_line, format!("file ends early: expected {what}"))
        })?;
        self.pos += 1;
        Ok(t)
    }
    fn expect(&mut self, word: &str) -> Result<Tok<'a>, BvhError> {
        let t = self.next(&format!("`{word}`"))?;
        if !t.text.eq_ignore_ascii_case(word) {
            return Err(BvhError::at(
                t.line,
                format!("expected `{word}`, found `{}`", t.text),
            ));
        }
        Ok(t)
    }
    fn number(&mut self, what: &str) -> Result<f64, BvhError> {
        let t = self.next(what)?;
        parse_number(t.text).ok_or_else(|| {
            BvhError::at(
                t.line,
                format!("expected {what} (a number), found `{}`", t.text),
            )
        })
    }
    fn vector(&mut self, what: &str) -> Result<Vector3<f64>, BvhError> {
        Ok(Vector3::new(
            self.number(what)?,
            self.number(what)?,
            self.number(what)?,
        ))
    }
    /// The name after ROOT/JOINT: every word up to `{` on the keyword's line.
    fn name(&mut self, kw: Tok<'a>) -> Result<String, BvhError> {
        let mut parts = vec![];
        while let Some(t) = self.peek() {
            if t.line != kw.line || t.text == "{" {
                break;
            }
            parts.push(t.text);
            self.pos += 1;
        }
        if parts.is_empty() {
            return Err(BvhError::at(
                kw.line,
                format!("`{}` needs a joint name", kw.text),
            ));
        }
        Ok(parts.join(" "))
    }
}

/// A finite decimal number (exponents allowed); `nan`/`inf` are refused.
fn parse_number(s: &str) -> Option<f64> {
    s.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// What is open on the hierarchy stack.
enum Open {
    Joint(usize),
    EndSite,
}

/// Parses the text of a BVH file.
pub fn parse(text: &str) -> Result<BvhFile, BvhError> {
    // Locate the MOTION line; the hierarchy is everything before it.
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l));
    let mut toks = Vec::new();
    let mut motion_line = None;
    for (no, line) in lines.by_ref() {
        if line.trim().eq_ignore_ascii_case("MOTION") {
            motion_line = Some(no);
            break;
        }
        words(no, line, &mut toks);
    }
    let Some(motion_line) = motion_line else {
        if toks.is_empty() {
            return Err(BvhError::at(1, "empty file: expected `HIERARCHY`"));
        }
        return Err(BvhError::at(
            text.lines().count().max(1),
            "no `MOTION` section: the file is truncated or not BVH",
        ));
    };
    let skeleton = parse_hierarchy(Cursor {
        toks,
        pos: 0,
        end_line: motion_line,
    })?;
    let nch = skeleton.channel_count();

    // MOTION header: the next two non-empty lines, `Frames: N` and
    // `Frame Time: t` (both may share one line), tolerant of spacing.
    let mut header = Vec::new();
    let mut data_start = motion_line;
    let mut seen = 0;
    for (no, line) in lines.by_ref() {
        data_start = no;
        if line.trim().is_empty() {
            continue;
        }
        words(no, line, &mut header);
        seen += 1;
        if seen == 2 || line.to_ascii_lowercase().contains("time") {
            break;
        }
    }
    let (frames, frames_line, frame_time) = parse_motion_header(&header, data_start)?;
    if nch == 0 && frames > 0 {
        return Err(BvhError::at(
            frames_line,
            "the skeleton has no CHANNELS, so frames cannot hold values",
        ));
    }

    // Never trust the count for allocation: a row needs at least 2 bytes per value.
    let cap = frames.saturating_mul(nch).min(text.len() / 2 + 1);
    let mut values = Vec::with_capacity(cap);
    let mut rows = 0usize;
    let mut last_data_line = data_start;
    for (no, line) in lines {
        // Frame rows are ASCII: the ASCII splitter skips Unicode tables.
        if line.trim_ascii().is_empty() {
            continue;
        }
        if rows == frames {
            return Err(BvhError::at(
                no,
                format!(
                    "more frame rows than `Frames: {frames}` (line {frames_line}) declares; fix the count or remove the extra rows"
                ),
            ));
        }
        let before = values.len();
        for w in line.split_ascii_whitespace() {
            if values.len() - before == nch {
                return Err(BvhError::at(
                    no,
                    format!(
                        "frame {} has more than {nch} values (the skeleton declares {nch} channels)",
                        rows
                    ),
                ));
            }
            let v = parse_number(w).ok_or_else(|| {
                BvhError::at(no, format!("frame {rows}: `{w}` is not a finite number"))
            })?;
            values.push(v);
        }
        let got = values.len() - before;
        if got != nch {
            return Err(BvhError::at(
                no,
                format!("frame {rows} has {got} values but the skeleton declares {nch} channels"),
            ));
        }
        rows += 1;
        last_data_line = no;
    }
    if rows < frames {
        return Err(BvhError::at(
            last_data_line,
            format!(
                "truncated: `Frames: {frames}` (line {frames_line}) but only {rows} frame rows follow"
            ),
        ));
    }
    Ok(BvhFile {
        skeleton,
        frame_time,
        values,
    })
}

fn parse_hierarchy(mut c: Cursor<'_>) -> Result<Skeleton, BvhError> {
    c.expect("HIERARCHY")?;
    let mut joints: Vec<BvhJoint> = Vec::new();
    let mut stack: Vec<Open> = Vec::new();
    while let Some(t) = c.peek() {
        c.pos += 1;
        let kw = t.text.to_ascii_uppercase();
        match kw.as_str() {
            "ROOT" | "JOINT" => {
                let parent = match stack.last() {
                    None if kw == "ROOT" => None,
                    Some(Open::Joint(p)) if kw == "JOINT" => Some(*p),
                    None => {
                        return Err(BvhError::at(
                            t.line,
                            "`JOINT` outside any ROOT; expected `ROOT`",
                        ));
                    }
                    Some(Open::Joint(_)) => {
                        return Err(BvhError::at(
                            t.line,
                            "`ROOT` inside a joint; expected `JOINT`",
                        ));
                    }
                    Some(Open::EndSite) => {
                        return Err(BvhError::at(t.line, "an End Site cannot have child joints"));
                    }
                };
                let name = c.name(t)?;
                if joints.iter().any(|j| j.name == name) {
                    return Err(BvhError::at(
                        t.line,
                        format!("joint name `{name}` is used twice; DOF names must be unique"),
                    ));
                }
                c.expect("{")?;
                joints.push(BvhJoint {
                    name,
                    parent,
                    offset: Vector3::zeros(),
                    channels: vec![],
                    end_sites: vec![],
                });
                stack.push(Open::Joint(joints.len() - 1));
                // OFFSET and CHANNELS come first, in that order (CHANNELS optional).
                c.expect("OFFSET")?;
                let off = c.vector("an OFFSET component")?;
                let j = joints.len() - 1;
                joints[j].offset = off;
                if c.peek()
                    .is_some_and(|t| t.text.eq_ignore_ascii_case("CHANNELS"))
                {
                    let ct = c.next("CHANNELS")?;
                    let n = c.next("the channel count")?;
                    let count: usize = n.text.parse().map_err(|_| {
                        BvhError::at(
                            n.line,
                            format!("expected a channel count 0..6, found `{}`", n.text),
                        )
                    })?;
                    if count > 6 {
                        return Err(BvhError::at(
                            n.line,
                            format!("CHANNELS {count}: a joint has at most 6 channels"),
                        ));
                    }
                    for _ in 0..count {
                        let w = c.next("a channel name")?;
                        let ch = Channel::parse(w.text).ok_or_else(|| {
                            BvhError::at(
                                w.line,
                                format!("`{}` is not a channel (CHANNELS {count} on line {} needs {count} of Xposition … Zrotation)", w.text, ct.line),
                            )
                        })?;
                        if joints[j].channels.contains(&ch) {
                            return Err(BvhError::at(
                                w.line,
                                format!("channel {} repeated", ch.name()),
                            ));
                        }
                        joints[j].channels.push(ch);
                    }
                }
            }
            "END" => {
                match stack.last() {
                    Some(Open::Joint(_)) => {}
                    _ => return Err(BvhError::at(t.line, "`End Site` must be inside a joint")),
                }
                c.expect("Site")?;
                c.expect("{")?;
                c.expect("OFFSET")?;
                let off = c.vector("an End Site OFFSET component")?;
                if let Some(Open::Joint(j)) = stack.last() {
                    joints[*j].end_sites.push(off);
                }
                stack.push(Open::EndSite);
            }
            "}" => {
                if stack.pop().is_none() {
                    return Err(BvhError::at(t.line, "unmatched `}`"));
                }
            }
            _ => {
                let other = t.text;
                return Err(BvhError::at(
                    t.line,
                    format!("unexpected `{other}`; expected `JOINT`, `End Site`, `}}` or `ROOT`"),
                ));
            }
        }
    }
    if !stack.is_empty() {
        return Err(BvhError::at(
            c.end_line,
            format!("{} unclosed `{{` before MOTION", stack.len()),
        ));
    }
    if joints.is_empty() {
        return Err(BvhError::at(c.end_line, "the HIERARCHY has no ROOT joint"));
    }
    Ok(Skeleton { joints })
}

/// `Frames: N` then `Frame Time: t`. Returns (N, line of N, t).
fn parse_motion_header(h: &[Tok<'_>], end_line: usize) -> Result<(usize, usize, f64), BvhError> {
    // Join words and split on ':' so `Frames:\t195`, `Frames : 195` all work.
    let mut it = h.iter().flat_map(|t| {
        t.text.split_inclusive(':').map(move |p| Tok {
            line: t.line,
            text: p,
        })
    });
    let mut take = |what: &str| {
        it.next()
            .ok_or_else(|| BvhError::at(end_line, format!("file ends early: expected {what}")))
    };
    let f = take("`Frames:`")?;
    if !f.text.eq_ignore_ascii_case("Frames:") {
        let f2 = if f.text.eq_ignore_ascii_case("Frames") {
            take("`:`")?
        } else {
            f
        };
        if f2.text != ":" {
            return Err(BvhError::at(
                f.line,
                format!("expected `Frames:`, found `{}`", f.text),
            ));
        }
    }
    let n = take("the frame count")?;
    let frames: usize = n.text.parse().map_err(|_| {
        BvhError::at(
            n.line,
            format!(
                "expected a whole frame count after `Frames:`, found `{}`",
                n.text
            ),
        )
    })?;
    let ft = take("`Frame Time:`")?;
    if !ft.text.eq_ignore_ascii_case("Frame") {
        return Err(BvhError::at(
            ft.line,
            format!("expected `Frame Time:`, found `{}`", ft.text),
        ));
    }
    let tm = take("`Time:`")?;
    if !tm.text.eq_ignore_ascii_case("Time:") {
        let t2 = if tm.text.eq_ignore_ascii_case("Time") {
            take("`:`")?
        } else {
            tm
        };
        if t2.text != ":" {
            return Err(BvhError::at(
                tm.line,
                format!("expected `Frame Time:`, found `{}`", tm.text),
            ));
        }
    }
    let v = take("the frame time")?;
    let dt = parse_number(v.text).filter(|d| *d > 0.0).ok_or_else(|| {
        BvhError::at(
            v.line,
            format!(
                "frame time must be a positive number of seconds, found `{}`",
                v.text
            ),
        )
    })?;
    if let Some(extra) = it.next() {
        return Err(BvhError::at(
            extra.line,
            format!("unexpected `{}` after the frame time", extra.text),
        ));
    }
    Ok((frames, n.line, dt))
}
