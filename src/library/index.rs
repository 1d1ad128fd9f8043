//! The library: its clips, every grid frame's features (normalised), and a
//! k-d tree over the *before* vectors that answers a gap's query exactly
//! (building it is `build.rs`).
//!
//! A stretch of clip c from grid frame s, L frames long, fills a gap
//! [t0, t1] with mismatch (|b(s) − q_b|² + |a(s+L) − q_a|²) / (2·DIM): b
//! and a the clip's normalised before and after vectors, q_b and q_a the
//! gap's (at t0 and t1). The tree yields frames in order of the first term,
//! a lower bound of the whole, so the search stops as soon as that bound
//! passes the k-th best total: exact, and it reads only the frames whose
//! arrival looks like the gap's (branch and bound over the tree's answer).

use super::LibraryError;
use super::clip::{ClipData, LibClip};
use super::features::{self, DIM, KeyJoints};
use kiddo::SquaredEuclidean;
use kiddo::immutable::float::kdtree::ImmutableKdTree;
use serde::{Deserialize, Serialize};
use std::num::NonZero;
use std::sync::OnceLock;

/// What an index is built with; a saved index is refused by a `load` that
/// asks for other settings.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Settings {
    /// Grid rate (Hz) every clip is sampled on: a capture's usual 30 frames a
    /// second, the in-betweening protocol's.
    pub rate: f64,
    /// Time warps a stretch may take: a stretch of w × the gap's length is
    /// played in the gap (1: as captured).
    pub warps: Vec<f64>,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            rate: 30.0,
            warps: vec![1.0],
        }
    }
}

impl Settings {
    pub fn check(&self) -> Result<(), LibraryError> {
        if !(self.rate.is_finite() && self.rate >= 1.0 && self.rate <= 1000.0) {
            return Err(LibraryError::InvalidOption {
                option: "rate",
                message: format!("rate must be between 1 and 1000 Hz, found {}", self.rate),
            });
        }
        if self.warps.is_empty()
            || self
                .warps
                .iter()
                .any(|w| !(w.is_finite() && (0.25..=4.0).contains(w)))
        {
            return Err(LibraryError::InvalidOption {
                option: "warps",
                message: format!(
                    "warps must be a non-empty list of factors between 0.25 and 4, found {:?}",
                    self.warps
                ),
            });
        }
        Ok(())
    }

    /// Grid frames of trajectory the features look back or ahead.
    pub fn horizon(&self) -> usize {
        ((features::HORIZON * self.rate).round() as usize).max(1)
    }
}

/// A clip that was not indexed, and why.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Skipped {
    pub clip: String,
    pub reason: String,
}

/// One library stretch for a gap.
#[derive(Clone, Debug, PartialEq)]
pub struct Match {
    /// Index of the clip in [`Library::clips`].
    pub clip: usize,
    pub name: String,
    /// Clip time (s) where the stretch starts: its frame at the gap's start.
    pub time: f64,
    /// Its length (s) in clip time: warp × the gap's.
    pub duration: f64,
    /// Clip time per gap time (1: as captured).
    pub warp: f64,
    /// Mean squared normalised feature difference over both sides (0: the
    /// clip arrives and leaves exactly as the gap's context does).
    pub mismatch: f64,
    /// Grid frame of the start in the clip.
    pub frame: usize,
}

type Tree = ImmutableKdTree<f32, u32, DIM, 32>;

/// The built index.
pub struct Library {
    pub settings: Settings,
    pub clips: Vec<LibClip>,
    pub skipped: Vec<Skipped>,
    /// Per dimension: the mean subtracted and the group scale divided by.
    pub mean: [f32; DIM],
    pub scale: [f32; DIM],
    /// Normalised before/after vectors of every grid frame (NaN: undefined,
    /// too near the clip's start or end).
    pub before: Vec<[f32; DIM]>,
    pub after: Vec<[f32; DIM]>,
    /// The tree over the valid before vectors and the global frame of each
    /// of its items: built at the first match (a build that only saves, and a
    /// load that is not searched, need none).
    tree: OnceLock<(Tree, Vec<u32>)>,
}

/// The gap's side of a match: its normalised before vector at t0 and after
/// vector at t1, and its length.
#[derive(Clone, Debug)]
pub struct Query {
    pub before: [f32; DIM],
    pub after: [f32; DIM],
    /// t1 − t0 (s).
    pub duration: f64,
}

/// Whether a feature vector is defined (NaN: too near a clip's ends).
pub(super) fn valid(v: &[f32; DIM]) -> bool {
    v[0].is_finite()
}

fn dist2(a: &[f32; DIM], b: &[f32; DIM]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| {
            let d = (*x as f64) - (*y as f64);
            d * d
        })
        .sum()
}

impl Library {
    /// The library from its parts (what a build and `load` end with).
    pub(super) fn assemble(
        settings: Settings,
        clips: Vec<LibClip>,
        skipped: Vec<Skipped>,
        mean: [f32; DIM],
        scale: [f32; DIM],
        before: Vec<[f32; DIM]>,
        after: Vec<[f32; DIM]>,
    ) -> Library {
        Library {
            settings,
            clips,
            skipped,
            mean,
            scale,
            before,
            after,
            tree: OnceLock::new(),
        }
    }

    /// Per clip, whether an earlier clip holds the same text (its file's
    /// or section's bytes: length and fingerprint, read in the same units). A repeat matches exactly
    /// where its first copy does, so the search reads the first copy only:
    /// a library of many copies costs a query what one copy does, and the k
    /// answers are k distinct stretches, not k copies of one. Clips made in
    /// memory have no stored bytes and are never repeats.
    pub fn repeats(&self) -> Vec<bool> {
        let mut seen = std::collections::HashSet::new();
        self.clips
            .iter()
            .map(|c| {
                c.data
                    .stamp()
                    .is_some_and(|k| !seen.insert((k, c.metres_per_unit.to_bits())))
            })
            .collect()
    }

    /// The global frames the search reads: valid, of clips that are not
    /// repeats ([`Library::repeats`]).
    fn searched_frames(&self) -> Vec<u32> {
        let repeats = self.repeats();
        self.clips
            .iter()
            .zip(repeats)
            .filter(|(_, r)| !r)
            .flat_map(|(c, _)| c.offset as u32..(c.offset + c.frames) as u32)
            .filter(|&f| valid(&self.before[f as usize]))
            .collect()
    }

    /// The tree and its items' frames, built over the searched frames the
    /// first time they are asked for.
    fn tree(&self) -> &(Tree, Vec<u32>) {
        self.tree.get_or_init(|| {
            let frames = self.searched_frames();
            let points: Vec<[f32; DIM]> = frames.iter().map(|&f| self.before[f as usize]).collect();
            (Tree::new_from_slice(&points), frames)
        })
    }

    /// Grid frames indexed (all clips).
    pub fn frames(&self) -> usize {
        self.before.len()
    }

    /// Bytes the index holds in memory (features, tree, clips kept in
    /// memory, the clips' descriptions), roughly.
    pub fn memory_bytes(&self) -> usize {
        let features = 2 * self.before.len() * DIM * 4;
        let valid_frames = self.before.iter().filter(|v| valid(v)).count();
        let tree = valid_frames * (DIM * 4 + 4 + 4);
        let clips: usize = self
            .clips
            .iter()
            .map(|c| {
                let kept = match &c.data {
                    ClipData::Memory(f) => f.values.len() * 8 + f.skeleton.joints.len() * 96,
                    _ => 0,
                };
                kept + std::mem::size_of::<LibClip>() + c.name.len() + 64
            })
            .sum();
        features + tree + clips
    }

    /// The gap's query, from `mu` driving `skeleton` around [t0, t1]: the
    /// motion must be defined over the feature horizon before t0 and after t1.
    pub fn query(
        &self,
        mu: &crate::motion::Mu,
        skeleton: &crate::mocap::bvh::Skeleton,
        metres_per_unit: f64,
        t0: f64,
        t1: f64,
    ) -> Result<Query, LibraryError> {
        if !(t0.is_finite() && t1.is_finite() && t1 > t0) {
            return Err(LibraryError::new(format!(
                "the gap must have t1 > t0, found [{t0}, {t1}]"
            )));
        }
        let keys = KeyJoints::find(skeleton).map_err(|e| {
            LibraryError::new(format!("the motion's skeleton cannot be matched: {e}"))
        })?;
        let h = self.settings.horizon();
        let rate = self.settings.rate;
        // Grid times outside the motion's span by at most half of its own
        // frame (and a thousandth of a grid step) are its ends. A context of
        // the whole frames nearest to the horizon falls short of it by up to
        // half a frame at rates the horizon is not a whole number of frames
        // of (8 frames at 25 Hz: 0.32 s; 33 at 100 Hz: 0.33 s), and a file's
        // rounded frame time (0.0333333 s, 0.0083333 s) by a few µs at any
        // rate; either would otherwise read as undefined. The position held
        // at the end is at most half a frame from the one the feature wants.
        let span = mu.span();
        let half_frame = crate::motion::sample_period(mu).map_or(0.0, |dt| dt / 2.0);
        let slack = half_frame + 1e-3 / rate;
        let snap = |t: f64| match span {
            Some((a, _)) if t < a && a - t <= slack => a,
            Some((_, b)) if t > b && t - b <= slack => b,
            _ => t,
        };
        let grid =
            |from: f64| -> Vec<f64> { (0..=h).map(|k| snap(from + k as f64 / rate)).collect() };
        let pos_b = features::key_positions(
            mu,
            skeleton,
            metres_per_unit,
            &keys,
            &grid(t0 - h as f64 / rate),
        );
        let pos_a = features::key_positions(mu, skeleton, metres_per_unit, &keys, &grid(t1));
        let up = crate::mocap::up::skeleton_up(skeleton, Some(mu), metres_per_unit);
        let side = |pos, f, dir, what: &str, at: f64| {
            features::frame_features(pos, f, dir, (h, rate), &up).ok_or_else(|| {
                LibraryError::new(format!(
                    "the motion is not defined over the {:.3} s {what} {at} s: a match compares that much context",
                    h as f64 / rate
                ))
            })
        };
        let mut before = side(&pos_b, h, -1, "before", t0)?;
        let mut after = side(&pos_a, 0, 1, "after", t1)?;
        for v in [&mut before, &mut after] {
            for (d, x) in v.iter_mut().enumerate() {
                *x = (*x - self.mean[d]) / self.scale[d];
            }
        }
        Ok(Query {
            before,
            after,
            duration: t1 - t0,
        })
    }

    /// Every (warp, stretch frames) the settings allow for a gap.
    fn lengths(&self, q: &Query) -> Vec<(f64, usize)> {
        self.settings
            .warps
            .iter()
            .map(|&w| {
                (
                    w,
                    (q.duration * w * self.settings.rate).round().max(1.0) as usize,
                )
            })
            .collect()
    }

    /// The candidates starting at global frame `g` (one per warp), with
    /// their totals, given its before distance `db`.
    fn candidates_at(
        &self,
        q: &Query,
        lengths: &[(f64, usize)],
        g: usize,
        db: f64,
        out: &mut Vec<(f64, usize, usize)>,
    ) {
        let c = self.clip_of(g);
        let end = self.clips[c].offset + self.clips[c].frames;
        for (wi, &(_, len)) in lengths.iter().enumerate() {
            let e = g + len;
            if e < end && valid(&self.after[e]) {
                out.push((db + dist2(&self.after[e], &q.after), g, wi));
            }
        }
    }

    fn clip_of(&self, g: usize) -> usize {
        self.clips.partition_point(|c| c.offset <= g) - 1
    }

    /// The k best stretches, best first, by the k-d tree (exact: the same as
    /// [`Library::match_brute`]). Stretches of one clip closer than the
    /// feature horizon to a better one are left out (the same stretch a
    /// frame later).
    pub fn match_gap(&self, q: &Query, k: usize) -> Vec<Match> {
        let (tree, tree_frames) = self.tree();
        if k == 0 || tree_frames.is_empty() {
            return vec![];
        }
        let lengths = self.lengths(q);
        let mut n = (16 * k).max(64);
        loop {
            let n_ask = n.min(tree_frames.len());
            let nn = tree.nearest_n::<SquaredEuclidean>(&q.before, NonZero::new(n_ask).unwrap());
            let mut cands = vec![];
            let mut bound = 0.0f64;
            for x in &nn {
                let g = tree_frames[x.item as usize] as usize;
                let db = dist2(&self.before[g], &q.before);
                bound = bound.max(db);
                self.candidates_at(q, &lengths, g, db, &mut cands);
            }
            let chosen = self.select(cands, &lengths, k);
            let exhausted = n_ask >= tree_frames.len();
            // every frame not yet read has a before distance at least the
            // tree's last one (up to f32 rounding), hence a total above it
            let last = nn.last().map_or(0.0, |x| x.distance as f64);
            let kth = chosen.last().map(|m| m.mismatch * (2 * DIM) as f64);
            if exhausted
                || (chosen.len() == k
                    && kth.is_some_and(|kth| last.min(bound) > kth * (1.0 + 1e-4) + 1e-6))
            {
                return chosen;
            }
            n *= 4;
        }
    }

    /// The k best stretches by reading every searched frame: the reference
    /// the tree search is tested against.
    pub fn match_brute(&self, q: &Query, k: usize) -> Vec<Match> {
        let lengths = self.lengths(q);
        let mut cands = vec![];
        for g in self.searched_frames() {
            let g = g as usize;
            let db = dist2(&self.before[g], &q.before);
            self.candidates_at(q, &lengths, g, db, &mut cands);
        }
        self.select(cands, &lengths, k)
    }

    fn select(
        &self,
        mut cands: Vec<(f64, usize, usize)>,
        lengths: &[(f64, usize)],
        k: usize,
    ) -> Vec<Match> {
        cands.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
        let h = self.settings.horizon();
        let mut out: Vec<Match> = vec![];
        for (total, g, wi) in cands {
            if out.len() == k {
                break;
            }
            let c = self.clip_of(g);
            let frame = g - self.clips[c].offset;
            if out
                .iter()
                .any(|m| m.clip == c && m.frame.abs_diff(frame) <= h)
            {
                continue;
            }
            let (warp, len) = lengths[wi];
            out.push(Match {
                clip: c,
                name: self.clips[c].name.clone(),
                time: self.clips[c].start + frame as f64 / self.settings.rate,
                duration: len as f64 / self.settings.rate,
                warp,
                mismatch: total / (2 * DIM) as f64,
                frame,
            });
        }
        out
    }
}
