//! `mx graph walk`: a random walk through the largest strongly connected
//! part of the graph, written as one BVH. Each node plays its clip's frames;
//! a transition edge plays the transition's frames and from then on moves
//! the next clip by the transition's alignment, composed along the walk, so
//! the figure travels on instead of jumping back to where each clip was
//! captured. The walk is a function of the graph and the seed.

use super::GraphError;
use super::library;
use super::model::{Edge, Graph};
use super::planar::Planar;
use crate::mocap::bvh::{self, BvhFile};
use std::path::Path;

/// SplitMix64: a small, fixed generator, so a seed gives the same walk everywhere.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// What a walk went through.
pub struct Walk {
    pub file: BvhFile,
    /// Edges taken (indices into the graph's edges).
    pub edges: Vec<usize>,
    pub transitions: usize,
}

/// A walk of at least `seconds` through `g` (built in `out`), starting at a
/// node of the largest strongly connected part chosen by `seed`.
pub fn walk(
    g: &Graph,
    out: &Path,
    clips_dir: Option<&Path>,
    seconds: f64,
    seed: u64,
) -> Result<Walk, GraphError> {
    if !(seconds.is_finite() && seconds > 0.0) {
        return Err(GraphError::new(format!(
            "--seconds must be a positive time, got {seconds}"
        )));
    }
    let dir = clips_dir
        .map(Path::to_path_buf)
        .unwrap_or_else(|| g.library.clips_dir.clone().into());
    let lib = library::load(&dir)?;
    let comps = g.components();
    let part = comps.first().cloned().unwrap_or_default();
    let out_edges = g.out_edges();
    let inside = |n: usize| part.binary_search(&n).is_ok();
    let staying: Vec<Vec<usize>> = (0..g.nodes.len())
        .map(|n| {
            out_edges[n]
                .iter()
                .copied()
                .filter(|&e| inside(g.edges[e].ends().1))
                .collect()
        })
        .collect();
    if part.is_empty() || staying[part[0]].is_empty() {
        return Err(GraphError::new(
            "the graph has no cycle to walk (no transitions lead back): raise --threshold or --k and rebuild",
        ));
    }
    let dt = g.library.frame_time;
    // (a BVH frame time is rounded, 0.0333333: a whole number of frames must not gain one)
    let want = (seconds / dt - 1e-3).ceil() as usize + 1;
    let nch = lib.skeleton.channel_count();
    let clip_of = |name: &str| -> Result<&library::LibClip, GraphError> {
        let k = lib.names.iter().position(|n| n == name);
        k.and_then(|k| lib.clips[k].as_ref()).ok_or_else(|| {
            GraphError::new(format!(
                "clip `{name}` of the graph is not in {}",
                dir.display()
            ))
        })
    };
    let mut rng = SplitMix(seed);
    let mut node = part[rng.below(part.len())];
    let mut place = Planar::IDENTITY;
    let mut values: Vec<f64> = Vec::with_capacity(want * nch);
    let mut taken = vec![];
    let mut transitions = 0;
    let push = |values: &mut Vec<f64>, rows: &[f64], place: &Planar| {
        let mut r = rows.to_vec();
        lib.root.transform_rows(&mut r, nch, place);
        values.extend_from_slice(&r);
    };
    while values.len() < want * nch {
        let n = &g.nodes[node];
        let c = clip_of(&n.clip)?;
        // the segment without its last frame: the next piece starts with it
        push(
            &mut values,
            &c.file.values[n.start * nch..n.end * nch],
            &place,
        );
        let e = staying[node][rng.below(staying[node].len())];
        taken.push(e);
        match &g.edges[e] {
            Edge::Clip { to, .. } => node = *to,
            Edge::Transition {
                to, file, align, ..
            } => {
                let p = out.join("transitions").join(file);
                let t = bvh::read_file(&p)
                    .map_err(|e| GraphError::new(format!("{}: {e}", p.display())))?;
                let f = t.frame_count();
                push(&mut values, &t.values[..(f - 1) * nch], &place);
                place = place.then_after(align);
                transitions += 1;
                node = *to;
            }
        }
    }
    values.truncate(want * nch);
    let mut file = BvhFile {
        skeleton: lib.skeleton.clone(),
        frame_time: dt,
        values,
    };
    // pieces join at equal rotations that may differ by whole turns: make the channels continuous
    file.unwrap_rotations();
    Ok(Walk {
        file,
        edges: taken,
        transitions,
    })
}
