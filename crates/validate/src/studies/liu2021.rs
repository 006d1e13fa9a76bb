//! Studies of the Liu et al. 2021 NFG model (dynamics): Table 2 amplitude ratio, the ω₁ sweep of
//! Fig. 11 with its thresholds, the responses of Fig. 8–10 and the load sweep of Fig. 15.
//!
//! All use Table 1 with the constant-b̄ reading (`R-LIU-EQ11`, the one the paper's figures
//! follow) and the derived Eq. (20)/(21) (`R-LIU-EQ20`, `R-LIU-EQ21`). Time integration from the
//! quasi-static contact position is the reference for the rattle state; harmonic balance is
//! reported beside it three ways: paper basis (R = 1) from a cold start, paper basis warm-started
//! from the time-integrated period (`HbmStart::FromTimeResponse`), and a full basis
//! K = Z2 + 2 = 65 warm-started the same way.

use gear_geometry::LiuRig;
use models::liu2021::{
    self, BaseRadius, BranchStability, ErrorTerm, HbmOptions, HbmStart, IntegrationOptions, Model,
    Parameters, RattleState, Readings, RigidAcceleration, SpeedBranch, SpeedContinuationOptions,
};
use rayon::prelude::*;

use crate::{
    Claim, Comparison, Cost, Error, Figure, Paper, ResultExt, Series, Study, StudyOutput, Table,
    Tolerance, ToleranceBand, Verdict, fmt_sig, published,
};

/// The studies of this file.
pub fn studies() -> Vec<Study> {
    vec![
        Study {
            id: "liu2021-table2-amplitude-ratio",
            paper: Paper::Liu2021,
            source: "Table 2, Eq. (23), Sect. 3.8",
            title: "Amplitude ratio ξ = A_e/A_c of Table 2 (theory and experiment columns)",
            description: "Model: Table 1 with T2 = 3 N·m (Sect. 3.8), rig constants that \
                reproduce the Table 2 frequencies (belt 21/16, Z2 = 64), harmonic balance on the \
                paper basis. Headers A_e/A_c are read as swapped (R-LIU-TABLE2): ξ = amplitude \
                at f_e / amplitude at f_c. The paper does not say which quantity's spectrum it \
                uses; the rows compare the velocity ratio (displacement ratio × Z2), the table \
                lists displacement, velocity and acceleration ratios. Tolerance: printed precision.",
            cost: Cost::Heavy,
            run: table2_ratio,
        },
        Study {
            id: "liu2021-fig11-speed-sweep",
            paper: Paper::Liu2021,
            source: "Fig. 11, Sect. 3.3",
            title: "Rattle state and ppv against input speed ω1 (100–250 rad/s)",
            description: "rsv and ppv (peak-to-peak of q over one period 2π/ω̄_c) from time \
                integration and from harmonic balance (paper basis cold and warm-started from \
                the time-integrated period; full basis K = 65 warm-started), 61 speeds. \
                Thresholds: the first speed with rsv ≥ 1 and with rsv = 2 from each method, \
                against the text's 150 and 170 rad/s; tolerance ±5 rad/s (the text quotes round \
                numbers, half of its 10 rad/s resolution). Claim: ppv jumps at the onset of \
                bilateral rattle.",
            cost: Cost::Heavy,
            run: speed_sweep,
        },
        Study {
            id: "liu2021-fig11-continuation",
            paper: Paper::Liu2021,
            source: "Fig. 11, Sect. 3.3",
            title: "Branches of periodic responses over ω1 by pseudo-arclength continuation",
            description: "Harmonic balance continued in ω1 (hbm pseudo-arclength) from the \
                bilateral response at 250 rad/s down to 100 rad/s on the paper basis, and on \
                the full basis K = 65 from 250 down and from 150 up. Folds (turning points) are \
                the jumps; stability from the multipliers of the time-integration period map \
                at the HBM state (BranchStability::Shooting). Claim: the jump of ppv at the \
                bilateral onset is a fold (hysteresis), with the time-integration onset inside \
                the coexistence range.",
            cost: Cost::Heavy,
            run: speed_continuation,
        },
        Study {
            id: "liu2021-fig8-10-responses",
            paper: Paper::Liu2021,
            source: "Fig. 8, 9, 10, Sect. 3.2",
            title: "Dynamic responses at ω1 = 160, 140, 180 rad/s: rattle state, time series, \
                phase portrait, spectrum",
            description: "Rattle state from time integration and harmonic balance (paper basis) \
                against the paper: unilateral at 160 (Fig. 8), no rattle at 140 (Fig. 9), \
                bilateral at 180 (Fig. 10); time series and phase portraits of one period; \
                amplitude spectrum of one steady period of q (time integration, 8192 samples, \
                bins at the harmonics k f_c) with the claims of Fig. 8c-10c on f_c and f_e.",
            cost: Cost::Heavy,
            run: responses,
        },
        Study {
            id: "liu2021-fig15-load-sweep",
            paper: Paper::Liu2021,
            source: "Fig. 15, Sect. 3.7",
            title: "Rattle state and ppv against load torque T2 (0–40 N·m)",
            description: "rsv and ppv from time integration and harmonic balance (paper basis \
                cold/warm, full basis K = 65 warm, converged points only, stability by the \
                period map) at ω1 = 160 rad/s, 41 torques; thresholds (last bilateral, first \
                rattle-free torque) against the text's 12 and 20 N·m, tolerance ±2 N·m (round \
                numbers). The text contradicts Fig. 8 (unilateral at T2 = 30): see R-LIU-FIG15.",
            cost: Cost::Heavy,
            run: load_sweep,
        },
        Study {
            id: "liu2021-fig12-14-parameter-sweeps",
            paper: Paper::Liu2021,
            source: "Fig. 12, 13, 14, Sect. 3.4-3.6",
            title: "Rattle state and ppv against e_r, ε and a_k (at ω1 = 140 and 160 rad/s)",
            description: "Time integration and harmonic balance (paper basis cold/warm, full \
                basis K = 65 warm; table columns) over e_r = 0–40 µm, \
                ε = 0–0.3 and a_k = k_r/k0 = 0.1–0.8, the other parameters from Table 1. Claims: \
                the succession no → unilateral → bilateral rattle with e_r and ε, a ppv jump at \
                the onset of bilateral rattle, and the paper's statement that a_k changes the \
                rattle state little (unilateral throughout at 160, no rattle throughout at 140).",
            cost: Cost::Heavy,
            run: parameter_sweeps,
        },
        Study {
            id: "liu2021-readings-speed-thresholds",
            paper: Paper::Liu2021,
            source: "Eq. (11), (20), (21); Fig. 11",
            title: "Which reading reproduces the Fig. 11 thresholds",
            description: "The ω1 sweep (time integration, 100–250 rad/s, step 5) under five \
                reading sets: consistent (time-varying b̄), constant b̄, constant b̄ with the \
                printed error sign, constant b̄ with the printed Eq. (20), and everything as \
                printed. Rows: first speed with unilateral and with bilateral rattle against the \
                text's 150 and 170 rad/s (±5 rad/s). Evidence for R-LIU-EQ11/EQ20/EQ21.",
            cost: Cost::Heavy,
            run: readings_thresholds,
        },
    ]
}

/// A number at 3 significant digits for claim evidence.
fn sig(x: f64) -> String {
    fmt_sig(x, 3)
}

/// Table 1 with the constant-b̄ reading.
fn base() -> Parameters {
    let mut p = liu2021::table1();
    p.readings.base_radius = BaseRadius::Mean;
    p
}

fn model(p: &Parameters) -> Result<Model, Error> {
    p.model().context("liu2021 model")
}

/// One HBM result of a sweep point.
#[derive(Debug, Clone, Copy)]
struct Hb {
    rsv: u8,
    ppv: f64,
    converged: bool,
    /// Converged only when started from a neighbouring sweep point (sequential continuation).
    from_neighbour: bool,
    /// Stability by the period-map multipliers (`shooting_multipliers`); `None` when not
    /// converged or not computed.
    stable: Option<bool>,
}

impl Hb {
    fn of(r: &liu2021::HbmResponse) -> Self {
        Self {
            rsv: r.rattle.state.rsv(),
            ppv: r.rattle.ppv,
            converged: r.converged(),
            from_neighbour: false,
            stable: None,
        }
    }
    const NONE: Hb = Hb {
        rsv: 0,
        ppv: f64::NAN,
        converged: false,
        from_neighbour: false,
        stable: None,
    };
}

/// One sweep point: time-integration and HBM rattle metrics (cold paper basis, warm paper basis,
/// warm full basis).
#[derive(Debug, Clone, Copy)]
struct Point {
    x: f64,
    rsv_time: u8,
    ppv_time: f64,
    cold: Hb,
    warm: Hb,
    full: Hb,
}

/// Highest harmonic of the full basis in the sweeps: K = Z2 + 2 (covers the paper basis).
const FULL_R: usize = 1;

type Evaluated = (Point, Model, liu2021::HbmResponse, liu2021::HbmResponse);

fn evaluate(x: f64, p: &Parameters) -> Result<Evaluated, Error> {
    let m = model(p)?;
    let ti = liu2021::integrate(&m, &IntegrationOptions::default()).context("integration")?;
    let paper = HbmOptions::default();
    let cold = liu2021::solve_hbm_with(&m, &paper, HbmStart::Cold).context("hbm cold")?;
    let warm =
        liu2021::solve_hbm_with(&m, &paper, HbmStart::FromTimeResponse(&ti)).context("hbm warm")?;
    let full = liu2021::solve_hbm_with(
        &m,
        &HbmOptions::full(&m, FULL_R),
        HbmStart::FromTimeResponse(&ti),
    )
    .context("hbm full")?;
    Ok((
        Point {
            x,
            rsv_time: ti.rattle.state.rsv(),
            ppv_time: ti.rattle.ppv,
            cold: Hb::of(&cold),
            warm: Hb::of(&warm),
            full: Hb::of(&full),
        },
        m,
        warm,
        full,
    ))
}

/// Sequential continuation along the sweep for the points where the warm start from the time
/// response did not converge: start from a converged neighbour (`HbmStart::Given`), sweeping
/// up and down until nothing changes (at most 4 passes). Sequential, so bit-identical for any
/// thread count.
fn fill_from_neighbours(
    models: &[Model],
    sols: &mut [liu2021::HbmResponse],
    hb: &mut [Hb],
    options: impl Fn(&Model) -> HbmOptions,
) -> Result<(), Error> {
    let n = sols.len();
    for pass in 0..4 {
        let mut changed = false;
        let order: Vec<usize> = if pass % 2 == 0 {
            (1..n).collect()
        } else {
            (0..n.saturating_sub(1)).rev().collect()
        };
        for i in order {
            let j = if pass % 2 == 0 { i - 1 } else { i + 1 };
            if sols[i].converged() || !sols[j].converged() {
                continue;
            }
            let m = &models[i];
            let r = liu2021::solve_hbm_with(m, &options(m), HbmStart::Given(&sols[j]))
                .context("hbm from neighbour")?;
            if r.converged() {
                hb[i] = Hb {
                    from_neighbour: true,
                    ..Hb::of(&r)
                };
                sols[i] = r;
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    Ok(())
}

/// The three HBM columns: (label, accessor).
/// Accessor of one HBM column of a [`Point`].
type HbKind = fn(&Point) -> Hb;

const HBM_KINDS: [(&str, HbKind); 3] = [
    ("HBM paper basis, cold start", |p| p.cold),
    ("HBM paper basis, warm start", |p| p.warm),
    ("HBM full basis K=65, warm start", |p| p.full),
];

/// First x where the converged HBM result of `kind` has rsv ≥ `rsv`.
fn first_hbm_at_least(pts: &[Point], kind: HbKind, rsv: u8) -> f64 {
    pts.iter()
        .find(|p| kind(p).converged && kind(p).rsv >= rsv)
        .map_or(f64::NAN, |p| p.x)
}

/// "n/N converged (m via a neighbour)".
fn converged_note(pts: &[Point], kind: HbKind) -> String {
    let n = pts.iter().filter(|p| kind(p).converged).count();
    let m = pts.iter().filter(|p| kind(p).from_neighbour).count();
    let u = pts.iter().filter(|p| kind(p).stable == Some(false)).count();
    format!(
        "{n}/{} converged, {m} of them via a neighbour, {u} unstable",
        pts.len()
    )
}

fn sweep(xs: &[f64], set: impl Fn(&mut Parameters, f64) + Sync) -> Result<Vec<Point>, Error> {
    let raw: Vec<Evaluated> = xs
        .par_iter()
        .map(|&x| {
            let mut p = base();
            set(&mut p, x);
            evaluate(x, &p)
        })
        .collect::<Result<_, Error>>()?;
    let mut pts: Vec<Point> = raw.iter().map(|r| r.0).collect();
    let models: Vec<Model> = raw.iter().map(|r| r.1).collect();
    let (mut warm, mut full): (Vec<_>, Vec<_>) = raw.into_iter().map(|r| (r.2, r.3)).unzip();
    let mut hb: Vec<Hb> = pts.iter().map(|p| p.warm).collect();
    fill_from_neighbours(&models, &mut warm, &mut hb, |_| HbmOptions::default())?;
    for (p, h) in pts.iter_mut().zip(&hb) {
        p.warm = *h;
    }
    let mut hb: Vec<Hb> = pts.iter().map(|p| p.full).collect();
    fill_from_neighbours(&models, &mut full, &mut hb, |m| HbmOptions::full(m, FULL_R))?;
    for (p, h) in pts.iter_mut().zip(&hb) {
        p.full = *h;
    }
    // stability of the converged warm/full solutions (three short integrations each)
    let stab = |m: &Model, r: &liu2021::HbmResponse| -> Result<Option<bool>, Error> {
        if !r.converged() {
            return Ok(None);
        }
        let mu = liu2021::shooting_multipliers(m, r).context("stability")?;
        let max = mu.iter().map(|z| z[0].hypot(z[1])).fold(0.0, f64::max);
        Ok(Some(max <= 1.0 + hbm::STABILITY_TOLERANCE))
    };
    let flags: Vec<(Option<bool>, Option<bool>)> = (0..pts.len())
        .into_par_iter()
        .map(|i| Ok((stab(&models[i], &warm[i])?, stab(&models[i], &full[i])?)))
        .collect::<Result<_, Error>>()?;
    for (p, (w, f)) in pts.iter_mut().zip(flags) {
        p.warm.stable = w;
        p.full.stable = f;
    }
    Ok(pts)
}

fn sweep_table(name: &str, x: (&str, &str), pts: &[Point]) -> Result<Table, Error> {
    let mut t = Table::new(
        name,
        &[
            x,
            ("rsv_time", "1"),
            ("ppv_time", "1"),
            ("rsv_hbm", "1"),
            ("ppv_hbm", "1"),
            ("hbm_converged", "1"),
            ("rsv_hbm_warm", "1"),
            ("ppv_hbm_warm", "1"),
            ("hbm_warm_converged", "1"),
            ("hbm_warm_stable", "1"),
            ("rsv_hbm_full", "1"),
            ("ppv_hbm_full", "1"),
            ("hbm_full_converged", "1"),
            ("hbm_full_stable", "1"),
        ],
    );
    let flag = |b: bool| if b { 1.0 } else { 0.0 };
    for p in pts {
        t.push_nums(&[
            p.x,
            f64::from(p.rsv_time),
            p.ppv_time,
            f64::from(p.cold.rsv),
            p.cold.ppv,
            flag(p.cold.converged),
            f64::from(p.warm.rsv),
            p.warm.ppv,
            flag(p.warm.converged),
            p.warm.stable.map_or(f64::NAN, flag),
            f64::from(p.full.rsv),
            p.full.ppv,
            flag(p.full.converged),
            p.full.stable.map_or(f64::NAN, flag),
        ])?;
    }
    Ok(t)
}

fn sweep_figures(out: &mut StudyOutput, name: &str, x: (&str, &str), pts: &[Point]) {
    let s = |f: &dyn Fn(&Point) -> f64| pts.iter().map(|p| (p.x, f(p))).collect::<Vec<_>>();
    let mut rsv = Figure::new(&format!("{name}_rsv"), "Rattle state", x, ("rsv", "1")).with(
        Series::step("time integration", s(&|p| f64::from(p.rsv_time))),
    );
    let mut ppv = Figure::new(
        &format!("{name}_ppv"),
        "Peak-to-peak value of q",
        x,
        ("ppv", "1"),
    )
    .with(Series::line("time integration", s(&|p| p.ppv_time)));
    for (label, kind) in HBM_KINDS {
        rsv = rsv.with(Series::markers(label, s(&|p| f64::from(kind(p).rsv))));
        ppv = ppv.with(Series::markers(label, s(&|p| kind(p).ppv)));
    }
    out.figure(rsv);
    out.figure(ppv);
}

fn first_at_least(pts: &[Point], rsv: u8) -> f64 {
    pts.iter()
        .find(|p| p.rsv_time >= rsv)
        .map_or(f64::NAN, |p| p.x)
}

fn table2_ratio() -> Result<StudyOutput, Error> {
    let paper = published!("liu2021.toml")?;
    let rig = LiuRig::liu2021_table2();
    let mut out = StudyOutput::new();
    let rpms: Vec<(String, f64)> = paper
        .values_with_prefix("table2.rpm.")
        .map(|v| (v.id.trim_start_matches("table2.rpm.").to_owned(), v.value))
        .collect();
    let z2 = f64::from(rig.z2);
    let ratios: Vec<(f64, f64, bool, u8)> = rpms
        .par_iter()
        .map(|(_, n)| {
            let mut p = base();
            p.load_torque = 3.0;
            p.ratio = z2 / f64::from(rig.z1);
            p.omega1 = rig.pinion_angular_speed(*n);
            let m = model(&p)?;
            let hb = liu2021::solve_hbm(&m, &HbmOptions::default(), None).context("hbm")?;
            let disp = hb.amplitude(m.z2 as usize) / hb.amplitude(1);
            Ok((*n, disp, hb.converged(), hb.rattle.state.rsv()))
        })
        .collect::<Result<_, Error>>()?;
    let mut t = Table::new(
        "ratios",
        &[
            ("n_motor", "rpm"),
            ("xi_theory_paper", "1"),
            ("xi_experiment_paper", "1"),
            ("ratio_displacement_model", "1"),
            ("ratio_velocity_model", "1"),
            ("ratio_acceleration_model", "1"),
            ("rsv_model", "1"),
            ("hbm_converged", "1"),
        ],
    );
    let mut model_pts = Vec::new();
    let mut th_pts = Vec::new();
    let mut ex_pts = Vec::new();
    for ((key, _), &(n, disp, conv, rsv)) in rpms.iter().zip(&ratios) {
        let th = paper.value(&format!("table2.theory.xi.{key}"))?;
        let ex = paper.value(&format!("table2.experiment.xi.{key}"))?;
        let vel = disp * z2;
        out.compare(
            Comparison::published(th, vel)?
                .reading("R-LIU-TABLE2")
                .note("model: velocity-spectrum ratio A(f_e)/A(f_c), HBM paper basis"),
        );
        out.compare(
            Comparison::published(ex, vel)?
                .reading("R-LIU-TABLE2")
                .note("model: velocity-spectrum ratio A(f_e)/A(f_c), HBM paper basis"),
        );
        t.push_nums(&[
            n,
            th.value,
            ex.value,
            disp,
            vel,
            disp * z2 * z2,
            f64::from(rsv),
            if conv { 1.0 } else { 0.0 },
        ])?;
        model_pts.push((n, vel));
        th_pts.push((n, th.value));
        ex_pts.push((n, ex.value));
    }
    let increasing = ratios.windows(2).all(|w| w[1].1 > w[0].1);
    out.claim(Claim::new(
        "The theoretical amplitude ratio ξ grows with the motor speed (48.6 → 59.1).",
        "Table 2",
        format!(
            "model displacement ratio {} → {} ({})",
            sig(ratios.first().map_or(f64::NAN, |r| r.1)),
            sig(ratios.last().map_or(f64::NAN, |r| r.1)),
            if increasing {
                "monotone increasing"
            } else {
                "not monotone"
            }
        ),
        Verdict::from_bool(increasing),
    ));
    out.table(t);
    out.figure(
        Figure::new(
            "xi",
            "Amplitude ratio ξ = A_e/A_c",
            ("n_motor", "rpm"),
            ("xi", "1"),
        )
        .with(Series::markers("paper theory", th_pts))
        .with(Series::markers("paper experiment", ex_pts))
        .with(Series::line("model (velocity ratio)", model_pts)),
    );
    Ok(out)
}

fn speed_sweep() -> Result<StudyOutput, Error> {
    let paper = published!("liu2021.toml")?;
    let xs: Vec<f64> = (0..=60).map(|i| 100.0 + 2.5 * f64::from(i)).collect();
    let pts = sweep(&xs, |p, x| p.omega1 = x)?;
    let mut out = StudyOutput::new();
    let tol = || {
        Tolerance::stated(
            ToleranceBand::Absolute(5.0),
            "round number in the text; half its 10 rad/s resolution",
        )
    };
    let uni = first_at_least(&pts, 1);
    let bi = first_at_least(&pts, 2);
    out.compare(
        Comparison::published(paper.value("sect34.unilateral-onset")?, uni)?
            .with_tolerance(tol())
            .reading("R-LIU-EQ11")
            .note("first ω1 with rsv ≥ 1, time integration, 2.5 rad/s grid"),
    );
    out.compare(
        Comparison::published(paper.value("sect34.bilateral-onset")?, bi)?
            .with_tolerance(tol())
            .reading("R-LIU-EQ11")
            .note("first ω1 with rsv = 2, time integration, 2.5 rad/s grid"),
    );
    for (label, kind) in HBM_KINDS {
        let n_conv = converged_note(&pts, kind);
        out.compare(
            Comparison::published(
                paper.value("sect34.unilateral-onset")?,
                first_hbm_at_least(&pts, kind, 1),
            )?
            .with_tolerance(tol())
            .reading("R-LIU-HBM")
            .note(&format!(
                "first converged ω1 with rsv ≥ 1, {label} ({n_conv})"
            )),
        );
        out.compare(
            Comparison::published(
                paper.value("sect34.bilateral-onset")?,
                first_hbm_at_least(&pts, kind, 2),
            )?
            .with_tolerance(tol())
            .reading("R-LIU-HBM")
            .note(&format!(
                "first converged ω1 with rsv = 2, {label} (NaN: none; {n_conv})"
            )),
        );
    }
    // ppv jump at the onset of bilateral rattle
    let jump = pts
        .windows(2)
        .find(|w| w[0].rsv_time < 2 && w[1].rsv_time == 2)
        .map(|w| (w[0].x, w[0].ppv_time, w[1].x, w[1].ppv_time));
    let (evidence, ok) = match jump {
        Some((x0, p0, x1, p1)) => (
            format!(
                "ppv {} at {} rad/s → {} at {} rad/s (×{})",
                sig(p0),
                sig(x0),
                sig(p1),
                sig(x1),
                sig(p1 / p0)
            ),
            p1 > 3.0 * p0,
        ),
        None => (
            "no onset of bilateral rattle in the sweep".to_owned(),
            false,
        ),
    };
    out.claim(Claim::new(
        "At the start of the bilateral rattle, a sudden increase occurs in the curve of ppv.",
        "Sect. 3.3, Fig. 11b",
        evidence,
        Verdict::from_bool(ok),
    ));
    let order_ok = uni.is_finite() && bi.is_finite() && uni < bi;
    out.claim(Claim::new(
        "With increasing ω1 the NFG passes through no rattle, unilateral and bilateral rattle.",
        "Sect. 3.3, Fig. 11a",
        format!(
            "time integration: unilateral from {} rad/s, bilateral from {} rad/s",
            sig(uni),
            sig(bi)
        ),
        Verdict::from_bool(order_ok),
    ));
    out.table(sweep_table("sweep", ("omega1", "rad/s"), &pts)?);
    sweep_figures(&mut out, "omega1", ("omega1", "rad/s"), &pts);
    Ok(out)
}

fn responses() -> Result<StudyOutput, Error> {
    let mut out = StudyOutput::new();
    let cases = [
        (160.0, RattleState::Unilateral, "Fig. 8"),
        (140.0, RattleState::NoRattle, "Fig. 9"),
        (180.0, RattleState::Bilateral, "Fig. 10"),
    ];
    let results: Vec<_> = cases
        .par_iter()
        .map(|&(w, _, _)| {
            let mut p = base();
            p.omega1 = w;
            let m = model(&p)?;
            let opts = IntegrationOptions {
                sample_step: m.period() / SPECTRUM_SAMPLES as f64,
                ..IntegrationOptions::default()
            };
            let ti = liu2021::integrate(&m, &opts).context("integration")?;
            let hb = liu2021::solve_hbm(&m, &HbmOptions::default(), None).context("hbm")?;
            let n = SPECTRUM_SAMPLES.min(ti.q.len());
            let sp =
                timestep::amplitude_spectrum(&ti.q[..n], opts.sample_step).context("spectrum")?;
            Ok((ti, hb, sp, m))
        })
        .collect::<Result<_, Error>>()?;
    let label = |s: RattleState| match s {
        RattleState::NoRattle => "no rattle",
        RattleState::Unilateral => "unilateral",
        RattleState::Bilateral => "bilateral",
    };
    spectrum_outputs(&mut out, &cases, &results)?;
    for (&(w, expected, fig), (ti, hb, _, m)) in cases.iter().zip(&results) {
        let full = liu2021::solve_hbm_with(
            m,
            &HbmOptions::full(m, FULL_R),
            HbmStart::FromTimeResponse(ti),
        )
        .context("hbm full")?;
        out.claim(Claim::new(
            &format!("At ω1 = {w} rad/s the NFG shows {}.", label(expected)),
            &format!("Sect. 3.2, {fig}"),
            format!(
                "time integration: {} (ppv {}); HBM paper basis, cold: {} (ppv {}, converged {}); HBM K = 65 from the time response: {} (ppv {}, converged {})",
                label(ti.rattle.state),
                sig(ti.rattle.ppv),
                label(hb.rattle.state),
                sig(hb.rattle.ppv),
                hb.converged(),
                label(full.rattle.state),
                sig(full.rattle.ppv),
                full.converged()
            ),
            Verdict::from_bool(ti.rattle.state == expected),
        ));
        let step = (ti.tau.len() / 600).max(1);
        let pick = |v: &[f64]| -> Vec<(f64, f64)> {
            ti.tau
                .iter()
                .zip(v)
                .step_by(step)
                .map(|(&t, &q)| (t - ti.tau[0], q))
                .collect()
        };
        let hbm_q: Vec<(f64, f64)> = ti
            .tau
            .iter()
            .step_by(step)
            .map(|&t| (t - ti.tau[0], hb.eval(t)))
            .collect();
        out.figure(
            Figure::new(
                &format!("time_{w}"),
                &format!("q(τ), ω1 = {w} rad/s"),
                ("tau", "1"),
                ("q", "1"),
            )
            .with(Series::line("time integration", pick(&ti.q)))
            .with(Series::line("HBM paper basis", hbm_q)),
        );
        let phase: Vec<(f64, f64)> =
            ti.q.iter()
                .zip(&ti.v)
                .step_by(step)
                .map(|(&q, &v)| (q, v))
                .collect();
        out.figure(
            Figure::new(
                &format!("phase_{w}"),
                &format!("Phase portrait, ω1 = {w} rad/s"),
                ("q", "1"),
                ("dq/dtau", "1"),
            )
            .with(Series::line("time integration", phase)),
        );
    }
    Ok(out)
}

/// Samples per period for the spectra of Fig. 8c–10c (bin k = harmonic k f_c, no leakage).
const SPECTRUM_SAMPLES: usize = 8192;

type Response = (
    liu2021::TimeResponse,
    liu2021::HbmResponse,
    timestep::Spectrum,
    Model,
);

/// Spectrum figures, table and claims of Fig. 8c–10c.
fn spectrum_outputs(
    out: &mut StudyOutput,
    cases: &[(f64, RattleState, &str); 3],
    results: &[Response],
) -> Result<(), Error> {
    let mut t = Table::new(
        "spectrum_peaks",
        &[
            ("omega1", "rad/s"),
            ("f_c", "Hz"),
            ("f_e", "Hz"),
            ("A_fc", "1"),
            ("A_2fc", "1"),
            ("A_fe", "1"),
            ("A_fe_minus_fc", "1"),
            ("A_fe_plus_fc", "1"),
            ("A_2fe", "1"),
            ("rank_fc", "1"),
            ("rank_fe", "1"),
        ],
    );
    let mut amps = Vec::new();
    for (&(w, _, fig), (_, hb, sp, m)) in cases.iter().zip(results) {
        let z2 = m.z2 as usize;
        let kmax = (2 * z2 + 4).min(sp.amplitude.len() - 1);
        // physical frequency of harmonic k: k ω̄_c ω_n / 2π = k ω_c / 2π
        let fc = m.omega_c * m.omega_n / (2.0 * std::f64::consts::PI);
        let a = |k: usize| sp.amplitude.get(k).copied().unwrap_or(f64::NAN);
        // rank among the non-DC harmonics 1..=kmax (1 = largest)
        let rank = |k: usize| 1 + (1..=kmax).filter(|&j| a(j) > a(k)).count();
        let (r1, re) = (rank(1), rank(z2));
        t.push_nums(&[
            w,
            fc,
            fc * z2 as f64,
            a(1),
            a(2),
            a(z2),
            a(z2 - 1),
            a(z2 + 1),
            a(2 * z2),
            r1 as f64,
            re as f64,
        ])?;
        let mut top: Vec<usize> = (1..=kmax).collect();
        top.sort_by(|&i, &j| a(j).total_cmp(&a(i)));
        let top_txt = top
            .iter()
            .take(4)
            .map(|&k| format!("k={k} ({} Hz): {}", sig(k as f64 * fc), sig(a(k))))
            .collect::<Vec<_>>()
            .join(", ");
        if fig == "Fig. 8" {
            out.claim(Claim::new(
                "The amplitudes at the instantaneous-centre frequency f_c and the mesh frequency f_e are relatively large (they dominate the spectrum).",
                "Sect. 3.2, Fig. 8c",
                format!(
                    "ω1 = {w}: f_c = {} Hz ranks {r1}, f_e = {} Hz ranks {re} among harmonics 1–{kmax}; largest: {top_txt}",
                    sig(fc),
                    sig(fc * z2 as f64)
                ),
                Verdict::from_bool(r1 <= 3 && re <= 3),
            ));
        }
        amps.push((a(1), a(z2)));
        let spec: Vec<(f64, f64)> = (1..=kmax).map(|k| (k as f64 * fc, a(k))).collect();
        let hbm_pts: Vec<(f64, f64)> = hb
            .solution
            .basis
            .harmonics()
            .iter()
            .map(|&k| (k as f64 * fc, hb.amplitude(k)))
            .collect();
        out.figure(
            Figure::new(
                &format!("spectrum_{w}"),
                &format!("Amplitude spectrum of q, ω1 = {w} rad/s"),
                ("f", "Hz"),
                ("amplitude", "1"),
            )
            .with(Series::markers("time integration (one period)", spec))
            .with(Series::markers("HBM paper basis", hbm_pts)),
        );
    }
    out.table(t);
    if let [(c160, e160), (c140, e140), (c180, e180)] = amps[..] {
        out.claim(Claim::new(
            "At ω1 = 140 rad/s the amplitudes at each frequency all reduce slightly (against 160 rad/s).",
            "Sect. 3.2, Fig. 9c",
            format!(
                "A(f_c) {} → {}, A(f_e) {} → {} (160 → 140 rad/s)",
                sig(c160),
                sig(c140),
                sig(e160),
                sig(e140)
            ),
            Verdict::from_bool(c140 < c160 && e140 < e160),
        ));
        out.claim(Claim::new(
            "At ω1 = 180 rad/s the amplitude of each excitation frequency increases greatly (bilateral rattle).",
            "Sect. 3.2, Fig. 10c",
            format!(
                "A(f_c) {} → {} (×{}), A(f_e) {} → {} (×{}) from 160 to 180 rad/s; 'greatly' read as ×2",
                sig(c160),
                sig(c180),
                sig(c180 / c160),
                sig(e160),
                sig(e180),
                sig(e180 / e160)
            ),
            Verdict::from_bool(c180 > 2.0 * c160 && e180 > 2.0 * e160),
        ));
    }
    Ok(())
}

/// Spacing in ω1 \[rad/s\] of the branch points whose stability is computed.
const STABILITY_SPACING: f64 = 2.0;

fn speed_continuation() -> Result<StudyOutput, Error> {
    let paper = published!("liu2021.toml")?;
    let runs: [(&str, f64, f64, bool); 3] = [
        ("paper basis from 250", 250.0, 100.0, false),
        ("full K=65 from 250", 250.0, 100.0, true),
        ("full K=65 from 150", 150.0, 250.0, true),
    ];
    let branches: Vec<SpeedBranch> = runs
        .par_iter()
        .map(|&(_, w0, w1, full)| {
            let mut p = base();
            p.omega1 = w0;
            let m = model(&p)?;
            let ti =
                liu2021::integrate(&m, &IntegrationOptions::default()).context("integration")?;
            let hbm = if full {
                HbmOptions::full(&m, FULL_R)
            } else {
                HbmOptions::default()
            };
            let o = SpeedContinuationOptions {
                hbm,
                omega1_end: w1,
                max_points: 800,
                stability: BranchStability::None,
                ..SpeedContinuationOptions::default()
            };
            liu2021::continue_in_speed(&p, &o, HbmStart::FromTimeResponse(&ti))
                .context("continuation")
        })
        .collect::<Result<_, Error>>()?;
    // Stability (period-map multipliers, three integrations each) on a thinned subset: points at
    // least STABILITY_SPACING rad/s apart along the branch, in parallel, in input order.
    let branches: Vec<SpeedBranch> = branches
        .into_iter()
        .map(|mut b| {
            let mut last = f64::NAN;
            let picked: Vec<usize> = (0..b.points.len())
                .filter(|&i| {
                    let w = b.points[i].omega1;
                    let take = last.is_nan() || (w - last).abs() >= STABILITY_SPACING;
                    if take {
                        last = w;
                    }
                    take
                })
                .collect();
            let base_model = model(&base())?;
            let to_wc = base_model.omega_c / base().omega1;
            let mus: Vec<f64> = picked
                .par_iter()
                .map(|&i| {
                    let pt = &b.points[i];
                    let m = base_model
                        .with_omega_c(pt.omega1 * to_wc)
                        .context("model")?;
                    let r = liu2021::HbmResponse {
                        solution: pt.solution.clone(),
                        rattle: pt.rattle,
                    };
                    let mu = liu2021::shooting_multipliers(&m, &r).context("stability")?;
                    Ok(mu.iter().map(|z| z[0].hypot(z[1])).fold(0.0, f64::max))
                })
                .collect::<Result<_, Error>>()?;
            for (&i, &mu) in picked.iter().zip(&mus) {
                b.points[i].max_multiplier = Some(mu);
                b.points[i].stable = Some(mu <= 1.0 + hbm::STABILITY_TOLERANCE);
            }
            Ok(b)
        })
        .collect::<Result<_, Error>>()?;
    let xs: Vec<f64> = (0..=30).map(|i| 100.0 + 5.0 * f64::from(i)).collect();
    let ti: Vec<(f64, u8, f64)> = xs
        .par_iter()
        .map(|&x| {
            let mut p = base();
            p.omega1 = x;
            let m = model(&p)?;
            let r =
                liu2021::integrate(&m, &IntegrationOptions::default()).context("integration")?;
            Ok((x, r.rattle.state.rsv(), r.rattle.ppv))
        })
        .collect::<Result<_, Error>>()?;
    let mut out = StudyOutput::new();
    let mut t = Table::new(
        "branches",
        &[
            ("branch", "-"),
            ("omega1", "rad/s"),
            ("rsv", "1"),
            ("ppv", "1"),
            ("stable", "1"),
            ("max_multiplier", "1"),
        ],
    );
    let mut runs_t = Table::new(
        "runs",
        &[
            ("branch", "-"),
            ("points", "1"),
            ("folds_omega1", "rad/s"),
            ("end", "-"),
        ],
    );
    let mut fig = Figure::new(
        "ppv",
        "ppv along the continued branches (stable/unstable by period-map multipliers)",
        ("omega1", "rad/s"),
        ("ppv", "1"),
    );
    for (j, ((label, ..), b)) in runs.iter().zip(&branches).enumerate() {
        let mut pts = Vec::new();
        for p in &b.points {
            t.push(vec![
                (*label).into(),
                p.omega1.into(),
                f64::from(p.rattle.state.rsv()).into(),
                p.rattle.ppv.into(),
                p.stable
                    .map_or(f64::NAN, |s| if s { 1.0 } else { 0.0 })
                    .into(),
                p.max_multiplier.unwrap_or(f64::NAN).into(),
            ])?;
            pts.push((p.omega1, p.rattle.ppv, p.stable));
        }
        runs_t.push(vec![
            (*label).into(),
            (b.points.len() as f64).into(),
            b.folds
                .iter()
                .map(|f| sig(f.omega1))
                .collect::<Vec<_>>()
                .join(" ")
                .into(),
            format!("{:?}", b.end).into(),
        ])?;
        // a fold lies between two points: mark it at the fitted ω₁ and their mean ppv
        let folds = b
            .folds
            .iter()
            .filter_map(|f| {
                let (a, c) = (
                    b.points.get(f.after_index)?,
                    b.points.get(f.after_index + 1)?,
                );
                Some((f.omega1, 0.5 * (a.rattle.ppv + c.rattle.ppv)))
            })
            .collect();
        fig = fig.branch(label, j, &pts, folds);
    }
    fig = fig.with(
        Series::markers(
            "time integration from rest",
            ti.iter().map(|&(x, _, p)| (x, p)).collect(),
        )
        .colour(6), // black: the branches take 0..3
    );
    let ti_onset = ti.iter().find(|p| p.1 == 2).map_or(f64::NAN, |p| p.0);
    let tol = || {
        Tolerance::stated(
            ToleranceBand::Absolute(5.0),
            "round number in the text; half its 10 rad/s resolution",
        )
    };
    let mut evidence = Vec::new();
    let mut ok = false;
    for ((label, ..), b) in runs.iter().zip(&branches) {
        // the jump-up point: the highest fold on the unilateral/no-rattle part of the branch
        let fold_max = b
            .folds
            .iter()
            .filter(|f| {
                b.points
                    .get(f.after_index)
                    .is_some_and(|p| p.rattle.state != RattleState::Bilateral)
            })
            .map(|f| f.omega1)
            .fold(f64::NAN, f64::max);
        let bi_min = b
            .points
            .iter()
            .filter(|p| p.rattle.state == RattleState::Bilateral)
            .map(|p| p.omega1)
            .fold(f64::NAN, f64::min);
        evidence.push(format!(
            "{label}: folds at [{}] rad/s (jump-up fold of the rattle-free/unilateral part {}), bilateral points down to {} rad/s, end {:?}",
            b.folds
                .iter()
                .map(|f| sig(f.omega1))
                .collect::<Vec<_>>()
                .join(", "),
            sig(fold_max),
            sig(bi_min),
            b.end
        ));
        if fold_max.is_finite() {
            out.compare(
                Comparison::published(paper.value("sect34.bilateral-onset")?, fold_max)?
                    .with_tolerance(tol())
                    .reading("R-LIU-HBM")
                    .note(&format!(
                        "{label}: fold (jump point) of the unilateral branch, pseudo-arclength"
                    )),
            );
        }
        if *label == "paper basis from 250" {
            ok = fold_max.is_finite() && bi_min < ti_onset && ti_onset <= fold_max + 5.0;
        }
    }
    out.claim(Claim::new(
        "At the start of the bilateral rattle, a sudden increase occurs in the curve of ppv (jump phenomenon).",
        "Sect. 3.3, Fig. 11b",
        format!(
            "{}; time integration from rest: bilateral from {} rad/s (5 rad/s grid). Pass: the paper-basis branch folds and the time-integration onset lies inside its coexistence range.",
            evidence.join("; "),
            sig(ti_onset)
        ),
        Verdict::from_bool(ok),
    ));
    out.table(t);
    out.table(runs_t);
    out.figure(fig);
    Ok(out)
}

fn load_sweep() -> Result<StudyOutput, Error> {
    let paper = published!("liu2021.toml")?;
    let xs: Vec<f64> = (0..=40).map(f64::from).collect();
    let pts = sweep(&xs, |p, x| p.load_torque = x)?;
    let mut out = StudyOutput::new();
    let tol = || Tolerance::stated(ToleranceBand::Absolute(2.0), "round number in the text");
    // first torque above which rattle is no longer bilateral / no rattle at all (time integration)
    let first_not_bi = pts
        .iter()
        .find(|p| p.rsv_time < 2)
        .map_or(f64::NAN, |p| p.x);
    let first_none = pts
        .iter()
        .find(|p| p.rsv_time == 0)
        .map_or(f64::NAN, |p| p.x);
    out.compare(
        Comparison::published(paper.value("sect37.t2-bilateral-below")?, first_not_bi)?
            .with_tolerance(tol())
            .reading("R-LIU-FIG15")
            .note("first T2 with rsv < 2, time integration (NaN: none up to 40 N·m)"),
    );
    out.compare(
        Comparison::published(paper.value("sect37.t2-no-rattle-from")?, first_none)?
            .with_tolerance(tol())
            .reading("R-LIU-FIG15")
            .note("first T2 with rsv = 0, time integration (NaN: none up to 40 N·m)"),
    );
    for (label, kind) in HBM_KINDS {
        let n_conv = converged_note(&pts, kind);
        let not_bi = pts
            .iter()
            .find(|p| kind(p).converged && kind(p).rsv < 2)
            .map_or(f64::NAN, |p| p.x);
        let none = pts
            .iter()
            .find(|p| kind(p).converged && kind(p).rsv == 0)
            .map_or(f64::NAN, |p| p.x);
        out.compare(
            Comparison::published(paper.value("sect37.t2-bilateral-below")?, not_bi)?
                .with_tolerance(tol())
                .reading("R-LIU-HBM")
                .note(&format!(
                    "first converged T2 with rsv < 2, {label} ({n_conv})"
                )),
        );
        out.compare(
            Comparison::published(paper.value("sect37.t2-no-rattle-from")?, none)?
                .with_tolerance(tol())
                .reading("R-LIU-HBM")
                .note(&format!(
                    "first converged T2 with rsv = 0, {label} ({n_conv})"
                )),
        );
    }
    let drop = pts
        .windows(2)
        .find(|w| w[0].rsv_time == 2 && w[1].rsv_time < 2)
        .map(|w| (w[0].ppv_time, w[1].ppv_time, w[1].x));
    let (evidence, ok) = match drop {
        Some((p0, p1, x)) => (
            format!(
                "ppv {} → {} at T2 = {} N·m (×{})",
                sig(p0),
                sig(p1),
                sig(x),
                sig(p1 / p0)
            ),
            p1 < p0 / 3.0,
        ),
        None => (
            "no bilateral → unilateral transition in 0–40 N·m".to_owned(),
            false,
        ),
    };
    out.claim(Claim::new(
        "When the vibration state changes from the bilateral to the unilateral rattle, the amplitude of ppv drops sharply.",
        "Sect. 3.7, Fig. 15b",
        evidence,
        Verdict::from_bool(ok),
    ));
    out.table(sweep_table("sweep", ("T2", "N m"), &pts)?);
    sweep_figures(&mut out, "t2", ("T2", "N m"), &pts);
    Ok(out)
}

/// Claim that the time-integration states are non-decreasing and pass through all three.
fn succession_claim(out: &mut StudyOutput, text: &str, source: &str, unit: &str, pts: &[Point]) {
    let monotone = pts.windows(2).all(|w| w[1].rsv_time >= w[0].rsv_time);
    let uni = first_at_least(pts, 1);
    let bi = first_at_least(pts, 2);
    let all = pts.first().is_some_and(|p| p.rsv_time == 0) && bi.is_finite();
    out.claim(Claim::new(
        text,
        source,
        format!(
            "time integration: unilateral from {} {unit}, bilateral from {} {unit}; states {}",
            sig(uni),
            sig(bi),
            if monotone {
                "non-decreasing"
            } else {
                "not monotone (coexisting responses)"
            }
        ),
        Verdict::from_bool(all),
    ));
    let jump = pts
        .windows(2)
        .find(|w| w[0].rsv_time < 2 && w[1].rsv_time == 2)
        .map(|w| w[1].ppv_time / w[0].ppv_time);
    out.claim(Claim::new(
        "As the bilateral rattle arises, ppv increases suddenly.",
        source,
        jump.map_or("no onset of bilateral rattle".to_owned(), |r| {
            format!("ppv ratio across the onset ×{}", sig(r))
        }),
        Verdict::from_bool(jump.is_some_and(|r| r > 3.0)),
    ));
}

fn parameter_sweeps() -> Result<StudyOutput, Error> {
    let mut out = StudyOutput::new();
    let er: Vec<f64> = (0..=40).map(|i| 1e-6 * f64::from(i)).collect();
    let pts = sweep(&er, |p, x| p.er = x)?;
    succession_claim(
        &mut out,
        "As e_r increases, the NFG undergoes non-rattle, unilateral rattle and bilateral rattle in succession.",
        "Sect. 3.4, Fig. 12",
        "m",
        &pts,
    );
    out.table(sweep_table("er", ("e_r", "m"), &pts)?);
    sweep_figures(&mut out, "er", ("e_r", "m"), &pts);

    let eps: Vec<f64> = (0..=30).map(|i| 0.01 * f64::from(i)).collect();
    let pts = sweep(&eps, |p, x| p.eccentricity = x)?;
    succession_claim(
        &mut out,
        "The NFG also undergoes the three rattle states with the increase in eccentric ratio.",
        "Sect. 3.5, Fig. 13",
        "",
        &pts,
    );
    out.table(sweep_table("eps", ("epsilon", "1"), &pts)?);
    sweep_figures(&mut out, "eps", ("epsilon", "1"), &pts);

    let ak: Vec<f64> = (1..=16).map(|i| 0.05 * f64::from(i)).collect();
    for (w, expected) in [(160.0, 1u8), (140.0, 0u8)] {
        let pts = sweep(&ak, |p, x| {
            p.omega1 = w;
            p.kr = x * p.k0;
        })?;
        let states: Vec<u8> = pts.iter().map(|p| p.rsv_time).collect();
        let same = states.iter().all(|&s| s == expected);
        let ppv_up = pts.last().map_or(f64::NAN, |p| p.ppv_time)
            > pts.first().map_or(f64::NAN, |p| p.ppv_time);
        out.claim(Claim::new(
            &format!(
                "At ω1 = {w} rad/s the rattle state stays {} for a_k = 0.1–0.8.",
                if expected == 1 {
                    "unilateral"
                } else {
                    "non-rattle"
                }
            ),
            "Sect. 3.6, Fig. 14a",
            format!("time-integration rsv over a_k = 0.05…0.8: {states:?}"),
            Verdict::from_bool(same),
        ));
        out.claim(Claim::new(
            &format!("At ω1 = {w} rad/s ppv rises as a_k increases."),
            "Sect. 3.6, Fig. 14b",
            format!(
                "time-integration ppv {} at a_k = 0.05 → {} at 0.8",
                sig(pts.first().map_or(f64::NAN, |p| p.ppv_time)),
                sig(pts.last().map_or(f64::NAN, |p| p.ppv_time))
            ),
            Verdict::from_bool(ppv_up),
        ));
        let name = format!("ak_{w}");
        out.table(sweep_table(&name, ("a_k", "1"), &pts)?);
        sweep_figures(&mut out, &name, ("a_k", "1"), &pts);
    }
    Ok(out)
}

fn readings_thresholds() -> Result<StudyOutput, Error> {
    let paper = published!("liu2021.toml")?;
    let mean = Readings {
        base_radius: BaseRadius::Mean,
        ..Readings::default()
    };
    let sets: [(&str, Readings, &str); 5] = [
        (
            "consistent (time-varying b̄)",
            Readings::default(),
            "R-LIU-EQ11",
        ),
        ("constant b̄", mean, "R-LIU-EQ11"),
        (
            "constant b̄, printed Eq. (21) sign",
            Readings {
                error_term: ErrorTerm::Printed,
                ..mean
            },
            "R-LIU-EQ21",
        ),
        (
            "constant b̄, printed Eq. (20)",
            Readings {
                rigid_acceleration: RigidAcceleration::PrintedEq20,
                ..mean
            },
            "R-LIU-EQ20",
        ),
        ("all as printed", Readings::printed(), "R-LIU-EQ20"),
    ];
    let xs: Vec<f64> = (0..=30).map(|i| 100.0 + 5.0 * f64::from(i)).collect();
    let mut out = StudyOutput::new();
    let mut t = Table::new(
        "thresholds",
        &[
            ("reading_set", "-"),
            ("unilateral_from", "rad/s"),
            ("bilateral_from", "rad/s"),
        ],
    );
    let tol = || {
        Tolerance::stated(
            ToleranceBand::Absolute(5.0),
            "round number in the text; half its 10 rad/s resolution",
        )
    };
    for (label, readings, id) in sets {
        let pts: Vec<Point> = xs
            .par_iter()
            .map(|&x| {
                let mut p = base();
                p.readings = readings;
                p.omega1 = x;
                let m = model(&p)?;
                let ti = liu2021::integrate(&m, &IntegrationOptions::default())
                    .context("integration")?;
                Ok(Point {
                    x,
                    rsv_time: ti.rattle.state.rsv(),
                    ppv_time: ti.rattle.ppv,
                    cold: Hb::NONE,
                    warm: Hb::NONE,
                    full: Hb::NONE,
                })
            })
            .collect::<Result<_, Error>>()?;
        let uni = first_at_least(&pts, 1);
        let bi = first_at_least(&pts, 2);
        out.compare(
            Comparison::published(paper.value("sect34.unilateral-onset")?, uni)?
                .with_tolerance(tol())
                .reading(id)
                .note(&format!(
                    "{label}: first ω1 with rsv ≥ 1 (time integration, step 5)"
                )),
        );
        out.compare(
            Comparison::published(paper.value("sect34.bilateral-onset")?, bi)?
                .with_tolerance(tol())
                .reading(id)
                .note(&format!(
                    "{label}: first ω1 with rsv = 2 (time integration, step 5)"
                )),
        );
        t.push(vec![label.into(), uni.into(), bi.into()])?;
    }
    out.table(t);
    Ok(out)
}
