//! A large library built in shards, then merged: `mx library build CLIPS
//! --out x.mxlib --shard i/n` on the scheduler `mx graph` uses (`--shard`,
//! Slurm's job-array variables, GNU parallel), then `mx library merge x.mxlib`.
//!
//! File k of the folder's sorted `.bvh` files belongs to shard k mod n
//! ([`crate::shard::Shard`]). A shard indexes its files in parallel (a
//! progress bar on a terminal) and writes their raw features to
//! `x.mxlib.shards/i-of-n.part`, atomically. Merging reads every part,
//! normalises over all clips in file order and writes the `.mxlib`, the
//! clips' texts copied from their files: the same bytes as a build in one
//! shard, which writes the `.mxlib` at once. A part is a small `.mxlib`
//! without clips: the magic `MXPART\n`, the version, a JSON header, the raw
//! before and after vectors, a checksum.

use super::build::{IndexedClip, index_files};
use super::clip::{ClipData, LabelData, LibClip, Source};
use super::features::{DIM, HORIZON, KeyJoints};
use super::file::{self, HashReader, HashWriter, read_vectors, write_vectors};
use super::index::{Library, Settings, Skipped};
use super::labels::ClipLabels;
use super::{Fingerprint, LibraryError, bvh_files, clip_name};
use crate::shard::Shard;
use serde::{Deserialize, Serialize};
use std::io::{BufReader, BufWriter, Read, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

const MAGIC: &[u8; 7] = b"MXPART\n";

/// What one `mx library build` runs.
#[derive(Clone, Debug)]
pub struct BuildOptions {
    /// The folder of `.bvh` clips.
    pub clips: PathBuf,
    /// The `.mxlib` to write (its parts beside it, in `<out>.shards/`).
    pub out: PathBuf,
    pub settings: Settings,
    pub shard: Shard,
    /// Clips indexed at once; `None`: every core.
    pub threads: Option<usize>,
    /// Draw a progress bar (on a terminal).
    pub progress: bool,
}

/// What a build or a merge did.
#[derive(Clone, Debug)]
pub struct BuildSummary {
    /// Clip files of this shard (of the whole folder, for a merge).
    pub files: usize,
    pub indexed: usize,
    pub skipped: Vec<Skipped>,
    /// Grid frames indexed.
    pub frames: usize,
    /// The file written: the `.mxlib`, or this shard's part.
    pub wrote: PathBuf,
    pub seconds: f64,
}

#[derive(Serialize, Deserialize)]
struct PartHeader {
    settings: Settings,
    dim: usize,
    horizon: f64,
    /// (i, n).
    shard: (usize, usize),
    /// The folder, and the count and a fingerprint of its sorted file
    /// names: the parts of one build agree on them.
    folder: PathBuf,
    files: usize,
    listing: u64,
    clips: Vec<PartClip>,
    /// Skipped clips by file index.
    skipped: Vec<(usize, Skipped)>,
    frames: usize,
}

#[derive(Serialize, Deserialize)]
struct PartClip {
    /// Index of its file in the folder's sorted list.
    file: usize,
    name: String,
    metres_per_unit: f64,
    source: Option<Source>,
    keys: KeyJoints,
    start: f64,
    frames: usize,
    /// Its contact labels, or why it has none.
    labels: PartLabels,
}

/// A part's clip's contact labels ([`ClipLabels`]), or why it has none.
#[derive(Serialize, Deserialize)]
enum PartLabels {
    Labelled(ClipLabels),
    Unlabelled { reason: String },
}

/// The folder of `out`'s parts.
pub fn parts_dir(out: &Path) -> PathBuf {
    let mut name = out.file_name().unwrap_or_default().to_os_string();
    name.push(".shards");
    out.with_file_name(name)
}

fn listing(paths: &[PathBuf]) -> u64 {
    let mut f = Fingerprint::default();
    for p in paths {
        f.update(clip_name(p).as_bytes());
        f.update(b"\n");
    }
    f.finish()
}

/// Runs one shard: indexes its files and writes its part, or the `.mxlib`
/// itself when it is the only shard.
pub fn build(o: &BuildOptions) -> Result<BuildSummary, LibraryError> {
    let clock = Instant::now();
    o.settings.check()?;
    let paths = bvh_files(&o.clips)?;
    let folder = std::fs::canonicalize(&o.clips).unwrap_or_else(|_| o.clips.clone());
    let mine: Vec<usize> = (0..paths.len()).filter(|&k| o.shard.owns(k)).collect();
    let my_paths: Vec<PathBuf> = mine.iter().map(|&k| paths[k].clone()).collect();
    let bar = o.shard.progress_bar(o.progress, mine.len(), "clips");
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(t) = o.threads {
        pool = pool.num_threads(t);
    }
    let pool = pool
        .build()
        .map_err(|e| LibraryError::new(format!("cannot start the threads: {e}")))?;
    let done = pool.install(|| index_files(&my_paths, &o.settings, &|| bar.inc(1)));
    bar.finish_and_clear();
    let mut clips = vec![];
    let mut skipped = vec![];
    for (k, r) in mine.iter().zip(done) {
        match r {
            Ok(c) => clips.push((*k, c)),
            Err(s) => skipped.push((*k, s)),
        }
    }
    let indexed = clips.len();
    let frames = clips.iter().map(|(_, c)| c.before.len()).sum();
    let skipped_now: Vec<Skipped> = skipped.iter().map(|(_, s)| s.clone()).collect();
    let wrote = if o.shard.count == 1 {
        let lib = Library::from_indexed(
            clips.into_iter().map(|(_, c)| c).collect(),
            skipped_now.clone(),
            o.settings.clone(),
        )?;
        file::save(&lib, &o.out)?;
        o.out.clone()
    } else {
        let header = PartHeader {
            settings: o.settings.clone(),
            dim: DIM,
            horizon: HORIZON,
            shard: (o.shard.index, o.shard.count),
            folder,
            files: paths.len(),
            listing: listing(&paths),
            clips: clips
                .iter()
                .map(|(k, c)| PartClip {
                    file: *k,
                    name: c.clip.name.clone(),
                    metres_per_unit: c.clip.metres_per_unit,
                    source: c.clip.source.clone(),
                    keys: c.clip.keys.clone(),
                    start: c.clip.start,
                    frames: c.clip.frames,
                    labels: match &c.clip.labels {
                        LabelData::Memory(l) => PartLabels::Labelled((**l).clone()),
                        LabelData::None(why) => PartLabels::Unlabelled {
                            reason: why.clone(),
                        },
                        // an indexed clip's labels are taken in memory
                        LabelData::Section(_) => PartLabels::Unlabelled {
                            reason: "not kept".into(),
                        },
                    },
                })
                .collect(),
            skipped,
            frames,
        };
        let dir = parts_dir(&o.out);
        std::fs::create_dir_all(&dir).map_err(|e| {
            LibraryError::file(&dir, format!("cannot create {}: {e}", dir.display()))
        })?;
        let path = dir.join(format!("{}.part", o.shard.dir_name()));
        let cs: Vec<&IndexedClip> = clips.iter().map(|(_, c)| c).collect();
        write_part(&path, &header, &cs)?;
        path
    };
    Ok(BuildSummary {
        files: mine.len(),
        indexed,
        skipped: skipped_now,
        frames,
        wrote,
        seconds: clock.elapsed().as_secs_f64(),
    })
}

fn write_part(
    path: &Path,
    header: &PartHeader,
    clips: &[&IndexedClip],
) -> Result<(), LibraryError> {
    let json = serde_json::to_vec(header).map_err(|e| LibraryError::new(e.to_string()))?;
    crate::atomic_file::write_with(path, |f| {
        let mut w = BufWriter::with_capacity(1 << 20, f);
        let mut h = HashWriter {
            inner: &mut w,
            hash: Fingerprint::default(),
        };
        h.write_all(MAGIC)?;
        h.write_all(&file::VERSION.to_le_bytes())?;
        h.write_all(&(json.len() as u64).to_le_bytes())?;
        h.write_all(&json)?;
        write_vectors(&mut h, clips.iter().flat_map(|c| c.before.iter()))?;
        write_vectors(&mut h, clips.iter().flat_map(|c| c.after.iter()))?;
        let sum = h.hash.finish();
        w.write_all(&sum.to_le_bytes())?;
        w.flush()
    })
    .map_err(|e| LibraryError::file(path, format!("cannot write {}: {e}", path.display())))
}

/// A part read back: its header and clips.
struct Part {
    header: PartHeader,
    clips: Vec<(usize, IndexedClip)>,
}

fn read_part(path: &Path) -> Result<Part, LibraryError> {
    let damaged = || {
        LibraryError::file(
            path,
            format!(
                "{}: damaged (truncated, or changed since it was written): build that shard again",
                path.display()
            ),
        )
    };
    let f = std::fs::File::open(path)
        .map_err(|e| LibraryError::file(path, format!("cannot read {}: {e}", path.display())))?;
    let mut r = HashReader {
        inner: BufReader::with_capacity(1 << 20, f),
        hash: Fingerprint::default(),
    };
    let mut magic = [0u8; 7];
    r.read_exact(&mut magic).map_err(|_| damaged())?;
    let mut word = [0u8; 4];
    r.read_exact(&mut word).map_err(|_| damaged())?;
    if &magic != MAGIC || u32::from_le_bytes(word) != file::VERSION {
        return Err(LibraryError::file(
            path,
            format!(
                "{}: not a part of this mx's library build (format version {}): build that shard again",
                path.display(),
                file::VERSION
            ),
        ));
    }
    let mut long = [0u8; 8];
    r.read_exact(&mut long).map_err(|_| damaged())?;
    let hlen = u64::from_le_bytes(long);
    let mut json = vec![];
    (&mut r)
        .take(hlen)
        .read_to_end(&mut json)
        .map_err(|_| damaged())?;
    let header: PartHeader = serde_json::from_slice(&json).map_err(|_| damaged())?;
    if header.dim != DIM || header.horizon != HORIZON {
        return Err(damaged());
    }
    let before = read_vectors(&mut r, header.frames).map_err(|_| damaged())?;
    let after = read_vectors(&mut r, header.frames).map_err(|_| damaged())?;
    let sum = r.hash.finish();
    r.read_exact(&mut long).map_err(|_| damaged())?;
    if sum != u64::from_le_bytes(long) || r.inner.read(&mut word).map_err(|_| damaged())? != 0 {
        return Err(damaged());
    }
    let mut clips = vec![];
    let mut at = 0;
    for c in &header.clips {
        let (Some(b), Some(a)) = (before.get(at..at + c.frames), after.get(at..at + c.frames))
        else {
            return Err(damaged());
        };
        at += c.frames;
        let Some(source) = c.source.clone() else {
            return Err(damaged());
        };
        clips.push((
            c.file,
            IndexedClip {
                clip: LibClip {
                    name: c.name.clone(),
                    metres_per_unit: c.metres_per_unit,
                    data: ClipData::File(source.clone()),
                    source: Some(source),
                    keys: c.keys.clone(),
                    start: c.start,
                    frames: c.frames,
                    offset: 0,
                    labels: match &c.labels {
                        PartLabels::Labelled(l) => {
                            LabelData::Memory(std::sync::Arc::new(l.clone()))
                        }
                        PartLabels::Unlabelled { reason } => LabelData::None(reason.clone()),
                    },
                },
                before: b.to_vec(),
                after: a.to_vec(),
            },
        ));
    }
    if at != header.frames {
        return Err(damaged());
    }
    Ok(Part { header, clips })
}

/// Joins the parts in `<out>.shards/` into `out`: refused while a shard is
/// missing, or when the parts come from different builds.
pub fn merge(out: &Path) -> Result<BuildSummary, LibraryError> {
    let clock = Instant::now();
    let dir = parts_dir(out);
    let mut names: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map_err(|e| {
            LibraryError::file(
                &dir,
                format!(
                    "no shard parts at {}: {e} (build them with mx library build … --out {} --shard i/n)",
                    dir.display(),
                    out.display()
                ),
            )
        })?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "part"))
        .collect();
    names.sort();
    if names.is_empty() {
        return Err(LibraryError::file(
            &dir,
            format!(
                "no shard parts in {}: build them with mx library build … --out {} --shard i/n",
                dir.display(),
                out.display()
            ),
        ));
    }
    let mut parts = vec![];
    for p in &names {
        parts.push(read_part(p)?);
    }
    let first = &parts[0].header;
    let n = first.shard.1;
    for p in &parts {
        let h = &p.header;
        if h.shard.1 != n
            || h.settings != first.settings
            || h.folder != first.folder
            || (h.files, h.listing) != (first.files, first.listing)
        {
            return Err(LibraryError::file(
                &dir,
                format!(
                    "the parts in {} come from different builds (shards of {} and {}, or other clips or settings): remove them and build again",
                    dir.display(),
                    n,
                    h.shard.1
                ),
            ));
        }
    }
    let missing: Vec<String> = (0..n)
        .filter(|i| !parts.iter().any(|p| p.header.shard.0 == *i))
        .map(|i| format!("{i}/{n}"))
        .collect();
    if !missing.is_empty() {
        return Err(LibraryError::file(
            &dir,
            format!(
                "shard {} of {} not built yet: run mx library build {} --out {} --shard {}",
                missing.join(", "),
                dir.display(),
                first.folder.display(),
                out.display(),
                missing[0]
            ),
        ));
    }
    let settings = first.settings.clone();
    let files = first.files;
    let mut clips = vec![];
    let mut skipped = vec![];
    for p in parts {
        clips.extend(p.clips);
        skipped.extend(p.header.skipped);
    }
    clips.sort_by_key(|(k, _)| *k);
    skipped.sort_by_key(|(k, _)| *k);
    let skipped: Vec<Skipped> = skipped.into_iter().map(|(_, s)| s).collect();
    let indexed = clips.len();
    let lib = Library::from_indexed(
        clips.into_iter().map(|(_, c)| c).collect(),
        skipped.clone(),
        settings,
    )?;
    file::save(&lib, out)?;
    Ok(BuildSummary {
        files,
        indexed,
        skipped,
        frames: lib.frames(),
        wrote: out.to_path_buf(),
        seconds: clock.elapsed().as_secs_f64(),
    })
}
