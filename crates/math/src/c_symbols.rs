//! The C math library's symbols, defined over this crate's functions (feature `c-symbols`).
//!
//! A dependency that calls `f64::sin` (rustfft's twiddle factors, plotters, nalgebra) compiles
//! to a call of the C symbol `sin`; with these definitions in the binary the linker binds it
//! here instead of to the platform's libm. Signatures are C's (`<math.h>`; `sincos` is the GNU
//! extension that LLVM emits for a `sin` and `cos` of the same argument).
#![allow(unsafe_code)]

macro_rules! unary {
    ($($name:ident => $f:path;)*) => {$(
        #[doc = concat!("C `", stringify!($name), "` over [`", stringify!($f), "`].")]
        #[unsafe(no_mangle)]
        pub extern "C" fn $name(x: f64) -> f64 {
            $f(x)
        }
    )*};
}

macro_rules! unary_f32 {
    ($($name:ident => $f:path;)*) => {$(
        #[doc = concat!("C `", stringify!($name), "` over `", stringify!($f), "`.")]
        #[unsafe(no_mangle)]
        pub extern "C" fn $name(x: f32) -> f32 {
            $f(x)
        }
    )*};
}

macro_rules! binary {
    ($($name:ident => $f:path : $t:ty;)*) => {$(
        #[doc = concat!("C `", stringify!($name), "` over `", stringify!($f), "`.")]
        #[unsafe(no_mangle)]
        pub extern "C" fn $name(x: $t, y: $t) -> $t {
            $f(x, y)
        }
    )*};
}

unary! {
    sin => crate::sin;
    cos => crate::cos;
    tan => crate::tan;
    exp => crate::exp;
    exp2 => crate::exp2;
    expm1 => crate::exp_m1;
    log => crate::ln;
    log1p => crate::ln_1p;
    log2 => crate::log2;
    log10 => crate::log10;
    atan => crate::atan;
    asin => crate::asin;
    acos => crate::acos;
    sinh => crate::sinh;
    cosh => crate::cosh;
    tanh => crate::tanh;
    cbrt => crate::cbrt;
    asinh => libm::asinh;
    acosh => libm::acosh;
    atanh => libm::atanh;
    erf => libm::erf;
    erfc => libm::erfc;
    tgamma => libm::tgamma;
    lgamma => libm::lgamma;
}

unary_f32! {
    sinf => libm::sinf;
    cosf => libm::cosf;
    tanf => libm::tanf;
    expf => libm::expf;
    exp2f => libm::exp2f;
    expm1f => libm::expm1f;
    logf => libm::logf;
    log1pf => libm::log1pf;
    log2f => libm::log2f;
    log10f => libm::log10f;
    atanf => libm::atanf;
    asinf => libm::asinf;
    acosf => libm::acosf;
    sinhf => libm::sinhf;
    coshf => libm::coshf;
    tanhf => libm::tanhf;
    cbrtf => libm::cbrtf;
}

binary! {
    pow => crate::powf: f64;
    atan2 => crate::atan2: f64;
    hypot => crate::hypot: f64;
    powf => libm::powf: f32;
    atan2f => libm::atan2f: f32;
    hypotf => libm::hypotf: f32;
}

/// C `sincos` (GNU): `*s = sin x`, `*c = cos x`.
///
/// # Safety
///
/// `s` and `c` must be valid for writing an `f64` (C's contract for `sincos`).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn sincos(x: f64, s: *mut f64, c: *mut f64) {
    let (sv, cv) = crate::sin_cos(x);
    // SAFETY: the caller passes writable pointers (C's contract)
    unsafe {
        s.write(sv);
        c.write(cv);
    }
}

/// C `sincosf` (GNU): `*s = sin x`, `*c = cos x` in `f32`.
///
/// # Safety
///
/// `s` and `c` must be valid for writing an `f32` (C's contract for `sincosf`).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn sincosf(x: f32, s: *mut f32, c: *mut f32) {
    let (sv, cv) = libm::sincosf(x);
    // SAFETY: the caller passes writable pointers (C's contract)
    unsafe {
        s.write(sv);
        c.write(cv);
    }
}

/// Makes the linker keep this module's symbols: a binary that enables `c-symbols` calls it once
/// (for example at the start of `main`), so that the object that defines `sin`, `pow`, … is
/// part of the link even where no other item of this crate is referenced.
#[inline(never)]
pub fn link() {}
