//! Static checks for `mx check`, without running: every name used must be
//! bound by a `let`, `fn`, parameter, import or built-in visible at that
//! point; every named argument of a call to a built-in or a known `fn` must
//! be one of its parameters (the built-in's [`Signature`], the one its usage
//! line and `:help` print); every imported script is checked too, its
//! errors pointing into it, and `walks.name` on an import must be one of its
//! names. Method names are not checked here (a record may supply them at
//! run time).

use std::collections::HashMap;

use super::ast::*;
use super::diagnostics::{ErrorKind, MxError, MxResult, did_you_mean};
use super::signature::Signature;

/// What a call may be given by name.
#[derive(Clone, Debug)]
pub struct Callee {
    pub name: String,
    pub params: Vec<String>,
    /// Takes any named argument (`...options`): nothing to check.
    pub open: bool,
    /// The usage line errors show.
    pub usage: String,
}

impl Callee {
    pub fn of_signature(sig: &Signature) -> Callee {
        Callee {
            name: sig.name().to_string(),
            params: sig.params().iter().map(|p| p.to_string()).collect(),
            open: sig.open_named(),
            usage: sig.to_string(),
        }
    }

    pub fn of_fn(def: &FnDef) -> Callee {
        let params: Vec<String> = def.params.iter().map(|p| p.name.clone()).collect();
        let name = def.name.clone().unwrap_or_else(|| "fn".into());
        Callee {
            usage: format!("{name}({})", params.join(", ")),
            name,
            params,
            open: false,
        }
    }
}

/// What a check needs from outside the script.
pub trait Outside {
    /// Whether a global (built-in or already defined) exists.
    fn known(&self, name: &str) -> bool;
    /// Every global name, for suggestions.
    fn names(&self) -> Vec<String>;
    /// What a global function takes, if it is one.
    fn callee(&self, name: &str) -> Option<Callee>;
    /// Check an imported script (reporting its errors itself, or pushing
    /// them to `errors`); its exported names, `None` when it cannot be read.
    fn import(&mut self, imp: &Import, errors: &mut Vec<MxError>) -> Option<Vec<String>>;
}

/// What the checker knows of a local name.
#[derive(Clone, Debug, Default)]
struct Binding {
    /// A `fn` statement: its parameters.
    callee: Option<Callee>,
    /// An import: its names.
    exports: Option<Vec<String>>,
}

pub struct Resolver<'a> {
    scopes: Vec<HashMap<String, Binding>>,
    outside: &'a mut dyn Outside,
    all_known: Vec<String>,
    /// Every error met so far, in source order (an unknown name does not
    /// stop the walk: the names after it are independent).
    errors: Vec<MxError>,
}

impl<'a> Resolver<'a> {
    pub fn new(outside: &'a mut dyn Outside) -> Self {
        let all_known = outside.names();
        Resolver {
            scopes: vec![HashMap::new()],
            outside,
            all_known,
            errors: vec![],
        }
    }

    /// The program's first error, if any.
    pub fn program(&mut self, p: &Program) -> MxResult<()> {
        match self.program_all(p).into_iter().next() {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }

    /// Every error in the program, in source order, so `mx check` reports
    /// them all, not only the script's first. A `let` whose value has an
    /// error still binds its name: its later uses are not errors of their own.
    pub fn program_all(&mut self, p: &Program) -> Vec<MxError> {
        self.stmts(&p.stmts);
        std::mem::take(&mut self.errors)
    }

    fn stmts(&mut self, stmts: &[Stmt]) {
        for s in stmts {
            match s {
                Stmt::Let(n, _, e) => {
                    self.expr(e);
                    self.bind(n, Binding::default());
                }
                Stmt::Fn(def) => {
                    if let Some(n) = &def.name {
                        self.bind(n, fn_binding(def));
                    }
                    self.func(def);
                }
                Stmt::Import(imp) => {
                    let exports = self.outside.import(imp, &mut self.errors);
                    self.bind(
                        &imp.name,
                        Binding {
                            callee: None,
                            exports,
                        },
                    );
                }
                Stmt::Expr(e) => self.expr(e),
            }
        }
    }

    fn bind(&mut self, n: &str, b: Binding) {
        if let Some(s) = self.scopes.last_mut() {
            s.insert(n.to_string(), b);
        }
    }

    /// The innermost local binding of `n`, if any.
    fn local(&self, n: &str) -> Option<&Binding> {
        self.scopes.iter().rev().find_map(|s| s.get(n))
    }

    fn func(&mut self, def: &FnDef) {
        self.scopes.push(HashMap::new());
        if let Some(n) = &def.name {
            self.bind(n, fn_binding(def));
        }
        for p in &def.params {
            if let Some(d) = &p.default {
                self.expr(d);
            }
            self.bind(&p.name, Binding::default());
        }
        self.expr(&def.body);
        self.scopes.pop();
    }

    /// The named arguments of a call to `name` against what it takes.
    fn named_args(&mut self, name: &str, args: &[Arg]) {
        let callee = match self.local(name) {
            Some(b) => b.callee.clone(),
            None => self.outside.callee(name),
        };
        let Some(c) = callee.filter(|c| !c.open) else {
            return;
        };
        for a in args {
            let Some((n, span)) = &a.name else { continue };
            if c.params.iter().any(|p| p == n) {
                continue;
            }
            let e = MxError::new(
                ErrorKind::Arity,
                format!("`{}` has no parameter named `{n}`", c.name),
            )
            .at(*span)
            .label("unknown parameter");
            self.errors
                .push(match did_you_mean(n, c.params.iter().map(String::as_str)) {
                    Some(s) => e.help(format!("did you mean `{s}`? usage: {}", c.usage)),
                    None => e.help(format!("usage: {}", c.usage)),
                });
        }
    }

    fn is_import(&self, e: &Expr) -> bool {
        matches!(&e.kind, ExprKind::Ident(n) if self.local(n).is_some_and(|b| b.exports.is_some()))
    }

    /// `walks.name` where `walks` is an import: one of its names.
    fn import_field(&mut self, recv: &Expr, field: &str, span: Span) {
        let ExprKind::Ident(n) = &recv.kind else {
            return;
        };
        let Some(exports) = self.local(n).and_then(|b| b.exports.clone()) else {
            return;
        };
        if exports.iter().any(|x| x == field) {
            return;
        }
        let e = MxError::value(format!(
            "the script imported as `{n}` has no name `{field}`"
        ))
        .at(span)
        .label("not defined there");
        self.errors.push(
            match did_you_mean(field, exports.iter().map(String::as_str)) {
                Some(s) => e.help(format!("did you mean `{s}`?")),
                None => e.help(format!(
                    "it defines: {} (names starting with `_` stay private)",
                    exports.join(", ")
                )),
            },
        );
    }

    fn name(&mut self, n: &str, span: Span) {
        if self.local(n).is_some() || self.outside.known(n) {
            return;
        }
        let local: Vec<&str> = self
            .scopes
            .iter()
            .flat_map(|s| s.keys().map(String::as_str))
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
                args.iter().for_each(|a| self.expr(&a.value));
                if let ExprKind::Ident(name) = &f.kind {
                    self.named_args(name, args);
                }
            }
            ExprKind::Method(r, name, nspan, args) => {
                self.expr(r);
                args.iter().for_each(|a| self.expr(&a.value));
                // `walks.f(…)` calls the import's own `f`
                if self.is_import(r) {
                    self.import_field(r, name, *nspan);
                } else {
                    self.named_args(name, args);
                }
            }
            ExprKind::Field(r, name, span) => {
                self.expr(r);
                self.import_field(r, name, *span);
            }
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
                self.scopes.push(HashMap::new());
                self.stmts(stmts);
                self.scopes.pop();
            }
        }
    }
}

fn fn_binding(def: &FnDef) -> Binding {
    Binding {
        callee: Some(Callee::of_fn(def)),
        exports: None,
    }
}
