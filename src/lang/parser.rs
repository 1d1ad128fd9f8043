//! Source text → AST. pest does the tokenising and structure
//! (`grammar/mx.pest`); an operator-precedence loop builds the operator
//! trees; `nesting.rs` bounds pest's recursion before it runs; syntax
//! errors become [`MxError`]s with the span pest reports and a help line.

use std::sync::Arc;

use pest::Parser;
use pest::iterators::Pair;
use pest_derive::Parser;

use super::ast::*;
use super::diagnostics::{ErrorKind, MxError, MxResult};
pub use super::nesting::MAX_NESTING;
use super::nesting::check_nesting;

#[derive(Parser)]
#[grammar = "../grammar/mx.pest"]
struct MxParser;

/// A binary operator and its precedence, lowest first (documented in README.md):
/// `||` < `&&` < comparisons < `+ -` < `& ∧` < `* / %` < unary `- !` < postfix.
/// All binary operators are left-associative.
fn binary_op(rule: Rule) -> Option<(BinOp, u8)> {
    Some(match rule {
        Rule::or_op => (BinOp::Or, 1),
        Rule::and_op => (BinOp::And, 2),
        Rule::eq => (BinOp::Eq, 3),
        Rule::ne => (BinOp::Ne, 3),
        Rule::lt => (BinOp::Lt, 3),
        Rule::le => (BinOp::Le, 3),
        Rule::gt => (BinOp::Gt, 3),
        Rule::ge => (BinOp::Ge, 3),
        Rule::add => (BinOp::Add, 4),
        Rule::sub => (BinOp::Sub, 4),
        Rule::meet => (BinOp::Meet, 5),
        Rule::mul => (BinOp::Mul, 6),
        Rule::div => (BinOp::Div, 6),
        Rule::rem => (BinOp::Rem, 6),
        _ => return None,
    })
}

/// Parse a whole program from source `file`.
pub fn parse_program(src: &str, file: SourceId) -> MxResult<Program> {
    check_nesting(src, file)?;
    // pest recurses once per nesting level, which `check_nesting` bounds;
    // run it on a stack of known size (reserved, not committed) so that
    // bound fits whatever thread we are on (test threads have 2 MB).
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

/// Reserved (not committed) for pest's recursion: [`MAX_NESTING`] levels of
/// the deepest construct took under 1 MB (measured, release and dev), so
/// the bound leaves a wide margin.
const PARSE_STACK: usize = 256 * 1024 * 1024;

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

    /// A flat chain `prefix* operand (infix prefix* operand)*` → a tree, by
    /// operator precedence with explicit stacks: no recursion, so long
    /// chains of operators (`- - - x`, `a + b + …`) need no deep stack.
    fn expr_inner(&self, p: Pair<Rule>) -> MxResult<Expr> {
        match p.as_rule() {
            Rule::expr => {}
            Rule::postfix_expr => return self.postfix(p),
            _ => return self.primary(p),
        }
        let span = self.span(&p);
        let items = p.into_inner();
        // Most expressions are a single operand: no stacks needed.
        let mut single = items.clone();
        if let (Some(q), None) = (single.next(), single.next())
            && q.as_rule() == Rule::postfix_expr
        {
            return self.postfix(q);
        }
        let mut operands: Vec<Expr> = Vec::new();
        let mut pending: Vec<(BinOp, u8)> = Vec::new();
        let mut prefixes: Vec<Pair<Rule>> = Vec::new();
        for q in items {
            match q.as_rule() {
                Rule::neg | Rule::not => prefixes.push(q),
                Rule::postfix_expr => {
                    let mut e = self.postfix(q)?;
                    // The operator nearest the operand applies first.
                    while let Some(op) = prefixes.pop() {
                        e = self.unary(&op, e);
                    }
                    operands.push(e);
                }
                rule => {
                    let (op, prec) = binary_op(rule).ok_or_else(|| internal(span))?;
                    while let Some(&(top, _)) = pending.last().filter(|(_, p)| *p >= prec) {
                        pending.pop();
                        reduce(&mut operands, top).ok_or_else(|| internal(span))?;
                    }
                    pending.push((op, prec));
                }
            }
        }
        while let Some((op, _)) = pending.pop() {
            reduce(&mut operands, op).ok_or_else(|| internal(span))?;
        }
        match (operands.pop(), operands.is_empty()) {
            (Some(e), true) => Ok(e),
            _ => Err(internal(span)),
        }
    }

    fn unary(&self, op: &Pair<Rule>, rhs: Expr) -> Expr {
        let span = self.span(op).to(rhs.span);
        let op = if op.as_rule() == Rule::neg {
            UnOp::Neg
        } else {
            UnOp::Not
        };
        // Fold `-2s` into a literal so it prints and compares as one.
        if let (UnOp::Neg, ExprKind::Number(x)) = (op, &rhs.kind) {
            return Expr {
                kind: ExprKind::Number(-x),
                span,
            };
        }
        Expr {
            kind: ExprKind::Unary(op, Box::new(rhs)),
            span,
        }
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

    /// `if c {…} else if c2 {…} … else {…}`. The grammar reads the `else if`
    /// branches as a loop (so a long chain needs no deep stack); here they
    /// become nested `If`s, each spanning from its `if` to the end of the chain.
    fn if_chain(&self, p: Pair<Rule>, span: Span) -> MxResult<Expr> {
        let mut starts = vec![span.start];
        let mut branches: Vec<(Expr, Expr)> = Vec::new();
        let mut cond = None;
        let mut els = None;
        for q in p.into_inner() {
            match q.as_rule() {
                Rule::kw_else => {}
                Rule::kw_elif => starts.push(q.as_span().start() as u32),
                Rule::expr => cond = Some(self.expr(q)?),
                Rule::block => match cond.take() {
                    Some(c) => branches.push((c, self.block(q)?)),
                    None => els = Some(Box::new(self.block(q)?)),
                },
                _ => return Err(internal(span)),
            }
        }
        if branches.is_empty() || starts.len() != branches.len() || cond.is_some() {
            return Err(internal(span));
        }
        while let (Some((cond, then)), Some(start)) = (branches.pop(), starts.pop()) {
            els = Some(Box::new(Expr {
                kind: ExprKind::If(Box::new(cond), Box::new(then), els),
                span: Span { start, ..span },
            }));
        }
        els.map(|e| *e).ok_or_else(|| internal(span))
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
                let mut e = self.expr(inner)?;
                e.span = span;
                return Ok(e);
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
            Rule::if_expr => return self.if_chain(p, span),
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

/// Replace the top two operands by `a op b` (`None` if there are fewer).
fn reduce(operands: &mut Vec<Expr>, op: BinOp) -> Option<()> {
    let rhs = operands.pop()?;
    let lhs = operands.pop()?;
    let span = lhs.span.to(rhs.span);
    operands.push(Expr {
        kind: ExprKind::Binary(op, Box::new(lhs), Box::new(rhs)),
        span,
    });
    Some(())
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

    /// Runs on the test harness's thread (2 MB stack): deep input must give
    /// the nesting diagnostic, not overflow the stack.
    #[test]
    fn deep_nesting_is_refused_with_a_diagnostic() {
        let n = 100_000;
        for src in [
            format!("{}1{}", "(".repeat(n), ")".repeat(n)),
            format!("{}1", "[".repeat(n)),
            format!("{}1", "{a: ".repeat(n)),
            format!("{}1", "{ ".repeat(n)),
            format!("{}1", "f(".repeat(n)),
            format!("let f = {}1", "fn(x) = ".repeat(n)),
            format!("fn f(x = {}1) = x", "fn(y = ".repeat(n)),
            format!("{}true{}", "if ".repeat(n), " { 1 }".repeat(n)),
            format!("if a {{ {}1", "if b { ".repeat(n)),
        ] {
            let e = parse_program(&src, 0).unwrap_err();
            assert!(e.message.contains("nesting too deep"), "{}", e.message);
            let span = e.span.expect("a span");
            assert!(span.start > 0 && (span.start as usize) < src.len() / 2);
            assert!(e.help.is_some());
        }
    }

    /// At the limit every recursive construct still parses (on the parse
    /// stack, from the harness's 2 MB thread).
    #[test]
    fn nesting_up_to_the_limit_parses() {
        let n = MAX_NESTING;
        for src in [
            format!("{}1{}", "(".repeat(n), ")".repeat(n)),
            format!("{}1{}", "[".repeat(n), "]".repeat(n)),
            format!("{}1{}", "{a: ".repeat(n), "}".repeat(n)),
            format!("{}1{}", "f(".repeat(n), ")".repeat(n)),
            // The last `fn`'s parameter list, the blocks after the last
            // `if`, open one level more.
            format!("{}1", "fn(x) = ".repeat(n - 1)),
            format!("{}true{}", "if ".repeat(n - 1), " { 1 }".repeat(n - 1)),
            format!("{}1{}", "if b { ".repeat(n / 2), " }".repeat(n / 2)),
            format!(
                "{}1{}",
                "-[fn(x) = if x { ".repeat(n / 4),
                " }]".repeat(n / 4)
            ),
        ] {
            if let Err(e) = parse_program(&src, 0) {
                panic!("{}: {e} {:?}", &src[..20], e.span);
            }
        }
    }

    /// Chains of operators, calls and `else if` are loops in the grammar and
    /// in the precedence parser, and the tree drops iteratively: they have
    /// no depth limit.
    #[test]
    fn long_chains_parse_and_drop() {
        let n = 1_000_000;
        let chains = [
            format!("{}x", "-".repeat(n)),
            format!("{}x", "not ".repeat(n)),
            format!("x{}", " + x".repeat(n)),
            format!("x{}", " * -x".repeat(n)),
            format!("f{}", "()".repeat(n)),
            format!("r{}", ".a".repeat(n)),
            format!(
                "if a {{ 1 }}{} else {{ 3 }}",
                " else if b { 2 }".repeat(n / 10)
            ),
        ];
        for src in chains {
            assert_one_statement(&src);
        }
    }

    /// `src` parses to exactly one statement (long inputs: the error names its start).
    fn assert_one_statement(src: &str) {
        match parse_program(src, 0) {
            Ok(p) => assert_eq!(p.stmts.len(), 1),
            Err(e) => panic!("{}: {e}", &src[..20.min(src.len())]),
        }
    }

    #[test]
    fn else_if_chains_nest_from_each_if() {
        let src = "if a { 1 } else if b { 2 } else if c { 3 } else { 4 }";
        let [Stmt::Expr(e)] = &p(src).stmts[..] else {
            panic!()
        };
        let mut node = e;
        for (start, cond) in [(0, "a"), (16, "b"), (32, "c")] {
            let ExprKind::If(c, _, Some(els)) = &node.kind else {
                panic!("{node:?}")
            };
            assert_eq!(
                (node.span.start, node.span.end as usize),
                (start, src.len())
            );
            assert_eq!(show(c), cond);
            node = els;
        }
        assert!(matches!(node.kind, ExprKind::Block(_)));
        let [Stmt::Expr(e)] = &p("if a { 1 } else if b { 2 }").stmts[..] else {
            panic!()
        };
        let ExprKind::If(_, _, Some(inner)) = &e.kind else {
            panic!()
        };
        assert!(matches!(inner.kind, ExprKind::If(_, _, None)));
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
            assert_one_statement(&src);
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
