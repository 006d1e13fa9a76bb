//! The order the studies start in, and the progress of a run in expected CPU seconds.
//!
//! Both rest on one table: each study's CPU seconds as measured by the cost table of a full run
//! (`validation/stats/cost.csv`, [`crate::cost_csv`]). It changes *when* a study starts and what
//! the progress bar shows, never what a study computes. A study missing from the table (a new
//! one) counts [`UNKNOWN_CPU_SECONDS`]; refresh the table from a new cost table when the costs
//! move (the test `schedule::tests::every_study_has_a_figure` lists the studies without one).

use crate::study::Study;

/// Expected CPU seconds of a study that the table of measured costs does not list.
pub const UNKNOWN_CPU_SECONDS: f64 = 5.0;

/// CPU seconds per study, from the cost table of a fresh-clone `cargo xtask validate` on 2 cores
/// (AMD EPYC, 2026-11-30, round 36; `liu2021-basins` at its own cost, 18.2 s with `validate
/// --only`, which the full run charges to the parameter sweeps that reach its memo first;
/// `yu2021-fig12-phase` and `yu2021-fig11-spectrum` from round 38's full run, after their
/// cheaper Lyapunov Jacobian), to 0.1 s (at least 0.1); see the module docs. Only the ratios matter (order and progress).
const EXPECTED_CPU_SECONDS: &[(&str, f64)] = &[
    ("liu2021-fig12-14-parameter-sweeps", 200.8),
    ("liu2021-design-charts", 277.1),
    ("liu2021-orbit-branch", 56.5),
    ("liu2021-fig11-speed-sweep", 58.2),
    ("liu2021-fig15-load-sweep", 37.2),
    ("yu2021-df-rms-sweeps", 38.1),
    ("liu2021-readings-speed-thresholds", 17.1),
    ("liu2021-fig11-continuation", 4.4),
    ("liu2021-basins", 18.2),
    ("liu2021-table2-amplitude-ratio", 22.2),
    ("yu2021-sensitivity", 15.3),
    ("karpov2017-fig3-time-series", 6.5),
    ("yu2021-fig14-rms", 6.4),
    ("yu2021-fig13-df", 3.5),
    ("yu2021-fig9-11-readings", 4.1),
    ("liu2021-fig8-10-responses", 0.3),
    ("yu2021-d-trends", 2.7),
    ("yu2021-chen-amplitude", 1.4),
    ("liu2021-fig17-spectrum", 0.7),
    ("yu2021-fig12-phase", 6.3),
    ("yu2021-fig10-dte", 0.5),
    ("yu2021-fig10-scaling", 0.5),
    ("yu2021-fig11-spectrum", 3.4),
    ("yu2021-fig9-dynamic-backlash", 0.2),
    ("karpov2017-eq4-speed-fluctuation", 0.1),
    ("karpov2017-eq6-max-acceleration", 0.1),
    ("karpov2017-table1", 0.1),
    ("karpov2017-fig1-centrodes", 0.1),
    ("karpov2017-fig2-ratio-shape", 0.1),
    ("karpov2017-sect4-sinusoidal-j2", 0.1),
    ("karpov2017-fig4-a-vs-omega", 0.1),
    ("karpov2017-fig5-a-vs-b-k", 0.1),
    ("karpov2017-fig6-a-vs-b-xi", 0.1),
    ("liu2021-table2-frequencies", 0.1),
    ("yu2021-eq16-pressure-angle", 0.1),
    ("yu2021-fig4-constant-backlash", 0.1),
];

/// The expected CPU seconds of the study `id` (module docs).
pub fn expected_cpu_seconds(id: &str) -> f64 {
    EXPECTED_CPU_SECONDS
        .iter()
        .find(|(k, _)| *k == id)
        .map_or(UNKNOWN_CPU_SECONDS, |&(_, v)| v)
}

/// Indices of `studies` in the order they start: the largest expected CPU time first, ties in
/// input order (a stable sort, so the order is the same on every run and platform).
pub fn longest_first(studies: &[Study]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..studies.len()).collect();
    order.sort_by(|&a, &b| {
        expected_cpu_seconds(studies[b].id).total_cmp(&expected_cpu_seconds(studies[a].id))
    });
    order
}

/// Where a run stands, for a progress bar.
#[derive(Debug, Clone, PartialEq)]
pub struct RunProgress {
    /// Studies finished.
    pub studies_done: usize,
    /// Studies in the run.
    pub studies_total: usize,
    /// Work done, in expected CPU seconds: the expected seconds of the finished studies plus,
    /// for each running one, the CPU seconds its account has been charged so far (at most 95 %
    /// of its expected seconds until it finishes). Never decreases; equals
    /// [`RunProgress::work_total`] exactly when every study has finished.
    ///
    /// A running study counts its CPU time, not the fraction of its points done: the points of
    /// one study differ in cost by orders of magnitude (`liu2021-design-charts`: 3200 map cells
    /// of about 50 ms, then twenty continuation branches of several seconds each), so a count
    /// of points would run ahead of the work (an ETA of about a third of the time left). CPU
    /// time reaches an account when a sweep point or an account's scope ends
    /// (`system::account`), so a study counts in steps of its points, and one without sweep
    /// points only when it ends.
    pub work_done: f64,
    /// The expected CPU seconds of all the studies of the run.
    pub work_total: f64,
    /// Sweep points finished, over all studies.
    pub points_done: u64,
    /// The study that finished last, if any.
    pub last_finished: Option<&'static str>,
}

/// Computes [`RunProgress`] from the studies' accounts (see [`RunProgress::work_done`]).
#[derive(Debug)]
pub struct ProgressMeter {
    expected: Vec<f64>,
    done: Vec<bool>,
    high_water: f64,
    last_finished: Option<&'static str>,
}

impl ProgressMeter {
    /// A meter for `studies` (their accounts are passed to [`ProgressMeter::read`]).
    pub fn new(studies: &[Study]) -> ProgressMeter {
        ProgressMeter {
            expected: studies.iter().map(|s| expected_cpu_seconds(s.id)).collect(),
            done: vec![false; studies.len()],
            high_water: 0.0,
            last_finished: None,
        }
    }

    /// Mark study `i` finished.
    pub fn finished(&mut self, i: usize, id: &'static str) {
        if let Some(d) = self.done.get_mut(i) {
            *d = true;
            self.last_finished = Some(id);
        }
    }

    /// The progress now, from the accounts (one per study, in order).
    pub fn read(&mut self, accounts: &[std::sync::Arc<system::account::Account>]) -> RunProgress {
        let mut work = 0.0;
        let mut points = 0;
        for (i, e) in self.expected.iter().enumerate() {
            let u = accounts.get(i).map(|a| a.usage()).unwrap_or_default();
            points += u.points;
            if self.done[i] {
                work += e;
            } else if u.cpu_seconds.is_finite() {
                work += u.cpu_seconds.clamp(0.0, 0.95 * e);
            }
        }
        let total: f64 = self.expected.iter().sum();
        let studies_done = self.done.iter().filter(|d| **d).count();
        self.high_water = if studies_done == self.done.len() {
            total
        } else {
            self.high_water.max(work).min(total)
        };
        RunProgress {
            studies_done,
            studies_total: self.done.len(),
            work_done: self.high_water,
            work_total: total,
            points_done: points,
            last_finished: self.last_finished,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_study_has_a_figure() {
        let missing: Vec<&str> = crate::all_studies()
            .iter()
            .map(|s| s.id)
            .filter(|id| !EXPECTED_CPU_SECONDS.iter().any(|(k, _)| k == id))
            .collect();
        assert!(
            missing.is_empty(),
            "studies without an expected CPU time (schedule.rs): {missing:?}"
        );
        // no stale entries either
        for (k, v) in EXPECTED_CPU_SECONDS {
            assert!(
                crate::all_studies().iter().any(|s| s.id == *k),
                "stale: {k}"
            );
            assert!(v.is_finite() && *v > 0.0);
        }
    }

    #[test]
    fn longest_first_is_a_stable_permutation() {
        let studies = crate::all_studies();
        let order = longest_first(&studies);
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..studies.len()).collect::<Vec<_>>());
        for w in order.windows(2) {
            let (a, b) = (
                expected_cpu_seconds(studies[w[0]].id),
                expected_cpu_seconds(studies[w[1]].id),
            );
            match a.total_cmp(&b) {
                std::cmp::Ordering::Greater => {}
                std::cmp::Ordering::Equal => assert!(w[0] < w[1]),
                std::cmp::Ordering::Less => panic!("{a} before {b}"),
            }
        }
    }

    #[test]
    fn meter_is_monotone_and_ends_at_the_total() {
        let studies: Vec<Study> = crate::all_studies().into_iter().take(3).collect();
        let accounts: Vec<_> = studies
            .iter()
            .map(|s| system::account::Account::new(s.id))
            .collect();
        let mut m = ProgressMeter::new(&studies);
        let p0 = m.read(&accounts);
        assert_eq!((p0.studies_done, p0.work_done.to_bits()), (0, 0));
        // some points of the first study: the CPU time they took, below 95 % of its expected
        // time (each point spins until its thread has used 2 ms of CPU, for at most 1 s of
        // wall time: where the thread clock cannot be read it stays at 0, and the assertion
        // below fails instead of the loop running on)
        let spin = |x: &u64| {
            let t0 = system::account::thread_cpu_ns();
            let wall = std::time::Instant::now();
            let mut k = *x;
            while system::account::thread_cpu_ns() < t0 + 2_000_000
                && wall.elapsed() < std::time::Duration::from_secs(1)
            {
                k = std::hint::black_box(k.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1));
            }
            k
        };
        system::account::scope(&accounts[0], || {
            system::sweep::sweep(&[1, 2, 3, 4], spin, None)
        });
        let p1 = m.read(&accounts);
        let cpu = accounts[0].usage().cpu_seconds;
        assert!(cpu >= 0.008, "{cpu}");
        assert_eq!(p1.work_done.to_bits(), cpu.to_bits());
        assert!(p1.work_done < p1.work_total);
        assert_eq!(p1.points_done, 4);
        let mut last = p1.work_done;
        for (i, s) in studies.iter().enumerate() {
            m.finished(i, s.id);
            let p = m.read(&accounts);
            assert!(p.work_done >= last);
            last = p.work_done;
        }
        let end = m.read(&accounts);
        assert_eq!(end.work_done.to_bits(), end.work_total.to_bits());
        assert_eq!(end.studies_done, 3);
    }

    /// A running study's share is the CPU time charged to it, capped at 95 % of its expected
    /// time, whatever the fraction of its points: all points of the cheap first part of a study
    /// done do not make it look done (the optimistic ETA of round 22).
    #[test]
    fn a_running_study_counts_its_cpu_not_its_points() {
        let studies: Vec<Study> = crate::all_studies()
            .into_iter()
            .filter(|s| s.id == "liu2021-design-charts")
            .collect();
        let e = expected_cpu_seconds(studies[0].id);
        let account = system::account::Account::new(studies[0].id);
        let accounts = [account];
        let mut m = ProgressMeter::new(&studies);
        // every planned point done at (almost) no CPU: the old meter read 95 % here
        system::account::scope(&accounts[0], || {
            system::sweep::sweep(&[1u32, 2, 3], |x| x + 1, None)
        });
        let p = m.read(&accounts);
        assert_eq!(p.points_done, 3);
        let cpu = accounts[0].usage().cpu_seconds;
        assert!(
            p.work_done <= cpu && p.work_done < 0.01 * e,
            "{} of {e}",
            p.work_done
        );
        m.finished(0, studies[0].id);
        assert_eq!(m.read(&accounts).work_done.to_bits(), e.to_bits());
    }
}
