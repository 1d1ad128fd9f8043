//! Static name resolution for `mx check`: every name used must be bound by a
//! `let`, `fn`, parameter or built-in visible at that point. Method names are
//! not checked here (a record may supply them at run time).

use std::collections::HashSet;

use super::ast::*;
use super::diagnostics::{ErrorKind, MxError, MxResult, did_you_mean};

pub struct Resolver<'a> {
    scopes: Vec<HashSet<String>>,
    known: &'a dyn Fn(&str) -> bool,
    all_known: Vec<String>,
    /// Every unknown name met so far, in source order (a use of an unknown
    /// name does not stop the walk: the names after it are independent).
    errors: Vec<MxError>,
}

impl<'a> Resolver<'a> {
    /// `known(name)` says whether a global (built-in or already defined) exists;
    /// `globals` lists them for suggestions.
    pub fn new(known: &'a dyn Fn(&str) -> bool, globals: Vec<String>) -> Self {
        Resolver {
            scopes: vec![HashSet::new()],
            known,
            all_known: globals,
            errors: vec![],
        }
    }

    /// The program's first unknown name, if any.
    pub fn program(&mut self, p: &Program) -> MxResult<()> {
        match self.program_all(p).into_iter().next() {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }

    /// Every use of an unknown name in the program, in source order, so
    /// `mx check` reports them all, not only the script's first. A `let`
    /// whose value has an error still binds its name: its later uses are
    /// not errors of their own.
    pub fn program_all(&mut self, p: &Program) -> Vec<MxError> {
        self.stmts(&p.stmts);
        std::mem::take(&mut self.errors)
    }

    fn stmts(&mut self, stmts: &[Stmt]) {
        for s in stmts {
            match s {
                Stmt::Let(n, _, e) => {
                    self.expr(e);
                    self.bind(n);
                }
                Stmt::Fn(def) => {
                    if let Some(n) = &def.name {
                        self.bind(n);
                    }
                    self.func(def);
                }
                Stmt::Expr(e) => self.expr(e),
            }
        }
    }

    fn bind(&mut self, n: &str) {
        if let Some(s) = self.scopes.last_mut() {
            s.insert(n.to_string());
        }
    }

    fn func(&mut self, def: &FnDef) {
        self.scopes.push(HashSet::new());
        if let Some(n) = &def.name {
            self.bind(n);
        }
        for p in &def.params {
            if let Some(d) = &p.default {
                self.expr(d);
            }
            self.bind(&p.name);
        }
        self.expr(&def.body);
        self.scopes.pop();
    }

    fn name(&mut self, n: &str, span: Span) {
        if self.scopes.iter().any(|s| s.contains(n)) || (self.known)(n) {
            return;
        }
        let local: Vec<&str> = self
            .scopes
            .iter()
            .flat_map(|s| s.iter().map(String::as_str))
            .collect();
        let e = MxError::new(ErrorKind::UnknownName, format!("unknown name `{n}`"))
            .at(span)
            .label("not defined");
        let e = match did_you_mean(
            n,
            local
                .into_iter()
                .chain(self.all_known.iter().map(String::as_str)),
        ) {
            Some(s) => e.help(format!("did you mean `{s}`?")),
            None => e.help(
                "define it first with `let` or `fn`; `:help` in the REPL lists the built-ins",
            ),
        };
        self.errors.push(e);
    }

    fn expr(&mut self, e: &Expr) {
        stacker::maybe_grow(64 * 1024, 1024 * 1024, || self.expr_inner(e))
    }

    fn expr_inner(&mut self, e: &Expr) {
        match &e.kind {
            ExprKind::Number(_) | ExprKind::Str(_) | ExprKind::Bool(_) => {}
            ExprKind::Ident(n) => self.name(n, e.span),
            ExprKind::List(xs) => xs.iter().for_each(|x| self.expr(x)),
            ExprKind::Record(fs) => fs.iter().for_each(|(_, _, x)| self.expr(x)),
            ExprKind::Unary(_, x) => self.expr(x),
            ExprKind::Binary(_, a, b) => {
                self.expr(a);
                self.expr(b)
            }
            ExprKind::Call(f, args) => {
                self.expr(f);
                args.iter().for_each(|a| self.expr(&a.value))
            }
            ExprKind::Method(r, _, _, args) => {
                self.expr(r);
                args.iter().for_each(|a| self.expr(&a.value))
            }
            ExprKind::Field(r, _, _) => self.expr(r),
            ExprKind::Index(r, i) => {
                self.expr(r);
                self.expr(i)
            }
            ExprKind::If(c, t, f) => {
                self.expr(c);
                self.expr(t);
                if let Some(f) = f {
                    self.expr(f);
                }
            }
            ExprKind::Lambda(def) => self.func(def),
            ExprKind::Block(stmts) => {
                self.scopes.push(HashSet::new());
                self.stmts(stmts);
                self.scopes.pop();
            }
        }
    }
}
