//! `.mxlib` files: a built index kept, so a large library is indexed once.
//!
//! Layout (little-endian): the magic `MXLIB\n`, the format version (u32), a
//! JSON header (u64 length, then the settings, the feature definition, the
//! normalisation, the clips with their sources' fingerprints and the skipped
//! clips), each clip as BVH text (lossless: shortest round-trip numbers),
//! the before and after feature vectors (f32), and an FNV-1a checksum of
//! everything before it (u64). The file is self-contained: the clips SP
//! follows are inside, so it loads where their files are not.
//!
//! `load` refuses, each with its own sentence: a file that is not one, a
//! foreign version, a damaged file (checksum), an index built with other
//! settings than asked for, and a stale one (a source file that still
//! exists but changed since). The k-d tree is rebuilt on load (it is
//! derived data; building it is a small part of building the index).

use super::LibraryError;
use super::features::{DIM, HORIZON, KeyJoints};
use super::fingerprint;
use super::index::{ClipInput, LibClip, Library, Settings, Skipped};
use crate::mocap::bvh;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

const MAGIC: &[u8; 6] = b"MXLIB\n";

/// The `.mxlib` format version this build writes and reads. Bump it when the
/// layout or the feature definition changes.
pub const VERSION: u32 = 1;

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
    source: Option<(PathBuf, u64)>,
    bvh_bytes: usize,
    keys: KeyJoints,
    start: f64,
    frames: usize,
    offset: usize,
}

/// The file's bytes.
pub fn to_bytes(lib: &Library) -> Result<Vec<u8>, LibraryError> {
    let mut texts = vec![];
    let mut clips = vec![];
    for c in &lib.clips {
        let text = bvh::to_string(&c.input.file)
            .map_err(|e| LibraryError::new(format!("clip `{}`: {e}", c.name())))?;
        clips.push(ClipHeader {
            name: c.input.name.clone(),
            metres_per_unit: c.input.metres_per_unit,
            source: c.input.source.clone(),
            bvh_bytes: text.len(),
            keys: c.keys.clone(),
            start: c.start,
            frames: c.frames,
            offset: c.offset,
        });
        texts.push(text);
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
    };
    let json = serde_json::to_vec(&header).map_err(|e| LibraryError::new(e.to_string()))?;
    let mut out = Vec::with_capacity(
        json.len() + texts.iter().map(String::len).sum::<usize>() + lib.frames() * DIM * 8 + 64,
    );
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&VERSION.to_le_bytes());
    out.extend_from_slice(&(json.len() as u64).to_le_bytes());
    out.extend_from_slice(&json);
    for t in &texts {
        out.extend_from_slice(t.as_bytes());
    }
    for v in lib.before.iter().chain(&lib.after) {
        for x in v {
            out.extend_from_slice(&x.to_le_bytes());
        }
    }
    let sum = fingerprint(&out);
    out.extend_from_slice(&sum.to_le_bytes());
    Ok(out)
}

/// Writes `lib` to `path` atomically: a killed or failed save leaves the
/// old file as it was.
pub fn save(lib: &Library, path: &Path) -> Result<(), LibraryError> {
    let bytes = to_bytes(lib)?;
    crate::atomic_file::write(path, &bytes)
        .map_err(|e| LibraryError::file(path, format!("cannot write {}: {e}", path.display())))
}

/// Reads an index; `expect`: the settings the caller asks for (refused
/// when it was built with others).
pub fn load(path: &Path, expect: Option<&Settings>) -> Result<Library, LibraryError> {
    let bytes = std::fs::read(path)
        .map_err(|e| LibraryError::file(path, format!("cannot read {}: {e}", path.display())))?;
    from_bytes(&bytes, expect)
        .map_err(|e| LibraryError::file(path, format!("{}: {e}", path.display())))
}

/// [`load`] on bytes in memory.
pub fn from_bytes(bytes: &[u8], expect: Option<&Settings>) -> Result<Library, LibraryError> {
    let err = |s: String| LibraryError::new(s);
    if !bytes.starts_with(MAGIC) {
        return Err(err(
            "not an mx clip library (.mxlib) file: save one with save(library(…), \"x.mxlib\")"
                .into(),
        ));
    }
    let corrupt = || {
        err("damaged (truncated, or changed since it was written: the checksum does not match): rebuild it with library(…)".into())
    };
    if bytes.len() < 10 + 8 + 8 {
        return Err(corrupt());
    }
    let version = u32::from_le_bytes(bytes[6..10].try_into().unwrap());
    if version != VERSION {
        return Err(err(format!(
            "written in .mxlib format version {version}, and this mx reads version {VERSION}: rebuild it with library(…) and save it again"
        )));
    }
    let (body, tail) = bytes.split_at(bytes.len() - 8);
    if fingerprint(body) != u64::from_le_bytes(tail.try_into().unwrap()) {
        return Err(corrupt());
    }
    let hlen = u64::from_le_bytes(body[10..18].try_into().unwrap()) as usize;
    let json = body
        .get(18..18usize.saturating_add(hlen))
        .ok_or_else(corrupt)?;
    let h: Header = serde_json::from_slice(json).map_err(|_| corrupt())?;
    if h.dim != DIM || h.horizon != HORIZON || h.mean.len() != DIM || h.scale.len() != DIM {
        return Err(err(format!(
            "built with another feature definition ({} numbers, {} s horizon; this mx uses {DIM}, {HORIZON} s): rebuild it",
            h.dim, h.horizon
        )));
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
        if let Some((p, fp)) = &c.source
            && let Ok(now) = std::fs::read(p)
            && fingerprint(&now) != *fp
        {
            return Err(err(format!(
                "stale: the clip `{}` ({}) changed since the index was built: rebuild it with library(…)",
                c.name,
                p.display()
            )));
        }
    }
    let mut at = 18 + hlen;
    let mut clips = vec![];
    let mut offset = 0;
    for c in h.clips {
        let text = body.get(at..at + c.bvh_bytes).ok_or_else(corrupt)?;
        at += c.bvh_bytes;
        let text = std::str::from_utf8(text).map_err(|_| corrupt())?;
        let file = bvh::parse(text).map_err(|_| corrupt())?;
        if c.offset != offset {
            return Err(corrupt());
        }
        offset += c.frames;
        clips.push(LibClip {
            input: ClipInput {
                name: c.name,
                file,
                metres_per_unit: c.metres_per_unit,
                source: c.source,
            },
            keys: c.keys,
            start: c.start,
            frames: c.frames,
            offset: c.offset,
        });
    }
    if offset != h.frames || clips.is_empty() {
        return Err(corrupt());
    }
    let need = 2 * h.frames * DIM * 4;
    let data = body
        .get(at..)
        .filter(|d| d.len() == need)
        .ok_or_else(corrupt)?;
    let mut vecs = data.chunks_exact(DIM * 4).map(|chunk| {
        let mut v = [0f32; DIM];
        for (x, b) in v.iter_mut().zip(chunk.chunks_exact(4)) {
            *x = f32::from_le_bytes(b.try_into().unwrap());
        }
        v
    });
    let before: Vec<[f32; DIM]> = vecs.by_ref().take(h.frames).collect();
    let after: Vec<[f32; DIM]> = vecs.collect();
    let arr = |v: &[f32]| -> [f32; DIM] { v.try_into().unwrap() };
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
