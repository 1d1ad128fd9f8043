//! `mx graph …`: the transition-library commands (the work is `mx::graph`).

use clap::{Args, Subcommand};
use mx::graph::{self, BuildOptions, Settings, Shard};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Subcommand)]
pub enum GraphCommand {
    /// Build a transition library (one shard of it) from a folder of clips of one skeleton.
    Build(BuildArgs),
    /// Join the shards under OUT_DIR/shards into OUT_DIR/graph.json.
    Merge { out: PathBuf },
    /// Summarise a graph: counts, the strongly connected part, edge costs.
    Info { out: PathBuf },
    /// Write a random walk through the graph as one BVH (and optionally the HTML viewer of it).
    Walk {
        out: PathBuf,
        /// Length of the walk.
        #[arg(long, default_value_t = 30.0)]
        seconds: f64,
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// The BVH to write (default OUT_DIR/walk.bvh).
        #[arg(long = "to")]
        to: Option<PathBuf>,
        /// Also write the HTML viewer of the walk here.
        #[arg(long)]
        html: Option<PathBuf>,
        /// Where the clips are, if they moved since the build.
        #[arg(long)]
        clips: Option<PathBuf>,
    },
}

#[derive(Args)]
pub struct BuildArgs {
    /// Folder of .bvh clips (one skeleton, one frame rate).
    clips: PathBuf,
    #[arg(long)]
    out: PathBuf,
    /// This run's share of the pairs, i/n (0 <= i < n); default: Slurm's
    /// SLURM_ARRAY_TASK_ID/SLURM_ARRAY_TASK_COUNT, else all pairs.
    #[arg(long)]
    shard: Option<String>,
    /// Pairs solved at once (default: every core).
    #[arg(long)]
    threads: Option<usize>,
    /// Append one JSON line per finished pair to this file (for schedulers).
    #[arg(long)]
    log: Option<PathBuf>,
    /// Transition points per ordered pair.
    #[arg(long, default_value_t = Settings::default().k)]
    k: usize,
    /// Frames of the point-cloud window (odd).
    #[arg(long, default_value_t = Settings::default().window)]
    window: usize,
    /// Largest RMS point distance (m) of a transition.
    #[arg(long, default_value_t = Settings::default().threshold)]
    threshold: f64,
    /// Gap frames of a perfect match.
    #[arg(long, default_value_t = Settings::default().min_gap)]
    min_gap: usize,
    /// Gap frames at the threshold distance.
    #[arg(long, default_value_t = Settings::default().max_gap)]
    max_gap: usize,
    /// Frames of each clip SP sees beside the gap.
    #[arg(long, default_value_t = Settings::default().context)]
    context: usize,
    /// SP: free B-spline coefficients per DOF (SP's default if absent).
    #[arg(long)]
    coefficients: Option<usize>,
    /// SP: Gauss points per gap.
    #[arg(long)]
    samples: Option<usize>,
    /// SP: iteration limit per gap group.
    #[arg(long)]
    iterations: Option<u64>,
    /// SP: stop when 25 iterations gain less than this fraction.
    #[arg(long)]
    tolerance: Option<f64>,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
}

fn fail(e: impl std::fmt::Display) -> ExitCode {
    eprintln!("error: {e}");
    ExitCode::from(1)
}

pub fn run(cmd: GraphCommand) -> ExitCode {
    match cmd {
        GraphCommand::Build(a) => build(a),
        GraphCommand::Merge { out } => match graph::merge(&out) {
            Ok(m) => {
                eprintln!(
                    "merged {} shard folder(s): {} nodes, {} edges → {}",
                    m.shards,
                    m.graph.nodes.len(),
                    m.graph.edges.len(),
                    out.join("graph.json").display()
                );
                ExitCode::SUCCESS
            }
            Err(e) => fail(e),
        },
        GraphCommand::Info { out } => match graph::read_graph(&out) {
            Ok(g) => {
                print!("{}", graph::info::summary(&g));
                ExitCode::SUCCESS
            }
            Err(e) => fail(e),
        },
        GraphCommand::Walk {
            out,
            seconds,
            seed,
            to,
            html,
            clips,
        } => {
            let g = match graph::read_graph(&out) {
                Ok(g) => g,
                Err(e) => return fail(e),
            };
            let w = match graph::walk::walk(&g, &out, clips.as_deref(), seconds, seed) {
                Ok(w) => w,
                Err(e) => return fail(e),
            };
            let to = to.unwrap_or_else(|| out.join("walk.bvh"));
            if let Err(e) = mx::mocap::bvh::write_file(&w.file, &to) {
                return fail(e);
            }
            eprintln!(
                "walk of {} frames through {} edges ({} transitions) → {}",
                w.file.frame_count(),
                w.edges.len(),
                w.transitions,
                to.display()
            );
            if let Some(h) = html {
                let r = (|| -> Result<(), Box<dyn std::error::Error>> {
                    let clip = mx::mocap::from_bvh(&w.file, mx::mocap::bvh::Units::Auto)?;
                    let (body, _) =
                        mx::mocap::body_of(&clip.skeleton, 70.0, clip.units.metres_per_unit)?;
                    let data = mx::io::viewer::from_motion(&clip.mu, &body, "graph walk", &[])?;
                    Ok(mx::io::viewer::write_html(&data, &h)?)
                })();
                if let Err(e) = r {
                    return fail(e);
                }
                eprintln!("viewer → {}", h.display());
            }
            ExitCode::SUCCESS
        }
    }
}

fn build(a: BuildArgs) -> ExitCode {
    let shard = match Shard::from_flag_or_env(a.shard.as_deref(), |k| std::env::var(k).ok()) {
        Ok(s) => s,
        Err(e) => return fail(e),
    };
    let settings = Settings {
        k: a.k,
        window: a.window,
        threshold: a.threshold,
        min_gap: a.min_gap,
        max_gap: a.max_gap,
        context: a.context,
        coefficients: a.coefficients,
        samples: a.samples,
        iterations: a.iterations,
        tolerance: a.tolerance,
    };
    if a.threads == Some(0) {
        return fail("--threads must be at least 1");
    }
    let o = BuildOptions {
        clips: a.clips,
        out: a.out.clone(),
        settings,
        shard,
        threads: a.threads,
        log: a.log,
        progress: !a.quiet && std::io::stderr().is_terminal(),
    };
    match graph::build(&o) {
        Ok(s) => {
            eprintln!(
                "shard {shard}: {} pairs ({} done before, {} now): {} transitions, {} pairs too far apart, {} failed; \
                 search {:.2} s, SP {:.2} s, wall {:.2} s",
                s.pairs,
                s.already,
                s.done_now,
                s.transitions,
                s.far,
                s.failed,
                s.search_seconds,
                s.sp_seconds,
                s.wall_seconds
            );
            if let Some((n, e)) = s.merged {
                eprintln!(
                    "graph: {n} nodes, {e} edges → {}",
                    a.out.join("graph.json").display()
                );
            }
            if s.failed > 0 || s.clip_failures > 0 {
                eprintln!(
                    "error: {} clip(s) failed to load and {} pair(s) failed; the rest are done. Errors: {}",
                    s.clip_failures,
                    s.failed,
                    mx::graph::store::shard_dir(&a.out, &shard)
                        .join("report.json")
                        .display()
                );
                return ExitCode::from(3);
            }
            ExitCode::SUCCESS
        }
        Err(e) => fail(e),
    }
}
