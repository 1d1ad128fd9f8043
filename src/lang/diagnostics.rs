//! Errors raised while parsing or evaluating mx, and their rendering as miette
//! diagnostics (file name, exact span, label, help line).
//!
//! Internally an error is an [`MxError`]: a message plus a [`Span`] that names
//! its source by id. The interpreter owns the source texts and turns an
//! `MxError` into a [`Diagnostic`] (which implements `miette::Diagnostic`) when
//! it reaches the user.

use std::fmt;
use std::sync::Arc;

use miette::{LabeledSpan, NamedSource, SourceCode};

use super::ast::Span;

/// What went wrong, for callers that react differently (the REPL treats
/// `Cancelled` quietly; tests check the kind).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    Syntax,
    UnknownName,
    Type,
    Arity,
    Value,
    DivisionByZero,
    Recursion,
    StepBudget,
    Cancelled,
    Io,
    Motion,
    Host,
}

impl ErrorKind {
    pub fn code(self) -> &'static str {
        match self {
            ErrorKind::Syntax => "mx::syntax",
            ErrorKind::UnknownName => "mx::unknown_name",
            ErrorKind::Type => "mx::type",
            ErrorKind::Arity => "mx::arity",
            ErrorKind::Value => "mx::value",
            ErrorKind::DivisionByZero => "mx::division_by_zero",
            ErrorKind::Recursion => "mx::recursion",
            ErrorKind::StepBudget => "mx::step_budget",
            ErrorKind::Cancelled => "mx::cancelled",
            ErrorKind::Io => "mx::io",
            ErrorKind::Motion => "mx::motion",
            ErrorKind::Host => "mx::host",
        }
    }
}

/// An error with the span it concerns (if any) and advice for the user.
#[derive(Clone, Debug)]
pub struct MxError {
    pub kind: ErrorKind,
    pub message: String,
    pub span: Option<Span>,
    /// Text printed under the underlined span.
    pub label: Option<String>,
    pub help: Option<String>,
}

pub type MxResult<T> = Result<T, MxError>;

impl MxError {
    pub fn new(kind: ErrorKind, message: impl Into<String>) -> Self {
        MxError {
            kind,
            message: message.into(),
            span: None,
            label: None,
            help: None,
        }
    }
    pub fn at(mut self, span: Span) -> Self {
        self.span = Some(span);
        self
    }
    /// Attach a span only if none is set yet (inner errors know better).
    pub fn or_at(mut self, span: Span) -> Self {
        if self.span.is_none() {
            self.span = Some(span);
        }
        self
    }
    pub fn label(mut self, label: impl Into<String>) -> Self {
        self.label = Some(label.into());
        self
    }
    pub fn help(mut self, help: impl Into<String>) -> Self {
        self.help = Some(help.into());
        self
    }
    pub fn type_error(message: impl Into<String>) -> Self {
        Self::new(ErrorKind::Type, message)
    }
    pub fn value(message: impl Into<String>) -> Self {
        Self::new(ErrorKind::Value, message)
    }
    pub fn host(message: impl Into<String>) -> Self {
        Self::new(ErrorKind::Host, message)
    }
}

impl fmt::Display for MxError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for MxError {}

/// A named source text (file path, `<repl:3>`, `<prelude>`).
#[derive(Clone, Debug)]
pub struct Source {
    pub name: String,
    pub text: Arc<str>,
}

/// A user-facing diagnostic: an [`MxError`] with its source text attached.
#[derive(Debug, Clone)]
pub struct Diagnostic(Box<DiagnosticInner>);

#[derive(Debug, Clone)]
struct DiagnosticInner {
    error: MxError,
    source: Option<NamedSource<Arc<str>>>,
    /// `file:line:col` of the span, for one-line renderings.
    location: Option<String>,
    /// The same place as data.
    place: Option<Location>,
}

/// Where in the source a diagnostic points, as data (so an embedder, such
/// as the Python bindings, never parses the rendered text): lines and
/// columns are 1-based, columns and `span` count characters, `span` is
/// `[start, end)` in the whole source text.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Location {
    /// The source's name: a file path, `<input>`, `<repl:3>`.
    pub file: String,
    pub line: usize,
    pub column: usize,
    pub end_line: usize,
    pub end_column: usize,
    pub span: (usize, usize),
}

impl Diagnostic {
    pub fn new(error: MxError, source: Option<&Source>) -> Self {
        let mut location = None;
        let mut place = None;
        let mut too_wide = false;
        let source = source.and_then(|s| {
            if let Some(span) = error.span {
                let (start, end) = (span.start as usize, span.end as usize);
                let (line, col) = line_col(&s.text, start);
                let (end_line, end_col) = line_col(&s.text, end);
                location = Some(format!("{}:{}:{}", s.name, line, col));
                too_wide = col.max(end_col) > MAX_SNIPPET_COLUMN;
                let chars = |o: usize| {
                    s.text
                        .get(..o.min(s.text.len()))
                        .map_or(0, |b| b.chars().count())
                };
                place = Some(Location {
                    file: s.name.clone(),
                    line,
                    column: col,
                    end_line,
                    end_column: end_col,
                    span: (chars(start), chars(end)),
                });
            }
            // miette pads to the column with a format width, which panics
            // beyond u16::MAX: such lines are named, not drawn.
            (!too_wide).then(|| NamedSource::new(s.name.clone(), s.text.clone()))
        });
        Diagnostic(Box::new(DiagnosticInner {
            error,
            source,
            place,
            location: location.map(|l| {
                if too_wide {
                    format!("{l} (line too long to show)")
                } else {
                    l
                }
            }),
        }))
    }
    pub fn kind(&self) -> ErrorKind {
        self.0.error.kind
    }
    pub fn error(&self) -> &MxError {
        &self.0.error
    }
    /// `file:line:col` of the error's span, if it has one.
    pub fn location(&self) -> Option<&str> {
        self.0.location.as_deref()
    }
    /// The error's place in its source as data, if it points into one.
    pub fn place(&self) -> Option<&Location> {
        self.0.place.as_ref()
    }

    fn add_location_if_not_drawn(&self, out: &mut String) {
        if let (None, Some(loc)) = (&self.0.source, &self.0.location) {
            out.push_str(&format!("  at {loc}\n"));
        }
    }

    /// Render without colour or Unicode art: stable for logs and snapshots.
    pub fn render_plain(&self) -> String {
        let mut out = String::new();
        let handler =
            miette::GraphicalReportHandler::new_themed(miette::GraphicalTheme::unicode_nocolor())
                .with_width(100)
                .with_links(false);
        if handler.render_report(&mut out, self).is_err() {
            return format!("error: {}", self.0.error.message);
        }
        self.add_location_if_not_drawn(&mut out);
        out
    }

    /// Render for a terminal (colours if `color`).
    pub fn render(&self, color: bool) -> String {
        let theme = if color {
            miette::GraphicalTheme::unicode()
        } else {
            miette::GraphicalTheme::unicode_nocolor()
        };
        let handler = miette::GraphicalReportHandler::new_themed(theme)
            .with_width(120)
            .with_links(false);
        let mut out = String::new();
        if handler.render_report(&mut out, self).is_err() {
            return format!("error: {}", self.0.error.message);
        }
        self.add_location_if_not_drawn(&mut out);
        out
    }
}

/// Spans further right than this are reported by location only.
const MAX_SNIPPET_COLUMN: usize = 10_000;

/// 1-based line and column (in characters) of a byte offset.
pub fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(text.len());
    let before = text.get(..offset).unwrap_or("");
    let line = before.matches('\n').count() + 1;
    let col = before
        .rsplit('\n')
        .next()
        .map(|l| l.chars().count())
        .unwrap_or(0)
        + 1;
    (line, col)
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0.error.message)
    }
}

impl std::error::Error for Diagnostic {}

impl miette::Diagnostic for Diagnostic {
    fn code<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        Some(Box::new(self.0.error.kind.code()))
    }
    fn help<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        self.0
            .error
            .help
            .as_ref()
            .map(|h| Box::new(h) as Box<dyn fmt::Display>)
    }
    fn source_code(&self) -> Option<&dyn SourceCode> {
        match (&self.0.source, self.0.error.span) {
            (Some(s), Some(_)) => Some(s as &dyn SourceCode),
            _ => None,
        }
    }
    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        let span = self.0.error.span?;
        self.0.source.as_ref()?;
        let len = span.len();
        let label = LabeledSpan::new(
            self.0.error.label.clone().or_else(|| Some("here".into())),
            span.start as usize,
            len,
        );
        Some(Box::new(std::iter::once(label)))
    }
}

/// The closest candidate to `name` (edit distance), for "did you mean".
pub fn did_you_mean<'a>(
    name: &str,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Option<String> {
    let mut best: Option<(f64, &str)> = None;
    for c in candidates {
        if c == name {
            continue;
        }
        let d = strsim::damerau_levenshtein(&name.to_lowercase(), &c.to_lowercase());
        // Allow roughly one edit per three characters.
        let allowed = (name.chars().count().max(c.chars().count()) / 3).max(1);
        if d <= allowed {
            // A name that is the start of the candidate (or the reverse) was
            // most likely cut short: `fil` means `fill` before `nil`, though
            // both are one edit away.
            let (n, l) = (name.to_lowercase(), c.to_lowercase());
            let prefix = if l.starts_with(&n) || n.starts_with(&l) {
                0.5
            } else {
                0.0
            };
            let score = d as f64 - prefix + (c.len() as f64 - name.len() as f64).abs() * 0.01;
            if best.is_none_or(|(b, _)| score < b) {
                best = Some((score, c));
            }
        }
    }
    best.map(|(_, c)| c.to_string())
}
