//! A spur pair that is not one of the papers, composed from the leaves: Yu Table 1 geometry, a
//! smoothed single/double tooth-pair stiffness (ε_α = 1.6, 2e8 N/m per pair), a constant 50 µm
//! half gap, 1-DOF and 6-DOF, solved by time stepping and by harmonic balance.
//!
//! ```text
//! cargo run -p geardyn-models --example generic_pair
//! ```

use geardyn_models::pair::{Dofs, GearPair, PairParams, TimeSettings};

fn main() -> Result<(), geardyn_models::Error> {
    let mut params = PairParams::example_spur();
    println!("# mesh frequency [rad/s], DOFs, dynamic factor (time stepping), mean DTE [µm]");
    for dofs in [Dofs::Torsional, Dofs::TransverseTorsional] {
        params.dofs = dofs;
        for omega in [1000.0, 4000.0, 8000.0, 16000.0] {
            params.mesh_frequency = omega;
            let pair = GearPair::from_params(&params)?;
            let r = pair.time_response(&TimeSettings::default(), None)?;
            let mean = r.delta.iter().sum::<f64>() / r.delta.len() as f64;
            println!(
                "{omega:8.0} {dofs:?} {:.4} {:.3}",
                r.dynamic_factor(params.static_force),
                mean * 1e6
            );
        }
    }
    // harmonic balance of the 1-DOF pair at 1000 rad/s, started from the static contact state
    params.dofs = Dofs::Torsional;
    params.mesh_frequency = 1000.0;
    let pair = GearPair::from_params(&params)?;
    let h = 16;
    let mut z0 = vec![0.0; 2 * h + 1];
    z0[0] = pair.static_state()[0];
    let mut problem = pair.hbm_problem(h, 256)?;
    let options = hbm::SolverOptions {
        tolerance: 1e-6, // N: 1e-9 of F_s
        ..Default::default()
    };
    let sol = problem.solve(&z0, &options)?;
    println!(
        "# HBM at 1000 rad/s: converged {} (residual {:.1e} N), mean u = {:.4} µm",
        sol.converged,
        sol.residual_norm,
        sol.coefficients[0] * 1e6
    );
    Ok(())
}
