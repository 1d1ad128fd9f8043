//! Building the spanned AST from pest's pairs: statements, expressions, and
//! the operator-precedence loop for binary operators (iterative, so long
//! chains have no depth limit).

use std::sync::Arc;

use pest::iterators::Pair;

use super::grammar::Rule;
use crate::lang::ast::*;
use crate::lang::diagnostics::{ErrorKind, MxError, MxResult};

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

pub struct Builder<'s> {
    pub file: SourceId,
    /// The whole source (spans index it).
    pub src: &'s str,
    /// Where in `src` the text pest parsed starts: pest's positions are
    /// relative to it (non-zero when `mx check` parses statement by statement).
    pub offset: usize,
}

pub(crate) fn unescape(s: &str) -> Result<String, String> {
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
        Span::new(self.file, self.offset + s.start(), self.offset + s.end())
    }

    pub fn stmt(&self, p: Pair<Rule>) -> MxResult<Stmt> {
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
            Rule::import_stmt => self.import(p, span),
            _ => Ok(Stmt::Expr(self.expr(p)?)),
        }
    }

    /// `import "path" as name`; without `as`, the name is the file's stem.
    fn import(&self, p: Pair<Rule>, span: Span) -> MxResult<Stmt> {
        let mut it = p
            .into_inner()
            .filter(|q| !matches!(q.as_rule(), Rule::kw_import | Rule::kw_as));
        let path = it.next().ok_or_else(|| internal(span))?;
        let path_span = self.span(&path);
        let file = match &self.expr(path)?.kind {
            ExprKind::Str(f) => f.clone(),
            _ => return Err(internal(span)),
        };
        let (name, name_span) = match it.next() {
            Some(n) => (n.as_str().to_string(), self.span(&n)),
            None => {
                let stem = std::path::Path::new(file.as_ref())
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_default();
                let is_ident = stem.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_')
                    && stem.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
                if !is_ident {
                    return Err(MxError::new(
                        ErrorKind::Syntax,
                        format!("`{stem}` is not a name the import can be bound to"),
                    )
                    .at(path_span)
                    .label("needs a name")
                    .help(format!("name it: `import \"{file}\" as walks`")));
                }
                (stem, path_span)
            }
        };
        let span = Span {
            end: name_span.end.max(path_span.end),
            ..span
        };
        Ok(Stmt::Import(Import {
            path: file,
            path_span,
            name,
            name_span,
            span,
        }))
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
                Rule::kw_elif => starts.push(self.span(&q).start),
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
                let x = in_base_units(x, it.next().map(|u| u.as_str()));
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

/// A number literal's value with its unit suffix applied: seconds and
/// radians are the base units (`250ms` is 0.25, `90deg` is π/2).
pub(super) fn in_base_units(x: f64, unit: Option<&str>) -> f64 {
    match unit {
        Some("ms") => x / 1000.0,
        Some("deg") => x.to_radians(),
        _ => x, // s and rad are the base units
    }
}
