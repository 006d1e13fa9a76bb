//! Parallel parameter sweeps (rayon).
//!
//! Without the `parallel` feature [`sweep`] runs the points serially, in order, with the same
//! results, and [`sweep_with_threads`] is not compiled.

use std::sync::atomic::{AtomicUsize, Ordering};

#[cfg(feature = "parallel")]
use rayon::prelude::*;

/// Runs `f` on every parameter in parallel and returns the results in input order.
///
/// Each result depends only on its own parameter (no parallel reduction), so the output is
/// bit-identical for any number of threads. `progress(done, total)` is called after each
/// completed point, from the worker threads, in completion order.
pub fn sweep<P, R, F>(
    params: &[P],
    f: F,
    progress: Option<&(dyn Fn(usize, usize) + Sync)>,
) -> Vec<R>
where
    P: Sync,
    R: Send,
    F: Fn(&P) -> R + Sync,
{
    let done = AtomicUsize::new(0);
    let total = params.len();
    #[cfg(feature = "parallel")]
    let points = params.par_iter();
    #[cfg(not(feature = "parallel"))]
    let points = params.iter();
    points
        .map(|p| {
            let r = f(p);
            let k = done.fetch_add(1, Ordering::Relaxed) + 1;
            if let Some(cb) = progress {
                cb(k, total);
            }
            r
        })
        .collect()
}

/// As [`sweep`], on a dedicated pool of `threads` threads (≥ 1).
#[cfg(feature = "parallel")]
pub fn sweep_with_threads<P, R, F>(
    threads: usize,
    params: &[P],
    f: F,
    progress: Option<&(dyn Fn(usize, usize) + Sync)>,
) -> crate::Result<Vec<R>>
where
    P: Sync,
    R: Send,
    F: Fn(&P) -> R + Sync,
{
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.max(1))
        .build()
        .map_err(|_| crate::Error::InvalidParameter {
            name: "threads (pool could not be built)",
            bound: "available",
            value: threads as f64,
        })?;
    let f = &f;
    Ok(pool.install(move || sweep(params, f, progress)))
}
