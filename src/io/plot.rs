//! Pictures of DOF curves: an SVG file (plotters' SVG backend, whose text is
//! laid out by an estimate, so no system font is needed) and a quick text plot
//! for the REPL's `:plot`.
//!
//! The input is plain data ([`Series`]); turning a motion unit into series
//! (sampling, finding gaps and conflicts) is the caller's job.

use plotters::prelude::*;
use std::path::Path;

/// One DOF to draw: its defined pieces (each a polyline over time), and the
/// time spans where it is undefined (gaps) or multiply defined (conflicts).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Series {
    pub name: String,
    /// Each piece is a run of (t, value) samples drawn as one line.
    pub pieces: Vec<Vec<(f64, f64)>>,
    /// Undefined spans `(t0, t1)` between defined pieces.
    pub gaps: Vec<(f64, f64)>,
    /// Multiply-defined spans `(t0, t1)`.
    pub conflicts: Vec<(f64, f64)>,
}

/// A plot error with what to do about it.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    #[error("nothing to plot: {0}")]
    Empty(String),
    #[error("cannot draw the plot: {0}")]
    Draw(String),
    #[error("cannot write {path}: {source}")]
    Io {
        path: std::path::PathBuf,
        #[source]
        source: std::io::Error,
    },
}

/// A colour per series, cycling through a fixed palette (readable on white).
fn colour(i: usize) -> RGBColor {
    const P: [(u8, u8, u8); 10] = [
        (31, 119, 180),
        (255, 127, 14),
        (44, 160, 44),
        (214, 39, 40),
        (148, 103, 189),
        (140, 86, 75),
        (227, 119, 194),
        (127, 127, 127),
        (188, 189, 34),
        (23, 190, 207),
    ];
    let (r, g, b) = P[i % P.len()];
    RGBColor(r, g, b)
}

/// Time and value ranges over all series (gaps and conflicts count for time).
fn bounds(series: &[Series]) -> Option<((f64, f64), (f64, f64))> {
    let mut t = (f64::INFINITY, f64::NEG_INFINITY);
    let mut v = (f64::INFINITY, f64::NEG_INFINITY);
    for s in series {
        for (a, b) in s.pieces.iter().flatten() {
            if a.is_finite() && b.is_finite() {
                t = (t.0.min(*a), t.1.max(*a));
                v = (v.0.min(*b), v.1.max(*b));
            }
        }
        for (a, b) in s.gaps.iter().chain(&s.conflicts) {
            if a.is_finite() && b.is_finite() {
                t = (t.0.min(*a), t.1.max(*b));
            }
        }
    }
    if !t.0.is_finite() {
        return None;
    }
    if !v.0.is_finite() {
        v = (-1.0, 1.0);
    }
    // A constant curve or a single instant still gets a visible range.
    if t.1 - t.0 < 1e-12 {
        t = (t.0 - 0.5, t.1 + 0.5);
    }
    let pad = ((v.1 - v.0) * 0.05).max(1e-6);
    Some((t, (v.0 - pad, v.1 + pad)))
}

/// The SVG text of a plot of `series` (width × height pixels).
pub fn svg(series: &[Series], title: &str, width: u32, height: u32) -> Result<String, PlotError> {
    let ((t0, t1), (v0, v1)) = bounds(series).ok_or_else(|| {
        PlotError::Empty("no DOF has a defined sample; choose DOFs with motion".into())
    })?;
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (width.max(200), height.max(150)))
            .into_drawing_area();
        let e = |e: &dyn std::fmt::Display| PlotError::Draw(e.to_string());
        root.fill(&WHITE).map_err(|x| e(&x))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 18))
            .margin(10)
            .x_label_area_size(30)
            .y_label_area_size(50)
            .build_cartesian_2d(t0..t1, v0..v1)
            .map_err(|x| e(&x))?;
        chart
            .configure_mesh()
            .x_desc("time (s)")
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(|x| e(&x))?;
        // Gaps: light grey bands; conflicts: light red bands with a red edge.
        for s in series {
            for (a, b) in &s.gaps {
                chart
                    .draw_series(std::iter::once(Rectangle::new(
                        [(*a, v0), (*b, v1)],
                        RGBColor(225, 225, 225).filled(),
                    )))
                    .map_err(|x| e(&x))?;
            }
            for (a, b) in &s.conflicts {
                chart
                    .draw_series(std::iter::once(Rectangle::new(
                        [(*a, v0), (*b, v1)],
                        RGBColor(255, 200, 200).filled(),
                    )))
                    .map_err(|x| e(&x))?;
                chart
                    .draw_series(std::iter::once(Rectangle::new(
                        [(*a, v0), (*b, v1)],
                        RED.stroke_width(1),
                    )))
                    .map_err(|x| e(&x))?;
            }
        }
        for (i, s) in series.iter().enumerate() {
            let c = colour(i);
            let mut first = true;
            for piece in &s.pieces {
                let pts: Vec<(f64, f64)> = piece
                    .iter()
                    .copied()
                    .filter(|(a, b)| a.is_finite() && b.is_finite())
                    .collect();
                let drawn = chart
                    .draw_series(LineSeries::new(pts, c.stroke_width(2)))
                    .map_err(|x| e(&x))?;
                if first {
                    drawn.label(s.name.clone()).legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 16, y)], c.stroke_width(2))
                    });
                    first = false;
                }
            }
        }
        if series.len() <= 12 {
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .draw()
                .map_err(|x| e(&x))?;
        }
        root.present().map_err(|x| e(&x))?;
    }
    Ok(out)
}

/// Writes the plot to `path` as SVG.
pub fn write_svg(series: &[Series], title: &str, path: &Path) -> Result<(), PlotError> {
    let text = svg(series, title, 960, 540)?;
    crate::atomic_file::write(path, text.as_bytes()).map_err(|source| PlotError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// A text plot (`width` × `height` characters) for a terminal: one letter per
/// series (a, b, c…), `░` over gaps and `!` over conflicts, with the value
/// range and a legend. Returns a clear message instead of a plot when there
/// is nothing to draw.
pub fn terminal(series: &[Series], width: usize, height: usize) -> String {
    let (w, h) = (width.clamp(10, 400), height.clamp(3, 200));
    let Some(((t0, t1), (v0, v1))) = bounds(series) else {
        return "nothing to plot: no DOF has a defined sample".into();
    };
    let mut grid = vec![vec![' '; w]; h];
    let col = |t: f64| {
        (((t - t0) / (t1 - t0)) * (w - 1) as f64)
            .round()
            .clamp(0.0, (w - 1) as f64) as usize
    };
    let row = |v: f64| {
        (h - 1)
            - (((v - v0) / (v1 - v0)) * (h - 1) as f64)
                .round()
                .clamp(0.0, (h - 1) as f64) as usize
    };
    for s in series {
        for (a, b) in &s.gaps {
            grid[h - 1][col(*a)..=col(*b)].fill('░');
        }
        for (a, b) in &s.conflicts {
            grid[h - 1][col(*a)..=col(*b)].fill('!');
        }
    }
    for (i, s) in series.iter().enumerate() {
        let mark = (b'a' + (i % 26) as u8) as char;
        for piece in &s.pieces {
            for (t, v) in piece {
                if t.is_finite() && v.is_finite() {
                    grid[row(*v)][col(*t)] = mark;
                }
            }
        }
    }
    let mut out = String::new();
    for (r, line) in grid.iter().enumerate() {
        let label = if r == 0 {
            format!("{v1:>10.4} ┤")
        } else if r == h - 1 {
            format!("{v0:>10.4} ┤")
        } else {
            format!("{:>10} │", "")
        };
        out.push_str(&label);
        out.extend(line.iter());
        out.push('\n');
    }
    out.push_str(&format!(
        "{:>10}  {t0:<.3} s{:>pad$}{t1:.3} s\n",
        "",
        "",
        pad = w.saturating_sub(16)
    ));
    for (i, s) in series.iter().enumerate() {
        out.push_str(&format!(
            "  {} = {}\n",
            (b'a' + (i % 26) as u8) as char,
            s.name
        ));
    }
    out
}

/// The series of DOFs of a motion: each interval sampled at `rate` Hz (plus
/// its ends); gaps and conflicts as the DOF reports them. Conflict intervals
/// draw no curve (the value there is not defined), only their band.
pub fn series_of(
    mu: &crate::motion::Mu,
    names: &[&str],
    rate: f64,
) -> Result<Vec<Series>, PlotError> {
    if !(rate.is_finite() && rate > 0.0) {
        return Err(PlotError::Empty(format!(
            "sampling rate must be positive, got {rate}"
        )));
    }
    let mut out = Vec::with_capacity(names.len());
    for &name in names {
        let dof = mu.dof(name).map_err(|e| PlotError::Empty(e.to_string()))?;
        let mut pieces = Vec::new();
        for iv in dof.intervals.iter().filter(|i| !i.is_conflict()) {
            let n = (((iv.stop - iv.start) * rate).ceil() as usize).clamp(1, 100_000);
            let mut piece = Vec::with_capacity(n + 1);
            for k in 0..=n {
                let t = iv.start + (iv.stop - iv.start) * k as f64 / n as f64;
                let v = iv.funcs[0]
                    .value(t)
                    .map_err(|e| PlotError::Draw(format!("{name} at t = {t}: {e}")))?;
                piece.push((t, v));
            }
            pieces.push(piece);
        }
        out.push(Series {
            name: name.to_string(),
            pieces,
            gaps: dof.gaps(),
            conflicts: dof.conflicts(),
        });
    }
    Ok(out)
}

/// `plot(m, "file.svg")`: the chosen DOFs (all when `names` is empty) of a
/// motion over time, sampled at `rate` Hz, with gaps and conflicts marked.
pub fn plot_motion(
    mu: &crate::motion::Mu,
    names: &[&str],
    rate: f64,
    path: &Path,
) -> Result<(), PlotError> {
    let all: Vec<&str> = mu.names().collect();
    let chosen = if names.is_empty() {
        all.as_slice()
    } else {
        names
    };
    if chosen.is_empty() {
        return Err(PlotError::Empty("the motion has no DOFs".into()));
    }
    let series = series_of(mu, chosen, rate)?;
    let title = if chosen.len() == 1 {
        chosen[0].to_string()
    } else {
        format!("{} DOFs", chosen.len())
    };
    write_svg(&series, &title, path)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sine() -> Series {
        Series {
            name: "Hips.Yrotation".into(),
            pieces: vec![
                (0..50)
                    .map(|i| (i as f64 * 0.02, (i as f64 * 0.2).sin()))
                    .collect(),
                (75..100)
                    .map(|i| (i as f64 * 0.02, (i as f64 * 0.2).sin()))
                    .collect(),
            ],
            gaps: vec![(1.0, 1.5)],
            conflicts: vec![(1.7, 1.8)],
        }
    }

    #[test]
    fn svg_has_curve_gap_conflict_and_label() {
        let s = svg(&[sine()], "test", 800, 400).unwrap();
        assert!(s.starts_with("<svg"));
        assert!(s.contains("Hips.Yrotation"));
        assert!(s.contains("polyline"), "curve drawn as a polyline");
        // Gap band (grey) and conflict band (light red).
        assert!(s.contains("#E1E1E1"), "gap band");
        assert!(s.contains("#FFC8C8"), "conflict band");
    }

    #[test]
    fn empty_and_degenerate_inputs() {
        assert!(matches!(svg(&[], "x", 100, 100), Err(PlotError::Empty(_))));
        let one = Series {
            name: "c".into(),
            pieces: vec![vec![(1.0, 2.0)]],
            ..Default::default()
        };
        assert!(svg(std::slice::from_ref(&one), "one point", 400, 300).is_ok());
        let nan = Series {
            name: "n".into(),
            pieces: vec![vec![(0.0, f64::NAN), (1.0, 1.0)]],
            ..Default::default()
        };
        assert!(svg(&[nan], "nan", 400, 300).is_ok());
        assert!(terminal(&[], 40, 10).contains("nothing to plot"));
        assert!(terminal(&[one], 40, 10).contains("c"));
    }

    #[test]
    fn terminal_plot_marks_curve_and_gap() {
        let t = terminal(&[sine()], 60, 12);
        assert!(t.contains('a'));
        assert!(t.contains('░'));
        assert!(t.contains('!'));
        assert!(t.contains("a = Hips.Yrotation"));
        assert_eq!(t.lines().count(), 12 + 2);
    }
}
