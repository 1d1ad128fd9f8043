//! A clip library: a motion-matching index over every frame of every clip
//! it is given (Clavet 2016; Holden et al. 2020), which finds for a gap the
//! library stretches that arrive and leave as the gap's context does. SP
//! follows the best one ([`crate::spacetime::reference`]); `match` shows them.
//!
//! - `features`: the 24 numbers of a frame, before and after, and the key joints by name;
//! - `index`: building, normalising, the k-d tree (kiddo) and the exact search;
//! - `file`: `.mxlib` files, versioned, fingerprinted, written atomically.
//!
//! Clips of different skeletons live in one library: each clip's features
//! come from its own skeleton, found by joint name; a clip whose key joints
//! cannot be found is listed in [`Library::skipped`] with the reason.

pub mod features;
pub mod file;
pub mod index;

pub use index::{ClipInput, LibClip, Library, Match, Query, Settings, Skipped};

use crate::mocap::bvh::{self, Units};
use std::path::{Path, PathBuf};

/// Why a library could not be built, searched, read or written; each
/// message is a sentence for the user.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LibraryError {
    /// A setting out of its range: `option` as the language spells it
    /// (`rate`, `warps`), so a diagnostic can point at the argument.
    #[error("{message}")]
    InvalidOption {
        option: &'static str,
        message: String,
    },
    /// A skeleton without the joints the features are read from.
    #[error(transparent)]
    Keys(#[from] features::KeyJointsError),
    /// A file or folder that cannot be read or written, or is no library.
    #[error("{message}")]
    File { path: PathBuf, message: String },
    /// The clips, the motion or the gap cannot be indexed or matched.
    #[error("{0}")]
    Invalid(String),
}

impl LibraryError {
    pub fn new(s: impl Into<String>) -> Self {
        LibraryError::Invalid(s.into())
    }

    /// A [`LibraryError::File`] about `path`.
    pub fn file(path: &Path, message: impl Into<String>) -> Self {
        LibraryError::File {
            path: path.to_path_buf(),
            message: message.into(),
        }
    }

    /// The option at fault, when the error is about one.
    pub fn option(&self) -> Option<&'static str> {
        match self {
            LibraryError::InvalidOption { option, .. } => Some(option),
            _ => None,
        }
    }
}

/// FNV-1a, 64 bits: the fingerprint of a clip's bytes and a file's checksum
/// (stable across builds and platforms, unlike std's hasher).
pub fn fingerprint(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// The clip name of a file: its name without the extension.
pub fn clip_name(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string())
}

/// The `.bvh` file at `path` as a clip, its unit detected; a file that
/// does not read is skipped with the reason.
pub fn read_clip(path: &Path) -> Result<ClipInput, Skipped> {
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
        source: Some((path.to_path_buf(), fingerprint(&bytes))),
    })
}

/// Every `.bvh` file directly in `dir`, sorted by name, as clips; a file
/// that does not read is skipped with the reason.
pub fn clips_in_folder(dir: &Path) -> Result<(Vec<ClipInput>, Vec<Skipped>), LibraryError> {
    let entries = std::fs::read_dir(dir).map_err(|e| {
        LibraryError::file(
            dir,
            format!("cannot read the clip folder {}: {e}", dir.display()),
        )
    })?;
    let mut paths: Vec<_> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file() && p.extension().is_some_and(|x| x.eq_ignore_ascii_case("bvh")))
        .collect();
    paths.sort();
    if paths.is_empty() {
        return Err(LibraryError::file(
            dir,
            format!(
                "no .bvh clips in {}: a library needs at least one clip",
                dir.display()
            ),
        ));
    }
    let mut clips = vec![];
    let mut skipped = vec![];
    for p in paths {
        match read_clip(&p) {
            Ok(c) => clips.push(c),
            Err(s) => skipped.push(s),
        }
    }
    Ok((clips, skipped))
}
