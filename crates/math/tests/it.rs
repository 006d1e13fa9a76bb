//! geardyn-math against the standard library (agreement to a few ulp), on special values, and
//! against a table of exact bit patterns (which catches any change of algorithm).
#![allow(clippy::disallowed_methods)] // the standard library's functions are the reference here
#![allow(clippy::float_cmp)] // special values are exact

use geardyn_math as m;
use geardyn_math::DetMath;

/// Distance in units in the last place between two finite `f64` of the same sign (or both
/// tiny), through the ordered integer representation.
fn ulps(a: f64, b: f64) -> u64 {
    fn ord(x: f64) -> i64 {
        let i = x.to_bits() as i64;
        if i < 0 { i64::MIN - i } else { i }
    }
    ord(a).abs_diff(ord(b))
}

/// `n` points spread over `[lo, hi]` (deterministic, irrational step so that no two ranges
/// share points).
fn grid(lo: f64, hi: f64, n: u32) -> impl Iterator<Item = f64> {
    (0..n).map(move |i| lo + (hi - lo) * ((f64::from(i) * 0.618_033_988_749_895) % 1.0))
}

type Unary = (&'static str, fn(f64) -> f64, fn(f64) -> f64, f64, f64);

const UNARY: [Unary; 17] = [
    ("sin", m::sin, f64::sin, -1e4, 1e4),
    ("cos", m::cos, f64::cos, -1e4, 1e4),
    ("tan", m::tan, f64::tan, -1.5, 1.5),
    ("exp", m::exp, f64::exp, -700.0, 700.0),
    ("exp2", m::exp2, f64::exp2, -1000.0, 1000.0),
    ("exp_m1", m::exp_m1, f64::exp_m1, -40.0, 40.0),
    ("ln", m::ln, f64::ln, 1e-300, 1e300),
    ("ln_1p", m::ln_1p, f64::ln_1p, -0.999, 1e10),
    ("log2", m::log2, f64::log2, 1e-10, 1e10),
    ("log10", m::log10, f64::log10, 1e-10, 1e10),
    ("atan", m::atan, f64::atan, -1e3, 1e3),
    ("asin", m::asin, f64::asin, -1.0, 1.0),
    ("acos", m::acos, f64::acos, -1.0, 1.0),
    ("sinh", m::sinh, f64::sinh, -700.0, 700.0),
    ("cosh", m::cosh, f64::cosh, -700.0, 700.0),
    ("tanh", m::tanh, f64::tanh, -20.0, 20.0),
    ("cbrt", m::cbrt, f64::cbrt, -1e10, 1e10),
];

#[test]
fn unary_functions_agree_with_std_to_two_ulp() {
    for (name, f, reference, lo, hi) in UNARY {
        let mut worst = 0;
        for x in grid(lo, hi, 20_000).chain(grid(-1e-3, 1e-3, 2_000)) {
            let (a, b) = (f(x), reference(x));
            if b.is_nan() {
                assert!(a.is_nan(), "{name}({x:e}) = {a:e}, std NaN");
                continue;
            }
            worst = worst.max(ulps(a, b));
        }
        assert!(worst <= 2, "{name}: {worst} ulp from std");
    }
}

#[test]
fn binary_functions_agree_with_std_to_two_ulp() {
    let mut worst = [0u64; 3];
    for x in grid(1e-3, 1e3, 300) {
        for y in grid(-50.0, 50.0, 300) {
            worst[0] = worst[0].max(ulps(m::powf(x, y), x.powf(y)));
            worst[1] = worst[1].max(ulps(m::atan2(y, x - 500.0), y.atan2(x - 500.0)));
            worst[2] = worst[2].max(ulps(m::hypot(x, y), x.hypot(y)));
        }
    }
    assert!(
        worst.iter().all(|&w| w <= 2),
        "pow, atan2, hypot: {worst:?} ulp"
    );
    for x in grid(-1e4, 1e4, 20_000) {
        let (s, c) = m::sin_cos(x);
        assert_eq!(
            (s.to_bits(), c.to_bits()),
            (m::sin(x).to_bits(), m::cos(x).to_bits())
        );
    }
}

#[test]
fn special_values() {
    let (inf, nan) = (f64::INFINITY, f64::NAN);
    for f in [m::sin, m::cos, m::tan] {
        assert!(f(nan).is_nan() && f(inf).is_nan() && f(-inf).is_nan());
    }
    // signed zeros are kept by the odd functions
    for f in [
        m::sin,
        m::tan,
        m::atan,
        m::asin,
        m::sinh,
        m::tanh,
        m::cbrt,
        m::exp_m1,
        m::ln_1p,
    ] {
        assert_eq!(f(0.0).to_bits(), 0.0f64.to_bits());
        assert_eq!(f(-0.0).to_bits(), (-0.0f64).to_bits());
        assert!(f(nan).is_nan());
    }
    assert_eq!(m::cos(0.0), 1.0);
    assert_eq!(m::cosh(0.0), 1.0);
    assert_eq!(m::exp(0.0), 1.0);
    assert_eq!(m::exp(-inf), 0.0);
    assert_eq!(m::exp(inf), inf);
    assert_eq!(m::exp(710.0), inf);
    assert_eq!(m::exp2(10.0), 1024.0);
    assert_eq!(m::exp_m1(-inf), -1.0);
    assert_eq!(m::ln(0.0), -inf);
    assert_eq!(m::ln(-0.0), -inf);
    assert!(m::ln(-1.0).is_nan());
    assert_eq!(m::ln(inf), inf);
    assert_eq!(m::ln(1.0).to_bits(), 0.0f64.to_bits());
    assert_eq!(m::ln_1p(-1.0), -inf);
    assert_eq!(m::log2(1024.0), 10.0);
    assert_eq!(m::log10(1e10), 10.0);
    assert!(m::asin(1.5).is_nan() && m::acos(-1.5).is_nan());
    assert_eq!(m::atan(inf), std::f64::consts::FRAC_PI_2);
    assert_eq!(m::cbrt(-27.0), -3.0);
    // pow: C's special cases
    assert_eq!(m::powf(nan, 0.0), 1.0);
    assert_eq!(m::powf(1.0, nan), 1.0);
    assert!(m::powf(-2.0, 0.5).is_nan());
    assert_eq!(m::powf(0.0, -1.0), inf);
    assert_eq!(m::powf(-0.0, -1.0), -inf);
    assert_eq!(m::powf(2.0, 0.5), std::f64::consts::SQRT_2);
    assert_eq!(m::powf(-2.0, 3.0), -8.0);
    assert_eq!(m::powf(inf, -0.5), 0.0);
    // atan2: quadrants and signed zeros
    assert_eq!(m::atan2(0.0, -1.0), std::f64::consts::PI);
    assert_eq!(m::atan2(-0.0, -1.0), -std::f64::consts::PI);
    assert_eq!(m::atan2(-0.0, 1.0).to_bits(), (-0.0f64).to_bits());
    assert_eq!(m::atan2(1.0, 0.0), std::f64::consts::FRAC_PI_2);
    assert!(m::atan2(nan, 1.0).is_nan());
    // hypot: an infinity wins over NaN (C99 Annex F)
    assert_eq!(m::hypot(inf, nan), inf);
    assert_eq!(m::hypot(3.0, 4.0), 5.0);
    assert_eq!(m::hypot(3e300, 4e300), 5e300);
}

#[test]
fn trait_methods_are_the_free_functions() {
    for x in grid(-3.0, 3.0, 500) {
        let y = 0.3 + x.abs();
        let pairs = [
            (x.dsin(), m::sin(x)),
            (x.dcos(), m::cos(x)),
            (x.dtan(), m::tan(x)),
            (x.dexp(), m::exp(x)),
            (x.dexp2(), m::exp2(x)),
            (x.dexp_m1(), m::exp_m1(x)),
            (y.dln(), m::ln(y)),
            (y.dln_1p(), m::ln_1p(y)),
            (y.dlog2(), m::log2(y)),
            (y.dlog10(), m::log10(y)),
            (y.dpowf(x), m::powf(y, x)),
            (x.datan(), m::atan(x)),
            (x.datan2(y), m::atan2(x, y)),
            ((x / 3.0).dasin(), m::asin(x / 3.0)),
            ((x / 3.0).dacos(), m::acos(x / 3.0)),
            (x.dsinh(), m::sinh(x)),
            (x.dcosh(), m::cosh(x)),
            (x.dtanh(), m::tanh(x)),
            (x.dhypot(y), m::hypot(x, y)),
            (x.dcbrt(), m::cbrt(x)),
            (x.dsin_cos().0, m::sin(x)),
            (x.dsin_cos().1, m::cos(x)),
        ];
        for (i, (a, b)) in pairs.into_iter().enumerate() {
            assert_eq!(a.to_bits(), b.to_bits(), "method {i} at {x}");
        }
    }
    // f32: libm's f32 functions, within an ulp or two of std
    for x in grid(-3.0, 3.0, 500) {
        let x = x as f32;
        assert!((x.dsin() - x.sin()).abs() <= 2.0 * f32::EPSILON);
        assert!((x.dexp() - x.exp()).abs() <= 2.0 * f32::EPSILON * x.exp());
    }
}

/// The fixed arguments of [`exact_bit_patterns`].
fn bit_cases() -> Vec<(&'static str, f64)> {
    vec![
        ("sin(0.5)", m::sin(0.5)),
        ("sin(1e6)", m::sin(1e6)),
        ("cos(0.5)", m::cos(0.5)),
        ("cos(100.0)", m::cos(100.0)),
        ("tan(1.0)", m::tan(1.0)),
        ("exp(1.0)", m::exp(1.0)),
        ("exp(-3.7)", m::exp(-3.7)),
        ("exp2(0.3)", m::exp2(0.3)),
        ("exp_m1(1e-5)", m::exp_m1(1e-5)),
        ("ln(2.0)", m::ln(2.0)),
        ("ln(1e-7)", m::ln(1e-7)),
        ("ln_1p(1e-5)", m::ln_1p(1e-5)),
        ("log2(3.0)", m::log2(3.0)),
        ("log10(7.0)", m::log10(7.0)),
        ("powf(0.9, -0.2)", m::powf(0.9, -0.2)),
        ("powf(1e-7, -0.2)", m::powf(1e-7, -0.2)),
        ("powf(2.5, 1.5)", m::powf(2.5, 1.5)),
        ("atan(0.7)", m::atan(0.7)),
        ("atan2(1.0, -2.0)", m::atan2(1.0, -2.0)),
        ("asin(0.3)", m::asin(0.3)),
        ("acos(0.3)", m::acos(0.3)),
        ("sinh(0.7)", m::sinh(0.7)),
        ("cosh(0.7)", m::cosh(0.7)),
        ("tanh(0.7)", m::tanh(0.7)),
        ("hypot(1.0, 1e-3)", m::hypot(1.0, 1e-3)),
        ("cbrt(10.0)", m::cbrt(10.0)),
    ]
}

/// Exact results for fixed arguments: any change of algorithm (a `libm` update that changes a
/// kernel, a switch to another implementation) changes some of these bits, and with them the
/// committed outputs, so it has to be a deliberate edit of this table. Values from the `libm`
/// crate 0.2.16 (musl's algorithms), cross-checked above against the standard library to 2 ulp.
#[test]
fn exact_bit_patterns() {
    let want: &[u64] = &[
        0x3fdeaee8744b05f0, // sin(0.5) = 4.79425538604203e-1
        0xbfd6664b2568d867, // sin(1e6) = -3.4999350217129294e-1
        0x3fec1528065b7d50, // cos(0.5) = 8.775825618903728e-1
        0x3feb981dbf665fdf, // cos(100.0) = 8.623188722876839e-1
        0x3ff8eb245cbee3a6, // tan(1.0) = 1.5574077246549023e0
        0x4005bf0a8b14576a, // exp(1.0) = 2.7182818284590455e0
        0x3f99511fc6871044, // exp(-3.7) = 2.4723526470339388e-2
        0x3ff3b2c47bff8329, // exp2(0.3) = 1.2311444133449163e0
        0x3ee4f8bc681cdfb6, // exp_m1(1e-5) = 1.0000050000166668e-5
        0x3fe62e42fefa39ef, // ln(2.0) = 6.931471805599453e-1
        0xc0301e3b843eaa73, // ln(1e-7) = -1.611809565095832e1
        0x3ee4f8aea9ae7317, // ln_1p(1e-5) = 9.999950000333332e-6
        0x3ff95c01a39fbd68, // log2(3.0) = 1.584962500721156e0
        0x3feb0b0b0b78cc3f, // log10(7.0) = 8.450980400142568e-1
        0x3ff0573a259c9d57, // powf(0.9, -0.2) = 1.0212956876001351e0
        0x40391e6de449ff78, // powf(1e-7, -0.2) = 2.5118864315095806e1
        0x400f9f6e4990f227, // powf(2.5, 1.5) = 3.952847075210474e0
        0x3fe38b112d7bd4ad, // atan(0.7) = 6.107259643892086e-1
        0x40056c6e7397f5ae, // atan2(1.0, -2.0) = 2.677945044588987e0
        0x3fd380159e14f6ff, // asin(0.3) = 3.046926540153975e-1
        0x3ff441f5ecbeef59, // acos(0.3) = 1.2661036727794992e0
        0x3fe8465153d5bdbc, // sinh(0.7) = 7.585837018395334e-1
        0x3ff4152c1862342f, // cosh(0.7) = 1.255169005630943e0
        0x3fe356fb17af2e90, // tanh(0.7) = 6.043677771171634e-1
        0x3ff000008637bad3, // hypot(1.0, 1e-3) = 1.000000499999875e0
        0x40013c484138704f, // cbrt(10.0) = 2.154434690031884e0
    ];
    let cases = bit_cases();
    assert_eq!(cases.len(), want.len());
    for ((name, got), want) in cases.into_iter().zip(want) {
        assert_eq!(
            got.to_bits(),
            *want,
            "{name} = {got:e}: bits {:#018x}",
            got.to_bits()
        );
    }
}

#[test]
#[ignore = "prints the table of exact_bit_patterns"]
fn print_bit_patterns() {
    for (name, v) in bit_cases() {
        println!("        {:#018x}, // {name} = {v:e}", v.to_bits());
    }
}
