//! The BVH reader: HIERARCHY (each joint its own channel order, 0–6 channels
//! per joint, `End Site` in any case, several roots), MOTION header and the
//! frame table. CRLF, tabs, trailing blanks, `-0`, `.5` and exponents are
//! accepted as they are. Loose frame tables that still lose nothing are read
//! with a [`BvhWarning`] each (more or fewer rows than `Frames:` declares, a
//! cut-short last row dropped, blank lines among the rows skipped). Every
//! malformed input is a [`BvhError`] naming the line (and the column of the
//! word to blame); nothing panics and nothing allocates more than the text
//! can hold.

use super::{BvhError, BvhFile, BvhJoint, BvhWarning, Channel, Skeleton};
use nalgebra::Vector3;
use std::path::Path;

/// Reads and parses a BVH file (warnings dropped: see [`read_file_with_warnings`]).
pub fn read_file(path: &Path) -> Result<BvhFile, BvhError> {
    read_file_with_warnings(path).map(|(f, _)| f)
}

/// Reads and parses a BVH file, with what the reader tolerated.
pub fn read_file_with_warnings(path: &Path) -> Result<(BvhFile, Vec<BvhWarning>), BvhError> {
    let bytes = std::fs::read(path).map_err(|source| BvhError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let text = String::from_utf8_lossy(&bytes);
    parse_with_warnings(&text)
}

/// The 1-based column (in characters) of `word`, a slice of `line`.
fn column_of(line: &str, word: &str) -> usize {
    let off = (word.as_ptr() as usize).saturating_sub(line.as_ptr() as usize);
    line.get(..off).map_or(off, |p| p.chars().count()) + 1
}

/// One whitespace-separated word with its 1-based line number. Braces are
/// always words of their own, even when glued to a name (`Hips{`).
#[derive(Clone, Copy, Debug)]
struct Tok<'a> {
    line: usize,
    col: usize,
    text: &'a str,
}

/// Splits one line into words, cutting braces out as separate words.
fn words<'a>(line_no: usize, line: &'a str, out: &mut Vec<Tok<'a>>) {
    for w in line.split_whitespace() {
        let mut rest = w;
        while !rest.is_empty() {
            let cut = match rest.find(['{', '}']) {
                Some(0) => 1,
                Some(i) => i,
                None => rest.len(),
            };
            out.push(Tok {
                line: line_no,
                col: column_of(line, rest),
                text: &rest[..cut],
            });
            rest = &rest[cut..];
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
            return Err(BvhError::at_col(
                t.line,
                t.col,
                format!("expected `{word}`, found `{}`", t.text),
            ));
        }
        Ok(t)
    }
    fn number(&mut self, what: &str) -> Result<f64, BvhError> {
        let t = self.next(what)?;
        parse_number(t.text).ok_or_else(|| {
            BvhError::at_col(
                t.line,
                t.col,
                format!("expected {what} (a finite number), found `{}`", t.text),
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

/// Parses the text of a BVH file (warnings dropped: see [`parse_with_warnings`]).
pub fn parse(text: &str) -> Result<BvhFile, BvhError> {
    parse_with_warnings(text).map(|(f, _)| f)
}

/// Parses the text of a BVH file, with one warning per kind of looseness the
/// reader tolerated.
pub fn parse_with_warnings(text: &str) -> Result<(BvhFile, Vec<BvhWarning>), BvhError> {
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
    let (values, rows, warnings) = parse_rows(lines, nch, frames, frames_line, text.len())?;
    if nch == 0 && rows > 0 {
        return Err(BvhError::at(
            frames_line,
            "the skeleton has no CHANNELS, so frames cannot hold values",
        ));
    }
    let file = BvhFile {
        skeleton,
        frame_time,
        values,
    };
    Ok((file, warnings))
}

/// The frame table: every row there is, whatever `Frames:` says (with a
/// warning when the count differs), blank lines among the rows skipped (one
/// warning), a cut-short last row dropped (one warning). Any other row with a
/// wrong number of values, and any word that is not a finite number, is an
/// error at its line and column. Returns (values, rows, warnings).
fn parse_rows<'a>(
    lines: impl Iterator<Item = (usize, &'a str)>,
    nch: usize,
    frames: usize,
    frames_line: usize,
    text_len: usize,
) -> Result<(Vec<f64>, usize, Vec<BvhWarning>), BvhError> {
    // Frame rows are ASCII: the ASCII splitter skips Unicode tables.
    let rest: Vec<(usize, &str)> = lines.collect();
    let last_row = rest
        .iter()
        .rposition(|(_, l)| !l.trim_ascii().is_empty())
        .map(|i| rest[i].0);
    // Never trust the count for allocation: a row needs at least 2 bytes per value.
    let cap = frames.saturating_mul(nch).min(text_len / 2 + 1);
    let mut values = Vec::with_capacity(cap);
    let mut warnings = Vec::new();
    let mut rows = 0usize;
    let mut blank: Option<(usize, usize)> = None; // (first line, count) among rows
    let mut first_extra = None; // the first row past the declared count
    for &(no, line) in &rest {
        if line.trim_ascii().is_empty() {
            if rows > 0 && Some(no) < last_row {
                blank.get_or_insert((no, 0)).1 += 1;
            }
            continue;
        }
        let before = values.len();
        let mut words = line.split_ascii_whitespace().peekable();
        while let Some(w) = words.next() {
            if values.len() - before == nch {
                return Err(BvhError::at_col(
                    no,
                    column_of(line, w),
                    format!(
                        "frame {rows} has more than {nch} values (the skeleton declares {nch} channels)"
                    ),
                ));
            }
            let is_last_word = Some(no) == last_row && words.peek().is_none();
            match parse_word(w) {
                Ok(v) => values.push(v),
                // A number cut in half at the very end of the file (`12.`, `-`,
                // `1e`): the row is short anyway and is dropped below.
                Err(_) if is_last_word && values.len() - before + 1 < nch => break,
                Err(why) => {
                    return Err(BvhError::at_col(
                        no,
                        column_of(line, w),
                        format!("frame {rows}: `{w}` {why}"),
                    ));
                }
            }
        }
        let got = values.len() - before;
        if got != nch {
            if Some(no) == last_row && got < nch {
                values.truncate(before);
                warnings.push(BvhWarning {
                    line: no,
                    message: format!(
                        "the last frame row is cut short ({got} of {nch} values): dropped it"
                    ),
                });
                break;
            }
            return Err(BvhError::at(
                no,
                format!("frame {rows} has {got} values but the skeleton declares {nch} channels"),
            ));
        }
        rows += 1;
        if Some(rows) == frames.checked_add(1) {
            first_extra = Some(no);
        }
    }
    if let Some((first, n)) = blank {
        warnings.push(BvhWarning {
            line: first,
            message: format!(
                "{n} blank line{} among the frame rows: skipped",
                if n == 1 { "" } else { "s" }
            ),
        });
    }
    if let Some(line) = first_extra {
        warnings.push(BvhWarning {
            line,
            message: format!(
                "{rows} frame rows but `Frames: {frames}` (line {frames_line}) declares {frames}: read all {rows}"
            ),
        });
    }
    if rows < frames {
        warnings.push(BvhWarning {
            line: frames_line,
            message: format!(
                "`Frames: {frames}` declares {frames} rows but only {rows} follow (a truncated export?): read {rows}"
            ),
        });
    }
    warnings.sort_by_key(|w| w.line);
    Ok((values, rows, warnings))
}

/// A frame value, or why the word is not one.
fn parse_word(w: &str) -> Result<f64, &'static str> {
    match w.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err("is not a finite number (NaN and infinities are refused)"),
        Err(_) => Err("is not a number"),
    }
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
    Ok(Skeleton {
        joints,
        inertias: None,
    })
}

/// `Frames: N` then `Frame Time: t`. Returns (N, line of N, t).
fn parse_motion_header(h: &[Tok<'_>], end_line: usize) -> Result<(usize, usize, f64), BvhError> {
    // Join words and split on ':' so `Frames:\t195`, `Frames : 195` all work.
    let mut it = h.iter().flat_map(|t| {
        t.text.split_inclusive(':').map(move |p| Tok {
            line: t.line,
            col: t.col + column_of(t.text, p) - 1,
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
        BvhError::at_col(
            v.line,
            v.col,
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
