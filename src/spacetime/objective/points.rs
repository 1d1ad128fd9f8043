//! What the stance, floor and clearance terms share: residual rows on the
//! world positions of contact points, r = d · p_link(q) − b per row, each
//! either two-sided (counted always) or one-sided (counted while positive,
//! max(0, r)), summed as w Σ r² per node. Each term only decides, per node,
//! its rows (`stance.rs`, `floor.rs`, `clearance.rs`).
//!
//! Forward kinematics gives p; the point Jacobian ∂p/∂q_c
//! ([`crate::model::kinematics::point_velocity`], the one `ik` and the hold
//! IK use) gives the gradient 2 w r dᵀ ∂p/∂q and the Gauss–Newton rows
//! dᵀ ∂p/∂q over the gap coordinates, exactly; q̇ and q̈ do not enter.

use super::super::error::SpError;
use super::super::torque::BodyDynamics;
use super::layout::GapLayout;
use super::term::{GaussNewtonNode, Node, NodeSum, Term, TermScratch, check_weight, scratch_of};
use crate::lie::Se3;
use crate::model::Model;
use crate::model::joint::{Derivatives, JointKinematics};
use crate::model::kinematics::point_velocity;
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

/// A term w Σ_rows r² on contact points' positions (see the module doc).
pub struct PointTerm<'a> {
    name: &'static str,
    model: &'a Model,
    weight: f64,
    /// Per node, its rows.
    rows: Vec<Vec<PointRow>>,
}

struct Scratch {
    poses: Vec<Se3>,
    jk: JointKinematics,
    /// The point Jacobian's columns of link `cols_of` ([`PointTerm::columns`]).
    cols: Vec<(usize, Vector3<f64>)>,
    cols_of: Option<usize>,
    /// Per model coordinate, its column among the Gauss–Newton's coordinates.
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

    /// At a node with rows (unless the weight is 0): its rows, and the
    /// scratch with the links posed at the node's q.
    fn posed<'w>(
        &'w self,
        node: &'w mut Node<'_, BodyDynamics<'_>>,
    ) -> Result<Option<(&'w [PointRow], &'w mut Scratch)>, SpError> {
        let rows = &self.rows[node.k];
        if rows.is_empty() || self.weight == 0.0 {
            return Ok(None);
        }
        let s = scratch_of::<Scratch>(node.scratch)?;
        self.model
            .forward_kinematics(node.q, &mut s.poses)
            .map_err(SpError::Kinematics)?;
        s.cols_of = None;
        Ok(Some((rows, s)))
    }

    /// Into `s.cols`: (c, ∂p_link/∂q_c) at q for every coordinate c that
    /// moves the link (its own and its ancestors'), `s.poses` from q; each
    /// joint's Jacobian computed once.
    fn columns(&self, s: &mut Scratch, q: &[f64], link: usize) {
        s.cols.clear();
        let p = s.poses[link].p;
        let mut l = Some(link);
        while let Some(i) = l {
            let lk = self.model.link(i);
            if lk.dof > 0 {
                lk.joint.kinematics(
                    &q[lk.q_index..lk.q_index + lk.dof],
                    Derivatives::Jacobian,
                    &mut s.jk,
                );
                for m in 0..lk.dof {
                    let col = point_velocity(&s.poses[i], &s.jk.s[m], &p);
                    s.cols.push((lk.q_index + m, col));
                }
            }
            l = lk.parent;
        }
        s.cols_of = Some(link);
    }
}

impl<'a> Term<BodyDynamics<'a>> for PointTerm<'a> {
    fn name(&self) -> &str {
        self.name
    }

    fn scratch(&self) -> TermScratch {
        Box::new(Scratch {
            poses: vec![],
            jk: JointKinematics::default(),
            cols: vec![],
            cols_of: None,
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
        let q = node.q;
        let Some((rows, s)) = self.posed(node)? else {
            return Ok(());
        };
        let mut f = 0.0;
        for row in rows {
            let r = row.value(&s.poses[row.link].p);
            if r == 0.0 {
                continue;
            }
            f += r * r;
            if let Some(g) = sum.gradient() {
                if s.cols_of != Some(row.link) {
                    self.columns(s, q, row.link);
                }
                let gr = 2.0 * self.weight * r;
                for (c, col) in &s.cols {
                    g.q[*c] += gr * row.dir.dot(col);
                }
            }
        }
        sum.add(self.weight * f);
        Ok(())
    }

    /// The rows with r ≠ 0 (a met bound has none): D_q = dᵀ ∂p/∂q over the
    /// gap coordinates; D_q̇ = D_q̈ = 0.
    fn gauss_newton(
        &self,
        node: &mut Node<'_, BodyDynamics<'a>>,
        gn: &mut GaussNewtonNode<'_>,
    ) -> Result<(), SpError> {
        let q = node.q;
        let Some((rows, s)) = self.posed(node)? else {
            return Ok(());
        };
        let live: Vec<&PointRow> = rows
            .iter()
            .filter(|r| !r.one_sided || r.value(&s.poses[r.link].p) > 0.0)
            .collect();
        if live.is_empty() {
            return Ok(());
        }
        let coords = gn.coords();
        for (j, &c) in coords.iter().enumerate() {
            s.at[c] = Some(j);
        }
        s.cols_of = None;
        let mut dq = DMatrix::zeros(live.len(), coords.len());
        for (i, row) in live.iter().enumerate() {
            if s.cols_of != Some(row.link) {
                self.columns(s, q, row.link);
            }
            for (c, col) in &s.cols {
                if let Some(j) = s.at[*c] {
                    dq[(i, j)] = row.dir.dot(col);
                }
            }
        }
        for &c in coords {
            s.at[c] = None;
        }
        let zero = DMatrix::zeros(live.len(), coords.len());
        gn.add_rows(
            &[dq, zero.clone(), zero],
            &vec![self.weight; live.len()],
            None,
        );
        Ok(())
    }
}
