//! Motion → CSV: header `t,<DOF names in first-definition order>`, one row
//! per time k/R inside the motion's span, empty cells where a DOF is
//! undefined, numbers in shortest round-trip form. A conflict is an error.

use std::fmt::Write as _;
use std::path::Path;

use super::FileError;
use super::atomic::write_atomic;
use crate::cancel::CancelToken;
use crate::motion::{MotionError, Mu, sample_grid};

/// Sample `mu` at `rate` Hz and write it atomically to `path`.
pub fn save_csv(mu: &Mu, path: impl AsRef<Path>, rate: f64) -> Result<(), FileError> {
    save_csv_cancellable(mu, path, rate, None)
}

pub fn save_csv_cancellable(
    mu: &Mu,
    path: impl AsRef<Path>,
    rate: f64,
    cancel: Option<&CancelToken>,
) -> Result<(), FileError> {
    let text = to_csv_string(mu, rate, cancel)?;
    write_atomic(path, text.as_bytes())
}

/// The CSV text (what `save_csv` writes).
pub fn to_csv_string(
    mu: &Mu,
    rate: f64,
    cancel: Option<&CancelToken>,
) -> Result<String, MotionError> {
    let grid = sample_grid(mu, rate, cancel)?;
    let mut out = String::with_capacity(16 * (grid.names.len() + 1) * (grid.times.len() + 1));
    out.push('t');
    for n in &grid.names {
        out.push(',');
        push_field(&mut out, n);
    }
    out.push('\n');
    for (k, t) in grid.times.iter().enumerate() {
        // `{}` on f64 prints the shortest text that reads back to the same number.
        let _ = write!(out, "{t}");
        for col in &grid.values {
            out.push(',');
            if let Some(v) = col[k] {
                let _ = write!(out, "{v}");
            }
        }
        out.push('\n');
    }
    Ok(out)
}

/// RFC 4180 quoting for names holding a comma, quote or line break.
fn push_field(out: &mut String, s: &str) {
    if s.contains([',', '"', '\n', '\r']) {
        out.push('"');
        out.push_str(&s.replace('"', "\"\""));
        out.push('"');
    } else {
        out.push_str(s);
    }
}
