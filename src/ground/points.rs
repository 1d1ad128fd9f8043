//! Contact points, their world positions over a motion, and the floor.
//!
//! Default contact points are a body's ankle and toe joints (Bandai's
//! `Foot_L/R`, `Toes_L/R`; CMU's `LeftFoot`, `LeftToeBase`; OpenSim's
//! `calcn_r`, `toes_r`): the reported joint points (`model::topology::
//! joint_points`) whose name contains `foot`, `toe`, `ankle`, `heel` or
//! `calcn`, case-insensitive, End Sites (`….end`) excluded — the definition
//! of `data/inbetween/README.md`'s ground measures, which use joints, not
//! the toe tips. A caller may name any links instead.
//!
//! "Up" and the floor are [`super::floor`]'s; a point's height is its
//! position along up.

use super::floor::{horizontal, up_direction};
use super::stance::{CONTACT_HEIGHT, CONTACT_SPEED};
use super::{GroundError, invalid, invalid_option};
use crate::model::Model;
use crate::model::topology::{is_foot_name, joint_points};
use crate::motion::{Mu, grid_times, sample_period};
use nalgebra::Vector3;

/// A point that can touch the floor: the origin of a link.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactPoint {
    /// The link's name (as `positions` reports it).
    pub name: String,
    /// Link index in the body.
    pub link: usize,
}

/// Where the floor is.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum Floor {
    /// The lowest height any contact point reaches over the motion.
    #[default]
    Auto,
    /// This height (metres, along up).
    At(f64),
}

/// The options every ground measure shares.
#[derive(Clone, Debug, PartialEq)]
pub struct GroundOptions {
    /// Link names of the contact points; `None`: [`default_contact_points`].
    pub points: Option<Vec<String>>,
    pub floor: Floor,
    /// A point is on the floor while within this height of it (m). Default
    /// [`CONTACT_HEIGHT`].
    pub height: f64,
    /// ... and while its horizontal speed is below this (m/s); `f64::INFINITY`
    /// turns the speed test off. Only [`super::contacts()`] uses it; skate and
    /// the residual use height alone, as the README defines them. Default
    /// [`CONTACT_SPEED`].
    pub speed: f64,
    /// Gravity (m/s²); `None`: the model's default gravity.
    pub gravity: Option<Vector3<f64>>,
    /// Sampling rate (Hz); `None`: the motion's frame rate, else 30 Hz.
    pub rate: Option<f64>,
}

impl Default for GroundOptions {
    fn default() -> Self {
        GroundOptions {
            points: None,
            floor: Floor::Auto,
            height: CONTACT_HEIGHT,
            speed: CONTACT_SPEED,
            gravity: None,
            rate: None,
        }
    }
}

impl GroundOptions {
    /// `Err` naming the first option out of range.
    pub fn check(&self) -> Result<(), GroundError> {
        if !(self.height.is_finite() && self.height >= 0.0) {
            return Err(invalid_option(
                "height",
                format!(
                    "height must be a finite distance ≥ 0 (m), got {}",
                    self.height
                ),
            ));
        }
        if self.speed.is_nan() || self.speed < 0.0 {
            return Err(invalid_option(
                "speed",
                format!(
                    "speed must be ≥ 0 (m/s; inf turns the speed test off), got {}",
                    self.speed
                ),
            ));
        }
        if let Floor::At(f) = self.floor
            && !f.is_finite()
        {
            return Err(invalid_option(
                "floor",
                format!("floor must be a finite height (m), got {f}"),
            ));
        }
        if let Some(r) = self.rate
            && !(r.is_finite() && r > 0.0)
        {
            return Err(invalid_option(
                "rate",
                format!("rate must be a positive number (Hz), got {r}"),
            ));
        }
        Ok(())
    }

    /// The gravity the measures use.
    pub fn gravity_of(&self, body: &Model) -> Vector3<f64> {
        self.gravity.unwrap_or(body.default_gravity)
    }
}

/// The body's ankle and toe joints (see the module doc); empty when none is named so.
pub fn default_contact_points(body: &Model) -> Vec<ContactPoint> {
    let (links, _) = joint_points(body);
    links
        .into_iter()
        .filter(|&l| is_foot_name(&body.link(l).name))
        .map(|l| ContactPoint {
            name: body.link(l).name.clone(),
            link: l,
        })
        .collect()
}

/// The contact points `names` picks (link names, case-insensitive; an
/// unknown name is an error with the closest names), or the default ones.
/// `Err` when the body has none.
pub fn contact_points(
    body: &Model,
    names: Option<&[String]>,
) -> Result<Vec<ContactPoint>, GroundError> {
    let Some(names) = names else {
        let found = default_contact_points(body);
        if found.is_empty() {
            return Err(invalid_option(
                "points",
                format!(
                    "the body `{}` has no foot contact points (no joint named like Foot, Toe, Ankle, Heel or calcn); name its contact links with `points: [\"…\"]`",
                    body.name
                ),
            ));
        }
        return Ok(found);
    };
    if names.is_empty() {
        return Err(invalid_option(
            "points",
            "points: [] names no contact point; leave it out for the feet",
        ));
    }
    let mut out: Vec<ContactPoint> = vec![];
    for n in names {
        let link = body
            .link_index(n)
            .or_else(|| (0..body.num_links()).find(|&i| body.link(i).name.eq_ignore_ascii_case(n)))
            .ok_or_else(|| {
                let (links, _) = joint_points(body);
                let mut near: Vec<(f64, &str)> = links
                    .iter()
                    .map(|&l| {
                        let c = body.link(l).name.as_str();
                        (
                            strsim::normalized_levenshtein(
                                &c.to_ascii_lowercase(),
                                &n.to_ascii_lowercase(),
                            ),
                            c,
                        )
                    })
                    .collect();
                near.sort_by(|a, b| b.0.total_cmp(&a.0));
                let hint: Vec<&str> = near
                    .iter()
                    .take(3)
                    .filter(|(s, _)| *s > 0.3)
                    .map(|(_, c)| *c)
                    .collect();
                invalid_option(
                    "points",
                    if hint.is_empty() {
                        format!("the body `{}` has no link `{n}`", body.name)
                    } else {
                        format!(
                            "the body `{}` has no link `{n}`; did you mean {}?",
                            body.name,
                            hint.iter()
                                .map(|h| format!("`{h}`"))
                                .collect::<Vec<_>>()
                                .join(", ")
                        )
                    },
                )
            })?;
        if !out.iter().any(|p| p.link == link) {
            out.push(ContactPoint {
                name: body.link(link).name.clone(),
                link,
            });
        }
    }
    Ok(out)
}

/// Contact points' world positions at the motion's frames.
#[derive(Clone, Debug)]
pub struct Tracks {
    pub points: Vec<ContactPoint>,
    pub times: Vec<f64>,
    /// Time between frames (s).
    pub frame_time: f64,
    /// Unit up vector (against gravity).
    pub up: Vector3<f64>,
    /// `positions[k][j]`: point `j` at `times[k]` (m, world).
    pub positions: Vec<Vec<Vector3<f64>>>,
}

impl Tracks {
    /// Height of point `j` at frame `k` along up (m).
    pub fn height(&self, k: usize, j: usize) -> f64 {
        self.positions[k][j].dot(&self.up)
    }

    /// The lowest height any point reaches (m).
    pub fn lowest(&self) -> f64 {
        (0..self.times.len())
            .flat_map(|k| (0..self.points.len()).map(move |j| (k, j)))
            .map(|(k, j)| self.height(k, j))
            .fold(f64::INFINITY, f64::min)
    }

    /// The floor height `floor` states (m).
    pub fn floor(&self, floor: Floor) -> f64 {
        match floor {
            Floor::Auto => self.lowest(),
            Floor::At(h) => h,
        }
    }

    /// Horizontal speed (m/s) of point `j` over the step from frame `k − 1` to
    /// frame `k` (`k ≥ 1`): the README's skate speed.
    pub fn step_speed(&self, k: usize, j: usize) -> f64 {
        let d = self.positions[k][j] - self.positions[k - 1][j];
        horizontal(&d, &self.up).norm() / self.frame_time
    }

    /// Horizontal speed of point `j` at frame `k`: the step into it, or at the
    /// first frame the step out of it; 0 for a single frame.
    pub fn speed(&self, k: usize, j: usize) -> f64 {
        match (k, self.times.len()) {
            (_, 0 | 1) => 0.0,
            (0, _) => self.step_speed(1, j),
            _ => self.step_speed(k, j),
        }
    }
}

/// The frame times of `m`: the grid `k/rate` over its span, `rate` the
/// option or the motion's own frame rate (else 30 Hz).
pub(crate) fn frame_times(m: &Mu, rate: Option<f64>) -> Result<(Vec<f64>, f64), GroundError> {
    let rate = rate
        .or_else(|| sample_period(m).map(|dt| 1.0 / dt))
        .unwrap_or(30.0);
    let span = m
        .span()
        .ok_or_else(|| invalid("the motion is empty: no DOF is defined anywhere"))?;
    let mut times = grid_times(span, rate)?;
    if times.is_empty() {
        times.push(span.0);
    }
    Ok((times, 1.0 / rate))
}

/// Checks that `m` has every coordinate of `body`.
pub(crate) fn check_coordinates(m: &Mu, body: &Model) -> Result<(), GroundError> {
    let coords = body.coordinate_names();
    let lacking: Vec<&str> = coords
        .iter()
        .filter(|c| m.get(c).is_none())
        .map(String::as_str)
        .collect();
    if !lacking.is_empty() {
        let shown: Vec<&str> = lacking.iter().take(5).copied().collect();
        return Err(invalid(format!(
            "the motion has no DOF for {} of the body's {} coordinates ({}{}); use the body of this motion's clip (body_of)",
            lacking.len(),
            coords.len(),
            shown.join(", "),
            if lacking.len() > 5 { ", …" } else { "" }
        )));
    }
    Ok(())
}

/// Samples every coordinate of `body` at `t` into `q` (and, when given, its
/// first and second time derivatives into `v`, `a`). `Err` names the DOF and
/// time where the motion has a gap.
pub(crate) fn sample_state(
    m: &Mu,
    body: &Model,
    t: f64,
    q: &mut [f64],
    mut va: Option<(&mut [f64], &mut [f64])>,
) -> Result<(), GroundError> {
    for (i, name) in body.coordinate_names().iter().enumerate() {
        let s = m.sample(name, t)?.ok_or_else(|| {
            invalid(format!(
                "DOF `{name}` is undefined at t = {t:.4} s: the motion has a gap there; ground measures need every coordinate at every frame — fill it (SP, fill) or clip the motion to its defined part"
            ))
        })?;
        q[i] = s[0];
        if let Some((v, a)) = va.as_mut() {
            v[i] = s[1];
            a[i] = s[2];
        }
    }
    Ok(())
}

/// The world positions of `points` at the frames of `m` (see [`frame_times`]).
pub fn tracks(
    m: &Mu,
    body: &Model,
    points: &[ContactPoint],
    opts: &GroundOptions,
) -> Result<Tracks, GroundError> {
    opts.check()?;
    check_coordinates(m, body)?;
    let up = up_direction(&opts.gravity_of(body))?;
    let (times, frame_time) = frame_times(m, opts.rate)?;
    let mut q = vec![0.0; body.nq()];
    let mut poses = Vec::with_capacity(body.num_links());
    let mut positions = Vec::with_capacity(times.len());
    for &t in &times {
        sample_state(m, body, t, &mut q, None)?;
        body.forward_kinematics(&q, &mut poses)?;
        positions.push(points.iter().map(|p| poses[p.link].p).collect());
    }
    Ok(Tracks {
        points: points.to_vec(),
        times,
        frame_time,
        up,
        positions,
    })
}

/// The floor of the recorded part of `m`: the lowest height `points` reach
/// at the motion's frames (the grid [`tracks`] samples) where every
/// coordinate of `body` is defined; `None` when there is no such frame. On a
/// motion without gaps it is the floor `contacts()` reports.
pub fn recorded_floor(
    m: &Mu,
    body: &Model,
    points: &[ContactPoint],
    opts: &GroundOptions,
) -> Result<Option<f64>, GroundError> {
    opts.check()?;
    let up = up_direction(&opts.gravity_of(body))?;
    check_coordinates(m, body)?;
    let names = body.coordinate_names();
    let (times, _) = frame_times(m, opts.rate)?;
    let mut q = vec![0.0; body.nq()];
    let mut poses = Vec::with_capacity(body.num_links());
    let mut lowest: Option<f64> = None;
    'frames: for &t in &times {
        for (i, name) in names.iter().enumerate() {
            match m.sample(name, t)? {
                Some(s) => q[i] = s[0],
                None => continue 'frames, // not recorded here
            }
        }
        body.forward_kinematics(&q, &mut poses)?;
        for p in points {
            let h = up.dot(&poses[p.link].p);
            lowest = Some(lowest.map_or(h, |l| l.min(h)));
        }
    }
    Ok(lowest)
}
