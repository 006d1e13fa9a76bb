//! Fig. 11 by continuation: branches of periodic responses over ω1, folds and stability.

use math::DetMath;
use models::liu2021::{
    self, BranchStability, HbmOptions, HbmStart, IntegrationOptions, RattleState, SpeedBranch,
    SpeedContinuationOptions,
};

use super::{base, model, sig, speed_tolerance};
use crate::{
    Cell, Claim, Comparison, Cost, Error, Figure, Paper, ResultExt, Series, Study, StudyOutput,
    Table, Verdict, published,
};

pub(super) fn study() -> Study {
    Study {
        id: "liu2021-fig11-continuation",
        paper: Paper::Liu2021,
        source: "Fig. 11, Sect. 3.3",
        title: "Branches of periodic responses over ω1 by pseudo-arclength continuation",
        description: "Harmonic balance continued in ω1 (hbm pseudo-arclength) from the \
            bilateral response at 250 rad/s down to 100 rad/s on the paper basis, and on the \
            full basis K = 65 from 250 down and from 150 up. Folds (turning points) are the \
            jumps; stability from the multipliers of the time-integration period map at the HBM \
            state (policy: `models::liu2021::is_stable_multiplier`). Fold rows are HBM (shown); \
            the claim is judged: the jump of ppv at the bilateral onset is a fold (hysteresis), \
            with the time-integration onset inside the coexistence range.",
        cost: Cost::Heavy,
        run,
    }
}

/// Highest harmonic multiple of the full basis (K = Z2 + 2).
const FULL_R: usize = 1;

/// Spacing in ω1 \[rad/s\] of the branch points whose stability is computed.
const STABILITY_SPACING: f64 = 2.0;

fn run() -> Result<StudyOutput, Error> {
    let paper = published!("liu2021.toml")?;
    let runs: [(&str, f64, f64, bool); 3] = [
        ("paper basis from 250", 250.0, 100.0, false),
        ("full K=65 from 250", 250.0, 100.0, true),
        ("full K=65 from 150", 150.0, 250.0, true),
    ];
    let branches: Vec<SpeedBranch> = timestep::sweep(
        &runs,
        |&(_, w0, w1, full)| {
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
        },
        None,
    )
    .into_iter()
    .collect::<Result<_, Error>>()?;
    // Stability (period-map multipliers, one variational integration each) on a thinned subset: points at
    // least STABILITY_SPACING rad/s apart along the branch (the library's policy).
    let branches: Vec<SpeedBranch> = branches
        .into_iter()
        .map(|mut b| {
            liu2021::add_branch_stability(&base(), &mut b, STABILITY_SPACING)
                .context("stability")?;
            Ok(b)
        })
        .collect::<Result<_, Error>>()?;
    let xs: Vec<f64> = (0..=30).map(|i| 100.0 + 5.0 * f64::from(i)).collect();
    let ti: Vec<(f64, u8, f64, Option<String>, bool)> = timestep::sweep(
        &xs,
        |&x| {
            let mut p = base();
            p.omega1 = x;
            let m = model(&p)?;
            // the long-window statistics judge the time-integration side (validation/README.md)
            let r = liu2021::long_window(&m, &models::liu2021::LongWindowOptions::default())
                .context("long window")?;
            Ok((
                x,
                r.nominal.state.rsv(),
                r.nominal.ppv,
                r.state().is_none().then(|| {
                    format!(
                        "at {}: long-window rattle state not robust ({})",
                        super::at(x),
                        crate::unsettled(r.describe())
                    )
                }),
                models::response::window_unsettled(&r, super::SETTLED),
            ))
        },
        None,
    )
    .into_iter()
    .collect::<Result<_, Error>>()?;
    let mut out = StudyOutput::new();
    let branch_columns = [
        ("branch", "-"),
        ("omega1", "rad/s"),
        ("rsv", "1"),
        ("ppv", "1"),
        ("stable", "1"),
        ("max_multiplier", "1, floor 1e-3, 3 s.f."),
        ("residual_norm", "1"),
        ("truncation", "1"),
    ];
    let mut t = Table::new("branches", &branch_columns);
    // the unsettled branches as their own record (validation/stats/ only): their number of
    // points itself moves under a retune, so they are no rows of the committed table
    let mut t_unsettled = Table::new("branches_full_basis", &branch_columns);
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
    for (j, ((label, .., full), b)) in runs.iter().zip(&branches).enumerate() {
        let unsettled = branch_unsettled(*full);
        let cell = |x: f64| Cell::settled_if(x, unsettled);
        let mut pts = Vec::new();
        let rows = if unsettled { &mut t_unsettled } else { &mut t };
        for p in &b.points {
            let marginal = p.max_multiplier().is_some_and(marginal_multiplier);
            rows.push(vec![
                (*label).into(),
                cell(p.parameter),
                cell(f64::from(p.rattle.state.rsv())),
                cell(p.rattle.ppv),
                Cell::settled_if(
                    p.stable().map_or(f64::NAN, |s| if s { 1.0 } else { 0.0 }),
                    unsettled || marginal,
                ),
                // the multiplier itself is resolved to a few per cent only (MULTIPLIER_FLOOR):
                // the committed judgement is the stability column
                Cell::Unsettled(p.max_multiplier().map_or(f64::NAN, resolved_multiplier)),
                p.solution.residual_norm.into(),
                p.solution.truncation.into(),
            ])?;
            // a marginal multiplier draws as "not known stable" (dashed) whichever side it falls
            pts.push((
                p.parameter,
                p.rattle.ppv,
                if marginal { None } else { p.stable() },
            ));
        }
        let text = |s: String| if unsettled { crate::unsettled(s) } else { s };
        runs_t.push(vec![
            (*label).into(),
            cell(b.points.len() as f64),
            text(
                b.folds
                    .iter()
                    .map(|f| sig(f.parameter))
                    .collect::<Vec<_>>()
                    .join(" "),
            )
            .into(),
            text(end_label(&b.stop)).into(),
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
                Some((f.parameter, 0.5 * (a.rattle.ppv + c.rattle.ppv)))
            })
            .collect();
        let before = fig.series.len();
        fig = fig.branch(label, j, &pts, folds);
        if unsettled {
            for s in &mut fig.series[before..] {
                s.unsettled = vec![true; s.points.len()];
            }
        }
    }
    fig = fig.with(
        Series::markers(
            "time integration from rest",
            ti.iter().map(|&(x, _, p, ..)| (x, p)).collect(),
        )
        .unsettled(ti.iter().map(|p| p.4))
        .colour(6), // black: the branches take 0..3
    );
    let ti_onset = ti.iter().find(|p| p.1 == 2).map_or(f64::NAN, |p| p.0);
    let mut evidence = Vec::new();
    let mut ok = false;
    for ((label, .., full), b) in runs.iter().zip(&branches) {
        let unsettled = branch_unsettled(*full);
        // the jump-up point: the highest fold on the unilateral/no-rattle part of the branch
        let fold_max = b
            .folds
            .iter()
            .filter(|f| {
                b.points
                    .get(f.after_index)
                    .is_some_and(|p| p.rattle.state != RattleState::Bilateral)
            })
            .map(|f| f.parameter)
            .fold(f64::NAN, f64::max);
        let bi_min = b
            .points
            .iter()
            .filter(|p| p.rattle.state == RattleState::Bilateral)
            .map(|p| p.parameter)
            .fold(f64::NAN, f64::min);
        let text = format!(
            "folds at [{}] rad/s (jump-up fold of the rattle-free/unilateral part {}), bilateral points down to {} rad/s, end {:?}",
            b.folds
                .iter()
                .map(|f| sig(f.parameter))
                .collect::<Vec<_>>()
                .join(", "),
            sig(fold_max),
            sig(bi_min),
            end_label(&b.stop)
        );
        evidence.push(format!(
            "{label}: {}",
            if unsettled {
                crate::unsettled(text)
            } else {
                text
            }
        ));
        if fold_max.is_finite() {
            out.compare(
                Comparison::published(paper.value("sect34.bilateral-onset")?, fold_max)?
                    .with_tolerance(speed_tolerance(
                        &paper.value("sect34.bilateral-onset")?.printed,
                    ))
                    .reading("R-LIU-HBM")
                    .shown_only()
                    .unsettled_if(unsettled)
                    .note(&format!(
                        "{label}: fold (jump point) of the unilateral branch, pseudo-arclength"
                    )),
            );
        }
        if *label == "paper basis from 250" {
            ok = fold_max.is_finite() && bi_min < ti_onset && ti_onset <= fold_max + 5.0;
        }
    }
    // claim-local: the two grid points that bracket the time-integration onset
    let onset_idx = ti
        .iter()
        .position(|p| p.1 == 2)
        .unwrap_or(ti.len().saturating_sub(1));
    let used = &ti[onset_idx.saturating_sub(1)..=onset_idx.min(ti.len().saturating_sub(1))];
    let flags: Vec<String> = used.iter().filter_map(|p| p.3.clone()).collect();
    let needs: Vec<f64> = used.iter().map(|p| p.0).collect();
    out.claim(
        Claim::new(
            "At the start of the bilateral rattle, a sudden increase occurs in the curve of ppv (jump phenomenon).",
            "Sect. 3.3, Fig. 11b",
            format!(
                "{}; long-window time integration: bilateral from {} rad/s (5 rad/s grid). Pass: the paper-basis branch folds and the time-integration onset lies inside its coexistence range.",
                evidence.join("; "),
                sig(ti_onset)
            ),
            Verdict::from_bool(ok),
        )
        .reading("R-LIU-HBM")
        .needs(needs)
        .flagged_all(flags),
    );
    out.table(t);
    out.table(t_unsettled.unsettled_record(
        "full-basis branches: their initial solve from the one-period response is borderline (under a controller retune the branch from 250 rad/s failed to start)",
    ));
    out.table(runs_t);
    out.figure(fig);
    Ok(out)
}

/// A full-basis (K = 65) branch is not reproducible under a solver retune: its initial Newton
/// solve from the one-period time response at the start speed is borderline (measured: under
/// the step-size controller retune of docs/examples/validate-diff.md the branch from 250 rad/s
/// failed its initial solve, residual 1.8e-5). Its rows, figure and notes are written in full
/// to validation/stats/ and committed as `n/p`; the claim is judged on the paper basis only.
fn branch_unsettled(full: bool) -> bool {
    full
}

/// Multipliers within this distance of the unit circle are not committed: the period map is
/// taken at the harmonic-balance state, not at a fixed point of the time integration, so a
/// multiplier near the circle moves with that state (the HBM truncation and corrector
/// tolerance); their stability is not committed and their segment draws as not known stable.
const MARGINAL: f64 = 0.1;

fn marginal_multiplier(mu: f64) -> bool {
    !mu.is_finite() || (mu - 1.0).abs() < MARGINAL
}

/// Floor of the committed multiplier modulus: below it an orbit is stable by a wide margin
/// and the value carries no verdict (the deleted finite-difference period map had its noise
/// floor there; the variational monodromy resolves ~1e-10, but the floor keeps snapshot
/// diffs to changes that matter; `shooting_multipliers_flag_stable_orbits` bounds them by the
/// same 1e-3). The table writes `max(|μ|, 1e-3)` at 3 significant digits so that a snapshot
/// diff means a changed multiplier; the stability flag uses the unrounded value.
const MULTIPLIER_FLOOR: f64 = 1e-3;

fn resolved_multiplier(mu: f64) -> f64 {
    if !mu.is_finite() {
        return mu;
    }
    let m = mu.max(MULTIPLIER_FLOOR);
    let scale = 10f64.powi(2 - m.dlog10().floor() as i32);
    (m * scale).round() / scale
}

/// The end of a branch at 6 significant digits (the raw `Debug` form prints round-off), its
/// speed in rad/s (`SpeedBranch` reports every parameter as `ω₁`).
fn end_label(end: &orbit::StopReason) -> String {
    match end {
        orbit::StopReason::ReachedEnd => "ReachedEnd".to_owned(),
        orbit::StopReason::MaxPoints => "MaxPoints".to_owned(),
        orbit::StopReason::LeftRange { parameter } => {
            format!("LeftRange {{ omega1: {} rad/s }}", sig(*parameter))
        }
        orbit::StopReason::StepTooSmall { parameter, .. } => {
            format!("StepTooSmall {{ omega1: {} rad/s }}", sig(*parameter))
        }
        orbit::StopReason::Stalled { parameter, points } => {
            format!(
                "Stalled {{ omega1: {} rad/s, points: {points} }}",
                sig(*parameter)
            )
        }
        orbit::StopReason::InitialSolveFailed { residual_norm } => {
            format!(
                "InitialSolveFailed {{ residual_norm: {} }}",
                sig(*residual_norm)
            )
        }
        other => format!("{other:?}"),
    }
}
