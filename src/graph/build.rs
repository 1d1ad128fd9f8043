//! `mx graph build`: one shard of a transition library. Its pairs run in
//! parallel on a rayon pool of `threads`, one pair per thread at a time; each finished pair writes its
//! transitions, then its record, then a line to the log; a progress bar
//! shows pairs done, transitions per second and the time left (on a
//! terminal only). With one shard the graph is merged at the end.

use super::GraphError;
use super::library::{self, Library};
use super::model::{ClipEntry, FORMAT, LibraryInfo, PairRecord, PairStatus, TransitionRecord};
use super::search;
use super::settings::Settings;
use super::shard::{Shard, pairs};
use super::store;
use super::transition::{self, gap_frames};
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

#[derive(Clone, Debug)]
pub struct BuildOptions {
    pub clips: PathBuf,
    pub out: PathBuf,
    pub settings: Settings,
    pub shard: Shard,
    /// Pairs in parallel; `None`: rayon's default (every core).
    pub threads: Option<usize>,
    /// One JSON line per finished pair, appended.
    pub log: Option<PathBuf>,
    /// Draw the progress bar (it hides itself off a terminal anyway).
    pub progress: bool,
}

/// What a build did.
#[derive(Clone, Debug, Default)]
pub struct BuildSummary {
    pub pairs: usize,
    /// Finished by an earlier run and skipped.
    pub already: usize,
    pub done_now: usize,
    pub transitions: usize,
    pub failed: usize,
    pub far: usize,
    /// Seconds in the transition-point search and in SP, over the pairs done now.
    pub search_seconds: f64,
    pub sp_seconds: f64,
    pub wall_seconds: f64,
    pub clip_failures: usize,
    /// The merged graph's node and edge counts, when this build merged it.
    pub merged: Option<(usize, usize)>,
}

/// A finished pair: its record, the transitions' BVH text, and timings.
struct PairResult {
    record: PairRecord,
    files: Vec<(String, String)>,
    search_seconds: f64,
    sp_seconds: f64,
}

fn run_pair(lib: &Library, a: usize, b: usize, s: &Settings) -> PairResult {
    let (na, nb) = (&lib.names[a], &lib.names[b]);
    let mut record = PairRecord {
        a: na.clone(),
        b: nb.clone(),
        status: PairStatus::Done,
        best_distance: None,
        transitions: vec![],
        error: None,
    };
    let failed_clip = [a, b]
        .into_iter()
        .find_map(|c| lib.failures.iter().find(|f| f.clip == lib.names[c]));
    let (Some(ca), Some(cb), None) = (&lib.clips[a], &lib.clips[b], failed_clip) else {
        let f = failed_clip.expect("a missing clip has a failure");
        record.status = PairStatus::Failed;
        record.error = Some(format!("clip `{}` failed to load: {}", f.clip, f.error));
        return PairResult {
            record,
            files: vec![],
            search_seconds: 0.0,
            sp_seconds: 0.0,
        };
    };
    let clock = Instant::now();
    let found = search::search(&ca.points, &cb.points, s.window, s.k, s.threshold);
    let search_seconds = clock.elapsed().as_secs_f64();
    record.best_distance = found.best.is_finite().then_some(found.best);
    if found.points.is_empty() {
        record.status = PairStatus::Far;
    }
    let clock = Instant::now();
    let mut files = vec![];
    let mut errors = vec![];
    for (k, p) in found.points.iter().enumerate() {
        let gap = gap_frames(s, p.distance);
        match transition::fill(lib, ca, cb, p, gap, s) {
            Ok(t) => {
                let name = store::transition_file(na, nb, k);
                match crate::mocap::bvh::to_string(&t.file) {
                    Ok(text) => files.push((name.clone(), text)),
                    Err(e) => {
                        errors.push(format!("point {k} (a {} → b {}): {e}", p.i, p.j));
                        continue;
                    }
                }
                record.transitions.push(TransitionRecord {
                    i: p.i,
                    j: p.j,
                    distance: p.distance,
                    gap,
                    duration: (gap + 1) as f64 * lib.frame_time,
                    energy: t.energy,
                    align: t.align,
                    file: name,
                });
            }
            Err(e) => errors.push(format!(
                "point {k} (a frame {} → b frame {}): {e}",
                p.i, p.j
            )),
        }
    }
    if !errors.is_empty() {
        record.status = PairStatus::Failed;
        record.error = Some(errors.join("; "));
    }
    PairResult {
        record,
        files,
        search_seconds,
        sp_seconds: clock.elapsed().as_secs_f64(),
    }
}

/// The library's description as every shard records it.
fn library_info(lib: &Library, clips_dir: &Path, s: &Settings) -> LibraryInfo {
    LibraryInfo {
        format: FORMAT.into(),
        clips_dir: clips_dir.to_string_lossy().into_owned(),
        frame_time: lib.frame_time,
        clips: lib
            .names
            .iter()
            .zip(&lib.clips)
            .map(|(n, c)| ClipEntry {
                name: n.clone(),
                frames: c.as_ref().map(|c| c.frames()),
            })
            .collect(),
        settings: s.clone(),
        clip_failures: lib.failures.clone(),
    }
}

fn json_escape(s: &str) -> String {
    serde_json::to_string(s).expect("a string serialises")
}

/// The clip folder, canonical, or why it cannot be one.
fn clip_folder(clips: &Path) -> Result<PathBuf, GraphError> {
    let dir = std::fs::canonicalize(clips).map_err(|e| {
        GraphError::new(format!(
            "cannot open the clip folder {}: {e}",
            clips.display()
        ))
    })?;
    if !dir.is_dir() {
        return Err(GraphError::new(format!(
            "{} is not a folder of clips",
            clips.display()
        )));
    }
    Ok(dir)
}

/// The `--log` file, opened for appending (several shards may share it).
fn open_log(path: &Path) -> Result<std::fs::File, GraphError> {
    std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(path)
        .map_err(|e| GraphError::new(format!("cannot open the log {}: {e}", path.display())))
}

/// Rayon's pool with `--threads` threads (its default without).
fn thread_pool(threads: Option<usize>) -> Result<rayon::ThreadPool, GraphError> {
    let mut b = rayon::ThreadPoolBuilder::new();
    if let Some(t) = threads {
        b = b.num_threads(t);
    }
    b.build().map_err(|e| {
        // the number, not `Some(4)`
        let n = threads.map_or("the default number of".into(), |t| t.to_string());
        GraphError::new(format!("cannot start {n} threads: {e}"))
    })
}

/// One JSON line of the `--log` for a finished pair.
fn log_line(shard: &Shard, r: &PairResult, finished: usize, of: usize) -> String {
    format!(
        "{{\"shard\":\"{}\",\"a\":{},\"b\":{},\"status\":\"{}\",\"transitions\":{},\"search_seconds\":{},\"sp_seconds\":{},\"finished\":{},\"of\":{}{}}}\n",
        shard,
        json_escape(&r.record.a),
        json_escape(&r.record.b),
        match r.record.status {
            PairStatus::Done => "done",
            PairStatus::Far => "far",
            PairStatus::Failed => "failed",
        },
        r.record.transitions.len(),
        crate::fmt_num::format_number(r.search_seconds),
        crate::fmt_num::format_number(r.sp_seconds),
        finished,
        of,
        r.record
            .error
            .as_ref()
            .map(|e| format!(",\"error\":{}", json_escape(e)))
            .unwrap_or_default()
    )
}

/// Pair records in the library's pair order, each pair once.
fn in_pair_order<'a>(
    lib: &Library,
    records: impl Iterator<Item = &'a PairRecord>,
) -> Vec<&'a PairRecord> {
    let mut v: Vec<&PairRecord> = records.collect();
    let order = |r: &PairRecord| {
        let a = lib.names.iter().position(|n| n == &r.a);
        let b = lib.names.iter().position(|n| n == &r.b);
        (a, b)
    };
    v.sort_by_key(|r| order(r));
    v.dedup_by(|x, y| x.a == y.a && x.b == y.b);
    v
}

/// Runs one shard.
pub fn build(o: &BuildOptions) -> Result<BuildSummary, GraphError> {
    let wall = Instant::now();
    o.settings.check()?;
    let clips_dir = clip_folder(&o.clips)?;
    let lib = library::load(&clips_dir)?;
    let dir = store::shard_dir(&o.out, &o.shard);
    std::fs::create_dir_all(&dir)
        .map_err(|e| GraphError::new(format!("cannot create {}: {e}", dir.display())))?;
    store::claim(&dir, &library_info(&lib, &clips_dir, &o.settings))?;
    store::remove_stale_temporaries(&dir, false);
    let all = pairs(lib.names.len());
    let mine: Vec<(usize, usize)> = all
        .iter()
        .enumerate()
        .filter(|(p, _)| o.shard.owns(*p))
        .map(|(_, &ab)| ab)
        .collect();
    let done = store::finished(&dir);
    let todo: Vec<(usize, usize)> = mine
        .iter()
        .copied()
        .filter(|&(a, b)| !done.contains_key(&(lib.names[a].clone(), lib.names[b].clone())))
        .collect();
    let log = o.log.as_deref().map(open_log).transpose()?.map(Mutex::new);
    let bar = o.shard.progress_bar(o.progress, todo.len(), "pairs");
    let transitions_now = AtomicUsize::new(0);
    let finished_now = AtomicUsize::new(0);
    let timings = Mutex::new((0.0f64, 0.0f64));
    let started = Instant::now();
    let pool = thread_pool(o.threads)?;
    // One worker loop per pool thread (`broadcast` pins each to its thread), each taking the
    // next pair: at most --threads pairs at once. (A parallel iterator would not bound them:
    // a worker blocked in SP's own one-thread pool steals further pairs meanwhile.)
    let next = AtomicUsize::new(0);
    let collected: Mutex<Vec<(usize, Result<PairRecord, GraphError>)>> = Mutex::new(vec![]);
    let one_pair = |&(a, b): &(usize, usize)| -> Result<PairRecord, GraphError> {
        let r = run_pair(&lib, a, b, &o.settings);
        for (name, text) in &r.files {
            store::write(&dir.join("transitions").join(name), text.as_bytes())?;
        }
        let file = dir
            .join("pairs")
            .join(store::pair_file(&r.record.a, &r.record.b));
        store::write(&file, &store::to_json(&r.record))?;
        let n = transitions_now.fetch_add(r.record.transitions.len(), Ordering::Relaxed)
            + r.record.transitions.len();
        let k = finished_now.fetch_add(1, Ordering::Relaxed) + 1;
        {
            let mut t = timings.lock().expect("timings lock");
            t.0 += r.search_seconds;
            t.1 += r.sp_seconds;
        }
        let rate = n as f64 / started.elapsed().as_secs_f64().max(1e-9);
        bar.inc(1);
        bar.set_message(format!("{n} transitions, {rate:.2}/s"));
        if let Some(log) = &log {
            let line = log_line(&o.shard, &r, done.len() + k, mine.len());
            // one write per line: appends from several shards do not interleave within it
            let mut f = log.lock().expect("log lock");
            f.write_all(line.as_bytes())
                .map_err(|e| GraphError::new(format!("cannot write the log: {e}")))?;
        }
        Ok(r.record)
    };
    pool.broadcast(|_| {
        loop {
            let k = next.fetch_add(1, Ordering::Relaxed);
            let Some(pair) = todo.get(k) else { break };
            let r = one_pair(pair);
            collected.lock().expect("results lock").push((k, r));
        }
    });
    let mut results = collected.into_inner().expect("results lock");
    results.sort_by_key(|(k, _)| *k);
    let results: Vec<Result<PairRecord, GraphError>> =
        results.into_iter().map(|(_, r)| r).collect();
    bar.finish_and_clear();
    let mut now = vec![];
    for r in results {
        now.push(r?);
    }
    let all_records = in_pair_order(&lib, done.values().chain(now.iter()));
    let report = store::shard_report(&o.shard, mine.len(), &all_records, &lib.failures);
    store::write(&dir.join("report.json"), &store::to_json(&report))?;
    let (search_seconds, sp_seconds) = *timings.lock().expect("timings lock");
    let mut summary = BuildSummary {
        pairs: mine.len(),
        already: done.len(),
        done_now: now.len(),
        transitions: report.transitions,
        failed: report.failed,
        far: report.far,
        search_seconds,
        sp_seconds,
        wall_seconds: 0.0,
        clip_failures: lib.failures.len(),
        merged: None,
    };
    if o.shard.count == 1 {
        let m = store::merge(&o.out)?;
        summary.merged = Some((m.graph.nodes.len(), m.graph.edges.len()));
    }
    summary.wall_seconds = wall.elapsed().as_secs_f64();
    Ok(summary)
}
