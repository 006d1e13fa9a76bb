//! A deliberately different C math library, loaded with `LD_PRELOAD` by `.ci/libm-swap`.
//!
//! Each exported function (`sin`, `cos`, `sincos`, `tan`, `pow`, `exp`, `log`, …) returns the
//! `libm` crate's value with the last bit of the mantissa flipped, for finite non-zero results
//! (special values, zeros, infinities and NaN pass unchanged): every result differs from any
//! correctly working libm by one ulp. A program whose outputs do not change under it does not
//! use the process's C math library for them.
#![allow(unsafe_code)]

/// The value with its last mantissa bit flipped (finite, non-zero values only).
fn perturb(x: f64) -> f64 {
    if x.is_finite() && x != 0.0 {
        f64::from_bits(x.to_bits() ^ 1)
    } else {
        x
    }
}

/// The `f32` value with its last mantissa bit flipped (finite, non-zero values only).
fn perturb_f32(x: f32) -> f32 {
    if x.is_finite() && x != 0.0 {
        f32::from_bits(x.to_bits() ^ 1)
    } else {
        x
    }
}

macro_rules! unary {
    ($($name:ident),*) => {$(
        /// The C function of this name, perturbed.
        #[unsafe(no_mangle)]
        pub extern "C" fn $name(x: f64) -> f64 {
            perturb(libm::$name(x))
        }
    )*};
}

macro_rules! unary_f32 {
    ($($name:ident),*) => {$(
        /// The C function of this name, perturbed.
        #[unsafe(no_mangle)]
        pub extern "C" fn $name(x: f32) -> f32 {
            perturb_f32(libm::$name(x))
        }
    )*};
}

macro_rules! binary {
    ($($name:ident),*) => {$(
        /// The C function of this name, perturbed.
        #[unsafe(no_mangle)]
        pub extern "C" fn $name(x: f64, y: f64) -> f64 {
            perturb(libm::$name(x, y))
        }
    )*};
}

unary!(
    sin, cos, tan, asin, acos, atan, sinh, cosh, tanh, exp, exp2, expm1, log, log2, log10, log1p,
    cbrt
);
unary_f32!(sinf, cosf, tanf, expf, logf, exp2f, log2f, log10f);
binary!(pow, atan2, hypot);

/// `powf` (f32), perturbed.
#[unsafe(no_mangle)]
pub extern "C" fn powf(x: f32, y: f32) -> f32 {
    perturb_f32(libm::powf(x, y))
}

/// GNU `sincos`, perturbed.
///
/// # Safety
///
/// `s` and `c` must be valid for writing an `f64` (C's contract).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn sincos(x: f64, s: *mut f64, c: *mut f64) {
    let (sv, cv) = libm::sincos(x);
    // SAFETY: the caller passes writable pointers (C's contract)
    unsafe {
        s.write(perturb(sv));
        c.write(perturb(cv));
    }
}
