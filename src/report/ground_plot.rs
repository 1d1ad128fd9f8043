//! A gap's per-frame ground measures as one SVG (plotters): three panels
//! over time — skate, depth below the floor, ground residual — one line per
//! motion (a fill, another fill, the capture), the gap shaded, linear axes
//! from 0 so a motion that never skates or sinks lies on the axis. Written
//! atomically.

use super::error::ReportError;
use super::plot::COLORS;
use crate::score::GroundFrames;
use plotters::prelude::*;
use std::path::Path;

/// One figure: per-frame ground measures of several motions over one window.
#[derive(Clone, Debug)]
pub struct GroundFigure {
    pub file: String,
    pub title: String,
    /// The gap (s): the last frame before it and the first after it, shaded between.
    pub gap: (f64, f64),
    /// (label, its measures over the window).
    pub series: Vec<(String, GroundFrames)>,
}

/// One panel's measure: its axis label and its (time, value) points.
type Measure = (&'static str, fn(&GroundFrames) -> Vec<(f64, f64)>);

const MEASURES: [Measure; 3] = [
    ("skate (cm/s)", |g| {
        // a step's speed is drawn at the frame it ends on
        g.times
            .iter()
            .skip(1)
            .copied()
            .zip(g.skate.iter().copied())
            .collect()
    }),
    ("depth below floor (cm)", |g| {
        g.times
            .iter()
            .copied()
            .zip(g.depth.iter().copied())
            .collect()
    }),
    ("ground residual (% BW)", |g| {
        g.times
            .iter()
            .copied()
            .zip(g.residual.iter().copied())
            .collect()
    }),
];

impl GroundFigure {
    /// Every plotted number (for the report's finiteness check).
    pub fn values(&self) -> impl Iterator<Item = f64> + '_ {
        self.series.iter().flat_map(|(_, g)| {
            MEASURES
                .iter()
                .flat_map(move |(_, pts)| pts(g).into_iter().map(|(_, y)| y))
        })
    }

    /// The time range of every series and the gap.
    fn time_range(&self) -> (f64, f64) {
        let mut r = self.gap;
        for (_, g) in &self.series {
            for &t in &g.times {
                r = (r.0.min(t), r.1.max(t));
            }
        }
        r
    }
}

/// Draws `fig` to `dir/fig.file` (atomically). Errors name the file.
pub fn draw(fig: &GroundFigure, dir: &Path) -> Result<(), ReportError> {
    if !fig.values().any(f64::is_finite) {
        return Err(ReportError::EmptyFigure {
            file: fig.file.clone(),
        });
    }
    let e = |err: &dyn std::fmt::Display| ReportError::Draw {
        file: fig.file.clone(),
        message: err.to_string(),
    };
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (760, 760)).into_drawing_area();
        root.fill(&WHITE).map_err(|x| e(&x))?;
        let root = root
            .titled(&fig.title, ("sans-serif", 16))
            .map_err(|x| e(&x))?;
        for (k, (panel, measure)) in root.split_evenly((3, 1)).iter().zip(MEASURES).enumerate() {
            draw_panel(panel, fig, measure, k == 0).map_err(|x| e(&x))?;
        }
        root.present().map_err(|x| e(&x))?;
    }
    let path = dir.join(&fig.file);
    crate::atomic_file::write(&path, svg.as_bytes())
        .map_err(|source| ReportError::Write { path, source })
}

/// One panel: the measure of every series, the gap shaded, the legend on the first.
fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    fig: &GroundFigure,
    (label, points): Measure,
    legend: bool,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let data: Vec<Vec<(f64, f64)>> = fig
        .series
        .iter()
        .map(|(_, g)| {
            points(g)
                .into_iter()
                .filter(|(t, v)| t.is_finite() && v.is_finite())
                .collect()
        })
        .collect();
    let top = data
        .iter()
        .flatten()
        .map(|(_, v)| *v)
        .fold(0.0, f64::max)
        .max(1e-3)
        * 1.1;
    let (t0, t1) = fig.time_range();
    let mut chart = ChartBuilder::on(area)
        .margin(8)
        .x_label_area_size(30)
        .y_label_area_size(60)
        .build_cartesian_2d(t0..t1, 0.0..top)?;
    chart
        .configure_mesh()
        .x_desc("time (s)")
        .y_desc(label)
        .light_line_style(RGBColor(235, 235, 235))
        .draw()?;
    chart.draw_series(std::iter::once(Rectangle::new(
        [(fig.gap.0, 0.0), (fig.gap.1, top)],
        RGBColor(225, 225, 225).filled(),
    )))?;
    for (k, ((name, _), pts)) in fig.series.iter().zip(data).enumerate() {
        let c = COLORS[k % COLORS.len()];
        chart
            .draw_series(LineSeries::new(pts, c.stroke_width(2)))?
            .label(name.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(2)));
    }
    if legend {
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_figure_of_three_panels_is_written_with_its_gap_shaded() {
        let frames = |scale: f64| GroundFrames {
            times: (0..20).map(|k| k as f64 / 30.0).collect(),
            skate: (1..20).map(|k| scale * k as f64).collect(),
            depth: vec![0.0; 20],
            residual: (0..20).map(|k| scale * (k % 5) as f64).collect(),
        };
        let fig = GroundFigure {
            file: "gap_test.svg".into(),
            title: "a gap".into(),
            gap: (5.0 / 30.0, 15.0 / 30.0),
            series: vec![("SP".into(), frames(1.0)), ("capture".into(), frames(0.5))],
        };
        let dir = std::env::temp_dir().join(format!("mx_ground_plot_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        draw(&fig, &dir).unwrap();
        let svg = std::fs::read_to_string(dir.join("gap_test.svg")).unwrap();
        assert!(svg.contains("#E1E1E1"), "the gap band");
        for label in [
            "skate (cm/s)",
            "depth below floor (cm)",
            "ground residual (% BW)",
        ] {
            assert!(svg.contains(label), "panel {label}");
        }
        assert!(svg.contains("SP") && svg.contains("capture"), "the legend");
        std::fs::remove_dir_all(&dir).unwrap();
        // nothing finite: an error naming the file, no picture
        let empty = GroundFigure {
            series: vec![],
            ..fig
        };
        assert!(matches!(
            draw(&empty, &dir),
            Err(ReportError::EmptyFigure { .. })
        ));
    }
}
