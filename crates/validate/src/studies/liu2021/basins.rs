//! Basins of attraction of the circular face gear (ε = 0) at ω1 = 160 rad/s: where the
//! coexistence rows of Sect. 3.5 come from.
//!
//! At ε = 0, 160 rad/s the robustness variants of the parameter sweeps disagree: the nominal
//! start (the quasi-static contact at rest) and the other start (`q = q' = 0`, the middle of the
//! gap) reach different long-window responses, so three Sect. 3.5 rows are inconclusive. This
//! study names every response a grid of starts reaches and the share of starts that reach each
//! ([`models::response::basin`]); those rows quote the fractions ([`evidence`]).

use models::liu2021::{self, LongWindowOptions};
use models::response::basin::{
    Attractor, Axis, BasinGrid, BasinOptions, Basins, Signature, basins,
};

use super::{base, model, sig};
use crate::{
    Cell, Claim, Cost, Error, Evidence, Figure, Paper, Series, Study, StudyOutput, Table, Verdict,
};

pub(super) fn study() -> Study {
    Study {
        id: "liu2021-basins",
        paper: Paper::Liu2021,
        source: "Sect. 3.5, Fig. 13 (ε = 0, ω1 = 160 rad/s)",
        title: "Basins of attraction of the circular face gear at 160 rad/s (coexisting responses)",
        description: "Model: Table 1 (constant-b̄ reading) with ε = 0, ω1 = 160 rad/s. A grid of \
            12 × 12 initial states q(0) ∈ [−3 b̄, 2 b̄], q'(0) ∈ [−2 b̄, 2 b̄] (b̄ the \
            dimensionless half backlash at τ = 0): it holds both starts of the robustness \
            variants (the quasi-static contact at rest and the middle of the gap) and reaches a \
            gap beyond either flank. Each cell: the settled long window of the parameter sweeps \
            (LongWindowOptions::default: 10 periods discarded, 50-period windows, up to two \
            windows that still hold a transient discarded, rtol 1e-8), named by its rattle \
            state, Poincaré period and ppv; cells with the same state and period and ppv within \
            1 % are one attractor. Output: the attractors with their basin fractions, the cells, \
            and the map of the cells coloured by attractor.",
        cost: Cost::Heavy,
        run,
    }
}

/// Grid points per axis (12 × 12 = 144 cells, about 0.25 CPU s each on the 2026 runner).
const STEPS: usize = 12;
/// The q(0) range in units of b̄(0).
const Q_RANGE: (f64, f64) = (-3.0, 2.0);
/// The q'(0) range in units of b̄(0).
const V_RANGE: (f64, f64) = (-2.0, 2.0);

/// A start of the robustness variants: its label, its initial state and its signature (or why
/// it failed).
pub(super) type Start = (&'static str, (f64, f64), Result<Signature, String>);

/// The basins at ε = 0, 160 rad/s with where the two starts of the robustness variants land.
#[derive(Debug, Clone)]
pub(super) struct LiuBasins {
    /// The basins on the grid.
    pub basins: Basins,
    /// `b̄(0)`, the unit of the grid.
    pub bbar: f64,
    /// The two starts of the variants (label, state, signature or failure).
    pub starts: Vec<Start>,
}

/// The basins at ε = 0, 160 rad/s ([`LiuBasins`]); memoised, so that this study and the
/// parameter sweeps that quote it compute them once per run.
pub(super) fn eps0_basins() -> Result<LiuBasins, Error> {
    let mut p = base();
    p.eccentricity = 0.0;
    let m = model(&p)?;
    // a cell's signature reads the state, the motion and the ppv only
    let wo = LongWindowOptions {
        detail: models::response::WindowDetail::Motion,
        ..LongWindowOptions::default()
    };
    let bbar = m.backlash_at(0.0);
    let axis = |(a, b): (f64, f64)| Axis::new(a * bbar, b * bbar, STEPS);
    let grid = BasinGrid::new(axis(Q_RANGE), axis(V_RANGE))
        .map_err(|e| Error::Study(format!("liu2021 basins: {e}")))?;
    let key = format!("{m:?}|{wo:?}|{grid:?}");
    models::memo::cached(
        "validate::liu2021_eps0_basins",
        || key,
        || {
            let cell = |q: f64, v: f64| {
                liu2021::settled_window(&m, &wo, Some((q, v)))
                    .map(|w| Signature::of_window(&w.stats))
                    .map_err(|e| e.to_string())
            };
            let b = basins(&grid, &BasinOptions::default(), cell)
                .map_err(|e| Error::Study(format!("liu2021 basins: {e}")))?;
            let starts = [
                (
                    "nominal start (quasi-static contact at rest)",
                    (m.static_position(0.0), 0.0),
                ),
                ("other start (q = q' = 0)", (0.0, 0.0)),
            ]
            .into_iter()
            .map(|(l, (q, v))| (l, (q, v), cell(q, v)))
            .collect();
            Ok(LiuBasins {
                basins: b,
                bbar,
                starts,
            })
        },
    )
}

/// The attractors as text: `A0 no rattle period-1 ppv 2.59e-5: 33 %, …`.
fn attractors_text(b: &Basins) -> String {
    let mut parts: Vec<String> = b
        .attractors
        .iter()
        .map(|a| {
            format!(
                "A{} {} {} ppv {}: {} %",
                a.label,
                state_name(a.state),
                Signature::new(a.state, a.motion, a.ppv).motion_label(),
                sig(a.ppv),
                sig(100.0 * a.fraction)
            )
        })
        .collect();
    if b.failed > 0 {
        parts.push(format!("failed: {} %", sig(100.0 * b.failed_fraction())));
    }
    parts.join(", ")
}

fn state_name(s: i8) -> &'static str {
    match s {
        0 => "no rattle",
        1 => "unilateral",
        2 => "bilateral",
        _ => "",
    }
}

/// Where each start of the variants lands: `nominal start (…) → A0, other start (…) → A2`.
fn starts_text(lb: &LiuBasins) -> String {
    lb.starts
        .iter()
        .map(|(label, _, s)| {
            let to = match s {
                Ok(s) => lb.basins.attractor_of(s).map_or_else(
                    || {
                        format!(
                            "{} {} ppv {} (no attractor of the grid)",
                            state_name(s.state),
                            s.motion_label(),
                            sig(s.ppv)
                        )
                    },
                    |a| format!("A{}", a.label),
                ),
                Err(e) => format!("failed ({e})"),
            };
            format!("{label} → {to}")
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The evidence the coexistence rows quote: the attractors at ε = 0, 160 rad/s with their basin
/// fractions, where the two starts of the variants land, and from which attractors the row's
/// reading of the claim holds (`holds`) with their share of the starts (or why there are none).
pub(super) fn evidence(holds: impl Fn(&Attractor) -> bool) -> String {
    match eps0_basins() {
        Ok(lb) => {
            let b = &lb.basins;
            let (yes, no): (Vec<&Attractor>, Vec<&Attractor>) =
                b.attractors.iter().partition(|a| holds(a));
            let side = |v: &[&Attractor]| {
                if v.is_empty() {
                    "none".to_owned()
                } else {
                    format!(
                        "{} ({} % of the starts)",
                        v.iter()
                            .map(|a| format!("A{}", a.label))
                            .collect::<Vec<_>>()
                            .join(", "),
                        sig(100.0 * v.iter().map(|a| a.fraction).sum::<f64>())
                    )
                }
            };
            format!(
                "basins at ε = 0, 160 rad/s (liu2021-basins, {n} × {n} starts): {}; {}; at ε = 0 \
                 the claim's reading holds on {} and not on {}",
                attractors_text(b),
                starts_text(&lb),
                side(&yes),
                side(&no),
                n = STEPS
            )
        }
        Err(e) => format!("basins at ε = 0 not computed: {e}"),
    }
}

fn run() -> Result<StudyOutput, Error> {
    let lb = eps0_basins()?;
    let b = &lb.basins;
    let mut out = StudyOutput::new();
    let distinct = b.attractors.len();
    out.claim(
        Claim::new(
            "At ε = 0, ω1 = 160 rad/s the responses the two starts reach coexist: each is an attractor with a basin of its own.",
            "Sect. 3.5, Fig. 13 (model check of the coexistence rows)",
            format!(
                "{distinct} attractor(s) on {} × {} starts: {}; {}",
                STEPS,
                STEPS,
                attractors_text(b),
                starts_text(&lb)
            ),
            Verdict::Shown,
        )
        .class(Evidence::NotCheckable(
            "the paper shows no basins; the model's own coexistence, quoted by the Sect. 3.5 rows"
                .to_owned(),
        ))
        .cause("basins of attraction of the long-window signatures (rattle state, Poincaré period, ppv within 1 %)"),
    );
    let mut fr = Table::new(
        "fractions",
        &[
            ("attractor", "1"),
            ("rsv", "1"),
            ("period", "1"),
            ("ppv", "1"),
            ("ppv_min", "1"),
            ("ppv_max", "1"),
            ("cells", "1"),
            ("fraction", "1"),
            ("seed q / b", "1"),
            ("seed q' / b", "1"),
        ],
    );
    for a in &b.attractors {
        let ppv = |x: f64| {
            if a.motion >= 1.0 {
                Cell::Num(x)
            } else {
                Cell::Unsettled(x)
            }
        };
        fr.push(vec![
            Cell::Count(a.label as u64),
            Cell::Num(f64::from(a.state)),
            Cell::Num(a.motion),
            ppv(a.ppv),
            ppv(a.ppv_min),
            ppv(a.ppv_max),
            Cell::Count(a.cells as u64),
            Cell::Num(a.fraction),
            Cell::Num(a.seed.0 / lb.bbar),
            Cell::Num(a.seed.1 / lb.bbar),
        ])?;
    }
    out.table(fr);
    let mut cells = Table::new(
        "cells",
        &[
            ("q0 / b", "1"),
            ("q0' / b", "1"),
            ("rsv", "1"),
            ("period", "1"),
            ("ppv", "1"),
            ("attractor", "1"),
        ],
    );
    for (k, c) in b.cells.iter().enumerate() {
        let (q, v) = b.grid.cell(k);
        let (rsv, motion, ppv) = match c {
            Ok(s) if s.periodic() => (f64::from(s.state), s.motion, Cell::Num(s.ppv)),
            Ok(s) => (f64::from(s.state), s.motion, Cell::Unsettled(s.ppv)),
            Err(_) => (f64::NAN, f64::NAN, Cell::Num(f64::NAN)),
        };
        cells.push(vec![
            Cell::Num(q / lb.bbar),
            Cell::Num(v / lb.bbar),
            Cell::Num(rsv),
            Cell::Num(motion),
            ppv,
            b.labels[k].map_or(Cell::Num(f64::NAN), |l| Cell::Count(l as u64)),
        ])?;
    }
    out.table(cells);
    let mut fig = Figure::new(
        "attractor_map",
        "Basins of attraction, Liu model at ε = 0, ω1 = 160 rad/s (one marker per start)",
        ("q(0) / b", "1"),
        ("q'(0) / b", "1"),
    );
    for a in &b.attractors {
        let pts: Vec<(f64, f64)> = (0..b.cells.len())
            .filter(|&k| b.labels[k] == Some(a.label))
            .map(|k| {
                let (q, v) = b.grid.cell(k);
                (q / lb.bbar, v / lb.bbar)
            })
            .collect();
        let label = format!(
            "A{} {} {} ({} %)",
            a.label,
            state_name(a.state),
            Signature::new(a.state, a.motion, a.ppv).motion_label(),
            sig(100.0 * a.fraction)
        );
        fig.push(Series::markers(label, pts).colour(a.label));
    }
    let failed: Vec<(f64, f64)> = (0..b.cells.len())
        .filter(|&k| b.labels[k].is_none())
        .map(|k| {
            let (q, v) = b.grid.cell(k);
            (q / lb.bbar, v / lb.bbar)
        })
        .collect();
    if !failed.is_empty() {
        fig.push(Series::markers("failed", failed).colour(7));
    }
    out.figure(fig);
    out.note(format!(
        "Grid: {n} × {n} starts, q(0)/b̄ ∈ [{}, {}], q'(0)/b̄ ∈ [{}, {}], b̄ = {} (Table 1 at τ = 0). \
         Windows: those of the parameter sweeps (10 periods discarded; 50-period windows, a \
         window whose Poincaré section repeats over its last half but not over the whole is \
         discarded, at most twice): the free transient decays by about e^-17 per period at \
         Table 1 values, so a cell that settles does so well inside them, and a cell still in a \
         transient at the cap is 'unsettled' and an attractor of its own, never merged. \
         Failed cells: {}.",
        Q_RANGE.0,
        Q_RANGE.1,
        V_RANGE.0,
        V_RANGE.1,
        sig(lb.bbar),
        b.failed,
        n = STEPS
    ));
    Ok(out)
}
