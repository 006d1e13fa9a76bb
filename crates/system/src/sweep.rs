//! The one ordered parallel map over sweep points that every engine and study uses.
//!
//! A sweep evaluates independent points `r_i = f(p_i)` and returns them in input order. Each
//! result depends only on its own point (no parallel reduction), so the output is bit-identical
//! for any number of threads. With the `parallel` feature the points run on the current rayon
//! pool; without it they run serially, in order, with the same results.
//!
//! The [work account](crate::account) in force where a sweep is called is put in force around
//! each of its points, on whichever thread runs it, and counts the points.

use std::sync::atomic::{AtomicUsize, Ordering};

#[cfg(feature = "parallel")]
use rayon::prelude::*;

/// Progress callback `progress(done, total)`, called after each completed point from the worker
/// threads, in completion order.
pub type Progress<'a> = Option<&'a (dyn Fn(usize, usize) + Sync)>;

/// Runs `f` on every point (borrowed) and returns the results in input order.
pub fn sweep<P, R, F>(points: &[P], f: F, progress: Progress<'_>) -> Vec<R>
where
    P: Sync,
    R: Send,
    F: Fn(&P) -> R + Sync,
{
    let done = AtomicUsize::new(0);
    let total = points.len();
    let account = crate::account::current();
    crate::account::plan_points(account.as_ref(), total);
    let one = |p: &P| {
        let r = crate::account::scope_opt(account.as_ref(), || f(p));
        crate::account::point_done(account.as_ref());
        tick(&done, total, progress);
        r
    };
    #[cfg(feature = "parallel")]
    let out = points.par_iter().map(one).collect();
    #[cfg(not(feature = "parallel"))]
    let out = points.iter().map(one).collect();
    out
}

/// As [`sweep`], taking the points by value (for points that own their work, e.g. boxed
/// `FnOnce` jobs).
pub fn sweep_owned<P, R, F>(points: Vec<P>, f: F, progress: Progress<'_>) -> Vec<R>
where
    P: Send,
    R: Send,
    F: Fn(P) -> R + Sync,
{
    let done = AtomicUsize::new(0);
    let total = points.len();
    let account = crate::account::current();
    crate::account::plan_points(account.as_ref(), total);
    let one = |p: P| {
        let r = crate::account::scope_opt(account.as_ref(), || f(p));
        crate::account::point_done(account.as_ref());
        tick(&done, total, progress);
        r
    };
    #[cfg(feature = "parallel")]
    let out = points.into_par_iter().map(one).collect();
    #[cfg(not(feature = "parallel"))]
    let out = points.into_iter().map(one).collect();
    out
}

fn tick(done: &AtomicUsize, total: usize, progress: Progress<'_>) {
    let k = done.fetch_add(1, Ordering::Relaxed) + 1;
    if let Some(cb) = progress {
        cb(k, total);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn results_keep_input_order_and_progress_counts_every_point() {
        let xs: Vec<u64> = (0..200).collect();
        let calls = AtomicUsize::new(0);
        let cb = |_: usize, total: usize| {
            assert_eq!(total, 200);
            calls.fetch_add(1, Ordering::Relaxed);
        };
        let r = sweep(&xs, |x| x * x, Some(&cb));
        assert_eq!(r, xs.iter().map(|x| x * x).collect::<Vec<_>>());
        let r2 = sweep_owned(xs.clone(), |x| x + 1, Some(&cb));
        assert_eq!(r2, xs.iter().map(|x| x + 1).collect::<Vec<_>>());
        assert_eq!(calls.load(Ordering::Relaxed), 400);
    }

    #[cfg(feature = "parallel")]
    #[test]
    fn bit_identical_for_any_thread_count() {
        use math::DetMath;
        let xs: Vec<f64> = (0..500).map(|i| 0.01 * f64::from(i)).collect();
        let f = |x: &f64| (0..100).fold(*x, |a, k| (a + f64::from(k)).dsin());
        let run = |n: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap()
                .install(|| sweep(&xs, f, None))
        };
        let one = run(1);
        for n in [2, 3, 7] {
            let other = run(n);
            assert!(
                one.iter()
                    .zip(&other)
                    .all(|(a, b)| a.to_bits() == b.to_bits())
            );
        }
    }
}
