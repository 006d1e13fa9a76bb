//! Long-window rattle statistics of Eq. (9) with their spread ([`long_window`]).

use serde::{Deserialize, Serialize};

use super::integrate::{Stepping, run, run_to, system};
use super::model::Model;
use crate::Error;
use crate::response::{
    Crossing, Flank, Robust, WindowAccumulator, WindowDetail, WindowOptions, WindowStats,
};

/// Settings of [`long_window`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LongWindowOptions {
    /// Periods `T = 2π/ω̄_c` discarded before every window (`ζ = 0.01`: the free transient
    /// decays by `e^{-17}` per period at Table 1 values, so 10 periods leave none).
    pub transient_periods: f64,
    /// Periods of each window (≥ 50: the long window).
    pub periods: usize,
    /// Largest output sampling interval; the interval used is the largest `Δτ ≤ sample_step`
    /// that divides the period, so the section falls on the period starts (impact speeds are interpolated between samples; the
    /// state uses the located crossings, so no contact is missed). A window holds at most
    /// [`MAX_WINDOW_SAMPLES`] samples (`periods · T / Δτ`); more is an error naming this field.
    pub sample_step: f64,
    /// Largest integrator step.
    pub max_step: f64,
    /// Relative tolerance of the nominal runs.
    pub rtol: f64,
    /// The Runge–Kutta pair of every run ([`Stepping::long_window_method`]): with the default
    /// [`Stepping::Auto`], DOP853 at `rtol ≤` [`super::AUTO_DOP853_RTOL`], and also at
    /// `rtol ≤` [`super::AUTO_DOP853_ONE_FLANK_RTOL`] for the windows of a run whose transient
    /// crossed no back-flank edge; Dormand–Prince 5(4) otherwise.
    #[serde(default)]
    pub stepping: Stepping,
    /// The tolerance variant runs with `rtol / refine_factor` (default: the one accuracy
    /// check's factor, [`crate::contract::TIGHTER`]).
    pub refine_factor: f64,
    /// Minimum separation depth (fraction of `b̄`) for a unilateral period
    /// ([`WindowOptions::min_depth`]).
    pub min_depth: f64,
    /// Windows that a record may discard because they caught the end of a transient
    /// ([`WindowStats::transient`]: the section repeats over the window's last half but not over
    /// the whole). Near a bifurcation the transient outlasts `transient_periods`: at Liu
    /// Fig. 11, 180 and 225 rad/s under `Trig::Kernel`, the first 50-period window after 10
    /// periods is not periodic while the next one repeats to 1e-5 of the section tolerance (under
    /// the default `Trig::Table` the transients end sooner). A window before the first kept one
    /// whose section repeats nowhere is held until the next window is judged, and discarded
    /// (spending one of these) when the next one repeats: a transient that ended inside the
    /// window's last half (the record's hold). Two non-periodic windows in a row are kept as
    /// the motion, so this costs one window more at a chaotic point, and more only where a
    /// transient is seen.
    #[serde(default = "default_settle_windows")]
    pub settle_windows: usize,
    /// What each window measures ([`WindowDetail`]): everything by default; a caller that
    /// reads only the motion (state, ppv, section tests) saves the lines and impact speeds.
    #[serde(default)]
    pub detail: WindowDetail,
}

fn default_settle_windows() -> usize {
    2
}

impl Default for LongWindowOptions {
    fn default() -> Self {
        Self {
            transient_periods: 10.0,
            periods: 50,
            sample_step: 0.1,
            max_step: 0.5,
            rtol: 1e-8,
            stepping: Stepping::Auto,
            refine_factor: crate::contract::TIGHTER,
            min_depth: 0.0,
            settle_windows: default_settle_windows(),
            detail: WindowDetail::Full,
        }
    }
}

impl LongWindowOptions {
    fn validate(&self) -> Result<(), Error> {
        let pos = |name: &'static str, v: f64| {
            if v > 0.0 && v.is_finite() {
                Ok(())
            } else {
                Err(Error::invalid(
                    format!("liu2021.long_window.{name}"),
                    "> 0",
                    v,
                ))
            }
        };
        pos("sample_step", self.sample_step)?;
        pos("max_step", self.max_step)?;
        pos("rtol", self.rtol)?;
        if !(self.refine_factor >= 1.0 && self.refine_factor <= 1e6) {
            return Err(Error::invalid(
                "liu2021.long_window.refine_factor",
                "in [1, 1e6]",
                self.refine_factor,
            ));
        }
        if !(self.transient_periods >= 0.0 && self.transient_periods <= 1e5) {
            return Err(Error::invalid(
                "liu2021.long_window.transient_periods",
                "in [0, 1e5]",
                self.transient_periods,
            ));
        }
        if self.settle_windows > 1000 {
            return Err(Error::invalid(
                "liu2021.long_window.settle_windows",
                "at most 1000",
                self.settle_windows as f64,
            ));
        }
        if !(1..=100_000).contains(&self.periods) {
            return Err(Error::invalid(
                "liu2021.long_window.periods",
                "in [1, 100000]",
                self.periods as f64,
            ));
        }
        Ok(())
    }
}

/// The sampling interval of a window: the largest `Δτ ≤ sample_step` that divides the period
/// `T`, `Δτ = T/⌈T/sample_step⌉`, so that sample `k·T/Δτ` of a window falls on the start of
/// period `k` (to rounding). The stroboscopic section of [`window_stats`](crate::response::window_stats) is then the state at
/// `τ₀ + kT` itself: with a step that does not divide `T` the section point of period `k` lies
/// up to `Δτ` after the period start, at a phase that drifts from period to period, so that a
/// periodic orbit with fast impacts (Liu Fig. 11 above 185 rad/s: 63 impacts per period) did
/// not repeat on the section and its 0–1 test read the drift.
pub(crate) fn section_step(period: f64, sample_step: f64) -> f64 {
    period / (period / sample_step).ceil().max(1.0)
}

/// The most samples one window may hold (`periods · T / Δτ`; 800 MB of kept `t` and `q'`): a
/// larger request is an error before any integration, not an allocation failure after it. The
/// validation's windows hold about 10⁶ (50 periods at `Δτ = 0.1`).
pub const MAX_WINDOW_SAMPLES: f64 = 5e7;

/// The gap-edge crossings of a run's events (`system::gap_edges`: event 0 the back flank
/// `q = b̄`, event 1 the drive flank `q = −b̄`), entering where the motion enters contact.
fn crossings(events: &[timestep::Event]) -> Vec<Crossing> {
    events
        .iter()
        .map(|e| {
            let flank = if e.index == 0 {
                Flank::Back
            } else {
                Flank::Drive
            };
            let entering = match flank {
                Flank::Back => e.direction == system::Direction::Rising,
                Flank::Drive => e.direction == system::Direction::Falling,
            };
            Crossing {
                t: e.t,
                flank,
                entering,
            }
        })
        .collect()
}

/// One record of `windows` consecutive windows after the transient, from `start`, at `rtol`:
/// the statistics of the kept windows ([`Keeper`]), the periods integrated before the first of
/// them, and the work of the whole run.
fn record(
    model: &Model,
    o: &LongWindowOptions,
    start: (f64, f64),
    rtol: f64,
    windows: usize,
) -> Result<(Vec<WindowStats>, f64, timestep::Stats), Error> {
    let period = model.period();
    let dt = section_step(period, o.sample_step);
    // the accumulator keeps `t` and `q'` of every sample of a window (16 bytes each)
    let samples = o.periods as f64 * period / dt;
    if samples.is_nan() || samples > MAX_WINDOW_SAMPLES {
        return Err(Error::invalid(
            "liu2021.long_window.sample_step",
            format!(
                "at least periods·T/{MAX_WINDOW_SAMPLES:e} = {:e} (a window of at most {MAX_WINDOW_SAMPLES:e} samples)",
                o.periods as f64 * period / MAX_WINDOW_SAMPLES
            ),
            o.sample_step,
        ));
    }
    let mut io = super::IntegrationOptions {
        rtol,
        max_step: o.max_step,
        method: o.stepping,
        ..super::IntegrationOptions::default()
    };
    io.sample_step = dt;
    let (_, base) = system(model, &io)?;
    let t_rec = o.transient_periods * period;
    let warm = run(
        model,
        0.0,
        &[start.0, start.1],
        t_rec,
        base.clone().with_output(timestep::Output::Final),
    )?;
    let wo = WindowOptions {
        period,
        min_depth: o.min_depth,
        lines: [1, model.z2],
        detail: o.detail,
    };
    // the windows' pair: the transient tells whether the back flank is reached
    let back_flank = warm.events.iter().any(|e| e.index == 0);
    let base = base.with_method(o.stepping.long_window_method(rtol, back_flank));
    let mut work = warm.stats;
    let mut y = warm.y_final;
    let mut keeper = Keeper::new(windows, o.settle_windows);
    // at most `windows + settle_windows` windows ([`Keeper`])
    for w in 0..windows + o.settle_windows {
        if keeper.done() {
            break;
        }
        let t0 = t_rec + (w * o.periods) as f64 * period;
        let t1 = t0 + o.periods as f64 * period;
        // the samples are reduced as they are computed (`WindowAccumulator`, bit for bit
        // `window_stats` of the stored samples): the window's last sample is the uniform
        // grid's last within t1, or the final state where the grid stops a rounding error short
        let output = timestep::Output::Uniform { dt };
        let grid_last = output.last_sample(t0, t1).ok_or_else(|| {
            Error::Solver(format!("long window: no uniform grid from {t0} to {t1}"))
        })?;
        let close = grid_last < t1 - 1e-9 * period;
        let t_last = if close { t1 } else { grid_last };
        // a constant gap (constant b̄) needs no evaluation of the backlash law per sample
        let constant = model.readings.base_radius == super::BaseRadius::Mean;
        let gap = |tau: f64| {
            if constant {
                model.backlash
            } else {
                model.backlash_at(tau)
            }
        };
        let mut acc = WindowAccumulator::new(t0, t_last, gap, &wo)?;
        acc.reserve(((t1 - t0) / dt) as usize + 2);
        let mut sink = |t: f64, y: &[f64]| acc.push(t, y[0], y[1]);
        let rec = run_to(
            model,
            t0,
            &y,
            t1,
            base.clone().with_output(output),
            Some(&mut sink),
        )?;
        work.add(&rec.stats);
        if close {
            acc.push(rec.t_final, rec.y_final[0], rec.y_final[1]);
        }
        let stats = acc.finish(&crossings(&rec.events))?;
        y = rec.y_final;
        keeper.offer(stats, w);
    }
    let (out, kept_at) = keeper.finish();
    // periods integrated before the first kept window
    let before = kept_at.map_or(f64::NAN, |w| o.transient_periods + (w * o.periods) as f64);
    Ok((out, before, work))
}

/// The choice of the kept windows of one record, window by window.
///
/// * A window that holds the visible end of a transient ([`WindowStats::transient`]: not
///   periodic, but its last half is) is discarded.
/// * Before the first kept window, a window that is not periodic and shows no such end is held
///   until the next window confirms it (a settled record is not re-judged window by window; a
///   window shorter than [`crate::response::MIN_CLASSIFIED_PERIODS`] is not classified, and not
///   held). If the next window is periodic, or shows the end of a transient, the held
///   window was a transient that outlasted its last half, and it is discarded. Otherwise both
///   windows are the motion, and the held one is kept.
/// * Every discard spends one of `settle_windows`. Once they are spent, each window is kept as it
///   comes. A window still held when the record ends is kept unconfirmed.
///
/// Each offered window is kept, discarded or held, and a held window is settled by the next
/// offer. So `windows + settle_windows` offers always fill `windows` kept windows.
///
/// The hold matters at Liu Fig. 11, 190 rad/s (mean `b̄`): about one start in five within
/// `10⁻¹¹` of the default one leaves a unilateral transient that ends inside the last half of the
/// first window. Without the hold, that window was judged "settled, not periodic", with another
/// ppv, under each of the three `Trig` paths.
#[derive(Debug)]
struct Keeper {
    windows: usize,
    settle_windows: usize,
    discarded: usize,
    kept: Vec<WindowStats>,
    /// The index of the first kept window.
    first: Option<usize>,
    held: Option<(WindowStats, usize)>,
}

impl Keeper {
    fn new(windows: usize, settle_windows: usize) -> Self {
        Self {
            windows,
            settle_windows,
            discarded: 0,
            kept: Vec::with_capacity(windows),
            first: None,
            held: None,
        }
    }

    fn done(&self) -> bool {
        self.kept.len() >= self.windows
    }

    fn keep(&mut self, stats: WindowStats, w: usize) {
        if self.kept.len() < self.windows {
            self.first.get_or_insert(w);
            self.kept.push(stats);
        }
    }

    /// Window `w` of the record (windows are offered in order, without gaps).
    fn offer(&mut self, stats: WindowStats, w: usize) {
        if let Some((held, wh)) = self.held.take() {
            if stats.regular() || stats.transient() {
                self.discarded += 1;
            } else {
                self.keep(held, wh);
                self.keep(stats, w);
                return;
            }
        }
        if self.discarded < self.settle_windows {
            if stats.transient() {
                self.discarded += 1;
                return;
            }
            if self.kept.is_empty()
                && !stats.regular()
                && stats.periods >= crate::response::MIN_CLASSIFIED_PERIODS
            {
                self.held = Some((stats, w));
                return;
            }
        }
        self.keep(stats, w);
    }

    /// The kept windows and the index of the first.
    fn finish(mut self) -> (Vec<WindowStats>, Option<usize>) {
        if let Some((held, wh)) = self.held.take() {
            self.keep(held, wh);
        }
        (self.kept, self.first)
    }
}

/// The window kept by [`settled_window`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SettledWindow {
    /// The kept window's statistics (its motion: [`crate::response::window_motion`]).
    pub stats: WindowStats,
    /// Periods integrated before the kept window: `transient_periods + discarded·periods`.
    pub transient_periods: f64,
    /// Work counters of the whole run (transient, discarded windows, kept window).
    pub work: timestep::Stats,
}

/// The settled window of Eq. (9) at one point, without the variants of [`long_window`]: from
/// `start` (default: the quasi-static contact position at rest), after `transient_periods`,
/// windows of `periods` periods at `rtol`, each window that still holds the end of a transient
/// discarded ([`WindowStats::transient`], or a non-periodic window followed by a periodic one),
/// up to `settle_windows` of them. Returns the kept
/// window's statistics and the periods integrated before it
/// (`transient_periods + discarded·periods`, at most
/// `transient_periods + settle_windows·periods`). Its motion is
/// [`crate::response::window_motion`]: periodic, quasi-periodic, chaotic, or unsettled (still a
/// transient at the cap, or fewer than 20 periods). With the same options the window is the
/// nominal window of [`long_window`] bit for bit.
///
/// # Errors
/// Invalid options (as [`long_window`]) or a failed integration.
pub fn settled_window(
    model: &Model,
    options: &LongWindowOptions,
    start: Option<(f64, f64)>,
) -> Result<SettledWindow, Error> {
    options.validate()?;
    let start = start.unwrap_or((model.static_position(0.0), 0.0));
    let (mut w, before, work) = record(model, options, start, options.rtol, 1)?;
    let stats = w
        .pop()
        .ok_or_else(|| Error::Solver("empty window".into()))?;
    Ok(SettledWindow {
        stats,
        transient_periods: before,
        work,
    })
}

/// Long-window statistics of Eq. (9) at one point, with their spread over two tolerances, two
/// windows and two initial states.
///
/// Runs, each after `transient_periods`:
/// * nominal: from the quasi-static contact position at rest, `rtol`, two consecutive windows
///   of `periods` (the first is [`Robust::nominal`], the second the variant `window B`);
/// * `rtol/refine`: the same start with the tolerance divided by `refine_factor`;
/// * `other start`: from the middle of the gap at rest (`q = q' = 0`), at `rtol`.
///
/// Each run samples at the largest step `≤ sample_step` that divides the period, so the
/// stroboscopic section is the state at the period starts (`T/⌈T/sample_step⌉`), and discards up
/// to `settle_windows` windows that still hold the end of a transient
/// ([`WindowStats::transient`]). The statistics ([`crate::response::window_stats`]) use the
/// located gap-edge crossings, so a contact shorter than a sample step still counts.
///
/// Memoised while a [`crate::memo::Session`] is open (key: the model and the options).
pub fn long_window(model: &Model, options: &LongWindowOptions) -> Result<Robust, Error> {
    crate::memo::cached(
        "liu2021::long_window",
        || format!("{model:?}|{options:?}"),
        || Ok(robust_window(model, options, None)?.0),
    )
}

/// [`long_window`] with the nominal runs (both windows and the `rtol/refine` variant) from
/// `start` (default: the quasi-static contact position at rest; the `other start` variant
/// starts from the middle of the gap at rest either way), and the nominal window as a
/// [`SettledWindow`] whose `work` counts every run of the variants.
///
/// # Errors
/// Invalid options or a failed integration.
pub fn robust_window(
    model: &Model,
    options: &LongWindowOptions,
    start: Option<(f64, f64)>,
) -> Result<(Robust, SettledWindow), Error> {
    options.validate()?;
    let rest = start.unwrap_or((model.static_position(0.0), 0.0));
    let (mut nominal, before, mut work) = record(model, options, rest, options.rtol, 2)?;
    let window_b = nominal
        .pop()
        .ok_or_else(|| Error::Solver("empty window".into()))?;
    let nominal = nominal
        .pop()
        .ok_or_else(|| Error::Solver("empty window".into()))?;
    let (tight, _, w_tight) = record(
        model,
        options,
        rest,
        options.rtol / options.refine_factor,
        1,
    )?;
    let (other, _, w_other) = record(model, options, (0.0, 0.0), options.rtol, 1)?;
    work.add(&w_tight);
    work.add(&w_other);
    let mut variants = vec![("window B".to_owned(), window_b)];
    variants.extend(tight.into_iter().map(|w| ("rtol/refine".to_owned(), w)));
    variants.extend(other.into_iter().map(|w| ("other start".to_owned(), w)));
    let settled = SettledWindow {
        stats: nominal,
        transient_periods: before,
        work,
    };
    Ok((Robust { nominal, variants }, settled))
}

#[cfg(test)]
mod tests {
    use super::super::params::{BaseRadius, table1};
    use super::*;
    use crate::liu2021::RattleState;
    use crate::response::{assert_motion_only, motion_fields};

    fn model(omega1: f64) -> Model {
        model_with(omega1, true)
    }

    /// Table 1 at `omega1`, with the mean base radius (a constant gap) when `mean`.
    fn model_with(omega1: f64, mean: bool) -> Model {
        let mut p = table1();
        p.omega1 = omega1;
        if mean {
            p.readings.base_radius = BaseRadius::Mean;
        }
        p.model().unwrap()
    }

    /// A record reduces its samples while it integrates (`WindowAccumulator` fed by
    /// `timestep::integrate_streamed`); the result is, bit for bit, that of storing the samples
    /// and calling `window_stats` on them, as the record did before: in bilateral rattle
    /// (located crossings on both flanks) with a constant gap, and in unilateral rattle with
    /// the gap law evaluated at every sample.
    #[test]
    fn a_streamed_window_is_the_stored_one_bit_for_bit() {
        for (omega1, mean) in [(200.0, true), (160.0, false)] {
            let m = model_with(omega1, mean);
            let o = LongWindowOptions {
                transient_periods: 1.0,
                periods: 20,
                settle_windows: 0,
                sample_step: 0.5,
                rtol: 1e-6,
                ..LongWindowOptions::default()
            };
            let streamed = settled_window(&m, &o, None).unwrap();

            // the stored path
            let period = m.period();
            let dt = section_step(period, o.sample_step);
            let io = super::super::IntegrationOptions {
                rtol: o.rtol,
                max_step: o.max_step,
                method: o.stepping,
                sample_step: dt,
                ..super::super::IntegrationOptions::default()
            };
            let (_, base) = system(&m, &io).unwrap();
            let t0 = o.transient_periods * period;
            let y0 = [m.static_position(0.0), 0.0];
            let warm = run(
                &m,
                0.0,
                &y0,
                t0,
                base.clone().with_output(timestep::Output::Final),
            )
            .unwrap();
            let back = warm.events.iter().any(|e| e.index == 0);
            let base = base.with_method(o.stepping.long_window_method(o.rtol, back));
            let t1 = t0 + o.periods as f64 * period;
            let rec = run(
                &m,
                t0,
                &warm.y_final,
                t1,
                base.with_output(timestep::Output::Uniform { dt }),
            )
            .unwrap();
            let crossings = crossings(&rec.events);
            assert!(!crossings.is_empty(), "{omega1}: no crossing exercised");
            let stored = crate::response::window_stats(
                &rec.t,
                &rec.component(0),
                &rec.component(1),
                |tau| if mean { m.backlash } else { m.backlash_at(tau) },
                &crossings,
                &WindowOptions {
                    period,
                    min_depth: o.min_depth,
                    lines: [1, m.z2],
                    detail: o.detail,
                },
            )
            .unwrap();
            let json = |w: &WindowStats| serde_json::to_string(w).unwrap();
            assert_eq!(json(&streamed.stats), json(&stored), "{omega1}");
            assert_eq!(streamed.stats.ppv.to_bits(), stored.ppv.to_bits());
            assert_eq!(
                streamed.stats.line_coherent.map(f64::to_bits),
                stored.line_coherent.map(f64::to_bits)
            );
            assert!(stored.drive.count + stored.back.count > 0);
        }
    }

    /// [`WindowDetail::Motion`] measures the motion bit for bit as [`WindowDetail::Full`] does
    /// (state, fractions, extremes, depth, impact counts, section tests, the windows a transient
    /// discards), and leaves the lines and impact speeds NaN: at bilateral points (200 and
    /// 180 rad/s, constant gap) and a unilateral one (160 rad/s, the gap law per sample), each
    /// with one more window allowed for a transient.
    #[test]
    fn motion_detail_is_the_full_motion_bit_for_bit() {
        for (omega1, mean) in [(200.0, true), (160.0, false), (180.0, true)] {
            let m = model_with(omega1, mean);
            let full = LongWindowOptions {
                transient_periods: 1.0,
                periods: 20,
                settle_windows: 1,
                rtol: 1e-6,
                ..LongWindowOptions::default()
            };
            let motion = LongWindowOptions {
                detail: WindowDetail::Motion,
                ..full
            };
            let (a, b) = (
                settled_window(&m, &full, None).unwrap(),
                settled_window(&m, &motion, None).unwrap(),
            );
            let (f, w) = (&a.stats, &b.stats);
            assert_eq!(motion_fields(f), motion_fields(w), "{omega1}");
            assert_eq!(a.transient_periods.to_bits(), b.transient_periods.to_bits());
            assert_eq!(
                a.work.n_accepted, b.work.n_accepted,
                "{omega1}: the same steps"
            );
            assert!(
                f.drive.count + f.back.count > 0,
                "{omega1}: impacts exercised"
            );
            assert!(f.line_incoherent.iter().all(|x| x.is_finite()));
            assert!(f.drive.mean_speed.is_finite() && f.drive.max_speed.is_finite());
            assert_motion_only(w);
        }
    }

    /// A window of more samples than [`MAX_WINDOW_SAMPLES`] is refused before any integration,
    /// naming the sample step and its bound; one at the limit's order is accepted.
    #[test]
    fn an_absurd_window_is_an_error_not_an_allocation() {
        let m = model(160.0);
        let o = LongWindowOptions {
            periods: 100_000,
            sample_step: 1e-3,
            ..LongWindowOptions::default()
        };
        match settled_window(&m, &o, None) {
            Err(Error::InvalidParameter { field, .. }) => {
                assert_eq!(field, "liu2021.long_window.sample_step");
            }
            other => panic!("expected an invalid sample step, got {other:?}"),
        }
        assert!(long_window(&m, &o).is_err());
    }

    /// A synthetic window: `P` periodic, `T` the end of a transient (its last half periodic),
    /// `C` not periodic; `tag` marks it (as its ppv).
    fn win(kind: char, tag: f64) -> WindowStats {
        WindowStats {
            periods: 50,
            state: RattleState::Bilateral,
            fraction: [0.0, 0.0, 1.0],
            ppv: tag,
            q_min: 0.0,
            q_max: tag,
            max_depth: 1.0,
            drive: Default::default(),
            back: Default::default(),
            line_coherent: [0.0; 2],
            line_incoherent: [0.0; 2],
            chaos_k: if kind == 'P' { 0.0 } else { 0.9 },
            tail_regular: kind != 'C',
            period_multiple: usize::from(kind == 'P'),
        }
    }

    /// The kept windows' tags and the first kept index, offering `kinds` in order as `record`
    /// does (stopping once `windows` are kept).
    fn keep(kinds: &str, windows: usize, settle: usize) -> (Vec<f64>, Option<usize>) {
        let mut k = Keeper::new(windows, settle);
        let mut offered = 0;
        for (w, kind) in kinds.chars().enumerate() {
            if k.done() {
                break;
            }
            k.offer(win(kind, w as f64), w);
            offered += 1;
        }
        assert!(offered <= windows + settle, "{kinds}: {offered} offers");
        let (kept, first) = k.finish();
        (kept.iter().map(|s| s.ppv).collect(), first)
    }

    /// The settling rule of [`Keeper`], window by window: a transient window is discarded; a
    /// non-periodic window before the first kept one is held and discarded when the next one is
    /// periodic or transient, kept when the next one is not periodic either; after the first
    /// kept window nothing is held; the budget bounds the discards and a held window at the end
    /// of the budget is kept.
    #[test]
    #[allow(clippy::float_cmp)] // exact: the tags are assigned, never computed
    fn a_window_is_judged_not_periodic_only_when_the_next_one_is_not_either() {
        // the old rule, unchanged
        assert_eq!(keep("P", 1, 2), (vec![0.0], Some(0)));
        assert_eq!(keep("TP", 1, 2), (vec![1.0], Some(1)));
        assert_eq!(keep("TTP", 1, 1), (vec![1.0], Some(1)));
        // a transient that ends inside the first window's last half (190 rad/s)
        assert_eq!(keep("CP", 1, 2), (vec![1.0], Some(1)));
        assert_eq!(keep("CTP", 1, 2), (vec![2.0], Some(2)));
        // chaos: two non-periodic windows in a row, the first one kept
        assert_eq!(keep("CC", 1, 2), (vec![0.0], Some(0)));
        assert_eq!(keep("CCC", 2, 2), (vec![0.0, 1.0], Some(0)));
        assert_eq!(keep("TCC", 1, 2), (vec![1.0], Some(1)));
        // no budget: nothing is held
        assert_eq!(keep("C", 1, 0), (vec![0.0], Some(0)));
        // the budget spent on the hold: the next window is kept as it comes
        assert_eq!(keep("CT", 1, 1), (vec![1.0], Some(1)));
        assert_eq!(keep("TCP", 1, 1), (vec![1.0], Some(1)));
        // after the first kept window, a record is not re-judged (window B of a chaotic-looking
        // tail stays a variant)
        assert_eq!(keep("PC", 2, 2), (vec![0.0, 1.0], Some(0)));
        assert_eq!(keep("CPC", 2, 2), (vec![1.0, 2.0], Some(1)));
        // a held window at the end of the offers is kept unconfirmed
        let mut k = Keeper::new(1, 1);
        k.offer(win('C', 7.0), 0);
        assert!(!k.done());
        assert_eq!(k.finish().0[0].ppv, 7.0);
        // an unclassified (short) window is not held
        let mut k = Keeper::new(1, 1);
        k.offer(
            WindowStats {
                periods: 2,
                ..win('C', 3.0)
            },
            0,
        );
        assert!(k.done());
    }

    /// Below the unilateral onset (Table 1, 120 rad/s) the gears stay in drive-flank contact
    /// in every period of every variant, with no back-flank impacts.
    #[test]
    #[allow(clippy::float_cmp)] // exact: 3 periods given, 3 used
    fn no_rattle_point_is_robustly_no_rattle() {
        let o = LongWindowOptions {
            periods: 2,
            transient_periods: 3.0,
            ..LongWindowOptions::default()
        };
        let r = long_window(&model(120.0), &o).unwrap();
        assert_eq!(r.state(), Some(RattleState::NoRattle), "{}", r.describe());
        // the settled window is the nominal window bit for bit, and the robust window's spread
        // is long_window's; the work counts every run
        let s = settled_window(&model(120.0), &o, None).unwrap();
        // (Debug text: chaos_k is NaN below 20 periods, and NaN != NaN)
        let text = |w: &WindowStats| format!("{w:?}");
        assert_eq!(text(&s.stats), text(&r.nominal));
        assert_eq!(s.transient_periods, 3.0);
        let (rr, rs) = robust_window(&model(120.0), &o, None).unwrap();
        assert_eq!(format!("{rr:?}"), format!("{r:?}"));
        assert!(
            rs.work.n_rhs > 3 * s.work.n_rhs,
            "{:?} {:?}",
            rs.work,
            s.work
        );
        assert_eq!(r.nominal.back.count, 0);
        assert_eq!(r.variants.len(), 3);
        assert!(r.ppv_spread() < 1e-3, "{}", r.describe());
    }

    #[test]
    fn invalid_options_are_errors() {
        let m = model(160.0);
        for o in [
            LongWindowOptions {
                periods: 0,
                ..LongWindowOptions::default()
            },
            LongWindowOptions {
                rtol: f64::NAN,
                ..LongWindowOptions::default()
            },
            LongWindowOptions {
                min_depth: 1.5,
                periods: 1,
                transient_periods: 0.0,
                ..LongWindowOptions::default()
            },
            LongWindowOptions {
                refine_factor: 0.5,
                ..LongWindowOptions::default()
            },
        ] {
            assert!(long_window(&m, &o).is_err(), "{o:?}");
        }
    }
}
