//! The graph file (`graph.json`): nodes are clip segments, edges either run
//! on within a clip (`clip`) or jump through a transition (`transition`,
//! with its BVH file, duration, ∫Στ², alignment and distance).
//!
//! Made from the pair records alone, in the sorted pair order, so one shard
//! or n shards merged give the same bytes. Nothing timed or host-dependent
//! is in it.

use super::library::ClipFailure;
use super::planar::Planar;
use super::settings::Settings;
use serde::{Deserialize, Serialize};

pub const FORMAT: &str = "mx-graph 1";

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ClipEntry {
    pub name: String,
    /// `None`: the clip failed to load.
    pub frames: Option<usize>,
}

/// What every shard of a build shares: the library and the settings.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LibraryInfo {
    pub format: String,
    /// The clip folder (absolute), where `walk` finds the clips.
    pub clips_dir: String,
    pub frame_time: f64,
    pub clips: Vec<ClipEntry>,
    pub settings: Settings,
    /// Clips that failed to load, and why (their pairs are failed pairs).
    pub clip_failures: Vec<ClipFailure>,
}

/// One transition found for a pair.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TransitionRecord {
    /// Last frame of a before the gap, first frame of b after it.
    pub i: usize,
    pub j: usize,
    /// RMS point-cloud distance at (i, j) (m).
    pub distance: f64,
    /// Frames strictly inside the gap.
    pub gap: usize,
    /// Seconds from a's frame i to b's frame j.
    pub duration: f64,
    /// ∫Στ² over the transition.
    pub energy: f64,
    /// b's coordinates → the transition's (and a's).
    pub align: Planar,
    /// File name under `transitions/`.
    pub file: String,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PairStatus {
    /// At least one transition point under the threshold, all filled.
    Done,
    /// No transition point under the threshold.
    Far,
    /// A clip failed to load or SP failed: `error` says which.
    Failed,
}

/// What a shard finished for one ordered pair (written after its BVHs).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PairRecord {
    pub a: String,
    pub b: String,
    pub status: PairStatus,
    /// The smallest window distance over all (i, j), if the search ran.
    pub best_distance: Option<f64>,
    pub transitions: Vec<TransitionRecord>,
    pub error: Option<String>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Node {
    pub clip: String,
    /// First and last frame (inclusive; a segment shares its end frame with the next one's start).
    pub start: usize,
    pub end: usize,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Edge {
    /// The clip plays on into its next segment.
    Clip { from: usize, to: usize },
    Transition {
        from: usize,
        to: usize,
        file: String,
        frames: usize,
        duration: f64,
        energy: f64,
        distance: f64,
        align: Planar,
    },
}

impl Edge {
    pub fn ends(&self) -> (usize, usize) {
        match self {
            Edge::Clip { from, to } | Edge::Transition { from, to, .. } => (*from, *to),
        }
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PairFailure {
    pub a: String,
    pub b: String,
    pub error: String,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Graph {
    #[serde(flatten)]
    pub library: LibraryInfo,
    pub nodes: Vec<Node>,
    pub edges: Vec<Edge>,
    pub pair_failures: Vec<PairFailure>,
}

impl Graph {
    /// The graph of `records` (sorted by pair, one per pair).
    pub fn from_records(library: LibraryInfo, records: &[PairRecord]) -> Graph {
        let index = |name: &str| library.clips.iter().position(|c| c.name == name);
        // cut points of each clip: its ends, every exit frame i and every entry frame j
        let mut cuts: Vec<Vec<usize>> = library
            .clips
            .iter()
            .map(|c| match c.frames {
                Some(f) if f > 0 => vec![0, f - 1],
                _ => vec![],
            })
            .collect();
        for r in records {
            for t in &r.transitions {
                if let (Some(a), Some(b)) = (index(&r.a), index(&r.b)) {
                    cuts[a].push(t.i);
                    cuts[b].push(t.j);
                }
            }
        }
        let mut nodes = vec![];
        let mut first_node = vec![0; cuts.len()];
        let mut edges = vec![];
        for (c, cut) in cuts.iter_mut().enumerate() {
            cut.sort_unstable();
            cut.dedup();
            first_node[c] = nodes.len();
            for w in cut.windows(2) {
                if nodes.len() > first_node[c] {
                    edges.push(Edge::Clip {
                        from: nodes.len() - 1,
                        to: nodes.len(),
                    });
                }
                nodes.push(Node {
                    clip: library.clips[c].name.clone(),
                    start: w[0],
                    end: w[1],
                });
            }
        }
        let node_of = |clip: usize, pick: &dyn Fn(&Node) -> bool| {
            let end = first_node.get(clip + 1).copied().unwrap_or(nodes.len());
            (first_node[clip]..end).find(|&n| pick(&nodes[n]))
        };
        let mut pair_failures = vec![];
        for r in records {
            if let Some(e) = &r.error {
                pair_failures.push(PairFailure {
                    a: r.a.clone(),
                    b: r.b.clone(),
                    error: e.clone(),
                });
            }
            let (Some(a), Some(b)) = (index(&r.a), index(&r.b)) else {
                continue;
            };
            for t in &r.transitions {
                let from = node_of(a, &|n: &Node| n.end == t.i);
                let to = node_of(b, &|n: &Node| n.start == t.j);
                if let (Some(from), Some(to)) = (from, to) {
                    edges.push(Edge::Transition {
                        from,
                        to,
                        file: t.file.clone(),
                        frames: t.gap + 2,
                        duration: t.duration,
                        energy: t.energy,
                        distance: t.distance,
                        align: t.align,
                    });
                }
            }
        }
        Graph {
            library,
            nodes,
            edges,
            pair_failures,
        }
    }

    /// Outgoing edges of every node, in edge order.
    pub fn out_edges(&self) -> Vec<Vec<usize>> {
        let mut out = vec![vec![]; self.nodes.len()];
        for (k, e) in self.edges.iter().enumerate() {
            out[e.ends().0].push(k);
        }
        out
    }

    /// Strongly connected components (Tarjan, iterative), largest first
    /// (ties: the one with the smallest node), each sorted.
    pub fn components(&self) -> Vec<Vec<usize>> {
        let n = self.nodes.len();
        let out: Vec<Vec<usize>> = self
            .out_edges()
            .iter()
            .map(|es| es.iter().map(|&e| self.edges[e].ends().1).collect())
            .collect();
        let mut index = vec![usize::MAX; n];
        let mut low = vec![0; n];
        let mut on_stack = vec![false; n];
        let mut stack = vec![];
        let mut comps = vec![];
        let mut next = 0;
        for root in 0..n {
            if index[root] != usize::MAX {
                continue;
            }
            let mut call: Vec<(usize, usize)> = vec![(root, 0)];
            index[root] = next;
            low[root] = next;
            next += 1;
            stack.push(root);
            on_stack[root] = true;
            while let Some(&mut (v, ref mut k)) = call.last_mut() {
                if *k < out[v].len() {
                    let w = out[v][*k];
                    *k += 1;
                    if index[w] == usize::MAX {
                        index[w] = next;
                        low[w] = next;
                        next += 1;
                        stack.push(w);
                        on_stack[w] = true;
                        call.push((w, 0));
                    } else if on_stack[w] {
                        low[v] = low[v].min(index[w]);
                    }
                } else {
                    call.pop();
                    if let Some(&(u, _)) = call.last() {
                        low[u] = low[u].min(low[v]);
                    }
                    if low[v] == index[v] {
                        let mut comp = vec![];
                        loop {
                            let w = stack.pop().expect("on the stack");
                            on_stack[w] = false;
                            comp.push(w);
                            if w == v {
                                break;
                            }
                        }
                        comp.sort_unstable();
                        comps.push(comp);
                    }
                }
            }
        }
        comps.sort_by(|a, b| b.len().cmp(&a.len()).then(a[0].cmp(&b[0])));
        comps
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn info(clips: &[(&str, usize)]) -> LibraryInfo {
        LibraryInfo {
            format: FORMAT.into(),
            clips_dir: "/clips".into(),
            frame_time: 1.0 / 30.0,
            clips: clips
                .iter()
                .map(|(n, f)| ClipEntry {
                    name: n.to_string(),
                    frames: Some(*f),
                })
                .collect(),
            settings: Settings::default(),
            clip_failures: vec![],
        }
    }

    fn tr(i: usize, j: usize, file: &str) -> TransitionRecord {
        TransitionRecord {
            i,
            j,
            distance: 0.1,
            gap: 4,
            duration: 5.0 / 30.0,
            energy: 1.0,
            align: Planar::IDENTITY,
            file: file.into(),
        }
    }

    #[test]
    fn segments_edges_and_components() {
        let recs = vec![
            PairRecord {
                a: "a".into(),
                b: "b".into(),
                status: PairStatus::Done,
                best_distance: Some(0.1),
                transitions: vec![tr(20, 5, "ab0")],
                error: None,
            },
            PairRecord {
                a: "b".into(),
                b: "a".into(),
                status: PairStatus::Done,
                best_distance: Some(0.1),
                transitions: vec![tr(30, 10, "ba0")],
                error: None,
            },
        ];
        let g = Graph::from_records(info(&[("a", 40), ("b", 50)]), &recs);
        // a cut at 0, 10, 20, 39; b at 0, 5, 30, 49
        assert_eq!(g.nodes.len(), 6);
        assert_eq!(
            g.nodes[1],
            Node {
                clip: "a".into(),
                start: 10,
                end: 20
            }
        );
        let trans: Vec<(usize, usize)> = g
            .edges
            .iter()
            .filter(|e| matches!(e, Edge::Transition { .. }))
            .map(|e| e.ends())
            .collect();
        assert_eq!(trans, vec![(1, 4), (4, 1)]);
        // a[10..20] → b[5..30] → a[10..20] is a cycle; the clip ends and starts are not on one
        assert_eq!(g.components()[0], vec![1, 4]);
        let json = serde_json::to_string(&g).unwrap();
        let back: Graph = serde_json::from_str(&json).unwrap();
        assert_eq!(back, g);
    }
}
