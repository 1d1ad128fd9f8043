//! The `mx` command line: `mx run FILE`, `mx check FILE`, `mx eval 'EXPR'`,
//! `mx help [TOPIC|NAME]` (`--markdown`: the page `docs/reference.md`),
//! and `mx` alone for the REPL. stdout carries only `print` output (and the
//! value printed by `eval`); diagnostics go to stderr. Exit status: 0 on
//! success, 1 on a user error, 2 on a usage error (clap).

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

mod graph_cli;
mod library_cli;
mod repl;

#[derive(Parser)]
#[command(
    name = "mx",
    version,
    about = "The mx motion expression language",
    disable_help_subcommand = true
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Limit each evaluation to this many steps (catches runaway scripts).
    #[arg(long, global = true)]
    steps: Option<u64>,
    /// Confine load/save to files under this folder.
    #[arg(long, global = true)]
    root: Option<PathBuf>,
}

#[derive(Subcommand)]
enum Command {
    /// Run a script.
    Run { file: PathBuf },
    /// Parse a script and resolve its names without running it.
    Check { file: PathBuf },
    /// Evaluate an expression (or statements) and print the value.
    Eval { source: String },
    /// Start the interactive REPL (the default).
    Repl,
    /// Print the built-ins' help: all by topic, one topic, or one name (the REPL's `:help`).
    Help {
        /// A topic (language, motion, spacetime, joints, dynamics, files), `formats` or a name.
        topic: Option<String>,
        /// Print the whole reference page as Markdown (`mx help --markdown > docs/reference.md`).
        #[arg(long)]
        markdown: bool,
    },
    /// Regenerate the accuracy report (docs/accuracy.md and its figures).
    #[cfg(feature = "report")]
    Report {
        /// Fewer points per curve, same code path (CI).
        #[arg(long)]
        smoke: bool,
        #[arg(long, default_value = "docs")]
        out: PathBuf,
    },
    /// Transition libraries (motion graphs): build, merge, info, walk.
    #[command(subcommand)]
    Graph(Box<graph_cli::GraphCommand>),
    /// Clip libraries (.mxlib) from the command line: build (in shards), merge, info.
    #[command(subcommand)]
    Library(Box<library_cli::LibraryCommand>),
}

/// Let a closed stdout end mx as it ends other Unix tools: killed by SIGPIPE
/// (status 141 in a shell), silently. Rust ignores SIGPIPE, which turns every
/// write to a closed pipe into an error, and `print!` panics on that error
/// with a backtrace (`mx eval … | head -c 20`); the REPL, `print`, `mx help`
/// and `mx report` all write to stdout, so one setting covers them all.
#[cfg(unix)]
fn quiet_on_closed_stdout() {
    // SAFETY: called first thing in `main`, before any thread is started;
    // `signal` with `SIG_DFL` installs no handler of ours, so no code runs
    // in signal context.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

#[cfg(not(unix))]
fn quiet_on_closed_stdout() {}

fn main() -> ExitCode {
    quiet_on_closed_stdout();
    let cli = Cli::parse();
    let command = cli.command.unwrap_or(Command::Repl);
    // the graph and library commands need no interpreter
    let command = match command {
        Command::Graph(g) => return graph_cli::run(*g),
        Command::Library(l) => return library_cli::run(*l),
        c => c,
    };
    let mut mx = mx::Interpreter::new();
    mx.set_step_budget(cli.steps);
    mx.set_file_root(cli.root.clone());
    let color = std::io::stderr().is_terminal() && std::env::var_os("NO_COLOR").is_none();
    let report = |d: mx::lang::Diagnostic| {
        eprint!("{}", d.render(color));
        ExitCode::from(1)
    };
    match command {
        Command::Run { file } => match mx.eval_file(&file) {
            Ok(_) => ExitCode::SUCCESS,
            Err(d) => report(d),
        },
        Command::Check { file } => {
            let text = match std::fs::read_to_string(&file) {
                Ok(t) => t,
                Err(e) => {
                    eprintln!("error: cannot read {}: {e}", file.display());
                    return ExitCode::from(1);
                }
            };
            let errors = mx.check_script(&file, &text);
            if errors.len() > 1 {
                eprintln!("{} errors in {}:", errors.len(), file.display());
            }
            match errors.into_iter().map(report).last() {
                Some(code) => code,
                None => ExitCode::SUCCESS,
            }
        }
        Command::Eval { source } => match mx.eval_named("<eval>", &source) {
            Ok(mx::Value::Nil) => ExitCode::SUCCESS,
            Ok(v) => {
                println!("{}", v.repr());
                ExitCode::SUCCESS
            }
            Err(d) => report(d),
        },
        Command::Repl => repl::run(mx),
        Command::Help { topic, markdown } => {
            if markdown {
                print!("{}", mx.help_markdown());
                return ExitCode::SUCCESS;
            }
            match mx.help(topic.as_deref().unwrap_or("")) {
                Ok(text) => {
                    print!("{text}");
                    ExitCode::SUCCESS
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::from(1)
                }
            }
        }
        // answered above, before the interpreter is made
        Command::Graph(g) => graph_cli::run(*g),
        Command::Library(l) => library_cli::run(*l),
        #[cfg(feature = "report")]
        Command::Report { smoke, out } => {
            match mx::report::generate(&mx::report::Options::new(out, smoke)) {
                Ok(s) => {
                    eprintln!("{}", mx::report::describe(&s));
                    ExitCode::SUCCESS
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::from(1)
                }
            }
        }
    }
}
