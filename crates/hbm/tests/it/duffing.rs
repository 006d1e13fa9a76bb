//! Duffing oscillator `q'' + 2ζq' + q + γq³ = F cos ωt`: one-harmonic closed form, backbone,
//! folds, stability and time stepping.

use crate::common::{Duffing, rk4};
use geardyn_hbm::{
    Basis, ContinuationOptions, ContinuationParameter, HbmProblem, SecondOrderSystem, SolverOptions,
};

const ZETA: f64 = 0.05;
const GAMMA: f64 = 1.0;
const FORCE: f64 = 0.3;

fn duffing(omega: f64) -> Duffing {
    Duffing {
        zeta: ZETA,
        gamma: GAMMA,
        force: FORCE,
        omega,
    }
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
fn one_harmonic_matches_closed_form() {
    // (ω, initial cos amplitude); at ω = 1.2 the zero guess stalls in a local minimum of ‖r‖
    for (omega, guess) in [(0.5, 0.0), (1.2, 0.8), (2.5, 0.0)] {
        let mut p = HbmProblem::new(duffing(omega), Basis::full(1).unwrap(), omega).unwrap();
        let mut z0 = p.zero_guess();
        z0[1] = guess;
        let sol = p.solve(&z0, &SolverOptions::default()).unwrap();
        assert!(sol.converged);
        let a = sol.coefficients[1].hypot(sol.coefficients[2]);
        let lhs = ((1.0 - omega * omega + 0.75 * GAMMA * a * a).powi(2)
            + (2.0 * ZETA * omega).powi(2))
            * a
            * a;
        assert!((lhs - FORCE * FORCE).abs() < 1e-10, "ω = {omega}: {lhs}");
    }
}

#[test]
fn continuation_goes_round_both_folds_and_flags_middle_branch() {
    // H = 1: folds against the closed form (reference: one-harmonic FRF above)
    let exact = one_harmonic_folds();
    assert_eq!(exact.len(), 2);
    let mut p = HbmProblem::new(duffing(0.5), Basis::full(1).unwrap(), 0.5).unwrap();
    let opts = ContinuationOptions {
        max_step: 0.1,
        ..ContinuationOptions::default()
    };
    let z0 = p.zero_guess();
    let br = p
        .continuation(ContinuationParameter::Frequency, &z0, 0.5, 2.5, &opts)
        .unwrap();
    assert_eq!(br.end, geardyn_hbm::ContinuationEnd::ReachedEnd);
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
    let br5 = p
        .continuation(ContinuationParameter::Frequency, &z0, 0.5, 2.5, &opts)
        .unwrap();
    assert_eq!(br5.folds.len(), 2, "{:?}", br5.folds);
    check_stability_pattern(&br5);
    for (f5, f1) in br5.folds.iter().zip(&br.folds) {
        assert!((f5.parameter - f1.parameter).abs() < 0.02 * f1.parameter);
    }
}

fn check_stability_pattern(br: &geardyn_hbm::Branch) {
    let (a, b) = (br.folds[0].after_index, br.folds[1].after_index);
    for (i, pt) in br.points.iter().enumerate() {
        let st = pt.solution.stability.as_ref().unwrap();
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
    let opts = ContinuationOptions {
        max_step: 0.05,
        stability: false,
        max_points: 400,
        ..ContinuationOptions::default()
    };
    let z0 = p.zero_guess();
    let br = p
        .continuation(ContinuationParameter::Frequency, &z0, 1.0, 1.5, &opts)
        .unwrap();
    let peak = br
        .points
        .iter()
        .max_by(|a, b| {
            let pa = a.solution.peak_to_peak(0).unwrap();
            let pb = b.solution.peak_to_peak(0).unwrap();
            pa.total_cmp(&pb)
        })
        .unwrap();
    let amp = 0.5 * peak.solution.peak_to_peak(0).unwrap();
    let wb = backbone(amp);
    assert!(amp > 0.5, "peak amplitude {amp}");
    assert!(
        (peak.parameter - wb).abs() < 5e-3 * wb,
        "peak at ω = {} (A = {amp}), backbone {wb}",
        peak.parameter
    );
}

#[test]
fn multi_harmonic_solution_is_a_periodic_orbit_of_the_ode() {
    // ω inside the multivalued range: both the low and the high stable branches
    for (omega, guess_amp) in [(0.6, 0.3), (1.5, 0.3), (1.5, 1.5), (2.2, 0.1)] {
        let mut p = HbmProblem::new(duffing(omega), Basis::full(9).unwrap(), omega).unwrap();
        let mut z0 = p.zero_guess();
        z0[1] = guess_amp;
        let sol = p.solve(&z0, &SolverOptions::default()).unwrap();
        assert!(sol.converged);
        let st = p.stability(&sol, None).unwrap();
        assert!(st.stable, "ω = {omega}: {st:?}");
        let (q0, v0) = sol.state_at(0.0);
        let periods = 40.0;
        let steps = 40 * 400;
        let (q, v) = rk4(
            p.system(),
            &q0,
            &v0,
            periods * sol.period(),
            periods * sol.period() / steps as f64,
            |_, _, _| {},
        );
        let err = (q[0] - q0[0]).abs() + (v[0] - v0[0]).abs();
        assert!(err < 1e-5, "ω = {omega}: drift {err}");
        assert!(p.system().n_dof() == 1);
    }
}

#[test]
fn continuation_in_a_named_parameter() {
    let mut p = HbmProblem::new(duffing(1.5), Basis::full(3).unwrap(), 1.5).unwrap();
    let opts = ContinuationOptions {
        stability: false,
        max_points: 20,
        ..ContinuationOptions::default()
    };
    let z0 = p.zero_guess();
    let br = p
        .continuation(
            ContinuationParameter::Named("force".into()),
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
    p.residual(&last.solution.coefficients, &mut r).unwrap();
    assert!(r.iter().map(|x| x * x).sum::<f64>().sqrt() < 1e-8);
    let bad = p.continuation(
        ContinuationParameter::Named("nope".into()),
        &z0,
        0.1,
        0.2,
        &opts,
    );
    assert!(bad.is_err());
}
