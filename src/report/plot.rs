//! Log–log work-precision figures as SVG (plotters): one curve per method or
//! setting, the library default marked with a ring and named in the legend;
//! written atomically.

use crate::report::error::ReportError;
use plotters::prelude::*;
use std::path::Path;

/// One curve: `(x, y)` points (x usually wall time), drawn in the order given.
#[derive(Clone, Debug)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    /// Index into `points` of the library default, if this curve contains it.
    pub default_at: Option<usize>,
}

/// A figure: title, axis labels and curves.
#[derive(Clone, Debug)]
pub struct Figure {
    pub file: String,
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
}

impl Figure {
    /// Every plotted number (for the finiteness check of the smoke test).
    pub fn values(&self) -> impl Iterator<Item = f64> + '_ {
        self.series
            .iter()
            .flat_map(|s| s.points.iter().flat_map(|(x, y)| [*x, *y]))
    }
}

pub(super) const COLORS: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
];

/// Log axes need positive values: an exact zero (e.g. an error below
/// round-off) is drawn at `floor` so the point stays visible; the table next
/// to the figure keeps the true number.
fn positive(v: f64, floor: f64) -> f64 {
    if v > floor { v } else { floor }
}

/// Draws `fig` to `dir/fig.file`, written atomically. Errors carry the file name.
pub fn draw(fig: &Figure, dir: &Path) -> Result<(), ReportError> {
    let path = dir.join(&fig.file);
    let Some(ranges) = log_ranges(fig) else {
        return Err(ReportError::EmptyFigure {
            file: fig.file.clone(),
        });
    };
    let e = |err: &dyn std::fmt::Display| ReportError::Draw {
        file: fig.file.clone(),
        message: err.to_string(),
    };
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (760, 520)).into_drawing_area();
        root.fill(&WHITE).map_err(|x| e(&x))?;
        draw_curves(&root, fig, ranges).map_err(|x| e(&x))?;
        root.present().map_err(|x| e(&x))?;
    }
    crate::atomic_file::write(&path, svg.as_bytes())
        .map_err(|source| ReportError::Write { path, source })
}

/// Positive values below this are drawn at it on the log axes.
const LOG_FLOOR: f64 = 1e-16;

/// The axes' ranges: the finite points' (zeros at [`LOG_FLOOR`]) with a
/// decade of margin split around them, so single points still get a range;
/// `None` without a finite point.
fn log_ranges(fig: &Figure) -> Option<((f64, f64), (f64, f64))> {
    let pts: Vec<(f64, f64)> = fig
        .series
        .iter()
        .flat_map(|s| s.points.iter().copied())
        .filter(|(x, y)| x.is_finite() && y.is_finite())
        .collect();
    if pts.is_empty() {
        return None;
    }
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for (x, y) in &pts {
        let (x, y) = (positive(*x, LOG_FLOOR), positive(*y, LOG_FLOOR));
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    Some(((x0 / 2.0, x1 * 2.0), (y0 / 3.0, y1 * 3.0)))
}

/// The chart on `root`: log axes over `ranges`, one line with dots per
/// series, the default ringed, the legend.
fn draw_curves<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    fig: &Figure,
    ((x0, x1), (y0, y1)): ((f64, f64), (f64, f64)),
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let mut chart = ChartBuilder::on(root)
        .caption(&fig.title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(42)
        .y_label_area_size(70)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())?;
    chart
        .configure_mesh()
        .x_desc(&fig.x_label)
        .y_desc(&fig.y_label)
        .x_label_formatter(&|v| format!("{v:.0e}"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()?;
    for (k, s) in fig.series.iter().enumerate() {
        let c = COLORS[k % COLORS.len()];
        let p: Vec<(f64, f64)> = s
            .points
            .iter()
            .filter(|(x, y)| x.is_finite() && y.is_finite())
            .map(|(x, y)| (positive(*x, LOG_FLOOR), positive(*y, LOG_FLOOR)))
            .collect();
        let label = match s.default_at {
            Some(_) => format!("{} (◯ = default)", s.label),
            None => s.label.clone(),
        };
        chart
            .draw_series(LineSeries::new(p.clone(), c.stroke_width(2)))?
            .label(label)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(2)));
        chart.draw_series(p.iter().map(|q| Circle::new(*q, 3, c.filled())))?;
        if let Some(i) = s.default_at
            && let Some(q) = p.get(i)
        {
            chart.draw_series(std::iter::once(Circle::new(*q, 9, BLACK.stroke_width(2))))?;
        }
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()?;
    Ok(())
}
