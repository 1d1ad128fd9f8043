//! The interactive REPL (rustyline).

use std::process::ExitCode;

pub fn run(mut mx: mx::Interpreter) -> ExitCode {
    let _ = &mut mx;
    eprintln!("mx: the REPL is not implemented yet; use `mx run FILE` or `mx eval EXPR`");
    ExitCode::from(1)
}
