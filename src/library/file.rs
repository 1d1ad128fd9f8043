//! `.mxlib` files: a built index kept, so a large library is indexed once.
//!
//! Layout (little-endian): the magic `MXLIB\n` and the format version
//! (u32); a JSON header (u64 length, then the settings, the feature
//! definition, the normalisation, the skipped clips, and per clip its name,
//! key joints, grid and source stamp); the before and after vectors of every
//! grid frame (f32); a checksum of everything before it (u64,
//! [`Fingerprint`]); then the clip section: per clip its BVH text (a file's
//! own bytes, a clip made in memory written as BVH with shortest round-trip
//! numbers) and its contact labels ([`super::labels`], JSON), each deflated
//! ([`super::clip::deflate`]: BVH text to about a third, so the file is
//! smaller than the clips it indexes), back to back; last the clip table
//! (JSON: per clip where its text and labels lie, their sizes inflated and
//! fingerprints), its length (u64) and its checksum (u64). The table comes
//! last so a save streams: a clip's deflated length is known once it is
//! written. The file is self-contained: the clips SP follows are inside, so
//! it loads where their files are not.
//!
//! `load` reads everything but the clip section and keeps the file open: a
//! clip's text and labels are read when a match needs them ([`Stored`]) and
//! checked against their fingerprints in the table, which its checksum
//! covers. Loading 10⁴ clips reads their features, not their gigabytes of BVH.
//!
//! Refused, each with its own sentence: a file that is not one, a foreign
//! version, a damaged file (checksums, length; a clip's text when it is
//! read), an index built with other settings than asked for, and a stale
//! one (a source file that still exists but changed since: its size and
//! modification time tell without reading it, its bytes where they cannot).
//! The k-d tree is rebuilt on load (derived data, a small part of a build).
//! Saves stream through a temporary file renamed over the old one, so a
//! killed or failed save leaves the old file as it was.

use super::clip::{ClipData, LabelData, LibClip, SectionFile, Source, Stored, deflate};
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
/// read whole on load; 2: no contact labels; 3: clips stored as they are,
/// their places in the header.)
pub const VERSION: u32 = 4;

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
}

/// Where a clip's text or labels lie in the clip section (deflated), and
/// what they inflate to.
#[derive(Serialize, Deserialize)]
struct Piece {
    at: u64,
    len: u64,
    size: u64,
    fingerprint: u64,
}

/// A clip's entry in the clip table: its text, and its labels (none: not
/// labelled).
#[derive(Serialize, Deserialize)]
struct TableEntry {
    text: Piece,
    labels: Option<Piece>,
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

/// A clip's text as stored (a clip in memory written as BVH now).
fn text_of(c: &LibClip) -> Result<Vec<u8>, LibraryError> {
    match &c.data {
        ClipData::Memory(f) => Ok(bvh::to_string(f)
            .map_err(|e| LibraryError::new(format!("clip `{}`: {e}", c.name)))?
            .into_bytes()),
        _ => Ok(c.data.stored_bytes(&c.name)?.unwrap_or_default()),
    }
}

/// A clip's labels as stored; `None`: not labelled.
fn labels_of(c: &LibClip) -> Result<Option<Vec<u8>>, LibraryError> {
    match &c.labels {
        LabelData::None(_) => Ok(None),
        _ => c.labels.stored_bytes(&c.name).map(Some),
    }
}

/// Clips deflated at once (in parallel): enough to keep both cores busy,
/// few enough that a save holds a few megabytes, not the library.
const PACK_BATCH: usize = 16;

/// Writes the clip section, then the clip table, its length and checksum.
fn write_clips(lib: &Library, w: &mut impl Write) -> Result<(), LibraryError> {
    use rayon::prelude::*;
    let io_err = |e: io::Error| LibraryError::new(format!("cannot write the library: {e}"));
    let mut table = Vec::with_capacity(lib.clips.len());
    let mut at = 0u64;
    for batch in lib.clips.chunks(PACK_BATCH) {
        let raw: Vec<(Vec<u8>, Option<Vec<u8>>)> = batch
            .iter()
            .map(|c| Ok((text_of(c)?, labels_of(c)?)))
            .collect::<Result<_, LibraryError>>()?;
        let deflated: Vec<_> = raw
            .par_iter()
            .map(|(t, l)| (deflate(t), l.as_ref().map(|l| deflate(l))))
            .collect();
        for ((t, l), (pt, pl)) in raw.iter().zip(deflated) {
            let piece = |b: &[u8], p: &[u8], at: u64| Piece {
                at,
                len: p.len() as u64,
                size: b.len() as u64,
                fingerprint: fingerprint(b),
            };
            let text = piece(t, &pt, at);
            at += text.len;
            w.write_all(&pt).map_err(io_err)?;
            let labels = match (l, pl) {
                (Some(l), Some(pl)) => {
                    let p = piece(l, &pl, at);
                    at += p.len;
                    w.write_all(&pl).map_err(io_err)?;
                    Some(p)
                }
                _ => None,
            };
            table.push(TableEntry { text, labels });
        }
    }
    let json = serde_json::to_vec(&table).map_err(|e| LibraryError::new(e.to_string()))?;
    w.write_all(&json).map_err(io_err)?;
    w.write_all(&(json.len() as u64).to_le_bytes())
        .map_err(io_err)?;
    w.write_all(&fingerprint(&json).to_le_bytes())
        .map_err(io_err)
}

/// Writes `lib` as an `.mxlib` to `w`. A clip whose file changed since it
/// was indexed is an error (stale), as is one that cannot be read.
pub fn write_to(lib: &Library, w: &mut impl Write) -> Result<(), LibraryError> {
    let io_err = |e: io::Error| LibraryError::new(format!("cannot write the library: {e}"));
    let clips = lib
        .clips
        .iter()
        .map(|c| ClipHeader {
            name: c.name.clone(),
            metres_per_unit: c.metres_per_unit,
            source: c.source.clone(),
            keys: c.keys.clone(),
            start: c.start,
            frames: c.frames,
            offset: c.offset,
        })
        .collect();
    let header = Header {
        settings: lib.settings.clone(),
        dim: DIM,
        horizon: HORIZON,
        mean: lib.mean.to_vec(),
        scale: lib.scale.to_vec(),
        clips,
        skipped: lib.skipped.clone(),
        frames: lib.frames(),
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
    write_clips(lib, w)
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
    section_file: &Arc<SectionFile>,
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
    // (a frame count the file cannot hold is damage, not an allocation)
    if section_start.saturating_add(16) > total {
        return Err(corrupt());
    }
    let before = read_vectors(&mut r, h.frames).map_err(|_| corrupt())?;
    let after = read_vectors(&mut r, h.frames).map_err(|_| corrupt())?;
    let sum = r.hash.finish();
    r.read_exact(&mut long).map_err(|_| corrupt())?;
    if sum != u64::from_le_bytes(long) {
        return Err(corrupt());
    }
    // (after the features: the table is read through the same file handle,
    // whose position the reader above shares)
    let (table, section) = read_table(section_file, section_start, total).ok_or_else(corrupt)?;
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
    if table.len() != h.clips.len() {
        return Err(corrupt());
    }
    let stored = |p: &Piece| Stored {
        file: section_file.clone(),
        offset: section_start + p.at,
        len: p.len,
        size: p.size,
        fingerprint: p.fingerprint,
    };
    let mut clips = vec![];
    let (mut offset, mut at) = (0, 0);
    for (c, t) in h.clips.into_iter().zip(table) {
        let labels_len = t.labels.as_ref().map_or(0, |l| l.len);
        let labels_at = t.labels.as_ref().map_or(at + t.text.len, |l| l.at);
        if c.offset != offset || t.text.at != at || labels_at != at + t.text.len {
            return Err(corrupt());
        }
        offset += c.frames;
        at += t.text.len + labels_len;
        clips.push(LibClip {
            name: c.name,
            metres_per_unit: c.metres_per_unit,
            data: ClipData::Section(stored(&t.text)),
            source: c.source,
            keys: c.keys,
            start: c.start,
            frames: c.frames,
            offset: c.offset,
            labels: match &t.labels {
                None => LabelData::None("not labelled when it was built".into()),
                Some(l) => LabelData::Section(stored(l)),
            },
        });
    }
    if offset != h.frames || at != section || clips.is_empty() {
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

/// The clip table at the end of a file of `total` bytes whose clip section
/// starts at `start`, checked against its checksum, and the section's
/// length; `None` when it is cut short or damaged.
fn read_table(file: &SectionFile, start: u64, total: u64) -> Option<(Vec<TableEntry>, u64)> {
    let tail = file.read(total.checked_sub(16)?, 16).ok()?;
    let word = |i: usize| u64::from_le_bytes(tail[8 * i..8 * i + 8].try_into().expect("8 bytes"));
    let (len, sum) = (word(0), word(1));
    let table_at = total.checked_sub(16)?.checked_sub(len)?;
    let section = table_at.checked_sub(start)?;
    let json = file.read(table_at, len).ok()?;
    if fingerprint(&json) != sum {
        return None;
    }
    Some((serde_json::from_slice(&json).ok()?, section))
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
