//! The nesting bound checked before pest runs.
//!
//! pest's generated parser recurses once per nesting level and (at 2.8, see
//! Cargo.toml) has no stack guard, so input nested deeper than the stack
//! allows would abort the process. One linear pass over the source bounds
//! how deep pest can recurse and refuses deeper input with a diagnostic;
//! [`super::parser::parse_program`] then runs pest on a stack large enough
//! for that bound.
//!
//! In the grammar (`grammar/mx.pest`) only three constructs recurse; runs of
//! operators, postfix calls and `else if` branches are loops. Each counts one
//! level while it may still be open:
//! - a bracket `(`, `[` or `{`, until it closes;
//! - an `if` (except the `if` of `else if`) or `fn` keyword: its condition or
//!   body is an expression that may hold the next one without brackets
//!   (`if if a {…} {…}`, `fn(x) = fn(y) = …`). It counts until the expression
//!   it belongs to surely ends: at a `,` or `;` or the closing bracket of its
//!   level, or at a newline that ends a statement.
//!
//! The count over-estimates (a finished `if` still counts until its
//! statement ends), never under-estimates, so it is a safe bound.

use super::ast::{SourceId, Span};
use super::diagnostics::{ErrorKind, MxError, MxResult};

/// Input nested deeper than this (brackets, `if`, `fn`, counted as above) is
/// refused. Each level costs pest under 1 kB of stack (measured).
pub const MAX_NESTING: usize = 1000;

/// `Err` with a diagnostic at the first token nested deeper than [`MAX_NESTING`].
pub fn check_nesting(src: &str, file: SourceId) -> MxResult<()> {
    let b = src.as_bytes();
    // Open keywords per open bracket level (the first entry: outside any bracket).
    let mut levels: Vec<usize> = vec![0];
    let mut open_keywords = 0usize;
    // The last significant token ended an operand (a name, literal or
    // closing bracket), so a newline after it may end the statement.
    let mut after_operand = false;
    // A newline came after an operand; whether it ended the statement
    // depends on the next token (`else`, `.method` and `{` continue).
    let mut newline_pending = false;
    let mut last_was_else = false;
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        // Whitespace and comments: skipped, they change nothing.
        match c {
            b' ' | b'\t' | b'\r' => {
                i += 1;
                continue;
            }
            b'\\' if b.get(i + 1) == Some(&b'\n') => {
                i += 2;
                continue;
            }
            b'\\' if b.get(i + 1) == Some(&b'\r') && b.get(i + 2) == Some(&b'\n') => {
                i += 3;
                continue;
            }
            b'/' if b.get(i + 1) == Some(&b'/') => {
                i += memchr(b'\n', &b[i..]).unwrap_or(b.len() - i);
                continue;
            }
            b'/' if b.get(i + 1) == Some(&b'*') => {
                i = src[i + 2..].find("*/").map_or(b.len(), |k| i + 2 + k + 2);
                continue;
            }
            b'\n' => {
                newline_pending |= after_operand;
                i += 1;
                continue;
            }
            _ => {}
        }
        let start = i;
        let word_end = if c.is_ascii_alphanumeric() || c == b'_' {
            i + b[i..]
                .iter()
                .position(|&d| !(d.is_ascii_alphanumeric() || d == b'_'))
                .unwrap_or(b.len() - i)
        } else {
            i
        };
        let word = &b[start..word_end];
        if newline_pending {
            newline_pending = false;
            let continues = word == b"else" || c == b'.' || c == b'{';
            if !continues {
                let level = levels
                    .last_mut()
                    .expect("the outermost level is never popped");
                open_keywords -= *level;
                *level = 0;
            }
        }
        let mut too_deep = false;
        let mut is_else = false;
        if word_end > start {
            i = word_end;
            match word {
                b"if" if last_was_else => {}
                b"if" | b"fn" => {
                    *levels
                        .last_mut()
                        .expect("the outermost level is never popped") += 1;
                    open_keywords += 1;
                    too_deep = true;
                }
                _ => {}
            }
            is_else = word == b"else";
            after_operand = !matches!(
                word,
                b"if" | b"fn" | b"let" | b"else" | b"and" | b"or" | b"not"
            );
        } else {
            i += 1;
            after_operand = matches!(c, b')' | b']' | b'}' | b'"');
            match c {
                b'"' => i = string_end(b, i),
                b'(' | b'[' | b'{' => {
                    levels.push(0);
                    too_deep = true;
                }
                // (An unmatched closer is pest's to report.)
                b')' | b']' | b'}' if levels.len() > 1 => {
                    open_keywords -= levels.pop().unwrap_or(0);
                }
                b',' | b';' => {
                    let level = levels
                        .last_mut()
                        .expect("the outermost level is never popped");
                    open_keywords -= *level;
                    *level = 0;
                }
                _ => {}
            }
        }
        last_was_else = is_else;
        if too_deep && levels.len() - 1 + open_keywords > MAX_NESTING {
            let end = if word_end > start {
                word_end
            } else {
                start + 1
            };
            return Err(MxError::new(
                ErrorKind::Syntax,
                format!(
                    "nesting too deep: more than {MAX_NESTING} levels of brackets, `if` and `fn`"
                ),
            )
            .at(Span::new(file, start, end))
            .label("too deep")
            .help("name the inner parts with `let` bindings or functions"));
        }
    }
    Ok(())
}

/// The byte after a string that starts before `i` (after its `"`): the
/// closing `"`, or the end of the line for an unterminated one.
fn string_end(b: &[u8], mut i: usize) -> usize {
    while i < b.len() {
        match b[i] {
            b'\\' => i += 2,
            b'"' => return i + 1,
            b'\n' => return i,
            _ => i += 1,
        }
    }
    b.len()
}

fn memchr(needle: u8, hay: &[u8]) -> Option<usize> {
    hay.iter().position(|&d| d == needle)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn depth_error(src: &str) -> Option<MxError> {
        check_nesting(src, 0).err()
    }

    #[test]
    fn ordinary_scripts_pass() {
        let mut src = String::new();
        for i in 0..5000 {
            src.push_str(&format!(
                "fn f{i}(t) = if t < 1 {{ fn(x) = x }} else if t < 2 {{ 2 }} else {{ 3 }}\n"
            ));
        }
        assert!(depth_error(&src).is_none());
    }

    #[test]
    fn counts_brackets_and_unbracketed_keywords() {
        let n = MAX_NESTING + 1;
        for src in [
            format!("{}1{}", "(".repeat(n), ")".repeat(n)),
            format!("{}1", "fn(x) = ".repeat(n)),
            format!("{} true{}", "if ".repeat(n), " {1}".repeat(n)),
            // A newline after `=` or before `{` does not end the expression.
            format!("{}1", "fn(x) =\n".repeat(n)),
            format!("{}true{}", "if ".repeat(n), "\n{1}".repeat(n)),
        ] {
            let e = depth_error(&src).expect("too deep");
            assert!(e.message.contains("nesting too deep"), "{}", e.message);
            assert!(e.span.is_some() && e.help.is_some());
        }
        for src in [
            format!("{}1{}", "(".repeat(n - 1), ")".repeat(n - 1)),
            // `else if` is a loop in the grammar: a long chain is flat.
            format!("if a {{1}}{} else {{3}}", " else if b {2}".repeat(10 * n)),
            // Statements, `,` and `;` end what the keywords opened.
            "fn(x) = x\n".repeat(10 * n),
            format!("f({})", "fn(x) = x, ".repeat(10 * n)),
            "if a { 1 }; ".repeat(10 * n),
            // Keywords inside strings and comments do not count.
            format!("\"{}\" // {}", "fn(".repeat(10 * n), "if (".repeat(10 * n)),
        ] {
            assert!(depth_error(&src).is_none(), "{}", &src[..40]);
        }
    }
}
