//! `.mxlib` files: a built index kept, so a large library is indexed once.
//!
//! Layout (little-endian): the magic `MXLIB\n` and the format version
//! (u32); a JSON header (u64 length, then the settings, the feature
//! definition, the normalisation, the skipped clips, and per clip its name,
//! key joints, grid, source stamp and where its BVH text and contact labels
//! lie in the clip section); the before and after vectors of every grid
//! frame (f32); a checksum of everything before it (u64, [`Fingerprint`]);
//! then the clip section: per clip its BVH text (a file's own bytes, a clip
//! made in memory written as BVH with shortest round-trip numbers) and its
//! contact labels ([`super::labels`], JSON), back to back. The
//! file is self-contained: the clips SP follows are inside, so it loads
//! where their files are not.
//!
//! `load` reads everything but the clip section and keeps the file open: a
//! clip's text and labels are read when a match needs them ([`Stored`]) and
//! checked against its fingerprint in the header, which the checksum covers.
//! Loading 10⁴ clips reads their features, not their gigabytes of BVH.
//!
//! Refused, each with its own sentence: a file that is not one, a foreign
//! version, a damaged file (checksum, length; a clip's text when it is
//! read), an index built with other settings than asked for, and a stale
//! one (a source file that still exists but changed since: its size and
//! modification time tell without reading it, its bytes where they cannot).
//! The k-d tree is rebuilt on load (derived data, a small part of a build).
//! Saves stream through a temporary file renamed over the old one, so a
//! killed or failed save leaves the old file as it was.

use super::clip::{ClipData, LabelData, LibClip, SectionFile, Source, Stored};
use super::features::{DIM, HORIZON, KeyJoints};
use super::index::{Library, Settings, Skipped};
use super::{Fingerprint, LibraryError, fingerprint};
use crate::mocap::bvh;
use serde::{Deserialize, Serialize};
use std::fs::File;
use std::io::{self, BufReader, BufWriter, Read, Write};
use std::path::Path;
use std::sync::Arc;

const MAGIC: &[u8; 6] = b"MXLIB\n";

/// The `.mxlib` format version this build writes and reads. Bump it when the
/// layout or the feature definition changes. (1: clips inside the checksum,
/// read whole on load; 2: no contact labels.)
pub const VERSION: u32 = 3;

#[derive(Serialize, Deserialize)]
struct Header {
    settings: Settings,
    dim: usize,
    horizon: f64,
    mean: Vec<f32>,
    scale: Vec<f32>,
    clips: Vec<ClipHeader>,
    skipped: Vec<Skipped>,
    frames: usize,
    /// Bytes of the clip section.
    section: u64,
}

#[derive(Serialize, Deserialize)]
struct ClipHeader {
    name: String,
    metres_per_unit: f64,
    source: Option<Source>,
    keys: KeyJoints,
    start: f64,
    frames: usize,
    offset: usize,
    /// Its BVH text in the clip section: offset, length, fingerprint.
    text: (u64, u64, u64),
    /// Its contact labels right after the text: length (0: none),
    /// fingerprint.
    labels: (u64, u64),
}

/// A writer that fingerprints what passes through it.
pub(super) struct HashWriter<'a, W: Write> {
    pub inner: &'a mut W,
    pub hash: Fingerprint,
}

impl<W: Write> Write for HashWriter<'_, W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = self.inner.write(buf)?;
        self.hash.update(&buf[..n]);
        Ok(n)
    }
    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush()
    }
}

/// A reader that fingerprints what it reads.
pub(super) struct HashReader<R: Read> {
    pub inner: R,
    pub hash: Fingerprint,
}

impl<R: Read> Read for HashReader<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.hash.update(&buf[..n]);
        Ok(n)
    }
}

/// Writes feature vectors as f32, little-endian.
pub(super) fn write_vectors<'a>(
    w: &mut impl Write,
    vs: impl Iterator<Item = &'a [f32; DIM]>,
) -> io::Result<()> {
    let mut buf = Vec::with_capacity(4096 * DIM * 4);
    for v in vs {
        for x in v {
            buf.extend_from_slice(&x.to_le_bytes());
        }
        if buf.len() >= 4096 * DIM * 4 {
            w.write_all(&buf)?;
            buf.clear();
        }
    }
    w.write_all(&buf)
}

/// Reads `n` feature vectors written by [`write_vectors`].
pub(super) fn read_vectors(r: &mut impl Read, n: usize) -> io::Result<Vec<[f32; DIM]>> {
    let mut out = Vec::with_capacity(n);
    let mut buf = vec![0u8; 4096 * DIM * 4];
    let mut left = n;
    while left > 0 {
        let k = left.min(4096);
        let bytes = &mut buf[..k * DIM * 4];
        r.read_exact(bytes)?;
        out.extend(bytes.chunks_exact(DIM * 4).map(|chunk| {
            std::array::from_fn(|d| {
                f32::from_le_bytes(chunk[4 * d..4 * d + 4].try_into().expect("4 bytes"))
            })
        }));
        left -= k;
    }
    Ok(out)
}

/// A clip's text or labels as the file will hold them: made now (a clip in
/// memory, labels taken in this process), else copied from where they are
/// stored when written (their length and fingerprint known).
enum Bytes {
    Made(Vec<u8>),
    Stored,
}

impl Bytes {
    fn made(b: Vec<u8>) -> (Bytes, u64, u64) {
        let (len, fp) = (b.len() as u64, fingerprint(&b));
        (Bytes::Made(b), len, fp)
    }
}

/// A clip's text: (bytes, length, fingerprint).
fn text_of(c: &LibClip) -> Result<(Bytes, u64, u64), LibraryError> {
    Ok(match &c.data {
        ClipData::Memory(f) => Bytes::made(
            bvh::to_string(f)
                .map_err(|e| LibraryError::new(format!("clip `{}`: {e}", c.name)))?
                .into_bytes(),
        ),
        ClipData::File(s) => (Bytes::Stored, s.len, s.fingerprint),
        ClipData::Section(s) => (Bytes::Stored, s.len, s.fingerprint),
    })
}

/// A clip's labels: (bytes, length, fingerprint); length 0: none.
fn labels_of(c: &LibClip) -> (Bytes, u64, u64) {
    match &c.labels {
        LabelData::None(_) => (Bytes::Made(vec![]), 0, 0),
        LabelData::Memory(l) => Bytes::made(l.to_bytes()),
        LabelData::Section(s) => (Bytes::Stored, s.len, s.fingerprint),
    }
}

/// Writes `lib` as an `.mxlib` to `w`. A clip whose file changed since it
/// was indexed is an error (stale), as is one that cannot be read.
pub fn write_to(lib: &Library, w: &mut impl Write) -> Result<(), LibraryError> {
    let io_err = |e: io::Error| LibraryError::new(format!("cannot write the library: {e}"));
    let mut bytes = vec![];
    let mut clips = vec![];
    let mut at = 0u64;
    for c in &lib.clips {
        let (text, len, fp) = text_of(c)?;
        let (labels, llen, lfp) = labels_of(c);
        clips.push(ClipHeader {
            name: c.name.clone(),
            metres_per_unit: c.metres_per_unit,
            source: c.source.clone(),
            keys: c.keys.clone(),
            start: c.start,
            frames: c.frames,
            offset: c.offset,
            text: (at, len, fp),
            labels: (llen, lfp),
        });
        at += len + llen;
        bytes.push((text, labels));
    }
    let header = Header {
        settings: lib.settings.clone(),
        dim: DIM,
        horizon: HORIZON,
        mean: lib.mean.to_vec(),
        scale: lib.scale.to_vec(),
        clips,
        skipped: lib.skipped.clone(),
        frames: lib.frames(),
        section: at,
    };
    let json = serde_json::to_vec(&header).map_err(|e| LibraryError::new(e.to_string()))?;
    let mut h = HashWriter {
        inner: w,
        hash: Fingerprint::default(),
    };
    h.write_all(MAGIC).map_err(io_err)?;
    h.write_all(&VERSION.to_le_bytes()).map_err(io_err)?;
    h.write_all(&(json.len() as u64).to_le_bytes())
        .map_err(io_err)?;
    h.write_all(&json).map_err(io_err)?;
    write_vectors(&mut h, lib.before.iter().chain(&lib.after)).map_err(io_err)?;
    let sum = h.hash.finish();
    w.write_all(&sum.to_le_bytes()).map_err(io_err)?;
    for (c, (text, labels)) in lib.clips.iter().zip(bytes) {
        match text {
            Bytes::Made(b) => w.write_all(&b).map_err(io_err)?,
            Bytes::Stored => {
                let b = c.data.stored_bytes(&c.name)?.unwrap_or_default();
                w.write_all(&b).map_err(io_err)?;
            }
        }
        match labels {
            Bytes::Made(b) => w.write_all(&b).map_err(io_err)?,
            Bytes::Stored => w
                .write_all(&c.labels.stored_bytes(&c.name)?)
                .map_err(io_err)?,
        }
    }
    Ok(())
}

/// The file's bytes (a small library's; [`save`] streams).
pub fn to_bytes(lib: &Library) -> Result<Vec<u8>, LibraryError> {
    let mut out = vec![];
    write_to(lib, &mut out)?;
    Ok(out)
}

/// Writes `lib` to `path` atomically: a killed or failed save leaves the
/// old file as it was. The clips' texts stream from where they are kept.
pub fn save(lib: &Library, path: &Path) -> Result<(), LibraryError> {
    let mut failed = None;
    let r = crate::atomic_file::write_with(path, |f| {
        let mut w = BufWriter::with_capacity(1 << 20, f);
        match write_to(lib, &mut w) {
            Ok(()) => w.flush(),
            Err(e) => {
                failed = Some(e);
                Err(io::Error::other("not written"))
            }
        }
    });
    match (r, failed) {
        (_, Some(e)) => Err(e),
        (Err(e), None) => Err(LibraryError::file(
            path,
            format!("cannot write {}: {e}", path.display()),
        )),
        (Ok(()), None) => Ok(()),
    }
}

/// Reads an index, all but its clips' texts; `expect`: the settings the
/// caller asks for (refused when it was built with others).
pub fn load(path: &Path, expect: Option<&Settings>) -> Result<Library, LibraryError> {
    let cannot =
        |e: io::Error| LibraryError::file(path, format!("cannot read {}: {e}", path.display()));
    let file = File::open(path).map_err(cannot)?;
    let total = file.metadata().map_err(cannot)?.len();
    // a second handle reads the index; the first stays open for the clips
    // (both share one position, and a clip's read seeks before it reads)
    let reader = file.try_clone().map_err(cannot)?;
    let section = Arc::new(SectionFile::new(path, file));
    read(reader, total, &section, expect)
        .map_err(|e| LibraryError::file(path, format!("{}: {e}", path.display())))
}

/// The library of an open file of `total` bytes, its clips' texts left in
/// `section` (the same file).
fn read(
    reader: File,
    total: u64,
    section: &Arc<SectionFile>,
    expect: Option<&Settings>,
) -> Result<Library, LibraryError> {
    let err = |s: String| LibraryError::new(s);
    let corrupt = || {
        err("damaged (truncated, or changed since it was written: the checksum does not match): rebuild it with library(…)".into())
    };
    let mut r = HashReader {
        inner: BufReader::with_capacity(1 << 20, reader),
        hash: Fingerprint::default(),
    };
    let mut magic = [0u8; 6];
    let got = read_up_to(&mut r, &mut magic).map_err(|_| corrupt())?;
    if got < 6 && magic[..got] == MAGIC[..got] {
        return Err(corrupt());
    }
    if &magic != MAGIC {
        return Err(err(
            "not an mx clip library (.mxlib) file: save one with save(library(…), \"x.mxlib\")"
                .into(),
        ));
    }
    let mut word = [0u8; 4];
    r.read_exact(&mut word).map_err(|_| corrupt())?;
    let version = u32::from_le_bytes(word);
    if version != VERSION {
        return Err(err(format!(
            "written in .mxlib format version {version}, and this mx reads version {VERSION}: rebuild it with library(…) and save it again"
        )));
    }
    let mut long = [0u8; 8];
    r.read_exact(&mut long).map_err(|_| corrupt())?;
    let hlen = u64::from_le_bytes(long);
    if hlen > total {
        return Err(corrupt());
    }
    let mut json = vec![0u8; hlen as usize];
    r.read_exact(&mut json).map_err(|_| corrupt())?;
    let h: Header = serde_json::from_slice(&json).map_err(|_| corrupt())?;
    if h.dim != DIM || h.horizon != HORIZON || h.mean.len() != DIM || h.scale.len() != DIM {
        return Err(err(format!(
            "built with another feature definition ({} numbers, {} s horizon; this mx uses {DIM}, {HORIZON} s): rebuild it",
            h.dim, h.horizon
        )));
    }
    let features = 2 * (h.frames as u64).saturating_mul((DIM * 4) as u64);
    let section_start = (18 + hlen + 8).saturating_add(features);
    if section_start.checked_add(h.section) != Some(total) {
        return Err(corrupt());
    }
    let before = read_vectors(&mut r, h.frames).map_err(|_| corrupt())?;
    let after = read_vectors(&mut r, h.frames).map_err(|_| corrupt())?;
    let sum = r.hash.finish();
    r.read_exact(&mut long).map_err(|_| corrupt())?;
    if sum != u64::from_le_bytes(long) {
        return Err(corrupt());
    }
    if let Some(want) = expect
        && *want != h.settings
    {
        return Err(err(format!(
            "built with other settings (rate: {}, warps: {:?}) than asked for (rate: {}, warps: {:?}): rebuild it with library(…, rate: …, warps: …) or load it without them",
            h.settings.rate, h.settings.warps, want.rate, want.warps
        )));
    }
    h.settings.check()?;
    for c in &h.clips {
        if let Some(s) = &c.source
            && s.unchanged() == Some(false)
        {
            return Err(err(format!(
                "stale: the clip `{}` ({}) changed since the index was built: rebuild it with library(…)",
                c.name,
                s.path.display()
            )));
        }
    }
    let mut clips = vec![];
    let (mut offset, mut text_at) = (0, 0);
    let stored = |at: u64, len: u64, fingerprint: u64| Stored {
        file: section.clone(),
        offset: section_start + at,
        len,
        fingerprint,
    };
    for c in h.clips {
        let (at, len, fp) = c.text;
        let (llen, lfp) = c.labels;
        if c.offset != offset || at != text_at {
            return Err(corrupt());
        }
        offset += c.frames;
        text_at += len + llen;
        clips.push(LibClip {
            name: c.name,
            metres_per_unit: c.metres_per_unit,
            data: ClipData::Section(stored(at, len, fp)),
            source: c.source,
            keys: c.keys,
            start: c.start,
            frames: c.frames,
            offset: c.offset,
            labels: if llen == 0 {
                LabelData::None("not labelled when it was built".into())
            } else {
                LabelData::Section(stored(at + len, llen, lfp))
            },
        });
    }
    if offset != h.frames || text_at != h.section || clips.is_empty() {
        return Err(corrupt());
    }
    let arr = |v: &[f32]| -> [f32; DIM] { v.try_into().expect("DIM numbers") };
    Ok(Library::assemble(
        h.settings,
        clips,
        h.skipped,
        arr(&h.mean),
        arr(&h.scale),
        before,
        after,
    ))
}

/// Reads until `buf` is full or the input ends; the bytes read.
fn read_up_to(r: &mut impl Read, buf: &mut [u8]) -> io::Result<usize> {
    let mut n = 0;
    while n < buf.len() {
        match r.read(&mut buf[n..])? {
            0 => break,
            k => n += k,
        }
    }
    Ok(n)
}
