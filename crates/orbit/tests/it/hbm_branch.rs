//! Harmonic-balance branches through the one continuation (`orbit::continue_hbm`, moved here
//! with the continuation from `hbm`): the Duffing oscillator `q'' + 2ζq' + q + γq³ = F cos ωt`
//! against its one-harmonic closed form (folds), its exact backbone, named-parameter
//! continuation; natural against pseudo-arclength steps; HBM branch against shooting branch;
//! branch multipliers against the closed-form Floquet multipliers of the linear oscillator.

use math::DetMath;
use std::f64::consts::PI;

use crate::common::Duffing;
use hbm::{Basis, HbmProblem, PeriodicSolution};
use orbit::{
    Branch, ContinuationOptions, HbmContinuationOptions, HbmCorrection, OrbitProblem, Parameter,
    Predictor, ShootingContinuationOptions, ShootingCorrection, SpecialKind, StopReason,
    continue_hbm,
};

/// The reference case (`system::problems::Duffing::hardening`) and its coefficients.
const REFERENCE: Duffing = Duffing::hardening(1.0);
const ZETA: f64 = REFERENCE.zeta;
const GAMMA: f64 = REFERENCE.gamma;
const FORCE: f64 = REFERENCE.force;

fn duffing(omega: f64) -> Duffing {
    Duffing::hardening(omega)
}

/// Folds of the one-harmonic frequency response
/// `[(1 − ω² + ¾γA²)² + (2ζω)²] A² = F²` (extrema of `ω₊(A)`, fine scan).
fn one_harmonic_folds() -> Vec<f64> {
    let mut pts = Vec::new();
    let n = 200_000;
    for i in 1..n {
        let a = 5.0 * i as f64 / n as f64;
        let k = 0.75 * GAMMA * a * a;
        let d = (1.0 + k - 2.0 * ZETA * ZETA).powi(2) - (1.0 + k).powi(2) + (FORCE / a).powi(2);
        if d >= 0.0 {
            pts.push(((1.0 + k - 2.0 * ZETA * ZETA) + d.sqrt()).sqrt());
        }
    }
    let mut folds = Vec::new();
    for j in 1..pts.len() - 1 {
        if (pts[j] - pts[j - 1]) * (pts[j + 1] - pts[j]) < 0.0 {
            folds.push(pts[j]);
        }
    }
    folds
}

#[test]
fn continuation_goes_round_both_folds_and_flags_middle_branch() {
    // H = 1: folds against the closed form (reference: one-harmonic FRF above)
    let exact = one_harmonic_folds();
    assert_eq!(exact.len(), 2);
    let mut p = HbmProblem::new(duffing(0.5), Basis::full(1).unwrap(), 0.5).unwrap();
    let opts = HbmContinuationOptions {
        max_step: 0.1,
        ..HbmContinuationOptions::default()
    };
    let z0 = p.zero_guess();
    let br = continue_hbm(&mut p, Parameter::BaseFrequency, &z0, 0.5, 2.5, &opts).unwrap();
    assert_eq!(br.stop, StopReason::ReachedEnd);
    assert_eq!(br.folds.len(), 2, "{:?}", br.folds);
    let mut found: Vec<f64> = br.folds.iter().map(|f| f.parameter).collect();
    found.sort_by(f64::total_cmp);
    for (f, e) in found.iter().zip(&exact) {
        assert!((f - e).abs() < 2e-4 * e, "fold {f} vs closed form {e}");
    }
    // (no stability check at H = 1: Floquet analysis linearises the ODE about the HBM solution,
    // which only locates the folds correctly once H has converged)

    // H = 7: same folds within 2 %, middle branch unstable, outer branches stable
    let mut p = HbmProblem::new(duffing(0.5), Basis::full(7).unwrap(), 0.5).unwrap();
    let z0 = p.zero_guess();
    let br5 = continue_hbm(&mut p, Parameter::BaseFrequency, &z0, 0.5, 2.5, &opts).unwrap();
    assert_eq!(br5.folds.len(), 2, "{:?}", br5.folds);
    check_stability_pattern(&br5);
    for (f5, f1) in br5.folds.iter().zip(&br.folds) {
        assert!((f5.parameter - f1.parameter).abs() < 0.02 * f1.parameter);
    }
}

fn check_stability_pattern(br: &Branch<PeriodicSolution>) {
    let (a, b) = (br.folds[0].after_index, br.folds[1].after_index);
    for (i, pt) in br.points.iter().enumerate() {
        let st = pt.stability.as_ref().unwrap();
        // skip the points right at the folds, where a multiplier crosses 1
        if i + 2 < a || (i > a + 2 && i + 2 < b) || i > b + 2 {
            let middle = i > a && i <= b;
            assert_eq!(
                st.stable, !middle,
                "point {i} at ω = {}: max|μ| = {}",
                pt.parameter, st.max_modulus
            );
        }
    }
    // the middle branch exists
    assert!(b > a + 4);
}

/// Exact backbone of the undamped Duffing oscillator: ω = π √(1 + γA²) / (2 K(m)),
/// m = γA² / (2(1 + γA²)) (e.g. Kovacic & Brennan 2011, Ch. 2).
fn backbone(a: f64) -> f64 {
    let m = GAMMA * a * a / (2.0 * (1.0 + GAMMA * a * a));
    let (mut x, mut y) = (1.0_f64, (1.0 - m).sqrt());
    for _ in 0..30 {
        let (xn, yn) = (0.5 * (x + y), (x * y).sqrt());
        x = xn;
        y = yn;
    }
    let k = std::f64::consts::PI / (2.0 * x);
    std::f64::consts::PI * (1.0 + GAMMA * a * a).sqrt() / (2.0 * k)
}

#[test]
fn resonance_peak_lies_on_the_backbone() {
    // light damping: the peak of the forced response lies on the free backbone
    let sys = Duffing {
        zeta: 0.005,
        gamma: GAMMA,
        force: 0.01,
        omega: 1.0,
    };
    let mut p = HbmProblem::new(sys, Basis::full(7).unwrap(), 1.0).unwrap();
    let opts = HbmContinuationOptions {
        max_step: 0.05,
        max_points: 400,
        corrector: HbmCorrection {
            stability: false,
            ..HbmCorrection::default()
        },
        ..HbmContinuationOptions::default()
    };
    let z0 = p.zero_guess();
    let br = continue_hbm(&mut p, Parameter::BaseFrequency, &z0, 1.0, 1.5, &opts).unwrap();
    let peak = br
        .points
        .iter()
        .max_by(|a, b| {
            let pa = a.orbit.peak_to_peak(0).unwrap();
            let pb = b.orbit.peak_to_peak(0).unwrap();
            pa.total_cmp(&pb)
        })
        .unwrap();
    let amp = 0.5 * peak.orbit.peak_to_peak(0).unwrap();
    let wb = backbone(amp);
    assert!(amp > 0.5, "peak amplitude {amp}");
    assert!(
        (peak.parameter - wb).abs() < 5e-3 * wb,
        "peak at ω = {} (A = {amp}), backbone {wb}",
        peak.parameter
    );
}

#[test]
fn continuation_in_a_named_parameter() {
    let mut p = HbmProblem::new(duffing(1.5), Basis::full(3).unwrap(), 1.5).unwrap();
    let opts = HbmContinuationOptions {
        max_points: 20,
        corrector: HbmCorrection {
            stability: false,
            ..HbmCorrection::default()
        },
        ..HbmContinuationOptions::default()
    };
    let z0 = p.zero_guess();
    let br = continue_hbm(
        &mut p,
        Parameter::Named("force".into()),
        &z0,
        0.05,
        0.1,
        &opts,
    )
    .unwrap();
    assert!(br.points.len() > 2);
    let last = br.points.last().unwrap();
    assert!((p.system().force - last.parameter).abs() < 1e-12);
    let mut r = vec![0.0; p.n_unknowns()];
    p.residual(&last.orbit.coefficients, &mut r).unwrap();
    assert!(r.iter().map(|x| x * x).sum::<f64>().sqrt() < 1e-8);
    let bad = continue_hbm(
        &mut p,
        Parameter::Named("nope".into()),
        &z0,
        0.1,
        0.2,
        &opts,
    );
    assert!(bad.is_err());
}

/// Natural-parameter steps follow the same branch as pseudo-arclength up to the first fold
/// and stop there (the corrector cannot pass it); pseudo-arclength goes round it.
#[test]
fn natural_stops_at_the_fold_that_arclength_goes_round() {
    let exact = one_harmonic_folds();
    let upper = exact[1];
    let natural = HbmContinuationOptions {
        max_step: 0.1,
        predictor: Predictor::Natural,
        corrector: HbmCorrection {
            stability: false,
            ..HbmCorrection::default()
        },
        ..HbmContinuationOptions::default()
    };
    let mut p = HbmProblem::new(duffing(0.5), Basis::full(1).unwrap(), 0.5).unwrap();
    let z0 = p.zero_guess();
    let nat = continue_hbm(&mut p, Parameter::BaseFrequency, &z0, 0.5, 2.5, &natural).unwrap();
    let StopReason::StepTooSmall { parameter, .. } = nat.stop else {
        panic!("natural continuation passed the fold: {:?}", nat.stop);
    };
    assert!(nat.folds.is_empty());
    // monotone in ω, and it stops just below the (upper) fold of the resonance curve
    assert!(
        nat.points
            .windows(2)
            .all(|w| w[1].parameter > w[0].parameter)
    );
    assert!(
        parameter < upper && upper - parameter < 1e-5 * upper,
        "natural stop at {parameter}, fold {upper}"
    );
    // on the same branch as pseudo-arclength: the amplitude at the last natural point equals
    // the arclength branch's at that ω (linear interpolation between its bracketing points)
    let arc = HbmContinuationOptions {
        max_step: 0.02,
        corrector: HbmCorrection {
            stability: false,
            ..HbmCorrection::default()
        },
        ..HbmContinuationOptions::default()
    };
    let mut p = HbmProblem::new(duffing(0.5), Basis::full(1).unwrap(), 0.5).unwrap();
    let br = continue_hbm(&mut p, Parameter::BaseFrequency, &z0, 0.5, 2.5, &arc).unwrap();
    assert_eq!(br.stop, StopReason::ReachedEnd);
    assert_eq!(br.folds.len(), 2);
    let amp = |s: &PeriodicSolution| s.coefficients[1].dhypot(s.coefficients[2]);
    let w = nat.points[nat.points.len() / 2].parameter;
    let a_nat = amp(&nat.points[nat.points.len() / 2].orbit);
    let k = br
        .points
        .windows(2)
        .position(|x| x[0].parameter <= w && x[1].parameter >= w)
        .unwrap();
    let (l, r) = (&br.points[k], &br.points[k + 1]);
    let f = (w - l.parameter) / (r.parameter - l.parameter);
    let a_arc = amp(&l.orbit) + f * (amp(&r.orbit) - amp(&l.orbit));
    assert!(
        (a_nat - a_arc).abs() < 1e-5 * a_arc,
        "ω = {w}: natural {a_nat}, arclength {a_arc}"
    );
    // every natural point solves the harmonic balance at its ω
    for pt in &nat.points {
        let mut q =
            HbmProblem::new(duffing(pt.parameter), Basis::full(1).unwrap(), pt.parameter).unwrap();
        let mut r = vec![0.0; q.n_unknowns()];
        q.residual(&pt.orbit.coefficients, &mut r).unwrap();
        assert!(r.iter().map(|x| x * x).sum::<f64>().sqrt() < 1e-8);
    }
}

/// The same Duffing resonance curve by harmonic balance (H = 15) and by shooting: the HBM
/// branch's folds (quadratic estimate of `λ(s)`) agree with the shooting branch's located folds
/// (Illinois on `dλ/ds`), and the stability verdicts of the two branches agree away from the
/// folds.
#[test]
#[ignore = "heavy: run optimised by `cargo xtask heavy-tests` (.ci/run)"]
fn hbm_branch_matches_shooting_branch() {
    let s = Duffing {
        zeta: 0.05,
        gamma: 0.3,
        force: 0.2,
        omega: 0.8,
    };
    let mut hp = HbmProblem::new(s, Basis::full(15).unwrap(), 0.8).unwrap();
    let z0 = hp.zero_guess();
    let hopts = HbmContinuationOptions {
        max_step: 0.02,
        corrector: HbmCorrection {
            stability_steps: Some(2000),
            ..HbmCorrection::default()
        },
        ..HbmContinuationOptions::default()
    };
    let hb = continue_hbm(&mut hp, Parameter::BaseFrequency, &z0, 0.8, 2.0, &hopts).unwrap();
    assert_eq!(hb.stop, StopReason::ReachedEnd);
    let mut sp = OrbitProblem::new(s, 2.0 * PI / 0.8).unwrap();
    let sopts = ContinuationOptions {
        initial_step: 0.02,
        max_step: 0.1,
        corrector: ShootingCorrection {
            parameter: Parameter::BaseFrequency,
            range: [0.7, 2.0],
            ..ShootingCorrection::default()
        },
        ..Default::default()
    };
    let sb = sp.continuation(&[0.3, 0.0], 0.8, &sopts).unwrap();
    let located: Vec<f64> = sb
        .special
        .iter()
        .filter(|x| x.kind == SpecialKind::Fold)
        .map(|x| x.point.parameter)
        .collect();
    assert_eq!(hb.folds.len(), 2, "{:?}", hb.folds);
    assert_eq!(located.len(), 2, "{located:?}");
    // the shooting branch also records the quadratic estimates of the one loop
    assert_eq!(sb.folds.len(), 2);
    for ((h, s), e) in hb.folds.iter().zip(&located).zip(&sb.folds) {
        // measured 1e-9 (H = 15 truncation and the shooting tolerance)
        assert!(
            (h.parameter - s).abs() < 1e-6 * s,
            "HBM fold {} vs shooting {s}",
            h.parameter
        );
        // the quadratic estimate: measured 7e-5 at these steps
        assert!(
            (e.parameter - s).abs() < 1e-3 * s,
            "estimate {} vs located {s}",
            e.parameter
        );
    }
    // stability: below the lower fold (1.169) and above the upper one (1.258) one stable
    // orbit; between them (ω = 1.21) the middle, unstable orbit too, on both branches
    assert!((1.15..1.18).contains(&located[1]) && (1.24..1.27).contains(&located[0]));
    for w in [1.0, 1.21, 1.9] {
        let hv: Vec<bool> = stable_near(&hb, w);
        let sv: Vec<bool> = stable_near(&sb, w);
        assert!(!hv.is_empty() && !sv.is_empty(), "ω = {w}");
        let middle = (w - 1.21_f64).abs() < 1e-12;
        assert_eq!(hv.contains(&false), middle, "HBM ω = {w}: {hv:?}");
        assert_eq!(sv.contains(&false), middle, "shooting ω = {w}: {sv:?}");
        assert!(hv.contains(&true) && sv.contains(&true), "ω = {w}");
    }
}

/// The stability verdicts of the points of `b` within 0.05 of `w`.
fn stable_near<P>(b: &Branch<P>, w: f64) -> Vec<bool> {
    b.points
        .iter()
        .filter(|p| (p.parameter - w).abs() < 0.05)
        .filter_map(orbit::BranchPoint::stable)
        .collect()
}

/// Branch multipliers of the linear oscillator `q'' + 2ζq' + q = F cos ωt` (γ = 0) against
/// Floquet theory: the variational equation does not depend on the orbit, so the multipliers
/// are `exp((−ζ ± i√(1 − ζ²)) T)`, `T = 2π/ω`, at every point of both branches.
#[test]
fn branch_multipliers_match_closed_form_floquet_of_the_linear_oscillator() {
    let s = Duffing {
        zeta: ZETA,
        gamma: 0.0,
        force: FORCE,
        omega: 0.6,
    };
    let check = |w: f64, st: &system::Stability, tol: f64| {
        let t = 2.0 * PI / w;
        let wd = (1.0 - ZETA * ZETA).sqrt();
        let modulus = (-ZETA * t).dexp();
        let (re, im) = (modulus * (wd * t).dcos(), modulus * (wd * t).dsin().abs());
        assert_eq!(st.multipliers.len(), 2);
        for m in &st.multipliers {
            assert!(
                (m[0] - re).abs() < tol && (m[1].abs() - im).abs() < tol,
                "ω = {w}: {m:?} vs {re} ± {im}i"
            );
        }
        assert!((st.max_modulus - modulus).abs() < tol);
        assert!(st.stable);
    };
    let mut hp = HbmProblem::new(s, Basis::full(1).unwrap(), 0.6).unwrap();
    let z0 = hp.zero_guess();
    let hopts = HbmContinuationOptions {
        max_step: 0.1,
        max_points: 30,
        corrector: HbmCorrection {
            stability_steps: Some(4000),
            ..HbmCorrection::default()
        },
        ..HbmContinuationOptions::default()
    };
    let hb = continue_hbm(&mut hp, Parameter::BaseFrequency, &z0, 0.6, 1.6, &hopts).unwrap();
    assert!(hb.points.len() > 5);
    assert!(hb.folds.is_empty());
    for p in &hb.points {
        check(p.parameter, p.stability.as_ref().unwrap(), 1e-8);
    }
    let mut sp = OrbitProblem::new(s, 2.0 * PI / 0.6).unwrap();
    let sopts = ContinuationOptions {
        initial_step: 0.05,
        max_step: 0.2,
        max_points: 20,
        corrector: ShootingCorrection {
            parameter: Parameter::BaseFrequency,
            range: [0.5, 1.6],
            ..ShootingCorrection::default()
        },
        ..Default::default()
    };
    let sb = sp.continuation(&[0.0, 0.0], 0.6, &sopts).unwrap();
    assert!(sb.points.len() > 5);
    for p in &sb.points {
        check(p.parameter, p.stability.as_ref().unwrap(), 1e-8);
        assert_eq!(p.stability.as_ref(), Some(&p.floquet.stability()));
    }
}

/// The one options type: the shared fields are checked alike for both correctors (same field
/// names and bounds), each corrector's part by its own check.
#[test]
fn continuation_options_name_the_field_for_both_correctors() {
    let shoot = |o: &ContinuationOptions<ShootingCorrection>| match o.validate() {
        Err(orbit::OrbitError::InvalidInput { field, bound, .. }) => (field, bound),
        other => panic!("{other:?}"),
    };
    let mut p = HbmProblem::new(duffing(0.5), Basis::full(1).unwrap(), 0.5).unwrap();
    let z0 = p.zero_guess();
    let mut harmonic = |o: &HbmContinuationOptions| match continue_hbm(
        &mut p,
        Parameter::BaseFrequency,
        &z0,
        0.5,
        1.0,
        o,
    ) {
        Err(hbm::HbmError::InvalidParameter { name, bound, .. }) => (name, bound),
        other => panic!("{:?}", other.map(|b| b.points.len())),
    };
    let s = ShootingContinuationOptions::default();
    let h = HbmContinuationOptions::default();
    let shared = [
        ("ContinuationOptions::min_step", "> 0 and finite"),
        ("ContinuationOptions::max_step", ">= min_step and finite"),
        (
            "ContinuationOptions::initial_step",
            "in [min_step, max_step]",
        ),
        ("ContinuationOptions::max_points", ">= 1"),
    ];
    let bad_s = [
        ContinuationOptions {
            min_step: 0.0,
            ..s.clone()
        },
        ContinuationOptions {
            max_step: f64::NAN,
            ..s.clone()
        },
        ContinuationOptions {
            initial_step: 1.0,
            ..s.clone()
        },
        ContinuationOptions {
            max_points: 0,
            ..s.clone()
        },
    ];
    let bad_h = [
        ContinuationOptions {
            min_step: -1.0,
            ..h
        },
        ContinuationOptions {
            max_step: 1e-9,
            ..h
        },
        ContinuationOptions {
            initial_step: f64::NAN,
            ..h
        },
        ContinuationOptions { max_points: 0, ..h },
    ];
    for ((o_s, o_h), want) in bad_s.iter().zip(&bad_h).zip(shared) {
        assert_eq!(shoot(o_s), want);
        assert_eq!(harmonic(o_h), want);
    }
    let corrector = |c: HbmCorrection| ContinuationOptions { corrector: c, ..h };
    assert_eq!(
        harmonic(&corrector(HbmCorrection {
            tolerance: 0.0,
            ..HbmCorrection::default()
        })),
        ("HbmCorrection::tolerance", "> 0 and finite")
    );
    assert_eq!(
        harmonic(&corrector(HbmCorrection {
            max_iters: 0,
            ..HbmCorrection::default()
        })),
        ("HbmCorrection::max_iters", ">= 1")
    );
    assert_eq!(
        shoot(&ContinuationOptions {
            corrector: ShootingCorrection {
                state_scale: 0.0,
                ..ShootingCorrection::default()
            },
            ..s.clone()
        }),
        ("ShootingCorrection::state_scale", "> 0 and finite")
    );
    assert!(s.validate().is_ok() && h.validate().is_ok());
}
