//! Source text → AST. pest does the tokenising and structure
//! (`grammar/mx.pest`); a Pratt parser applies operator precedence; syntax
//! errors become [`MxError`]s with the span pest reports and a help line.

use std::sync::{Arc, LazyLock};

use pest::Parser;
use pest::iterators::Pair;
use pest::pratt_parser::{Assoc, Op, PrattParser};
use pest_derive::Parser;

use super::ast::*;
use super::diagnostics::{ErrorKind, MxError, MxResult};

#[derive(Parser)]
#[grammar = "../grammar/mx.pest"]
struct MxParser;

/// Operator precedence, lowest first (documented in README.md):
/// `||` < `&&` < comparisons < `+ -` < `& ∧` < `* / %` < unary `- !` < postfix.
static PRATT: LazyLock<PrattParser<Rule>> = LazyLock::new(|| {
    PrattParser::new()
        .op(Op::infix(Rule::or_op, Assoc::Left))
        .op(Op::infix(Rule::and_op, Assoc::Left))
        .op(Op::infix(Rule::eq, Assoc::Left)
            | Op::infix(Rule::ne, Assoc::Left)
            | Op::infix(Rule::lt, Assoc::Left)
            | Op::infix(Rule::le, Assoc::Left)
            | Op::infix(Rule::gt, Assoc::Left)
            | Op::infix(Rule::ge, Assoc::Left))
        .op(Op::infix(Rule::add, Assoc::Left) | Op::infix(Rule::sub, Assoc::Left))
        .op(Op::infix(Rule::meet, Assoc::Left))
        .op(Op::infix(Rule::mul, Assoc::Left)
            | Op::infix(Rule::div, Assoc::Left)
            | Op::infix(Rule::rem, Assoc::Left))
        .op(Op::prefix(Rule::neg) | Op::prefix(Rule::not))
});

/// Parse a whole program from source `file`.
pub fn parse_program(src: &str, file: SourceId) -> MxResult<Program> {
    check_nesting(src, file)?;
    // pest and its Pratt parser recurse once per nesting level / prefix
    // operator; run them on a generous stack (reserved, not committed) so
    // deep input fits whatever thread we are on (test threads have 2 MB).
    stacker::grow(PARSE_STACK, || parse_program_inner(src, file))
}

fn parse_program_inner(src: &str, file: SourceId) -> MxResult<Program> {
    let mut pairs = MxParser::parse(Rule::program, src).map_err(|e| syntax_error(e, src, file))?;
    let program = pairs
        .next()
        .ok_or_else(|| MxError::new(ErrorKind::Syntax, "empty parse"))?;
    let b = Builder { file, src };
    let mut stmts = Vec::new();
    for p in program.into_inner() {
        if p.as_rule() == Rule::EOI {
            break;
        }
        stmts.push(b.stmt(p)?);
    }
    Ok(Program { stmts })
}

/// Brackets nested deeper than this are refused up front with a clear
/// message (pest's own guard would report a confusing syntax error).
pub const MAX_NESTING: usize = 1000;
const PARSE_STACK: usize = 256 * 1024 * 1024;

fn check_nesting(src: &str, file: SourceId) -> MxResult<()> {
    let mut depth = 0usize;
    let mut in_str = false;
    let mut escaped = false;
    for (i, c) in src.char_indices() {
        if in_str {
            match (escaped, c) {
                (true, _) => escaped = false,
                (false, '\\') => escaped = true,
                (false, '"') | (false, '\n') => in_str = false,
                _ => {}
            }
            continue;
        }
        match c {
            '"' => in_str = true,
            '(' | '[' | '{' => {
                depth += 1;
                if depth > MAX_NESTING {
                    return Err(MxError::new(
                        ErrorKind::Syntax,
                        format!("brackets nested more than {MAX_NESTING} deep"),
                    )
                    .at(Span::new(file, i, i + 1))
                    .label("too deep")
                    .help("split the expression with `let` bindings"));
                }
            }
            ')' | ']' | '}' => depth = depth.saturating_sub(1),
            _ => {}
        }
    }
    Ok(())
}

/// Parse a single expression (REPL `:type`, `mx eval`).
pub fn parse_expr(src: &str, file: SourceId) -> MxResult<Expr> {
    let program = parse_program(src, file)?;
    let mut stmts = program.stmts;
    match (stmts.len(), stmts.pop()) {
        (1, Some(Stmt::Expr(e))) => Ok(e),
        (_, Some(s)) => Err(
            MxError::new(ErrorKind::Syntax, "expected a single expression")
                .at(s.span())
                .help("write one expression, e.g. `1 + 2` or `len([1, 2])`"),
        ),
        (_, None) => Err(
            MxError::new(ErrorKind::Syntax, "expected an expression, found nothing")
                .at(Span::new(file, 0, 0))
                .help("write one expression, e.g. `1 + 2`"),
        ),
    }
}

/// Whether `src` is incomplete in a way more lines could fix (open brackets,
/// an unterminated block comment or string): the REPL keeps reading.
pub fn is_incomplete(src: &str) -> bool {
    let mut depth: i64 = 0;
    let mut chars = src.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '(' | '[' | '{' => depth += 1,
            ')' | ']' | '}' => depth -= 1,
            '"' => {
                let mut closed = false;
                while let Some(d) = chars.next() {
                    match d {
                        '\\' => {
                            chars.next();
                        }
                        '"' => {
                            closed = true;
                            break;
                        }
                        '\n' => break,
                        _ => {}
                    }
                }
                if !closed && chars.peek().is_none() {
                    return false;
                }
            }
            '/' if chars.peek() == Some(&'/') => {
                for d in chars.by_ref() {
                    if d == '\n' {
                        break;
                    }
                }
            }
            '/' if chars.peek() == Some(&'*') => {
                chars.next();
                let mut closed = false;
                let mut prev = ' ';
                for d in chars.by_ref() {
                    if prev == '*' && d == '/' {
                        closed = true;
                        break;
                    }
                    prev = d;
                }
                if !closed {
                    return true;
                }
            }
            _ => {}
        }
    }
    if depth > 0 {
        return true;
    }
    // A trailing infix operator or `=` also asks for another line.
    let t = src.trim_end();
    t.ends_with(['+', '*', '/', '&', '∧', '=', ',', '|', '−']) && !t.ends_with("//")
        || (t.ends_with('-') && !t.ends_with("--"))
}

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
        Rule::let_stmt | Rule::fn_stmt => "a statement",
        _ => return None,
    })
}

fn syntax_error(e: pest::error::Error<Rule>, src: &str, file: SourceId) -> MxError {
    use pest::error::{ErrorVariant, InputLocation};
    let (start, end) = match e.location {
        InputLocation::Pos(p) => (p, p),
        InputLocation::Span((a, b)) => (a, b),
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
    if let Some((pos, open)) = unclosed_bracket(src)
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
    let help = syntax_help(src, start, rest);
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
fn syntax_help(src: &str, pos: usize, rest: &str) -> String {
    let before_raw = src.get(..pos).unwrap_or("");
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
    } else if c_is_newline(rest) || rest.is_empty() {
        "the statement ends here; to continue an expression on the next line, end this line with an operator or keep a bracket open".into()
    } else if unclosed_bracket(before_raw).is_some_and(|(_, c)| c != '{') {
        "inside brackets, separate items with `,`: `f(a, b)`, `[1, 2]`".into()
    } else {
        "statements are separated by newlines or `;`; calls look like `f(x, name: value)`".into()
    }
}

struct Builder<'s> {
    file: SourceId,
    src: &'s str,
}

fn unescape(s: &str) -> Result<String, String> {
    let mut out = String::with_capacity(s.len());
    let mut chars = s.chars();
    while let Some(c) = chars.next() {
        if c != '\\' {
            out.push(c);
            continue;
        }
        match chars.next() {
            Some('n') => out.push('\n'),
            Some('t') => out.push('\t'),
            Some('r') => out.push('\r'),
            Some('0') => out.push('\0'),
            Some('\\') => out.push('\\'),
            Some('"') => out.push('"'),
            Some('u') => {
                let rest: String = chars.clone().collect();
                let body = rest
                    .strip_prefix('{')
                    .and_then(|r| r.split_once('}'))
                    .map(|(h, _)| h.to_string());
                let Some(hex) = body else {
                    return Err("write unicode escapes as \\u{1F600}".into());
                };
                let code = u32::from_str_radix(&hex, 16).ok().and_then(char::from_u32);
                match code {
                    Some(ch) => out.push(ch),
                    None => return Err(format!("\\u{{{hex}}} is not a unicode scalar value")),
                }
                for _ in 0..hex.len() + 2 {
                    chars.next();
                }
            }
            Some(other) => {
                return Err(format!(
                    "unknown escape `\\{other}`; use \\n, \\t, \\r, \\0, \\\\, \\\" or \\u{{…}}"
                ));
            }
            None => return Err("a string cannot end with a lone backslash".into()),
        }
    }
    Ok(out)
}

impl Builder<'_> {
    fn text(&self, span: Span) -> Arc<str> {
        Arc::from(
            self.src
                .get(span.start as usize..span.end as usize)
                .unwrap_or(""),
        )
    }

    fn span(&self, p: &Pair<Rule>) -> Span {
        let s = p.as_span();
        Span::new(self.file, s.start(), s.end())
    }

    fn stmt(&self, p: Pair<Rule>) -> MxResult<Stmt> {
        let span = self.span(&p);
        match p.as_rule() {
            Rule::let_stmt => {
                let mut it = p.into_inner().filter(|q| q.as_rule() != Rule::kw_let);
                let name = it.next().ok_or_else(|| internal(span))?;
                let value = it.next().ok_or_else(|| internal(span))?;
                Ok(Stmt::Let(
                    name.as_str().to_string(),
                    self.span(&name),
                    self.expr(value)?,
                ))
            }
            Rule::fn_stmt => {
                let mut it = p.into_inner().filter(|q| q.as_rule() != Rule::kw_fn);
                let name = it.next().ok_or_else(|| internal(span))?;
                let params = it.next().ok_or_else(|| internal(span))?;
                let body = it.next().ok_or_else(|| internal(span))?;
                let params = self.params(params)?;
                let body = self.body(body)?;
                // The pair also holds the whitespace after the body.
                let span = Span {
                    end: body.span.end,
                    ..span
                };
                let def = FnDef {
                    name: Some(name.as_str().to_string()),
                    params,
                    body,
                    span,
                    text: self.text(span),
                };
                Ok(Stmt::Fn(Arc::new(def)))
            }
            _ => Ok(Stmt::Expr(self.expr(p)?)),
        }
    }

    fn body(&self, p: Pair<Rule>) -> MxResult<Expr> {
        match p.as_rule() {
            Rule::block => self.block(p),
            _ => self.expr(p),
        }
    }

    fn params(&self, p: Pair<Rule>) -> MxResult<Vec<Param>> {
        let mut out: Vec<Param> = Vec::new();
        for q in p.into_inner() {
            let mut it = q.into_inner();
            let Some(name) = it.next() else { continue };
            let span = self.span(&name);
            let name = name.as_str().to_string();
            if out.iter().any(|o| o.name == name) {
                return Err(MxError::new(
                    ErrorKind::Syntax,
                    format!("parameter `{name}` appears twice"),
                )
                .at(span)
                .label("second `{name}`")
                .help("give each parameter a different name"));
            }
            let default = it.next().map(|d| self.expr(d)).transpose()?;
            out.push(Param {
                name,
                span,
                default,
            });
        }
        Ok(out)
    }

    fn block(&self, p: Pair<Rule>) -> MxResult<Expr> {
        let span = self.span(&p);
        let stmts = p
            .into_inner()
            .map(|s| self.stmt(s))
            .collect::<MxResult<Vec<_>>>()?;
        Ok(Expr {
            kind: ExprKind::Block(stmts),
            span,
        })
    }

    fn expr(&self, p: Pair<Rule>) -> MxResult<Expr> {
        // Nested expressions recurse; grow the stack rather than overflow.
        stacker::maybe_grow(64 * 1024, 1024 * 1024, || self.expr_inner(p))
    }

    fn expr_inner(&self, p: Pair<Rule>) -> MxResult<Expr> {
        match p.as_rule() {
            Rule::expr => {}
            Rule::postfix_expr => return self.postfix(p),
            _ => return self.primary(p),
        }
        let file = self.file;
        PRATT
            .map_primary(|q| self.postfix(q))
            .map_prefix(|op, rhs| {
                let rhs = rhs?;
                let s = op.as_span();
                let span = Span::new(file, s.start(), s.end()).to(rhs.span);
                let op = if op.as_rule() == Rule::neg {
                    UnOp::Neg
                } else {
                    UnOp::Not
                };
                // Fold `-2s` into a literal so it prints and compares as one.
                if let (UnOp::Neg, ExprKind::Number(x)) = (op, &rhs.kind) {
                    return Ok(Expr {
                        kind: ExprKind::Number(-x),
                        span,
                    });
                }
                Ok(Expr {
                    kind: ExprKind::Unary(op, Box::new(rhs)),
                    span,
                })
            })
            .map_infix(|lhs, op, rhs| {
                let (lhs, rhs) = (lhs?, rhs?);
                let op = match op.as_rule() {
                    Rule::or_op => BinOp::Or,
                    Rule::and_op => BinOp::And,
                    Rule::eq => BinOp::Eq,
                    Rule::ne => BinOp::Ne,
                    Rule::lt => BinOp::Lt,
                    Rule::le => BinOp::Le,
                    Rule::gt => BinOp::Gt,
                    Rule::ge => BinOp::Ge,
                    Rule::add => BinOp::Add,
                    Rule::sub => BinOp::Sub,
                    Rule::meet => BinOp::Meet,
                    Rule::mul => BinOp::Mul,
                    Rule::div => BinOp::Div,
                    _ => BinOp::Rem,
                };
                let span = lhs.span.to(rhs.span);
                Ok(Expr {
                    kind: ExprKind::Binary(op, Box::new(lhs), Box::new(rhs)),
                    span,
                })
            })
            .parse(p.into_inner())
    }

    fn args(&self, p: Pair<Rule>) -> MxResult<Vec<Arg>> {
        let mut out = Vec::new();
        for a in p.into_inner() {
            if a.as_rule() == Rule::ident {
                continue; // the method name, handled by the caller
            }
            if a.as_rule() == Rule::named_arg {
                let mut it = a.into_inner();
                let name = it.next().ok_or_else(|| internal(Span::default()))?;
                let value = it.next().ok_or_else(|| internal(Span::default()))?;
                out.push(Arg {
                    name: Some((name.as_str().to_string(), self.span(&name))),
                    value: self.expr(value)?,
                });
            } else {
                out.push(Arg {
                    name: None,
                    value: self.expr(a)?,
                });
            }
        }
        Ok(out)
    }

    fn postfix(&self, p: Pair<Rule>) -> MxResult<Expr> {
        let mut it = p.into_inner();
        let first = it.next().ok_or_else(|| internal(Span::default()))?;
        let mut e = self.primary(first)?;
        for post in it {
            let pspan = self.span(&post);
            let span = e.span.to(pspan);
            e = match post.as_rule() {
                Rule::call => Expr {
                    kind: ExprKind::Call(Box::new(e), self.args(post)?),
                    span,
                },
                Rule::method => {
                    let name = post
                        .clone()
                        .into_inner()
                        .next()
                        .ok_or_else(|| internal(pspan))?;
                    let nspan = self.span(&name);
                    let name = name.as_str().to_string();
                    Expr {
                        kind: ExprKind::Method(Box::new(e), name, nspan, self.args(post)?),
                        span,
                    }
                }
                Rule::field => {
                    let name = post.into_inner().next().ok_or_else(|| internal(pspan))?;
                    Expr {
                        kind: ExprKind::Field(
                            Box::new(e),
                            name.as_str().to_string(),
                            self.span(&name),
                        ),
                        span,
                    }
                }
                _ => {
                    let idx = post.into_inner().next().ok_or_else(|| internal(pspan))?;
                    Expr {
                        kind: ExprKind::Index(Box::new(e), Box::new(self.expr(idx)?)),
                        span,
                    }
                }
            };
        }
        Ok(e)
    }

    fn primary(&self, p: Pair<Rule>) -> MxResult<Expr> {
        let span = self.span(&p);
        let kind = match p.as_rule() {
            Rule::number => {
                let mut it = p.into_inner();
                let m = it.next().ok_or_else(|| internal(span))?;
                let x: f64 = m.as_str().parse().map_err(|_| {
                    MxError::new(
                        ErrorKind::Syntax,
                        format!("`{}` is not a number", m.as_str()),
                    )
                    .at(span)
                })?;
                let x = match it.next().map(|u| u.as_str()) {
                    Some("ms") => x / 1000.0,
                    Some("deg") => x.to_radians(),
                    _ => x, // s and rad are the base units
                };
                if !x.is_finite() {
                    return Err(MxError::new(ErrorKind::Syntax, "number too large")
                        .at(span)
                        .help("numbers must fit in a 64-bit float (|x| < 1.8e308)"));
                }
                ExprKind::Number(x)
            }
            Rule::string => {
                let inner = p.into_inner().next().map(|q| q.as_str()).unwrap_or("");
                let s = unescape(inner).map_err(|h| {
                    MxError::new(ErrorKind::Syntax, "invalid escape in string")
                        .at(span)
                        .help(h)
                })?;
                ExprKind::Str(Arc::from(s))
            }
            Rule::boolean => ExprKind::Bool(p.as_str() == "true"),
            Rule::ident => ExprKind::Ident(p.as_str().to_string()),
            Rule::paren => {
                let inner = p.into_inner().next().ok_or_else(|| internal(span))?;
                return Ok(Expr {
                    span,
                    ..self.expr(inner)?
                });
            }
            Rule::list => ExprKind::List(
                p.into_inner()
                    .map(|q| self.expr(q))
                    .collect::<MxResult<_>>()?,
            ),
            Rule::record => {
                let mut fields: Vec<(String, Span, Expr)> = Vec::new();
                for entry in p.into_inner() {
                    let mut it = entry.into_inner();
                    let key = it.next().ok_or_else(|| internal(span))?;
                    let kspan = self.span(&key);
                    let name = if key.as_rule() == Rule::string {
                        let inner = key.into_inner().next().map(|q| q.as_str()).unwrap_or("");
                        unescape(inner).map_err(|h| {
                            MxError::new(ErrorKind::Syntax, "invalid escape in string")
                                .at(kspan)
                                .help(h)
                        })?
                    } else {
                        key.as_str().to_string()
                    };
                    if fields.iter().any(|(k, _, _)| *k == name) {
                        return Err(MxError::new(
                            ErrorKind::Syntax,
                            format!("field `{name}` appears twice in this record"),
                        )
                        .at(kspan)
                        .label("duplicate field")
                        .help("each field of a record has one value; remove or rename one"));
                    }
                    let value = it.next().ok_or_else(|| internal(span))?;
                    fields.push((name, kspan, self.expr(value)?));
                }
                ExprKind::Record(fields)
            }
            Rule::block => return self.block(p),
            Rule::if_expr => {
                let mut it = p.into_inner().filter(|q| q.as_rule() != Rule::kw_else);
                let cond = self.expr(it.next().ok_or_else(|| internal(span))?)?;
                let then = self.block(it.next().ok_or_else(|| internal(span))?)?;
                let els = match it.next() {
                    Some(q) if q.as_rule() == Rule::if_expr => Some(Box::new(self.primary(q)?)),
                    Some(q) => Some(Box::new(self.block(q)?)),
                    None => None,
                };
                ExprKind::If(Box::new(cond), Box::new(then), els)
            }
            Rule::lambda => {
                let mut it = p.into_inner();
                let params = self.params(it.next().ok_or_else(|| internal(span))?)?;
                let body = self.body(it.next().ok_or_else(|| internal(span))?)?;
                // The pair also holds the whitespace after the body.
                let span = Span {
                    end: body.span.end,
                    ..span
                };
                return Ok(Expr {
                    kind: ExprKind::Lambda(Arc::new(FnDef {
                        name: None,
                        params,
                        body,
                        span,
                        text: self.text(span),
                    })),
                    span,
                });
            }
            Rule::expr => return self.expr(p),
            Rule::postfix_expr => return self.postfix(p),
            other => {
                return Err(
                    MxError::new(ErrorKind::Syntax, format!("unexpected {other:?}")).at(span),
                );
            }
        };
        Ok(Expr { kind, span })
    }
}

fn internal(span: Span) -> MxError {
    MxError::new(
        ErrorKind::Syntax,
        "internal parser error: the syntax tree has an unexpected shape",
    )
    .at(span)
    .help("please report this script as a bug")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(src: &str) -> Program {
        match parse_program(src, 0) {
            Ok(p) => p,
            Err(e) => panic!("{src:?}: {e} {:?}", e.span),
        }
    }

    fn show(e: &Expr) -> String {
        match &e.kind {
            ExprKind::Number(x) => format!("{x}"),
            ExprKind::Ident(n) => n.clone(),
            ExprKind::Binary(op, a, b) => format!("({} {} {})", show(a), op.symbol(), show(b)),
            ExprKind::Unary(UnOp::Neg, a) => format!("(-{})", show(a)),
            ExprKind::Unary(UnOp::Not, a) => format!("(!{})", show(a)),
            ExprKind::Call(f, args) => format!(
                "{}({})",
                show(f),
                args.iter()
                    .map(|a| show(&a.value))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            ExprKind::Method(r, n, _, args) => {
                format!(
                    "{}.{}({})",
                    show(r),
                    n,
                    args.iter()
                        .map(|a| show(&a.value))
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            }
            other => format!("{other:?}"),
        }
    }

    fn e(src: &str) -> String {
        match &p(src).stmts[..] {
            [Stmt::Expr(e)] => show(e),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn precedence() {
        assert_eq!(e("a + b * c"), "(a + (b * c))");
        assert_eq!(e("a - b - c"), "((a - b) - c)");
        assert_eq!(e("a + b & c"), "(a + (b & c))");
        assert_eq!(e("a ∧ b − c"), "((a & b) - c)");
        assert_eq!(e("-a * b"), "((-a) * b)");
        assert_eq!(e("a < b + 1 && c || d"), "(((a < (b + 1)) && c) || d)");
        assert_eq!(e("x.only(1).f(2)"), "x.only(1).f(2)");
        assert_eq!(e("a - -b"), "(a - (-b))");
    }

    #[test]
    fn units() {
        assert_eq!(e("2s"), "2");
        assert_eq!(e("250ms"), "0.25");
        assert_eq!(e("180deg"), format!("{}", std::f64::consts::PI));
        assert_eq!(e("1.2rad"), "1.2");
        assert_eq!(e("-2s"), "-2");
        assert!(parse_program("2sin", 0).is_err());
    }

    #[test]
    fn statements_and_newlines() {
        let prog = p(
            "let a = 1; let b = 2\n\n// comment\nfn f(t) = t * 2 /* block\n comment */\nf(a +\n b)\n",
        );
        assert_eq!(prog.stmts.len(), 4);
        let prog = p(
            "let r = {a: 1, \"Hips.Xposition\": 2,\n}\nlet l = [\n1,\n2\n]\nsave(m, \"x.csv\", rate: 30)",
        );
        assert_eq!(prog.stmts.len(), 3);
        let prog = p(
            "if a < 1 { 2 } else if b { 3 } else {\n 4\n}\nlet g = fn(x, y = 2) = x + y\nwalk\n  .only(\"x\")",
        );
        assert_eq!(prog.stmts.len(), 3);
        // A newline ends a statement: `a` then `-1`.
        assert_eq!(p("a\n-1").stmts.len(), 2);
    }

    #[test]
    fn syntax_errors_have_spans_and_help() {
        let err = parse_program("let x = (1 + 2", 0).unwrap_err();
        assert_eq!(err.kind, ErrorKind::Syntax);
        assert!(err.help.is_some());
        let err = parse_program("let = 3", 0).unwrap_err();
        assert_eq!(err.span.map(|s| s.start), Some(4));
        assert!(parse_program("print(\"abc)", 0).is_err());
        assert!(parse_program("{a: 1, a: 2}", 0).is_err());
    }

    #[test]
    fn deep_nesting_does_not_overflow() {
        let src = format!("{}1{}", "(".repeat(5000), ")".repeat(5000));
        let e = parse_program(&src, 0).unwrap_err();
        assert!(e.message.contains("nested"), "{}", e.message);
        for n in [100, MAX_NESTING] {
            let src = format!("{}1{}", "(".repeat(n), ")".repeat(n));
            match parse_program(&src, 0) {
                Ok(_) => {}
                Err(e) => panic!("{n}: {e} {:?} {:?}", e.span, e.help),
            }
        }
        let src = format!("{}1", "-".repeat(5000));
        let _ = parse_program(&src, 0);
    }

    #[test]
    fn long_runs_of_whitespace_and_prefixes_parse() {
        // Whitespace, newlines, comments and prefix operators are loops in
        // the grammar, not recursion: long runs need no deep stack.
        let n = 200_000;
        for src in [
            format!("1{}+ 1", " ".repeat(n)),
            format!("f(1,{}2)", "\n".repeat(n)),
            format!("1{}+ 1", "/**/".repeat(n)),
            format!("{}1", "- ".repeat(n)),
        ] {
            let prog = match parse_program(&src, 0) {
                Ok(p) => p,
                Err(e) => panic!("{}: {e}", &src[..20]),
            };
            assert_eq!(prog.stmts.len(), 1);
        }
    }

    #[test]
    fn incomplete_input() {
        assert!(is_incomplete("f(1,"));
        assert!(is_incomplete("let a = [1,\n2"));
        assert!(is_incomplete("1 +"));
        assert!(!is_incomplete("f(1)"));
        assert!(!is_incomplete("\"abc"));
    }
}
