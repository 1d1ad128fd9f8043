//! Where an indexed clip's frames are, read only when a match needs them:
//! the index keeps features in memory, not clips, so a library of 10⁴
//! clips fits where its clips would not, and SP reads the few it follows.

use super::features::KeyJoints;
use super::labels::ClipLabels;
use super::{LibraryError, fingerprint};
use crate::mocap::bvh::{self, BvhFile, Units};
use crate::mocap::{self, Clip};
use serde::{Deserialize, Serialize};
use std::fs::File;
use std::io::{Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::{Duration, SystemTime};

/// A clip handed to [`super::Library::build`].
#[derive(Clone, Debug)]
pub struct ClipInput {
    pub name: String,
    pub file: BvhFile,
    pub metres_per_unit: f64,
    /// The file it was read from, as it was then: the library reads the clip
    /// from there when a match needs it, and a saved index whose sources
    /// changed since is refused as stale. `None`: a clip made in memory,
    /// which the library keeps.
    pub source: Option<Source>,
}

/// A clip's file as it was when it was read: its fingerprint and size, and
/// its modification time where that can be trusted to tell a change.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Source {
    pub path: PathBuf,
    pub fingerprint: u64,
    pub len: u64,
    /// Nanoseconds since 1970; `None` when the file was modified within
    /// [`RACY`] of being read, where another change could keep the same time.
    pub modified_ns: Option<u64>,
}

/// How recent a modification time is too recent to vouch for the file's
/// content (git's "racily clean" entries): a later write within the file
/// system's timestamp granularity could leave it unchanged.
const RACY: Duration = Duration::from_secs(2);

fn modified_ns(meta: &std::fs::Metadata) -> Option<u64> {
    let m = meta.modified().ok()?;
    if SystemTime::now()
        .duration_since(m)
        .is_ok_and(|age| age < RACY)
    {
        return None;
    }
    Some(m.duration_since(SystemTime::UNIX_EPOCH).ok()?.as_nanos() as u64)
}

impl Source {
    /// The stamp of `path`, whose content is `bytes` (read just now).
    pub fn of(path: &Path, bytes: &[u8]) -> Source {
        let meta = std::fs::metadata(path).ok();
        Source {
            path: path.to_path_buf(),
            fingerprint: fingerprint(bytes),
            len: bytes.len() as u64,
            modified_ns: meta.as_ref().and_then(modified_ns),
        }
    }

    /// Whether the file still holds what was indexed: `None` when it is gone
    /// (the library stands alone where its clips are kept). The size and the
    /// modification time answer without reading it; where they cannot
    /// vouch, the bytes are fingerprinted.
    pub fn unchanged(&self) -> Option<bool> {
        let meta = std::fs::metadata(&self.path).ok()?;
        if meta.len() != self.len {
            return Some(false);
        }
        if self.modified_ns.is_some() && modified_ns(&meta) == self.modified_ns {
            return Some(true);
        }
        let now = std::fs::read(&self.path).ok()?;
        Some(fingerprint(&now) == self.fingerprint)
    }
}

/// An open `.mxlib` file whose clip section is read on demand. The handle
/// keeps the file that was loaded, even when a later save renames another
/// over its path.
pub struct SectionFile {
    pub path: PathBuf,
    file: Mutex<File>,
}

impl SectionFile {
    pub fn new(path: &Path, file: File) -> SectionFile {
        SectionFile {
            path: path.to_path_buf(),
            file: Mutex::new(file),
        }
    }

    /// `len` bytes at `offset`.
    pub fn read(&self, offset: u64, len: u64) -> std::io::Result<Vec<u8>> {
        let mut f = self.file.lock().unwrap_or_else(|p| p.into_inner());
        f.seek(SeekFrom::Start(offset))?;
        let mut out = vec![0; len as usize];
        f.read_exact(&mut out)?;
        Ok(out)
    }
}

impl std::fmt::Debug for SectionFile {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "SectionFile({})", self.path.display())
    }
}

/// Bytes of an `.mxlib`'s clip section: `len` at `offset`, deflated (the
/// file is smaller than the clips it holds), and the `size` and fingerprint
/// of what they inflate to (in the header, which the checksum covers).
#[derive(Clone, Debug)]
pub struct Stored {
    pub file: Arc<SectionFile>,
    pub offset: u64,
    pub len: u64,
    pub size: u64,
    pub fingerprint: u64,
}

impl Stored {
    /// The bytes, inflated and checked; damaged (naming the clip and `what`
    /// of it) when they cannot be read, do not inflate or do not match.
    pub fn read(&self, name: &str, what: &str) -> Result<Vec<u8>, LibraryError> {
        let damaged = || {
            LibraryError::file(
                &self.file.path,
                format!(
                    "{}: damaged (the clip `{name}`'s {what} does not match its checksum): rebuild it with library(…)",
                    self.file.path.display()
                ),
            )
        };
        let packed = self
            .file
            .read(self.offset, self.len)
            .map_err(|_| damaged())?;
        let bytes = inflate(&packed, self.size).ok_or_else(damaged)?;
        if fingerprint(&bytes) != self.fingerprint {
            return Err(damaged());
        }
        Ok(bytes)
    }
}

/// How hard a clip's bytes are deflated in an `.mxlib`: miniz's fastest
/// level, which already takes BVH text to about a third (its digits repeat)
/// while a build of 10⁴ clips stays within its time.
const DEFLATE_LEVEL: u8 = 1;

/// `bytes` deflated (raw deflate, no header), as an `.mxlib` stores a clip.
pub fn deflate(bytes: &[u8]) -> Vec<u8> {
    miniz_oxide::deflate::compress_to_vec(bytes, DEFLATE_LEVEL)
}

/// `packed` inflated to exactly `size` bytes; `None` when it does not.
fn inflate(packed: &[u8], size: u64) -> Option<Vec<u8>> {
    let out = miniz_oxide::inflate::decompress_to_vec_with_limit(packed, size as usize).ok()?;
    (out.len() as u64 == size).then_some(out)
}

/// Where a clip's frames are.
#[derive(Clone, Debug)]
pub enum ClipData {
    /// Kept in memory: a clip made from a motion, with no file.
    Memory(Arc<BvhFile>),
    /// Its `.bvh` file, read when needed and refused if it changed.
    File(Source),
    /// BVH text inside an `.mxlib` file.
    Section(Stored),
}

impl ClipData {
    /// The stored bytes' length and fingerprint (a file's or an `.mxlib`
    /// section's), which identify its text; `None` for a clip in memory.
    pub fn stamp(&self) -> Option<(u64, u64)> {
        match self {
            ClipData::Memory(_) => None,
            ClipData::File(s) => Some((s.len, s.fingerprint)),
            ClipData::Section(s) => Some((s.size, s.fingerprint)),
        }
    }

    /// The clip's BVH text as stored (`None` for a clip in memory), checked
    /// against the fingerprint taken when it was indexed or saved.
    pub fn stored_bytes(&self, name: &str) -> Result<Option<Vec<u8>>, LibraryError> {
        match self {
            ClipData::Memory(_) => Ok(None),
            ClipData::File(s) => {
                let bytes = std::fs::read(&s.path).map_err(|e| {
                    LibraryError::file(&s.path, format!(
                        "the clip `{name}` cannot be read from {}: {e} (the library refers to its file: keep it, or save the library while it is there)",
                        s.path.display()
                    ))
                })?;
                if fingerprint(&bytes) != s.fingerprint {
                    return Err(LibraryError::file(
                        &s.path,
                        format!(
                            "stale: the clip `{name}` ({}) changed since the library was built: rebuild it with library(…)",
                            s.path.display()
                        ),
                    ));
                }
                Ok(Some(bytes))
            }
            ClipData::Section(stored) => stored.read(name, "text").map(Some),
        }
    }

    /// The clip as parsed BVH.
    pub fn bvh(&self, name: &str) -> Result<Arc<BvhFile>, LibraryError> {
        if let ClipData::Memory(f) = self {
            return Ok(f.clone());
        }
        let bytes = self.stored_bytes(name)?.unwrap_or_default();
        let text = String::from_utf8_lossy(&bytes);
        bvh::parse(&text)
            .map(Arc::new)
            .map_err(|e| LibraryError::new(format!("the clip `{name}`: {e}")))
    }

    /// The frames `range` picks by the clip's frame time (first, last; those
    /// it has) as parsed BVH, and the first: only their rows are parsed, not
    /// the whole take.
    fn rows(
        &self,
        name: &str,
        range: impl Fn(f64) -> (usize, usize),
    ) -> Result<(BvhFile, usize), LibraryError> {
        let bad = |e: String| LibraryError::new(format!("the clip `{name}`: {e}"));
        if let ClipData::Memory(f) = self {
            let (first, last) = range(f.frame_time);
            let nch = f.skeleton.channel_count();
            let end = (last + 1).min(f.frame_count());
            let begin = first.min(end);
            let values = f.values[begin * nch..end * nch].to_vec();
            return Ok((
                BvhFile {
                    skeleton: f.skeleton.clone(),
                    frame_time: f.frame_time,
                    values,
                },
                begin,
            ));
        }
        let bytes = self.stored_bytes(name)?.unwrap_or_default();
        let text = String::from_utf8_lossy(&bytes);
        let parse = |first, last| {
            let some =
                rows_of(&text, first, last).ok_or_else(|| bad("no MOTION section".into()))?;
            bvh::parse(&some).map_err(|e| bad(e.to_string()))
        };
        // the header and one row give the frame time
        let (first, last) = range(parse(0, 0)?.frame_time);
        Ok((parse(first, last)?, first))
    }
}

/// A BVH text's header (the hierarchy, `MOTION`, and the `Frames:` and
/// `Frame Time:` lines, by the reader's rule: the two non-empty lines after
/// `MOTION`, or the first that names the time) and its frame rows [first,
/// last] (blank lines skipped, as the reader skips them); `None` without a
/// `MOTION` line. Its `Frames:` still counts the whole take: the reader
/// reads the rows there are.
fn rows_of(text: &str, first: usize, last: usize) -> Option<String> {
    let mut lines = text.split_inclusive('\n');
    let (mut at, mut motion, mut seen) = (0, false, 0);
    let mut header = None;
    for line in lines.by_ref() {
        at += line.len();
        let t = line.trim();
        if !motion {
            motion = t.eq_ignore_ascii_case("MOTION");
            continue;
        }
        if t.is_empty() {
            continue;
        }
        seen += 1;
        if seen == 2 || t.to_ascii_lowercase().contains("time") {
            header = Some(at);
            break;
        }
    }
    let mut out = text[..header?].to_string();
    let row = |out: &mut String, line: &str| {
        if !out.ends_with('\n') {
            out.push('\n');
        }
        out.push_str(line);
    };
    for (k, line) in lines
        .filter(|l| !l.trim_ascii().is_empty())
        .enumerate()
        .take(last.saturating_add(1))
    {
        if k >= first {
            row(&mut out, line);
        }
    }
    Some(out)
}

/// Frames of a clip's own read on either side of a stretch: its samples are
/// joined by a not-a-knot cubic spline, whose ends pull on the curve by
/// (2 − √3)ᵏ at k frames in (3·10⁻⁵ at 8), so a stretch read with this many
/// more frames each side has the whole take's curve inside it.
const STRETCH_MARGIN: usize = 8;

/// Where a clip's contact labels are ([`ClipLabels`], taken when it was indexed).
#[derive(Clone, Debug)]
pub enum LabelData {
    /// None: its body could not be labelled (the reason).
    None(String),
    /// In memory (a library built in this process).
    Memory(Arc<ClipLabels>),
    /// In an `.mxlib`'s clip section, after the clip's text.
    Section(Stored),
}

impl LabelData {
    /// The labels as they are stored (empty for none).
    pub fn stored_bytes(&self, name: &str) -> Result<Vec<u8>, LibraryError> {
        match self {
            LabelData::None(_) => Ok(vec![]),
            LabelData::Memory(l) => Ok(l.to_bytes()),
            LabelData::Section(s) => s.read(name, "contact labels"),
        }
    }
}

/// One indexed clip: its name, where its frames are, and where its features
/// sit in the index.
#[derive(Clone, Debug)]
pub struct LibClip {
    pub name: String,
    pub metres_per_unit: f64,
    pub data: ClipData,
    /// The file it was read from, as it was then (the stale check of a
    /// saved index), if any.
    pub source: Option<Source>,
    pub keys: KeyJoints,
    /// Time (s) of grid frame 0 (the clip's first frame).
    pub start: f64,
    /// Grid frames.
    pub frames: usize,
    /// Index of its frame 0 in the library's feature arrays.
    pub offset: usize,
    /// Its contact labels.
    pub labels: LabelData,
}

impl LibClip {
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The clip as a motion (radians, metres), for SP's example: read from
    /// where it is kept.
    pub fn motion(&self) -> Result<Clip, LibraryError> {
        let file = self.data.bvh(&self.name)?;
        mocap::from_bvh(&file, Units::MetresPerUnit(self.metres_per_unit))
            .map_err(|e| LibraryError::new(format!("clip `{}`: {e}", self.name)))
    }

    /// The clip over clip times [from, to] (s) and a few frames more either
    /// side ([`STRETCH_MARGIN`]), as a motion on the clip's own clock (radians,
    /// metres): what SP's example reads of it. Only those frames are parsed,
    /// so a stretch of a long take costs what a stretch of a short one does.
    pub fn stretch(&self, from: f64, to: f64) -> Result<Clip, LibraryError> {
        let bad = |e: String| LibraryError::new(format!("clip `{}`: {e}", self.name));
        if !(from.is_finite() && to.is_finite() && to >= from) {
            return Err(bad(format!("no stretch [{from}, {to}] s")));
        }
        let range = |dt: f64| {
            // (a frame time that is no number: every row, as a whole read)
            let frame = |t: f64| ((t - self.start) / dt).max(0.0);
            let first = (frame(from).floor() as usize).saturating_sub(STRETCH_MARGIN);
            let last = (frame(to).ceil() as usize).saturating_add(STRETCH_MARGIN);
            if dt > 0.0 {
                (first, last)
            } else {
                (0, usize::MAX - 1)
            }
        };
        let (file, first) = self.data.rows(&self.name, range)?;
        let dt = file.frame_time;
        mocap::from_bvh_at(
            &file,
            Units::MetresPerUnit(self.metres_per_unit),
            self.start + first as f64 * dt,
        )
        .map_err(|e| bad(e.to_string()))
    }

    /// Its contact labels, read from where they are kept; `None` when it
    /// has none (a body without foot contact points has them, empty).
    pub fn labels(&self) -> Result<Option<Arc<ClipLabels>>, LibraryError> {
        match &self.labels {
            LabelData::None(_) => Ok(None),
            LabelData::Memory(l) => Ok(Some(l.clone())),
            LabelData::Section(s) => {
                let bytes = s.read(&self.name, "contact labels")?;
                ClipLabels::from_bytes(&bytes).map(|l| Some(Arc::new(l))).ok_or_else(|| {
                    LibraryError::file(
                        &s.file.path,
                        format!(
                            "{}: damaged (the clip `{}`'s contact labels do not read): rebuild it with library(…)",
                            s.file.path.display(),
                            self.name
                        ),
                    )
                })
            }
        }
    }
}
