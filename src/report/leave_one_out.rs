//! Leave-one-out clip libraries for the in-betweening benchmark: a window of
//! a clip is filled from a library of every other clip of its folder, never
//! from its own file, so the library cannot hand back the frames that were
//! cut (the held-out protocol the literature reports).
//!
//! The folders' clips are indexed once (their raw features); each file's
//! library is assembled from the others' the first time one of its windows
//! asks for it (normalised over them alone, its own tree) and kept for the
//! rest: every gap length, root setting and method of that file, and every
//! clip made from it by a time warp or mirror, share it; windows asking at
//! once wait for one build.

use crate::library::{self, IndexedClip, Library, LibraryError, Settings, Skipped};
use crate::mocap::bvh::Skeleton;
use crate::spacetime::reference::LibrarySource;
use std::collections::HashMap;
use std::path::Path;
use std::sync::{Arc, Mutex};

/// One held-out clip's library once built, behind its own lock.
type Slot = Arc<Mutex<Option<Arc<Library>>>>;

/// The folder's clips, indexed, and the libraries assembled so far, by
/// held-out clip.
pub struct LeaveOneOut {
    indexed: Vec<Result<IndexedClip, Skipped>>,
    settings: Settings,
    /// Per held-out clip, its library once built (its own lock: one build
    /// per clip, other clips' windows go on meanwhile).
    built: Mutex<HashMap<String, Slot>>,
}

impl std::fmt::Debug for LeaveOneOut {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "LeaveOneOut({} clips)", self.indexed.len())
    }
}

fn name(r: &Result<IndexedClip, Skipped>) -> &str {
    match r {
        Ok(c) => &c.clip.name,
        Err(s) => &s.clip,
    }
}

impl LeaveOneOut {
    /// Every `.bvh` clip of `dir` (as `library(dir)` reads them), indexed.
    pub fn new(dir: &Path, settings: Settings) -> Result<LeaveOneOut, LibraryError> {
        LeaveOneOut::of_folders(&[dir], settings)
    }

    /// Every `.bvh` clip of every folder of `dirs` (the held-out runs'
    /// library can be the shared clips while the windows come from elsewhere).
    pub fn of_folders(dirs: &[&Path], settings: Settings) -> Result<LeaveOneOut, LibraryError> {
        settings.check()?;
        let mut paths = vec![];
        for dir in dirs {
            paths.extend(library::bvh_files(dir)?);
        }
        Ok(LeaveOneOut {
            indexed: library::index_files(&paths, &settings, &|| {}),
            settings,
            built: Mutex::new(HashMap::new()),
        })
    }

    /// Clips in the folder (the held-out one included).
    pub fn len(&self) -> usize {
        self.indexed.len()
    }

    pub fn is_empty(&self) -> bool {
        self.indexed.is_empty()
    }

    /// The library of every clip but `clip` (a file's name without its
    /// extension), assembled once.
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
        let others = self
            .indexed
            .iter()
            .filter(|r| name(r) != clip)
            .cloned()
            .collect();
        let lib = Arc::new(Library::from_results(
            others,
            vec![],
            self.settings.clone(),
        )?);
        *slot = Some(lib.clone());
        Ok(lib)
    }

    /// SP's `example:` source for a window of `clip`: the library without
    /// the clip's own file, read through its skeleton.
    pub fn source(
        &self,
        clip: &str,
        skeleton: Arc<Skeleton>,
        metres_per_unit: f64,
    ) -> Result<LibrarySource, LibraryError> {
        Ok(LibrarySource {
            library: self.without(clip)?,
            skeleton,
            metres_per_unit,
        })
    }
}
