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
use super::base::check_weight;
use super::layout::GapLayout;
use super::term::{GaussNewtonNode, Node, NodeSum, Term, TermScratch, scratch_of};
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
    /// Per coordinate, the link whose joint it belongs to.
    owner: Vec<usize>,
}

struct Scratch {
    poses: Vec<Se3>,
    jk: JointKinematics,
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
        let model = body.model;
        let mut owner = vec![0; model.nq()];
        for (i, l) in model.links().iter().enumerate() {
            owner[l.q_index..l.q_index + l.dof].fill(i);
        }
        Ok(PointTerm {
            name,
            model,
            weight,
            rows,
            owner,
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

    /// ∂p_link/∂q_c at q (`s.poses` from q): zero unless coordinate c
    /// moves the link.
    fn column(&self, s: &mut Scratch, q: &[f64], c: usize, link: usize) -> Vector3<f64> {
        let o = self.owner[c];
        if !self.model.is_ancestor(o, link) {
            return Vector3::zeros();
        }
        let l = self.model.link(o);
        l.joint.kinematics(
            &q[l.q_index..l.q_index + l.dof],
            Derivatives::Jacobian,
            &mut s.jk,
        );
        point_velocity(&s.poses[o], &s.jk.s[c - l.q_index], &s.poses[link].p)
    }

    /// The coordinates that move `link`: its own and its ancestors'.
    fn chain(&self, link: usize) -> impl Iterator<Item = usize> + '_ {
        std::iter::successors(Some(link), |&i| self.model.link(i).parent).flat_map(|i| {
            let l = self.model.link(i);
            l.q_index..l.q_index + l.dof
        })
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
        let rows = &self.rows[node.k];
        if rows.is_empty() || self.weight == 0.0 {
            return Ok(());
        }
        let s = scratch_of::<Scratch>(node.scratch)?;
        self.model
            .forward_kinematics(node.q, &mut s.poses)
            .map_err(SpError::Kinematics)?;
        let mut f = 0.0;
        for row in rows {
            let r = row.value(&s.poses[row.link].p);
            if r == 0.0 {
                continue;
            }
            f += r * r;
            if let Some(g) = sum.gradient() {
                let gr = 2.0 * self.weight * r;
                for c in self.chain(row.link) {
                    g.q[c] += gr * row.dir.dot(&self.column(s, node.q, c, row.link));
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
        let rows = &self.rows[node.k];
        if rows.is_empty() || self.weight == 0.0 {
            return Ok(());
        }
        let s = scratch_of::<Scratch>(node.scratch)?;
        self.model
            .forward_kinematics(node.q, &mut s.poses)
            .map_err(SpError::Kinematics)?;
        let live: Vec<&PointRow> = rows
            .iter()
            .filter(|r| !r.one_sided || r.value(&s.poses[r.link].p) > 0.0)
            .collect();
        if live.is_empty() {
            return Ok(());
        }
        let coords = gn.coords();
        let mut dq = DMatrix::zeros(live.len(), coords.len());
        for (i, row) in live.iter().enumerate() {
            for (j, &c) in coords.iter().enumerate() {
                dq[(i, j)] = row.dir.dot(&self.column(s, node.q, c, row.link));
            }
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
