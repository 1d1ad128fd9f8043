//! The output folder:
//!
//! ```text
//! OUT_DIR/shards/<i>-of-<n>/library.json        the library and settings (checked on rerun and merge)
//! OUT_DIR/shards/<i>-of-<n>/pairs/<a>__<b>.json  one record per finished pair, written last
//! OUT_DIR/shards/<i>-of-<n>/transitions/*.bvh    the pair's transitions, written before its record
//! OUT_DIR/shards/<i>-of-<n>/report.json          what the shard did (errors included)
//! OUT_DIR/graph.json, OUT_DIR/transitions/*.bvh  the merged graph
//! OUT_DIR/report.json                            what failed, over every shard
//! ```
//!
//! Every file is written atomically (temporary file, then rename), so a
//! killed shard leaves whole files or none; a pair's record is its "done"
//! mark, so a rerun redoes exactly the pairs without one. Two shards given
//! the same share write the same bytes to the same names, so whichever
//! rename lands last changes nothing.

use super::GraphError;
use super::library::ClipFailure;
use super::model::{FORMAT, Graph, LibraryInfo, PairRecord, PairStatus};
use super::shard::Shard;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

pub fn shard_dir(out: &Path, shard: &Shard) -> PathBuf {
    out.join("shards").join(shard.dir_name())
}

/// The record file of a pair (names are file stems, so `__` joins them unambiguously enough
/// for one folder; a clash would be caught by the record's own a and b).
pub fn pair_file(a: &str, b: &str) -> String {
    format!("{a}__{b}.json")
}

pub fn transition_file(a: &str, b: &str, k: usize) -> String {
    format!("{a}__{b}__{k}.bvh")
}

fn io_err(what: &str, p: &Path, e: impl std::fmt::Display) -> GraphError {
    GraphError::new(format!("{what} {}: {e}", p.display()))
}

pub fn write(path: &Path, bytes: &[u8]) -> Result<(), GraphError> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(|e| io_err("cannot create", dir, e))?;
    }
    crate::atomic_file::write(path, bytes).map_err(|e| io_err("cannot write", path, e))
}

pub fn to_json<T: Serialize>(v: &T) -> Vec<u8> {
    let mut s = serde_json::to_string_pretty(v).expect("plain data serialises");
    s.push('\n');
    s.into_bytes()
}

fn read_json<T: for<'de> Deserialize<'de>>(path: &Path) -> Result<T, GraphError> {
    let text = std::fs::read_to_string(path).map_err(|e| io_err("cannot read", path, e))?;
    serde_json::from_str(&text).map_err(|e| io_err("cannot parse", path, e))
}

/// Removes temporary files a killed writer left in `dir` (and its subfolders):
/// `.<name>.<pid>.<n>.tmp` whose process is gone, or every one with `all`
/// (when no writer can be running, as in a merge).
pub fn remove_stale_temporaries(dir: &Path, all: bool) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            remove_stale_temporaries(&p, all);
            continue;
        }
        let name = e.file_name().to_string_lossy().into_owned();
        if !(name.starts_with('.') && name.ends_with(".tmp")) {
            continue;
        }
        let pid = name.rsplit('.').nth(2).and_then(|s| s.parse::<u32>().ok());
        let gone = pid.is_some_and(|pid| !Path::new(&format!("/proc/{pid}")).exists());
        if all || gone {
            let _ = std::fs::remove_file(&p);
        }
    }
}

/// Writes `library.json` of a shard, or checks that the one there matches.
pub fn claim(dir: &Path, info: &LibraryInfo) -> Result<(), GraphError> {
    let path = dir.join("library.json");
    if path.exists() {
        let old: LibraryInfo = read_json(&path)?;
        if &old != info {
            return Err(GraphError::new(format!(
                "{} was built from other clips or settings ({}); use a new output folder or the same options",
                dir.display(),
                describe_difference(&old, info)
            )));
        }
        return Ok(());
    }
    write(&path, &to_json(info))
}

fn describe_difference(a: &LibraryInfo, b: &LibraryInfo) -> String {
    if a.clips_dir != b.clips_dir {
        format!("clips from {} there, {} now", a.clips_dir, b.clips_dir)
    } else if a.clips != b.clips {
        "the clip list differs".into()
    } else if a.settings != b.settings {
        settings_difference(&a.settings, &b.settings)
    } else {
        "the frame time differs".into()
    }
}

/// The settings that differ, one phrase each (`window 9 there, 11 now`), in
/// words rather than as a Rust struct.
fn settings_difference(a: &super::settings::Settings, b: &super::settings::Settings) -> String {
    let fields = |s| match serde_json::to_value(s) {
        Ok(serde_json::Value::Object(m)) => m,
        _ => serde_json::Map::new(),
    };
    let (fa, fb) = (fields(a), fields(b));
    let show = |v: Option<&serde_json::Value>| match v {
        None | Some(serde_json::Value::Null) => "the default".to_string(),
        Some(v) => v.to_string(),
    };
    let parts: Vec<String> = fa
        .iter()
        .filter(|(k, v)| fb.get(*k) != Some(*v))
        .map(|(k, v)| format!("{k} {} there, {} now", show(Some(v)), show(fb.get(k))))
        .collect();
    if parts.is_empty() {
        "the settings differ".into()
    } else {
        parts.join("; ")
    }
}

/// The pairs a shard has finished: every record that reads back whole.
pub fn finished(dir: &Path) -> BTreeMap<(String, String), PairRecord> {
    let mut out = BTreeMap::new();
    let Ok(entries) = std::fs::read_dir(dir.join("pairs")) else {
        return out;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.extension().is_some_and(|x| x == "json")
            && let Ok(r) = read_json::<PairRecord>(&p)
        {
            out.insert((r.a.clone(), r.b.clone()), r);
        }
    }
    out
}

/// What a shard did (no timings: two runs of one share write the same report).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShardReport {
    pub shard: String,
    pub pairs: usize,
    pub finished: usize,
    pub transitions: usize,
    pub far: usize,
    pub failed: usize,
    pub clip_failures: Vec<ClipFailure>,
    /// Failed pairs and why.
    pub errors: Vec<super::model::PairFailure>,
}

pub fn shard_report(
    shard: &Shard,
    pairs: usize,
    records: &[&PairRecord],
    clip_failures: &[ClipFailure],
) -> ShardReport {
    ShardReport {
        shard: shard.to_string(),
        pairs,
        finished: records.len(),
        transitions: records.iter().map(|r| r.transitions.len()).sum(),
        far: records
            .iter()
            .filter(|r| r.status == PairStatus::Far)
            .count(),
        failed: records
            .iter()
            .filter(|r| r.status == PairStatus::Failed)
            .count(),
        clip_failures: clip_failures.to_vec(),
        errors: records
            .iter()
            .filter_map(|r| {
                r.error.as_ref().map(|e| super::model::PairFailure {
                    a: r.a.clone(),
                    b: r.b.clone(),
                    error: e.clone(),
                })
            })
            .collect(),
    }
}

/// What a merge made.
pub struct Merged {
    pub graph: Graph,
    pub shards: usize,
}

/// Joins every shard under `out/shards` into `out/graph.json` and
/// `out/transitions/`. Every pair of the library must have a record in some
/// shard (a missing one names its shard); records of one pair in two shards
/// must agree.
pub fn merge(out: &Path) -> Result<Merged, GraphError> {
    let root = out.join("shards");
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(&root)
        .map_err(|e| io_err("no shards to merge in", &root, e))?
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.join("library.json").is_file())
        .collect();
    dirs.sort();
    if dirs.is_empty() {
        return Err(GraphError::new(format!(
            "no shard results in {}: run `mx graph build CLIPS --out {}` (with --shard i/n) first",
            root.display(),
            out.display()
        )));
    }
    let info: LibraryInfo = read_json(&dirs[0].join("library.json"))?;
    if info.format != FORMAT {
        return Err(GraphError::new(format!(
            "{} is not an {FORMAT} library",
            dirs[0].display()
        )));
    }
    let mut records: BTreeMap<(String, String), (PairRecord, PathBuf)> = BTreeMap::new();
    for d in &dirs {
        let other: LibraryInfo = read_json(&d.join("library.json"))?;
        if other != info {
            return Err(GraphError::new(format!(
                "shards {} and {} were built from different clips or settings ({})",
                dirs[0].display(),
                d.display(),
                describe_difference(&info, &other)
            )));
        }
        remove_stale_temporaries(d, true);
        for (k, r) in finished(d) {
            if let Some((old, from)) = records.get(&k) {
                if old != &r {
                    return Err(GraphError::new(format!(
                        "pair {} → {} differs between {} and {}",
                        k.0,
                        k.1,
                        from.display(),
                        d.display()
                    )));
                }
                continue;
            }
            records.insert(k, (r, d.clone()));
        }
    }
    // every ordered pair of the library, in sorted order
    let names: Vec<&str> = info.clips.iter().map(|c| c.name.as_str()).collect();
    let all = super::shard::pairs(names.len());
    let mut missing = vec![];
    let mut sorted = vec![];
    for (p, &(a, b)) in all.iter().enumerate() {
        match records.get(&(names[a].to_string(), names[b].to_string())) {
            Some((r, d)) => sorted.push((r.clone(), d.clone())),
            None => missing.push((p, names[a], names[b])),
        }
    }
    if !missing.is_empty() {
        let counts: Vec<usize> = dirs
            .iter()
            .filter_map(|d| d.file_name()?.to_str()?.split("-of-").nth(1)?.parse().ok())
            .collect();
        let n = counts.first().copied().unwrap_or(1);
        let (p, a, b) = missing[0];
        return Err(GraphError::new(format!(
            "{} of {} pairs are not finished yet, first {a} → {b} (shard {}/{n}); rerun that shard, then merge",
            missing.len(),
            all.len(),
            p % n
        )));
    }
    // transitions: copied into out/transitions, unchanged files left alone
    let tdir = out.join("transitions");
    for (r, d) in &sorted {
        for t in &r.transitions {
            let src = d.join("transitions").join(&t.file);
            let bytes = std::fs::read(&src).map_err(|e| io_err("cannot read", &src, e))?;
            let dst = tdir.join(&t.file);
            if std::fs::read(&dst).ok().as_deref() != Some(&bytes[..]) {
                write(&dst, &bytes)?;
            }
        }
    }
    let records: Vec<PairRecord> = sorted.into_iter().map(|(r, _)| r).collect();
    let graph = Graph::from_records(info, &records);
    write(&out.join("graph.json"), &to_json(&graph))?;
    #[derive(Serialize)]
    struct Report<'a> {
        shards: Vec<String>,
        clip_failures: &'a [ClipFailure],
        pair_failures: &'a [super::model::PairFailure],
    }
    let report = Report {
        shards: dirs
            .iter()
            .filter_map(|d| d.file_name().map(|n| n.to_string_lossy().into_owned()))
            .collect(),
        clip_failures: &graph.library.clip_failures,
        pair_failures: &graph.pair_failures,
    };
    write(&out.join("report.json"), &to_json(&report))?;
    Ok(Merged {
        shards: dirs.len(),
        graph,
    })
}

/// Reads `out/graph.json`.
pub fn read_graph(out: &Path) -> Result<Graph, GraphError> {
    let p = out.join("graph.json");
    if !p.is_file() {
        return Err(GraphError::new(format!(
            "no graph in {}: run `mx graph build` (and `mx graph merge` after shards) first",
            out.display()
        )));
    }
    read_json(&p)
}

#[cfg(test)]
mod tests {
    use super::super::settings::Settings;
    use super::settings_difference;

    #[test]
    fn a_settings_difference_reads_as_words() {
        let a = Settings::default();
        let b = Settings {
            window: 11,
            coefficients: Some(5),
            ..Settings::default()
        };
        let d = settings_difference(&a, &b);
        assert!(d.contains("window 9 there, 11 now"), "{d}");
        assert!(d.contains("coefficients the default there, 5 now"), "{d}");
        assert!(!d.contains("Settings") && !d.contains("threshold"), "{d}");
    }
}
