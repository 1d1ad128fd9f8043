//! Leave-one-out clip libraries for the in-betweening benchmark: a window of
//! a clip is filled from a library of every other clip of its folder, never
//! from its own file, so the library cannot hand back the frames that were
//! cut (the held-out protocol the literature reports).
//!
//! The folders are read once; each file's library is built the first time
//! one of its windows asks for it and kept for the rest (every gap length,
//! root setting and method of that file, and every clip made from it by a
//! time warp or mirror, share it; windows asking at once wait for one build).

use super::inbetween::Case;
use crate::library::{self, ClipInput, Library, LibraryError, Settings, Skipped};
use crate::spacetime::reference::LibrarySource;
use std::collections::HashMap;
use std::path::Path;
use std::sync::{Arc, Mutex};

/// The folder's clips and the libraries built so far, by held-out clip.
pub struct LeaveOneOut {
    clips: Vec<ClipInput>,
    skipped: Vec<Skipped>,
    settings: Settings,
    /// Per held-out clip, its library once built (its own lock: one build
    /// per clip, other clips' windows go on meanwhile).
    built: Mutex<HashMap<String, Arc<Mutex<Option<Arc<Library>>>>>>,
}

impl std::fmt::Debug for LeaveOneOut {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "LeaveOneOut({} clips)", self.clips.len())
    }
}

impl LeaveOneOut {
    /// Every `.bvh` clip of `dir` (as `library(dir)` reads them).
    pub fn new(dir: &Path, settings: Settings) -> Result<LeaveOneOut, LibraryError> {
        LeaveOneOut::of_folders(&[dir], settings)
    }

    /// Every `.bvh` clip of every folder of `dirs` (the held-out runs'
    /// library can be the shared clips while the windows come from elsewhere).
    pub fn of_folders(dirs: &[&Path], settings: Settings) -> Result<LeaveOneOut, LibraryError> {
        settings.check()?;
        let (mut clips, mut skipped) = (vec![], vec![]);
        for dir in dirs {
            let (c, s) = library::clips_in_folder(dir)?;
            clips.extend(c);
            skipped.extend(s);
        }
        Ok(LeaveOneOut {
            clips,
            skipped,
            settings,
            built: Mutex::new(HashMap::new()),
        })
    }

    /// Clips in the folder (the held-out one included).
    pub fn len(&self) -> usize {
        self.clips.len()
    }

    pub fn is_empty(&self) -> bool {
        self.clips.is_empty()
    }

    /// The library of every clip but `clip` (a file's name without its
    /// extension), built once.
    pub fn without(&self, clip: &str) -> Result<Arc<Library>, LibraryError> {
        let cell = self
            .built
            .lock()
            .expect("library cache")
            .entry(clip.to_string())
            .or_default()
            .clone();
        let mut slot = cell.lock().expect("library slot");
        if let Some(l) = slot.as_ref() {
            return Ok(l.clone());
        }
        let others: Vec<ClipInput> = self
            .clips
            .iter()
            .filter(|c| c.name != clip)
            .cloned()
            .collect();
        let skipped = self
            .skipped
            .iter()
            .filter(|s| s.clip != clip)
            .cloned()
            .collect();
        let lib = Arc::new(Library::build(others, skipped, self.settings.clone())?);
        *slot = Some(lib.clone());
        Ok(lib)
    }

    /// SP's `example:` source for a window of `case`: the library without
    /// the file the case was read or made from, read through its skeleton.
    pub fn source(&self, case: &Case) -> Result<LibrarySource, LibraryError> {
        Ok(LibrarySource {
            library: self.without(&case.source)?,
            skeleton: case.skeleton.clone(),
            metres_per_unit: case.metres_per_unit,
        })
    }
}
