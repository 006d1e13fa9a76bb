//! Basins of attraction at fixed parameters: a grid of initial states `(q, q̇)`, each cell's
//! settled long window named by its **attractor signature**, the signatures clustered into
//! attractors, the basin fraction of each and a label per cell.
//!
//! # Signature
//!
//! A cell's [`Signature`] is what its settled window says about the motion it reached:
//!
//! * the **rattle state** over the window (`rsv` 0 no rattle, 1 unilateral, 2 bilateral;
//!   [`Signature::NO_STATE`] for a system without one, e.g. a Duffing oscillator);
//! * the **motion code** ([`timestep::Motion::code`]: `n ≥ 1` period-n from the stroboscopic
//!   Poincaré section, 0 quasi-periodic, −1 chaotic, [`crate::response::UNSETTLED_CODE`]
//!   unsettled);
//! * the long-window **ppv** `max q − min q`;
//! * optionally the 0–1 test `K` and the largest Lyapunov exponent `λ1` (informative; not used
//!   to cluster).
//!
//! # Clustering
//!
//! Two cells reach the same attractor when they have the same rattle state and the same motion
//! code and, for a periodic motion, ppv values that a chain of neighbours joins with relative
//! gaps `|p_{i+1} − p_i| ≤ ppv_tol · max(|p_i|, |p_{i+1}|, ppv_floor)` (single linkage on the
//! sorted ppv values of the group). A periodic orbit reproduces its ppv to integration noise
//! (~1e-6 relative), so two distinct orbits separate unless their ppv values are within
//! `ppv_tol` of each other. A non-periodic window's ppv is a sample of the attractor, not a
//! value: the non-periodic cells of one (state, motion) group form one attractor.
//!
//! The clustering uses only the multiset of signatures, never the order in which cells were
//! computed; the attractors are numbered in a fixed order (rattle state, then periodic by
//! period, quasi-periodic, chaotic, non-periodic, unsettled, then ppv ascending), so labels
//! are independent of the thread count. [`basins`] computes the cells with
//! [`system::sweep::sweep`], the one ordered parallel map: bit-identical for any number of
//! threads.
//!
//! A cell whose computation fails (an error or a panic) is one failed cell (no label, its
//! message kept), never a lost study. The attractor fractions and the failed fraction sum to 1.
//!
//! ```
//! use geardyn_models::response::basin::{Axis, BasinGrid, BasinOptions, Signature, basins};
//! let grid = BasinGrid::new(Axis::new(-1.0, 1.0, 4), Axis::new(-1.0, 1.0, 3)).unwrap();
//! // two "attractors": the sign of q decides
//! let b = basins(&grid, &BasinOptions::default(), |q, _| {
//!     Ok(Signature::new(Signature::NO_STATE, 1.0, if q < 0.0 { 1.0 } else { 2.0 }))
//! })
//! .unwrap();
//! assert_eq!(b.attractors.len(), 2);
//! assert_eq!(b.attractors[0].cells + b.attractors[1].cells, 12);
//! ```

use std::panic::{AssertUnwindSafe, catch_unwind};

use serde::Serialize;

use super::{UNSETTLED_CODE, WindowStats, motion_code};

/// Most points of one grid axis.
pub const MAX_BASIN_AXIS: usize = 1000;
/// Most cells of a grid (the most values of a study sweep, `geardyn_study::MAX_SWEEP_VALUES`).
pub const MAX_BASIN_CELLS: usize = 100_000;

/// An invalid basin input: the field, the bound it violates and the value given.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum BasinError {
    /// A grid or option value is out of bounds.
    #[error("basin.{field} must be {bound}, got {got}")]
    OutOfBounds {
        /// The field (`q.steps`, `q_dot.from`, `cells`, `ppv_tol`, …).
        field: String,
        /// The bound, in words.
        bound: String,
        /// The value given.
        got: String,
    },
    /// The signatures do not match the grid.
    #[error("basin: {got} cell results for a grid of {cells} cells")]
    Cells {
        /// Cells of the grid.
        cells: usize,
        /// Results given.
        got: usize,
    },
}

fn out_of_bounds(field: &str, bound: impl Into<String>, got: impl ToString) -> BasinError {
    BasinError::OutOfBounds {
        field: field.to_owned(),
        bound: bound.into(),
        got: got.to_string(),
    }
}

/// One axis of the grid: `steps` equally spaced values from `from` to `to` (inclusive).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Axis {
    /// First value.
    pub from: f64,
    /// Last value (> `from`).
    pub to: f64,
    /// Number of values (2 ..= [`MAX_BASIN_AXIS`]).
    pub steps: usize,
}

impl Axis {
    /// An axis (checked by [`BasinGrid::new`]).
    pub fn new(from: f64, to: f64, steps: usize) -> Self {
        Axis { from, to, steps }
    }

    /// The `i`-th value, `from·(1 − t) + to·t` with `t = i/(steps − 1)` (no overflow for
    /// finite ends).
    pub fn value(&self, i: usize) -> f64 {
        let t = i as f64 / (self.steps.max(2) - 1) as f64;
        self.from * (1.0 - t) + self.to * t
    }

    /// Every value, in order.
    pub fn values(&self) -> Vec<f64> {
        (0..self.steps).map(|i| self.value(i)).collect()
    }

    fn check(&self, name: &str) -> Result<(), BasinError> {
        if !self.from.is_finite() {
            return Err(out_of_bounds(&format!("{name}.from"), "finite", self.from));
        }
        if !(self.to.is_finite() && self.to > self.from) {
            return Err(out_of_bounds(
                &format!("{name}.to"),
                format!("finite and > {name}.from = {}", self.from),
                self.to,
            ));
        }
        if !(2..=MAX_BASIN_AXIS).contains(&self.steps) {
            return Err(out_of_bounds(
                &format!("{name}.steps"),
                format!("in [2, {MAX_BASIN_AXIS}]"),
                self.steps,
            ));
        }
        Ok(())
    }
}

/// The grid of initial states: cell `k` is `(q[k mod n_q], q̇[k div n_q])` (q fastest).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BasinGrid {
    /// Initial displacement axis.
    pub q: Axis,
    /// Initial velocity axis.
    pub q_dot: Axis,
}

impl BasinGrid {
    /// A checked grid: finite ends with `to > from`, 2 ..= [`MAX_BASIN_AXIS`] steps per axis,
    /// at most [`MAX_BASIN_CELLS`] cells. Errors name the field and the bound.
    pub fn new(q: Axis, q_dot: Axis) -> Result<Self, BasinError> {
        q.check("q")?;
        q_dot.check("q_dot")?;
        let cells = q.steps.saturating_mul(q_dot.steps);
        if cells > MAX_BASIN_CELLS {
            return Err(out_of_bounds(
                "cells",
                format!("≤ {MAX_BASIN_CELLS} (q.steps · q_dot.steps)"),
                cells,
            ));
        }
        Ok(BasinGrid { q, q_dot })
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.q.steps * self.q_dot.steps
    }

    /// True if the grid has no cell (never for a checked grid).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The initial state `(q, q̇)` of cell `k`.
    pub fn cell(&self, k: usize) -> (f64, f64) {
        (
            self.q.value(k % self.q.steps),
            self.q_dot.value(k / self.q.steps),
        )
    }
}

/// Clustering options.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BasinOptions {
    /// Relative ppv gap that still joins two periodic cells of the same state and period
    /// (in (0, 0.5]; default 0.01).
    pub ppv_tol: f64,
    /// Absolute ppv below which the relative gap is taken against this floor instead (≥ 0;
    /// default 1e-9), so that ppv values near zero do not split on noise.
    pub ppv_floor: f64,
}

impl Default for BasinOptions {
    fn default() -> Self {
        BasinOptions {
            ppv_tol: 0.01,
            ppv_floor: 1e-9,
        }
    }
}

impl BasinOptions {
    /// Check the options; errors name the field and the bound.
    pub fn check(&self) -> Result<(), BasinError> {
        if !(self.ppv_tol > 0.0 && self.ppv_tol <= 0.5) {
            return Err(out_of_bounds("ppv_tol", "in (0, 0.5]", self.ppv_tol));
        }
        if !(self.ppv_floor >= 0.0 && self.ppv_floor.is_finite()) {
            return Err(out_of_bounds("ppv_floor", "finite and ≥ 0", self.ppv_floor));
        }
        Ok(())
    }
}

/// What a cell's settled window says about the attractor it reached (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Signature {
    /// Rattle state (0, 1, 2), or [`Signature::NO_STATE`].
    pub state: i8,
    /// Motion code ([`timestep::Motion::code`], or [`crate::response::UNSETTLED_CODE`]).
    pub motion: f64,
    /// Long-window ppv `max q − min q`.
    pub ppv: f64,
    /// 0–1 test `K` of the window (NaN when not computed).
    pub chaos_k: f64,
    /// Largest Lyapunov exponent (NaN when not computed).
    pub lambda1: f64,
}

impl Signature {
    /// The state of a system without a rattle state.
    pub const NO_STATE: i8 = -1;

    /// A signature without `K` and `λ1`.
    pub fn new(state: i8, motion: f64, ppv: f64) -> Self {
        Signature {
            state,
            motion,
            ppv,
            chaos_k: f64::NAN,
            lambda1: f64::NAN,
        }
    }

    /// The signature of a settled long window ([`crate::response::window_stats`]): its rattle
    /// state, [`motion_code`], ppv and 0–1 `K`.
    pub fn of_window(w: &WindowStats) -> Self {
        Signature {
            state: w.state.rsv() as i8,
            motion: motion_code(w),
            ppv: w.ppv,
            chaos_k: w.chaos_k,
            lambda1: f64::NAN,
        }
    }

    /// The motion is periodic (code ≥ 1).
    pub fn periodic(&self) -> bool {
        self.motion >= 1.0
    }

    /// A check that the signature can be clustered: `state` in −1 ..= 2, `motion` a motion
    /// code, `ppv` finite and ≥ 0.
    fn check(&self) -> Result<(), String> {
        #[allow(clippy::float_cmp)] // exact: codes are small integers
        let code_ok =
            self.motion == UNSETTLED_CODE || timestep::Motion::from_code(self.motion).is_some();
        if !(-1..=2).contains(&self.state) {
            Err(format!("rattle state {} is not −1, 0, 1 or 2", self.state))
        } else if !code_ok {
            Err(format!("motion {} is not a motion code", self.motion))
        } else if !(self.ppv.is_finite() && self.ppv >= 0.0) {
            Err(format!("ppv {} is not finite and ≥ 0", self.ppv))
        } else {
            Ok(())
        }
    }

    /// Sort rank of the motion: periodic by period, then quasi-periodic, chaotic,
    /// non-periodic, unsettled.
    fn motion_rank(&self) -> (u8, u64) {
        if self.periodic() {
            (0, self.motion as u64)
        } else {
            #[allow(clippy::float_cmp)] // exact: codes are small integers
            let r = if self.motion == 0.0 {
                1
            } else if self.motion == -1.0 {
                2
            } else if self.motion == -2.0 {
                3
            } else {
                4
            };
            (r, 0)
        }
    }

    /// The motion's label (`period-1`, …, `chaotic`, `unsettled`).
    pub fn motion_label(&self) -> String {
        super::motion_label(self.motion).unwrap_or_else(|| "unknown".to_owned())
    }
}

/// One attractor found on the grid.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Attractor {
    /// Its label (index in [`Basins::attractors`]).
    pub label: usize,
    /// Rattle state (or [`Signature::NO_STATE`]).
    pub state: i8,
    /// Motion code.
    pub motion: f64,
    /// Median ppv of its cells.
    pub ppv: f64,
    /// Smallest ppv of its cells.
    pub ppv_min: f64,
    /// Largest ppv of its cells.
    pub ppv_max: f64,
    /// Cells that reached it.
    pub cells: usize,
    /// Its basin fraction: cells / all cells of the grid (failed ones included).
    pub fraction: f64,
    /// The initial state of its first cell (lowest index): a start that reaches it.
    pub seed: (f64, f64),
}

impl Attractor {
    /// A short name: `A<label>: <state> <motion> ppv <ppv>` (the heat map's legend).
    pub fn name(&self) -> String {
        let state = match self.state {
            0 => "no rattle ",
            1 => "unilateral ",
            2 => "bilateral ",
            _ => "",
        };
        let sig = Signature::new(self.state, self.motion, self.ppv);
        format!(
            "A{}: {state}{} ppv {}",
            self.label,
            sig.motion_label(),
            system::format::fmt6(self.ppv)
        )
    }
}

/// The basins of attraction on a grid.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Basins {
    /// The grid.
    pub grid: BasinGrid,
    /// The clustering options.
    pub options: BasinOptions,
    /// Each cell's signature or its failure message, in cell order.
    pub cells: Vec<Result<Signature, String>>,
    /// Each cell's attractor label (`None`: failed cell), in cell order.
    pub labels: Vec<Option<usize>>,
    /// The attractors, in label order.
    pub attractors: Vec<Attractor>,
    /// Failed cells.
    pub failed: usize,
}

impl Basins {
    /// Fraction of failed cells (the attractor fractions and this sum to 1).
    pub fn failed_fraction(&self) -> f64 {
        self.failed as f64 / self.cells.len().max(1) as f64
    }

    /// The attractor a signature computed elsewhere (another start, another run) belongs to:
    /// the first with the same rattle state and motion and, for a periodic motion, a ppv within
    /// `ppv_tol` (relative, as the clustering) of the attractor's ppv range. `None` when the
    /// signature reaches no attractor of the grid.
    pub fn attractor_of(&self, s: &Signature) -> Option<&Attractor> {
        let o = &self.options;
        self.attractors.iter().find(|a| {
            let rep = Signature::new(a.state, a.motion, a.ppv);
            let near =
                |p: f64| (s.ppv - p).abs() <= o.ppv_tol * s.ppv.abs().max(p.abs()).max(o.ppv_floor);
            rep.state == s.state
                && rep.motion_rank() == s.motion_rank()
                && (!rep.periodic()
                    || near(a.ppv_min)
                    || near(a.ppv_max)
                    || (s.ppv >= a.ppv_min && s.ppv <= a.ppv_max))
        })
    }
}

/// Cluster the cell results of `grid` (see the module docs). A signature that is not a valid
/// one (rattle state, motion code, non-finite ppv) makes its cell a failed cell.
pub fn cluster(
    grid: &BasinGrid,
    options: &BasinOptions,
    cells: Vec<Result<Signature, String>>,
) -> Result<Basins, BasinError> {
    options.check()?;
    if cells.len() != grid.len() {
        return Err(BasinError::Cells {
            cells: grid.len(),
            got: cells.len(),
        });
    }
    let cells: Vec<Result<Signature, String>> = cells
        .into_iter()
        .map(|c| c.and_then(|s| s.check().map(|()| s)))
        .collect();
    // Ok cells, sorted by (state, motion rank, ppv, index): a total order on the signatures.
    let mut ok: Vec<(usize, Signature)> = cells
        .iter()
        .enumerate()
        .filter_map(|(k, c)| c.as_ref().ok().map(|s| (k, *s)))
        .collect();
    ok.sort_by(|(ka, a), (kb, b)| {
        (a.state, a.motion_rank())
            .cmp(&(b.state, b.motion_rank()))
            .then(a.ppv.total_cmp(&b.ppv))
            .then(ka.cmp(kb))
    });
    let joins = |a: &Signature, b: &Signature| {
        a.state == b.state
            && a.motion_rank() == b.motion_rank()
            && (!a.periodic()
                || (b.ppv - a.ppv).abs()
                    <= options.ppv_tol * a.ppv.abs().max(b.ppv.abs()).max(options.ppv_floor))
    };
    let mut labels = vec![None; cells.len()];
    let mut attractors: Vec<Attractor> = Vec::new();
    let mut members: Vec<usize> = Vec::new();
    let total = cells.len() as f64;
    let mut close = |members: &mut Vec<usize>, attractors: &mut Vec<Attractor>| {
        if members.is_empty() {
            return;
        }
        let label = attractors.len();
        let sig = |k: usize| match &cells[k] {
            Ok(s) => *s,
            Err(_) => Signature::new(Signature::NO_STATE, UNSETTLED_CODE, f64::NAN),
        };
        let first = sig(members[0]);
        let ppvs: Vec<f64> = members.iter().map(|&k| sig(k).ppv).collect();
        let seed = *members.iter().min().unwrap_or(&0);
        for &k in members.iter() {
            labels[k] = Some(label);
        }
        attractors.push(Attractor {
            label,
            state: first.state,
            motion: first.motion,
            ppv: ppvs[ppvs.len() / 2],
            ppv_min: ppvs[0],
            ppv_max: ppvs[ppvs.len() - 1],
            cells: members.len(),
            fraction: members.len() as f64 / total,
            seed: grid.cell(seed),
        });
        members.clear();
    };
    let mut prev: Option<Signature> = None;
    for (k, s) in &ok {
        if let Some(p) = prev
            && !joins(&p, s)
        {
            close(&mut members, &mut attractors);
        }
        members.push(*k);
        prev = Some(*s);
    }
    close(&mut members, &mut attractors);
    let failed = cells.iter().filter(|c| c.is_err()).count();
    Ok(Basins {
        grid: *grid,
        options: *options,
        cells,
        labels,
        attractors,
        failed,
    })
}

/// Compute every cell of `grid` with `cell(q, q̇)` in parallel ([`system::sweep::sweep`], in
/// cell order: bit-identical for any thread count) and [`cluster`] the signatures. A cell that
/// fails or panics is a failed cell with its message.
pub fn basins<F>(grid: &BasinGrid, options: &BasinOptions, cell: F) -> Result<Basins, BasinError>
where
    F: Fn(f64, f64) -> Result<Signature, String> + Sync,
{
    basins_with_progress(grid, options, cell, None)
}

/// [`basins`] with a progress callback `(cells done, total)`.
pub fn basins_with_progress<F>(
    grid: &BasinGrid,
    options: &BasinOptions,
    cell: F,
    progress: Option<&(dyn Fn(usize, usize) + Sync)>,
) -> Result<Basins, BasinError>
where
    F: Fn(f64, f64) -> Result<Signature, String> + Sync,
{
    options.check()?;
    let idx: Vec<usize> = (0..grid.len()).collect();
    let results = system::sweep::sweep(
        &idx,
        |&k| {
            let (q, v) = grid.cell(k);
            catch_unwind(AssertUnwindSafe(|| cell(q, v))).unwrap_or_else(|p| {
                let m = p
                    .downcast_ref::<&str>()
                    .map(|s| (*s).to_owned())
                    .or_else(|| p.downcast_ref::<String>().cloned())
                    .unwrap_or_else(|| "unknown panic".to_owned());
                Err(format!("internal error (panic caught): {m}"))
            })
        },
        progress,
    );
    cluster(grid, options, results)
}

#[cfg(test)]
#[allow(clippy::float_cmp)] // exact: motion codes and a fraction of 1
mod tests {
    use super::*;

    fn grid(nq: usize, nv: usize) -> BasinGrid {
        BasinGrid::new(Axis::new(-2.5, 2.5, nq), Axis::new(-3.0, 3.0, nv)).unwrap()
    }

    #[test]
    fn inputs_are_checked_with_field_and_bound() {
        let a = Axis::new(0.0, 1.0, 3);
        let cases = [
            (Axis::new(f64::NAN, 1.0, 3), a, "q.from"),
            (Axis::new(0.0, 0.0, 3), a, "q.to"),
            (Axis::new(0.0, f64::INFINITY, 3), a, "q.to"),
            (Axis::new(0.0, 1.0, 1), a, "q.steps"),
            (Axis::new(0.0, 1.0, 1001), a, "q.steps"),
            (a, Axis::new(0.0, 1.0, usize::MAX), "q_dot.steps"),
            (
                Axis::new(0.0, 1.0, 1000),
                Axis::new(0.0, 1.0, 1000),
                "cells",
            ),
        ];
        for (q, v, field) in cases {
            let e = BasinGrid::new(q, v).unwrap_err();
            let BasinError::OutOfBounds {
                field: f, bound, ..
            } = &e
            else {
                panic!("{e}")
            };
            assert_eq!(f, field, "{e}");
            assert!(!bound.is_empty());
            assert!(e.to_string().contains(field), "{e}");
        }
        let g = BasinGrid::new(a, a).unwrap();
        for tol in [0.0, -1.0, 0.6, f64::NAN] {
            let o = BasinOptions {
                ppv_tol: tol,
                ..BasinOptions::default()
            };
            let e = basins(&g, &o, |_, _| Ok(Signature::new(0, 1.0, 1.0))).unwrap_err();
            assert!(e.to_string().contains("ppv_tol"), "{e}");
        }
        let e = cluster(&g, &BasinOptions::default(), Vec::new()).unwrap_err();
        assert_eq!(e, BasinError::Cells { cells: 9, got: 0 });
        assert_eq!(g.cell(4), (0.5, 0.5));
        assert_eq!(g.cell(8), (1.0, 1.0));
    }

    #[test]
    fn failures_and_panics_are_failed_cells_and_fractions_sum_to_one() {
        let g = grid(5, 4);
        let b = basins(&g, &BasinOptions::default(), |q, v| {
            if q > 2.0 {
                panic!("boom")
            } else if v > 2.0 {
                Err("no".to_owned())
            } else if q < 0.0 {
                Ok(Signature::new(2, -1.0, 3.0 + q))
            } else {
                Ok(Signature::new(0, 1.0, f64::NAN))
            }
        })
        .unwrap();
        // q = 2.5 panics (4 cells), v = 3 fails (5 cells, one of them already q = 2.5),
        // q ≥ 0 and < 2.5 gives a NaN ppv (invalid): 2 columns × 3 rows
        assert_eq!(b.failed, 4 + 4 + 6);
        assert_eq!(b.attractors.len(), 1, "{:?}", b.attractors);
        // the chaotic cells join whatever their ppv
        assert_eq!(b.attractors[0].cells, 6);
        let sum: f64 = b.attractors.iter().map(|a| a.fraction).sum::<f64>() + b.failed_fraction();
        assert!((sum - 1.0).abs() < 1e-12);
        assert!(matches!(&b.cells[4], Err(m) if m.contains("boom")));
        assert!(b.labels[4].is_none());
    }

    #[test]
    fn clusters_by_state_period_and_ppv_in_a_fixed_order() {
        let g = grid(4, 2);
        // ppv 1.0 and 1.005 join (0.5 % < 1 %); 1.2 does not; a period-2 and another state
        // are attractors of their own
        let sig = [
            Signature::new(1, 1.0, 1.2),
            Signature::new(1, 1.0, 1.0),
            Signature::new(1, 2.0, 1.0),
            Signature::new(0, 1.0, 1.0),
            Signature::new(1, 1.0, 1.005),
            Signature::new(1, 1.0, 1.2),
            Signature::new(1, 1.0, 1.0),
            Signature::new(1, UNSETTLED_CODE, 9.0),
        ];
        let b = cluster(
            &g,
            &BasinOptions::default(),
            sig.iter().map(|s| Ok(*s)).collect(),
        )
        .unwrap();
        let got: Vec<(i8, f64, f64, usize)> = b
            .attractors
            .iter()
            .map(|a| (a.state, a.motion, a.ppv_min, a.cells))
            .collect();
        assert_eq!(
            got,
            [
                (0, 1.0, 1.0, 1),
                (1, 1.0, 1.0, 3),
                (1, 1.0, 1.2, 2),
                (1, 2.0, 1.0, 1),
                (1, UNSETTLED_CODE, 9.0, 1),
            ]
        );
        assert_eq!(
            b.labels,
            [2, 1, 3, 0, 1, 2, 1, 4].map(Some).to_vec(),
            "{:?}",
            b.labels
        );
        // the first cell of attractor 2 is cell 0
        assert_eq!(b.attractors[2].seed, g.cell(0));
        // signatures from elsewhere: matched within ppv_tol of the range, or none
        let label = |s: Signature| b.attractor_of(&s).map(|a| a.label);
        assert_eq!(label(Signature::new(1, 1.0, 1.0099)), Some(1));
        assert_eq!(label(Signature::new(1, 1.0, 1.19)), Some(2));
        assert_eq!(label(Signature::new(1, 1.0, 1.1)), None);
        assert_eq!(label(Signature::new(2, 1.0, 1.0)), None);
        assert_eq!(label(Signature::new(1, UNSETTLED_CODE, 1.0)), Some(4));
        // any order of the same cells: the same attractors
        let mut rev: Vec<_> = sig.iter().rev().map(|s| Ok(*s)).collect();
        rev.rotate_left(3);
        let r = cluster(&g, &BasinOptions::default(), rev).unwrap();
        let got2: Vec<(i8, f64, f64, usize)> = r
            .attractors
            .iter()
            .map(|a| (a.state, a.motion, a.ppv_min, a.cells))
            .collect();
        assert_eq!(got, got2);
        assert!(
            b.attractors[1]
                .name()
                .starts_with("A1: unilateral period-1 ppv 1")
        );
    }

    /// Settled signature of a forced oscillator from `(q0, v0)`: period from the stroboscopic
    /// section after `transient` periods, ppv over the last period (dense steps).
    fn oscillator_cell<S: timestep::OdeSystem>(
        sys: &S,
        period: f64,
        q0: f64,
        v0: f64,
        transient: usize,
    ) -> Result<Signature, String> {
        let opts = timestep::Options {
            rtol: 1e-9,
            atol: 1e-11,
            h_max: period / 64.0,
            ..timestep::Options::default()
        };
        let co = timestep::ClassifyOptions {
            transient_periods: transient,
            n_points: 16,
            max_period: 4,
            ..timestep::ClassifyOptions::new(period)
        };
        let c = timestep::classify_motion(sys, 0.0, &[q0, v0], &co, &opts)
            .map_err(|e| e.to_string())?;
        let last = c.section.len() - 1;
        let y = c.section.point(last).to_vec();
        let t0 = c.section.t[last];
        let s = timestep::integrate(sys, t0, &y, t0 + period, &opts).map_err(|e| e.to_string())?;
        let q: Vec<f64> = s.y.iter().step_by(s.dim).copied().collect();
        let ppv = q.iter().copied().fold(f64::NEG_INFINITY, f64::max)
            - q.iter().copied().fold(f64::INFINITY, f64::min);
        Ok(Signature::new(Signature::NO_STATE, c.motion.code(), ppv))
    }

    /// Hardening Duffing `x'' + δx' + x + x³ = γ cos ωt` at δ = 0.1, γ = 0.3, ω = 1.6: inside
    /// its hysteresis band (three one-harmonic balance solutions).
    fn duffing() -> timestep::FirstOrder<timestep::Duffing> {
        timestep::FirstOrder(timestep::Duffing {
            delta: 0.1,
            alpha: 1.0,
            beta: 1.0,
            gamma: 0.3,
            omega: 1.6,
        })
    }

    /// The one-harmonic balance orbits `x = a cos ωt + b sin ωt` of [`duffing`]: with
    /// `κ = 1 − ω² + ¾A²`, `A²[κ² + (δω)²] = γ²`, `a = γκ/(κ² + (δω)²)`,
    /// `b = γδω/(κ² + (δω)²)`; the small and the large stable branch as (A, x(0), x'(0)).
    fn hbm_orbits() -> [(f64, f64, f64); 2] {
        let (d, g, w) = (0.1_f64, 0.3_f64, 1.6_f64);
        let f = |u: f64| u * ((1.0 - w * w + 0.75 * u).powi(2) + (d * w).powi(2)) - g * g;
        // bisection on the two outer roots of the cubic in u = A²
        let root = |mut lo: f64, mut hi: f64| {
            for _ in 0..200 {
                let m = 0.5 * (lo + hi);
                if f(lo) * f(m) <= 0.0 {
                    hi = m;
                } else {
                    lo = m;
                }
            }
            0.5 * (lo + hi)
        };
        let orbit = |u: f64| {
            let k = 1.0 - w * w + 0.75 * u;
            let den = k * k + (d * w).powi(2);
            (u.sqrt(), g * k / den, g * d * w / den * w)
        };
        // f(0) < 0, f(0.5) > 0 (small); f(2.1) < 0 (between middle and large), f(3) > 0
        [orbit(root(0.0, 0.5)), orbit(root(2.1, 3.0))]
    }

    #[test]
    fn hardening_duffing_has_two_basins_and_hbm_starts_land_on_their_orbit() {
        let sys = duffing();
        let period = 2.0 * std::f64::consts::PI / 1.6;
        // decay rate δ/2 = 0.05: e^{-0.05·100·3.93} ≈ 3e-9 after 100 periods
        let cell = |q: f64, v: f64| oscillator_cell(&sys, period, q, v, 100);
        let g = grid(6, 6);
        let b = basins(&g, &BasinOptions::default(), cell).unwrap();
        assert_eq!(b.failed, 0);
        assert_eq!(b.attractors.len(), 2, "{:?}", b.attractors);
        let sum: f64 = b.attractors.iter().map(|a| a.fraction).sum();
        assert!((sum - 1.0).abs() < 1e-12, "{sum}");
        let [small, large] = hbm_orbits();
        for (a, (amp, _, _)) in b.attractors.iter().zip([small, large]) {
            assert_eq!(a.motion, 1.0);
            // one harmonic: the third is a few % of the large orbit's amplitude
            assert!(
                (a.ppv / (2.0 * amp) - 1.0).abs() < 0.08,
                "ppv {} against 2A = {}",
                a.ppv,
                2.0 * amp
            );
            assert!(a.ppv_max / a.ppv_min - 1.0 < 1e-4, "{a:?}");
            assert!(a.cells > 0);
        }
        // cells around each HBM start land on that orbit
        for (k, (_, x0, v0)) in [small, large].into_iter().enumerate() {
            let near = BasinGrid::new(
                Axis::new(x0 - 0.02, x0 + 0.02, 2),
                Axis::new(v0 - 0.02, v0 + 0.02, 2),
            )
            .unwrap();
            let n = basins(&near, &BasinOptions::default(), cell).unwrap();
            assert_eq!(n.attractors.len(), 1, "{:?}", n.attractors);
            let p = n.attractors[0].ppv;
            assert!(
                (p / b.attractors[k].ppv - 1.0).abs() < 1e-4,
                "start near HBM orbit {k}: ppv {p}, basin attractor {}",
                b.attractors[k].ppv
            );
        }
    }

    #[test]
    fn monostable_linear_oscillator_has_one_basin() {
        let sys = timestep::LinearOscillator {
            omega0: 1.0,
            zeta: 0.1,
            force: 1.0,
            omega: 1.3,
        }
        .first_order();
        let period = 2.0 * std::f64::consts::PI / 1.3;
        let g = grid(4, 3);
        let b = basins(&g, &BasinOptions::default(), |q, v| {
            oscillator_cell(&sys, period, q, v, 60)
        })
        .unwrap();
        assert_eq!(b.attractors.len(), 1, "{:?}", b.attractors);
        assert_eq!(b.attractors[0].fraction, 1.0);
        // exact amplitude F/√((1−Ω²)² + (2ζΩ)²)
        let amp = 1.0 / ((1.0 - 1.69_f64).powi(2) + (0.26_f64).powi(2)).sqrt();
        assert!((b.attractors[0].ppv / (2.0 * amp) - 1.0).abs() < 1e-4);
    }

    #[test]
    fn bit_identical_for_one_and_two_threads() {
        let sys = duffing();
        let period = 2.0 * std::f64::consts::PI / 1.6;
        let g = grid(3, 3);
        let run = |n: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap()
                .install(|| {
                    basins(&g, &BasinOptions::default(), |q, v| {
                        oscillator_cell(&sys, period, q, v, 40)
                    })
                    .unwrap()
                })
        };
        let (a, b) = (run(1), run(2));
        assert_eq!(a.labels, b.labels);
        let bits = |x: &Basins| {
            x.cells
                .iter()
                .map(|c| c.as_ref().map(|s| s.ppv.to_bits()).unwrap_or(0))
                .collect::<Vec<_>>()
        };
        assert_eq!(bits(&a), bits(&b));
        assert_eq!(a.attractors, b.attractors);
    }
}
