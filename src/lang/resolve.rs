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
}

impl<'a> Resolver<'a> {
    /// `known(name)` says whether a global (built-in or already defined) exists;
    /// `globals` lists them for suggestions.
    pub fn new(known: &'a dyn Fn(&str) -> bool, globals: Vec<String>) -> Self {
        Resolver {
            scopes: vec![HashSet::new()],
            known,
            all_known: globals,
        }
    }

    pub fn program(&mut self, p: &Program) -> MxResult<()> {
        self.stmts(&p.stmts)
    }

    /// Every top-level statement resolved on its own, so `mx check` reports
    /// each statement's first unknown name, not only the script's first. A
    /// `let` whose value has an error still binds its name: its later uses
    /// are not errors of their own.
    pub fn program_all(&mut self, p: &Program) -> Vec<MxError> {
        let mut errors = vec![];
        for s in &p.stmts {
            if let Err(e) = self.stmts(std::slice::from_ref(s)) {
                errors.push(e);
                if let Stmt::Let(n, _, _) = s {
                    self.bind(n);
                }
            }
        }
        errors
    }

    fn stmts(&mut self, stmts: &[Stmt]) -> MxResult<()> {
        for s in stmts {
            match s {
                Stmt::Let(n, _, e) => {
                    self.expr(e)?;
                    self.bind(n);
                }
                Stmt::Fn(def) => {
                    if let Some(n) = &def.name {
                        self.bind(n);
                    }
                    self.func(def)?;
                }
                Stmt::Expr(e) => self.expr(e)?,
            }
        }
        Ok(())
    }

    fn bind(&mut self, n: &str) {
        if let Some(s) = self.scopes.last_mut() {
            s.insert(n.to_string());
        }
    }

    fn func(&mut self, def: &FnDef) -> MxResult<()> {
        self.scopes.push(HashSet::new());
        if let Some(n) = &def.name {
            self.bind(n);
        }
        let mut r = Ok(());
        for p in &def.params {
            if let Some(d) = &p.default {
                r = r.and_then(|_| self.expr(d));
            }
            self.bind(&p.name);
        }
        let r = r.and_then(|_| self.expr(&def.body));
        self.scopes.pop();
        r
    }

    fn name(&self, n: &str, span: Span) -> MxResult<()> {
        if self.scopes.iter().any(|s| s.contains(n)) || (self.known)(n) {
            return Ok(());
        }
        let local: Vec<&str> = self
            .scopes
            .iter()
            .flat_map(|s| s.iter().map(String::as_str))
            .collect();
        let e = MxError::new(ErrorKind::UnknownName, format!("unknown name `{n}`"))
            .at(span)
            .label("not defined");
        Err(
            match did_you_mean(
                n,
                local
                    .into_iter()
                    .chain(self.all_known.iter().map(String::as_str)),
            ) {
                Some(s) => e.help(format!("did you mean `{s}`?")),
                None => e.help(
                    "define it first with `let` or `fn`; `:help` in the REPL lists the built-ins",
                ),
            },
        )
    }

    fn expr(&mut self, e: &Expr) -> MxResult<()> {
        stacker::maybe_grow(64 * 1024, 1024 * 1024, || self.expr_inner(e))
    }

    fn expr_inner(&mut self, e: &Expr) -> MxResult<()> {
        match &e.kind {
            ExprKind::Number(_) | ExprKind::Str(_) | ExprKind::Bool(_) => Ok(()),
            ExprKind::Ident(n) => self.name(n, e.span),
            ExprKind::List(xs) => xs.iter().try_for_each(|x| self.expr(x)),
            ExprKind::Record(fs) => fs.iter().try_for_each(|(_, _, x)| self.expr(x)),
            ExprKind::Unary(_, x) => self.expr(x),
            ExprKind::Binary(_, a, b) => {
                self.expr(a)?;
                self.expr(b)
            }
            ExprKind::Call(f, args) => {
                self.expr(f)?;
                args.iter().try_for_each(|a| self.expr(&a.value))
            }
            ExprKind::Method(r, _, _, args) => {
                self.expr(r)?;
                args.iter().try_for_each(|a| self.expr(&a.value))
            }
            ExprKind::Field(r, _, _) => self.expr(r),
            ExprKind::Index(r, i) => {
                self.expr(r)?;
                self.expr(i)
            }
            ExprKind::If(c, t, f) => {
                self.expr(c)?;
                self.expr(t)?;
                if let Some(f) = f {
                    self.expr(f)?;
                }
                Ok(())
            }
            ExprKind::Lambda(def) => self.func(def),
            ExprKind::Block(stmts) => {
                self.scopes.push(HashSet::new());
                let r = self.stmts(stmts);
                self.scopes.pop();
                r
            }
        }
    }
}
