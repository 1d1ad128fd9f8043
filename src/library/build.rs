//! Building a library: each clip's raw features on the library's grid
//! (clips in parallel; a clip read from a file is dropped once its features
//! are taken), then the library from them: normalised over every clip, the
//! k-d tree built. The two steps are apart so a large build can run the
//! first in shards and merge ([`super::shards`]), and the leave-one-out
//! benchmark can assemble many libraries from one pass over the clips.

use super::clip::{ClipData, ClipInput, LabelData, LibClip, Source};
use super::features::{self, DIM, GROUPS, KeyJoints};
use super::index::{Library, Settings, Skipped, valid};
use super::labels::ClipLabels;
use super::{LibraryError, clip_name};
use crate::mocap::bvh::{self, Units};
use crate::mocap::{self, Clip};
use rayon::prelude::*;
use std::path::PathBuf;
use std::sync::Arc;

/// A clip described and its raw (unnormalised) before and after vectors on
/// the library's grid, NaN where undefined.
#[derive(Clone, Debug)]
pub struct IndexedClip {
    pub clip: LibClip,
    pub before: Vec<[f32; DIM]>,
    pub after: Vec<[f32; DIM]>,
}

/// Raw (unnormalised) features of a clip's grid, NaN where undefined.
fn clip_features(
    clip: &Clip,
    keys: &KeyJoints,
    settings: &Settings,
) -> (f64, Vec<[f32; DIM]>, Vec<[f32; DIM]>) {
    let (t0, t1) = clip.mu.span().unwrap_or((0.0, 0.0));
    let n = ((t1 - t0) * settings.rate + 1e-6).floor() as usize + 1;
    let times: Vec<f64> = (0..n)
        .map(|k| (t0 + k as f64 / settings.rate).min(t1))
        .collect();
    let pos = features::key_positions(
        &clip.mu,
        &clip.skeleton,
        clip.units.metres_per_unit,
        keys,
        &times,
    );
    let h = settings.horizon();
    let up = mocap::up::skeleton_up(&clip.skeleton, Some(&clip.mu), clip.units.metres_per_unit);
    let nan = [f32::NAN; DIM];
    let side = |dir: i64| -> Vec<[f32; DIM]> {
        (0..n)
            .map(|f| features::frame_features(&pos, f, dir, (h, settings.rate), &up).unwrap_or(nan))
            .collect()
    };
    (t0, side(-1), side(1))
}

/// Indexes one clip: its key joints, raw features and contact labels
/// ([`ClipLabels`]). A clip read from a file keeps only a reference to it;
/// one made in memory is kept. A clip
/// that cannot be matched (no key joints, too short, unreadable) is
/// skipped with the reason.
pub fn index_clip(input: ClipInput, settings: &Settings) -> Result<IndexedClip, Skipped> {
    let skip = |reason: String| Skipped {
        clip: input.name.clone(),
        reason,
    };
    let keys = KeyJoints::find(&input.file.skeleton).map_err(|e| skip(e.to_string()))?;
    let clip = mocap::from_bvh(&input.file, Units::MetresPerUnit(input.metres_per_unit))
        .map_err(|e| skip(e.to_string()))?;
    let (start, before, after) = clip_features(&clip, &keys, settings);
    let min_frames = 2 * settings.horizon() + 2;
    if before.len() < min_frames {
        return Err(skip(format!(
            "too short: {} frames at {} Hz, a clip needs {min_frames} (the features look {} s back and ahead)",
            before.len(),
            settings.rate,
            features::HORIZON
        )));
    }
    let labels = match ClipLabels::of(&clip) {
        Ok(l) => LabelData::Memory(Arc::new(l)),
        Err(e) => LabelData::None(e.to_string()),
    };
    let data = match &input.source {
        Some(s) => ClipData::File(s.clone()),
        None => ClipData::Memory(Arc::new(input.file)),
    };
    Ok(IndexedClip {
        clip: LibClip {
            name: input.name,
            metres_per_unit: input.metres_per_unit,
            data,
            source: input.source,
            keys,
            start,
            frames: before.len(),
            offset: 0,
            labels,
        },
        before,
        after,
    })
}

/// Reads a `.bvh` file as a clip named after it, its stamp taken.
pub fn read_clip(path: &std::path::Path) -> Result<ClipInput, Skipped> {
    let skip = |reason: String| Skipped {
        clip: clip_name(path),
        reason,
    };
    let bytes = std::fs::read(path).map_err(|e| skip(e.to_string()))?;
    let file = bvh::parse(&String::from_utf8_lossy(&bytes)).map_err(|e| skip(e.to_string()))?;
    let units = bvh::resolve_units(Units::Auto, &file.skeleton).map_err(|e| skip(e.to_string()))?;
    Ok(ClipInput {
        name: clip_name(path),
        file,
        metres_per_unit: units.metres_per_unit,
        source: Some(Source::of(path, &bytes)),
    })
}

/// Indexes `.bvh` files in parallel, each read, indexed and let go (only its
/// features stay), in the order given; `done` is called as each finishes.
pub fn index_files(
    paths: &[PathBuf],
    settings: &Settings,
    done: &(dyn Fn() + Sync),
) -> Vec<Result<IndexedClip, Skipped>> {
    paths
        .par_iter()
        .map(|p| {
            let r = read_clip(p).and_then(|c| index_clip(c, settings));
            done();
            r
        })
        .collect()
}

/// Per dimension, the mean over every valid vector, and per group the root
/// mean variance of its dimensions (1 where a group never varies). Sums
/// run clip by clip in order, so a library merged from shards has the
/// same normalisation to the bit as one built whole.
fn normalisation(clips: &[IndexedClip]) -> ([f32; DIM], [f32; DIM]) {
    let all = || {
        clips
            .iter()
            .flat_map(|c| c.before.iter().chain(&c.after))
            .filter(|v| valid(v))
    };
    let n = all().count().max(1) as f64;
    let mut mean = [0f64; DIM];
    for v in all() {
        for d in 0..DIM {
            mean[d] += v[d] as f64 / n;
        }
    }
    let mut var = [0f64; DIM];
    for v in all() {
        for d in 0..DIM {
            var[d] += (v[d] as f64 - mean[d]).powi(2) / n;
        }
    }
    let mut scale = [1f32; DIM];
    for (first, len) in GROUPS {
        let s = (var[first..first + len].iter().sum::<f64>() / len as f64).sqrt();
        scale[first..first + len].fill(if s > 1e-9 { s as f32 } else { 1.0 });
    }
    (mean.map(|m| m as f32), scale)
}

impl Library {
    /// Indexes `clips` (in parallel). Clips that cannot be matched go to
    /// [`Library::skipped`] with the reason, beside those the caller already
    /// skipped; an index with no clip is an error.
    pub fn build(
        clips: Vec<ClipInput>,
        skipped: Vec<Skipped>,
        settings: Settings,
    ) -> Result<Library, LibraryError> {
        settings.check()?;
        if clips.is_empty() && skipped.is_empty() {
            return Err(LibraryError::new(
                "no clips: a library needs at least one clip (a folder of .bvh files or a list of motions)",
            ));
        }
        let done: Vec<_> = clips
            .into_par_iter()
            .map(|c| index_clip(c, &settings))
            .collect();
        Library::from_results(done, skipped, settings)
    }

    /// Indexes `.bvh` files (in parallel, each read and let go), as
    /// `library(folder)` does.
    pub fn build_files(paths: &[PathBuf], settings: Settings) -> Result<Library, LibraryError> {
        settings.check()?;
        let done = index_files(paths, &settings, &|| {});
        Library::from_results(done, vec![], settings)
    }

    /// The library from clips indexed or skipped, in their order.
    pub fn from_results(
        done: Vec<Result<IndexedClip, Skipped>>,
        mut skipped: Vec<Skipped>,
        settings: Settings,
    ) -> Result<Library, LibraryError> {
        let mut kept = vec![];
        for r in done {
            match r {
                Ok(c) => kept.push(c),
                Err(s) => skipped.push(s),
            }
        }
        Library::from_indexed(kept, skipped, settings)
    }

    /// The library from indexed clips: their features normalised over all of
    /// them, in order, and the tree built; an error when there is none.
    pub fn from_indexed(
        clips: Vec<IndexedClip>,
        skipped: Vec<Skipped>,
        settings: Settings,
    ) -> Result<Library, LibraryError> {
        if clips.is_empty() {
            let why: Vec<String> = skipped
                .iter()
                .take(5)
                .map(|s| format!("`{}`: {}", s.clip, s.reason))
                .collect();
            return Err(LibraryError::new(format!(
                "no clip could be indexed ({} skipped): {}",
                skipped.len(),
                why.join("; ")
            )));
        }
        let (mean, scale) = normalisation(&clips);
        let frames: usize = clips.iter().map(|c| c.before.len()).sum();
        let (mut before, mut after) = (Vec::with_capacity(frames), Vec::with_capacity(frames));
        let mut kept = Vec::with_capacity(clips.len());
        let norm =
            |v: &[f32; DIM]| -> [f32; DIM] { std::array::from_fn(|d| (v[d] - mean[d]) / scale[d]) };
        // clip by clip, each clip's raw vectors let go as they are copied
        for c in clips {
            let mut lc = c.clip;
            lc.offset = before.len();
            before.extend(c.before.iter().map(norm));
            after.extend(c.after.iter().map(norm));
            kept.push(lc);
        }
        Ok(Library::assemble(
            settings, kept, skipped, mean, scale, before, after,
        ))
    }
}

/// Every `.bvh` file directly in `dir`, sorted by name, read as clips (in
/// parallel); a file that does not read is skipped with the reason.
pub fn clips_in_folder(
    dir: &std::path::Path,
) -> Result<(Vec<ClipInput>, Vec<Skipped>), LibraryError> {
    let paths = super::bvh_files(dir)?;
    let read: Vec<_> = paths.par_iter().map(|p| read_clip(p)).collect();
    let mut clips = vec![];
    let mut skipped = vec![];
    for r in read {
        match r {
            Ok(c) => clips.push(c),
            Err(s) => skipped.push(s),
        }
    }
    Ok((clips, skipped))
}
