//! The worked example of the user guide (`docs/guide/rust.md`): solve a spur pair of your own —
//! not one of the papers — from the crates.
//!
//! A pair of 2 mm module, 30 / 45 teeth, 20° pressure angle, 80 N·m on the pinion, a smoothed
//! single/double tooth-pair stiffness (contact ratio 1.55, 3·10⁸ N/m per tooth pair), a
//! constant 30 µm half gap and a 5 µm static transmission error, 1-DOF torsional:
//!
//! 1. a sweep of the mesh frequency by time stepping (`GearPair::time_response`): dynamic
//!    factor `max F / F_s`, the smallest `δ − b` (negative: the teeth separated), the step
//!    and gap-event counts;
//! 2. harmonic balance (`GearPair::hbm_problem`) at one frequency, started from the static
//!    contact state, checked against the time response there.
//!
//! ```text
//! cargo run -p geardyn-models --example guide_gear_pair
//! ```
//!
//! In a project of your own the crates are `geardyn-models`, `geardyn-mesh-stiffness`,
//! `geardyn-backlash`, `geardyn-gear-geometry` and `geardyn-hbm`; renamed as in this workspace
//! (`mesh-stiffness = { package = "geardyn-mesh-stiffness", version = "0.1" }`), the code
//! below compiles unchanged.

use backlash::{Backlash, CentreDistanceForm, PressureAngleLaw};
use geardyn_models::pair::{Dofs, GearPair, PairParams, TimeSettings, equivalent_mass};
use mesh_stiffness::{MeshTimed, Stiffness, ToothPairStiffness};

/// The pair's data, SI units.
fn my_pair(mesh_frequency: f64) -> Result<PairParams, Box<dyn std::error::Error>> {
    let module = 2e-3;
    let (z_p, z_g) = (30.0, 45.0);
    let (r_p, r_g) = (module * z_p / 2.0, module * z_g / 2.0); // reference radii, m
    let (i_p, i_g) = (2.0e-4, 1.0e-3); // polar moments of inertia, kg m²
    let m_e = equivalent_mass(i_p, i_g, r_p, r_g); // kg
    // single/double tooth-pair stiffness: contact ratio 1.55, 3e8 N/m per tooth pair,
    // transitions smoothed over 0.1 of a mesh period
    let curve = ToothPairStiffness::from_pair_stiffness(1.55, 3e8, 0.1)?;
    let k_mean = curve.mean();
    Ok(PairParams {
        geometry: gear_geometry::SpurPairParams {
            rp: r_p,
            rg: r_g,
            pressure_angle: 20f64.to_radians(),
        },
        dofs: Dofs::Torsional,
        equivalent_mass: m_e,
        masses: [1.0, 2.0],          // used by the 6-DOF pair only
        bearing_stiffness: [1e8; 4], // (6-DOF only)
        bearing_damping: [1e3; 4],   // (6-DOF only)
        mesh_damping: 2.0 * 0.05 * (k_mean * m_e).sqrt(), // 5 % of critical
        static_force: 80.0 / r_p,    // T_p / R_p, N
        ste_amplitude: 5e-6,         // m
        ste_phase: 0.0,
        mesh_frequency,
        stiffness: Stiffness::ToothPair(MeshTimed {
            curve,
            omega_e: mesh_frequency,
        }),
        backlash: Backlash::Constant { b: 30e-6 }, // half gap, m
        pressure_angle: PressureAngleLaw::Involute,
        centre_distance: CentreDistanceForm::Consistent,
    })
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // 1. time stepping over the mesh frequency (rad/s); the natural frequency of the
    //    mean-stiffness mesh is sqrt(k_mean / m_e)
    let p0 = my_pair(1000.0)?;
    let k_mean = ToothPairStiffness::from_pair_stiffness(1.55, 3e8, 0.1)?.mean();
    println!(
        "natural frequency of the mesh: {:.0} rad/s",
        (k_mean / p0.equivalent_mass).sqrt()
    );
    let settings = TimeSettings {
        transient_periods: 100,
        record_periods: 10,
        ..TimeSettings::default()
    };
    println!("mesh frequency [rad/s] | dynamic factor | min δ − b [µm] | steps | gap events");
    for omega in [10000.0, 30000.0, 50000.0, 55000.0, 60000.0] {
        let pair = GearPair::from_params(&my_pair(omega)?)?;
        let r = pair.time_response(&settings, None)?;
        let df = r.dynamic_factor(p0.static_force);
        // δ < b (here 30 µm): the teeth have separated at least once in the recorded window
        let min_delta = r.delta.iter().copied().fold(f64::INFINITY, f64::min);
        println!(
            "{omega:>22.0} | {df:>14.3} | {:>14.2} | {:>6} | {:>10}",
            (min_delta - 30e-6) * 1e6,
            r.stats.n_accepted,
            r.stats.n_events
        );
        assert!(
            df.is_finite() && df >= 1.0,
            "a steady mesh force peaks above its mean"
        );
    }

    // 2. harmonic balance at 5000 rad/s (no separation there), 16 harmonics, 256 AFT samples
    let omega = 5000.0;
    let pair = GearPair::from_params(&my_pair(omega)?)?;
    let h = 16;
    let mut z0 = vec![0.0; 2 * h + 1];
    z0[0] = pair.static_state()[0];
    let ts = pair.time_response(&settings, None)?; // before: hbm_problem takes the pair
    let mut problem = pair.hbm_problem(h, 256)?;
    let options = hbm::SolverOptions {
        tolerance: 1e-6, // N: about 4e-10 of the static force
        ..Default::default()
    };
    let sol = problem.solve(&z0, &options)?;
    let mean_ts = ts.delta.iter().sum::<f64>() / ts.delta.len() as f64;
    println!(
        "HBM at {omega} rad/s: converged {}, residual {:.1e} N, mean u = {:.4} µm \
         (time stepping: mean δ = {:.4} µm)",
        sol.converged,
        sol.residual_norm,
        sol.coefficients[0] * 1e6,
        mean_ts * 1e6
    );
    assert!(sol.converged, "the contact-keeping orbit converges");
    Ok(())
}
