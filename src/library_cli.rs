//! `mx library …`: clip libraries built from the command line, in shards
//! for large folders (the work is `mx::library::shards`).

use clap::{Args, Subcommand};
use mx::library::shards::{self, BuildOptions, BuildSummary};
use mx::library::{Settings, file};
use mx::shard::Shard;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Subcommand)]
pub enum LibraryCommand {
    /// Index a folder of .bvh clips into an .mxlib (one shard of it with --shard).
    Build(BuildArgs),
    /// Join the shards' parts in OUT.shards/ into OUT.
    Merge { out: PathBuf },
    /// Summarise an .mxlib: clips, frames, settings, skipped clips.
    Info { lib: PathBuf },
}

#[derive(Args)]
pub struct BuildArgs {
    /// Folder of .bvh clips (every .bvh file in it a clip, named after the file).
    clips: PathBuf,
    /// The .mxlib to write (shards write their parts to OUT.shards/).
    #[arg(long)]
    out: PathBuf,
    /// This run's share of the clips, i/n (0 <= i < n); default: Slurm's
    /// SLURM_ARRAY_TASK_ID/SLURM_ARRAY_TASK_COUNT, else all clips.
    #[arg(long)]
    shard: Option<String>,
    /// Clips indexed at once (default: every core).
    #[arg(long)]
    threads: Option<usize>,
    /// The grid the clips are sampled on (Hz).
    #[arg(long, default_value_t = Settings::default().rate)]
    rate: f64,
    /// Time warps a stretch may take, comma-separated (clip time per gap time).
    #[arg(long, value_delimiter = ',', default_values_t = Settings::default().warps)]
    warps: Vec<f64>,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
}

fn fail(e: impl std::fmt::Display) -> ExitCode {
    eprintln!("error: {e}");
    ExitCode::from(1)
}

fn report(what: &str, s: &BuildSummary) {
    eprintln!(
        "{what}: {} clip files, {} indexed ({} grid frames), {} skipped → {} in {:.2} s",
        s.files,
        s.indexed,
        s.frames,
        s.skipped.len(),
        s.wrote.display(),
        s.seconds
    );
    for k in &s.skipped {
        eprintln!("warning: clip `{}` skipped: {}", k.clip, k.reason);
    }
}

pub fn run(cmd: LibraryCommand) -> ExitCode {
    match cmd {
        LibraryCommand::Build(a) => {
            let shard = match Shard::from_flag_or_env(a.shard.as_deref(), |k| std::env::var(k).ok())
            {
                Ok(s) => s,
                Err(e) => return fail(e),
            };
            if a.threads == Some(0) {
                return fail("--threads must be at least 1");
            }
            let o = BuildOptions {
                clips: a.clips,
                out: a.out,
                settings: Settings {
                    rate: a.rate,
                    warps: a.warps,
                },
                shard,
                threads: a.threads,
                progress: !a.quiet && std::io::stderr().is_terminal(),
            };
            match shards::build(&o) {
                Ok(s) => {
                    report(&format!("shard {shard}"), &s);
                    ExitCode::SUCCESS
                }
                Err(e) => fail(e),
            }
        }
        LibraryCommand::Merge { out } => match shards::merge(&out) {
            Ok(s) => {
                report("merged", &s);
                ExitCode::SUCCESS
            }
            Err(e) => fail(e),
        },
        LibraryCommand::Info { lib } => match file::load(&lib, None) {
            Ok(l) => {
                println!(
                    "{} clips, {} grid frames at {} Hz, warps {:?}, {} skipped",
                    l.clips.len(),
                    l.frames(),
                    l.settings.rate,
                    l.settings.warps,
                    l.skipped.len()
                );
                for k in &l.skipped {
                    println!("skipped `{}`: {}", k.clip, k.reason);
                }
                ExitCode::SUCCESS
            }
            Err(e) => fail(e),
        },
    }
}
