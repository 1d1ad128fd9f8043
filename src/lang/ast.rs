//! The abstract syntax tree. Every node keeps the byte span of the source it
//! came from (and which source file), so diagnostics can point at the exact
//! offending sub-expression.

use std::sync::Arc;

/// Identifies one source text registered with the interpreter (a file, a REPL
/// line, the prelude). Spans carry it so errors raised inside a function
/// defined in another file still point into the right text.
pub type SourceId = u32;

/// A byte range `[start, end)` in source `file`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
pub struct Span {
    pub file: SourceId,
    pub start: u32,
    pub end: u32,
}

impl Span {
    pub fn new(file: SourceId, start: usize, end: usize) -> Self {
        Span {
            file,
            start: start as u32,
            end: end as u32,
        }
    }
    /// The smallest span covering both (same file assumed).
    pub fn to(self, other: Span) -> Span {
        Span {
            file: self.file,
            start: self.start.min(other.start),
            end: self.end.max(other.end),
        }
    }
    pub fn len(&self) -> usize {
        (self.end - self.start) as usize
    }
    pub fn is_empty(&self) -> bool {
        self.end == self.start
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BinOp {
    Or,
    And,
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
    /// `+`: arithmetic on numbers, union on motions, concatenation on strings/lists.
    Add,
    /// `-` / `−`: arithmetic on numbers, difference on motions.
    Sub,
    /// `&` / `∧`: intersection on motions.
    Meet,
    Mul,
    Div,
    Rem,
}

impl BinOp {
    pub fn symbol(self) -> &'static str {
        match self {
            BinOp::Or => "||",
            BinOp::And => "&&",
            BinOp::Eq => "==",
            BinOp::Ne => "!=",
            BinOp::Lt => "<",
            BinOp::Le => "<=",
            BinOp::Gt => ">",
            BinOp::Ge => ">=",
            BinOp::Add => "+",
            BinOp::Sub => "-",
            BinOp::Meet => "&",
            BinOp::Mul => "*",
            BinOp::Div => "/",
            BinOp::Rem => "%",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnOp {
    Neg,
    Not,
}

#[derive(Clone, Debug)]
pub struct Expr {
    pub kind: ExprKind,
    pub span: Span,
}

/// Dropped iteratively: a chain of operators or calls (`a + b + …` with a
/// million terms, `- - … x`, `f()()…`, a long `else if` chain) is as deep as
/// it is long, and the derived recursive drop would overflow the stack.
/// (Brackets, `if` and `fn` nest at most `MAX_NESTING` deep: the parser
/// refuses more, so the `Vec` and `Block` children may drop recursively.)
impl Drop for Expr {
    fn drop(&mut self) {
        let mut pending = Vec::new();
        detach_chain(&mut self.kind, &mut pending);
        while let Some(mut e) = pending.pop() {
            detach_chain(&mut e.kind, &mut pending);
        }
    }
}

/// Move the boxed operands of `kind` that have boxed operands themselves
/// into `out`, leaving leaves behind.
fn detach_chain(kind: &mut ExprKind, out: &mut Vec<Expr>) {
    let mut take = |e: &mut Box<Expr>| {
        if has_chain(&e.kind) {
            let leaf = ExprKind::Bool(false);
            out.push(Expr {
                kind: std::mem::replace(&mut e.kind, leaf),
                span: e.span,
            });
        }
    };
    match kind {
        ExprKind::Unary(_, a)
        | ExprKind::Call(a, _)
        | ExprKind::Method(a, ..)
        | ExprKind::Field(a, ..) => take(a),
        ExprKind::Binary(_, a, b) | ExprKind::Index(a, b) => {
            take(a);
            take(b);
        }
        ExprKind::If(c, t, e) => {
            take(c);
            take(t);
            if let Some(e) = e {
                take(e);
            }
        }
        _ => {}
    }
}

fn has_chain(kind: &ExprKind) -> bool {
    matches!(
        kind,
        ExprKind::Unary(..)
            | ExprKind::Call(..)
            | ExprKind::Method(..)
            | ExprKind::Field(..)
            | ExprKind::Binary(..)
            | ExprKind::Index(..)
            | ExprKind::If(..)
    )
}

/// A call argument: positional (`name == None`) or named (`rate: 30`).
#[derive(Clone, Debug)]
pub struct Arg {
    pub name: Option<(String, Span)>,
    pub value: Expr,
}

#[derive(Clone, Debug)]
pub struct Param {
    pub name: String,
    pub span: Span,
    pub default: Option<Expr>,
}

/// A function literal (named or anonymous), shared by every closure made from it.
#[derive(Debug)]
pub struct FnDef {
    pub name: Option<String>,
    pub params: Vec<Param>,
    pub body: Expr,
    pub span: Span,
    /// The definition's own source text (`fn(t) = …`), so a function can be
    /// written out (motion JSON) and compiled again.
    pub text: Arc<str>,
}

#[derive(Clone, Debug)]
pub enum ExprKind {
    Number(f64),
    Str(Arc<str>),
    Bool(bool),
    Ident(String),
    List(Vec<Expr>),
    Record(Vec<(String, Span, Expr)>),
    Unary(UnOp, Box<Expr>),
    Binary(BinOp, Box<Expr>, Box<Expr>),
    Call(Box<Expr>, Vec<Arg>),
    /// `recv.name(args)`: a record's callable field, else `name(recv, args…)`.
    Method(Box<Expr>, String, Span, Vec<Arg>),
    Field(Box<Expr>, String, Span),
    Index(Box<Expr>, Box<Expr>),
    If(Box<Expr>, Box<Expr>, Option<Box<Expr>>),
    Lambda(Arc<FnDef>),
    Block(Vec<Stmt>),
}

#[derive(Clone, Debug)]
pub enum Stmt {
    Let(String, Span, Expr),
    Fn(Arc<FnDef>),
    Import(Import),
    Expr(Expr),
}

/// `import "walks.mx" as walks`: binds `name` to the record of the script's
/// top-level names (those not starting with `_`).
#[derive(Clone, Debug)]
pub struct Import {
    /// The file as written, relative to the importing script's folder.
    pub path: Arc<str>,
    pub path_span: Span,
    /// `as name`, else the file's stem (`walks` for "lib/walks.mx").
    pub name: String,
    pub name_span: Span,
    pub span: Span,
}

impl Stmt {
    pub fn span(&self) -> Span {
        match self {
            Stmt::Let(_, s, e) => s.to(e.span),
            Stmt::Fn(f) => f.span,
            Stmt::Import(i) => i.span,
            Stmt::Expr(e) => e.span,
        }
    }
}

#[derive(Clone, Debug)]
pub struct Program {
    pub stmts: Vec<Stmt>,
}
