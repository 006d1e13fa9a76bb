//! # fft
//!
//! The FFT planning of the geardyn engines: [rustfft] and [realfft] for `f64` behind concrete,
//! non-generic planners.
//!
//! Conventions (rustfft's, unnormalised): for `N` samples `x_j` the forward transform is
//!
//! `X_k = Σ_{j=0}^{N−1} x_j e^{−2πi jk/N}`, k = 0..N,
//!
//! the inverse is the same sum with `e^{+2πi jk/N}`, so inverse ∘ forward multiplies by `N`. The
//! real-to-complex forward transform ([`RealFftPlanner::plan_forward`]) returns the bins
//! `0..=N/2` of the forward DFT of a real signal (the others are their conjugates,
//! `X_{N−k} = conj X_k`); the complex-to-real inverse takes those `N/2 + 1` bins and returns
//! the `N` real samples of the unnormalised inverse.
//!
//! ## Why a crate of its own
//!
//! Generic code is compiled in the crate that names its type parameters. A crate that calls
//! `rustfft::FftPlanner::<f64>::new()` compiles every FFT algorithm and butterfly of rustfft
//! (thousands of functions) at its own opt-level, and once more for its unit-test harness. Here
//! that happens once per build, and at the opt-level of this crate (3 in the workspace's dev and
//! test profile); the engine crates call the non-generic functions of [`FftPlanner`] and
//! [`RealFftPlanner`] and run the plans through the `dyn` traits [`Fft`], [`RealToComplex`] and
//! [`ComplexToReal`] (re-exported here).
//!
//! ## One code path on every CPU
//!
//! rustfft's planner picks AVX, SSE or NEON algorithms at run time when its cargo features
//! `avx`, `sse`, `neon` are on (its default); those sum in other orders than the scalar
//! algorithms, so a result would depend on the CPU. The workspace builds rustfft and realfft
//! without these features, so the planner has only the scalar algorithms
//! (`rustfft::FftPlannerScalar`'s choices) on every CPU, and every FFT that reaches an output
//! gives the same bits everywhere (tested: `plans_are_rustffts_scalar_algorithms`). Their
//! twiddle factors come from `f64::sin`/`cos`, which the output binaries bind to
//! `geardyn-math` (its `c-symbols` feature). What pinning costs is in the README.
//!
//! ## Same plans, same bytes
//!
//! The planners wrap rustfft's and realfft's one to one: a plan for a length is the plan rustfft
//! chooses for it, so a result is the bytes rustfft gives. rustfft's planner
//! reuses, for a new length, plans it already holds for the lengths of the steps of the new plan;
//! a planner kept between calls (as `geardyn-hbm` keeps one per thread) can therefore choose a
//! different decomposition than a fresh one. Whoever held a fresh `rustfft::FftPlanner` per call
//! holds a fresh [`FftPlanner`] per call here, and whoever kept one keeps one.
//!
//! Any length is accepted, `0` and `1` included (rustfft's behaviour: an empty or identity
//! transform); a buffer of the wrong length is reported by rustfft (a panic in
//! [`Fft::process`], an [`FftError`] from the real transforms), as before.

use std::sync::Arc;

pub use num_complex::Complex;
pub use realfft::{ComplexToReal, FftError, RealToComplex};
pub use rustfft::{Fft, FftDirection, Length};

/// Planner of complex `f64` FFTs (rustfft's `FftPlanner<f64>`, built without its SIMD features:
/// the scalar algorithms on every CPU).
///
/// Plans are cached by the planner: planning the same length twice returns the same plan.
pub struct FftPlanner {
    inner: rustfft::FftPlanner<f64>,
}

impl FftPlanner {
    /// A new planner with an empty cache.
    #[inline(never)]
    pub fn new() -> Self {
        Self {
            inner: rustfft::FftPlanner::new(),
        }
    }

    /// Forward transform of length `len`, `X_k = Σ_j x_j e^{−2πi jk/N}`.
    #[inline(never)]
    pub fn plan_forward(&mut self, len: usize) -> Arc<dyn Fft<f64>> {
        self.inner.plan_fft_forward(len)
    }

    /// Inverse (unnormalised) transform of length `len`, `x_j = Σ_k X_k e^{+2πi jk/N}`.
    #[inline(never)]
    pub fn plan_inverse(&mut self, len: usize) -> Arc<dyn Fft<f64>> {
        self.inner.plan_fft_inverse(len)
    }
}

impl Default for FftPlanner {
    fn default() -> Self {
        Self::new()
    }
}

impl std::fmt::Debug for FftPlanner {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FftPlanner").finish_non_exhaustive()
    }
}

/// Planner of real-to-complex and complex-to-real `f64` FFTs (realfft's `RealFftPlanner<f64>`,
/// with a complex planner of its own inside).
///
/// Plans are cached by the planner: planning the same length twice returns the same plan.
pub struct RealFftPlanner {
    inner: realfft::RealFftPlanner<f64>,
}

impl RealFftPlanner {
    /// A new planner with an empty cache.
    #[inline(never)]
    pub fn new() -> Self {
        Self {
            inner: realfft::RealFftPlanner::new(),
        }
    }

    /// Real-to-complex forward transform of length `len`: the bins `0..=len/2` of
    /// `X_k = Σ_j x_j e^{−2πi jk/N}` for real `x_j`, at about half the cost of a complex FFT.
    #[inline(never)]
    pub fn plan_forward(&mut self, len: usize) -> Arc<dyn RealToComplex<f64>> {
        self.inner.plan_fft_forward(len)
    }

    /// Complex-to-real inverse (unnormalised) transform of length `len`: the real
    /// `x_j = Σ_k X_k e^{+2πi jk/N}` from the bins `0..=len/2` of a Hermitian spectrum.
    #[inline(never)]
    pub fn plan_inverse(&mut self, len: usize) -> Arc<dyn ComplexToReal<f64>> {
        self.inner.plan_fft_inverse(len)
    }
}

impl Default for RealFftPlanner {
    fn default() -> Self {
        Self::new()
    }
}

impl std::fmt::Debug for RealFftPlanner {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RealFftPlanner").finish_non_exhaustive()
    }
}

/// The README's example, compiled and run as a doctest so that it cannot rot.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
