//! The viewer's ground layers: what `view(…, ground: …)` embeds so the page
//! can show the floor, where feet stand and what holds the body up — every
//! number from the engine, none recomputed in the page.
//!
//! - `floor`: the plane at the floor of the first motion on the page
//!   (`ground`'s recorded floor: the lowest its contact points reach where
//!   it is defined — the capture's, when a fill is overlaid on it), or the
//!   height `floor:` states. Anything below it is drawn under it.
//! - `plan`: footprints. A motion SP filled shows its contact plan (each
//!   stance of `SpReport::contacts` at its anchor, coloured by the stance's
//!   [`Source`]); any other motion shows its own contacts (`ground`'s rule,
//!   one footprint per contact interval at the point's mean position).
//! - `contacts`: the strip under the curves, one row per contact point: when
//!   each motion's point is in contact by `ground`'s rule (within 2 cm of
//!   the page's floor, slower than 0.3 m/s), and when the plan stands it;
//!   inside a planned gap the frames where the two disagree are marked.
//! - `forces`, `residual`: [`crate::ground::ground_forces`] per frame — an
//!   arrow per contact force, scaled by body weight, and the residual force
//!   at the centre of mass. Only these two run dynamics, so they are off
//!   unless asked for.

use super::{Track, ViewerData, ViewerError};
use crate::ground::{
    self, ContactPoint, Floor, GroundForces, GroundOptions, Tracks, contacts_of_tracks,
    default_contact_points, up_of,
};
use crate::model::Model;
use crate::motion::Mu;
use crate::spacetime::contact::ContactPlan;
use serde::Serialize;

/// One of the page's ground layers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Layer {
    Floor,
    Plan,
    Contacts,
    Forces,
    Residual,
}

impl Layer {
    /// Every layer, in the order the page lists them.
    pub const ALL: [Layer; 5] = [
        Layer::Floor,
        Layer::Plan,
        Layer::Contacts,
        Layer::Forces,
        Layer::Residual,
    ];
    /// The layers `ground: true` shows: those that need no dynamics.
    pub const DEFAULT: [Layer; 3] = [Layer::Floor, Layer::Plan, Layer::Contacts];

    /// The name the language, the page and its address use.
    pub fn name(self) -> &'static str {
        match self {
            Layer::Floor => "floor",
            Layer::Plan => "plan",
            Layer::Contacts => "contacts",
            Layer::Forces => "forces",
            Layer::Residual => "residual",
        }
    }

    /// The layer named `name`, if any.
    pub fn parse(name: &str) -> Option<Layer> {
        Layer::ALL.into_iter().find(|l| l.name() == name)
    }

    /// Whether the layer needs the motion's dynamics.
    pub fn needs_dynamics(self) -> bool {
        matches!(self, Layer::Forces | Layer::Residual)
    }
}

/// What a page's ground should show.
#[derive(Clone, Debug, PartialEq)]
pub struct GroundRequest {
    /// The layers shown when the page opens (the page carries these; a layer
    /// that is not asked for is not computed).
    pub layers: Vec<Layer>,
    /// The floor height (m along up); `None`: the first motion's floor.
    pub floor: Option<f64>,
    /// Friction coefficient of the force layers' cones.
    pub friction: f64,
}

impl Default for GroundRequest {
    fn default() -> Self {
        GroundRequest {
            layers: Layer::DEFAULT.to_vec(),
            floor: None,
            friction: 0.8,
        }
    }
}

/// The residual arrow is drawn where the residual force is at least this
/// share of body weight (%): below it the cone solve's own tolerance and a
/// capture's noise are all there is to see.
pub const RESIDUAL_SHOWN: f64 = 1.0;

/// The ground data embedded in the page.
#[derive(Clone, Debug, Serialize)]
pub struct GroundLayer {
    /// The floor's height along the page's up axis (m).
    pub floor: f64,
    /// Contact points by link name: ground's points, then any other point a
    /// plan stands.
    pub points: Vec<String>,
    /// Each point's index among the page's drawn points (`None`: not drawn).
    pub joint: Vec<Option<usize>>,
    /// The layers the page carries, shown when it opens.
    pub on: Vec<Layer>,
    /// Per track, in the page's track order.
    pub tracks: Vec<TrackGround>,
    /// Smallest residual drawn (% of body weight): [`RESIDUAL_SHOWN`].
    pub residual_shown: f64,
}

/// One motion's ground.
#[derive(Clone, Debug, Default, Serialize)]
pub struct TrackGround {
    /// Per point: `[start, stop]` (s) of each run of frames in contact (by
    /// `ground`'s rule on the page's floor); frames where the motion is
    /// undefined are not in contact.
    pub contacts: Vec<Vec<[f64; 2]>>,
    /// The motion's contact plan (SP's), stance by stance; empty for a
    /// motion SP did not fill.
    pub stances: Vec<Footprint>,
    /// The plan's gaps `[t0, t1]`: where the strip compares plan and contact.
    pub gaps: Vec<[f64; 2]>,
    /// The motion's own contact intervals as footprints (source "motion"),
    /// for a motion without a plan.
    pub own: Vec<Footprint>,
    /// The force layers' values, when asked for and computable.
    pub forces: Option<ForceFrames>,
    /// Why a force layer asked for has no values for this motion ("" else).
    pub note: String,
}

/// A footprint: a point standing still over `[t0, t1]` at `at`.
#[derive(Clone, Debug, Serialize)]
pub struct Footprint {
    /// Index into [`GroundLayer::points`].
    pub point: usize,
    pub t0: f64,
    pub t1: f64,
    /// The anchor (m, world); the page draws the print on the floor under it.
    pub at: [f64; 3],
    /// What made it: `Source::name` of a plan, or "motion".
    pub source: &'static str,
}

/// `ground_forces` on the page's frames, rounded to the precision printed:
/// forces and the residual force to 1 mN, moments to 1 mN·m, the centre of
/// mass to 0.1 mm, % BW to 0.001.
#[derive(Clone, Debug, Serialize)]
pub struct ForceFrames {
    /// Body weight (N): an arrow of this force is half the figure's height.
    pub weight: f64,
    /// Per page frame (`None` where the motion's forces have no frame):
    /// 3 numbers per point (its force, N, world), then the residual force
    /// (3, N), the residual moment about the centre of mass (3, N·m), the
    /// centre of mass (3, m) and the residual as % of body weight (1).
    pub frames: Vec<Option<Vec<f64>>>,
}

/// `x` to `decimals` places (the shortest text of the result is short).
fn round_to(x: f64, decimals: i32) -> f64 {
    let scale = 10f64.powi(decimals);
    (x * scale).round() / scale
}

/// The page's ground, or `None` when there is none to show: no gravity, or
/// a body without foot contact points and no plan. `motions` are the page's
/// motions in track order, `plans` each one's contact plan (SP's).
pub fn ground_layer(
    body: &Model,
    motions: &[(&str, &Mu)],
    data: &ViewerData,
    plans: &[Option<&ContactPlan>],
    request: &GroundRequest,
) -> Result<Option<GroundLayer>, ViewerError> {
    let invalid = |e: &dyn std::fmt::Display| ViewerError::Invalid(e.to_string());
    let Some(up) = up_of(&body.default_gravity) else {
        return Ok(None);
    };
    let mut points = default_contact_points(body);
    for plan in plans.iter().flatten() {
        for p in plan.gaps.iter().flat_map(|g| &g.points) {
            if !points.iter().any(|c| c.link == p.link) {
                points.push(ContactPoint {
                    name: p.name.clone(),
                    link: p.link,
                });
            }
        }
    }
    if points.is_empty() || motions.is_empty() {
        return Ok(None);
    }
    let opts = GroundOptions::default();
    let floor = match request.floor {
        Some(f) => f,
        None => match ground::recorded_floor(motions[0].1, body, &points, &opts) {
            Ok(Some(f)) => f,
            // no frame of the first motion has every coordinate: its drawn points
            _ => lowest_drawn(data, &points, &up),
        },
    };
    let joint: Vec<Option<usize>> = points
        .iter()
        .map(|p| data.joint_names.iter().position(|n| *n == p.name))
        .collect();
    let mut tracks = Vec::new();
    for (k, track) in data.tracks.iter().enumerate() {
        let mut tg = TrackGround {
            contacts: track_contacts(data, track, &points, &joint, floor, up)
                .map_err(|e| invalid(&e))?,
            ..TrackGround::default()
        };
        match plans.get(k).copied().flatten() {
            Some(plan) => {
                tg.gaps = plan.gaps.iter().map(|g| [g.t0, g.t1]).collect();
                tg.stances = plan_footprints(plan, &points);
            }
            None => tg.own = own_footprints(&tg.contacts, track, data, &joint),
        }
        if request.layers.iter().any(|l| l.needs_dynamics()) {
            let mut o = opts.clone();
            o.floor = Floor::At(floor);
            o.rate = Some(1.0 / data.frame_time);
            o.points = Some(points.iter().map(|p| p.name.clone()).collect());
            match ground::ground_forces(motions[k].1, body, &o, request.friction) {
                Ok(g) => tg.forces = Some(force_frames(&g, &data.times)),
                Err(e) => tg.note = format!("no forces: {e}"),
            }
        }
        tracks.push(tg);
    }
    Ok(Some(GroundLayer {
        floor,
        points: points.iter().map(|p| p.name.clone()).collect(),
        joint,
        on: request.layers.clone(),
        tracks,
        residual_shown: RESIDUAL_SHOWN,
    }))
}

/// The lowest height the drawn contact points reach on the first track.
fn lowest_drawn(data: &ViewerData, points: &[ContactPoint], up: &nalgebra::Vector3<f64>) -> f64 {
    let idx: Vec<usize> = points
        .iter()
        .filter_map(|p| data.joint_names.iter().position(|n| *n == p.name))
        .collect();
    let lowest = data.tracks[0]
        .positions
        .iter()
        .flat_map(|fr| idx.iter().map(move |&j| fr[j]))
        .map(|p| up.x * p[0] + up.y * p[1] + up.z * p[2])
        .fold(f64::INFINITY, f64::min);
    if lowest.is_finite() { lowest } else { 0.0 }
}

/// A track's contact intervals per point, by `ground`'s rule on the page's
/// frames and floor (the positions the page draws), undefined frames out.
fn track_contacts(
    data: &ViewerData,
    track: &Track,
    points: &[ContactPoint],
    joint: &[Option<usize>],
    floor: f64,
    up: nalgebra::Vector3<f64>,
) -> Result<Vec<Vec<[f64; 2]>>, ground::GroundError> {
    let drawn: Vec<(ContactPoint, usize)> = points
        .iter()
        .zip(joint)
        .filter_map(|(p, j)| j.map(|j| (p.clone(), j)))
        .collect();
    let tr = Tracks {
        points: drawn.iter().map(|(p, _)| p.clone()).collect(),
        times: data.times.clone(),
        frame_time: data.frame_time,
        up,
        positions: track
            .positions
            .iter()
            .map(|fr| drawn.iter().map(|&(_, j)| fr[j].into()).collect())
            .collect(),
    };
    let opts = GroundOptions {
        floor: Floor::At(floor),
        ..GroundOptions::default()
    };
    let c = contacts_of_tracks(&tr, &opts)?;
    let undefined = |k: usize| track.undefined.get(k).copied().unwrap_or(false);
    let mut out = vec![vec![]; points.len()];
    let mut found = c.points.into_iter();
    for (j, slot) in joint.iter().enumerate() {
        if slot.is_none() {
            continue;
        }
        let Some(pc) = found.next() else { break };
        let flags: Vec<bool> = pc
            .in_contact
            .iter()
            .enumerate()
            .map(|(k, &on)| on && !undefined(k))
            .collect();
        out[j] = ground::contacts::runs(&flags, &data.times)
            .iter()
            .map(|i| [i.start, i.stop])
            .collect();
    }
    Ok(out)
}

/// A plan's stances as footprints, in gap and point order (as
/// `sp_report(m).contacts` lists them).
fn plan_footprints(plan: &ContactPlan, points: &[ContactPoint]) -> Vec<Footprint> {
    let mut out = vec![];
    for g in &plan.gaps {
        for p in &g.points {
            let Some(point) = points.iter().position(|c| c.link == p.link) else {
                continue;
            };
            for s in &p.stances {
                out.push(Footprint {
                    point,
                    t0: s.t0,
                    t1: s.t1,
                    at: [s.p0.x, s.p0.y, s.p0.z],
                    source: s.source.name(),
                });
            }
        }
    }
    out
}

/// A motion's own contact intervals as footprints: each at the point's
/// mean drawn position over the interval.
fn own_footprints(
    contacts: &[Vec<[f64; 2]>],
    track: &Track,
    data: &ViewerData,
    joint: &[Option<usize>],
) -> Vec<Footprint> {
    let mut out = vec![];
    for (point, intervals) in contacts.iter().enumerate() {
        let Some(j) = joint[point] else { continue };
        for &[t0, t1] in intervals {
            let frames: Vec<usize> = (0..data.times.len())
                .filter(|&k| data.times[k] >= t0 && data.times[k] <= t1)
                .collect();
            let mut at = [0.0; 3];
            for &k in &frames {
                for (c, a) in at.iter_mut().enumerate() {
                    *a += track.positions[k][j][c] / frames.len() as f64;
                }
            }
            out.push(Footprint {
                point,
                t0,
                t1,
                at,
                source: "motion",
            });
        }
    }
    out
}

/// `g` on the page's frames: the nearest of its frames within half a frame.
fn force_frames(g: &GroundForces, times: &[f64]) -> ForceFrames {
    let frames = times
        .iter()
        .map(|&t| {
            let first = *g.times.first()?;
            let k = ((t - first) / g.frame_time).round();
            if !(k >= 0.0 && k < g.times.len() as f64) {
                return None;
            }
            let k = k as usize;
            if (g.times[k] - t).abs() > 0.5 * g.frame_time {
                return None;
            }
            let mut row = Vec::with_capacity(3 * g.points.len() + 10);
            for f in &g.forces[k] {
                row.extend(f.iter().map(|&x| round_to(x, 3)));
            }
            row.extend(g.residual_force[k].iter().map(|&x| round_to(x, 3)));
            row.extend(g.residual_moment[k].iter().map(|&x| round_to(x, 3)));
            row.extend(g.com[k].iter().map(|&x| round_to(x, 4)));
            row.push(round_to(g.percent_bw(k), 3));
            Some(row)
        })
        .collect();
    ForceFrames {
        weight: g.weight,
        frames,
    }
}

impl GroundLayer {
    /// `Err` when the layer does not fit a page of `tracks` tracks, `points`
    /// drawn points and `frames` frames.
    pub fn check(&self, tracks: usize, points: usize, frames: usize) -> Result<(), ViewerError> {
        let bad = |m: String| Err(ViewerError::Invalid(format!("ground layer: {m}")));
        if !self.floor.is_finite() {
            return bad(format!("floor {} is not finite", self.floor));
        }
        if self.tracks.len() != tracks {
            return bad(format!("{} tracks for {tracks} motions", self.tracks.len()));
        }
        if self.joint.len() != self.points.len()
            || self.joint.iter().flatten().any(|&j| j >= points)
        {
            return bad("a contact point is not among the drawn points".into());
        }
        for t in &self.tracks {
            let prints = t.stances.iter().chain(&t.own);
            if t.contacts.len() != self.points.len()
                || prints.clone().any(|f| f.point >= self.points.len())
            {
                return bad("a footprint or contact row names no contact point".into());
            }
            if prints.flat_map(|f| f.at).any(|x| !x.is_finite()) {
                return bad("a footprint's anchor is not finite".into());
            }
            if let Some(f) = &t.forces {
                let width = 3 * self.points.len() + 10;
                if f.frames.len() != frames
                    || f.frames
                        .iter()
                        .flatten()
                        .any(|r| r.len() != width || r.iter().any(|x| !x.is_finite()))
                {
                    return bad("forces must give one finite row per frame".into());
                }
            }
        }
        Ok(())
    }
}
