//! The report's markdown under construction: numbers (remembered for the
//! smoke test's finiteness check), tables, figures and pending sections.

use super::error::ReportError;
use super::ground_plot::{self, GroundFigure};
use super::plot::{self, Figure};
use std::fmt::Write as _;
use std::path::PathBuf;

/// A number as the report prints it: 4 decimals in [1e-3, 1e4), else 3
/// significant digits in exponent form.
pub(crate) fn g(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else if (1e-3..1e4).contains(&x.abs()) {
        format!("{x:.4}")
    } else {
        format!("{x:.2e}")
    }
}

pub(crate) struct Doc {
    pub md: String,
    pub numbers: Vec<f64>,
    pub figures: Vec<PathBuf>,
    pub pending: Vec<String>,
    /// Where figures are drawn.
    pub out: PathBuf,
}

impl Doc {
    pub fn new(out: PathBuf) -> Doc {
        Doc {
            md: String::new(),
            numbers: Vec::new(),
            figures: Vec::new(),
            pending: Vec::new(),
            out,
        }
    }

    /// A number into the text, remembered for the finiteness check.
    pub fn n(&mut self, x: f64) -> String {
        self.numbers.push(x);
        g(x)
    }

    /// A table's header line and separator.
    pub fn header(&mut self, columns: &[&str]) {
        let _ = writeln!(self.md, "| {} |", columns.join(" | "));
        let _ = writeln!(self.md, "|{}", "---|".repeat(columns.len()));
    }

    /// One table row (numbers in it come from [`Doc::n`]); `|` in a cell is escaped.
    pub fn row(&mut self, cells: &[String]) {
        let cells: Vec<String> = cells.iter().map(|c| c.replace('|', "\\|")).collect();
        let _ = writeln!(self.md, "| {} |", cells.join(" | "));
    }

    pub fn figure(&mut self, f: &Figure) {
        self.numbers.extend(f.values());
        let drawn = plot::draw(f, &self.out);
        self.link_figure(&f.file, &f.title, drawn);
    }

    /// A figure of per-frame ground measures ([`ground_plot`]).
    pub fn ground_figure(&mut self, f: &GroundFigure) {
        self.numbers.extend(f.values());
        let drawn = ground_plot::draw(f, &self.out);
        self.link_figure(&f.file, &f.title, drawn);
    }

    /// The markdown link to a drawn figure, or why it could not be drawn.
    fn link_figure(&mut self, file: &str, title: &str, drawn: Result<(), ReportError>) {
        match drawn {
            Ok(()) => {
                self.figures.push(self.out.join(file));
                let _ = writeln!(self.md, "\n![{title}]({file})\n");
            }
            Err(e) => {
                self.pending.push(format!("figure {file}: {e}"));
                let _ = writeln!(self.md, "\n*Figure {file} could not be drawn: {e}*\n");
            }
        }
    }

    pub fn pending(&mut self, section: &str, why: &str) {
        self.pending.push(format!("{section}: {why}"));
        let _ = writeln!(self.md, "\n**Pending** — {section} did not run: {why}\n");
    }
}
