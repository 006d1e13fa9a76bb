//! Scratch: Yu Fig. 10 scaling experiments (not part of the API).
use geardyn_models::yu2021::*;

fn rig(d: f64) -> Yu2021Params {
    let mut p = Yu2021Params::table2();
    p.nominal_length = 6e-6;
    p.backlash = BacklashSpec::Fractal {
        b0: 30e-6,
        surface: FractalSurface {
            dimension: d,
            roughness: 1e-11,
            lambda: 1.5,
            l_max: 1e-3,
            l_min: 1e-6,
            length: 1e-3,
        },
    };
    p
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let mode = args.get(1).map(|s| s.as_str()).unwrap_or("tstar");
    if mode == "k18" {
        for d in [1.2, 1.4, 1.5, 1.6, 1.8] {
            let mut c = FractalContact::yu2021_default();
            c.fractal_dimension = d;
            let k = fractal_contact_stiffness(&c, FractalForm::Consistent).unwrap();
            let mut c2 = c;
            c2.largest_contact_area = 1.0;
            let k2 = fractal_contact_stiffness(&c2, FractalForm::Consistent).unwrap();
            println!("D={d} k_c={k:.4e} (a_L=1 m2: {k2:.4e})");
        }
        return;
    }
    let eps: f64 = args.get(2).map(|s| s.parse().unwrap()).unwrap_or(0.2);
    let printed = args.get(3).map(|s| s == "printed").unwrap_or(false);
    let omega: f64 = args.get(4).map(|s| s.parse().unwrap()).unwrap_or(0.2);
    let ste: f64 = args.get(5).map(|s| s.parse().unwrap()).unwrap_or(5e-6);
    for (d, tstar) in [
        (1.2, 60.0),
        (1.4, 14.0),
        (1.6, 2.6),
        (1.8, 0.3),
        (1.2, 1.89),
        (1.8, 1.89),
    ] {
        let mut p = rig(d);
        p.stiffness_ratio = eps;
        p.ste_amplitude = ste;
        p.mesh_stiffness = p.static_force() / (tstar * p.nominal_length);
        let mut o = Options::default();
        if printed {
            o.form = EquationForm::Printed;
        }
        let m = Yu2021Model::new(&p, o).unwrap();
        let s = RunSettings {
            omega,
            transient_periods: 200,
            record_periods: 20,
            steps_per_period: 256,
        };
        let r = m.simulate_with(&s, &Engine::timestep(), None).unwrap();
        let max = r.dte.iter().cloned().fold(f64::MIN, f64::max);
        let min = r.dte.iter().cloned().fold(f64::MAX, f64::min);
        let sep = r
            .dte
            .iter()
            .zip(&r.backlash)
            .filter(|(x, b)| x.abs() < **b)
            .count() as f64
            / r.dte.len() as f64;
        println!(
            "D={d} T*={tstar:.3} k={:.3e} bs={:.3} meanB={:.3} meanDTE={:.3} pp={:.3} max={:.3} min={:.3} sepfrac={:.3} DF={:.3}",
            p.mesh_stiffness,
            m.params.backlash,
            r.mean_backlash(),
            r.mean_dte(),
            max - min,
            max,
            min,
            sep,
            r.dynamic_factor()
        );
    }
}
