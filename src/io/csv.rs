//! Motion → CSV: header `t,<DOF names in first-definition order>`, one row
//! per time k/R inside the motion's span, empty cells where a DOF is
//! undefined, numbers in shortest round-trip form. A conflict is an error.

use std::fmt::Write as _;
use std::path::Path;

use super::atomic::write_atomic;
use super::{ContentError, FileError};
use crate::cancel::CancelToken;
use crate::fmt_num::Shortest;
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
        // Shortest round-trip text, exponent form for tiny or huge values
        // (1e-300, not 300 zeros), so read(save(m)) gives the same numbers.
        let _ = write!(out, "{}", Shortest(*t));
        for col in &grid.values {
            out.push(',');
            if let Some(v) = col[k] {
                let _ = write!(out, "{}", Shortest(v));
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

/// Read a motion CSV (as written by [`save_csv`]): the `t` column must be a
/// uniform grid; each run of two or more consecutive filled cells of a
/// column becomes an interval of sampled data (C² spline through the
/// values), empty cells stay undefined. Conflicts cannot be represented in
/// CSV, so a loaded motion has none.
pub fn load_csv(path: impl AsRef<Path>) -> Result<Mu, FileError> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).map_err(|source| FileError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    from_csv_str(&text).map_err(|m| FileError::content(path, m))
}

/// Parse motion CSV text; the error says which line and what is wrong.
pub fn from_csv_str(text: &str) -> Result<Mu, ContentError> {
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let (_, header) = lines.next().ok_or_else(|| {
        ContentError::new("the file is empty; a motion CSV starts with a header `t,<DOF names>`")
    })?;
    let names = split_header(header.trim_end_matches('\r'))?;
    if names.first().map(String::as_str) != Some("t") {
        return Err(ContentError::new(
            "the first column must be `t` (time in seconds)",
        ));
    }
    let names = &names[1..];
    let mut times: Vec<f64> = Vec::new();
    let mut cols: Vec<Vec<Option<f64>>> = vec![Vec::new(); names.len()];
    for (ln, line) in lines {
        let cells: Vec<&str> = line.trim_end_matches('\r').split(',').collect();
        if cells.len() != names.len() + 1 {
            return Err(ContentError::at(
                ln + 1,
                format!("{} cells, expected {}", cells.len(), names.len() + 1),
            ));
        }
        let num = |s: &str, what: &str| -> Result<f64, ContentError> {
            match s.trim().parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(v),
                _ => Err(ContentError::at(
                    ln + 1,
                    format!("{what} `{s}` is not a finite number"),
                )),
            }
        };
        times.push(num(cells[0], "time")?);
        for (c, cell) in cells[1..].iter().enumerate() {
            cols[c].push(if cell.trim().is_empty() {
                None
            } else {
                Some(num(cell, &names[c])?)
            });
        }
    }
    mu_from_grid(names, &times, &cols)
}

/// A motion unit from columns sampled on one uniform time grid (to 1e-6 of
/// the step; `None`: undefined there): each run of at least two defined
/// samples becomes a C² sampled curve. Shared by CSV and OpenSim Storage
/// loading and the Python bindings' `Motion.from_array`.
pub fn mu_from_grid(
    names: &[String],
    times: &[f64],
    cols: &[Vec<Option<f64>>],
) -> Result<Mu, ContentError> {
    use crate::motion::{Curve, Dof, Interval};

    if let Some(k) = times.iter().position(|t| !t.is_finite()) {
        return Err(ContentError::new(format!(
            "time {k} is {}, not a finite number",
            times[k]
        )));
    }
    if cols.len() != names.len() || cols.iter().any(|c| c.len() != times.len()) {
        return Err(ContentError::new(format!(
            "{} names and {} columns of {} times do not match",
            names.len(),
            cols.len(),
            times.len()
        )));
    }
    // Uniform time grid (as saved: k/R).
    let dt = match times.len() {
        0 | 1 => 1.0,
        n => (times[n - 1] - times[0]) / (n - 1) as f64,
    };
    if !(dt.is_finite() && dt > 0.0) {
        return Err(ContentError::new("times must increase"));
    }
    for (k, t) in times.iter().enumerate() {
        let want = times[0] + k as f64 * dt;
        if (t - want).abs() > 1e-6 * dt {
            return Err(ContentError::new(format!(
                "row {}: time {t} is off the uniform grid (step {dt}); resample the data first",
                k + 1
            )));
        }
    }
    let mut mu = Mu::new();
    for (c, name) in names.iter().enumerate() {
        if mu.get(name).is_some() {
            return Err(ContentError::new(format!(
                "DOF '{name}' appears twice in the header"
            )));
        }
        let mut intervals = Vec::new();
        let col = &cols[c];
        let mut k = 0;
        while k < col.len() {
            if col[k].is_none() {
                k += 1;
                continue;
            }
            let first = k;
            while k < col.len() && col[k].is_some() {
                k += 1;
            }
            if k - first < 2 {
                return Err(ContentError::new(format!(
                    "DOF '{name}' has a single isolated value at t = {}; an interval needs at least two samples",
                    times[first]
                )));
            }
            let values: Vec<f64> = col[first..k].iter().flatten().copied().collect();
            let curve = Curve::samples(times[first], dt, values)
                .map_err(|e| ContentError::new(format!("DOF '{name}': {e}")))?;
            let iv = Interval::curve(curve, times[first], times[k - 1])
                .map_err(|e| ContentError::new(format!("DOF '{name}': {e}")))?;
            intervals.push(iv);
        }
        mu.insert(name.clone(), Dof { intervals });
    }
    Ok(mu)
}

/// Split a header line, honouring RFC 4180 quotes (`"a,x"`, `""` for a quote).
fn split_header(line: &str) -> Result<Vec<String>, ContentError> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut chars = line.chars().peekable();
    let mut quoted = false;
    while let Some(ch) = chars.next() {
        match (quoted, ch) {
            (false, ',') => out.push(std::mem::take(&mut cur)),
            (false, '"') if cur.is_empty() => quoted = true,
            (true, '"') if chars.peek() == Some(&'"') => {
                chars.next();
                cur.push('"');
            }
            (true, '"') => quoted = false,
            (_, ch) => cur.push(ch),
        }
    }
    if quoted {
        return Err(ContentError::new("the header has an unclosed quote"));
    }
    out.push(cur);
    Ok(out)
}
