//! A self-contained HTML viewer: one file holding the motion (joint world
//! positions per frame, DOF curves) as JSON and a hand-written canvas player
//! (3D stick figure, play/pause, time slider, camera orbit and zoom, DOF curves
//! below). No network, no CDN: the template is `viewer/template.html`.
//!
//! The slider, clock and curves run over the motion's own span (`times`, not
//! from 0), and the pose of a frame is the one sampled at the time shown.
//! Where a motion is undefined its curves have gaps and the figure holds the
//! last defined pose, drawn faded and marked "undefined". Several motions of
//! one body can share the page and its clock ([`overlay`], [`write_overlay`]),
//! each a [`Track`] in its own colour with a legend.
//!
//! After drawing the first frame the page writes `mx-viewer-ok … drawn=N`
//! (N = stage pixels that differ from the background) into its title, or
//! `mx-viewer-error: …` on any script error, so a headless browser can check
//! it. A URL fragment `#t=3.5` opens the page at that time; the title then
//! also names the time and frame shown, which tracks are undefined there and
//! how many pixels each track's colour covers.
//!
//! Camera presets front/side/top (buttons, keys 1/2/3) and the time are in
//! the URL fragment, read on load and kept up to date (`#view=side&t=2.5`),
//! so a view can be shared as a link. Spans a transition filled (SP's
//! report, [`Track::filled`]) are shaded on the curves in their own colour.
//! Which curves are drawn is [`curves`]' choice.

pub mod curves;
pub mod ground;

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
    /// Seconds between frames (the playback rate).
    pub frame_time: f64,
    /// The time of each frame, increasing: the motion's own clock.
    pub times: Vec<f64>,
    /// The motions drawn, all on `times` (at least one).
    pub tracks: Vec<Track>,
    /// Index of the vertical axis (1 for y-up mocap, 2 for z-up robots).
    pub up: usize,
    /// DOF curves drawn below the figure.
    pub curves: Vec<CurveData>,
    /// The floor, footprints, contact strip and forces ([`ground`]); `None`:
    /// a grid at the lowest point drawn.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ground: Option<ground::GroundLayer>,
}

/// One motion on the page.
#[derive(Clone, Debug, Serialize)]
pub struct Track {
    /// Legend label.
    pub label: String,
    /// `positions[frame][point] = [x, y, z]`, metres.
    pub positions: Vec<Vec<[f64; 3]>>,
    /// `undefined[frame]`: the motion is undefined there and the pose is the
    /// last defined one (empty: defined everywhere).
    pub undefined: Vec<bool>,
    /// Spans `[start, stop]` (seconds) a transition filled (SP's gaps):
    /// shaded on the curves, and named in the legend while the clock is in
    /// one (empty: none known).
    pub filled: Vec<[f64; 2]>,
}

/// A DOF curve for the page (the JSON form of a plot [`Series`]).
#[derive(Clone, Debug, Serialize)]
pub struct CurveData {
    pub name: String,
    pub pieces: Vec<Vec<[f64; 2]>>,
    pub gaps: Vec<[f64; 2]>,
    pub conflicts: Vec<[f64; 2]>,
    /// The track whose colour the curve takes when several are shown.
    pub track: usize,
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
            track: 0,
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
    let frames = data.times.len();
    if frames == 0 {
        return Err(ViewerError::Invalid(
            "the motion has no frames to show".into(),
        ));
    }
    if data.times.iter().any(|t| !t.is_finite()) || data.times.windows(2).any(|w| w[1] <= w[0]) {
        return Err(ViewerError::Invalid(
            "frame times must be finite and increasing".into(),
        ));
    }
    if data.tracks.is_empty() {
        return Err(ViewerError::Invalid("no motion to show".into()));
    }
    for tr in &data.tracks {
        if tr.positions.len() != frames {
            return Err(ViewerError::Invalid(format!(
                "`{}` has {} frames for {frames} times",
                tr.label,
                tr.positions.len()
            )));
        }
        if !tr.undefined.is_empty() && tr.undefined.len() != frames {
            return Err(ViewerError::Invalid(format!(
                "`{}` marks {} frames undefined-or-not for {frames} times",
                tr.label,
                tr.undefined.len()
            )));
        }
        if tr
            .filled
            .iter()
            .any(|[a, b]| !(a.is_finite() && b.is_finite() && a <= b))
        {
            return Err(ViewerError::Invalid(format!(
                "`{}` has a filled span that is not [start, stop] with start ≤ stop",
                tr.label
            )));
        }
        if let Some(f) = tr.positions.iter().position(|fr| fr.len() != n) {
            return Err(ViewerError::Invalid(format!(
                "frame {f} has {} points, expected {n}",
                tr.positions[f].len()
            )));
        }
        if tr
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
    }
    if let Some(c) = data.curves.iter().find(|c| c.track >= data.tracks.len()) {
        return Err(ViewerError::Invalid(format!(
            "curve `{}` belongs to track {} of {}",
            c.name,
            c.track,
            data.tracks.len()
        )));
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
    if let Some(g) = &data.ground {
        g.check(data.tracks.len(), n, frames)?;
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
/// the figure the DOF curves `curve_names` (default: the 6 DOFs that move
/// most, see [`curves::most_moving`]).
pub fn from_motion(
    mu: &crate::motion::Mu,
    body: &crate::model::Model,
    title: &str,
    curve_names: &[&str],
) -> Result<ViewerData, ViewerError> {
    overlay(body, &[(title, mu)], title, curve_names)
}

/// Several motions of one body on one page and one clock: the union of their
/// spans sampled at the first motion's frame rate (else 30 Hz) from its start;
/// each motion is a [`Track`] (held and marked undefined outside its own span
/// and in its gaps), and the curves `curve_names` (default: the DOFs that move
/// most in the first motion, 6 for one motion, 3 for several) are drawn per
/// track. Links that carry no mass and never move (Bandai's `joint_Root` at
/// the origin) are left out, so no bone runs to them.
pub fn overlay(
    body: &crate::model::Model,
    motions: &[(&str, &crate::motion::Mu)],
    title: &str,
    curve_names: &[&str],
) -> Result<ViewerData, ViewerError> {
    use crate::mocap::{Missing, positions_at, to_motion::sample_period};
    let invalid = |e: &dyn std::fmt::Display| ViewerError::Invalid(e.to_string());
    let Some(&(_, first)) = motions.first() else {
        return Err(ViewerError::Invalid("no motion to show".into()));
    };
    let mut span: Option<(f64, f64)> = None;
    for (label, mu) in motions {
        let s = mu.span().ok_or_else(|| {
            ViewerError::Invalid(format!("`{label}` is empty: no DOF is defined anywhere"))
        })?;
        span = Some(span.map_or(s, |(a, b)| (a.min(s.0), b.max(s.1))));
    }
    let (t0, t1) = span.unwrap_or((0.0, 0.0));
    let frame_time = sample_period(first).unwrap_or(1.0 / 30.0);
    let frames = (((t1 - t0) / frame_time + 1e-6).floor() as usize).min(1_000_000) + 1;
    let times: Vec<f64> = (0..frames).map(|k| t0 + k as f64 * frame_time).collect();
    let mut tracks = Vec::new();
    let mut points = None;
    for (label, mu) in motions {
        let p = positions_at(mu, body, times.clone(), Missing::Hold).map_err(|e| invalid(&e))?;
        let mut positions: Vec<Vec<[f64; 3]>> = p
            .points
            .iter()
            .map(|fr| fr.iter().map(|v| [v.x, v.y, v.z]).collect())
            .collect();
        // Before its first defined frame a motion shows that frame's pose.
        if let Some(k) = p.undefined.iter().position(|u| !u) {
            for f in 0..k {
                positions[f] = positions[k].clone();
            }
        }
        tracks.push(Track {
            label: label.to_string(),
            positions,
            undefined: p.undefined.clone(),
            filled: vec![],
        });
        points.get_or_insert((p.names, p.parents, p.links));
    }
    let (names, parents, links) = points.unwrap_or_default();
    let (names, parents) = drop_still_massless(body, &links, names, parents, &mut tracks);
    let g = body.default_gravity;
    let up = (0..3)
        .max_by(|&a, &b| g[a].abs().total_cmp(&g[b].abs()))
        .unwrap_or(1);
    let picked: Vec<&str> = if curve_names.is_empty() {
        curves::most_moving(first, &times, if motions.len() > 1 { 3 } else { 6 })
    } else {
        curve_names.to_vec()
    };
    let rate = (1.0 / frame_time).min(120.0);
    let mut curves = Vec::new();
    for (k, (label, mu)) in motions.iter().enumerate() {
        let names: Vec<&str> = picked
            .iter()
            .copied()
            .filter(|n| mu.get(n).is_some())
            .collect();
        let series = super::plot::series_of(mu, &names, rate).map_err(|e| invalid(&e))?;
        curves.extend(series.iter().map(|s| {
            let mut c = CurveData::from(s);
            c.track = k;
            // the angle, not its wraps between −π and π
            if curves::is_angle(&c.name) {
                for piece in &mut c.pieces {
                    let mut v: Vec<f64> = piece.iter().map(|p| p[1]).collect();
                    curves::unwrap(&mut v);
                    for (p, v) in piece.iter_mut().zip(v) {
                        p[1] = v;
                    }
                }
            }
            if motions.len() > 1 {
                c.name = format!("{label}: {}", c.name);
            }
            c
        }));
    }
    Ok(ViewerData {
        title: title.to_string(),
        joint_names: names,
        parents,
        frame_time,
        times,
        tracks,
        up,
        curves,
        ground: None,
    })
}

/// Leaves out points whose link has no mass and stays put in every track
/// (a placeholder such as Bandai's `joint_Root` at the origin); their
/// children hang from the nearest kept ancestor.
fn drop_still_massless(
    body: &crate::model::Model,
    links: &[usize],
    names: Vec<String>,
    parents: Vec<Option<usize>>,
    tracks: &mut [Track],
) -> (Vec<String>, Vec<Option<usize>>) {
    let n = names.len();
    let still = |j: usize| {
        tracks.iter().all(|tr| {
            let p0 = tr.positions[0][j];
            tr.positions
                .iter()
                .all(|fr| (0..3).all(|k| (fr[j][k] - p0[k]).abs() < 1e-9))
        })
    };
    let drop: Vec<bool> = (0..n)
        .map(|j| {
            let l = body.link(links[j]);
            l.inertia.mass == 0.0 && !body.children(links[j]).is_empty() && still(j)
        })
        .collect();
    if !drop.iter().any(|d| *d) || drop.iter().all(|d| *d) {
        return (names, parents);
    }
    let mut index = vec![None; n];
    let mut kept = 0;
    for j in 0..n {
        if !drop[j] {
            index[j] = Some(kept);
            kept += 1;
        }
    }
    let new_parents = (0..n)
        .filter(|&j| !drop[j])
        .map(|j| {
            let mut p = parents[j];
            while let Some(k) = p {
                if !drop[k] {
                    break;
                }
                p = parents[k];
            }
            p.and_then(|k| index[k])
        })
        .collect();
    for tr in tracks.iter_mut() {
        for fr in &mut tr.positions {
            let mut j = 0;
            fr.retain(|_| {
                j += 1;
                !drop[j - 1]
            });
        }
    }
    let names = names
        .into_iter()
        .enumerate()
        .filter(|(j, _)| !drop[*j])
        .map(|(_, s)| s)
        .collect();
    (names, new_parents)
}

/// Writes a page overlaying `motions` (label, motion) of one body with a
/// legend and one shared clock (see [`overlay`]); the curves are the 3 DOFs
/// that move most in the first motion.
pub fn write_overlay(
    path: &Path,
    body: &crate::model::Model,
    motions: &[(&str, &crate::motion::Mu)],
    title: &str,
) -> Result<(), ViewerError> {
    write_html(&overlay(body, motions, title, &[])?, path)
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
            times: vec![2.5, 2.6, 2.7],
            tracks: vec![Track {
                label: "t".into(),
                positions: vec![vec![[0.0, 1.0, 0.0], [0.0, 0.0, 0.0]]; 3],
                undefined: vec![],
                filled: vec![],
            }],
            up: 1,
            curves: vec![],
            ground: None,
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
        d.tracks[0].positions[1].pop();
        assert!(html(&d).unwrap_err().to_string().contains("frame 1"));
        let mut d = tiny();
        d.tracks[0].positions[0][0][0] = f64::NAN;
        assert!(html(&d).is_err());
        let mut d = tiny();
        d.tracks[0].positions.pop();
        assert!(html(&d).unwrap_err().to_string().contains("2 frames for 3"));
        let mut d = tiny();
        d.times[2] = 2.5;
        assert!(html(&d).unwrap_err().to_string().contains("increasing"));
        let mut d = tiny();
        d.tracks[0].undefined = vec![false];
        assert!(html(&d).is_err());
        let mut d = tiny();
        d.tracks.clear();
        assert!(html(&d).is_err());
        let mut d = tiny();
        d.tracks[0].filled = vec![[2.7, 2.6]];
        assert!(html(&d).unwrap_err().to_string().contains("filled span"));
    }
}
