//! The interactive REPL (rustyline): persistent history in the user's data
//! folder, multi-line input while brackets are open, tab completion (names in
//! scope and built-ins; inside strings, file paths and DOF names: see
//! `mx::lang::completion`), `:help` (by topic), `:type`, `:info`, `:load`, `:time`, `:quit`.
//! Ctrl-C during an evaluation cancels it (through the interpreter's
//! cancellation token) and returns to the prompt; at the prompt it clears the line.

use std::borrow::Cow;
use std::process::ExitCode;
use std::sync::{Arc, Mutex};
use std::time::Instant;

use rustyline::completion::{Completer, Pair};
use rustyline::error::ReadlineError;
use rustyline::highlight::Highlighter;
use rustyline::hint::Hinter;
use rustyline::validate::{ValidationContext, ValidationResult, Validator};
use rustyline::{Config, Context, Editor, Helper};

use mx::Interpreter;
use mx::lang::ErrorKind;
use mx::lang::completion::{self, COMMANDS, Scope};

struct MxHelper {
    /// What Tab completes from, taken again after each input.
    scope: Arc<Mutex<Scope>>,
}

impl Completer for MxHelper {
    type Candidate = Pair;
    fn complete(
        &self,
        line: &str,
        pos: usize,
        _: &Context<'_>,
    ) -> rustyline::Result<(usize, Vec<Pair>)> {
        let scope = self.scope.lock().unwrap_or_else(|p| p.into_inner());
        let (start, found) = completion::complete(line, pos, &scope);
        let pairs = found
            .into_iter()
            .map(|c| Pair {
                display: c.display,
                replacement: c.replacement,
            })
            .collect();
        Ok((start, pairs))
    }
}

impl Hinter for MxHelper {
    type Hint = String;
}
impl Highlighter for MxHelper {
    fn highlight_prompt<'b, 's: 'b, 'p: 'b>(
        &'s self,
        prompt: &'p str,
        _default: bool,
    ) -> Cow<'b, str> {
        Cow::Borrowed(prompt)
    }
}
impl Validator for MxHelper {
    fn validate(&self, ctx: &mut ValidationContext) -> rustyline::Result<ValidationResult> {
        let input = ctx.input();
        if !input.trim_start().starts_with(':') && Interpreter::is_incomplete(input) {
            Ok(ValidationResult::Incomplete)
        } else {
            Ok(ValidationResult::Valid(None))
        }
    }
}
impl Helper for MxHelper {}

fn history_path() -> Option<std::path::PathBuf> {
    let dir = dirs::data_dir()?.join("mx");
    std::fs::create_dir_all(&dir).ok()?;
    Some(dir.join("history.txt"))
}

pub fn run(mut mx: mx::Interpreter) -> ExitCode {
    let token = mx.cancel_token();
    let scope = Arc::new(Mutex::new(session_scope(&mx)));
    let config = Config::builder().auto_add_history(false).build();
    let mut rl: Editor<MxHelper, rustyline::history::DefaultHistory> =
        match Editor::with_config(config) {
            Ok(r) => r,
            Err(e) => {
                eprintln!("error: cannot start the line editor: {e}");
                return ExitCode::from(1);
            }
        };
    rl.set_helper(Some(MxHelper {
        scope: scope.clone(),
    }));
    {
        let t = token.clone();
        // Ctrl-C while evaluating: cancel. Installed after the editor,
        // which sets its own SIGINT handler when it is created. (At the prompt rustyline reads the
        // key itself and reports Interrupted.)
        if let Err(e) = ctrlc::set_handler(move || t.cancel()) {
            eprintln!("warning: Ctrl-C will not cancel evaluations: {e}");
        }
    }
    let history = history_path();
    if let Some(h) = &history {
        let _ = rl.load_history(h);
    }
    eprintln!(
        "mx {} — :help for help, :quit to leave",
        env!("CARGO_PKG_VERSION")
    );
    let mut n = 0usize;
    loop {
        match rl.readline("mx> ") {
            Ok(line) => {
                if line.trim().is_empty() {
                    continue;
                }
                let _ = rl.add_history_entry(line.as_str());
                if let Some(h) = &history {
                    let _ = rl.append_history(h);
                }
                n += 1;
                token.reset();
                if !command(&mut mx, line.trim(), n) {
                    break;
                }
                scope.lock().unwrap_or_else(|p| p.into_inner()).refresh(&mx);
            }
            Err(ReadlineError::Interrupted) => continue,
            Err(ReadlineError::Eof) => break,
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::from(1);
            }
        }
    }
    ExitCode::SUCCESS
}

/// The session's names, signatures and motions; paths relative to the current
/// folder (the REPL reads files from there, issue 28).
fn session_scope(mx: &Interpreter) -> Scope {
    Scope::of(mx, std::env::current_dir().unwrap_or_default())
}

fn report(d: mx::lang::Diagnostic) {
    if d.kind() == ErrorKind::Cancelled {
        eprintln!("cancelled");
    } else {
        eprint!("{}", d.render(false));
    }
}

fn show(v: &mx::Value) {
    if !matches!(v, mx::Value::Nil) {
        println!("{}", v.repr());
    }
}

/// Run one REPL input. Returns false to quit.
fn command(mx: &mut mx::Interpreter, line: &str, n: usize) -> bool {
    let (cmd, rest) = match line.split_once(char::is_whitespace) {
        Some((c, r)) => (c, r.trim()),
        None => (line, ""),
    };
    // the words a newcomer types first, unless the session defined them
    let bare = line.trim();
    if matches!(bare, "exit" | "quit") && mx.get(bare).is_none() {
        return false;
    }
    if cmd == "help" && mx.get("help").is_none() {
        help(mx, rest);
        return true;
    }
    match cmd {
        ":quit" | ":q" | ":exit" => return false,
        ":help" | ":h" => help(mx, rest),
        ":type" | ":t" => match mx.type_of(rest) {
            Ok(t) => println!("{t}"),
            Err(d) => report(d),
        },
        ":load" | ":l" => match mx.eval_file(rest) {
            Ok(v) => show(&v),
            Err(d) => report(d),
        },
        ":time" => {
            let t0 = Instant::now();
            let r = mx.eval_named(&format!("<repl:{n}>"), rest);
            let dt = t0.elapsed();
            match r {
                Ok(v) => show(&v),
                Err(d) => report(d),
            }
            eprintln!("time: {:.3} ms", dt.as_secs_f64() * 1e3);
        }
        ":plot" | ":p" => plot(mx, rest, n),
        ":info" | ":i" => info(mx, rest, n),
        c if c.starts_with(':') => {
            eprintln!("unknown command `{c}`; commands: {}", COMMANDS.join(", "));
        }
        _ => match mx.eval_named(&format!("<repl:{n}>"), line) {
            Ok(v) => show(&v),
            Err(d) => report(d),
        },
    }
    true
}

/// `:info EXPR`: what is known about a value beyond its summary: for a clip
/// its frame rate and frame count; for a motion SP returned, SP's report (gap groups, energies, why each solve stopped).
fn info(mx: &mut mx::Interpreter, expr: &str, n: usize) {
    let v = match mx.eval_named(&format!("<repl:{n}>"), expr) {
        Ok(v) => v,
        Err(d) => return report(d),
    };
    println!("{}: {}", v.type_name(), v.repr());
    // Animators count frames: a clip's rate and frame count, as frames(m) gives them.
    if let Some(Ok(Some((dt, count)))) = Interpreter::motion_of(&v).map(|m| mx::motion::frames(&m))
    {
        println!(
            "frames: {count} at {} fps ({} s per frame)",
            mx::fmt_num::format_number((1000.0 / dt).round() / 1000.0),
            mx::fmt_num::format_number(dt)
        );
    }
    if let Some(c) = Interpreter::clip_text(&v) {
        println!("clip {c}");
    }
    if let Some(r) = Interpreter::sp_report_text(&v) {
        print!("SP report:\n{r}");
    }
}

/// `:plot EXPR`: a quick text plot of a motion's first DOF curves, in the
/// terminal. Samples the curves only; runs no dynamics.
fn plot(mx: &mut mx::Interpreter, expr: &str, n: usize) {
    const MAX_CURVES: usize = 6;
    let v = match mx.eval_named(&format!("<repl:{n}>"), expr) {
        Ok(v) => v,
        Err(d) => return report(d),
    };
    let mu = match Interpreter::motion_of(&v) {
        Some(m) => m,
        None => {
            eprintln!(
                ":plot needs a motion (an Mu, Dof or Interval), not a {}",
                v.type_name()
            );
            return;
        }
    };
    let names: Vec<&str> = mu.names().take(MAX_CURVES).collect();
    if mu.len() > MAX_CURVES {
        eprintln!(
            "plotting the first {MAX_CURVES} of {} DOFs; use .only(...) to choose",
            mu.len()
        );
    }
    match mx::io::plot::series_of(&mu, &names, 60.0) {
        Ok(series) => println!("{}", mx::io::plot::terminal(&series, 72, 16)),
        Err(e) => eprintln!("cannot plot: {e}"),
    }
}

/// `:help`, `:help TOPIC`, `:help NAME`, `:help formats` (the text is the
/// interpreter's, the same as `docs/reference.md`).
fn help(mx: &mx::Interpreter, word: &str) {
    match mx.help(word) {
        Ok(text) => print!("{text}"),
        Err(e) => eprintln!("{e}"),
    }
}
