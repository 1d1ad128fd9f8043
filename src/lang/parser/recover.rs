//! Parsing on after a syntax error, for `mx check`: the script is read one
//! statement at a time (`stmt_at` in the grammar); a statement that does not
//! parse is reported and skipped to the next statement boundary, and the
//! statements after it are parsed and checked as usual. So a script with
//! three typos gets three errors, in source order, not one.
//!
//! Runs only after the whole-program parse failed, so a good script costs
//! nothing more. Each statement is parsed from where it starts (pest only
//! reads that statement), so the whole pass is linear in the script.

use pest::Parser;

use super::build::Builder;
use super::errors::{error_pos, syntax_error_from};
use super::grammar::{MxParser, Rule};
use crate::lang::ast::*;
use crate::lang::diagnostics::{ErrorKind, MxError};

/// At most this many syntax errors are reported; then one more says the
/// check stopped (a script this broken is usually one unclosed thing).
pub const MAX_SYNTAX_ERRORS: usize = 50;

/// The statements of `src` that parse, and an error for each one that does
/// not, in source order. A broken `let x = …` or `fn f…` still binds its
/// name (to an empty list, in the program returned: the program is for name
/// resolution only, never run), so its later uses are not reported as
/// unknown names: they are not errors of their own.
pub fn parse_statements(src: &str, file: SourceId) -> (Program, Vec<MxError>) {
    let mut stmts = Vec::new();
    let mut errors = Vec::new();
    let mut at = 0;
    while at < src.len() {
        if errors.len() == MAX_SYNTAX_ERRORS {
            errors.push(
                MxError::new(
                    ErrorKind::Syntax,
                    format!("stopped after {MAX_SYNTAX_ERRORS} syntax errors"),
                )
                .at(Span::new(file, at, at))
                .help("fix the errors above and check again"),
            );
            break;
        }
        let rest = &src[at..];
        match MxParser::parse(Rule::stmt_at, rest) {
            Ok(mut pairs) => {
                let Some(top) = pairs.next() else { break };
                let end = at + top.as_span().end();
                let b = Builder {
                    file,
                    src,
                    offset: at,
                };
                for p in top.into_inner() {
                    if p.as_rule() == Rule::EOI {
                        continue;
                    }
                    let stmt_start = at + p.as_span().start();
                    match b.stmt(p) {
                        Ok(s) => stmts.push(s),
                        // A statement pest accepts but the tree refuses
                        // (a bad escape, a repeated record key).
                        Err(e) => {
                            errors.push(e);
                            stmts.extend(placeholder(src, stmt_start, end, file));
                        }
                    }
                }
                if end <= at {
                    break;
                }
                at = end;
            }
            Err(e) => {
                let pos = at + error_pos(&e);
                errors.push(syntax_error_from(e, src, at, file));
                stmts.extend(placeholder(src, at, pos, file));
                at = resume(src, at, pos);
            }
        }
    }
    (Program { stmts }, errors)
}

/// `let NAME = []` for a broken statement in `src[from..to]` that starts
/// `let NAME` or `fn NAME`: the name it meant to bind.
fn placeholder(src: &str, from: usize, to: usize, file: SourceId) -> Option<Stmt> {
    let text = src.get(from..to.max(from))?;
    let trimmed = text.trim_start_matches(|c: char| c.is_whitespace() || c == ';');
    let after_kw = trimmed
        .strip_prefix("let")
        .or_else(|| trimmed.strip_prefix("fn"))?;
    let name_text = after_kw.trim_start_matches([' ', '\t']);
    if name_text.len() == after_kw.len() {
        return None; // `letter`, `fnord`: not a keyword
    }
    let len = name_text
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .unwrap_or(name_text.len());
    let name = &name_text[..len];
    if !name.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_') {
        return None;
    }
    let start = from + (text.len() - name_text.len());
    let span = Span::new(file, start, start + len);
    Some(Stmt::Let(
        name.to_string(),
        span,
        Expr {
            kind: ExprKind::List(vec![]),
            span,
        },
    ))
}

/// Where to parse on after a statement starting at `from` failed at `err`:
/// the first statement boundary at or after `err` (a `;`, or the start of a
/// line) where the brackets opened since `from` are closed again and the
/// line does not continue the statement (`.method()`). When a bracket is
/// never closed, the first line start after the error, so one unclosed `(`
/// does not hide the rest of the script.
fn resume(src: &str, from: usize, err: usize) -> usize {
    let b = src.as_bytes();
    let mut depth: i64 = 0;
    let mut fallback = None;
    let mut i = from;
    while i < b.len() {
        match b[i] {
            b'"' => {
                // to the closing quote, or to the end of the line (an
                // unclosed string ends there)
                i += 1;
                while i < b.len() && b[i] != b'"' && b[i] != b'\n' {
                    i += if b[i] == b'\\' { 2 } else { 1 };
                }
                if i < b.len() && b[i] == b'\n' {
                    continue;
                }
            }
            b'/' if b.get(i + 1) == Some(&b'/') => {
                while i < b.len() && b[i] != b'\n' {
                    i += 1;
                }
                continue;
            }
            b'/' if b.get(i + 1) == Some(&b'*') => {
                i = src[i + 2..].find("*/").map_or(b.len(), |k| i + 2 + k + 2);
                continue;
            }
            b'(' | b'[' | b'{' => depth += 1,
            b')' | b']' | b'}' => depth -= 1,
            b';' if depth <= 0 && i >= err => return i + 1,
            b'\n' => {
                let next = i + 1;
                if next >= err && next > from {
                    fallback.get_or_insert(next);
                    let continues = src[next..].trim_start().starts_with('.');
                    if depth <= 0 && !continues {
                        return next;
                    }
                }
            }
            _ => {}
        }
        i += 1;
    }
    fallback.unwrap_or(src.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// (line, column) of each error, 1-based.
    fn positions(src: &str) -> Vec<(usize, usize)> {
        let (_, errors) = parse_statements(src, 0);
        errors
            .iter()
            .map(|e| {
                let s = e.span.expect("a span").start as usize;
                let line = src[..s].matches('\n').count() + 1;
                let col = s - src[..s].rfind('\n').map_or(0, |k| k + 1) + 1;
                (line, col)
            })
            .collect()
    }

    #[test]
    fn every_broken_statement_is_reported_and_the_rest_parse() {
        let src = "let a = 1\nprint(a 2)\nlet = 3\nlet b = [1, 2\nlet c = a +* 2\nprint(b, c)\n";
        let (program, errors) = parse_statements(src, 0);
        assert_eq!(
            positions(src),
            vec![(2, 9), (3, 5), (4, 9), (5, 12)],
            "{errors:?}"
        );
        // `let a`, `print(b, c)` parse; `b` and `c` are bound by placeholders.
        let names: Vec<String> = program
            .stmts
            .iter()
            .filter_map(|s| match s {
                Stmt::Let(n, ..) => Some(n.clone()),
                _ => None,
            })
            .collect();
        assert_eq!(names, ["a", "b", "c"]);
        assert!(matches!(program.stmts.last(), Some(Stmt::Expr(_))));
    }

    #[test]
    fn a_statement_over_several_lines_is_skipped_whole() {
        // The error is on the first line; the bracket closes on the second,
        // and the third line starts the next statement.
        let src = "let a = f(1 2,\n  3)\nlet b = 4 4\nfn g(x) {\n  x +* 1\n  x\n}\ng(b)\n";
        assert_eq!(positions(src), vec![(1, 13), (3, 11), (5, 6)]);
        let (program, _) = parse_statements(src, 0);
        assert_eq!(program.stmts.len(), 4, "{:?}", program.stmts);
    }

    #[test]
    fn a_good_program_parses_the_same_statement_by_statement() {
        let src = "let a = 1; let b = 2\n\n// c\nfn f(t) = t * 2 /* x\n y */\nf(a +\n b)\nw\n  .only(\"x\")\nif a { 1 } else if b { 2 }\n";
        let whole = super::super::parse_program(src, 0).unwrap();
        let (parts, errors) = parse_statements(src, 0);
        assert!(errors.is_empty(), "{errors:?}");
        assert_eq!(parts.stmts.len(), whole.stmts.len());
        for (a, b) in parts.stmts.iter().zip(&whole.stmts) {
            assert_eq!(format!("{a:?}"), format!("{b:?}"));
        }
    }

    #[test]
    fn errors_are_capped() {
        let src = "let = 1\n".repeat(200);
        let (_, errors) = parse_statements(&src, 0);
        assert_eq!(errors.len(), MAX_SYNTAX_ERRORS + 1);
        assert!(errors[MAX_SYNTAX_ERRORS].message.contains("stopped after"));
    }
}
