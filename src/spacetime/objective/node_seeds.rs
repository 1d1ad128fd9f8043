//! The per-node buffers the terms share (`node_state.rs` fills them): one
//! thread's state cache and sweep buffers, and the seeds of one node's
//! reverse sweep. Apart from `node_state.rs` so that `term.rs`, which holds
//! them in a [`super::term::Node`], and `node_state.rs`, which computes on
//! a `Node`, import them without importing each other.

use crate::dynamics::StateCache;
use crate::lie::Twist;

/// One thread's shared passes and the buffers of [`Node::reverse`].
pub(super) struct Shared {
    /// Built at the first request (only a multibody model has one).
    pub(super) cache: Option<StateCache>,
    pub(super) grad: [Vec<f64>; 3],
}

impl Shared {
    pub(super) fn new(nq: usize) -> Self {
        Shared {
            cache: None,
            grad: std::array::from_fn(|_| vec![0.0; nq]),
        }
    }
}

/// The seeds of one node's reverse sweep: ∂f/∂τ and ∂f/∂w_root summed over
/// the terms, and whether any term gave one.
pub(super) struct Seeds {
    pub(super) tau: Vec<f64>,
    pub(super) root: Twist,
    pub(super) on_tau: bool,
    pub(super) on_root: bool,
}

/// −0 is the sum's neutral element to the bit (−0 + x = x for every x, −0
/// included), so a term's seed added to it is the seed exactly.
pub(super) const NEUTRAL: f64 = -0.0;

impl Seeds {
    pub(super) fn new(nq: usize) -> Self {
        Seeds {
            tau: vec![NEUTRAL; nq],
            root: Twist::repeat(NEUTRAL),
            on_tau: false,
            on_root: false,
        }
    }

    /// No seed yet (a new node).
    pub(super) fn clear(&mut self) {
        if self.on_tau {
            self.tau.fill(NEUTRAL);
        }
        self.root = Twist::repeat(NEUTRAL);
        self.on_tau = false;
        self.on_root = false;
    }
}
