//! Nelder–Mead on argmin with parallel, speculative evaluations.
//!
//! [`SpeculativeNelderMead`] is an argmin [`Solver`] that runs the same algorithm as argmin's
//! own `NelderMead` (argmin 0.11: reflection α = 1, expansion γ = 2, contraction ρ = 0.5,
//! shrink σ = 0.5, the same centroid, ordering, acceptance tests and standard-deviation
//! stopping rule, in the same floating-point operations), so it visits the same points and
//! returns the same answer (`tests/placement_search.rs` checks this against argmin's solver).
//! What differs is how the points are evaluated:
//!
//! - the initial simplex and every shrink are evaluated as one parallel batch;
//! - each iteration evaluates the reflected point together with a guess of the point the
//!   iteration may need next, in parallel: the inside contraction (the step a simplex closing
//!   in on a feasibility boundary takes most: 47 of the 76 iterations of the default job, where
//!   guessing the kind of the last step was right 29 times and this guess 47 times). When the
//!   guess is right, the iteration costs one evaluation's wall time instead of two; when the
//!   reflected point shows that it is not needed (its cost is below the worst vertex's), the
//!   guess is abandoned where it stands ([`BatchCost::evaluate_guessed`]), so that the next
//!   evaluation (the expansion, the outside contraction, the next iteration) gets both
//!   threads sooner.
//!
//! The cost function sees the evaluations **committed** in exactly the order a sequential
//! Nelder–Mead would ask for them ([`BatchCost::commit`]): budgets, histories and the visited
//! set are identical; an unused guess is discarded (counted separately as speculative work).
//! How many guesses are made depends only on the simplex, never on timing or the thread count
//! (one guess per iteration; none when the cost function says it runs on one thread), so the
//! answer is identical for any thread count.

use argmin::core::{Error, IterState, Problem, Solver, TerminationReason, TerminationStatus, KV};

/// A cost function that can evaluate a batch of points in parallel and then hand the results
/// to the algorithm one by one, in the order the algorithm asks for them.
pub trait BatchCost {
    /// An evaluated point, not yet counted.
    type Pending: Send;
    /// Evaluate `points` (in parallel where it pays); nothing is counted yet. The result has
    /// one entry per point, in order.
    fn evaluate(&self, points: &[Vec<f64>]) -> Result<Vec<Self::Pending>, Error>;
    /// The algorithm takes `p` as its next cost evaluation: count it and return its cost.
    fn commit(&self, p: Self::Pending) -> Result<f64, Error>;
    /// Whether speculative guesses can run beside the needed evaluation (more than one
    /// worker thread).
    fn parallel(&self) -> bool;
    /// Record that a speculative evaluation was not needed.
    fn discarded(&self, _p: Self::Pending) {}
    /// Evaluate `point` and, beside it, `guess`, which the algorithm needs next only when
    /// `point`'s cost is at least `needed_from`: an unneeded guess may be abandoned part-way
    /// (`None`). A needed guess must be returned in full. Default: both as one batch.
    fn evaluate_guessed(
        &self,
        point: &[f64],
        guess: &[f64],
        needed_from: f64,
    ) -> Result<(Self::Pending, Option<Self::Pending>), Error> {
        let _ = needed_from;
        let mut v = self.evaluate(&[point.to_vec(), guess.to_vec()])?;
        let g = v.pop();
        let p = v.pop().ok_or_else(|| Error::msg("no evaluation"))?;
        Ok((p, g))
    }
}

/// Nelder–Mead with parallel batches and one speculative evaluation per iteration; the
/// iterates are those of argmin's `NelderMead` with default coefficients.
#[derive(Clone, Debug)]
pub struct SpeculativeNelderMead {
    params: Vec<(Vec<f64>, f64)>,
    sd_tolerance: f64,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Action {
    Reflection,
    Expansion,
    ContractionOutside,
    ContractionInside,
    Shrink,
}

const ALPHA: f64 = 1.0;
const GAMMA: f64 = 2.0;
const RHO: f64 = 0.5;
const SIGMA: f64 = 0.5;

fn add(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).map(|(x, y)| x + y).collect()
}
fn sub(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).map(|(x, y)| x - y).collect()
}
fn mul(a: &[f64], s: f64) -> Vec<f64> {
    a.iter().map(|x| x * s).collect()
}

impl SpeculativeNelderMead {
    /// A solver from the initial simplex (`dim + 1` points of dimension `dim`).
    pub fn new(simplex: Vec<Vec<f64>>) -> Self {
        SpeculativeNelderMead {
            params: simplex.into_iter().map(|p| (p, f64::NAN)).collect(),
            sd_tolerance: f64::EPSILON,
        }
    }

    /// Stop when the standard deviation of the simplex's costs falls below `tol` (≥ 0).
    pub fn with_sd_tolerance(mut self, tol: f64) -> Result<Self, Error> {
        if tol.is_nan() || tol < 0.0 {
            return Err(Error::msg("sd_tolerance must be >= 0"));
        }
        self.sd_tolerance = tol;
        Ok(self)
    }

    fn sort(&mut self) {
        self.params
            .sort_by(|a, b| a.1.partial_cmp(&b.1).unwrap_or(std::cmp::Ordering::Equal));
    }

    fn centroid(&self) -> Vec<f64> {
        let num = self.params.len() - 1;
        let s = self
            .params
            .iter()
            .take(num)
            .skip(1)
            .fold(self.params[0].0.clone(), |acc, p| add(&acc, &p.0));
        mul(&s, 1.0 / num as f64)
    }

    fn reflect(x0: &[f64], x: &[f64]) -> Vec<f64> {
        add(x0, &mul(&sub(x0, x), ALPHA))
    }
    fn expand(x0: &[f64], x: &[f64]) -> Vec<f64> {
        add(x0, &mul(&sub(x, x0), GAMMA))
    }
    fn contract(x0: &[f64], x: &[f64]) -> Vec<f64> {
        add(x0, &mul(&sub(x, x0), RHO))
    }

    /// Evaluate `points` as one batch and commit them in order.
    fn batch<O: BatchCost>(o: &O, points: &[Vec<f64>]) -> Result<Vec<f64>, Error> {
        let mut out = Vec::with_capacity(points.len());
        for p in o.evaluate(points)? {
            out.push(o.commit(p)?);
        }
        Ok(out)
    }

    fn shrink<O: BatchCost>(&mut self, o: &O) -> Result<(), Error> {
        let x0 = self.params[0].0.clone();
        let pts: Vec<Vec<f64>> = self
            .params
            .iter()
            .skip(1)
            .map(|(p, _)| add(&x0, &mul(&sub(p, &x0), SIGMA)))
            .collect();
        // Commit one by one, so that a budget running out stops at the same point as a
        // sequential shrink would.
        let pending = o.evaluate(&pts)?;
        for ((slot, p), pend) in self.params.iter_mut().skip(1).zip(pts).zip(pending) {
            slot.0 = p;
            slot.1 = o.commit(pend)?;
        }
        Ok(())
    }
}

type St = IterState<Vec<f64>, (), (), (), (), f64>;

impl<O: BatchCost> Solver<O, St> for SpeculativeNelderMead {
    fn name(&self) -> &str {
        "Nelder-Mead method (parallel, speculative)"
    }

    fn init(&mut self, problem: &mut Problem<O>, state: St) -> Result<(St, Option<KV>), Error> {
        let o = problem
            .problem
            .as_ref()
            .ok_or_else(|| Error::msg("no problem"))?;
        let pts: Vec<Vec<f64>> = self.params.iter().map(|p| p.0.clone()).collect();
        let costs = Self::batch(o, &pts)?;
        for (p, c) in self.params.iter_mut().zip(costs) {
            p.1 = c;
        }
        self.sort();
        Ok((
            state.param(self.params[0].0.clone()).cost(self.params[0].1),
            None,
        ))
    }

    fn next_iter(
        &mut self,
        problem: &mut Problem<O>,
        state: St,
    ) -> Result<(St, Option<KV>), Error> {
        let o = problem
            .problem
            .as_ref()
            .ok_or_else(|| Error::msg("no problem"))?;
        let n = self.params.len();
        let x0 = self.centroid();
        let best_c = self.params[0].1;
        let worst = self.params[n - 1].clone();
        let second_worst_c = self.params[n - 2].1;
        let xr = Self::reflect(&x0, &worst.0);
        // The guess: always the inside contraction (deterministic; see the module docs), the
        // point needed next exactly when the reflected point is no better than the worst.
        let (pend, mut spec) = if o.parallel() {
            o.evaluate_guessed(&xr, &Self::contract(&x0, &worst.0), worst.1)?
        } else {
            let mut v = o.evaluate(std::slice::from_ref(&xr))?;
            (v.pop().ok_or_else(|| Error::msg("no evaluation"))?, None)
        };
        let xr_c = o.commit(pend)?;
        // The second evaluation: the guess when it is the point needed, else evaluated now.
        let mut second = |inside: bool, p: &Vec<f64>| -> Result<f64, Error> {
            match spec.take() {
                Some(s) if inside => o.commit(s),
                other => {
                    if let Some(s) = other {
                        o.discarded(s);
                    }
                    let mut v = o.evaluate(std::slice::from_ref(p))?;
                    o.commit(v.pop().ok_or_else(|| Error::msg("no evaluation"))?)
                }
            }
        };
        let action = if xr_c < second_worst_c && xr_c >= best_c {
            self.params[n - 1] = (xr, xr_c);
            Action::Reflection
        } else if xr_c < best_c {
            let xe = Self::expand(&x0, &xr);
            let xe_c = second(false, &xe)?;
            self.params[n - 1] = if xe_c < xr_c { (xe, xe_c) } else { (xr, xr_c) };
            Action::Expansion
        } else if xr_c >= second_worst_c {
            if xr_c < worst.1 {
                let xc = Self::contract(&x0, &xr);
                let xc_c = second(false, &xc)?;
                if xc_c <= xr_c {
                    self.params[n - 1] = (xc, xc_c);
                    Action::ContractionOutside
                } else {
                    self.shrink(o)?;
                    Action::Shrink
                }
            } else {
                let xc = Self::contract(&x0, &worst.0);
                let xc_c = second(true, &xc)?;
                if xc_c < worst.1 {
                    self.params[n - 1] = (xc, xc_c);
                    Action::ContractionInside
                } else {
                    self.shrink(o)?;
                    Action::Shrink
                }
            }
        } else {
            // NaN costs: argmin's solver reports a potential bug here.
            return Err(Error::msg("Nelder-Mead: cost is NaN"));
        };
        if let Some(s) = spec.take() {
            o.discarded(s);
        }
        self.sort();
        Ok((
            state.param(self.params[0].0.clone()).cost(self.params[0].1),
            Some(argmin::kv!("action" => format!("{action:?}");)),
        ))
    }

    fn terminate(&mut self, _state: &St) -> TerminationStatus {
        let n = self.params.len() as f64;
        let c0: f64 = self.params.iter().map(|(_, c)| *c).sum::<f64>() / n;
        let s: f64 = (1.0 / (n - 1.0)
            * self
                .params
                .iter()
                .map(|(_, c)| (*c - c0).powi(2))
                .sum::<f64>())
        .sqrt();
        if s < self.sd_tolerance {
            return TerminationStatus::Terminated(TerminationReason::SolverConverged);
        }
        TerminationStatus::NotTerminated
    }
}
