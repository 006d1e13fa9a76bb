//! Parallel parameter sweeps (rayon), bit-identical for any number of threads.
//!
//! Without the `parallel` feature the same function runs the points serially, in order, with
//! the same results.

use crate::{HbmError, HbmProblem, PeriodicSolution, SecondOrderSystem, SolverOptions};

/// Solve independent problems for each parameter value in parallel.
///
/// `make(value)` builds the problem for one value (e.g. a system with that load at frequency
/// `ω`), `guess(value, &problem)` gives its initial coefficients. Every point is solved
/// independently from its own guess and the results are collected in input order, so the output
/// is bit-identical whatever the size of the rayon thread pool. (Use
/// `orbit::continue_hbm` (crate `geardyn-orbit`) when points should follow one branch.)
pub fn parallel_sweep<S, F, G>(
    values: &[f64],
    make: F,
    guess: G,
    options: &SolverOptions,
) -> Vec<Result<PeriodicSolution, HbmError>>
where
    S: SecondOrderSystem,
    F: Fn(f64) -> Result<HbmProblem<S>, HbmError> + Sync,
    G: Fn(f64, &HbmProblem<S>) -> Vec<f64> + Sync,
{
    system::sweep::sweep(
        values,
        |&v| {
            let mut p = make(v)?;
            let z0 = guess(v, &p);
            p.solve(&z0, options)
        },
        None,
    )
}
