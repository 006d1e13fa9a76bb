//! Duffing oscillator `q'' + 2ζq' + q + γq³ = F cos ωt`: one-harmonic closed form, stability
//! and time stepping (its branches, folds and backbone are tested with the one continuation,
//! in `geardyn-orbit`'s `tests/it/hbm_branch.rs`).

use crate::common::{Duffing, rk4};
use geardyn_hbm::{Basis, HbmProblem, SecondOrderSystem, SolverOptions};
use math::DetMath;

/// The reference case (`system::problems::Duffing::hardening`) and its coefficients.
const REFERENCE: Duffing = Duffing::hardening(1.0);
const ZETA: f64 = REFERENCE.zeta;
const GAMMA: f64 = REFERENCE.gamma;
const FORCE: f64 = REFERENCE.force;

fn duffing(omega: f64) -> Duffing {
    Duffing::hardening(omega)
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
        let a = sol.coefficients[1].dhypot(sol.coefficients[2]);
        let lhs = ((1.0 - omega * omega + 0.75 * GAMMA * a * a).powi(2)
            + (2.0 * ZETA * omega).powi(2))
            * a
            * a;
        assert!((lhs - FORCE * FORCE).abs() < 1e-10, "ω = {omega}: {lhs}");
    }
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
