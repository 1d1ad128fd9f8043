//! Leave-one-out clip libraries for the in-betweening benchmark: a window of
//! a clip is filled from a library of every other clip of its folder, never
//! from its own file, so the library cannot hand back the frames that were
//! cut (the held-out protocol the literature reports).
//!
//! The folder is read once; each file's library is built the first time one
//! of its windows asks for it and kept for the rest (every gap length, root
//! setting and method of that file shares it).

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
    built: Mutex<HashMap<String, Arc<Library>>>,
}

impl std::fmt::Debug for LeaveOneOut {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "LeaveOneOut({} clips)", self.clips.len())
    }
}

impl LeaveOneOut {
    /// Every `.bvh` clip of `dir` (as `library(dir)` reads them).
    pub fn new(dir: &Path, settings: Settings) -> Result<LeaveOneOut, LibraryError> {
        settings.check()?;
        let (clips, skipped) = library::clips_in_folder(dir)?;
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
        if let Some(l) = self.built.lock().expect("library cache").get(clip) {
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
        self.built
            .lock()
            .expect("library cache")
            .insert(clip.to_string(), lib.clone());
        Ok(lib)
    }

    /// SP's `example:` source for a window of `case`: the library without
    /// the case's own file, read through the case's skeleton.
    pub fn source(&self, case: &Case) -> Result<LibrarySource, LibraryError> {
        Ok(LibrarySource {
            library: self.without(&case.name)?,
            skeleton: case.skeleton.clone(),
            metres_per_unit: case.metres_per_unit,
        })
    }
}
