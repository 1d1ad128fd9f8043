//! Helpers shared by the benchmarks.

use std::path::PathBuf;

/// The folder holding `data/` (reference data, motion capture): `$MX_SHARED`,
/// else `../shared` from the repository root, as the tests find it.
pub fn shared() -> PathBuf {
    std::env::var_os("MX_SHARED")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(env!("CARGO_MANIFEST_DIR"))
                .join("..")
                .join("shared")
        })
}
