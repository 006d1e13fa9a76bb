//! FFT plans shared by every problem and solution on one thread.
//!
//! Planning a 1024-point FFT costs more than a whole Newton iteration of a small problem, so
//! plans are cached per thread (a planner reuses a plan for a size it has seen). The planners are
//! `geardyn-fft`'s, which compiles rustfft's generic algorithms once, in that crate.

use fft::{Fft, FftPlanner, RealFftPlanner, RealToComplex};
use num_complex::Complex;
use std::cell::RefCell;
use std::sync::Arc;

/// A complex FFT buffer.
type Buffer = Vec<Complex<f64>>;

thread_local! {
    static PLANNER: RefCell<FftPlanner> = RefCell::new(FftPlanner::new());
    static REAL_PLANNER: RefCell<RealFftPlanner> = RefCell::new(RealFftPlanner::new());
    /// signal and scratch buffers of [`with_buffers`], kept between calls
    static BUFFERS: RefCell<(Buffer, Buffer)> =
        const { RefCell::new((Vec::new(), Vec::new())) };
}

/// Run `f` with this thread's buffers resized to `n` (signal) and `scratch` elements, contents
/// unspecified; saves allocating (and faulting in) large buffers at every call.
pub(crate) fn with_buffers<T>(
    n: usize,
    scratch: usize,
    f: impl FnOnce(&mut [Complex<f64>], &mut [Complex<f64>]) -> T,
) -> T {
    BUFFERS.with(|b| match b.try_borrow_mut() {
        Ok(mut b) => {
            let (buf, scr) = &mut *b;
            buf.resize(n, Complex::default());
            scr.resize(scratch, Complex::default());
            f(&mut buf[..n], &mut scr[..scratch])
        }
        // re-entered (cannot happen today): fresh buffers
        Err(_) => f(
            &mut vec![Complex::default(); n],
            &mut vec![Complex::default(); scratch],
        ),
    })
}

/// Forward and inverse plans of size `n` (cached on this thread).
pub(crate) fn plans(n: usize) -> (Arc<dyn Fft<f64>>, Arc<dyn Fft<f64>>) {
    PLANNER.with(|p| {
        let mut p = p.borrow_mut();
        (p.plan_forward(n), p.plan_inverse(n))
    })
}

/// Real-to-complex forward plan of size `n` (cached on this thread): the `n/2 + 1` bins
/// `0..=n/2` of the DFT of a real signal, at about half the cost of a complex FFT of size `n`.
pub(crate) fn real_forward(n: usize) -> Arc<dyn RealToComplex<f64>> {
    REAL_PLANNER.with(|p| p.borrow_mut().plan_forward(n))
}
