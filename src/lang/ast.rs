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
    Expr(Expr),
}

impl Stmt {
    pub fn span(&self) -> Span {
        match self {
            Stmt::Let(_, s, e) => s.to(e.span),
            Stmt::Fn(f) => f.span,
            Stmt::Expr(e) => e.span,
        }
    }
}

#[derive(Clone, Debug)]
pub struct Program {
    pub stmts: Vec<Stmt>,
}
