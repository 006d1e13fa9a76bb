//! FFT plans shared by every problem and solution on one thread.
//!
//! Planning a 1024-point FFT costs more than a whole Newton iteration of a small problem, so
//! plans are cached per thread (a `rustfft::FftPlanner` reuses a plan for a size it has seen).
//! A plan depends only on the size and the CPU, so the cache changes no result.

use rustfft::{Fft, FftPlanner};
use std::cell::RefCell;
use std::sync::Arc;

thread_local! {
    static PLANNER: RefCell<FftPlanner<f64>> = RefCell::new(FftPlanner::new());
}

/// Forward and inverse plans of size `n` (cached on this thread).
pub(crate) fn plans(n: usize) -> (Arc<dyn Fft<f64>>, Arc<dyn Fft<f64>>) {
    PLANNER.with(|p| {
        let mut p = p.borrow_mut();
        (p.plan_fft_forward(n), p.plan_fft_inverse(n))
    })
}
