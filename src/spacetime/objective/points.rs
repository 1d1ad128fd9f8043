//! What the stance, floor and clearance terms share: residual rows on the
//! world positions of contact points, r = d · p_link(q) − b per row, each
//! either two-sided (counted always) or one-sided (counted while positive,
//! max(0, r)), summed as w Σ r² per node. Each term only decides, per node,
//! its rows (`stance.rs`, `floor.rs`, `clearance.rs`).
//!
//! The node's shared forward kinematics gives p ([`Node::poses`]: one pass
//! for every term at the node, the RNEA's own); the point Jacobian ∂p/∂q_c
//! ([`Node::point_jacobian`], through [`crate::model::kinematics::point_velocity`],
//! the one `ik` and the hold IK use; taken once per link and node) gives the
//! gradient 2 w r dᵀ ∂p/∂q and the Gauss–Newton rows dᵀ ∂p/∂q over the gap
//! coordinates, exactly; q̇ and q̈ do not enter.

use super::super::error::SpError;
use super::super::torque::BodyDynamics;
use super::layout::GapLayout;
use super::term::{GaussNewtonNode, Node, NodeSum, Term, TermScratch, check_weight, scratch_of};
use crate::model::Model;
use nalgebra::{DMatrix, Vector3};

/// One residual row r = `dir` · p − `target` on the origin of a link.
#[derive(Clone, Debug, PartialEq)]
pub struct PointRow {
    pub link: usize,
    pub dir: Vector3<f64>,
    pub target: f64,
    /// Counted only while r > 0 (a bound), else always (a goal).
    pub one_sided: bool,
}

impl PointRow {
    /// r at the link's world position `p` (0 for a bound met).
    fn value(&self, p: &Vector3<f64>) -> f64 {
        let r = self.dir.dot(p) - self.target;
        if self.one_sided { r.max(0.0) } else { r }
    }
}

/// A node's rows and their residuals.
type Residuals<'w> = (&'w [PointRow], Vec<f64>);

/// A term w Σ_rows r² on contact points' positions (see the module doc).
pub struct PointTerm<'a> {
    name: &'static str,
    model: &'a Model,
    weight: f64,
    /// Per node, its rows.
    rows: Vec<Vec<PointRow>>,
}

/// One thread's buffers: the node's residuals, and per model coordinate
/// its column among the Gauss–Newton's coordinates.
struct Scratch {
    r: Vec<f64>,
    at: Vec<Option<usize>>,
}

impl<'a> PointTerm<'a> {
    /// The term `name` with weight `weight` (≥ 0, on m² per second) and
    /// `rows[k]` at node k of `layout`.
    pub(super) fn new(
        name: &'static str,
        body: &'a BodyDynamics<'a>,
        layout: &GapLayout,
        weight: f64,
        rows: Vec<Vec<PointRow>>,
    ) -> Result<Self, SpError> {
        check_weight(name, weight)?;
        debug_assert_eq!(rows.len(), layout.nodes().0.len());
        Ok(PointTerm {
            name,
            model: body.model,
            weight,
            rows,
        })
    }

    /// The rows at node k (for reports and tests).
    pub fn rows(&self, k: usize) -> &[PointRow] {
        &self.rows[k]
    }

    /// The unweighted residuals at node k for configuration `q`, in the
    /// order of [`PointTerm::rows`].
    pub fn residual(&self, k: usize, q: &[f64]) -> Result<Vec<f64>, SpError> {
        let mut poses = vec![];
        self.model
            .forward_kinematics(q, &mut poses)
            .map_err(SpError::Kinematics)?;
        Ok(self.rows[k]
            .iter()
            .map(|r| r.value(&poses[r.link].p))
            .collect())
    }

    /// At a node with rows (unless the weight is 0): its rows, and into
    /// `s.r` their residuals, from the node's link poses.
    fn residuals<'w>(
        &'w self,
        node: &mut Node<'_, BodyDynamics<'_>>,
    ) -> Result<Option<Residuals<'w>>, SpError> {
        let rows = &self.rows[node.k];
        if rows.is_empty() || self.weight == 0.0 {
            return Ok(None);
        }
        let mut r = std::mem::take(&mut scratch_of::<Scratch>(node.scratch)?.r);
        let poses = node.poses()?;
        r.clear();
        r.extend(rows.iter().map(|row| row.value(&poses[row.link].p)));
        Ok(Some((rows, r)))
    }

    /// Gives the residuals' buffer back to the scratch.
    fn keep(node: &mut Node<'_, BodyDynamics<'_>>, r: Vec<f64>) -> Result<(), SpError> {
        scratch_of::<Scratch>(node.scratch)?.r = r;
        Ok(())
    }
}

impl<'a> Term<BodyDynamics<'a>> for PointTerm<'a> {
    fn name(&self) -> &str {
        self.name
    }

    fn scratch(&self) -> TermScratch {
        Box::new(Scratch {
            r: vec![],
            at: vec![None; self.model.nq()],
        })
    }

    fn set_weight(&mut self, w: f64) -> Result<(), SpError> {
        check_weight(self.name, w)?;
        self.weight = w;
        Ok(())
    }

    fn node(
        &self,
        node: &mut Node<'_, BodyDynamics<'a>>,
        sum: &mut NodeSum<'_>,
    ) -> Result<(), SpError> {
        let Some((rows, r)) = self.residuals(node)? else {
            return Ok(());
        };
        sum.add(self.weight * r.iter().map(|r| r * r).sum::<f64>());
        if let Some(g) = sum.gradient() {
            for (row, &r) in rows.iter().zip(&r) {
                if r == 0.0 {
                    continue;
                }
                let gr = 2.0 * self.weight * r;
                for (c, col) in node.point_jacobian(row.link)? {
                    g.q[*c] += gr * row.dir.dot(col);
                }
            }
        }
        Self::keep(node, r)
    }

    /// The rows with r ≠ 0 (a met bound has none): D_q = dᵀ ∂p/∂q over the
    /// gap coordinates; D_q̇ = D_q̈ = 0.
    fn gauss_newton(
        &self,
        node: &mut Node<'_, BodyDynamics<'a>>,
        gn: &mut GaussNewtonNode<'_>,
    ) -> Result<(), SpError> {
        let Some((rows, r)) = self.residuals(node)? else {
            return Ok(());
        };
        let live: Vec<&PointRow> = rows
            .iter()
            .zip(&r)
            .filter(|(row, r)| !row.one_sided || **r > 0.0)
            .map(|(row, _)| row)
            .collect();
        Self::keep(node, r)?;
        if live.is_empty() {
            return Ok(());
        }
        let coords = gn.coords();
        let mut at = std::mem::take(&mut scratch_of::<Scratch>(node.scratch)?.at);
        for (j, &c) in coords.iter().enumerate() {
            at[c] = Some(j);
        }
        let mut dq = DMatrix::zeros(live.len(), coords.len());
        for (i, row) in live.iter().enumerate() {
            for (c, col) in node.point_jacobian(row.link)? {
                if let Some(j) = at[*c] {
                    dq[(i, j)] = row.dir.dot(col);
                }
            }
        }
        for &c in coords {
            at[c] = None;
        }
        scratch_of::<Scratch>(node.scratch)?.at = at;
        let zero = DMatrix::zeros(live.len(), coords.len());
        gn.add_rows(
            &[dq, zero.clone(), zero],
            &vec![self.weight; live.len()],
            None,
        );
        Ok(())
    }
}
