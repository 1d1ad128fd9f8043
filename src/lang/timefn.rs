//! mx functions of time as motion curves ([`crate::motion::TimeFunction`]).
//!
//! A curve may be sampled from any thread (rayon, during optimisation), so it
//! carries a [`Context`] (all `Arc`s) and makes a fresh [`Evaluator`] per
//! call. For motion JSON a function must be written as self-contained mx
//! source: its own text, preceded by `let`s for the values it captures
//! (numbers, strings, lists, records and other functions, recursively).

use std::collections::HashSet;
use std::sync::Arc;

use super::ast::*;
use super::eval::{Context, Evaluator};
use super::parser;
use super::value::{Closure, Value};
use crate::motion::{FnError, TimeFunction};

/// Source id used for functions compiled back from a motion file.
pub const COMPILED_SOURCE: SourceId = u32::MAX;

pub struct MxTimeFn {
    f: Value,
    ctx: Context,
}

impl std::fmt::Debug for MxTimeFn {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "MxTimeFn({})", self.f.repr())
    }
}

impl MxTimeFn {
    pub fn new(f: Value, ctx: Context) -> Self {
        MxTimeFn { f, ctx }
    }
    pub fn function(&self) -> &Value {
        &self.f
    }
}

impl TimeFunction for MxTimeFn {
    fn eval(&self, t: f64) -> Result<f64, FnError> {
        let mut ev = Evaluator::new(self.ctx.clone());
        match ev.call(&self.f, vec![Value::Number(t)], Span::default()) {
            Ok(Value::Number(x)) => Ok(x),
            Ok(other) => Err(FnError::Host(format!(
                "the function returned {}, not a number",
                super::args::describe(&other)
            ))),
            Err(e) => Err(FnError::Host(e.message)),
        }
    }

    fn source(&self) -> Option<String> {
        value_source(&self.f, 0)
    }
}

/// Compile self-contained source (as written by [`TimeFunction::source`]) back
/// into a function of time.
pub fn compile(src: &str, ctx: &Context) -> Result<Arc<dyn TimeFunction>, String> {
    let expr = parser::parse_expr(src, COMPILED_SOURCE)
        .map_err(|e| format!("function source does not parse: {}", e.message))?;
    let mut ev = Evaluator::new(ctx.clone());
    let v = ev
        .eval(&expr, &super::value::Env::empty())
        .map_err(|e| format!("function source fails: {}", e.message))?;
    if !v.is_callable() {
        return Err(format!(
            "function source gives {}, not a function",
            super::args::describe(&v)
        ));
    }
    Ok(Arc::new(MxTimeFn::new(v, ctx.clone())))
}

/// mx source that evaluates to `v` in an empty environment, if there is one.
fn value_source(v: &Value, depth: usize) -> Option<String> {
    if depth > 32 {
        return None;
    }
    match v {
        Value::Number(x) if x.is_finite() => Some(super::value::format_number(*x)),
        Value::Number(_) => None,
        Value::Bool(_) | Value::Str(_) | Value::Nil => Some(v.repr()),
        Value::List(l) => {
            let items: Option<Vec<String>> = l.iter().map(|x| value_source(x, depth + 1)).collect();
            Some(format!("[{}]", items?.join(", ")))
        }
        Value::Record(r) => {
            let items: Option<Vec<String>> = r
                .iter()
                .map(|(k, x)| {
                    value_source(x, depth + 1).map(|s| format!("{}: {s}", super::value::quote(k)))
                })
                .collect();
            Some(format!("{{{}}}", items?.join(", ")))
        }
        Value::Builtin(b) => Some(b.name.clone()),
        Value::Function(c) => closure_source(c, depth),
        Value::Object(_) => None,
    }
}

fn closure_source(c: &Closure, depth: usize) -> Option<String> {
    let mut free = Vec::new();
    let mut bound: Vec<HashSet<String>> = vec![HashSet::new()];
    free_in_fn(&c.def, &mut bound, &mut free);
    let mut lets = String::new();
    for name in &free {
        // Captured from the closure's environment; otherwise it must be a
        // built-in (resolved again when compiled).
        if let Some(v) = c.env.get(name) {
            let src = value_source(v, depth + 1)?;
            lets.push_str(&format!("let {name} = {src}\n"));
        }
    }
    let text = c.def.text.trim();
    let body = match &c.def.name {
        Some(n) => format!("{text}\n{n}"),
        None => text.to_string(),
    };
    if lets.is_empty() && c.def.name.is_none() {
        Some(body)
    } else {
        Some(format!("{{\n{lets}{body}\n}}"))
    }
}

fn free_in_fn(def: &FnDef, bound: &mut Vec<HashSet<String>>, free: &mut Vec<String>) {
    let mut scope = HashSet::new();
    if let Some(n) = &def.name {
        scope.insert(n.clone());
    }
    bound.push(scope);
    for p in &def.params {
        if let Some(d) = &p.default {
            free_in(d, bound, free);
        }
        if let Some(s) = bound.last_mut() {
            s.insert(p.name.clone());
        }
    }
    free_in(&def.body, bound, free);
    bound.pop();
}

fn note(name: &str, bound: &[HashSet<String>], free: &mut Vec<String>) {
    if !bound.iter().any(|s| s.contains(name)) && !free.iter().any(|f| f == name) {
        free.push(name.to_string());
    }
}

fn free_in(e: &Expr, bound: &mut Vec<HashSet<String>>, free: &mut Vec<String>) {
    // Operator chains make deep trees: grow the stack rather than overflow.
    stacker::maybe_grow(64 * 1024, 1024 * 1024, || free_in_node(e, bound, free))
}

fn free_in_node(e: &Expr, bound: &mut Vec<HashSet<String>>, free: &mut Vec<String>) {
    match &e.kind {
        ExprKind::Number(_) | ExprKind::Str(_) | ExprKind::Bool(_) => {}
        ExprKind::Ident(n) => note(n, bound, free),
        ExprKind::List(xs) => xs.iter().for_each(|x| free_in(x, bound, free)),
        ExprKind::Record(fs) => fs.iter().for_each(|(_, _, x)| free_in(x, bound, free)),
        ExprKind::Unary(_, x) | ExprKind::Field(x, _, _) => free_in(x, bound, free),
        ExprKind::Binary(_, a, b) | ExprKind::Index(a, b) => {
            free_in(a, bound, free);
            free_in(b, bound, free);
        }
        ExprKind::Call(f, args) => {
            free_in(f, bound, free);
            args.iter().for_each(|a| free_in(&a.value, bound, free));
        }
        ExprKind::Method(r, name, _, args) => {
            free_in(r, bound, free);
            note(name, bound, free);
            args.iter().for_each(|a| free_in(&a.value, bound, free));
        }
        ExprKind::If(c, t, f) => {
            free_in(c, bound, free);
            free_in(t, bound, free);
            if let Some(f) = f {
                free_in(f, bound, free);
            }
        }
        ExprKind::Lambda(def) => free_in_fn(def, bound, free),
        ExprKind::Block(stmts) => {
            bound.push(HashSet::new());
            for s in stmts {
                match s {
                    Stmt::Let(n, _, x) => {
                        free_in(x, bound, free);
                        if let Some(b) = bound.last_mut() {
                            b.insert(n.clone());
                        }
                    }
                    Stmt::Fn(def) => {
                        if let (Some(b), Some(n)) = (bound.last_mut(), &def.name) {
                            b.insert(n.clone());
                        }
                        free_in_fn(def, bound, free);
                    }
                    Stmt::Import(i) => {
                        if let Some(b) = bound.last_mut() {
                            b.insert(i.name.clone());
                        }
                    }
                    Stmt::Expr(x) => free_in(x, bound, free),
                }
            }
            bound.pop();
        }
    }
}
