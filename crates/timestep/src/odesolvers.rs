//! Backends built on `ode_solvers` 0.6 (`Dopri5`, `Dop853`) with this crate's event handling.
//!
//! `ode_solvers` offers no per-step control besides its `solout` callback, which sees every
//! accepted step `(t, y, y')`. Events are therefore detected on a cubic Hermite interpolant of
//! each accepted step (built from the end values and derivatives, local error O(h^4)), the
//! solver is stopped at the crossing step, the crossing is located on the interpolant, and the
//! solver is restarted from the start of that step with end time = event time, so that the
//! state at the event comes from the method itself. Output samples between steps also come
//! from the Hermite interpolant. Each segment between events re-selects its initial step.
//! State vectors are `nalgebra::DVector` (one heap allocation per stage inside `ode_solvers`),
//! so these backends are slower than [`crate::Method::DormandPrince54`].

use ode_solvers::dop_shared::IntegrationError;
use ode_solvers::{DVector, Dop853, Dopri5, OutputType, System};

use crate::options::{Method, Options};
use crate::record::{EventMonitor, Recorder};
use crate::solution::{Event, Solution, Stats, Status};
use crate::stepper::hermite;
use crate::system::{EventAction, OdeSystem};

struct Adapter<'a, S: ?Sized> {
    sys: &'a S,
    watch: bool,
    record: bool,
    tol: f64,
    t_prev: f64,
    y_prev: Vec<f64>,
    f_prev: Vec<f64>,
    y_last: Vec<f64>,
    f_last: Vec<f64>,
    buf: Vec<f64>,
    mon: EventMonitor,
    rec: Recorder<'static>,
    events: Vec<Event>,
    first_new: usize,
    hit: Option<(f64, f64, f64)>,
    stats: Stats,
    /// Accepted steps seen by `solout` (for the periodic deadline check).
    n_out: u64,
    /// `solout` stopped the integration at the thread's deadline.
    timed_out: bool,
}

impl<S: OdeSystem + ?Sized> System<f64, DVector<f64>> for &mut Adapter<'_, S> {
    fn system(&self, x: f64, y: &DVector<f64>, dy: &mut DVector<f64>) {
        self.sys.rhs(x, y.as_slice(), dy.as_mut_slice());
    }

    fn solout(&mut self, x: f64, y: &DVector<f64>, dy: &DVector<f64>) -> bool {
        let a = &mut **self;
        a.y_last.copy_from_slice(y.as_slice());
        a.f_last.copy_from_slice(dy.as_slice());
        let h = x - a.t_prev;
        if a.watch && a.mon.ne > 0 {
            a.sys.events(x, y.as_slice(), &mut a.mon.g_new);
            let (yp, fp, yl, fl) = (&a.y_prev, &a.f_prev, &a.y_last, &a.f_last);
            let mut dense = |th: f64, out: &mut [f64]| hermite(th, h, yp, fp, yl, fl, out);
            let found = a.mon.locate(
                a.sys,
                a.t_prev,
                h,
                a.tol,
                &mut a.buf,
                &mut dense,
                &mut a.stats,
            );
            if let Some(th) = found {
                a.hit = Some((a.t_prev, h, th));
                return true;
            }
            a.mon
                .commit(h, None, x, a.tol, &mut a.events, &mut a.first_new);
        }
        if a.record {
            let (yp, fp, yl, fl) = (&a.y_prev, &a.f_prev, &a.y_last, &a.f_last);
            let mut dense = |th: f64, out: &mut [f64]| hermite(th, h, yp, fp, yl, fl, out);
            a.rec.step(a.t_prev, h, yl, &mut a.buf, &mut dense);
        }
        a.t_prev = x;
        a.y_prev.copy_from_slice(&a.y_last);
        a.f_prev.copy_from_slice(&a.f_last);
        a.n_out += 1;
        if a.watch && ::system::deadline::expired_at_step(a.n_out) {
            a.timed_out = true;
            return true;
        }
        false
    }
}

fn solve<S: OdeSystem + ?Sized>(
    ad: &mut Adapter<'_, S>,
    method: Method,
    t: f64,
    t_end: f64,
    y: &[f64],
    opts: &Options,
    n_max: u32,
) -> Result<ode_solvers::dop_shared::Stats, IntegrationError> {
    let y0 = DVector::from_column_slice(y);
    let h_max = opts.h_max.min(t_end - t);
    let st = match method {
        Method::OdeSolversDop853 => {
            let mut s = Dop853::from_param(
                ad,
                t,
                t_end,
                t_end - t,
                y0,
                opts.rtol,
                opts.atol,
                0.9,
                0.0,
                0.333,
                6.0,
                h_max,
                opts.h_init.unwrap_or(0.0).min(h_max),
                n_max,
                u32::MAX,
                OutputType::Sparse,
            );
            s.integrate()?
        }
        _ => {
            let mut s = Dopri5::from_param(
                ad,
                t,
                t_end,
                t_end - t,
                y0,
                opts.rtol,
                opts.atol,
                0.9,
                0.04,
                0.2,
                10.0,
                h_max,
                opts.h_init.unwrap_or(0.0).min(h_max),
                n_max,
                u32::MAX,
                OutputType::Sparse,
            );
            s.integrate()?
        }
    };
    Ok(st)
}

pub(crate) fn run<S: OdeSystem + ?Sized>(
    sys: &S,
    t0: f64,
    y0: &[f64],
    t_end: f64,
    opts: &Options,
) -> Solution {
    let n = y0.len();
    let ne = if opts.events { sys.n_events() } else { 0 };
    let mut f0 = vec![0.0; n];
    sys.rhs(t0, y0, &mut f0);
    let mut ad = Adapter {
        sys,
        watch: true,
        record: true,
        tol: opts.event_tol,
        t_prev: t0,
        y_prev: y0.to_vec(),
        f_prev: f0.clone(),
        y_last: y0.to_vec(),
        f_last: f0,
        buf: vec![0.0; n],
        mon: EventMonitor::new(ne),
        rec: Recorder::new(n, &opts.output, t0, t_end, None),
        events: Vec::new(),
        first_new: 0,
        hit: None,
        stats: Stats {
            n_rhs: 1,
            ..Stats::default()
        },
        n_out: 0,
        timed_out: false,
    };
    ad.rec.initial(t0, y0);
    ad.mon.start(sys, t0, y0);
    let mut t = t0;
    let mut y = y0.to_vec();
    let mut status = Status::Completed;
    let mut ysave = vec![0.0; n];
    let mut steps_used: u64 = 0;
    while t < t_end {
        if ::system::deadline::expired() {
            status = Status::TimeLimit { t };
            break;
        }
        let budget = opts
            .max_steps
            .saturating_sub(steps_used)
            .min(u32::MAX as u64) as u32;
        ad.hit = None;
        ad.watch = true;
        ad.record = true;
        let res = solve_counted(
            &mut ad,
            opts.method,
            t,
            t_end,
            &y,
            opts,
            budget,
            &mut steps_used,
        );
        if let Err(e) = res {
            status = match e {
                IntegrationError::MaxNumStepReached { x, .. } => Status::MaxSteps { t: x },
                IntegrationError::StepSizeUnderflow { x } => Status::StepSizeUnderflow { t: x },
                IntegrationError::StiffnessDetected { x } => Status::StepSizeUnderflow { t: x },
            };
            t = ad.t_prev;
            y.copy_from_slice(&ad.y_prev);
            break;
        }
        let Some((ta, h, th)) = ad.hit else {
            if ad.timed_out {
                status = Status::TimeLimit { t: ad.t_prev };
                t = ad.t_prev;
                y.copy_from_slice(&ad.y_prev);
                break;
            }
            t = t_end;
            y.copy_from_slice(&ad.y_last);
            break;
        };
        // Restart loop (see `integrate`): re-integrate from the start of the crossing step up
        // to the located crossing, re-locate on the Hermite interpolant of the shortened step,
        // until the step end agrees with the crossing to `event_tol`.
        let ya = ad.y_prev.clone();
        let fa = ad.f_prev.clone();
        let (mut yb, mut fb) = (ad.y_last.clone(), ad.f_last.clone());
        let mut tb = ta + h;
        let mut th = th;
        let mut theta_star = None;
        ad.watch = false;
        ad.record = false;
        for pass in 0..8 {
            let hb = tb - ta;
            if (1.0 - th) * hb <= opts.event_tol || pass == 7 {
                theta_star = Some(th);
                break;
            }
            let t1 = ta + th * hb;
            ad.t_prev = ta;
            let budget = opts
                .max_steps
                .saturating_sub(steps_used)
                .min(u32::MAX as u64) as u32;
            let ok = t1 - ta > 1e3 * f64::EPSILON * ta.abs().max(1.0)
                && solve_counted(
                    &mut ad,
                    opts.method,
                    ta,
                    t1,
                    &ya,
                    opts,
                    budget,
                    &mut steps_used,
                )
                .is_ok();
            if ok {
                yb.copy_from_slice(&ad.y_last);
            } else {
                // too short to re-integrate: take the interpolant
                let mut buf = vec![0.0; n];
                hermite(th, hb, &ya, &fa, &yb, &fb, &mut buf);
                yb.copy_from_slice(&buf);
            }
            tb = t1;
            sys.rhs(tb, &yb, &mut fb);
            ad.stats.n_rhs += 1;
            sys.events(tb, &yb, &mut ad.mon.g_new);
            let hb = tb - ta;
            let mut buf = vec![0.0; n];
            let mut dense = |tt: f64, out: &mut [f64]| hermite(tt, hb, &ya, &fa, &yb, &fb, out);
            let found = ad.mon.locate(
                sys,
                ta,
                hb,
                opts.event_tol,
                &mut buf,
                &mut dense,
                &mut ad.stats,
            );
            match found {
                Some(x) => th = x,
                None => break,
            }
        }
        {
            let hb = tb - ta;
            let mut buf = vec![0.0; n];
            let mut dense = |tt: f64, out: &mut [f64]| hermite(tt, hb, &ya, &fa, &yb, &fb, out);
            ad.rec.step(ta, hb, &yb, &mut buf, &mut dense);
        }
        t = tb;
        y.copy_from_slice(&yb);
        ad.mon.commit(
            tb - ta,
            theta_star,
            t,
            opts.event_tol,
            &mut ad.events,
            &mut ad.first_new,
        );
        let mut stop = false;
        let mut changed = false;
        for k in ad.first_new..ad.events.len() {
            ad.stats.n_events += 1;
            ysave.copy_from_slice(&y);
            if sys.on_event(&ad.events[k], &mut y) == EventAction::Stop {
                stop = true;
            }
            changed |= ysave != y;
        }
        if changed {
            let mut work = vec![0.0; n];
            let mut fbuf = vec![0.0; n];
            ad.mon
                .refresh(sys, t, &y, 1e-6 * (tb - ta), &mut work, &mut fbuf);
            ad.stats.n_rhs += 1;
        }
        ad.t_prev = t;
        ad.y_prev.copy_from_slice(&y);
        sys.rhs(t, &y, &mut ad.f_prev);
        ad.stats.n_rhs += 1;
        if stop {
            status = Status::StoppedByEvent;
            break;
        }
    }
    Solution {
        dim: n,
        t: ad.rec.t,
        y: ad.rec.y,
        events: ad.events,
        t_final: t,
        y_final: y,
        h_last: f64::NAN,
        status,
        stats: ad.stats,
    }
}

fn solve_counted<S: OdeSystem + ?Sized>(
    ad: &mut Adapter<'_, S>,
    method: Method,
    t: f64,
    t_end: f64,
    y: &[f64],
    opts: &Options,
    n_max: u32,
    used: &mut u64,
) -> Result<(), IntegrationError> {
    let s = solve(ad, method, t, t_end, y, opts, n_max)?;
    ad.stats.n_rhs += u64::from(s.num_eval);
    ad.stats.n_accepted += u64::from(s.accepted_steps);
    ad.stats.n_rejected += u64::from(s.rejected_steps);
    *used += u64::from(s.accepted_steps) + u64::from(s.rejected_steps);
    Ok(())
}
