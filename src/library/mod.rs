//! A clip library: a motion-matching index over every frame of every clip
//! it is given (Clavet 2016; Holden et al. 2020), which finds for a gap the
//! library stretches that arrive and leave as the gap's context does. SP
//! follows the best one ([`crate::spacetime::reference`]); `match` shows them.
//!
//! - `features`: the 24 numbers of a frame, before and after, and the key joints by name;
//! - `clip`: where an indexed clip's frames are (memory, its file, a section
//!   of an `.mxlib`), read only when a match needs them;
//! - `build`: a clip's raw features, and the library from them (normalised, the tree built);
//! - `index`: the library, the k-d tree (kiddo) and the exact search;
//! - `labels`: a clip's contact labels, taken when it is indexed and kept with it;
//! - `file`: `.mxlib` files, versioned, checksummed, written atomically, clips read lazily;
//! - `shards`: a large build split into shards (`mx library build --shard i/n`) and merged.
//!
//! Clips of different skeletons live in one library: each clip's features
//! come from its own skeleton, found by joint name; a clip whose key joints
//! cannot be found is listed in [`Library::skipped`] with the reason. The
//! index keeps features in memory, not clips: a library of 10⁴ clips takes
//! the memory of its features (about 200 bytes a grid frame).

pub mod build;
pub mod clip;
pub mod features;
pub mod file;
pub mod index;
pub mod labels;
pub mod shards;

pub use build::{IndexedClip, clips_in_folder, index_clip, index_files, read_clip};
pub use clip::{ClipData, ClipInput, LabelData, LibClip, Source};
pub use index::{Library, Match, Query, Settings, Skipped};
pub use labels::ClipLabels;

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

const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
const FNV_PRIME: u64 = 0x0100_0000_01b3;

/// A 64-bit fingerprint of a byte stream, fed in pieces: FNV-1a over
/// little-endian 8-byte words (a byte at a time for the last few), so
/// gigabytes of clips hash at memory speed. Stable across builds and
/// platforms, unlike std's hasher; every change within one word changes
/// the result (each step is a bijection of the state).
#[derive(Clone, Debug)]
pub struct Fingerprint {
    h: u64,
    pending: [u8; 8],
    n: usize,
}

impl Default for Fingerprint {
    fn default() -> Self {
        Fingerprint {
            h: FNV_OFFSET,
            pending: [0; 8],
            n: 0,
        }
    }
}

impl Fingerprint {
    pub fn update(&mut self, mut bytes: &[u8]) {
        if self.n > 0 {
            let take = (8 - self.n).min(bytes.len());
            self.pending[self.n..self.n + take].copy_from_slice(&bytes[..take]);
            self.n += take;
            bytes = &bytes[take..];
            if self.n < 8 {
                return;
            }
            self.word(u64::from_le_bytes(self.pending));
            self.n = 0;
        }
        let mut words = bytes.chunks_exact(8);
        for w in &mut words {
            self.word(u64::from_le_bytes(w.try_into().expect("8 bytes")));
        }
        let rest = words.remainder();
        self.pending[..rest.len()].copy_from_slice(rest);
        self.n = rest.len();
    }

    fn word(&mut self, w: u64) {
        self.h = (self.h ^ w).wrapping_mul(FNV_PRIME);
    }

    pub fn finish(&self) -> u64 {
        let mut h = self.h;
        for &b in &self.pending[..self.n] {
            h = (h ^ b as u64).wrapping_mul(FNV_PRIME);
        }
        h
    }
}

/// The fingerprint of a clip's bytes and a file's checksum ([`Fingerprint`]).
pub fn fingerprint(bytes: &[u8]) -> u64 {
    let mut f = Fingerprint::default();
    f.update(bytes);
    f.finish()
}

/// The clip name of a file: its name without the extension.
pub fn clip_name(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string())
}

/// Every `.bvh` file directly in `dir`, sorted by name; an error when
/// there is none.
pub fn bvh_files(dir: &Path) -> Result<Vec<PathBuf>, LibraryError> {
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
    Ok(paths)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_fingerprint_fed_in_pieces_is_the_whole_ones_and_sees_every_change() {
        let bytes: Vec<u8> = (0..1000u32).map(|i| (i * 7 + i / 13) as u8).collect();
        let whole = fingerprint(&bytes);
        for cuts in [[1, 2], [7, 9], [8, 16], [13, 500], [999, 1000]] {
            let mut f = Fingerprint::default();
            f.update(&bytes[..cuts[0]]);
            f.update(&bytes[cuts[0]..cuts[1]]);
            f.update(&bytes[cuts[1]..]);
            assert_eq!(f.finish(), whole, "{cuts:?}");
        }
        for at in [0, 5, 8, 501, 996, 999] {
            for bit in [0, 3, 7] {
                let mut b = bytes.clone();
                b[at] ^= 1 << bit;
                assert_ne!(fingerprint(&b), whole, "byte {at} bit {bit}");
            }
        }
        assert_ne!(fingerprint(&bytes[..999]), whole);
    }
}
