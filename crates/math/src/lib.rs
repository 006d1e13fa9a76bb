//! # geardyn-math
//!
//! Deterministic `f64` transcendental functions: the same bits on every platform.
//!
//! The standard library's `f64::sin`, `f64::exp`, `f64::powf`, … call the platform's C math
//! library (glibc, musl, Apple's libm, the Windows CRT). Those agree to within an ulp or so, but
//! not bit for bit, and geardyn's committed outputs (`validation/`) are compared byte for byte.
//! Every transcendental function that reaches an output therefore goes through this crate:
//! pure Rust with fixed algorithms (the [`libm`] crate, a port of musl's math library). With
//! IEEE-754 `f64` arithmetic and no fused multiply-add contraction (Rust never contracts
//! `a * b + c` on its own), the same source gives the same bits on every platform.
//!
//! The accuracy is musl's: within 1 ulp of the exact value for the functions used here (most are
//! correctly rounded on nearly all arguments), tested against the standard library in the unit
//! tests. `f64::sqrt`, `abs`, `mul_add`, `powi`, `floor`, … are IEEE-exact or deterministic and
//! stay as they are.
//!
//! ## Use
//!
//! Free functions with the C names' meaning and the standard library's Rust names
//! ([`sin`], [`cos`], [`sin_cos`], [`exp`], [`ln`], [`powf`], …), and the extension trait
//! [`DetMath`], whose methods carry the standard method's name with a `d` ("deterministic")
//! in front, so that a call site reads as before:
//!
//! ```
//! use geardyn_math::DetMath;
//!
//! let x = 0.5_f64;
//! let (s, c) = x.dsin_cos();
//! assert_eq!(s.to_bits(), geardyn_math::sin(x).to_bits());
//! assert!((s * s + c * c - 1.0).abs() < 1e-15);
//! assert!((2.0_f64.dpowf(0.5) - std::f64::consts::SQRT_2).abs() < 1e-15);
//! ```
//!
//! The workspace's `clippy.toml` lists the standard methods under `disallowed-methods`, so a
//! raw `x.sin()` fails `cargo clippy -D warnings`.
//!
//! ## Dependencies that call the C symbols
//!
//! rustfft computes its twiddle factors with `f64::sin`/`cos`, plotters and nalgebra call others;
//! in a binary those are calls to the C symbols `sin`, `cos`, `pow`, … With the cargo feature
//! `c-symbols` this crate defines those symbols (`#[no_mangle] extern "C"`) over its own
//! functions, so the linker binds them here and the binary imports none from the platform's
//! libm (checked by `.ci/no-libm-imports` with `nm -D`). Only the binaries that compute outputs
//! enable it (`xtask`, the `geardyn` CLI, the Python extension); a library never should. A
//! shared library must also bind its own definitions (`-Wl,-Bsymbolic` on Linux), or the
//! process's libm, loaded first, interposes them.
//!
//! ## Limitations
//!
//! Speed: musl's algorithms are about as fast as glibc's for `sin`, `cos`, `exp`, `ln`, and
//! slower for `powf` (see the README for the measured instruction counts). The inner loops take
//! the short [`short::sin_cos`] of this crate where it is faster (a Cody–Waite reduction and
//! Taylor polynomials, within a few `10⁻¹⁶` of [`sin_cos`], not the same bits), and
//! `geardyn-models` keeps its own `fastlog`; both are pure Rust as well and fall back to this
//! crate.

#![no_std]

#[cfg(feature = "c-symbols")]
pub mod c_symbols;

pub mod short;

/// `sin x` (musl's algorithm: Payne–Hanek/Cody–Waite reduction, polynomial on `[−π/4, π/4]`).
#[inline]
pub fn sin(x: f64) -> f64 {
    libm::sin(x)
}

/// `cos x`.
#[inline]
pub fn cos(x: f64) -> f64 {
    libm::cos(x)
}

/// `(sin x, cos x)`, one argument reduction for both.
#[inline]
pub fn sin_cos(x: f64) -> (f64, f64) {
    libm::sincos(x)
}

/// `tan x`.
#[inline]
pub fn tan(x: f64) -> f64 {
    libm::tan(x)
}

/// `eˣ`.
#[inline]
pub fn exp(x: f64) -> f64 {
    libm::exp(x)
}

/// `2ˣ`.
#[inline]
pub fn exp2(x: f64) -> f64 {
    libm::exp2(x)
}

/// `eˣ − 1`, accurate near `x = 0`.
#[inline]
pub fn exp_m1(x: f64) -> f64 {
    libm::expm1(x)
}

/// Natural logarithm `ln x`.
#[inline]
pub fn ln(x: f64) -> f64 {
    libm::log(x)
}

/// `ln(1 + x)`, accurate near `x = 0`.
#[inline]
pub fn ln_1p(x: f64) -> f64 {
    libm::log1p(x)
}

/// `log₂ x`.
#[inline]
pub fn log2(x: f64) -> f64 {
    libm::log2(x)
}

/// `log₁₀ x`.
#[inline]
pub fn log10(x: f64) -> f64 {
    libm::log10(x)
}

/// `xʸ` (C's `pow`, with its special cases: `pow(x, ±0) = 1` for any `x`, NaN included).
#[inline]
pub fn powf(x: f64, y: f64) -> f64 {
    libm::pow(x, y)
}

/// `atan x` in `[−π/2, π/2]`.
#[inline]
pub fn atan(x: f64) -> f64 {
    libm::atan(x)
}

/// The angle of the point `(x, y)`: `atan2(y, x)` in `[−π, π]` (argument order as
/// `f64::atan2`: `y.atan2(x)` is `atan2(y, x)`).
#[inline]
pub fn atan2(y: f64, x: f64) -> f64 {
    libm::atan2(y, x)
}

/// `asin x` in `[−π/2, π/2]` (NaN outside `[−1, 1]`).
#[inline]
pub fn asin(x: f64) -> f64 {
    libm::asin(x)
}

/// `acos x` in `[0, π]` (NaN outside `[−1, 1]`).
#[inline]
pub fn acos(x: f64) -> f64 {
    libm::acos(x)
}

/// `sinh x`.
#[inline]
pub fn sinh(x: f64) -> f64 {
    libm::sinh(x)
}

/// `cosh x`.
#[inline]
pub fn cosh(x: f64) -> f64 {
    libm::cosh(x)
}

/// `tanh x`.
#[inline]
pub fn tanh(x: f64) -> f64 {
    libm::tanh(x)
}

/// `√(x² + y²)` without undue overflow or underflow.
#[inline]
pub fn hypot(x: f64, y: f64) -> f64 {
    libm::hypot(x, y)
}

/// The real cube root `∛x` (negative for negative `x`).
#[inline]
pub fn cbrt(x: f64) -> f64 {
    libm::cbrt(x)
}

/// The deterministic functions as methods: `x.dsin()` is [`sin`]`(x)`, and so on; each method is
/// the standard library's method of the same name with a `d` in front, with the same arguments.
///
/// Implemented for `f64` (the functions of this crate) and `f32` (the `libm` crate's `f32`
/// functions, equally deterministic).
pub trait DetMath: Sized + Copy {
    /// `sin self`.
    fn dsin(self) -> Self;
    /// `cos self`.
    fn dcos(self) -> Self;
    /// `(sin self, cos self)`.
    fn dsin_cos(self) -> (Self, Self);
    /// `tan self`.
    fn dtan(self) -> Self;
    /// `e^self`.
    fn dexp(self) -> Self;
    /// `2^self`.
    fn dexp2(self) -> Self;
    /// `e^self − 1`.
    fn dexp_m1(self) -> Self;
    /// `ln self`.
    fn dln(self) -> Self;
    /// `ln(1 + self)`.
    fn dln_1p(self) -> Self;
    /// `log₂ self`.
    fn dlog2(self) -> Self;
    /// `log₁₀ self`.
    fn dlog10(self) -> Self;
    /// `self^y`.
    fn dpowf(self, y: Self) -> Self;
    /// `atan self`.
    fn datan(self) -> Self;
    /// `atan2(self, x)`: the angle of the point `(x, self)`.
    fn datan2(self, x: Self) -> Self;
    /// `asin self`.
    fn dasin(self) -> Self;
    /// `acos self`.
    fn dacos(self) -> Self;
    /// `sinh self`.
    fn dsinh(self) -> Self;
    /// `cosh self`.
    fn dcosh(self) -> Self;
    /// `tanh self`.
    fn dtanh(self) -> Self;
    /// `√(self² + y²)`.
    fn dhypot(self, y: Self) -> Self;
    /// `∛self`.
    fn dcbrt(self) -> Self;
}

impl DetMath for f64 {
    #[inline]
    fn dsin(self) -> f64 {
        sin(self)
    }
    #[inline]
    fn dcos(self) -> f64 {
        cos(self)
    }
    #[inline]
    fn dsin_cos(self) -> (f64, f64) {
        sin_cos(self)
    }
    #[inline]
    fn dtan(self) -> f64 {
        tan(self)
    }
    #[inline]
    fn dexp(self) -> f64 {
        exp(self)
    }
    #[inline]
    fn dexp2(self) -> f64 {
        exp2(self)
    }
    #[inline]
    fn dexp_m1(self) -> f64 {
        exp_m1(self)
    }
    #[inline]
    fn dln(self) -> f64 {
        ln(self)
    }
    #[inline]
    fn dln_1p(self) -> f64 {
        ln_1p(self)
    }
    #[inline]
    fn dlog2(self) -> f64 {
        log2(self)
    }
    #[inline]
    fn dlog10(self) -> f64 {
        log10(self)
    }
    #[inline]
    fn dpowf(self, y: f64) -> f64 {
        powf(self, y)
    }
    #[inline]
    fn datan(self) -> f64 {
        atan(self)
    }
    #[inline]
    fn datan2(self, x: f64) -> f64 {
        atan2(self, x)
    }
    #[inline]
    fn dasin(self) -> f64 {
        asin(self)
    }
    #[inline]
    fn dacos(self) -> f64 {
        acos(self)
    }
    #[inline]
    fn dsinh(self) -> f64 {
        sinh(self)
    }
    #[inline]
    fn dcosh(self) -> f64 {
        cosh(self)
    }
    #[inline]
    fn dtanh(self) -> f64 {
        tanh(self)
    }
    #[inline]
    fn dhypot(self, y: f64) -> f64 {
        hypot(self, y)
    }
    #[inline]
    fn dcbrt(self) -> f64 {
        cbrt(self)
    }
}

impl DetMath for f32 {
    #[inline]
    fn dsin(self) -> f32 {
        libm::sinf(self)
    }
    #[inline]
    fn dcos(self) -> f32 {
        libm::cosf(self)
    }
    #[inline]
    fn dsin_cos(self) -> (f32, f32) {
        libm::sincosf(self)
    }
    #[inline]
    fn dtan(self) -> f32 {
        libm::tanf(self)
    }
    #[inline]
    fn dexp(self) -> f32 {
        libm::expf(self)
    }
    #[inline]
    fn dexp2(self) -> f32 {
        libm::exp2f(self)
    }
    #[inline]
    fn dexp_m1(self) -> f32 {
        libm::expm1f(self)
    }
    #[inline]
    fn dln(self) -> f32 {
        libm::logf(self)
    }
    #[inline]
    fn dln_1p(self) -> f32 {
        libm::log1pf(self)
    }
    #[inline]
    fn dlog2(self) -> f32 {
        libm::log2f(self)
    }
    #[inline]
    fn dlog10(self) -> f32 {
        libm::log10f(self)
    }
    #[inline]
    fn dpowf(self, y: f32) -> f32 {
        libm::powf(self, y)
    }
    #[inline]
    fn datan(self) -> f32 {
        libm::atanf(self)
    }
    #[inline]
    fn datan2(self, x: f32) -> f32 {
        libm::atan2f(self, x)
    }
    #[inline]
    fn dasin(self) -> f32 {
        libm::asinf(self)
    }
    #[inline]
    fn dacos(self) -> f32 {
        libm::acosf(self)
    }
    #[inline]
    fn dsinh(self) -> f32 {
        libm::sinhf(self)
    }
    #[inline]
    fn dcosh(self) -> f32 {
        libm::coshf(self)
    }
    #[inline]
    fn dtanh(self) -> f32 {
        libm::tanhf(self)
    }
    #[inline]
    fn dhypot(self, y: f32) -> f32 {
        libm::hypotf(self, y)
    }
    #[inline]
    fn dcbrt(self) -> f32 {
        libm::cbrtf(self)
    }
}

/// The README's example, compiled and run as a doctest so that it cannot rot.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
