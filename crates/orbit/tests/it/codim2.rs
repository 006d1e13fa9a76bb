//! Codim-2 continuation: grazing curves against closed forms and time integration, fold
//! curves against harmonic balance, option checks and named stops.

use crate::common::Bilinear;
use math::DetMath;
use orbit::{
    Codim2ContinuationOptions, ContinuationOptions, EnvelopeEnd, Extremum, OrbitProblem, Parameter,
    ShootingCorrection, SpecialKind, StopReason,
};
use std::f64::consts::PI;

/// `q'' + 2ζq' + k(q) = f₀ + f cos ωt`, kink at `q = d` (`ζ = 0.05`, `κ = 4`, `d = 0.5`,
/// `f₀ = 0.1`).
fn bilinear(f: f64, omega: f64) -> Bilinear {
    Bilinear {
        zeta: 0.05,
        kappa: 4.0,
        d: 0.5,
        f0: 0.1,
        f,
        omega,
    }
}

/// Below the kink the orbit is linear, `q = f₀ + P cos(ωt − ψ)` with
/// `P = f/√((1−ω²)² + (2ζω)²)`, `ψ = atan2(2ζω, 1 − ω²)`: its maximum `f₀ + P` touches the
/// kink `q = d` (the maximum of the event function `q − d` grazes zero) at
/// `f_g(ω) = (d − f₀) √((1−ω²)² + (2ζω)²)`, at the time `t_g = ψ/ω (mod 2π/ω)`.
fn grazing_closed_form(s: &Bilinear, omega: f64) -> (f64, f64) {
    let w = omega;
    let f = (s.d - s.f0) * ((1.0 - w * w).powi(2) + (2.0 * s.zeta * w).powi(2)).sqrt();
    let psi = (2.0 * s.zeta * w).datan2(1.0 - w * w);
    (f, psi / w)
}

/// The grazing of the bilinear oscillator located on a branch in `f` at `ω = omega`.
fn grazing_start(
    omega: f64,
) -> (
    OrbitProblem<Bilinear>,
    orbit::SpecialPoint<orbit::ShootingPoint>,
) {
    let s = bilinear(0.2, omega);
    let mut p = OrbitProblem::new(s, 2.0 * PI / omega).unwrap();
    let opts = ContinuationOptions {
        initial_step: 0.05,
        max_step: 0.1,
        corrector: ShootingCorrection {
            parameter: Parameter::Named("f".into()),
            range: [0.0, 0.6],
            locate_tol: 1e-10,
            ..ShootingCorrection::default()
        },
        ..Default::default()
    };
    let br = p.continuation(&[0.1, 0.0], 0.2, &opts).unwrap();
    let g = br
        .special
        .iter()
        .find(|x| {
            x.kind
                == SpecialKind::Grazing {
                    event: 0,
                    extremum: Extremum::Max,
                }
        })
        .expect("grazing on the branch in f")
        .clone();
    assert!(g.located);
    (p, g)
}

/// The grazing curve of the bilinear oscillator in (f, ω) from a grazing located on a branch
/// in `f`: every point on the closed form `f_g(ω)` (source: the linear response, see
/// [`grazing_closed_form`]) to 1e-7 and at the closed-form grazing time, stable, and the curve
/// reaches the end of its `ω` range.
#[test]
fn bilinear_grazing_curve_matches_closed_form() {
    let (mut p, g) = grazing_start(1.5);
    let mut opts =
        Codim2ContinuationOptions::codim2(Parameter::Named("f".into()), Parameter::BaseFrequency);
    opts.initial_step = 0.05;
    opts.max_step = 0.2;
    opts.max_points = 12;
    opts.corrector.range = [1.2, 2.0];
    let curve = p.continue_codim2(&g, &opts).unwrap();
    assert_eq!(curve.stop, StopReason::ReachedEnd, "{:?}", curve.stop);
    assert!(curve.points.len() >= 4);
    let s = bilinear(0.2, 1.5);
    for pt in &curve.points {
        let w = pt.parameter;
        let (f, tg) = grazing_closed_form(&s, w);
        assert!(
            (pt.first_parameter - f).abs() < 1e-9 * (1.0 + f),
            "ω = {w}: f = {} vs {f}",
            pt.first_parameter
        );
        let t = 2.0 * PI / w;
        let dt = (pt.grazing_time.unwrap() - tg).rem_euclid(t);
        assert!(
            dt.min(t - dt) < 1e-5,
            "ω = {w}: t_g {:?} vs {tg}",
            pt.grazing_time
        );
        assert!(pt.stable().unwrap());
        assert!(pt.curvature.unwrap() < 0.0);
    }
}

/// The bilinear oscillator as a plain first-order system for `timestep`, with the event
/// `q' = 0` (falling: a maximum of `q`); records the largest `q` at the maxima after `after`.
struct BilinearOde {
    s: Bilinear,
    after: f64,
    max_q: std::cell::Cell<f64>,
}

impl timestep::OdeSystem for BilinearOde {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, t: f64, y: &[f64], dydt: &mut [f64]) {
        let s = &self.s;
        let k = if y[0] < s.d {
            y[0]
        } else {
            s.d + s.kappa * (y[0] - s.d)
        };
        dydt[0] = y[1];
        dydt[1] = s.f0 + s.f * (s.omega * t).dcos() - 2.0 * s.zeta * y[1] - k;
    }
    fn n_events(&self) -> usize {
        1
    }
    fn events(&self, _t: f64, y: &[f64], g: &mut [f64]) {
        g[0] = y[1];
    }
    fn event_direction(&self, _index: usize) -> system::Direction {
        system::Direction::Falling
    }
    fn on_event(&self, event: &timestep::Event, y: &mut [f64]) -> timestep::EventAction {
        if event.t >= self.after {
            self.max_q.set(self.max_q.get().max(y[0]));
        }
        timestep::EventAction::Continue
    }
}

/// `max q − d` of the steady state at `(f, ω)` by time integration: 200 forcing periods of
/// transient (decay `e^{−ζt}`, below `1e-13`), then the maxima of two periods, each located as
/// the event `q' = 0`. The start is the linear orbit's state at `t = 0` moved by
/// `(−0.02, 0.01)`: near the resonance the stiff side makes a large orbit coexist with the
/// linear one, and a start from rest may reach it instead.
fn steady_max_gap(f: f64, omega: f64) -> f64 {
    let s = bilinear(f, omega);
    let t = 2.0 * PI / omega;
    let dw = ((1.0 - omega * omega).powi(2) + (2.0 * s.zeta * omega).powi(2)).sqrt();
    let psi = (2.0 * s.zeta * omega).datan2(1.0 - omega * omega);
    let amp = f / dw;
    let x0 = [
        s.f0 + amp * psi.dcos() - 0.02,
        amp * omega * psi.dsin() + 0.01,
    ];
    let sys = BilinearOde {
        s,
        after: 200.0 * t,
        max_q: std::cell::Cell::new(f64::NEG_INFINITY),
    };
    let opts = timestep::Options::default()
        .with_tol(1e-11, 1e-13)
        .with_events(true)
        .with_output(timestep::Output::Final);
    let sol = timestep::integrate(&sys, 0.0, &x0, 202.0 * t, &opts).unwrap();
    assert!(sol.status.is_success(), "{:?}", sol.status);
    sys.max_q.get() - s.d
}

/// The grazing curve against bisection on time integration: at three frequencies along the
/// curve, the forcing amplitude where the steady orbit starts to reach the kink (bisection
/// on `max q − d` by `timestep`, to 1e-10 relative) equals the curve's `f` to 1e-7.
#[test]
#[ignore = "heavy: run optimised by `cargo xtask heavy-tests` (.ci/run)"]
fn bilinear_grazing_curve_matches_time_integration() {
    let (mut p, g) = grazing_start(1.5);
    let mut opts =
        Codim2ContinuationOptions::codim2(Parameter::Named("f".into()), Parameter::BaseFrequency);
    opts.initial_step = 0.05;
    opts.max_step = 0.2;
    opts.corrector.range = [0.6, 2.0];
    opts.corrector.direction = -1.0;
    let curve = p.continue_codim2(&g, &opts).unwrap();
    assert_eq!(curve.stop, StopReason::ReachedEnd);
    assert!(curve.points.len() >= 6);
    // away from ω ≈ 1…1.3, where the stiff side's large orbit coexists with the linear one
    // and the time integration may settle on it (seen at ω = 1.034 from a perturbed start)
    for target in [1.45, 0.9, 0.65] {
        let pt = curve
            .points
            .iter()
            .min_by(|a, b| {
                (a.parameter - target)
                    .abs()
                    .total_cmp(&(b.parameter - target).abs())
            })
            .unwrap();
        assert!((pt.parameter - target).abs() < 0.1, "{}", pt.parameter);
        let (w, fc) = (pt.parameter, pt.first_parameter);
        let (mut a, mut b) = (0.95 * fc, 1.05 * fc);
        assert!(steady_max_gap(a, w) < 0.0 && steady_max_gap(b, w) > 0.0);
        while b - a > 1e-10 * fc {
            let m = 0.5 * (a + b);
            if steady_max_gap(m, w) < 0.0 {
                a = m;
            } else {
                b = m;
            }
        }
        let f_ti = 0.5 * (a + b);
        // measured ≤ 1.4e-10 relative
        assert!(
            (f_ti - fc).abs() < 1e-7 * fc,
            "ω = {w}: time integration {f_ti} vs curve {fc}"
        );
    }
}

/// Duffing `q'' + 0.1q' + q + 0.3q³ = F cos ωt` (the case of the HBM-against-shooting test,
/// folds at ω ≈ 1.258 and 1.169 for F = 0.2).
fn duffing(force: f64, omega: f64) -> crate::common::Duffing {
    crate::common::Duffing {
        zeta: 0.05,
        gamma: 0.3,
        force,
        omega,
    }
}

/// The folds of the HBM branch (H = 15, `orbit::continue_hbm`, quadratic estimate at steps
/// ≤ 0.02; it agrees with located shooting folds to 1e-9 in `hbm_branch_matches_shooting_branch`)
/// at forcing `force`.
fn hbm_folds(force: f64) -> Vec<f64> {
    let mut hp =
        hbm::HbmProblem::new(duffing(force, 0.8), hbm::Basis::full(15).unwrap(), 0.8).unwrap();
    let z0 = hp.zero_guess();
    let hopts = orbit::HbmContinuationOptions {
        max_step: 0.02,
        max_points: 5000,
        corrector: orbit::HbmCorrection {
            stability: false,
            ..orbit::HbmCorrection::default()
        },
        ..orbit::HbmContinuationOptions::default()
    };
    let hb = orbit::continue_hbm(&mut hp, Parameter::BaseFrequency, &z0, 0.8, 2.0, &hopts).unwrap();
    assert_eq!(hb.stop, StopReason::ReachedEnd);
    hb.folds.iter().map(|f| f.parameter).collect()
}

/// The located folds (Illinois on `dω/ds` to 1e-10) of the shooting branch in `ω` at `force`.
fn shooting_folds(force: f64) -> Vec<f64> {
    let mut p = OrbitProblem::new(duffing(force, 0.8), 2.0 * PI / 0.8).unwrap();
    let sopts = ContinuationOptions {
        initial_step: 0.02,
        max_step: 0.05,
        corrector: ShootingCorrection {
            parameter: Parameter::BaseFrequency,
            range: [0.7, 2.0],
            locate_tol: 1e-10,
            ..ShootingCorrection::default()
        },
        ..Default::default()
    };
    let br = p.continuation(&[0.3, 0.0], 0.8, &sopts).unwrap();
    br.special
        .iter()
        .filter(|x| x.kind == SpecialKind::Fold && x.located)
        .map(|x| x.point.parameter)
        .collect()
}

/// The shooting branch of the Duffing oscillator at F = 0.2 in ω from 0.8 up to 2 (steps up to
/// 0.1), stopping at the special points of `stop_at`.
fn duffing_omega_branch(stop_at: Vec<SpecialKind>) -> orbit::ShootingBranch {
    duffing_omega_branch_with(stop_at, false)
}

/// [`duffing_omega_branch`], stopping at its first loss of stability when `unstable`.
fn duffing_omega_branch_with(stop_at: Vec<SpecialKind>, unstable: bool) -> orbit::ShootingBranch {
    let mut p = OrbitProblem::new(duffing(0.2, 0.8), 2.0 * PI / 0.8).unwrap();
    let sopts = ContinuationOptions {
        initial_step: 0.02,
        max_step: 0.1,
        corrector: ShootingCorrection {
            parameter: Parameter::BaseFrequency,
            range: [0.7, 2.0],
            stop_at,
            stop_at_instability: unstable,
            ..ShootingCorrection::default()
        },
        ..Default::default()
    };
    p.continuation(&[0.3, 0.0], 0.8, &sopts).unwrap()
}

/// `ShootingCorrection::stop_at`: asked to stop at its first fold, the Duffing branch in ω ends
/// with the point after that fold, and everything up to there (points, located special points)
/// is the same, bit for bit, as on the branch that goes on to the end of its range.
#[test]
fn a_branch_asked_to_stop_at_its_fold_ends_there_unchanged() {
    let run = duffing_omega_branch;
    let full = run(vec![]);
    let stopped = run(vec![SpecialKind::Fold]);
    let fold = full
        .special
        .iter()
        .find(|x| x.kind == SpecialKind::Fold)
        .unwrap();
    assert!(fold.located && (1.24..1.27).contains(&fold.point.parameter));
    assert_eq!(
        stopped.stop,
        StopReason::SpecialPoint {
            parameter: fold.point.parameter,
            kind: SpecialKind::Fold
        }
    );
    // it ends with the point after the fold; the full branch goes on past it
    assert_eq!(stopped.points.len(), fold.after + 2);
    assert!(full.points.len() > stopped.points.len());
    assert_eq!(stopped.points[..], full.points[..stopped.points.len()]);
    let n_special = full
        .special
        .iter()
        .take_while(|x| x.after <= fold.after)
        .count();
    assert_eq!(stopped.special[..], full.special[..n_special]);
    // a kind the branch never meets: the same branch as without the stop
    let pd = run(vec![SpecialKind::PeriodDoubling]);
    assert_eq!(pd.points, full.points);
    assert_eq!(pd.stop, full.stop);
}

/// `ShootingCorrection::stop_at_instability`: the Duffing branch in ω loses stability at its
/// upper fold (the middle branch is a saddle); asked to stop there, it ends with its first
/// unstable point, which follows a stable one, and everything up to there is the same, bit for
/// bit, as on the branch that goes on.
#[test]
fn a_branch_asked_to_stop_at_its_loss_of_stability_ends_at_its_first_unstable_point() {
    let full = duffing_omega_branch(vec![]);
    let stopped = duffing_omega_branch_with(vec![], true);
    let k = full
        .points
        .iter()
        .position(|p| !p.floquet.stable)
        .expect("an unstable point on the full branch");
    assert!(k > 0 && full.points[k - 1].floquet.stable);
    let fold = full
        .special
        .iter()
        .find(|x| x.kind == SpecialKind::Fold)
        .unwrap();
    // the loss of stability is the fold's (a multiplier through +1)
    assert_eq!(k, fold.after + 1);
    assert_eq!(
        stopped.stop,
        StopReason::LostStability {
            parameter: full.points[k].parameter
        }
    );
    assert_eq!(stopped.stop.parameter(), Some(full.points[k].parameter));
    assert_eq!(stopped.points[..], full.points[..=k]);
    let n_special = full.special.iter().take_while(|x| x.after < k).count();
    assert_eq!(stopped.special[..], full.special[..n_special]);
    assert!(full.points.len() > stopped.points.len());
}

/// The Duffing fold curve in (F, ω) from the upper fold of a shooting branch in ω: every
/// point has a multiplier `+1` and the other `e^{−2ζT}` (Liouville: `det Φ = e^{−2ζT}`);
/// towards smaller `F` the curve turns in `F` at the cusp (a fold of the curve, recorded in
/// `Branch::folds`) and comes back as the lower fold; at points on both sides of the cusp the
/// curve's `ω` is a fold of the HBM branch at that `F` (to 2e-6 relative) and a located fold of
/// the shooting branch in `ω` at that `F` (to 1e-8).
#[test]
#[ignore = "heavy: run optimised by `cargo xtask heavy-tests` (.ci/run)"]
fn duffing_fold_curve_matches_hbm_folds() {
    let br = duffing_omega_branch(vec![]);
    let fold = br
        .special
        .iter()
        .find(|x| x.kind == SpecialKind::Fold)
        .unwrap()
        .clone();
    assert!(fold.located && (1.24..1.27).contains(&fold.point.parameter));
    // the problem is at the end of the branch: back to the fold's ω and F = 0.2
    let mut p = OrbitProblem::new(duffing(0.2, 0.8), 2.0 * PI / 0.8).unwrap();
    let mut opts = Codim2ContinuationOptions::codim2(
        Parameter::BaseFrequency,
        Parameter::Named("force".into()),
    );
    opts.initial_step = 0.01;
    opts.max_step = 0.05;
    opts.max_points = 200;
    opts.corrector.range = [0.01, 0.2];
    opts.corrector.direction = -1.0;
    let curve = p.continue_codim2(&fold, &opts).unwrap();
    // down to the cusp, round it, back up past F = 0.2 on the lower fold
    assert!(
        matches!(curve.stop, StopReason::LeftRange { .. }),
        "{:?}",
        curve.stop
    );
    assert_eq!(curve.folds.len(), 1, "{:?}", curve.folds);
    let cusp = curve.folds[0].after_index;
    // the lower fold (ω = 1.169 at F = 0.2, `hbm_branch_matches_shooting_branch`), just past
    // F = 0.2 (the last step is at most 0.05)
    let last = curve.points.last().unwrap();
    assert!(
        last.parameter > 0.2 && last.parameter < 0.25,
        "{}",
        last.parameter
    );
    assert!(
        (1.16..1.2).contains(&last.first_parameter),
        "{}",
        last.first_parameter
    );
    for pt in &curve.points {
        let w = pt.first_parameter;
        let mu = &pt.floquet.multipliers;
        let (near, other) = if (mu[0][0] - 1.0).abs() < (mu[1][0] - 1.0).abs() {
            (mu[0], mu[1])
        } else {
            (mu[1], mu[0])
        };
        assert!(
            (near[0] - 1.0).abs() < 1e-6 && near[1] == 0.0,
            "F = {}: {mu:?}",
            pt.parameter
        );
        let liouville = (-2.0 * 0.05 * 2.0 * PI / w).dexp();
        assert!((other[0] - liouville).abs() < 1e-6, "{mu:?} vs {liouville}");
    }
    let n = curve.points.len();
    for i in [1, cusp / 2, cusp + (n - cusp) / 2, n - 2] {
        let pt = &curve.points[i];
        let folds = hbm_folds(pt.parameter);
        let w = pt.first_parameter;
        let d = folds
            .iter()
            .map(|f| (f - w).abs())
            .fold(f64::INFINITY, f64::min);
        let sf = shooting_folds(pt.parameter);
        let ds = sf
            .iter()
            .map(|f| (f - w).abs())
            .fold(f64::INFINITY, f64::min);
        // measured ≤ 8.1e-7 (the HBM branch's quadratic fold estimate at steps ≤ 0.02)
        assert!(
            d < 2e-6 * w,
            "F = {}: ω = {w} vs HBM folds {folds:?}",
            pt.parameter
        );
        // measured ≤ 2.9e-10
        assert!(
            ds < 1e-8 * w,
            "F = {}: ω = {w} vs shooting folds {sf:?}",
            pt.parameter
        );
    }
}

/// `q'' + 2ζq' + k(q) = f₀ + f cos ωt + a cos 2ωt` with the bilinear kink of [`Bilinear`] at
/// `q = d` (`κ = 4`) and two event functions: `q − d` (the kink) and `q + c` (a second
/// surface, no force change); named parameters `f`, `f0`, `a`.
#[derive(Debug, Clone, Copy)]
struct TwoSurfaces {
    zeta: f64,
    d: f64,
    c: f64,
    f0: f64,
    f: f64,
    a: f64,
    omega: f64,
    /// a broken model: setting `f0` resets `f` to 0.2
    reset_f: bool,
}

impl system::SecondOrderSystem for TwoSurfaces {
    fn n_dof(&self) -> usize {
        1
    }
    fn mass(&self) -> nalgebra::DMatrix<f64> {
        nalgebra::DMatrix::identity(1, 1)
    }
    fn damping(&self) -> nalgebra::DMatrix<f64> {
        nalgebra::DMatrix::from_element(1, 1, 2.0 * self.zeta)
    }
    fn nonlinear_force(&self, _t: f64, q: &[f64], _v: &[f64], g: &mut [f64]) {
        g[0] = if q[0] < self.d {
            q[0]
        } else {
            self.d + 4.0 * (q[0] - self.d)
        };
    }
    fn force_jacobian(&self, _t: f64, q: &[f64], _v: &[f64], dq: &mut [f64], dv: &mut [f64]) {
        dq[0] = if q[0] < self.d { 1.0 } else { 4.0 };
        dv[0] = 0.0;
    }
    fn forcing(&self, t: f64, f: &mut [f64]) {
        f[0] = self.f0 + self.f * (self.omega * t).dcos() + self.a * (2.0 * self.omega * t).dcos();
    }
    fn n_events(&self) -> usize {
        2
    }
    fn events(&self, _t: f64, q: &[f64], _v: &[f64], e: &mut [f64]) {
        e[0] = q[0] - self.d;
        e[1] = q[0] + self.c;
    }
    fn set_base_frequency(&mut self, omega: f64) -> Result<(), system::SystemError> {
        self.omega = omega;
        Ok(())
    }
    fn set_parameter(&mut self, name: &str, value: f64) -> Result<(), system::SystemError> {
        match name {
            "f" => self.f = value,
            "f0" => {
                self.f0 = value;
                if self.reset_f {
                    self.f = 0.2;
                }
            }
            "a" => self.a = value,
            _ => {
                return Err(system::SystemError::UnknownParameter {
                    name: name.to_string(),
                });
            }
        }
        Ok(())
    }
    fn parameter(&self, name: &str) -> Result<f64, system::SystemError> {
        match name {
            "f" => Ok(self.f),
            "f0" => Ok(self.f0),
            "a" => Ok(self.a),
            _ => Err(system::SystemError::UnknownParameter {
                name: name.to_string(),
            }),
        }
    }
}

/// The first grazing of the maximum of `q − d` on a branch in `f` from `f = 0.2`.
fn two_surfaces_start(
    s: TwoSurfaces,
) -> (
    OrbitProblem<TwoSurfaces>,
    orbit::SpecialPoint<orbit::ShootingPoint>,
) {
    two_surfaces_grazing_in(s, "f", s.f, [0.0, 0.6], (0.05, 0.1))
}

/// The grazing of the maximum of `q − d` on a branch in the named parameter `name` from
/// `from` (the other parameters as in `s`), within `range`, with `(initial, max)` steps.
fn two_surfaces_grazing_in(
    s: TwoSurfaces,
    name: &str,
    from: f64,
    range: [f64; 2],
    steps: (f64, f64),
) -> (
    OrbitProblem<TwoSurfaces>,
    orbit::SpecialPoint<orbit::ShootingPoint>,
) {
    let mut p = OrbitProblem::new(s, 2.0 * PI / s.omega).unwrap();
    let opts = ContinuationOptions {
        initial_step: steps.0,
        max_step: steps.1,
        corrector: ShootingCorrection {
            parameter: Parameter::Named(name.into()),
            range,
            locate_tol: 1e-10,
            ..ShootingCorrection::default()
        },
        ..Default::default()
    };
    let br = p.continuation(&[s.f0, 0.0], from, &opts).unwrap();
    let g = br
        .special
        .iter()
        .find(|x| {
            x.kind
                == SpecialKind::Grazing {
                    event: 0,
                    extremum: Extremum::Max,
                }
        })
        .expect("grazing of q - d on the branch")
        .clone();
    (p, g)
}

/// Undamped, below both resonances at `ω = 0.4`, far from the second surface: the orbit is
/// `q = f₀ + A cos ωt + B cos 2ωt` with `A = f/(1 − ω²)`, `B = a/(1 − 4ω²)` (`d = 0.5`,
/// `f₀ = 0.1`, `f = 0.2`, `a = 0`).
fn two_harmonics() -> TwoSurfaces {
    TwoSurfaces {
        zeta: 0.0,
        d: 0.5,
        c: 5.0,
        f0: 0.1,
        f: 0.2,
        a: 0.0,
        omega: 0.4,
        reset_f: false,
    }
}

/// Codim-2 options from `first` to `second` (named parameters), steps 0.01 … 0.02, over
/// `range` of the second.
fn named_codim2(first: &str, second: &str, range: [f64; 2]) -> Codim2ContinuationOptions {
    let mut opts = Codim2ContinuationOptions::codim2(
        Parameter::Named(first.into()),
        Parameter::Named(second.into()),
    );
    opts.initial_step = 0.01;
    opts.max_step = 0.02;
    opts.corrector.range = range;
    opts
}

/// A change of the grazing flank: on the grazing curve of `max q = d` in `(f, f₀)` the linear
/// orbit `q = f₀ + P cos(ωt − ψ)` has `P = d − f₀`, so its minimum `2f₀ − d` reaches the
/// second surface `q = −c` at `f₀ = (d − c)/2` exactly (closed form), where the curve records
/// a located [`SpecialKind::Grazing`] of event 1's minimum; every point on `f = (d − f₀) D(ω)`.
#[test]
fn grazing_curve_locates_the_change_of_flank() {
    let s = TwoSurfaces {
        zeta: 0.05,
        d: 0.5,
        c: 0.3,
        f0: 0.15,
        f: 0.2,
        a: 0.0,
        omega: 1.5,
        reset_f: false,
    };
    let (mut p, g) = two_surfaces_start(s);
    let mut opts = Codim2ContinuationOptions::codim2(
        Parameter::Named("f".into()),
        Parameter::Named("f0".into()),
    );
    opts.initial_step = 0.02;
    opts.max_step = 0.05;
    opts.corrector.range = [0.0, 0.2];
    opts.corrector.direction = -1.0;
    let curve = p.continue_codim2(&g, &opts).unwrap();
    assert_eq!(curve.stop, StopReason::ReachedEnd, "{:?}", curve.stop);
    let w = s.omega;
    let dw = ((1.0 - w * w).powi(2) + (2.0 * s.zeta * w).powi(2)).sqrt();
    for pt in &curve.points {
        let f = (s.d - pt.parameter) * dw;
        assert!(
            (pt.first_parameter - f).abs() < 1e-9,
            "{} vs {f}",
            pt.first_parameter
        );
    }
    assert_eq!(curve.special.len(), 1, "{:?}", curve.special);
    let sp = &curve.special[0];
    assert_eq!(
        sp.kind,
        SpecialKind::Grazing {
            event: 1,
            extremum: Extremum::Min
        }
    );
    assert!(sp.located);
    let f0 = 0.5 * (s.d - s.c);
    assert!(
        (sp.point.parameter - f0).abs() < 1e-8,
        "{} vs {f0}",
        sp.point.parameter
    );
    assert!(sp.point.extrema[1][0].abs() < 1e-8);
    assert!(sp.bracket[0] - 1e-8 <= f0 && f0 <= sp.bracket[1] + 1e-8);
    // a model whose setting of λ₂ = f₀ resets λ₁ = f is refused, not continued wrongly
    let (_, g) = two_surfaces_start(s);
    let mut broken = OrbitProblem::new(TwoSurfaces { reset_f: true, ..s }, 2.0 * PI / w).unwrap();
    assert!(matches!(
        broken.continue_codim2(&g, &opts),
        Err(orbit::OrbitError::InvalidInput {
            field: "Codim2Correction::parameter",
            ..
        })
    ));
}

/// A degenerate tangency stops the curve with a named reason: undamped and below both
/// resonances the orbit is `q = f₀ + A cos ωt + B cos 2ωt`, `A = f/(1 − ω²)`,
/// `B = a/(1 − 4ω²)` (in phase), grazing `q = d` at `t = 0` (the section: `θ` wraps) while
/// `f₀ + A + B = d`; its curvature `−(A + 4B)ω²` vanishes at `B = −(d − f₀)/3`. The curve in
/// `(f, a)` follows the closed form `f = (1 − ω²)(d − f₀ − B)` and stops with
/// `Degenerate { GrazingCurvature }` next to that point, never past it on a wrong curve.
#[test]
#[ignore = "heavy: run optimised by `cargo xtask heavy-tests` (.ci/run)"]
fn degenerate_grazing_stops_with_a_named_reason() {
    let s = two_harmonics();
    let w = s.omega;
    let (mut p, g) = two_surfaces_start(s);
    let mut opts = named_codim2("f", "a", [-0.5, 0.5]);
    opts.corrector.direction = -1.0;
    let curve = p.continue_codim2(&g, &opts).unwrap();
    let StopReason::Degenerate {
        parameter,
        condition,
    } = curve.stop
    else {
        panic!("{:?}", curve.stop);
    };
    assert_eq!(condition, orbit::Degeneracy::GrazingCurvature);
    let a_deg = -(s.d - s.f0) / 3.0 * (1.0 - 4.0 * w * w);
    let last = curve.points.last().unwrap();
    assert_eq!(parameter.to_bits(), last.parameter.to_bits());
    assert!(
        (parameter - a_deg).abs() < 0.03,
        "stopped at a = {parameter} vs {a_deg}"
    );
    for pt in &curve.points[..curve.points.len() - 1] {
        let b = pt.parameter / (1.0 - 4.0 * w * w);
        let f = (1.0 - w * w) * (s.d - s.f0 - b);
        assert!(
            (pt.first_parameter - f).abs() < 1e-8,
            "{} vs {f}",
            pt.first_parameter
        );
        assert!(pt.parameter > a_deg);
        let t = pt.grazing_time.unwrap().rem_euclid(2.0 * PI / w);
        assert!(t.min(2.0 * PI / w - t) < 1e-5, "t_g = {t}");
    }
}

/// The grazing envelope follows the global maximum across a double grazing, forward and
/// back. Undamped and below both resonances the orbit is `q = f₀ + A cos ωt + B cos 2ωt`,
/// `A = f/(1 − ω²)`, `B = a/(1 − 4ω²)`; for `B > 0` its maximum is `f₀ + |A| + B` (at `ωt = 0`
/// for `A > 0`, at `π` for `A < 0`), so contact is bounded by `|A| + B = d − f₀`: two local-
/// maximum grazing curves that cross at `A = 0`, with a corner of the envelope there.
/// * In `(f, a)`, traced in `a`: `f = (1 − ω²)(d − f₀ − B)` falls to 0 at `B = d − f₀`,
///   where the envelope turns back along `f = −(1 − ω²)(d − f₀ − B)` (the back restart).
/// * In `(a, f)`, traced in `f`: `B = d − f₀ − |A|` goes on through `f = 0` (the forward
///   restart).
///
/// Every envelope point lies on the closed form, on the side of its extremum; a plain
/// `continue_codim2` stops at the corner with `GrazingNotGlobal`.
#[test]
#[ignore = "heavy: run optimised by `cargo xtask heavy-tests` (.ci/run)"]
fn grazing_envelope_follows_the_global_maximum() {
    let s = two_harmonics();
    let w = s.omega;
    let (ka, kb) = (1.0 - w * w, 1.0 - 4.0 * w * w);
    let gap = s.d - s.f0;
    let residual = |f: f64, a: f64| f.abs() / ka + a / kb - gap;
    // back: traced in a from the grazing on the branch in f at a = 0 (f = ka·gap > 0)
    let (mut p, g) = two_surfaces_start(s);
    let opts = named_codim2("f", "a", [0.0, 0.3]);
    let plain = p.continue_codim2(&g, &opts).unwrap();
    assert!(
        matches!(
            plain.stop,
            StopReason::Degenerate {
                condition: orbit::Degeneracy::GrazingNotGlobal,
                ..
            }
        ),
        "{:?}",
        plain.stop
    );
    let (mut p, g) = two_surfaces_start(s);
    let env = p.continue_grazing_envelope(&g, &opts, 4).unwrap();
    assert_eq!(env.end, EnvelopeEnd::Stopped);
    assert_eq!(env.pieces.len(), 2);
    assert!(
        env.stop().is_some_and(StopReason::left_range),
        "{:?}",
        env.stop()
    );
    for (k, piece) in env.pieces.iter().enumerate() {
        let n = piece.points.len();
        // the first piece's stop point is past the corner (f < 0 on the old maximum)
        for pt in &piece.points[..if k == 0 { n - 1 } else { n }] {
            let (f, a) = (pt.first_parameter, pt.parameter);
            assert!(residual(f, a).abs() < 1e-8, "piece {k}: f = {f}, a = {a}");
            assert!(
                if k == 0 { f > -1e-9 } else { f < 1e-9 },
                "piece {k}: f = {f}"
            );
        }
    }
    let sw = env.switches();
    assert_eq!(sw.len(), 1);
    // the double grazing is bisected to 2⁻¹⁰ of a step (≤ 0.02) before the restart
    assert!(
        (sw[0].parameter - kb * gap).abs() < 1e-4,
        "back restart at a = {} vs the corner {}",
        sw[0].parameter,
        kb * gap
    );
    assert!(
        sw[0].parameter < kb * gap,
        "the back piece starts before the corner"
    );
    assert_eq!(
        env.points().len(),
        env.pieces[0].points.len() - 1 + env.pieces[1].points.len()
    );
    // forward: traced in f from the grazing of the maximum at ωt = π on a branch in a at f < 0
    let s2 = TwoSurfaces { f: -0.2, ..s };
    let steps = (0.02, 0.05);
    let (mut p, g) = two_surfaces_grazing_in(s2, "a", 0.0, [0.0, 0.3], steps);
    let opts = named_codim2("a", "f", [-0.3, 0.2]);
    let env = p.continue_grazing_envelope(&g, &opts, 4).unwrap();
    assert_eq!(env.end, EnvelopeEnd::Stopped);
    assert_eq!(env.pieces.len(), 2);
    assert_eq!(env.stop(), Some(&StopReason::ReachedEnd));
    let pts = env.points();
    for pt in &pts {
        let (a, f) = (pt.first_parameter, pt.parameter);
        assert!(residual(f, a).abs() < 1e-8, "f = {f}, a = {a}");
    }
    assert!(pts.windows(2).all(|w| w[1].parameter > w[0].parameter));
    let sw = env.switches();
    assert_eq!(sw.len(), 1);
    assert!(
        sw[0].parameter.abs() < 1e-4,
        "forward restart at f = {}",
        sw[0].parameter
    );
    assert!(pts.first().unwrap().parameter < 0.0 && pts.last().unwrap().parameter > 0.19);
    // the switch cap ends the envelope at the corner, with the first piece kept
    let (mut p, g) = two_surfaces_grazing_in(s2, "a", 0.0, [0.0, 0.3], steps);
    let capped = p.continue_grazing_envelope(&g, &opts, 0).unwrap();
    assert_eq!(
        (capped.end.clone(), capped.pieces.len()),
        (EnvelopeEnd::SwitchLimit, 1)
    );
    assert!(matches!(
        p.continue_grazing_envelope(&g, &opts, orbit::MAX_ENVELOPE_SWITCHES + 1),
        Err(orbit::OrbitError::InvalidInput {
            field: "max_switches",
            ..
        })
    ));
}

/// Options are checked (fields named), and a start of another kind is refused.
#[test]
fn codim2_options_and_start_are_checked() {
    let (mut p, g) = grazing_start(1.5);
    let ok =
        Codim2ContinuationOptions::codim2(Parameter::Named("f".into()), Parameter::BaseFrequency);
    assert!(ok.validate().is_ok());
    let mut same = ok.clone();
    same.corrector.parameter = Parameter::Named("f".into());
    let mut bad_tol = ok.clone();
    bad_tol.corrector.curvature_tol = 1.5;
    let mut bad_range = ok.clone();
    bad_range.corrector.first_range = [1.0, 0.0];
    let mut bad_step = ok.clone();
    bad_step.min_step = 0.0;
    for bad in [same, bad_tol, bad_range, bad_step] {
        assert!(matches!(
            p.continue_codim2(&g, &bad),
            Err(orbit::OrbitError::InvalidInput { .. })
        ));
    }
    let mut ns = g.clone();
    ns.kind = SpecialKind::NeimarkSacker;
    assert!(matches!(
        p.continue_codim2(&ns, &ok),
        Err(orbit::OrbitError::InvalidInput {
            field: "start.kind",
            ..
        })
    ));
    let mut wrong_event = g.clone();
    wrong_event.kind = SpecialKind::Grazing {
        event: 3,
        extremum: Extremum::Max,
    };
    assert!(p.continue_codim2(&wrong_event, &ok).is_err());
    // hostile starts: a NaN state, a fold start whose monodromy is not the state's size or
    // not finite, a λ₂ the model does not know
    let mut nan = g.clone();
    nan.point.orbit.x0[0] = f64::NAN;
    assert!(p.continue_codim2(&nan, &ok).is_err());
    let mut fold = g.clone();
    fold.kind = SpecialKind::Fold;
    fold.point.orbit.monodromy = nalgebra::DMatrix::zeros(3, 3);
    assert!(p.continue_codim2(&fold, &ok).is_err());
    fold.point.orbit.monodromy = nalgebra::DMatrix::from_element(2, 2, f64::NAN);
    assert!(p.continue_codim2(&fold, &ok).is_err());
    // the grazing envelope takes a grazing start and at most MAX_ENVELOPE_SWITCHES switches
    fold.point.orbit.monodromy = nalgebra::DMatrix::identity(2, 2);
    assert!(matches!(
        p.continue_grazing_envelope(&fold, &ok, 4),
        Err(orbit::OrbitError::InvalidInput {
            field: "start.kind",
            ..
        })
    ));
    assert!(matches!(
        p.continue_grazing_envelope(&g, &ok, orbit::MAX_ENVELOPE_SWITCHES + 1),
        Err(orbit::OrbitError::InvalidInput {
            field: "max_switches",
            ..
        })
    ));
    let unknown = Codim2ContinuationOptions::codim2(
        Parameter::Named("f".into()),
        Parameter::Named("x".into()),
    );
    assert!(p.continue_codim2(&g, &unknown).is_err());
    // λ₁ out of its range at the first point: a named stop, one point
    let mut narrow = ok.clone();
    narrow.corrector.first_range = [0.0, 0.1];
    let c = p.continue_codim2(&g, &narrow).unwrap();
    assert_eq!(c.points.len(), 1);
    assert!(
        matches!(c.stop, StopReason::FirstLeftRange { .. }),
        "{:?}",
        c.stop
    );
}

/// `ω` where the closed-form period-1 impacting orbit of `q'' + 2ζq' + q = cos ωt` with a
/// stop at `q = 0` (restitution `r`) has `det(Φ + I) = 0` in `[2.3, 3.0]` (bisection to 1e-13;
/// the closed form of `impact::closed_form`).
fn pd_closed_form(zeta: f64, r: f64) -> f64 {
    let f = |w: f64| {
        let s = crate::common::ImpactOscillator {
            zeta,
            sigma: 0.0,
            omega: w,
        };
        let c = crate::impact::closed_form(&s, r);
        (&c[0].monodromy + nalgebra::DMatrix::identity(2, 2)).determinant()
    };
    let (mut a, mut b) = (2.3, 3.0);
    assert!(f(a) * f(b) < 0.0, "ζ = {zeta}");
    while b - a > 1e-13 {
        let m = 0.5 * (a + b);
        if f(m) * f(a) > 0.0 {
            a = m;
        } else {
            b = m;
        }
    }
    0.5 * (a + b)
}

/// The period-doubling curve of the impact oscillator (`r = 0.8`, stop at `q = 0`) in
/// `(ω, ζ)`, from the flip located on a branch in `ω` at `ζ = 0.05`: at every point a
/// multiplier is `−1` (to 1e-6; measured ≤ 7e-12), and `ω` equals the closed-form flip at that
/// `ζ` (to 1e-9).
#[test]
#[ignore = "heavy: run optimised by `cargo xtask heavy-tests` (.ci/run)"]
fn impact_period_doubling_curve_matches_closed_form() {
    let r = 0.8;
    let w0 = 2.5;
    let mut p = crate::impact::problem(w0, r);
    let c = crate::impact::closed_form(p.system(), r);
    let opts = ContinuationOptions {
        initial_step: 0.02,
        max_step: 0.05,
        corrector: ShootingCorrection {
            parameter: Parameter::BaseFrequency,
            range: [2.0, 2.8],
            ..ShootingCorrection::default()
        },
        ..Default::default()
    };
    let br = p.continuation(&c[0].x_section, w0, &opts).unwrap();
    let pd = br
        .special
        .iter()
        .find(|s| s.kind == SpecialKind::PeriodDoubling && s.located)
        .unwrap()
        .clone();
    let mut p = crate::impact::problem(w0, r);
    let mut o = Codim2ContinuationOptions::codim2(
        Parameter::BaseFrequency,
        Parameter::Named("zeta".into()),
    );
    o.initial_step = 0.01;
    o.max_step = 0.02;
    o.corrector.range = [0.02, 0.1];
    let curve = p.continue_codim2(&pd, &o).unwrap();
    assert_eq!(curve.stop, StopReason::ReachedEnd, "{:?}", curve.stop);
    assert!(curve.points.len() >= 4);
    for pt in &curve.points {
        let flip = pt
            .floquet
            .multipliers
            .iter()
            .map(|m| (m[0] + 1.0).dhypot(m[1]))
            .fold(f64::INFINITY, f64::min);
        assert!(
            flip < 1e-6,
            "ζ = {}: {:?}",
            pt.parameter,
            pt.floquet.multipliers
        );
        let w = pd_closed_form(pt.parameter, r);
        // measured ≤ 2.5e-12
        assert!(
            (pt.first_parameter - w).abs() < 1e-9,
            "ζ = {}: ω = {} vs closed form {w}",
            pt.parameter,
            pt.first_parameter
        );
    }
}

/// The Duffing oscillator of [`duffing`] with a switching surface `q = d` that changes no
/// force (event `q − d` only).
#[derive(Debug, Clone, Copy)]
struct DuffingSurface {
    duffing: crate::common::Duffing,
    d: f64,
}

impl system::SecondOrderSystem for DuffingSurface {
    fn n_dof(&self) -> usize {
        1
    }
    fn mass(&self) -> nalgebra::DMatrix<f64> {
        self.duffing.mass()
    }
    fn damping(&self) -> nalgebra::DMatrix<f64> {
        self.duffing.damping()
    }
    fn stiffness(&self) -> nalgebra::DMatrix<f64> {
        self.duffing.stiffness()
    }
    fn nonlinear_force(&self, t: f64, q: &[f64], v: &[f64], g: &mut [f64]) {
        self.duffing.nonlinear_force(t, q, v, g);
    }
    fn force_jacobian(&self, t: f64, q: &[f64], v: &[f64], a: &mut [f64], b: &mut [f64]) {
        self.duffing.force_jacobian(t, q, v, a, b);
    }
    fn forcing(&self, t: f64, f: &mut [f64]) {
        self.duffing.forcing(t, f);
    }
    fn n_events(&self) -> usize {
        1
    }
    fn events(&self, _t: f64, q: &[f64], _v: &[f64], e: &mut [f64]) {
        e[0] = q[0] - self.d;
    }
    fn set_base_frequency(&mut self, omega: f64) -> Result<(), system::SystemError> {
        self.duffing.set_base_frequency(omega)
    }
    fn set_parameter(&mut self, name: &str, value: f64) -> Result<(), system::SystemError> {
        self.duffing.set_parameter(name, value)
    }
    fn parameter(&self, name: &str) -> Result<f64, system::SystemError> {
        self.duffing.parameter(name)
    }
}

/// A grazing that meets a fold: the orbits of the hardening Duffing oscillator whose maximum
/// touches `q = 1.3` form a curve in `(ω, F)` (about constant amplitude); followed from the
/// stable upper branch at `F = 0.2` to smaller `F`, it turns in `F` near the backbone and
/// crosses the fold curve, where `det(Φ − I)` changes sign: a located [`SpecialKind::Fold`]
/// on the grazing curve. There the shooting branch in `ω` at that `F` has its located fold at
/// the same `ω` (to 1e-8), with the orbit's maximum at `q = 1.3` (to 3e-7, the accuracy with
/// which the fold is placed in `F`).
#[test]
#[ignore = "heavy: run optimised by `cargo xtask heavy-tests` (.ci/run)"]
fn grazing_meets_fold_on_the_duffing_grazing_curve() {
    let d = 1.3;
    let sys = DuffingSurface {
        duffing: duffing(0.2, 0.8),
        d,
    };
    let mut p = OrbitProblem::new(sys, 2.0 * PI / 0.8).unwrap();
    let sopts = ContinuationOptions {
        initial_step: 0.02,
        max_step: 0.05,
        corrector: ShootingCorrection {
            parameter: Parameter::BaseFrequency,
            range: [0.7, 2.0],
            locate_tol: 1e-10,
            ..ShootingCorrection::default()
        },
        ..Default::default()
    };
    let br = p.continuation(&[0.3, 0.0], 0.8, &sopts).unwrap();
    let g = br
        .special
        .iter()
        .find(|x| {
            x.kind
                == SpecialKind::Grazing {
                    event: 0,
                    extremum: Extremum::Max,
                }
        })
        .unwrap()
        .clone();
    assert!(g.point.floquet.stable && g.located);
    let mut p = OrbitProblem::new(sys, 2.0 * PI / 0.8).unwrap();
    let mut o = Codim2ContinuationOptions::codim2(
        Parameter::BaseFrequency,
        Parameter::Named("force".into()),
    );
    o.initial_step = 0.01;
    o.max_step = 0.02;
    o.max_points = 200;
    o.corrector.range = [0.1, 0.2];
    o.corrector.direction = -1.0;
    let curve = p.continue_codim2(&g, &o).unwrap();
    let folds: Vec<_> = curve
        .special
        .iter()
        .filter(|s| s.kind == SpecialKind::Fold)
        .collect();
    assert!(!folds.is_empty(), "{:?} {:?}", curve.stop, curve.special);
    let sp = folds[0];
    assert!(sp.located);
    let (f_star, w_star) = (sp.point.parameter, sp.point.first_parameter);
    // det(Φ − I) ≈ −(μ₁ − 1) at the located fold: zero to the monodromy's own accuracy at the
    // flow's tolerance (measured 1.3e-6 since round 15's controller polynomials moved the step
    // sequence; below 1e-6 before); the location itself is checked against the shooting
    // branch's fold below, to 1e-8
    assert!(
        sp.point.floquet.test_fold.abs() < 1e-5,
        "test_fold {:e} at the located fold",
        sp.point.floquet.test_fold
    );
    // the shooting branch in ω at F*: its fold where the grazing curve met it
    let mut q = OrbitProblem::new(
        DuffingSurface {
            duffing: duffing(f_star, 0.8),
            d,
        },
        2.0 * PI / 0.8,
    )
    .unwrap();
    let b2 = q.continuation(&[0.3, 0.0], 0.8, &sopts).unwrap();
    let fw: Vec<_> = b2
        .special
        .iter()
        .filter(|x| x.kind == SpecialKind::Fold && x.located)
        .collect();
    let near = fw
        .iter()
        .min_by(|a, b| {
            (a.point.parameter - w_star)
                .abs()
                .total_cmp(&(b.point.parameter - w_star).abs())
        })
        .unwrap();
    // measured 3.8e-12 (F* = 0.15389, ω* = 1.18105)
    assert!(
        (near.point.parameter - w_star).abs() < 1e-8,
        "fold at ω = {} vs {w_star} (F = {f_star})",
        near.point.parameter
    );
    // the orbit's maximum at that fold on the surface, to the accuracy of F*: the fold is
    // located on the grazing curve where det(Φ − I) changes sign, known only to the
    // monodromy's own accuracy (|test_fold| up to ~1e-6 at the located point, above), and at
    // the fold the orbit's maximum changes by about 7 per unit of F. Measured: 5.3e-8 at the
    // flows' rtol 1e-10, 1.5e-7 at 1e-12 (round 15), 3.1e-7 at 1e-10 with round 21's
    // controller (whose `log₂` the flows' step control shares): F* scatters by 1e-8 … 4.4e-8
    // with the step sequence, with no trend in the tolerance. The bound, 1e-6, is that
    // scatter's largest value times 7 times 3; a maximum off the surface by more than that
    // would be a fold that is not on the grazing curve
    assert!(
        near.point.extrema[0][1].abs() < 1e-6,
        "{:?}",
        near.point.extrema
    );
}

/// A contact change continued in two parameters: undamped and below both resonances the
/// orbit is `q = f₀ + A cos ωt + B cos 2ωt` (`A = f/(1 − ω²)`, `B = a/(1 − 4ω²)`), whose
/// local maximum at `ωt = π` (one while `4B > A`) has the value `f₀ − A + B`. With the
/// second surface `q = −c` (an event without a force change) and the kink far away, the
/// branch in `f` first grazes `−c` with its two symmetric minima (a global grazing) and then,
/// at `A − B = f₀ + c`, with the local maximum at `π` while the global maximum lies far above:
/// the crossings of `q + c` go from four to two per period ([`SpecialKind::ContactChange`];
/// the branch starts at `f = 0.5`, between the two).
/// The curve from it is that local grazing, `f/(1 − ω²) − a/(1 − 4ω²) = f₀ + c` (closed form),
/// at `ωt_g = π`, where a global-extremum check would stop at once; traced down in `a` it
/// stops with [`orbit::Degeneracy::GrazingCurvature`] where the local maximum flattens out,
/// `4B = A`, i.e. `B = (f₀ + c)/3`. A contact change whose bracket holds no local grazing is
/// refused.
#[test]
fn contact_change_curve_matches_closed_form() {
    let w = 0.4;
    let (ka, kb) = (1.0 - w * w, 1.0 - 4.0 * w * w);
    let s = TwoSurfaces {
        zeta: 0.0,
        d: 10.0,
        c: 0.3,
        f0: 0.1,
        f: 0.5,
        a: 0.3 * kb,
        omega: w,
        reset_f: false,
    };
    let gap = s.f0 + s.c;
    let mut p = OrbitProblem::new(s, 2.0 * PI / w).unwrap();
    let opts = ContinuationOptions {
        initial_step: 0.05,
        max_step: 0.05,
        corrector: ShootingCorrection {
            parameter: Parameter::Named("f".into()),
            range: [0.0, 0.65],
            locate_tol: 1e-10,
            locate_contact_changes: true,
            ..ShootingCorrection::default()
        },
        ..Default::default()
    };
    let br = p.continuation(&[s.f0, 0.0], s.f, &opts).unwrap();
    let cc = br
        .special
        .iter()
        .find(|x| x.kind == SpecialKind::ContactChange { event: 1 })
        .expect("contact change of q + c on the branch")
        .clone();
    let f_cc = ka * (gap + 0.3);
    // located by bisection on the crossing count, which misses a pair of crossings closer
    // than the event detection resolves: past the tangency by δf the pair lies
    // ~√(δf/|ḧ|) apart, so the count changes a few 10⁻⁶ late
    assert!(
        cc.bracket[0] <= f_cc + 1e-5 && f_cc - 1e-5 <= cc.bracket[1],
        "bracket {:?} vs {f_cc}",
        cc.bracket
    );
    let residual = |f: f64, a: f64| f / ka - a / kb - gap;
    for (dir, range) in [(-1.0, [0.0, 0.15]), (1.0, [0.0, 0.15])] {
        let mut p = OrbitProblem::new(s, 2.0 * PI / w).unwrap();
        let mut o = named_codim2("f", "a", range);
        o.corrector.direction = dir;
        o.max_step = 0.02;
        let c = p.continue_codim2(&cc, &o).unwrap();
        assert!(c.points.len() > 3, "{} points", c.points.len());
        for pt in &c.points {
            let (f, a) = (pt.first_parameter, pt.parameter);
            assert!(residual(f, a).abs() < 1e-7, "f = {f}, a = {a}");
            // the local maximum at ωt = π, not the global one at 0
            let wt = (w * pt.grazing_time.unwrap()).rem_euclid(2.0 * PI);
            assert!((wt - PI).abs() < 1e-5, "ωt_g = {wt}");
            assert!(
                pt.extrema[1][1] > 1.0,
                "global max of q + c {}",
                pt.extrema[1][1]
            );
            assert_eq!(pt.curve, SpecialKind::ContactChange { event: 1 });
        }
        if dir < 0.0 {
            let StopReason::Degenerate {
                parameter,
                condition,
            } = c.stop
            else {
                panic!("{:?}", c.stop)
            };
            assert_eq!(condition, orbit::Degeneracy::GrazingCurvature);
            // ḧ ∝ A − 4B = f₀ + c − 3B at ωt = π: the stop point (the first degenerate one,
            // the curve's last) and the one before bracket B = (f₀ + c)/3, to the curvature
            // threshold
            let n = c.points.len();
            let (b_last, b_prev) = (parameter / kb, c.points[n - 2].parameter / kb);
            assert!(
                b_last < gap / 3.0 + 1e-3 && b_prev > gap / 3.0 - 1e-3,
                "stops between B = {b_prev} and {b_last}"
            );
            for pt in &c.points[..n - 1] {
                assert!(
                    pt.curvature.unwrap() < 0.0,
                    "a maximum at B = {}",
                    pt.parameter / kb
                );
            }
        } else {
            assert_eq!(c.stop, StopReason::ReachedEnd);
        }
    }
    // a contact change whose bracket holds no local grazing is refused, not continued
    let mut far = cc.clone();
    far.bracket = [0.1, 0.2];
    let mut p = OrbitProblem::new(s, 2.0 * PI / w).unwrap();
    assert!(matches!(
        p.continue_codim2(&far, &named_codim2("f", "a", [0.0, 0.2])),
        Err(orbit::OrbitError::NotConverged { .. })
    ));
}
