//! The objective as argmin sees it: cost and gradient in the whitened
//! variables y (x = T y), from one evaluation (the adjoint gives both, and
//! argmin asks for them separately at the same point), remembering the best
//! point seen, polling the cancel token and telling the progress callback.

use crate::cancel::CancelToken;
use crate::spacetime::objective::{Objective, Scratch};
use crate::spacetime::precond::Precond;
use crate::spacetime::progress::{Progress, ProgressEvent};
use crate::spacetime::torque::TorqueModel;
use argmin::core::{CostFunction, Error, Gradient};
use std::cell::RefCell;

/// The best point seen: x, e(x), ∂e/∂x.
pub(super) struct Best {
    pub x: Vec<f64>,
    pub e: f64,
    pub g: Vec<f64>,
}

/// What evaluations change: argmin's traits take `&self`, hence one `RefCell`.
struct State<W> {
    /// x = T(y); the solver works in y (re-linearised between rounds).
    t: Precond,
    scratch: Scratch<W>,
    /// The last evaluated point: (y, e, ∂e/∂y).
    last: Option<(Vec<f64>, f64, Vec<f64>)>,
    best: Option<Best>,
    evaluations: u64,
}

/// One solve's view of its objective.
pub(super) struct Evaluator<'o, 'a, M: TorqueModel> {
    obj: &'o Objective<'a, M>,
    state: RefCell<State<M::Workspace>>,
    cancel: CancelToken,
    progress: Progress,
}

impl<'o, 'a, M: TorqueModel> Evaluator<'o, 'a, M> {
    pub fn new(
        obj: &'o Objective<'a, M>,
        t: Precond,
        scratch: Scratch<M::Workspace>,
        cancel: CancelToken,
        progress: Progress,
    ) -> Self {
        Evaluator {
            obj,
            state: RefCell::new(State {
                t,
                scratch,
                last: None,
                best: None,
                evaluations: 0,
            }),
            cancel,
            progress,
        }
    }

    pub fn to_y(&self, x: &[f64]) -> Vec<f64> {
        self.state.borrow().t.solve(x)
    }

    /// e and ∂e/∂y = Tᵀ ∂e/∂x at y.
    pub fn eval(&self, y: &[f64]) -> Result<(f64, Vec<f64>), Error> {
        if let Some((ly, le, lg)) = self.state.borrow().last.as_ref()
            && ly.as_slice() == y
        {
            return Ok((*le, lg.clone()));
        }
        let x = self.state.borrow().t.apply(y);
        let (e, gx) = self.eval_x(&x)?;
        let mut s = self.state.borrow_mut();
        let gy = s.t.apply_t(&gx);
        s.last = Some((y.to_vec(), e, gy.clone()));
        Ok((e, gy))
    }

    /// e and ∂e/∂x at x (the best point is updated).
    pub fn eval_x(&self, x: &[f64]) -> Result<(f64, Vec<f64>), Error> {
        if self.cancel.is_cancelled() {
            return Err(Error::new(crate::spacetime::SpError::Cancelled));
        }
        let mut g = vec![0.0; x.len()];
        let mut s = self.state.borrow_mut();
        let e = self
            .obj
            .eval(&mut s.scratch, x, Some(&mut g))
            .map_err(Error::new)?;
        s.evaluations += 1;
        self.progress.report(ProgressEvent::Evaluation);
        if s.best.as_ref().is_none_or(|b| e < b.e) {
            s.best = Some(Best {
                x: x.to_vec(),
                e,
                g: g.clone(),
            });
        }
        Ok((e, g))
    }

    /// The best point's x so far, if any was evaluated.
    pub fn best_x(&self) -> Option<Vec<f64>> {
        self.state.borrow().best.as_ref().map(|b| b.x.clone())
    }

    /// Rebuilds the preconditioner at x (a new round starts there) and
    /// forgets the last point, which was in the old variables.
    pub fn relinearise_at(&self, x: &[f64]) -> Result<(), crate::spacetime::SpError> {
        let mut s = self.state.borrow_mut();
        let t = self.obj.gauss_newton_at(&mut s.scratch, x)?;
        s.t = t;
        s.last = None;
        Ok(())
    }

    /// The best point and how many evaluations were made.
    pub fn finish(self) -> (Option<Best>, u64) {
        let s = self.state.into_inner();
        (s.best, s.evaluations)
    }
}

/// argmin owns its problem; lend it ours so the best point survives the run.
pub(super) struct Lend<'p, 'o, 'a, M: TorqueModel>(pub &'p Evaluator<'o, 'a, M>);

impl<M: TorqueModel> CostFunction for Lend<'_, '_, '_, M> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, x: &Vec<f64>) -> Result<f64, Error> {
        Ok(self.0.eval(x)?.0)
    }
}

impl<M: TorqueModel> Gradient for Lend<'_, '_, '_, M> {
    type Param = Vec<f64>;
    type Gradient = Vec<f64>;
    fn gradient(&self, x: &Vec<f64>) -> Result<Vec<f64>, Error> {
        Ok(self.0.eval(x)?.1)
    }
}
