//! Yu 2021: evidence studies for the scaling of Figs. 9–14 (issue "Yu 2021 dynamics").
//!
//! * `yu2021-fig10-scaling`: which dimensionless load `T*` (i.e. which `k_am b_n`) the text's
//!   Fig. 10 numbers imply, the model's DTE at that load, and whether Eq. (18) can supply the
//!   stiffness trend in `D` this needs (reading R-YU-FIG10).
//! * `yu2021-d-trends`: DF (Eq. 20) and RMS (Eq. 21) against `ω*` per fractal dimension `D`
//!   (Eq. 18 stiffness and Eq. 4–5 backlash from the same surface) and per load (trends of
//!   Figs. 11–14).
//! * `yu2021-chen-amplitude`: sensitivity of Chen's DF to the amplitude `a_z` of its fractal
//!   backlash, which Yu does not state.
//!
//! Every run: `Engine::timestep()` (Dormand–Prince 5(4), rtol 1e-8, atol 1e-10, contact switches
//! as events), state-dependent backlash, 200 transient + 20 recorded mesh periods.

use math::DetMath;
use models::yu2021::{
    FractalContact, FractalForm, FractalMeshStiffness, Options, ReferenceRun, Response,
    Yu2021Params, fractal_contact_stiffness,
};

use super::yu2021::{
    check_cells, checked_columns, fractal_rig, row_with, run_checked, run_flags, stat_cells,
};
use crate::{
    Cell, Claim, Cost, Error, Evidence, Figure, Paper, ResultExt, Series, Study, StudyOutput,
    Table, Verdict, fmt_sig, published,
};

/// The studies of this file.
pub fn studies() -> Vec<Study> {
    vec![
        Study {
            id: "yu2021-fig10-scaling",
            paper: Paper::Yu2021,
            source: "Fig. 9, Fig. 10, Eq. (17)-(19), Sect. 4.1-4.2",
            title: "Load T* and stiffness implied by the Fig. 10 numbers; Eq. (18) against them",
            description: "Hand estimate (docs/models/yu2021.md): at ω* = 0.2 the pair stays in \
                contact and follows the load quasi-statically, so mean DTE ≈ B + T*/√(1−ε²) and \
                peak-to-peak ≈ 2εT*/(1−ε²). Inverting the text's means (70, 22, 12) with its \
                Fig. 9 backlash means (5.5, 7.2, 9.2) gives T*(D); the model (Fig. 10 rig, \
                k_am = F_s/(T* b_n)) is run at those loads for ε = 0.2 and 0.4. The stiffness \
                ratios k_am(1.4)/k_am(1.2) = T*(1.2)/T*(1.4) etc. are set against Eq. (18) \
                (consistent form, mesh-stiffness leaf defaults) and the largest-contact area a_L \
                Eq. (18) would need is computed. Engine: `timestep`.",
            cost: Cost::Heavy,
            run: fig10_scaling,
        },
        Study {
            id: "yu2021-d-trends",
            paper: Paper::Yu2021,
            source: "Fig. 11-14, Eq. (20)-(21), Sect. 4.3-4.4",
            title: "DF and RMS vs ω* per fractal dimension D and per load, D-dependent model",
            description: "Yu's 6-DOF model on the Fig. 10 rig (Table 2 pair, fractal backlash of \
                Eq. 4–5 and Eq. (18) stiffness from the same surface, G = 1e-11 m), 13 \
                frequencies ω* = 0.2 … 1.4, D = 1.2, 1.4, 1.6, 1.8 at 340 N·m and loads 170, \
                340, 680 N·m at D = 1.4. DF = max F_m/F_s, RMS of the first 4 DTE harmonics \
                (units of b_n). Engine: `timestep`.",
            cost: Cost::Heavy,
            run: d_trends,
        },
        Study {
            id: "yu2021-chen-amplitude",
            paper: Paper::Yu2021,
            source: "Fig. 13, Eq. (3), Sect. 4.4",
            title: "Chen's DF against the unstated amplitude a_z of its fractal backlash",
            description: "Chen's model (B = b_s + a_z z(ω_h t), z of Eq. 3 with D = 1.5) on \
                Yu2021Params::table1() for a_z/b_h = 0, 0.005, 0.01, 0.02, 0.05, 0.1 at \
                ω* = 0.3, 0.6, 0.9, 1.2. Yu does not state a_z and Chen's papers (Refs. [14], \
                [25]) are not in the seeds; the studies use a_z = 0.05 b_h. a_z = 0 is the \
                Kahraman–Singh model. Engine: `timestep`.",
            cost: Cost::Heavy,
            run: chen_amplitude,
        },
    ]
}

const EPS: [f64; 2] = [0.2, 0.4];
const D3: [f64; 3] = [1.2, 1.4, 1.6];

fn key(d: f64) -> String {
    format!("d{}", fmt_sig(10.0 * d, 2))
}

fn max_of(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::NEG_INFINITY, f64::max)
}

/// Fraction of the recorded samples inside the dead zone (`|δ*| < B`: contact lost).
fn separated(r: &Response) -> f64 {
    let n = r
        .dte
        .iter()
        .zip(&r.backlash)
        .filter(|(x, b)| x.abs() < **b)
        .count();
    n as f64 / r.dte.len().max(1) as f64
}

fn eq18(d: f64) -> Result<f64, Error> {
    let c = FractalContact {
        fractal_dimension: d,
        ..FractalMeshStiffness::table2().contact
    };
    fractal_contact_stiffness(&c, FractalForm::Consistent).context("Eq. (18)")
}

fn fig10_scaling() -> Result<StudyOutput, Error> {
    let paper = published!("yu2021.toml")?;
    let mut implied = Vec::new();
    for d in D3 {
        let mean = paper.value(&format!("fig10.mean.{}", key(d)))?.value;
        let b = paper.value(&format!("fig9.dynamic-mean.{}", key(d)))?.value;
        let amp = paper.value(&format!("fig10.amplitude.{}", key(d)))?.value;
        implied.push((d, mean, b, amp));
    }
    let jobs: Vec<(usize, usize)> = (0..D3.len())
        .flat_map(|i| (0..EPS.len()).map(move |j| (i, j)))
        .collect();
    let runs: Vec<Result<(f64, ReferenceRun), Error>> = timestep::sweep(
        &jobs,
        |&(i, j)| {
            let (d, mean, b, _) = implied[i];
            let eps = EPS[j];
            let t_star = (mean - b) * (1.0 - eps * eps).sqrt();
            let mut p = fractal_rig(d)?;
            p.stiffness_ratio = eps;
            p.mesh_stiffness = p.static_force() / (t_star * p.nominal_length);
            Ok((t_star, run_checked(&p, Options::default(), 0.2)?))
        },
        None,
    )
    .into_iter()
    .collect();
    let mut out = StudyOutput::new();
    let mut t = Table::new(
        "implied-load",
        &checked_columns(&[
            ("D", "1"),
            ("epsilon", "1"),
            ("T* implied", "1"),
            ("k_am", "N/m"),
            ("mean DTE text", "1"),
            ("mean DTE model", "1"),
            ("amplitude text", "1"),
            ("p-p DTE model", "1"),
            ("max DTE model", "1"),
            ("mean B model", "1"),
            ("fraction out of contact", "1"),
        ]),
    );
    let mut flags = Vec::new();
    let mut fit = [(0.0f64, 0.0f64); 2]; // per ε: worst relative miss of p-p and of max
    let mut tstars = [[0.0; 3]; 2];
    for (&(i, j), r) in jobs.iter().zip(runs) {
        let (t_star, checked) = r?;
        let (d, mean, _, amp) = implied[i];
        flags.extend(run_flags(
            [(format!("D = {d}, ε = {}", EPS[j]), &checked)],
            false,
        ));
        let [period, change] = check_cells(&checked);
        let stats = stat_cells(&checked);
        let resp = checked.response;
        let p = fractal_rig(d)?;
        let k = p.static_force() / (t_star * p.nominal_length);
        let (pp, mx) = (resp.dte_peak_to_peak(), max_of(&resp.dte));
        fit[j].0 = fit[j].0.max((pp / amp - 1.0).abs());
        fit[j].1 = fit[j].1.max((mx / amp - 1.0).abs());
        tstars[j][i] = t_star;
        t.push(row_with(
            &[
                d,
                EPS[j],
                t_star,
                k,
                mean,
                resp.mean_dte(),
                amp,
                pp,
                mx,
                resp.mean_backlash(),
                separated(&resp),
                period,
                change,
            ],
            stats,
        ))?;
    }
    out.table(t);
    let mut fits = Vec::new();
    for j in 0..EPS.len() {
        fits.push(format!(
            "ε = {}: worst |model/text − 1| over D = 1.2, 1.4, 1.6 is {} reading 'amplitude' as \
             peak-to-peak, {} reading it as the maximum DTE",
            EPS[j],
            fmt_sig(fit[j].0, 2),
            fmt_sig(fit[j].1, 2)
        ));
    }
    out.claim(
        Claim::new(
            "The vibration both fluctuate around 70 … a mean value of about 22 … The average value of dynamic backlash is about 12 … The amplitude of vibration gets about 115 for D = 1.2, while decrease to 30 at D = 1.4 … about 18 and 16 with D = 1.6 and D = 1.8",
            "Sect. 4.2, Fig. 10",
            format!(
                "with T*(D) inverted from the text's means the model reproduces them (table); the \
                 amplitudes then follow from ε alone: {}",
                fits.join("; ")
            ),
            Verdict::Inconclusive,
        )
        .class(Evidence::Calibration(
            "T*(D) inverted from the text's mean DTE, so the means agree by construction of the \
             load; the amplitudes then depend on ε only"
                .to_owned(),
        ))
        .reading("R-YU-FIG10")
        .flagged_all(flags),
    );
    // Stiffness ratios implied vs Eq. (18)
    let mut s = Table::new(
        "stiffness-ratios",
        &[
            ("D from", "1"),
            ("D to", "1"),
            ("k ratio implied (eps 0.2)", "1"),
            ("k ratio Eq. 18", "1"),
            ("a_L Eq. 18 would need", "m2"),
            ("a_L leaf default", "m2"),
        ],
    );
    let base = FractalMeshStiffness::table2().contact;
    let mut worst_al: f64 = 0.0;
    for i in 0..2 {
        let (d0, d1) = (D3[i], D3[i + 1]);
        let want = tstars[0][i] / tstars[0][i + 1];
        let have = eq18(d1)? / eq18(d0)?;
        // k_c ∝ a_L^{D/2}: the ratio scales with a_L^{(d1 − d0)/2}
        let a_l = base.largest_contact_area * (want / have).dpowf(2.0 / (d1 - d0));
        worst_al = worst_al.max(a_l);
        s.push_nums(&[d0, d1, want, have, a_l, base.largest_contact_area])?;
    }
    out.table(s);
    let falls = eq18(1.4)? < eq18(1.2)? && eq18(1.6)? < eq18(1.4)?;
    out.claim(
        Claim::new(
            "For smooth surface with high stiffness, the contact property is enhanced and leads to small amplitude of DTE.",
            "Sect. 4.2, Fig. 10",
            format!(
                "the text's means need k_am to rise ≈ {}× from D = 1.2 to 1.4 and ≈ {}× from 1.4 \
                 to 1.6; Eq. (18) with the leaf's inputs falls with D ({falls}); with a_L the only \
                 free input it would need a_L up to {} m² (the leaf's π l_a²/4 = {} m²; a tooth \
                 flank of Table 2 is ~1e-4 m²)",
                fmt_sig(tstars[0][0] / tstars[0][1], 3),
                fmt_sig(tstars[0][1] / tstars[0][2], 3),
                fmt_sig(worst_al, 3),
                fmt_sig(base.largest_contact_area, 3)
            ),
            Verdict::Deviation,
        )
        .class(Evidence::Consistency)
        .reading("R-YU-FIG10")
        .reading("R-YU-EQ18"),
    );
    Ok(out)
}

fn grid(a: f64, b: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| a + (b - a) * i as f64 / (n - 1) as f64)
        .collect()
}

const D4: [f64; 4] = [1.2, 1.4, 1.6, 1.8];
const LOADS: [f64; 3] = [170.0, 340.0, 680.0];

fn d_trends() -> Result<StudyOutput, Error> {
    let omegas = grid(0.2, 1.4, 13);
    // cases: D at 340 N·m, then loads at D = 1.4
    let mut cases: Vec<(f64, f64)> = D4.iter().map(|&d| (d, 340.0)).collect();
    cases.extend(LOADS.iter().map(|&l| (1.4, l)));
    let jobs: Vec<(usize, f64)> = (0..cases.len())
        .flat_map(|c| omegas.iter().map(move |&w| (c, w)))
        .collect();
    let checked: Vec<Result<ReferenceRun, Error>> = timestep::sweep(
        &jobs,
        |&(c, w)| {
            let (d, load) = cases[c];
            let mut p = fractal_rig(d)?;
            p.torque = load;
            run_checked(&p, Options::default(), w)
        },
        None,
    )
    .into_iter()
    .collect();
    let checked: Vec<ReferenceRun> = checked.into_iter().collect::<Result<_, _>>()?;
    let res: Vec<(f64, f64)> = checked
        .iter()
        .map(|r| (r.metrics.dynamic_factor, r.metrics.rms))
        .collect();
    let n = omegas.len();
    let mut out = StudyOutput::new();
    let label = |c: usize| {
        let (d, l) = cases[c];
        format!("D = {d}, T = {l} N·m")
    };
    let mut checks = Table::new(
        "checks",
        &checked_columns(&[("D", "1"), ("load", "N·m"), ("omega*", "1")]),
    );
    for (&(c, w), r) in jobs.iter().zip(&checked) {
        let [motion, change] = check_cells(r);
        checks.push(row_with(
            &[cases[c].0, cases[c].1, w, motion, change],
            stat_cells(r),
        ))?;
    }
    let mut cols: Vec<String> = vec!["omega*".to_owned()];
    for c in 0..cases.len() {
        cols.push(format!("DF {}", label(c)));
        cols.push(format!("RMS {}", label(c)));
    }
    let units: Vec<(&str, &str)> = cols.iter().map(|c| (c.as_str(), "1")).collect();
    let mut t = Table::new("df-rms", &units).reproducible_digits(super::yu2021::CHECKED_DIGITS);
    // values of runs that are not reproducible under the 100× tighter tolerance: n/p
    let unsettled = |k: usize| checked[k].flag(false).is_some();
    for (i, w) in omegas.iter().enumerate() {
        let mut row = vec![Cell::Num(*w)];
        for c in 0..cases.len() {
            let (df, rms) = res[c * n + i];
            let u = unsettled(c * n + i);
            row.push(Cell::settled_if(df, u));
            row.push(Cell::settled_if(rms, u));
        }
        t.push(row)?;
    }
    out.table(t);
    out.table(checks);
    for (name, title, pick) in [
        ("df", "DF vs ω* per D and load (Eq. 18 stiffness)", 0usize),
        ("rms", "RMS (n = 4, b_n) vs ω* per D and load", 1usize),
    ] {
        let mut fig = Figure::new(name, title, ("ω*", "1"), (name, "1"));
        for c in 0..cases.len() {
            let pts = omegas
                .iter()
                .enumerate()
                .map(|(i, w)| {
                    let v = res[c * n + i];
                    (*w, if pick == 0 { v.0 } else { v.1 })
                })
                .collect();
            fig.push(Series::line(label(c), pts).unsettled((0..n).map(|i| unsettled(c * n + i))));
        }
        out.figure(fig);
    }
    // Paper: DTE decreases with D (Fig. 12 at ω* = 0.31; conclusion 3). Compare the RMS summed
    // over the grid, per D.
    let totals: Vec<f64> = (0..D4.len())
        .map(|c| (0..n).map(|i| res[c * n + i].1).sum::<f64>())
        .collect();
    // a sum over a run that is not reproducible under the 100× tighter tolerance moves with
    // every retune of the integrator (issue 28: ΣRMS for D = 1.2, which includes the run at
    // ω* = 1.4, moved 6.61 → 6.57): an unsettled span (n/p committed, full in validation/stats/);
    // a sum over reproducible runs only is known to 1e-3 of itself, 3 significant digits
    let total_text = |c: usize| {
        let x = fmt_sig(totals[c], super::yu2021::CHECKED_DIGITS as usize);
        if (0..n).any(|i| unsettled(c * n + i)) {
            crate::unsettled(x)
        } else {
            x
        }
    };
    let falls = totals.windows(2).all(|w| w[1] < w[0]);
    out.claim(
        Claim::new(
            "both the DTE and relative velocity shows decreasing trend with D",
            "Sect. 4.3, Fig. 12; Conclusion (3)",
            format!(
                "ΣRMS over ω* = 0.2 … 1.4 for D = 1.2, 1.4, 1.6, 1.8: {}; falls with D: {falls} \
                 (Eq. 18 with the leaf inputs lowers k_am as D grows, raising T*)",
                (0..totals.len())
                    .map(total_text)
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            Verdict::from_bool(falls),
        )
        .reading("R-YU-FIG10")
        .flagged_all(run_flags(
            jobs.iter()
                .zip(&checked)
                .filter(|((c, _), _)| *c < D4.len())
                .map(|((c, w), r)| (format!("{}, ω* = {w}", label(*c)), r)),
            false,
        )),
    );
    Ok(out)
}

const AZ: [f64; 6] = [0.0, 0.005, 0.01, 0.02, 0.05, 0.1];
const W_CHEN: [f64; 4] = [0.3, 0.6, 0.9, 1.2];

fn chen_amplitude() -> Result<StudyOutput, Error> {
    let base = Yu2021Params::table1();
    let jobs: Vec<(f64, f64)> = AZ
        .iter()
        .flat_map(|&a| W_CHEN.iter().map(move |&w| (a, w)))
        .collect();
    let chen_runs: Vec<ReferenceRun> = timestep::sweep(
        &jobs,
        |&(a, w)| {
            let p = Yu2021Params {
                chen_amplitude: a * base.backlash.constant_part().context("b_s")?,
                ..base
            };
            run_checked(&p, Options::chen(), w)
        },
        None,
    )
    .into_iter()
    .collect::<Result<_, Error>>()?;
    let ks_runs: Vec<ReferenceRun> = timestep::sweep(
        &W_CHEN,
        |&w| run_checked(&base, Options::kahraman_singh(), w),
        None,
    )
    .into_iter()
    .collect::<Result<_, Error>>()?;
    let res: Vec<f64> = chen_runs
        .iter()
        .map(|r| r.response.dynamic_factor())
        .collect();
    let ks: Vec<f64> = ks_runs
        .iter()
        .map(|r| r.response.dynamic_factor())
        .collect();
    let mut out = StudyOutput::new();
    let mut checks = Table::new(
        "checks",
        &checked_columns(&[("model", "-"), ("a_z/b_h", "1"), ("omega*", "1")]),
    );
    let mut flags = Vec::new();
    for (&(a, w), r) in jobs.iter().zip(&chen_runs) {
        let [period, change] = check_cells(r);
        let mut row = vec![
            "Chen".into(),
            a.into(),
            w.into(),
            period.into(),
            change.into(),
        ];
        row.extend(stat_cells(r));
        checks.push(row)?;
        flags.extend(run_flags(
            [(format!("Chen a_z = {a} b_h, ω* = {w}"), r)],
            false,
        ));
    }
    for (&w, r) in W_CHEN.iter().zip(&ks_runs) {
        let [period, change] = check_cells(r);
        let mut row = vec![
            "Kahraman-Singh".into(),
            0.0.into(),
            w.into(),
            period.into(),
            change.into(),
        ];
        row.extend(stat_cells(r));
        checks.push(row)?;
        flags.extend(run_flags([(format!("Kahraman–Singh ω* = {w}"), r)], false));
    }
    let cols: Vec<String> = std::iter::once("a_z/b_h".to_owned())
        .chain(W_CHEN.iter().map(|w| format!("DF at omega* = {w}")))
        .collect();
    let units: Vec<(&str, &str)> = cols.iter().map(|c| (c.as_str(), "1")).collect();
    let mut t = Table::new("df", &units).reproducible_digits(super::yu2021::CHECKED_DIGITS);
    let mut fig = Figure::new(
        "df-vs-az",
        "Chen's DF vs a_z/b_h, Table 1",
        ("a_z/b_h", "1"),
        ("DF", "1"),
    );
    let m = W_CHEN.len();
    // a run that is not reproducible under the 100× tighter tolerance gives a value that moves
    // with every retune of the integrator: committed as n/p (full value in validation/stats/)
    let unsettled = |k: usize| chen_runs[k].flag(false).is_some();
    for (i, a) in AZ.iter().enumerate() {
        let mut row = vec![Cell::Num(*a)];
        row.extend((0..m).map(|j| Cell::settled_if(res[i * m + j], unsettled(i * m + j))));
        t.push(row)?;
    }
    for (j, w) in W_CHEN.iter().enumerate() {
        fig.push(
            Series::line(
                format!("ω* = {w}"),
                AZ.iter()
                    .enumerate()
                    .map(|(i, a)| (*a, res[i * m + j]))
                    .collect(),
            )
            .unsettled((0..AZ.len()).map(|i| unsettled(i * m + j))),
        );
    }
    out.table(t);
    out.table(checks);
    out.figure(fig);
    let zero_is_ks = (0..m).all(|j| (res[j] - ks[j]).abs() <= 1e-9 * ks[j]);
    let at = |a: f64| AZ.iter().position(|x| (x - a).abs() < 1e-12).unwrap_or(0);
    let (i1, i5) = (at(0.01), at(0.05));
    // the DF of a run that is not reproducible under the 100× tighter tolerance moves with
    // every retune of the integrator (issue 28: DF at a_z = 0.05 b_h, ω* = 0.3 moved 34.5 →
    // 28.1): an unsettled span; a reproducible one at 3 significant digits (known to 1e-3)
    let df_text = |k: usize| {
        let x = fmt_sig(res[k], super::yu2021::CHECKED_DIGITS as usize);
        if unsettled(k) { crate::unsettled(x) } else { x }
    };
    out.claim(Claim::new(
        "predicted values of Chen' model and Kahraman's model both are much bigger than the experimental data",
        "Sect. 4.4, Fig. 13",
        format!(
            "a_z is not stated (Chen's Refs. [14], [25] are not in the seeds). a_z = 0 gives the \
             Kahraman–Singh DF exactly: {zero_is_ks}. DF at ω* = 0.3: {} (a_z = 0), {} (0.01 b_h), \
             {} (0.05 b_h, the studies' choice); at ω* = 0.9: {}, {}, {}. Chen's level in Fig. 13 \
             is set by this choice, so the claim cannot be checked",
            df_text(0),
            df_text(i1 * m),
            df_text(i5 * m),
            df_text(2),
            df_text(i1 * m + 2),
            df_text(i5 * m + 2),
        ),
        Verdict::Inconclusive,
    )
    .flagged_all(flags)
    .class(Evidence::NotCheckable(
        "Fig. 13 experimental DF points and Chen's a_z are not in the seeds".to_owned(),
    ))
    .cause(
        "Chen's fractal amplitude a_z is not stated in the paper (swept here) and Fig. 13/14 give \
         no digitised experimental points, so 'much bigger' cannot be judged",
    ));
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use models::yu2021::Yu2021Model;

    #[test]
    fn eq18_falls_with_d_for_the_leaf_inputs() {
        // the basis of the R-YU-FIG10 claim "Eq. (18) falls with D"
        assert!(eq18(1.4).unwrap() < eq18(1.2).unwrap());
        assert!(eq18(1.6).unwrap() < eq18(1.4).unwrap());
    }

    #[test]
    fn separated_counts_dead_zone_samples() {
        let r = Response {
            omega: 1.0,
            steps_per_period: 4,
            load: 1.0,
            tau: vec![0.0; 4],
            dte: vec![0.5, 2.0, -0.5, -2.0],
            force: vec![0.0; 4],
            backlash: vec![1.0; 4],
            alpha: vec![0.0; 4],
            final_state: [0.0; models::yu2021::STATE_LEN],
            stats: timestep::Stats::default(),
        };
        assert!((separated(&r) - 0.5).abs() < 1e-15);
    }

    #[test]
    fn yu_model_is_built_from_the_scaled_rig() {
        let p = fractal_rig(1.4).unwrap();
        assert!(Yu2021Model::new(&p, Options::default()).is_ok());
    }
}
