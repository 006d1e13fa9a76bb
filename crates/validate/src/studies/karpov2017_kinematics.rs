//! Karpov et al. 2017 kinematics figures: the centrodes and gear ratio of Fig. 1 (with the
//! balancing statement of Sect. 4), the ξ-shapes of Fig. 2, and the Sect. 4 recommendation of
//! sinusoid-like centrodes with j = 2.

use math::DetMath;
use std::f64::consts::TAU;

use gear_geometry::{CentreDistance, KarpovPair, KarpovPairParams};

use crate::{
    ABOUT_BAND, Claim, Comparison, Cost, Error, Evidence, Figure, Paper, Reference, ResultExt,
    Series, Study, StudyOutput, Table, Tolerance, Verdict, fmt_sig,
};

/// The studies of this file.
pub fn studies() -> Vec<Study> {
    vec![
        Study {
            id: "karpov2017-fig1-centrodes",
            paper: Paper::Karpov2017,
            source: "Fig. 1, Sect. 2; Sect. 4",
            title: "Gear centrodes and gear ratio for j = 1…4 (u = ξ = 2, B = 0.1), and balancing",
            description: "Centrodes r1(φ1) and r2 (drawn over the output angle φ2) and the exact \
                ratio i(φ1) of the closing pair (R-KARPOV-EQ1-CLOSURE) for j = 1, 2, 3, 4 at the \
                figure's u = ξ = 2, B = 0.1. The text's statement that j = 2 is the smallest j at \
                which both gears are balanced is checked by the centroid of each centrode's \
                area (balanced: |centroid| ≤ 1e-9 r, the quadrature's accuracy with 4096 \
                points).",
            cost: Cost::Fast,
            run: fig1,
        },
        Study {
            id: "karpov2017-fig2-ratio-shape",
            paper: Paper::Karpov2017,
            source: "Fig. 2, Sect. 2",
            title: "Influence of ξ on the gear ratio i (u = 2, B = 0.001)",
            description: "i(φ1) for ξ = 1.1, 2, 5, 10 (j = 1). Two shape measures of i − mean: \
                the steepness s = max|di/dφ1| / (half the peak-to-peak of i) (1 for a sinusoid) \
                and the distance from a sinusoid d = RMS of the residual after the first Fourier \
                harmonic / RMS of i − mean. Claims: abrupt at ξ = 1.1 (s ≥ 3, three times a \
                sinusoid's), smoother with ξ (s decreasing), almost a sinusoid at ξ = 10 \
                (d within the 'almost' band).",
            cost: Cost::Fast,
            run: fig2,
        },
        Study {
            id: "karpov2017-sect4-sinusoidal-j2",
            paper: Paper::Karpov2017,
            source: "Sect. 4, Eq. (1), (2), (6)",
            title: "Sinusoid-like centrodes with j = 2: the limit ξ → ∞ and the smallest ε_max \
                among balanced designs",
            description: "Eq. (1) at ξ = 10⁶ against the printed sinusoidal centrodes \
                r1 = r(1 + B sin 2φ1), r2 = r(u − B sin 2φ1) (consistency: formula against its \
                limit form), and the exact ε_max (Table 1 pair, ω1 = 1 rad/s) over the balanced \
                designs j = 2, 3, 4 and ξ = 1.1, 2, 5, 10, ∞: the recommendation holds if j = 2, \
                ξ = ∞ gives the smallest ε_max. The resonance-amplitude part of the \
                recommendation is covered by karpov2017-fig6-a-vs-b-xi.",
            cost: Cost::Fast,
            run: sect4,
        },
    ]
}

/// Quadrature points per revolution.
const N: usize = 4096;

fn pair(u: f64, b: f64, xi: f64, j: u32) -> Result<KarpovPair, Error> {
    KarpovPair::new(KarpovPairParams {
        r: 1.0,
        u,
        b,
        xi,
        j,
        z1: 32,
        centre_distance: CentreDistance::Closing,
    })
    .context("Karpov pair")
}

/// Centroid distance (in units of r) of the area enclosed by the polar curve `(ρ(t), φ(t))`,
/// `t` uniform over one closed revolution, by the periodic trapezoidal rule:
/// `x_c = (1/3A)∮ρ³cos φ dφ`, `y_c = (1/3A)∮ρ³ sin φ dφ`, `A = ½∮ρ² dφ`.
fn centroid(curve: &[(f64, f64, f64)]) -> f64 {
    // (ρ, φ, dφ/dt·dt)
    let (mut a, mut x, mut y) = (0.0, 0.0, 0.0);
    for &(rho, phi, dphi) in curve {
        a += 0.5 * rho * rho * dphi;
        x += rho.powi(3) * phi.dcos() * dphi / 3.0;
        y += rho.powi(3) * phi.dsin() * dphi / 3.0;
    }
    x.dhypot(y) / a
}

fn fig1() -> Result<StudyOutput, Error> {
    let (u, xi, b) = (2.0, 2.0, 0.1);
    let mut out = StudyOutput::new();
    let mut t = Table::new(
        "balance",
        &[
            ("j", "1"),
            ("input_centroid_over_r", "1"),
            ("output_centroid_over_r", "1"),
            ("i_min", "1"),
            ("i_max", "1"),
        ],
    );
    let mut ratio = Figure::new(
        "ratio",
        "Karpov Fig. 1: gear ratio i(φ1), u = ξ = 2, B = 0.1",
        ("phi1", "rad"),
        ("i", "1"),
    );
    let mut shapes = Figure::new(
        "centrodes",
        "Karpov Fig. 1: centrodes (input at the origin, output at the centre distance)",
        ("x", "r"),
        ("y", "r"),
    );
    let mut balanced = Vec::new();
    for j in 1..=4u32 {
        let p = pair(u, b, xi, j)?;
        let dt = TAU / N as f64;
        let input: Vec<(f64, f64, f64)> = (0..N)
            .map(|k| {
                let f = k as f64 * dt;
                (p.r1(f), f, dt)
            })
            .collect();
        // the output closes after u input revolutions (φ2 = 2π); contact on the line of centres
        let m = (u * N as f64) as usize;
        let output: Vec<(f64, f64, f64)> = (0..m)
            .map(|k| {
                let f = k as f64 * dt;
                (p.r2(f), -p.output_angle(f), p.ratio(f) * dt)
            })
            .collect();
        let (ci, co) = (centroid(&input), centroid(&output));
        balanced.push((j, ci <= 1e-9, co <= 1e-9, ci, co));
        let is: Vec<f64> = (0..N).map(|k| p.ratio(k as f64 * dt)).collect();
        let (imin, imax) = is
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, c), &v| {
                (a.min(v), c.max(v))
            });
        t.push_nums(&[f64::from(j), ci, co, imin, imax])?;
        ratio.push(Series::line(
            format!("j = {j}"),
            (0..=256)
                .map(|k| {
                    let f = TAU * k as f64 / 256.0;
                    (f, p.ratio(f))
                })
                .collect(),
        ));
        let a = p.centre_distance();
        let stride = N / 256;
        shapes.push(Series::line(
            format!("input, j = {j}"),
            input
                .iter()
                .step_by(stride)
                .map(|&(r, f, _)| (r * f.dcos(), r * f.dsin()))
                .collect(),
        ));
        shapes.push(Series::line(
            format!("output, j = {j}"),
            output
                .iter()
                .step_by(stride)
                .map(|&(r, f, _)| (a - r * f.dcos(), r * f.dsin()))
                .collect(),
        ));
    }
    let smallest_both = balanced.iter().find(|b| b.1 && b.2).map_or(0, |b| b.0);
    out.claim(
        Claim::new(
            "Note that the minimum value of j at which both input and output gears are balanced is 2 (see Fig. 1).",
            "Sect. 4",
            format!(
                "centroid/r of input, output: {}; smallest j with both ≤ 1e-9: {smallest_both}",
                balanced
                    .iter()
                    .map(|b| format!("j = {}: {}, {}", b.0, fmt_sig(b.3, 3), fmt_sig(b.4, 3)))
                    .collect::<Vec<_>>()
                    .join("; ")
            ),
            Verdict::from_bool(smallest_both == 2),
        )
        .cause("centroids of the model's closed centrodes"),
    );
    out.table(t);
    out.figure(ratio);
    out.figure(shapes);
    Ok(out)
}

/// (steepness, distance from a sinusoid) of i(φ1) over one period.
fn shape(p: &KarpovPair) -> (f64, f64) {
    let dt = TAU / N as f64;
    let is: Vec<f64> = (0..N).map(|k| p.ratio(k as f64 * dt)).collect();
    let mean = is.iter().sum::<f64>() / N as f64;
    let (lo, hi) = is
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, c), &v| {
            (a.min(v), c.max(v))
        });
    let slope = (0..N)
        .map(|k| ((is[(k + 1) % N] - is[(k + N - 1) % N]) / (2.0 * dt)).abs())
        .fold(0.0, f64::max);
    let steep = slope / (0.5 * (hi - lo));
    let (mut c, mut s) = (0.0, 0.0);
    for (k, v) in is.iter().enumerate() {
        let f = k as f64 * dt;
        c += (v - mean) * f.dcos();
        s += (v - mean) * f.dsin();
    }
    let (c, s) = (2.0 * c / N as f64, 2.0 * s / N as f64);
    let (mut res, mut tot) = (0.0, 0.0);
    for (k, v) in is.iter().enumerate() {
        let f = k as f64 * dt;
        let d = v - mean;
        let r = d - c * f.dcos() - s * f.dsin();
        res += r * r;
        tot += d * d;
    }
    (steep, (res / tot).sqrt())
}

fn fig2() -> Result<StudyOutput, Error> {
    let xis = [1.1, 2.0, 5.0, 10.0];
    let mut out = StudyOutput::new();
    let mut t = Table::new(
        "shape",
        &[
            ("xi", "1"),
            ("steepness", "1"),
            ("distance_from_sinusoid", "1"),
        ],
    );
    let mut fig = Figure::new(
        "ratio",
        "Karpov Fig. 2: gear ratio i(φ1) for several ξ, u = 2, B = 0.001",
        ("phi1", "rad"),
        ("i", "1"),
    );
    let mut shapes = Vec::new();
    for &xi in &xis {
        let p = pair(2.0, 0.001, xi, 1)?;
        let (s, d) = shape(&p);
        shapes.push((xi, s, d));
        t.push_nums(&[xi, s, d])?;
        fig.push(Series::line(
            format!("ξ = {xi}"),
            (0..=512)
                .map(|k| {
                    let f = TAU * k as f64 / 512.0;
                    (f, p.ratio(f))
                })
                .collect(),
        ));
    }
    let listing = shapes
        .iter()
        .map(|(x, s, d)| format!("ξ = {x}: s = {}, d = {}", fmt_sig(*s, 3), fmt_sig(*d, 3)))
        .collect::<Vec<_>>()
        .join("; ");
    out.claim(
        Claim::new(
            "At ξ close to 1, i changes abruptly (see the curve ξ = 1.1).",
            "Sect. 2, Fig. 2",
            format!("{listing}; 'abruptly' read as s ≥ 3 (a sinusoid has s = 1)"),
            Verdict::from_bool(shapes[0].1 >= 3.0),
        )
        .cause("steepness of the model's gear ratio"),
    );
    let smoother = shapes.windows(2).all(|w| w[1].1 < w[0].1);
    out.claim(
        Claim::new(
            "With increasing ξ, the variation of i becomes smoother.",
            "Sect. 2, Fig. 2",
            format!("{listing}; smoother read as s strictly decreasing"),
            Verdict::from_bool(smoother),
        )
        .cause("steepness of the model's gear ratio"),
    );
    let d10 = shapes[3].2;
    out.compare(
        Comparison::new(
            "distance of i(φ1) from a sinusoid at ξ = 10 (RMS residual after the first harmonic / RMS)",
            "1",
            Reference::computed(0.0, "Sect. 2: 'i is almost a sinusoid' (a sinusoid has 0)"),
            d10,
            Tolerance::stated(
                crate::ToleranceBand::Absolute(ABOUT_BAND),
                "the text says \"almost\": the one band, 10 % (here of the RMS)",
            ),
        )
        .cause("shape of the model's gear ratio"),
    );
    out.table(t);
    out.figure(fig);
    Ok(out)
}

fn sect4() -> Result<StudyOutput, Error> {
    let mut out = StudyOutput::new();
    let (u, b) = (2.0, 0.01);
    // the limit ξ → ∞ of Eq. (1) at j = 2 against the printed sinusoidal centrodes
    let p = pair(u, b, 1e6, 2)?;
    let ps = KarpovPair::new(KarpovPairParams {
        centre_distance: CentreDistance::AsPrinted,
        ..p.params()
    })
    .context("Karpov pair (as printed)")?;
    let dev = (0..N)
        .map(|k| {
            let f = TAU * k as f64 / N as f64;
            let e1 = (ps.r1(f) - (1.0 + b * (2.0 * f).dsin())).abs();
            let e2 = (ps.r2(f) - (u - b * (2.0 * f).dsin())).abs();
            e1.max(e2)
        })
        .fold(0.0, f64::max);
    out.compare(
        Comparison::new(
            "max |Eq. (1) at ξ = 10⁶, j = 2 − r(1 ± B sin 2φ1)| / r",
            "1",
            Reference::computed(0.0, "Sect. 4: sinusoidal centrodes as the limit ξ → ∞"),
            dev,
            Tolerance::stated(
                crate::ToleranceBand::Absolute(2.0 * b / 1e6),
                "the limit error of Eq. (1) at finite ξ is O(B/ξ): 2B/ξ",
            ),
        )
        .class(Evidence::Consistency),
    );
    // ε_max over the balanced designs
    let base = models::karpov2017::pair_table1();
    let mut t = Table::new("emax", &[("j", "1"), ("xi", "1"), ("emax", "rad/s^2")]);
    let mut best = (0u32, 0.0, f64::INFINITY);
    for j in 2..=4u32 {
        for xi in [1.1, 2.0, 5.0, 10.0, f64::INFINITY] {
            let q = KarpovPair::new(KarpovPairParams {
                j,
                xi,
                ..base.params()
            })
            .context("Karpov pair")?;
            let e = q.max_acceleration(1.0);
            t.push_nums(&[f64::from(j), xi, e])?;
            if e < best.2 {
                best = (j, xi, e);
            }
        }
    }
    out.claim(
        Claim::new(
            "From Eqs. (1) and (2) at ξ → ∞ and j = 2, we obtain the gear centrodes with sinusoidal deviation ... which ensure a relatively small resonance amplitude with minimum additional dynamic loads.",
            "Sect. 4",
            format!(
                "exact ε_max of the Table 1 pair (ω1 = 1 rad/s) over the balanced designs j = 2…4, ξ = 1.1…∞: smallest at j = {}, ξ = {} ({}); the resonance-amplitude part is judged in karpov2017-fig6-a-vs-b-xi",
                best.0,
                best.1,
                fmt_sig(best.2, 4)
            ),
            Verdict::from_bool(best.0 == 2 && best.1.is_infinite()),
        )
        .cause("exact ε_max of the model pair over the balanced designs"),
    );
    out.table(t);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use math::DetMath;

    #[test]
    fn centroid_of_a_circle_is_zero_and_of_a_shifted_circle_is_its_offset() {
        let n = 2048;
        let dt = std::f64::consts::TAU / n as f64;
        let circle: Vec<_> = (0..n).map(|k| (1.0, k as f64 * dt, dt)).collect();
        assert!(super::centroid(&circle) < 1e-12);
        // circle of radius 1 through the origin shifted by e: ρ = 2e cos φ is degenerate; use
        // a small offset e: ρ(φ) = e cos φ + sqrt(1 − e² sin² φ)
        let e = 0.1;
        let shifted: Vec<_> = (0..n)
            .map(|k| {
                let f = k as f64 * dt;
                (
                    e * f.dcos() + (1.0 - e * e * f.dsin().powi(2)).sqrt(),
                    f,
                    dt,
                )
            })
            .collect();
        assert!((super::centroid(&shifted) - e).abs() < 1e-9);
    }
}
