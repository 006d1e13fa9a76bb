//! Parallel parameter sweeps (rayon).
//!
//! Without the `parallel` feature [`sweep`] runs the points serially, in order, with the same
//! results, and [`sweep_with_threads`] is not compiled.

/// Runs `f` on every parameter (in parallel with the `parallel` feature) and returns the
/// results in input order, bit-identical for any number of threads; `progress(done, total)` is
/// called after each completed point. The workspace's one sweep, [`system::sweep::sweep`].
pub use system::sweep::sweep;
/// As [`sweep`] with the points taken by value ([`system::sweep::sweep_owned`]).
pub use system::sweep::sweep_owned;

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
    // the pool's threads do not see this thread's work account: carry it over
    let account = system::account::current();
    Ok(pool.install(move || {
        system::account::scope_opt(account.as_ref(), || sweep(params, f, progress))
    }))
}
