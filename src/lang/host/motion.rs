//! The motion value (`Interval`, `Dof`, `Mu`) and its provenance: where a
//! motion unit came from (the clip's skeleton and scale) and SP's report on
//! it. Provenance travels with the value it belongs to (see [`Sourced`]), so
//! two interpreters, or two motions with the same DOFs, never mix them up.

use std::sync::{Arc, Mutex};

use crate::fmt_num::Rounded;
use crate::lang::ast::BinOp;
use crate::lang::value::{HostObject, Value};
use crate::mocap::bvh::Skeleton;
use crate::motion::{self, Dof, Interval, Mu};
use crate::spacetime::SpReport;

/// A motion value: an interval, a DOF or a motion unit.
#[derive(Clone, Debug)]
pub enum Motion {
    Interval(Interval),
    Dof(Dof),
    Mu(Mu),
}

impl Motion {
    /// Intervals and DOFs both act as DOFs in the algebra.
    pub fn as_dof(&self) -> Option<Dof> {
        match self {
            Motion::Interval(i) => Some(Dof::from(i.clone())),
            Motion::Dof(d) => Some(d.clone()),
            Motion::Mu(_) => None,
        }
    }
    pub fn span(&self) -> Option<(f64, f64)> {
        match self {
            Motion::Interval(i) => Some((i.start, i.stop)),
            Motion::Dof(d) => d.span(),
            Motion::Mu(m) => m.span(),
        }
    }
}

fn fmt_span(s: Option<(f64, f64)>) -> String {
    match s {
        Some((a, b)) => format!("[{}, {}]", Rounded(a), Rounded(b)),
        None => "nothing defined".into(),
    }
}

fn plural(n: usize, word: &str) -> String {
    format!("{n} {word}{}", if n == 1 { "" } else { "s" })
}

impl HostObject for Motion {
    fn type_name(&self) -> &'static str {
        match self {
            Motion::Interval(_) => "Interval",
            Motion::Dof(_) => "Dof",
            Motion::Mu(_) => "Mu",
        }
    }

    fn summary(&self) -> String {
        match self {
            Motion::Interval(i) => {
                let conflict = if i.is_conflict() { ", a conflict" } else { "" };
                format!(
                    "Interval {} ({}{conflict})",
                    fmt_span(Some((i.start, i.stop))),
                    plural(i.funcs.len(), "function")
                )
            }
            Motion::Dof(d) => format!(
                "Dof {} ({}, {}, {})",
                fmt_span(d.span()),
                plural(d.intervals.len(), "interval"),
                plural(d.gaps().len(), "gap"),
                plural(d.conflicts().len(), "conflict")
            ),
            Motion::Mu(m) => {
                let mut names: Vec<&str> = m.names().take(4).collect();
                if m.len() > 4 {
                    names.push("…");
                }
                format!(
                    "Mu {} ({}: {}; {}, {}, {})",
                    fmt_span(m.span()),
                    plural(m.len(), "DOF"),
                    names.join(", "),
                    plural(m.interval_count(), "interval"),
                    plural(motion::gaps(m).len(), "gap"),
                    plural(motion::conflicts(m).len(), "conflict")
                )
            }
        }
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }

    fn binary(&self, op: BinOp, other: &Value, self_left: bool) -> Option<Result<Value, String>> {
        if !matches!(op, BinOp::Add | BinOp::Sub | BinOp::Meet) {
            return None;
        }
        let other = other.as_object::<Motion>()?;
        let (a, b) = if self_left {
            (self, other)
        } else {
            (other, self)
        };
        let r = match (a, b) {
            (Motion::Mu(x), Motion::Mu(y)) => Motion::Mu(match op {
                BinOp::Add => motion::plus(x, y),
                BinOp::Sub => motion::minus(x, y),
                _ => motion::and(x, y),
            }),
            (Motion::Mu(_), _) | (_, Motion::Mu(_)) => {
                return Some(Err(format!(
                    "cannot combine {} with {}: a DOF has no name; wrap it with `mu({{name: d}})` first",
                    article(a.type_name()),
                    article(b.type_name())
                )));
            }
            _ => {
                let (x, y) = (a.as_dof()?, b.as_dof()?);
                Motion::Dof(match op {
                    BinOp::Add => x.plus(&y),
                    BinOp::Sub => x.minus(&y),
                    _ => x.and(&y),
                })
            }
        };
        Some(Ok(Value::object(r)))
    }

    fn equals(&self, other: &dyn HostObject) -> bool {
        match (self, other.as_any().downcast_ref::<Motion>()) {
            (Motion::Interval(a), Some(Motion::Interval(b))) => a == b,
            (Motion::Dof(a), Some(Motion::Dof(b))) => a == b,
            (Motion::Mu(a), Some(Motion::Mu(b))) => a == b,
            _ => false,
        }
    }
}

/// "a Dof", "an Interval": a type name with its article.
fn article(name: &str) -> String {
    if name.starts_with(['A', 'E', 'I', 'O', 'U']) {
        format!("an {name}")
    } else {
        format!("a {name}")
    }
}

/// The BVH clip a motion unit was read from: what writing it back to BVH or
/// building a body from it needs besides its DOFs.
#[derive(Clone, Debug)]
pub struct ClipSource {
    pub skeleton: Arc<Skeleton>,
    /// Metres per file unit.
    pub metres_per_unit: f64,
    /// Seconds per frame in the file.
    pub frame_time: f64,
    /// The file it was read from, as the script named it.
    pub path: String,
}

impl ClipSource {
    /// What the REPL's `:info` says of a clip: where it came from, its
    /// frames and rate, units and joints (`mu`: the motion shown).
    pub fn describe(&self, mu: &Mu) -> String {
        let frames = mu
            .span()
            .map(|(a, b)| ((b - a) / self.frame_time).round() as usize + 1)
            .unwrap_or(0);
        format!(
            "from {}: {frames} frames at {} Hz, {} m per file unit, {} joints",
            self.path,
            Rounded(1.0 / self.frame_time),
            Rounded(self.metres_per_unit),
            self.skeleton.joints.len()
        )
    }

    /// Whether the skeleton has a channel for every DOF of `mu`.
    pub fn covers(&self, mu: &Mu) -> bool {
        let names = self.skeleton.channel_names();
        mu.names().all(|n| names.iter().any(|c| c == n))
    }
}

/// The clips one interpreter loaded (a [`crate::lang::session::Session`]
/// slot), most recent last: a motion made from a clip by operations that do
/// not carry provenance (`clip`, `blend`, `mu({…})` …) finds its skeleton
/// here. Bounded to the last [`LoadedClips::KEEP`]; identical skeletons are
/// kept once.
#[derive(Debug, Default)]
pub struct LoadedClips(Mutex<Vec<Arc<ClipSource>>>);

impl LoadedClips {
    /// How many clips are remembered.
    pub const KEEP: usize = 64;

    pub fn remember(&self, clip: Arc<ClipSource>) {
        let mut k = self.0.lock().unwrap_or_else(|p| p.into_inner());
        k.retain(|x| *x.skeleton != *clip.skeleton);
        k.push(clip);
        if k.len() > Self::KEEP {
            let extra = k.len() - Self::KEEP;
            k.drain(..extra);
        }
    }

    /// The most recent clip whose skeleton names every DOF of `mu`.
    pub fn find_for(&self, mu: &Mu) -> Option<Arc<ClipSource>> {
        let k = self.0.lock().unwrap_or_else(|p| p.into_inner());
        k.iter().rev().find(|x| x.covers(mu)).cloned()
    }
}

/// Where a motion came from. Equality and printing ignore it.
#[derive(Clone, Debug, Default)]
pub struct Provenance {
    /// The clip it was loaded from, or the clip of the motion it was made from.
    pub clip: Option<Arc<ClipSource>>,
    /// SP's report, on the motion SP returned (not on motions made from it).
    pub sp_report: Option<Arc<SpReport>>,
    /// IK's report, on the motion `ik` returned.
    pub ik_report: Option<Arc<crate::ik::IkReport>>,
}

/// A motion together with its [`Provenance`]. Its `as_any` is the motion
/// itself, so every built-in that takes a [`Motion`] takes it unchanged;
/// [`provenance`] reads the attachment back.
#[derive(Debug)]
pub struct Sourced {
    pub motion: Motion,
    pub provenance: Provenance,
}

impl Motion {
    /// This motion as a value carrying `provenance`.
    pub fn with_provenance(self, provenance: Provenance) -> Value {
        Value::object(Sourced {
            motion: self,
            provenance,
        })
    }
}

/// The provenance of a motion value, if it has one.
/// The skeleton a motion value drives: the clip it was loaded from, or the
/// last loaded clip that names all its DOFs (`match`, SP's `example: lib`).
pub fn skeleton_of(
    value: &Value,
    mu: &Mu,
    ev: &crate::lang::eval::Evaluator,
) -> Option<Arc<ClipSource>> {
    provenance(value)
        .and_then(|p| p.clip.clone())
        .filter(|c| c.covers(mu))
        .or_else(|| ev.ctx.session.get::<LoadedClips>().find_for(mu))
}

pub fn provenance(v: &Value) -> Option<&Provenance> {
    v.attachment::<Provenance>()
}

impl HostObject for Sourced {
    fn type_name(&self) -> &'static str {
        self.motion.type_name()
    }
    fn summary(&self) -> String {
        self.motion.summary()
    }
    fn as_any(&self) -> &dyn std::any::Any {
        &self.motion
    }
    fn attachment(&self) -> Option<&(dyn std::any::Any + Send + Sync)> {
        Some(&self.provenance)
    }
    fn binary(&self, op: BinOp, other: &Value, self_left: bool) -> Option<Result<Value, String>> {
        self.motion.binary(op, other, self_left)
    }
    fn field_names(&self) -> &'static [&'static str] {
        self.motion.field_names()
    }
    fn read_field(&self, name: &str) -> Option<Value> {
        self.motion.read_field(name)
    }
    fn equals(&self, other: &dyn HostObject) -> bool {
        self.motion.equals(other)
    }
}

/// Used by `Evaluator` users that want a motion out of a value.
pub fn as_mu(v: &Value) -> Option<&Mu> {
    match v.as_object::<Motion>() {
        Some(Motion::Mu(m)) => Some(m),
        _ => None,
    }
}
