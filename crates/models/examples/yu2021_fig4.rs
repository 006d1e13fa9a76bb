//! Prints Yu Fig. 4 as data (b_s over D and G) with the documented parameters, the text's
//! claims, and the convergence numbers quoted in the docs (reading R-YU-FIG4). Run in release:
//! `cargo run -p geardyn-models --release --example yu2021_fig4`.

use backlash::{ConstantPartForm, Quadrature, SurfaceFractal, WmProfile, mean_asperity_height};
use geardyn_models::yu2021;

fn main() -> Result<(), backlash::Error> {
    let data = yu2021::fig4()?;
    println!(
        "# Yu Fig. 4 data: b_s in µm (b0 = {} µm)",
        data.params.b0 * 1e6
    );
    print!("D \\ G [m]");
    for g in &data.g {
        print!("\t{g:.3e}");
    }
    println!();
    for (i, d) in data.d.iter().enumerate() {
        print!("{d:.1}");
        for j in 0..data.g.len() {
            print!(
                "\t{:.3} ±{:.1e}",
                data.b_s[i][j] * 1e6,
                data.error[i][j] * 1e6
            );
        }
        println!();
    }
    println!("claims: {:?}", geardyn_models::yu2021::fig4_claims(&data)?);

    println!("\n# convergence of b_i/G^(D-1) with l_s (L = l_a = 1 mm, 8 points/wavelength)");
    for d in [1.2, 1.4, 1.6, 1.8] {
        let s = SurfaceFractal::new(d, 1.0)?;
        for l_s in [1e-4, 1e-5, 1e-6, 1e-7] {
            let p = WmProfile::new(s, 1.5, 1e-3, l_s)?;
            let m = mean_asperity_height(&p, 1e-3, Quadrature::default())?;
            println!(
                "D={d} l_s={l_s:.0e} n_terms={} N={} b_i/G^(D-1)={:.6e} quad_est={:.2e} trunc_bound={:.2e}",
                m.n_terms, m.n_points, m.value, m.quadrature_error, m.truncation_bound
            );
        }
    }

    println!("\n# dependence of b_i on the sampling length L (D = 1.3, l_s = 10 µm, l_a = 1 mm)");
    let s = SurfaceFractal::new(1.3, 1e-11)?;
    let p = WmProfile::new(s, 1.5, 1e-3, 1e-5)?;
    for l in [0.5e-3, 1e-3, 2e-3, 5e-3, 10e-3, 20e-3, 50e-3] {
        let m = mean_asperity_height(&p, l, Quadrature::default())?;
        println!("L={l:.1e} m  b_i={:.4} µm", m.value * 1e6);
    }

    println!("\n# printed Eq. (11) b_s (no |.|, k from 0), D = 1.2, G = 1e-11 m");
    let mut pr = yu2021::fig4_backlash_params();
    pr.form = ConstantPartForm::PrintedEq11;
    let s = SurfaceFractal::new(1.2, 1e-11)?;
    let c = pr.constant_part(s, s)?;
    println!("b_p = {:.4e} m, b_s = {:.4e} m", c.b_p, c.b_s);
    Ok(())
}
