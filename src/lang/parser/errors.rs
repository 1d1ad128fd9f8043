//! Syntax errors: pest's error at its span, named in words ("an
//! expression", "`(`"), with a help line for the most common slips.

use super::grammar::Rule;
use crate::lang::ast::{SourceId, Span};
use crate::lang::diagnostics::{ErrorKind, MxError};

fn rule_name(r: &Rule) -> Option<&'static str> {
    Some(match r {
        Rule::EOI => "end of input",
        Rule::expr | Rule::postfix_expr => "an expression",
        Rule::ident => "a name",
        Rule::number | Rule::mantissa => "a number",
        Rule::string => "a string",
        Rule::unit => "a unit (s, ms, deg, rad)",
        Rule::params => "a parameter list `(a, b)`",
        Rule::param => "a parameter name",
        Rule::block => "a block `{ … }`",
        Rule::entry => "a record field `name: value`",
        Rule::named_arg => "a named argument",
        Rule::call => "`(`",
        Rule::method | Rule::field => "`.`",
        Rule::index => "`[`",
        Rule::add | Rule::sub | Rule::mul | Rule::div | Rule::rem | Rule::meet => "an operator",
        Rule::or_op | Rule::and_op => "an operator",
        Rule::eq | Rule::ne | Rule::lt | Rule::le | Rule::gt | Rule::ge => "an operator",
        Rule::kw_else => "`else`",
        Rule::let_stmt | Rule::fn_stmt | Rule::import_stmt => "a statement",
        _ => return None,
    })
}

pub fn syntax_error(e: pest::error::Error<Rule>, src: &str, file: SourceId) -> MxError {
    syntax_error_from(e, src, 0, file)
}

/// Where pest's error is, relative to the text it parsed.
pub fn error_pos(e: &pest::error::Error<Rule>) -> usize {
    match e.location {
        pest::error::InputLocation::Pos(p) => p,
        pest::error::InputLocation::Span((a, _)) => a,
    }
}

/// [`syntax_error`] for pest's error on `src[from..]` (one statement of a
/// script parsed on its own): the span is shifted into `src`, and brackets
/// left open are looked for from `from` on, not in earlier statements.
pub fn syntax_error_from(
    e: pest::error::Error<Rule>,
    src: &str,
    from: usize,
    file: SourceId,
) -> MxError {
    use pest::error::{ErrorVariant, InputLocation};
    let (start, end) = match e.location {
        InputLocation::Pos(p) => (from + p, from + p),
        InputLocation::Span((a, b)) => (from + a, from + b),
    };
    // Point at the whole offending token, not just its first byte.
    let rest = src.get(start..).unwrap_or("");
    let tok_len = if end > start {
        end - start
    } else {
        let mut n = 0;
        for (i, c) in rest.char_indices() {
            if c.is_alphanumeric() || c == '_' || c == '.' {
                n = i + c.len_utf8();
            } else {
                if i == 0 {
                    n = c.len_utf8();
                }
                break;
            }
        }
        if c_is_newline(rest) { 0 } else { n }
    };
    let found = if rest.is_empty() {
        "end of input".to_string()
    } else if c_is_newline(rest) {
        "end of line".to_string()
    } else {
        format!(
            "`{}`",
            rest.get(..tok_len)
                .unwrap_or(rest)
                .chars()
                .take(20)
                .collect::<String>()
        )
    };
    let expected = match &e.variant {
        ErrorVariant::ParsingError { positives, .. } => {
            // Continuations of a complete expression (a call, `.`, an
            // operator, a unit) are always possible and only add noise.
            let continuation = |r: &Rule| {
                matches!(
                    r,
                    Rule::call
                        | Rule::postfix_start
                        | Rule::method
                        | Rule::field
                        | Rule::index
                        | Rule::unit
                        | Rule::add
                        | Rule::sub
                        | Rule::mul
                        | Rule::div
                        | Rule::rem
                        | Rule::meet
                        | Rule::or_op
                        | Rule::and_op
                        | Rule::eq
                        | Rule::ne
                        | Rule::lt
                        | Rule::le
                        | Rule::gt
                        | Rule::ge
                )
            };
            let mut names: Vec<&str> = positives
                .iter()
                .filter(|r| !continuation(r))
                .filter_map(rule_name)
                .collect();
            names.sort();
            names.dedup();
            names
        }
        ErrorVariant::CustomError { .. } => vec![],
    };
    let line_rest = rest.split('\n').next().unwrap_or("");
    if rest.starts_with('"') && !line_rest[1..].contains('"') {
        return MxError::new(ErrorKind::Syntax, "this string is never closed")
            .at(Span::new(file, start, start + line_rest.trim_end().len()))
            .label("string starts here")
            .help(
                "add a `\"` before the end of the line (write `\\\"` for a quote inside a string)",
            );
    }
    if let Some((pos, open)) = unclosed_bracket(&src[from..]).map(|(p, c)| (from + p, c))
        && pos < start
    {
        let close = match open {
            '(' => ')',
            '[' => ']',
            _ => '}',
        };
        return MxError::new(ErrorKind::Syntax, format!("this `{open}` is never closed"))
            .at(Span::new(file, pos, pos + 1))
            .label("opened here")
            .help(format!(
                "add a matching `{close}`; inside brackets, items are separated by `,`"
            ));
    }
    let message = if expected.is_empty() {
        format!("unexpected {found}")
    } else {
        format!("expected {}, found {found}", join_or(&expected))
    };
    // An empty span at the very end would not be drawn; point at the last character.
    let (start, tok_len) = if tok_len == 0 && start >= src.len() && !src.is_empty() {
        let last = src.char_indices().last().map(|(i, _)| i).unwrap_or(0);
        (last, src.len() - last)
    } else {
        (start, tok_len)
    };
    let help = syntax_help(src, from, start, rest);
    MxError::new(ErrorKind::Syntax, message)
        .at(Span::new(file, start, start + tok_len))
        .label("not expected here")
        .help(help)
}

/// The innermost bracket left open at the end of `src` (outside strings and comments).
fn unclosed_bracket(src: &str) -> Option<(usize, char)> {
    let mut stack: Vec<(usize, char)> = Vec::new();
    let mut it = src.char_indices().peekable();
    while let Some((i, c)) = it.next() {
        match c {
            '"' => {
                while let Some((_, d)) = it.next() {
                    match d {
                        '\\' => {
                            it.next();
                        }
                        '"' | '\n' => break,
                        _ => {}
                    }
                }
            }
            '/' if it.peek().map(|p| p.1) == Some('/') => {
                for (_, d) in it.by_ref() {
                    if d == '\n' {
                        break;
                    }
                }
            }
            '(' | '[' | '{' => stack.push((i, c)),
            ')' | ']' | '}' => {
                stack.pop();
            }
            _ => {}
        }
    }
    stack.pop()
}

fn c_is_newline(rest: &str) -> bool {
    rest.starts_with('\n') || rest.starts_with("\r\n")
}

fn join_or(items: &[&str]) -> String {
    match items {
        [] => String::new(),
        [a] => a.to_string(),
        [init @ .., last] => format!("{} or {last}", init.join(", ")),
    }
}

/// A help line for the most common syntax slips.
fn syntax_help(src: &str, from: usize, pos: usize, rest: &str) -> String {
    let before_raw = src.get(from..pos).unwrap_or("");
    let before = before_raw.trim_end();
    let line_rest = rest.split('\n').next().unwrap_or("");
    if rest.starts_with('"') && !line_rest[1..].contains('"') {
        "this string is never closed: add a `\"` before the end of the line".into()
    } else if before_raw.ends_with(|c: char| c.is_ascii_digit())
        && rest.starts_with(|c: char| c.is_alphabetic())
    {
        "numbers take the unit suffixes s, ms, deg and rad (e.g. `2s`, `90deg`); write `2 * x` to multiply".into()
    } else if before.ends_with("let") || before.ends_with("fn") {
        "names start with a letter or `_` and may not be keywords (let, fn, if, else, true, false, and, or, not)".into()
    } else if let Some(op) = leading_operator(before_raw, rest) {
        format!(
            "a line that begins with `{op}` continues the expression on the line above, and none is open here \
             (in the REPL the line above has already run: enter both lines as one input, the first ending \
             with the operator or inside `( … )`)"
        )
    } else if c_is_newline(rest) || rest.is_empty() {
        "the statement ends here; to continue an expression on the next line, begin that line with the operator (`+ b`, `- b` with a space), end this line with one, or keep a bracket open".into()
    } else if unclosed_bracket(before_raw).is_some_and(|(_, c)| c != '{') {
        "inside brackets, separate items with `,`: `f(a, b)`, `[1, 2]`".into()
    } else {
        "statements are separated by newlines or `;`; calls look like `f(x, name: value)`".into()
    }
}

/// The infix operator (or `.`) `rest` begins with, when it is the first token
/// on its line: such a line continues the expression above it, so a syntax
/// error there means no expression was open (see `line_cont` in mx.pest).
fn leading_operator<'a>(before: &str, rest: &'a str) -> Option<&'a str> {
    let line_start = before.rsplit('\n').next().unwrap_or("");
    if !line_start.trim().is_empty() || rest.starts_with("//") || rest.starts_with("/*") {
        return None;
    }
    let ops = [
        "==", "!=", "<=", ">=", "&&", "||", "and", "or", "+", "*", "/", "%", "&", "<", ">", "×",
        "∧", "≤", "≥", ".",
    ];
    let op = ops.into_iter().find(|op| rest.starts_with(op))?;
    let word = op.chars().all(char::is_alphabetic);
    let after = rest[op.len()..].chars().next();
    if word && after.is_some_and(|c| c.is_alphanumeric() || c == '_') {
        return None; // `order`, `and_then`: a name, not the operator
    }
    Some(&rest[..op.len()])
}
