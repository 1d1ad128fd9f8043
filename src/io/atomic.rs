//! Atomic file writes with `io`'s error type (the writer itself is
//! [`crate::atomic_file`], shared with `mocap`).

use std::path::Path;

use super::FileError;

/// Write `bytes` to `path` atomically (see [`crate::atomic_file::write`]).
pub fn write_atomic(path: impl AsRef<Path>, bytes: &[u8]) -> Result<(), FileError> {
    let path = path.as_ref();
    crate::atomic_file::write(path, bytes).map_err(|source| FileError::Write {
        path: path.to_path_buf(),
        source,
    })
}

#[cfg(test)]
mod tests {
    // Replacement and clean-up are tested on the writer (crate::atomic_file);
    // here only what this wrapper adds: the error names the file.
    use super::*;

    #[test]
    fn missing_folder_is_an_error_naming_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("no/such/folder/a.txt");
        let e = write_atomic(&p, b"x").unwrap_err();
        assert!(e.to_string().contains("a.txt"), "{e}");
    }
}
