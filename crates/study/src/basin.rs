//! Basin studies (`[basin]` in a study file): at fixed parameters, a grid of initial states
//! `(q, q̇)`, each cell one time-stepping point of the model started there; each cell's settled
//! long window is named by its attractor signature (rattle state `rsv`, `motion`, `ppv`), the
//! signatures are clustered into attractors and each attractor gets its basin fraction
//! ([`models::response::basin`], the one home of the clustering).
//!
//! ```toml
//! [basin]
//! q = { from = -3.0, to = 1.0, steps = 20 }      # initial q, 2 ..= 1000 values
//! q_dot = { from = -2.0, to = 2.0, steps = 20 }  # initial q̇, 2 ..= 1000 values
//! ppv_tol = 0.01                                 # relative ppv gap joining two cells
//! ```
//!
//! The grid sets the first two entries of the initial state; a model whose state is longer takes
//! the others from `initial = [...]`. A basin study has no `[sweep]`, `[sweep2]` nor
//! `[bifurcation]`, and its method must give the columns `ppv` and `motion` (time stepping);
//! `rsv` is used when present.
//!
//! **Outputs**: `<name>.csv`, one row per cell (`q`, `q_dot`, the model's columns, then
//! `attractor`, the cell's label; empty for a failed cell); `<name>_fractions.csv`, one row per
//! attractor (label, rsv, motion, ppv and its range over the cells, cells, fraction, the initial
//! state of its first cell) plus a `failed` row; `<name>_attractor_map.svg`, a categorical heat
//! map of the labels over (q, q̇). The cells are points of the study engine: they run in
//! parallel, shard, journal and merge like every study, and the labels are computed from the
//! complete, ordered records, so they do not depend on the thread count or the sharding.

use serde::{Deserialize, Serialize};

use crate::error::Error;
use models::response::basin::{Axis, BasinGrid, BasinOptions, Basins, Signature, cluster};
use plot::{Cell, HeatScale, Heatmap, Table};

/// The label column of a basin study's CSV.
pub const COLUMN: &str = "attractor";

/// Most attractors drawn with colours of their own on the map (the categorical palette); the
/// others share an `other` colour (their labels are in the CSV).
pub const MAP_ATTRACTORS: usize = 6;

/// One axis of the grid in a study file.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AxisSpec {
    /// First value.
    pub from: f64,
    /// Last value (> `from`).
    pub to: f64,
    /// Number of values (2 ..= [`models::response::basin::MAX_BASIN_AXIS`]).
    pub steps: i64,
}

fn default_tol() -> f64 {
    BasinOptions::default().ppv_tol
}

/// The `[basin]` table of a study file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BasinSpec {
    /// Initial displacement axis.
    pub q: AxisSpec,
    /// Initial velocity axis.
    pub q_dot: AxisSpec,
    /// Relative ppv gap that joins two periodic cells of the same state and period, in
    /// (0, 0.5] (default 0.01).
    #[serde(default = "default_tol")]
    pub ppv_tol: f64,
}

impl BasinSpec {
    /// The checked grid; errors name the key and its bound.
    pub fn grid(&self) -> Result<BasinGrid, Error> {
        let axis = |a: &AxisSpec, name: &str| {
            let steps = usize::try_from(a.steps).map_err(|_| {
                Error::StudyFile(format!(
                    "basin.{name}.steps must be in [2, {}], got {}",
                    models::response::basin::MAX_BASIN_AXIS,
                    a.steps
                ))
            })?;
            Ok::<_, Error>(Axis::new(a.from, a.to, steps))
        };
        BasinGrid::new(axis(&self.q, "q")?, axis(&self.q_dot, "q_dot")?)
            .map_err(|e| Error::StudyFile(e.to_string()))
    }

    /// The checked clustering options.
    pub fn options(&self) -> Result<BasinOptions, Error> {
        let o = BasinOptions {
            ppv_tol: self.ppv_tol,
            ..BasinOptions::default()
        };
        o.check().map_err(|e| Error::StudyFile(e.to_string()))?;
        Ok(o)
    }

    /// The initial state of cell `(q, q_dot)`: `base` with its first two entries replaced
    /// (`[q, q_dot]` without a base).
    pub fn initial(base: Option<&[f64]>, q: f64, q_dot: f64) -> Vec<f64> {
        let mut v = base.map_or_else(|| vec![0.0; 2], <[f64]>::to_vec);
        if v.len() < 2 {
            v.resize(2, 0.0);
        }
        v[0] = q;
        v[1] = q_dot;
        v
    }
}

/// Check that a method's output columns can name attractors: `ppv` and `motion` present.
pub fn check_outputs(model: &str, outputs: &[(String, String)]) -> Result<(), Error> {
    for need in ["ppv", "motion"] {
        if !outputs.iter().any(|(n, _)| n == need) {
            return Err(Error::StudyFile(format!(
                "a [basin] study needs the output columns `ppv` and `motion` (solver.method = \
                 \"time-stepping\"); {model} with this solver has no `{need}`"
            )));
        }
    }
    Ok(())
}

/// The signature of each cell from its record (`rsv`, `motion`, `ppv`; `rsv` absent: no state).
pub fn signatures(
    outputs: &[(String, String)],
    results: &[Result<Vec<f64>, String>],
) -> Vec<Result<Signature, String>> {
    let col = |name: &str| outputs.iter().position(|(n, _)| n == name);
    let (rsv, motion, ppv) = (col("rsv"), col("motion"), col("ppv"));
    results
        .iter()
        .map(|r| {
            let v = r.as_ref().map_err(Clone::clone)?;
            let get = |j: Option<usize>| j.and_then(|j| v.get(j).copied());
            let (Some(m), Some(p)) = (get(motion), get(ppv)) else {
                return Err("no `motion` or `ppv` column".to_owned());
            };
            let state = match get(rsv) {
                None => Signature::NO_STATE,
                Some(s)
                    if [0.0_f64, 1.0, 2.0]
                        .iter()
                        .any(|x| x.to_bits() == s.to_bits()) =>
                {
                    s as i8
                }
                Some(s) => return Err(format!("rsv = {s} is not a rattle state")),
            };
            let mut sig = Signature::new(state, m, p);
            sig.chaos_k = get(col("chaos_k")).unwrap_or(f64::NAN);
            Ok(sig)
        })
        .collect()
}

/// Cluster the records of a basin study.
pub fn basins_of(
    spec: &BasinSpec,
    outputs: &[(String, String)],
    results: &[Result<Vec<f64>, String>],
) -> Result<Basins, Error> {
    let grid = spec.grid()?;
    cluster(&grid, &spec.options()?, signatures(outputs, results))
        .map_err(|e| Error::Study(e.to_string()))
}

/// The label cell of cell `k` (empty text for a failed cell).
pub fn label_cell(b: &Basins, k: usize) -> Cell {
    match b.labels.get(k).copied().flatten() {
        Some(l) => Cell::Count(l as u64),
        None => Cell::Text(String::new()),
    }
}

/// The fractions table `<name>_fractions`: one row per attractor, then the failed cells.
pub fn fractions_table(name: &str, b: &Basins) -> Table {
    let mut t = Table::new(
        &format!("{name}_fractions"),
        &[
            (COLUMN, ""),
            ("rsv", "1"),
            ("motion", ""),
            ("ppv", "1"),
            ("ppv_min", "1"),
            ("ppv_max", "1"),
            ("cells", ""),
            ("fraction", "1"),
            ("seed_q", "1"),
            ("seed_q_dot", "1"),
        ],
    );
    for a in &b.attractors {
        let sig = Signature::new(a.state, a.motion, a.ppv);
        let _ = t.push(vec![
            Cell::Count(a.label as u64),
            if a.state >= 0 {
                Cell::Count(a.state as u64)
            } else {
                Cell::Text(String::new())
            },
            Cell::Text(sig.motion_label()),
            Cell::Num(a.ppv),
            Cell::Num(a.ppv_min),
            Cell::Num(a.ppv_max),
            Cell::Count(a.cells as u64),
            Cell::Num(a.fraction),
            Cell::Num(a.seed.0),
            Cell::Num(a.seed.1),
        ]);
    }
    let nan = Cell::Num(f64::NAN);
    let _ = t.push(vec![
        Cell::Text("failed".to_owned()),
        Cell::Text(String::new()),
        Cell::Text(String::new()),
        nan.clone(),
        nan.clone(),
        nan.clone(),
        Cell::Count(b.failed as u64),
        Cell::Num(b.failed_fraction()),
        nan.clone(),
        nan,
    ]);
    t
}

/// The categorical map `<name>_attractor_map` of the labels over (q, q̇); the attractors past
/// [`MAP_ATTRACTORS`] share one `other` colour. `None` if it cannot be built.
pub fn heat_map(name: &str, b: &Basins) -> Option<Heatmap> {
    let shown = b.attractors.len().min(MAP_ATTRACTORS);
    let mut states: Vec<(f64, String)> = b.attractors[..shown]
        .iter()
        .map(|a| {
            (
                a.label as f64,
                format!("{} ({:.0} %)", a.name(), 100.0 * a.fraction),
            )
        })
        .collect();
    let other = b.attractors.len() > MAP_ATTRACTORS;
    if other {
        states.push((
            MAP_ATTRACTORS as f64,
            format!("other ({} attractors)", b.attractors.len() - MAP_ATTRACTORS),
        ));
    }
    if states.is_empty() {
        return None;
    }
    let z: Vec<f64> = b
        .labels
        .iter()
        .map(|l| l.map_or(f64::NAN, |l| l.min(MAP_ATTRACTORS) as f64))
        .collect();
    Heatmap::new(
        &format!("{name}_attractor_map"),
        &format!("{name}: basins of attraction"),
        [("q(0)", "1"), ("q'(0)", "1"), (COLUMN, "")],
        b.grid.q.values(),
        b.grid.q_dot.values(),
        z,
        HeatScale::Categorical(states),
    )
    .ok()
}

/// The `basin` object of the JSON summary: the attractors and the failed fraction.
pub fn summary(b: &Basins) -> serde_json::Value {
    serde_json::json!({
        "grid": b.grid,
        "options": b.options,
        "attractors": b.attractors.iter().map(|a| serde_json::json!({
            "label": a.label,
            "name": a.name(),
            "rsv": a.state,
            "motion": Signature::new(a.state, a.motion, a.ppv).motion_label(),
            "ppv": a.ppv,
            "ppv_min": a.ppv_min,
            "ppv_max": a.ppv_max,
            "cells": a.cells,
            "fraction": a.fraction,
            "seed": [a.seed.0, a.seed.1],
        })).collect::<Vec<_>>(),
        "failed": b.failed,
        "failed_fraction": b.failed_fraction(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(text: &str) -> Result<BasinSpec, Error> {
        let s: BasinSpec = toml::from_str(text).map_err(|e| Error::StudyFile(e.to_string()))?;
        s.grid()?;
        s.options()?;
        Ok(s)
    }

    #[test]
    fn keys_are_checked() {
        let ok = "q = { from = -1, to = 1, steps = 3 }\nq_dot = { from = 0, to = 1, steps = 2 }";
        assert_eq!(spec(ok).unwrap().ppv_tol.to_bits(), 0.01_f64.to_bits());
        for (bad, key) in [
            (
                "q = { from = -1, to = 1, steps = 1 }\nq_dot = { from = 0, to = 1, steps = 2 }",
                "q.steps",
            ),
            (
                "q = { from = -1, to = 1, steps = -5 }\nq_dot = { from = 0, to = 1, steps = 2 }",
                "q.steps",
            ),
            (
                "q = { from = 1, to = 1, steps = 3 }\nq_dot = { from = 0, to = 1, steps = 2 }",
                "q.to",
            ),
            (
                "q = { from = -1, to = 1, steps = 3 }\nq_dot = { from = 0, to = nan, steps = 2 }",
                "q_dot.to",
            ),
            (
                "q = { from = -1, to = 1, steps = 1000 }\nq_dot = { from = 0, to = 1, steps = 1000 }",
                "cells",
            ),
            (&format!("{ok}\nppv_tol = 0.0"), "ppv_tol"),
            (&format!("{ok}\nppv_tol = 1.0"), "ppv_tol"),
            (&format!("{ok}\ntypo = 1"), "typo"),
            ("q = { from = -1, to = 1, steps = 3 }", "q_dot"),
        ] {
            let e = spec(bad).unwrap_err().to_string();
            assert!(e.contains(key), "{bad}: {e}");
        }
        assert_eq!(BasinSpec::initial(None, 1.0, 2.0), [1.0, 2.0]);
        assert_eq!(
            BasinSpec::initial(Some(&[0.0, 0.0, 5.0]), 1.0, 2.0),
            [1.0, 2.0, 5.0]
        );
    }
}
