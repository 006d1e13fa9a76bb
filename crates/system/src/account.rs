//! Work accounting: how many points, integrator steps, right-hand-side calls and CPU seconds a
//! piece of work (a validation study, a user study) cost, across the threads that did it.
//!
//! An [`Account`] is made by whoever wants the figures and put in force with [`scope`]. Like the
//! [deadline](crate::deadline) it is *ambient*, a thread-local, so it reaches the engines
//! through any model without a new argument on every API between them; unlike the deadline it
//! follows the work onto other threads: [`crate::sweep::sweep`] takes the account in force where
//! it is called and puts it in force around every point, on whichever thread runs the point.
//!
//! * **Points**: the points of every sweep run under the account (nested sweeps count at each
//!   level).
//! * **Steps and right-hand-side calls**: the time integrators of `geardyn-timestep` add their
//!   counters at the end of each integration ([`record_steps`]).
//! * **CPU time** is *exclusive*: the calling thread's CPU clock ([`thread_cpu_ns`]) is read
//!   when an account is put in force and when it is left, and the time between goes to the
//!   innermost account in force (and to its parents, below). When a thread waiting inside one
//!   study's sweep runs a point of another study (rayon's work stealing), the time of that
//!   point goes to the other study. So the CPU seconds of the accounts without a parent add up
//!   to the run's CPU time (less what ran under no account).
//!
//! A **child** account ([`Account::child`]) counts a part of its parent's work: whatever is
//! charged to the child is charged to the parent (and its parents) as well, at the same moment,
//! so the parent's figures are those it would have without the child, and the child's are the
//! part's own, across every thread that ran it. The in-run memo of `geardyn-models` counts a
//! shared computation this way inside the study that asked for it first.
//!
//! Accounting never changes a result: it only counts, with relaxed atomics.
//!
//! ```
//! use geardyn_system::account::{self, Account};
//!
//! let acc = Account::new("demo");
//! let squares = account::scope(&acc, || {
//!     geardyn_system::sweep::sweep(&[1u64, 2, 3], |x| x * x, None)
//! });
//! assert_eq!(squares, [1, 4, 9]);
//! let u = acc.usage();
//! assert_eq!(u.points, 3);
//! assert!(u.cpu_seconds >= 0.0);
//! ```

use std::cell::RefCell;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

/// Counters of one piece of work (see the module docs). Shared between threads.
#[derive(Debug, Default)]
pub struct Account {
    name: String,
    /// Charged with everything charged to this account ([`Account::child`]); set at creation,
    /// so the chain of parents is finite and free of cycles.
    parent: Option<Arc<Account>>,
    points: AtomicU64,
    points_planned: AtomicU64,
    accepted: AtomicU64,
    rejected: AtomicU64,
    rhs: AtomicU64,
    integrations: AtomicU64,
    cpu_ns: AtomicU64,
}

/// A snapshot of an [`Account`].
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Usage {
    /// Completed sweep points.
    pub points: u64,
    /// Sweep points started so far (completed or not): `points / points_planned` is the
    /// fraction done of the sweeps begun.
    pub points_planned: u64,
    /// Accepted integrator steps.
    pub steps_accepted: u64,
    /// Rejected integrator steps.
    pub steps_rejected: u64,
    /// Right-hand-side evaluations of the integrators.
    pub rhs_calls: u64,
    /// Completed integrations.
    pub integrations: u64,
    /// Exclusive CPU seconds (module docs).
    pub cpu_seconds: f64,
}

impl Account {
    /// A new, empty account named `name` (for reports).
    pub fn new(name: impl Into<String>) -> Arc<Account> {
        Arc::new(Account {
            name: name.into(),
            ..Account::default()
        })
    }

    /// A new, empty account named `name` for a part of `parent`'s work: everything charged to
    /// it is charged to `parent` (and to `parent`'s parents) as well (module docs).
    pub fn child(name: impl Into<String>, parent: &Arc<Account>) -> Arc<Account> {
        Arc::new(Account {
            name: name.into(),
            parent: Some(Arc::clone(parent)),
            ..Account::default()
        })
    }

    /// The name given to [`Account::new`] or [`Account::child`].
    pub fn name(&self) -> &str {
        &self.name
    }

    /// This account and its parents, innermost first (a finite chain: parents are set at
    /// creation).
    fn chain(&self) -> impl Iterator<Item = &Account> {
        std::iter::successors(Some(self), |a| a.parent.as_deref())
    }

    /// The counters now.
    pub fn usage(&self) -> Usage {
        Usage {
            points: self.points.load(Ordering::Relaxed),
            points_planned: self.points_planned.load(Ordering::Relaxed),
            steps_accepted: self.accepted.load(Ordering::Relaxed),
            steps_rejected: self.rejected.load(Ordering::Relaxed),
            rhs_calls: self.rhs.load(Ordering::Relaxed),
            integrations: self.integrations.load(Ordering::Relaxed),
            cpu_seconds: self.cpu_ns.load(Ordering::Relaxed) as f64 * 1e-9,
        }
    }
}

/// The account in force on this thread and the CPU clock when it was put in force (or last
/// charged).
struct Frame {
    account: Arc<Account>,
    since_ns: u64,
}

thread_local! {
    static CURRENT: RefCell<Option<Frame>> = const { RefCell::new(None) };
}

/// This thread's CPU time in nanoseconds (the `cpu-time` crate: `clock_gettime` with
/// `CLOCK_THREAD_CPUTIME_ID` on Unix, `GetThreadTimes` on Windows); 0 where the clock cannot be
/// read (the account then shows no CPU time rather than failing the work).
pub fn thread_cpu_ns() -> u64 {
    cpu_time::ThreadTime::try_now()
        .map(|t| u64::try_from(t.as_duration().as_nanos()).unwrap_or(u64::MAX))
        .unwrap_or(0)
}

/// Charge the frame in force (if any) with the CPU time since it was last charged.
fn charge(frame: &mut Frame, now: u64) {
    let dt = now.saturating_sub(frame.since_ns);
    for a in frame.account.chain() {
        a.cpu_ns.fetch_add(dt, Ordering::Relaxed);
    }
    frame.since_ns = now;
}

/// Restores the enclosing frame when a [`scope`] ends, also on panic.
struct Restore(Option<Frame>);

impl Drop for Restore {
    fn drop(&mut self) {
        let outer = self.0.take();
        CURRENT.with(|c| {
            let mut c = c.borrow_mut();
            let now = thread_cpu_ns();
            if let Some(inner) = c.as_mut() {
                charge(inner, now);
            }
            *c = outer.map(|mut f| {
                f.since_ns = now;
                f
            });
        });
    }
}

/// Run `f` with `account` in force on this thread (and, through sweeps, on the threads that run
/// its points); the enclosing account, if any, is charged up to here and resumes afterwards.
pub fn scope<R>(account: &Arc<Account>, f: impl FnOnce() -> R) -> R {
    let outer = CURRENT.with(|c| {
        let mut c = c.borrow_mut();
        let now = thread_cpu_ns();
        if let Some(o) = c.as_mut() {
            charge(o, now);
        }
        c.replace(Frame {
            account: Arc::clone(account),
            since_ns: now,
        })
    });
    let _restore = Restore(outer);
    f()
}

/// As [`scope`] when `account` is `Some`; otherwise just `f()`.
pub fn scope_opt<R>(account: Option<&Arc<Account>>, f: impl FnOnce() -> R) -> R {
    match account {
        Some(a) => scope(a, f),
        None => f(),
    }
}

/// The account in force on this thread, if any.
pub fn current() -> Option<Arc<Account>> {
    CURRENT.with(|c| c.borrow().as_ref().map(|f| Arc::clone(&f.account)))
}

/// Add the counters of one finished integration to the account in force (none: nothing).
pub fn record_steps(accepted: u64, rejected: u64, rhs_calls: u64) {
    CURRENT.with(|c| {
        if let Some(f) = c.borrow().as_ref() {
            for a in f.account.chain() {
                a.accepted.fetch_add(accepted, Ordering::Relaxed);
                a.rejected.fetch_add(rejected, Ordering::Relaxed);
                a.rhs.fetch_add(rhs_calls, Ordering::Relaxed);
                a.integrations.fetch_add(1, Ordering::Relaxed);
            }
        }
    });
}

/// `n` sweep points begun under `account` (called by the sweeps).
pub(crate) fn plan_points(account: Option<&Arc<Account>>, n: usize) {
    for a in account.into_iter().flat_map(|a| a.chain()) {
        a.points_planned.fetch_add(n as u64, Ordering::Relaxed);
    }
}

/// One sweep point done under `account` (called by the sweeps).
pub(crate) fn point_done(account: Option<&Arc<Account>>) {
    for a in account.into_iter().flat_map(|a| a.chain()) {
        a.points.fetch_add(1, Ordering::Relaxed);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn burn(n: u64) -> u64 {
        // some CPU work the optimiser cannot remove
        (0..n).fold(1u64, |a, i| {
            a.wrapping_mul(6364136223846793005).wrapping_add(i)
        })
    }

    #[test]
    fn nested_scopes_charge_exclusive_time_and_restore() {
        let outer = Account::new("outer");
        let inner = Account::new("inner");
        assert!(current().is_none());
        let (x, y) = scope(&outer, || {
            let x = burn(2_000_000);
            let y = scope(&inner, || {
                assert_eq!(
                    current().map(|a| a.name().to_owned()).as_deref(),
                    Some("inner")
                );
                record_steps(10, 2, 75);
                burn(2_000_000)
            });
            assert_eq!(
                current().map(|a| a.name().to_owned()).as_deref(),
                Some("outer")
            );
            record_steps(1, 0, 7);
            (x, y)
        });
        assert_eq!(x, y);
        assert!(current().is_none());
        let (o, i) = (outer.usage(), inner.usage());
        assert_eq!(
            (i.steps_accepted, i.steps_rejected, i.rhs_calls),
            (10, 2, 75)
        );
        assert_eq!((o.steps_accepted, o.steps_rejected, o.rhs_calls), (1, 0, 7));
        assert_eq!((o.integrations, i.integrations), (1, 1));
        assert!(o.cpu_seconds > 0.0 && i.cpu_seconds > 0.0);
    }

    /// A child's figures are its part's own, across the threads of its sweeps; the parent's
    /// include them, as if the part had run under the parent; a sibling account in force
    /// inside the child's scope takes its time from both.
    #[test]
    fn a_child_is_charged_to_its_parent_too() {
        let parent = Account::new("study");
        let child = Account::child("shared", &parent);
        let other = Account::new("other study");
        scope(&parent, || {
            record_steps(1, 0, 7);
            burn(1_000_000);
            scope(&child, || {
                let sq = crate::sweep::sweep(
                    &[1u64, 2, 3, 4],
                    |&x| {
                        record_steps(x, 1, 10 * x);
                        burn(500_000) ^ x
                    },
                    None,
                );
                assert_eq!(sq.len(), 4);
                // another study's point run by a thread waiting inside the child's work
                scope(&other, || {
                    record_steps(100, 0, 100);
                    burn(2_000_000)
                });
            });
        });
        let (p, c, o) = (parent.usage(), child.usage(), other.usage());
        // (points, planned, accepted, rejected, RHS calls, integrations)
        let counts = |u: Usage| {
            let n = [
                u.points,
                u.points_planned,
                u.steps_accepted,
                u.steps_rejected,
            ];
            (n, u.rhs_calls, u.integrations)
        };
        assert_eq!(counts(c), ([4, 4, 10, 4], 100, 4));
        assert_eq!(counts(p), ([4, 4, 11, 4], 107, 5));
        assert_eq!((o.steps_accepted, o.integrations), (100, 1));
        // the parent holds the child's CPU and more; the clock may read 0 on some platforms
        assert!(p.cpu_seconds >= c.cpu_seconds);
        if thread_cpu_ns() > 0 {
            assert!(c.cpu_seconds > 0.0 && o.cpu_seconds > 0.0);
            assert!(p.cpu_seconds > c.cpu_seconds);
        }
    }

    #[test]
    fn restored_after_a_panic() {
        let a = Account::new("a");
        let r = std::panic::catch_unwind(|| scope(&a, || panic!("boom")));
        assert!(r.is_err());
        assert!(current().is_none());
        // nothing is recorded without an account in force
        record_steps(5, 5, 5);
        assert_eq!(a.usage().steps_accepted, 0);
    }
}
