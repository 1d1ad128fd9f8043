//! OpenSim Storage files (`.mot`, `.sto`): a header of `key=value` lines (the
//! first line may be the table's name) closed by `endheader`, a line of column
//! labels (`time` first), then one row of numbers per time, tab- or
//! space-separated. Versions 1 (with `nRows`/`nColumns`) and 3 (what OpenSim
//! 4's `STOFileAdapter` writes) are read; files are written in version 1's
//! layout, which STOFileAdapter reads back.
//!
//! `inDegrees=yes` gives rotational coordinates in degrees: they are converted
//! to radians, translations (metres) are not. Which columns are rotational is
//! the body's to say ([`Columns::Body`]); without one, names ending in
//! `_tx`, `_ty`, `_tz` count as translations ([`Columns::ByName`]).

use std::fmt::Write as _;
use std::path::Path;

use super::atomic::write_atomic;
use super::{ContentError, FileError};
use crate::fmt_num::Shortest;
use crate::motion::{MotionError, Mu, sample_grid};

/// A parsed Storage file.
#[derive(Debug, Clone, PartialEq)]
pub struct Storage {
    /// The name line before the `key=value` lines, if any.
    pub name: Option<String>,
    /// `version=` (1 when absent).
    pub version: u32,
    /// `inDegrees=yes`.
    pub in_degrees: bool,
    /// Column labels after `time`.
    pub labels: Vec<String>,
    pub time: Vec<f64>,
    /// `columns[c][k]`: column c at `time[k]`, as written (no unit conversion).
    pub columns: Vec<Vec<f64>>,
}

/// Parses Storage text; errors name the line.
// Long (about 160 lines): one line-by-line pass (header keys, `endheader`, labels,
// rows) whose every error names its line, which a split would have to thread through.
pub fn parse_storage(text: &str) -> Result<Storage, ContentError> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim_end_matches('\r')));
    let mut name = None;
    let mut version = 1;
    let mut in_degrees = false;
    let mut n_rows: Option<usize> = None;
    let mut n_columns: Option<usize> = None;
    let mut ended = false;
    for (ln, line) in lines.by_ref() {
        let l = line.trim();
        if l.eq_ignore_ascii_case("endheader") {
            ended = true;
            break;
        }
        if l.is_empty() {
            continue;
        }
        match l.split_once('=') {
            Some((k, v)) => {
                let (k, v) = (k.trim(), v.trim());
                let count = |v: &str| {
                    v.parse::<usize>().map_err(|_| {
                        ContentError::at(ln, format!("`{k}={v}` is not a whole number"))
                    })
                };
                match k {
                    "version" => {
                        version = v.parse().map_err(|_| {
                            ContentError::at(ln, format!("`version={v}` is not a whole number"))
                        })?
                    }
                    "inDegrees" => {
                        in_degrees = match v.to_ascii_lowercase().as_str() {
                            "yes" | "true" => true,
                            "no" | "false" => false,
                            _ => {
                                return Err(ContentError::at(
                                    ln,
                                    format!("`inDegrees={v}`; expected yes or no"),
                                ));
                            }
                        }
                    }
                    "nRows" => n_rows = Some(count(v)?),
                    "nColumns" => n_columns = Some(count(v)?),
                    _ => {} // DataType, OpenSimVersion, user metadata
                }
            }
            None if ln == 1 => name = Some(l.to_string()),
            None => {
                return Err(ContentError::at(
                    ln,
                    format!("`{l}` in the header is neither `key=value` nor `endheader`"),
                ));
            }
        }
    }
    if !ended {
        return Err(ContentError::new(
            "the header has no `endheader` line: an OpenSim Storage file (.mot/.sto) starts with \
             `key=value` lines (inDegrees=yes, …) closed by `endheader`",
        ));
    }
    if version > 3 {
        return Err(ContentError::new(format!(
            "Storage version {version} is not one mx reads (1 and 3 are)"
        )));
    }
    let split = |l: &str| -> Vec<String> {
        if l.contains('\t') {
            l.split('\t').map(|s| s.trim().to_string()).collect()
        } else {
            l.split_whitespace().map(str::to_string).collect()
        }
    };
    let (label_ln, labels) = loop {
        match lines.next() {
            Some((_, l)) if l.trim().is_empty() => continue,
            Some((ln, l)) => break (ln, split(l.trim_end())),
            None => return Err("no column labels after `endheader`".into()),
        }
    };
    if !labels
        .first()
        .is_some_and(|t| t.eq_ignore_ascii_case("time"))
    {
        return Err(ContentError::at(
            label_ln,
            format!(
                "the first column is `{}`, not `time`",
                labels.first().map_or("", String::as_str)
            ),
        ));
    }
    if let Some(nc) = n_columns
        && nc != labels.len()
    {
        return Err(ContentError::at(
            label_ln,
            format!(
                "{} column labels, but the header says nColumns={nc}",
                labels.len()
            ),
        ));
    }
    let labels: Vec<String> = labels[1..].to_vec();
    for (i, l) in labels.iter().enumerate() {
        if l.is_empty() {
            return Err(ContentError::at(
                label_ln,
                format!("column {} has no label", i + 2),
            ));
        }
        if labels[..i].contains(l) {
            return Err(ContentError::at(
                label_ln,
                format!("column `{l}` appears twice"),
            ));
        }
    }
    let mut time = Vec::new();
    let mut columns = vec![Vec::new(); labels.len()];
    for (ln, line) in lines {
        if line.trim().is_empty() {
            continue;
        }
        let cells: Vec<&str> = line.split_whitespace().collect();
        if cells.len() != labels.len() + 1 {
            return Err(ContentError::at(
                ln,
                format!(
                    "{} numbers, expected {} (time and {} columns)",
                    cells.len(),
                    labels.len() + 1,
                    labels.len()
                ),
            ));
        }
        let mut row = cells.iter().map(|c| {
            c.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| ContentError::at(ln, format!("`{c}` is not a finite number")))
        });
        time.push(row.next().expect("a time cell")?);
        for (c, v) in row.enumerate() {
            columns[c].push(v?);
        }
    }
    if let Some(nr) = n_rows
        && nr != time.len()
    {
        return Err(ContentError::new(format!(
            "{} rows of data, but the header says nRows={nr}",
            time.len()
        )));
    }
    if time.len() < 2 {
        return Err(ContentError::new(format!(
            "{} rows of data; a motion needs at least two",
            time.len()
        )));
    }
    Ok(Storage {
        name,
        version,
        in_degrees,
        labels,
        time,
        columns,
    })
}

/// How columns map to coordinates.
pub enum Columns<'a> {
    /// A body's coordinates: (name, rotational). Every column must name one
    /// (or be an OpenSim state path `/jointset/<joint>/<name>/value`).
    Body(&'a [(String, bool)]),
    /// No body: every column is a DOF, rotational unless its name ends in `_tx`, `_ty`, `_tz`.
    ByName,
}

fn path_coordinate(label: &str) -> Option<&str> {
    let rest = label.strip_suffix("/value")?;
    rest.rsplit('/').next().filter(|s| !s.is_empty())
}

/// The motion in a Storage: one DOF per column, in radians and metres.
/// Returns the motion and notes for the user (how units were decided).
pub fn storage_to_mu(st: &Storage, columns: Columns) -> Result<(Mu, Vec<String>), ContentError> {
    let mut names = Vec::with_capacity(st.labels.len());
    let mut rotational = Vec::with_capacity(st.labels.len());
    let mut notes = Vec::new();
    match columns {
        Columns::Body(coords) => {
            let mut unknown = Vec::new();
            for l in &st.labels {
                let name = coords
                    .iter()
                    .find(|(c, _)| c == l || path_coordinate(l) == Some(c.as_str()));
                match name {
                    Some((c, rot)) => {
                        if names.contains(c) {
                            return Err(ContentError::new(format!(
                                "coordinate `{c}` has two columns"
                            )));
                        }
                        names.push(c.clone());
                        rotational.push(*rot);
                    }
                    None => unknown.push(l.as_str()),
                }
            }
            if !unknown.is_empty() {
                let all: Vec<&str> = coords.iter().map(|c| c.0.as_str()).take(12).collect();
                return Err(ContentError::new(format!(
                    "column(s) {} name no coordinate of the body (its coordinates: {}{}); load without `body:` to read every column",
                    unknown
                        .iter()
                        .map(|u| format!("`{u}`"))
                        .collect::<Vec<_>>()
                        .join(", "),
                    all.join(", "),
                    if coords.len() > 12 { ", …" } else { "" }
                )));
            }
        }
        Columns::ByName => {
            for l in &st.labels {
                names.push(l.clone());
                rotational.push(!(l.ends_with("_tx") || l.ends_with("_ty") || l.ends_with("_tz")));
            }
            if st.in_degrees {
                let tr: Vec<&str> = names
                    .iter()
                    .zip(&rotational)
                    .filter(|(_, r)| !**r)
                    .map(|(n, _)| n.as_str())
                    .collect();
                notes.push(format!(
                    "inDegrees=yes and no `body:`: columns ending in _tx/_ty/_tz ({}) are read as translations in metres, \
                     every other column as an angle in degrees (converted to radians); pass `body:` to decide by the model's coordinates",
                    if tr.is_empty() { "none here".to_string() } else { tr.join(", ") }
                ));
            }
        }
    }
    let cols: Vec<Vec<Option<f64>>> = st
        .columns
        .iter()
        .zip(&rotational)
        .map(|(c, &rot)| {
            let f = if st.in_degrees && rot {
                std::f64::consts::PI / 180.0
            } else {
                1.0
            };
            c.iter().map(|v| Some(v * f)).collect()
        })
        .collect();
    let mu = super::csv::mu_from_grid(&names, &st.time, &cols)?;
    Ok((mu, notes))
}

/// Reads a `.mot`/`.sto` file.
pub fn load_storage(
    path: impl AsRef<Path>,
    columns: Columns,
) -> Result<(Mu, Vec<String>), FileError> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).map_err(|source| FileError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    let st = parse_storage(&text).map_err(|m| FileError::content(path, m))?;
    storage_to_mu(&st, columns).map_err(|m| FileError::content(path, m))
}

/// Storage text of `mu` sampled at `rate` Hz: rotational DOFs (per
/// `rotational(name)`) in degrees, `inDegrees=yes`. Every DOF must be
/// defined at every sample time.
pub fn to_storage_string(
    mu: &Mu,
    rate: f64,
    name: &str,
    rotational: &dyn Fn(&str) -> bool,
) -> Result<String, MotionError> {
    let grid = sample_grid(mu, rate, None)?;
    for (n, col) in grid.names.iter().zip(&grid.values) {
        if let Some(k) = col.iter().position(Option::is_none) {
            return Err(MotionError::Undefined {
                dof: n.clone(),
                t: grid.times[k],
            });
        }
    }
    let mut out = String::new();
    let _ = writeln!(out, "{}", name.replace(['\n', '\r'], " "));
    let _ = writeln!(out, "version=1");
    let _ = writeln!(out, "nRows={}", grid.times.len());
    let _ = writeln!(out, "nColumns={}", grid.names.len() + 1);
    let _ = writeln!(out, "inDegrees=yes");
    let _ = writeln!(out, "endheader");
    out.push_str("time");
    for n in &grid.names {
        out.push('\t');
        out.push_str(n);
    }
    out.push('\n');
    let scale: Vec<f64> = grid
        .names
        .iter()
        .map(|n| {
            if rotational(n) {
                180.0 / std::f64::consts::PI
            } else {
                1.0
            }
        })
        .collect();
    for (k, t) in grid.times.iter().enumerate() {
        let _ = write!(out, "{}", Shortest(*t));
        for (col, s) in grid.values.iter().zip(&scale) {
            let _ = write!(out, "\t{}", Shortest(col[k].unwrap_or(f64::NAN) * s));
        }
        out.push('\n');
    }
    Ok(out)
}

/// Writes `mu` as a Storage file, atomically.
pub fn save_storage(
    mu: &Mu,
    path: impl AsRef<Path>,
    rate: f64,
    rotational: &dyn Fn(&str) -> bool,
) -> Result<(), FileError> {
    let path = path.as_ref();
    let name = path
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("motion");
    let text = to_storage_string(mu, rate, name, rotational)?;
    write_atomic(path, text.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    const V1: &str = "walk\nversion=1\nnRows=3\nnColumns=3\ninDegrees=yes\nendheader\ntime\tknee_angle_r\tpelvis_tx\n0\t10\t0.5\n0.5\t20\t0.6\n1\t30\t0.7\n";

    #[test]
    fn reads_version_1_and_converts_degrees() {
        let st = parse_storage(V1).unwrap();
        assert_eq!(st.version, 1);
        assert!(st.in_degrees);
        assert_eq!(st.name.as_deref(), Some("walk"));
        let (mu, notes) = storage_to_mu(&st, Columns::ByName).unwrap();
        assert_eq!(notes.len(), 1);
        let k = mu.sample_value("knee_angle_r", 0.5).unwrap().unwrap();
        assert!((k - 20f64.to_radians()).abs() < 1e-15);
        assert_eq!(mu.sample_value("pelvis_tx", 1.0).unwrap(), Some(0.7));
    }

    #[test]
    fn body_columns_must_name_coordinates() {
        let st = parse_storage(V1).unwrap();
        let coords = vec![("knee_angle_r".to_string(), true)];
        let e = storage_to_mu(&st, Columns::Body(&coords))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("`pelvis_tx`") && e.contains("name no coordinate"),
            "{e}"
        );
        let coords = vec![
            ("knee_angle_r".to_string(), true),
            ("pelvis_tx".to_string(), false),
        ];
        let (mu, notes) = storage_to_mu(&st, Columns::Body(&coords)).unwrap();
        assert!(notes.is_empty());
        assert_eq!(mu.sample_value("pelvis_tx", 0.5).unwrap(), Some(0.6));
    }

    #[test]
    fn bad_headers_are_clear_errors() {
        let e = parse_storage("version=1\ntime\ta\n0\t1\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("endheader"), "{e}");
        let e = parse_storage("version=1\nendheader\nt\ta\n0\t1\n1\t2\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("not `time`"), "{e}");
        let e = parse_storage("nRows=5\nendheader\ntime\ta\n0\t1\n1\t2\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("nRows=5"), "{e}");
        let e = parse_storage("endheader\ntime\ta\n0\t1\n1\tx\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 4") && e.contains("`x`"), "{e}");
    }

    #[test]
    fn round_trips_through_text() {
        let st = parse_storage(V1).unwrap();
        let (mu, _) = storage_to_mu(&st, Columns::ByName).unwrap();
        let text = to_storage_string(&mu, 2.0, "walk", &|n| n != "pelvis_tx").unwrap();
        let back = parse_storage(&text).unwrap();
        assert_eq!(back.labels, st.labels);
        assert_eq!(back.time, st.time);
        for (a, b) in back.columns.iter().zip(&st.columns) {
            for (x, y) in a.iter().zip(b) {
                assert!((x - y).abs() < 1e-12, "{x} {y}");
            }
        }
    }
}
