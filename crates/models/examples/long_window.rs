//! Long-window rattle statistics of the Liu model over the input speed ω1, with their spread
//! over two tolerances, two windows and two initial states.
//!
//! `cargo run --release -p geardyn-models --example long_window [from to step]`

use geardyn_models::liu2021::{self, BaseRadius, LongWindowOptions};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse())
        .collect::<Result<_, _>>()?;
    let (from, to, step) = match args[..] {
        [a, b, c] => (a, b, c),
        _ => (100.0, 250.0, 10.0),
    };
    if !(step > 0.0 && to >= from && (to - from) / step <= 10_000.0) {
        return Err("need from ≤ to and 0 < step, at most 10,000 points".into());
    }
    let n = ((to - from) / step).round() as usize;
    println!("omega1\trsv\tP_bi\tppv\tK\tregular\tspread");
    for i in 0..=n {
        let w = from + step * i as f64;
        let mut p = liu2021::table1();
        p.omega1 = w;
        p.readings.base_radius = BaseRadius::Mean;
        let r = liu2021::long_window(&p.model()?, &LongWindowOptions::default())?;
        println!(
            "{w}\t{}\t{:.3}\t{:.4}\t{:.2}\t{}\t{}",
            r.nominal.state.rsv(),
            r.nominal.bilateral_fraction(),
            r.nominal.ppv,
            r.nominal.chaos_k,
            r.regular(),
            r.describe()
        );
    }
    Ok(())
}
