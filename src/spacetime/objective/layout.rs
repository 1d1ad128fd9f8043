//! The layout of one group of gaps: which model coordinates a transition
//! solves, their curves, the quadrature nodes over the group's span, and at
//! every node the basis rows that turn the free coefficients into q, q̇, q̈.
//! Built once from the gaps and the settings; the torque objective and the
//! support IK ([`super::super::support`]) read the same layout.

use super::super::error::{SpError, invalid};
use super::super::quadrature::GaussLegendre;
use super::super::transition::{Continuity, EndState, TransitionCurve};
use super::{GapDof, TransitionSettings};
use crate::motion::Curve;
use std::sync::Arc;

/// Fewest Gauss points on one polynomial piece of a transition. With fewer,
/// the optimiser hides torque between nodes (aliasing): on the Fig. 8 case
/// on human44.urdf (5 coefficients, 6 pieces) a solve with 4 points per
/// piece reads 840 by its own rule but 1520 under a 200-point rule; on the
/// project's walk (8 coefficients) 3 points per piece read 212.4 against
/// 220.8. With 6 per piece the two agree within 0.1 % on both cases
/// (measured by hand; the spacetime benchmark shows the nodes per row).
pub const MIN_POINTS_PER_PIECE: usize = 6;

/// Quadrature nodes and weights for the curves of one group: Gauss rules on
/// every piece between consecutive knots of any curve (so neither a gap end,
/// where a curve meets its data with a jump in q̈, nor a knot, where q̈ kinks,
/// lies inside a rule), `samples` points in all, shared in proportion to the
/// length of each piece but at least [`MIN_POINTS_PER_PIECE`] per piece.
pub fn composite_nodes(
    curves: &[TransitionCurve],
    samples: usize,
) -> Result<(Vec<f64>, Vec<f64>), SpError> {
    if samples == 0 {
        return Err(invalid(
            "samples: 0 gives no quadrature points; use samples: 1 or more (default 20)",
        ));
    }
    let mut breaks: Vec<f64> = curves.iter().flat_map(|c| c.breakpoints()).collect();
    breaks.sort_by(f64::total_cmp);
    // merge knots closer than a relative 1e-12 (rounding of equal knots of different curves)
    let span = breaks.last().copied().unwrap_or(0.0) - breaks.first().copied().unwrap_or(0.0);
    breaks.dedup_by(|a, b| (*a - *b).abs() <= 1e-12 * span.max(1e-300));
    let mut nodes = vec![];
    let mut weights = vec![];
    let mut rules: Vec<Option<GaussLegendre>> = vec![];
    for w in breaks.windows(2) {
        let k = ((samples as f64 * (w[1] - w[0]) / span).ceil() as usize).max(MIN_POINTS_PER_PIECE);
        if rules.len() <= k {
            rules.resize(k + 1, None);
        }
        if rules[k].is_none() {
            rules[k] = Some(GaussLegendre::new(k).map_err(|e| invalid(e.to_string()))?);
        }
        if let Some(rule) = &rules[k] {
            let (t, qw) = rule.on(w[0], w[1]);
            nodes.extend(t);
            weights.extend(qw);
        }
    }
    Ok((nodes, weights))
}

/// A gap coordinate's curve at one node: q = offset + rows·x (per derivative order).
#[derive(Clone, Debug)]
pub struct NodeRows {
    pub offset: [f64; 3],
    pub rows: [Vec<f64>; 3],
    /// The free coefficients whose basis functions are alive here (at most four).
    pub live: std::ops::Range<usize>,
}

impl NodeRows {
    /// q (order 0), q̇ (1) or q̈ (2) for the DOF's free coefficients `xd`.
    pub fn value(&self, order: usize, xd: &[f64]) -> f64 {
        let dot: f64 = self.rows[order].iter().zip(xd).map(|(a, b)| a * b).sum();
        self.offset[order] + dot
    }
}

/// The gaps of one group laid out for a solve. The unknown vector is
/// `[coefficients | extras]`: `n_free` free coefficients per gap DOF, DOF
/// after DOF, then the extra unknowns a term may own beside the curves (the
/// root's coordinates, a value per node; none unless
/// [`GapLayout::with_extras`] adds them). A term reads its extras with
/// [`GapLayout::extras`] and adds to their gradient through
/// [`super::NodeGrad::add_extra`].
#[derive(Clone, Debug)]
pub struct GapLayout {
    pub(crate) dofs: Vec<GapDof>,
    pub(crate) curves: Vec<TransitionCurve>,
    pub(crate) n_free: usize,
    pub(crate) nodes: Vec<f64>,
    pub(crate) qweights: Vec<f64>,
    /// `active[d][k]`: gap DOF d's rows at node k, `None` outside its gap.
    pub(crate) active: Vec<Vec<Option<NodeRows>>>,
    /// The extra unknowns' starting values (their number is its length).
    pub(crate) extras_start: Vec<f64>,
    /// Per gap DOF, the curve its transition corrects, if any (a laid
    /// example, [`GapLayout::with_bases`]): q = base(t) + spline(x).
    pub(crate) bases: Vec<Option<Arc<Curve>>>,
    /// Per gap DOF, the end states its spline meets: the gap's, less the
    /// base's there.
    pub(crate) ends: Vec<(EndState, EndState)>,
}

impl GapLayout {
    /// The curves of `dofs`, the nodes of [`composite_nodes`] and every
    /// DOF's basis rows at every node of its gap. The gaps are taken as
    /// given (the objective checks them against its body first).
    pub fn new(dofs: Vec<GapDof>, settings: &TransitionSettings) -> Result<Self, SpError> {
        let bases = vec![None; dofs.len()];
        Self::with_bases(dofs, settings, bases)
    }

    /// The layout whose gap DOF d is a correction to `bases[d]` where it is
    /// `Some` (a laid example, defined over the gap): q = base(t) + s(t), the
    /// spline s meeting the differences of the end states, so x = 0 is the
    /// base itself and a perfect example is reproduced by construction,
    /// whatever the number of coefficients (issue 42: five per DOF cannot
    /// hold a punch, so a basis alone followed an exact example 7.6 cm off).
    pub fn with_bases(
        dofs: Vec<GapDof>,
        settings: &TransitionSettings,
        bases: Vec<Option<Arc<Curve>>>,
    ) -> Result<Self, SpError> {
        if bases.len() != dofs.len() {
            return Err(invalid(format!(
                "{} base curves for {} gap DOFs",
                bases.len(),
                dofs.len()
            )));
        }
        let curves = dofs
            .iter()
            .map(|d| TransitionCurve::new(d.t0, d.t1, settings.coefficients, settings.continuity))
            .collect::<Result<Vec<_>, _>>()?;
        let ends = dofs
            .iter()
            .zip(&bases)
            .map(|(d, b)| spline_ends(d, b.as_deref()))
            .collect::<Result<Vec<_>, _>>()?;
        let (nodes, qweights) = composite_nodes(&curves, settings.samples)?;
        let n_free = settings.coefficients;
        let mut active = vec![];
        for (((d, c), (e0, e1)), b) in dofs.iter().zip(&curves).zip(&ends).zip(&bases) {
            let fixed = c.coefficients(e0, e1, &vec![0.0; n_free]);
            let rows = nodes
                .iter()
                .map(|&t| rows_at(d, c, &fixed, n_free, t, b.as_deref()))
                .collect::<Result<Vec<_>, _>>()?;
            active.push(rows);
        }
        Ok(GapLayout {
            dofs,
            curves,
            n_free,
            nodes,
            qweights,
            active,
            extras_start: vec![],
            bases,
            ends,
        })
    }

    /// The same layout with extra unknowns after the coefficients, starting
    /// at `start` (replacing any it had); they must be finite.
    pub fn with_extras(mut self, start: Vec<f64>) -> Result<Self, SpError> {
        if let Some(i) = start.iter().position(|v| !v.is_finite()) {
            return Err(invalid(format!(
                "extra unknown {i} starts at {}, which is not finite",
                start[i]
            )));
        }
        self.extras_start = start;
        Ok(self)
    }

    /// Number of unknowns: gap DOFs × free coefficients, then the extras.
    pub fn n_vars(&self) -> usize {
        self.n_coefficients() + self.n_extras()
    }

    /// Number of free coefficients (gap DOFs × free coefficients per DOF):
    /// where the extras start in the unknown vector.
    pub fn n_coefficients(&self) -> usize {
        self.dofs.len() * self.n_free
    }

    /// Number of extra unknowns.
    pub fn n_extras(&self) -> usize {
        self.extras_start.len()
    }

    /// The extra unknowns in `x` (or their part of a gradient).
    pub fn extras<'x>(&self, x: &'x [f64]) -> &'x [f64] {
        &x[self.n_coefficients()..]
    }

    /// The extras' part of a gradient (or of x), to write.
    pub fn extras_mut<'x>(&self, g: &'x mut [f64]) -> &'x mut [f64] {
        let n = self.n_coefficients();
        &mut g[n..]
    }

    pub fn n_free(&self) -> usize {
        self.n_free
    }

    pub fn dofs(&self) -> &[GapDof] {
        &self.dofs
    }

    pub fn curves(&self) -> &[TransitionCurve] {
        &self.curves
    }

    /// The quadrature nodes (s) and their weights.
    pub fn nodes(&self) -> (&[f64], &[f64]) {
        (&self.nodes, &self.qweights)
    }

    /// Gap DOF d's rows at node k, `None` outside its gap.
    pub fn rows(&self, d: usize, k: usize) -> Option<&NodeRows> {
        self.active[d][k].as_ref()
    }

    /// Whether t lies in the gap of some DOF of coordinate c.
    pub fn in_gap(&self, c: usize, t: f64) -> bool {
        self.dofs
            .iter()
            .any(|d| d.coord == c && t >= d.t0 && t <= d.t1)
    }

    /// The free coefficients of DOF d in `x`.
    pub fn of_dof<'x>(&self, d: usize, x: &'x [f64]) -> &'x [f64] {
        &x[d * self.n_free..(d + 1) * self.n_free]
    }

    /// The starting point: every gap DOF's free coefficients fitted to the
    /// Hermite curve (cubic for C¹ — exactly representable — quintic for C²),
    /// then the extras' starting values.
    pub fn hermite_start(&self) -> Vec<f64> {
        let mut x = vec![];
        for (d, ((dof, c), (e0, e1))) in self
            .dofs
            .iter()
            .zip(&self.curves)
            .zip(&self.ends)
            .enumerate()
        {
            let base = self.bases[d].as_deref();
            let hermite = |t: f64| {
                let h = match c.continuity() {
                    Continuity::C1 => {
                        super::super::hermite::cubic(dof.t0, dof.t1, &dof.start, &dof.end, t)[0]
                    }
                    Continuity::C2 => {
                        super::super::hermite::quintic(dof.t0, dof.t1, &dof.start, &dof.end, t)[0]
                    }
                };
                h - base.map_or(0.0, |b| b.value(t).unwrap_or(f64::NAN))
            };
            x.extend(c.fit_free(e0, e1, hermite));
        }
        x.extend_from_slice(&self.extras_start);
        x
    }

    /// The starting point on the bases: zero correction where a DOF has a
    /// base (the laid example itself), the Hermite fit where it has none,
    /// then the extras' starting values.
    pub fn base_start(&self) -> Vec<f64> {
        let hermite = self.hermite_start();
        let mut x = vec![];
        for d in 0..self.dofs.len() {
            match self.bases[d] {
                Some(_) => x.extend(std::iter::repeat_n(0.0, self.n_free)),
                None => x.extend_from_slice(self.of_dof(d, &hermite)),
            }
        }
        x.extend_from_slice(&self.extras_start);
        x
    }

    /// Whether any gap DOF corrects a base curve.
    pub fn has_bases(&self) -> bool {
        self.bases.iter().any(Option::is_some)
    }

    /// Full spline coefficient vectors of every gap DOF for unknowns x (the
    /// extras, if any, are not read): the correction's, where a DOF has a base.
    pub fn coefficients(&self, x: &[f64]) -> Vec<Vec<f64>> {
        self.dofs
            .iter()
            .zip(&self.curves)
            .zip(&self.ends)
            .enumerate()
            .map(|(d, ((_, c), (e0, e1)))| c.coefficients(e0, e1, self.of_dof(d, x)))
            .collect()
    }

    /// Gap DOF d's curve for unknowns x, as the motion stores it: the
    /// spline, or its base plus the spline.
    pub fn curve(&self, d: usize, x: &[f64]) -> Result<Curve, SpError> {
        let (e0, e1) = &self.ends[d];
        let c = &self.curves[d];
        let spline = Curve::Spline(c.to_curve(c.coefficients(e0, e1, self.of_dof(d, x)))?);
        Ok(match &self.bases[d] {
            Some(b) => Curve::Sum(b.clone(), Arc::new(spline)),
            None => spline,
        })
    }

    /// q, q̇, q̈ of gap DOF d at time t (inside its gap) for unknowns x.
    pub fn state(&self, d: usize, x: &[f64], t: f64) -> Result<[f64; 3], SpError> {
        let (e0, e1) = &self.ends[d];
        let c = &self.curves[d];
        let mut s = c.eval(&c.coefficients(e0, e1, self.of_dof(d, x)), t);
        if let Some(b) = &self.bases[d] {
            let o = b.eval(t).map_err(SpError::Motion)?;
            for (s, o) in s.iter_mut().zip(o) {
                *s += o;
            }
        }
        Ok(s)
    }
}

/// The end states gap DOF `d`'s spline meets: its own, less `base`'s there.
fn spline_ends(d: &GapDof, base: Option<&Curve>) -> Result<(EndState, EndState), SpError> {
    let Some(b) = base else {
        return Ok((d.start, d.end));
    };
    let less = |e: &EndState, t: f64| -> Result<EndState, SpError> {
        let [q, v, a] = b.eval(t).map_err(SpError::Motion)?;
        let out = EndState {
            q: e.q - q,
            v: e.v - v,
            a: e.a - a,
        };
        if [out.q, out.v, out.a].iter().all(|x| x.is_finite()) {
            Ok(out)
        } else {
            Err(invalid(format!(
                "the base curve of coordinate {} is not finite at {t} s",
                d.coord
            )))
        }
    };
    Ok((less(&d.start, d.t0)?, less(&d.end, d.t1)?))
}

/// Gap DOF `d`'s rows at time t (`None` outside its gap): the basis of its
/// curve split into the part the coefficients `fixed` by the end states give
/// (the offset) and the free coefficients' rows.
fn rows_at(
    d: &GapDof,
    c: &TransitionCurve,
    fixed: &[f64],
    n_free: usize,
    t: f64,
    base: Option<&Curve>,
) -> Result<Option<NodeRows>, SpError> {
    if t < d.t0 || t > d.t1 {
        return Ok(None);
    }
    let k0 = c.first_free();
    let b = c.basis_at(t);
    let mut offset = [0.0; 3];
    for (o, row) in offset.iter_mut().zip(&b) {
        *o = row.iter().zip(fixed).map(|(x, y)| x * y).sum();
    }
    if let Some(base) = base {
        let at = base.eval(t).map_err(SpError::Motion)?;
        for (o, b) in offset.iter_mut().zip(at) {
            *o += b;
        }
    }
    let rows = [
        b[0][k0..k0 + n_free].to_vec(),
        b[1][k0..k0 + n_free].to_vec(),
        b[2][k0..k0 + n_free].to_vec(),
    ];
    let alive = |j: &usize| rows.iter().any(|r| r[*j] != 0.0);
    let lo = (0..n_free).find(alive).unwrap_or(0);
    let hi = (0..n_free).rev().find(alive).map_or(lo, |j| j + 1);
    Ok(Some(NodeRows {
        offset,
        rows,
        live: lo..hi,
    }))
}
