//! A self-contained HTML viewer: one file holding the motion (joint world
//! positions per frame, DOF curves) as JSON and a hand-written canvas player
//! (3D stick figure, play/pause, time slider, camera orbit and zoom, DOF curves
//! below). No network, no CDN: the template is `viewer/template.html`.
//!
//! After drawing the first frame the page writes `mx-viewer-ok … drawn=N`
//! (N = stage pixels that differ from the background) into its title, or
//! `mx-viewer-error: …` on any script error, so a headless browser can check it.

use super::plot::Series;
use serde::Serialize;
use std::path::Path;

const TEMPLATE: &str = include_str!("viewer/template.html");
const SLOT: &str = "/*MX_DATA*/null";

/// Everything the page shows.
#[derive(Clone, Debug, Serialize)]
pub struct ViewerData {
    pub title: String,
    /// One name per point drawn (joints, then end sites if wanted).
    pub joint_names: Vec<String>,
    /// Parent point of each point (`None` for roots): a bone is drawn to it.
    pub parents: Vec<Option<usize>>,
    /// Seconds between frames.
    pub frame_time: f64,
    /// `positions[frame][point] = [x, y, z]`, metres.
    pub positions: Vec<Vec<[f64; 3]>>,
    /// Index of the vertical axis (1 for y-up mocap, 2 for z-up robots).
    pub up: usize,
    /// DOF curves drawn below the figure.
    pub curves: Vec<CurveData>,
}

/// A DOF curve for the page (the JSON form of a plot [`Series`]).
#[derive(Clone, Debug, Serialize)]
pub struct CurveData {
    pub name: String,
    pub pieces: Vec<Vec<[f64; 2]>>,
    pub gaps: Vec<[f64; 2]>,
    pub conflicts: Vec<[f64; 2]>,
}

impl From<&Series> for CurveData {
    fn from(s: &Series) -> Self {
        CurveData {
            name: s.name.clone(),
            pieces: s
                .pieces
                .iter()
                .map(|p| {
                    p.iter()
                        .filter(|(t, v)| t.is_finite() && v.is_finite())
                        .map(|(t, v)| [*t, *v])
                        .collect()
                })
                .collect(),
            gaps: s.gaps.iter().map(|(a, b)| [*a, *b]).collect(),
            conflicts: s.conflicts.iter().map(|(a, b)| [*a, *b]).collect(),
        }
    }
}

#[derive(Debug, thiserror::Error)]
pub enum ViewerError {
    #[error("cannot make the viewer: {0}")]
    Invalid(String),
    #[error("cannot write {path}: {source}")]
    Io {
        path: std::path::PathBuf,
        #[source]
        source: std::io::Error,
    },
}

/// The HTML text of the viewer.
pub fn html(data: &ViewerData) -> Result<String, ViewerError> {
    let n = data.parents.len();
    if data.joint_names.len() != n {
        return Err(ViewerError::Invalid(format!(
            "{} names for {n} points",
            data.joint_names.len()
        )));
    }
    if let Some((i, p)) = data
        .parents
        .iter()
        .enumerate()
        .find(|(_, p)| p.is_some_and(|p| p >= n))
    {
        return Err(ViewerError::Invalid(format!(
            "point {i} has parent {p:?} out of range"
        )));
    }
    if let Some(f) = data.positions.iter().position(|fr| fr.len() != n) {
        return Err(ViewerError::Invalid(format!(
            "frame {f} has {} points, expected {n}",
            data.positions[f].len()
        )));
    }
    if data
        .positions
        .iter()
        .flatten()
        .flatten()
        .any(|v| !v.is_finite())
    {
        return Err(ViewerError::Invalid(
            "a joint position is not finite (NaN or infinite)".into(),
        ));
    }
    if data.positions.is_empty() {
        return Err(ViewerError::Invalid(
            "the motion has no frames to show".into(),
        ));
    }
    if !(data.frame_time.is_finite() && data.frame_time > 0.0) {
        return Err(ViewerError::Invalid(format!(
            "frame time {} must be positive",
            data.frame_time
        )));
    }
    if data.up > 2 {
        return Err(ViewerError::Invalid(format!(
            "up axis {} must be 0, 1 or 2",
            data.up
        )));
    }
    let json = serde_json::to_string(data).map_err(|e| ViewerError::Invalid(e.to_string()))?;
    // `</script>` (or any `</`) inside the JSON would end the script element.
    let json = json.replace("</", "<\\/");
    Ok(TEMPLATE.replacen(SLOT, &json, 1))
}

/// Writes the viewer to `path`.
pub fn write_html(data: &ViewerData, path: &Path) -> Result<(), ViewerError> {
    let text = html(data)?;
    crate::atomic_file::write(path, text.as_bytes()).map_err(|source| ViewerError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// The viewer of motion `mu` on `body`: joint positions by forward kinematics
/// (coordinates the motion lacks stay 0, gaps hold the last value), and below
/// the figure the DOF curves `curve_names` (default: the 6 DOFs that move most).
pub fn from_motion(
    mu: &crate::motion::Mu,
    body: &crate::model::Model,
    title: &str,
    curve_names: &[&str],
) -> Result<ViewerData, ViewerError> {
    use crate::mocap::{Missing, positions};
    let p = positions(mu, body, None, Missing::Hold)
        .map_err(|e| ViewerError::Invalid(e.to_string()))?;
    let frame_time = if p.times.len() > 1 {
        p.times[1] - p.times[0]
    } else {
        1.0 / 30.0
    };
    let g = body.default_gravity;
    let up = (0..3)
        .max_by(|&a, &b| g[a].abs().total_cmp(&g[b].abs()))
        .unwrap_or(1);
    let names: Vec<&str> = if curve_names.is_empty() {
        // The DOFs with the largest range over the sampled times.
        let mut ranked: Vec<(f64, &str)> = mu
            .dofs
            .iter()
            .map(|(n, d)| {
                let vals: Vec<f64> = p
                    .times
                    .iter()
                    .filter_map(|&t| d.sample_value(n, t).ok().flatten())
                    .collect();
                let lo = vals.iter().copied().fold(f64::INFINITY, f64::min);
                let hi = vals.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                (if hi >= lo { hi - lo } else { 0.0 }, n.as_str())
            })
            .collect();
        ranked.sort_by(|a, b| b.0.total_cmp(&a.0));
        ranked.into_iter().take(6).map(|(_, n)| n).collect()
    } else {
        curve_names.to_vec()
    };
    let rate = 1.0 / frame_time;
    let series = super::plot::series_of(mu, &names, rate.min(120.0))
        .map_err(|e| ViewerError::Invalid(e.to_string()))?;
    Ok(ViewerData {
        title: title.to_string(),
        joint_names: p.names.clone(),
        parents: p.parents.clone(),
        frame_time,
        positions: p
            .points
            .iter()
            .map(|fr| fr.iter().map(|v| [v.x, v.y, v.z]).collect())
            .collect(),
        up,
        curves: series.iter().map(CurveData::from).collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tiny() -> ViewerData {
        ViewerData {
            title: "t</script>".into(),
            joint_names: vec!["a".into(), "b".into()],
            parents: vec![None, Some(0)],
            frame_time: 0.1,
            positions: vec![vec![[0.0, 1.0, 0.0], [0.0, 0.0, 0.0]]; 3],
            up: 1,
            curves: vec![],
        }
    }

    #[test]
    fn embeds_data_without_breaking_the_script() {
        let h = html(&tiny()).unwrap();
        assert!(!h.contains(SLOT));
        assert_eq!(h.matches("</script>").count(), 1);
        assert!(
            !h.contains("http://") && !h.contains("https://"),
            "no network"
        );
    }

    #[test]
    fn rejects_inconsistent_data() {
        let mut d = tiny();
        d.parents[1] = Some(7);
        assert!(html(&d).is_err());
        let mut d = tiny();
        d.positions[1].pop();
        assert!(html(&d).unwrap_err().to_string().contains("frame 1"));
        let mut d = tiny();
        d.positions[0][0][0] = f64::NAN;
        assert!(html(&d).is_err());
        let mut d = tiny();
        d.positions.clear();
        assert!(html(&d).is_err());
    }
}
