//! A wall-clock deadline that long-running engine loops check cooperatively.
//!
//! A caller that must bound the time of one solve (a study with
//! `limits.max_seconds_per_point`, a Python sweep with a per-point limit) sets a deadline for
//! the current thread with [`scope`]. The engines check it at their natural boundaries:
//!
//! * the time integrators of `geardyn-timestep` between accepted or rejected steps (every
//!   [`CHECK_EVERY`] steps, so that the check costs nothing measurable), and stop with
//!   `Status::TimeLimit`;
//! * the harmonic balance solvers of `geardyn-hbm` between Newton/Broyden iterations, and
//!   stop with the termination reason [`REASON`] (reported as not converged);
//! * the shooting Newton of `geardyn-orbit` and the fixed-step loops of the models between
//!   iterations or steps.
//!
//! The deadline is *ambient* (a thread-local), so that it reaches the engines through any
//! model without a new option on every API between them. It is set only inside [`scope`] and
//! restored when the scope ends, also when the closure panics. Work a model hands to other
//! threads (a nested rayon sweep) does not see it; the caller keeps its own watchdog for that.
//!
//! ```
//! use geardyn_system::deadline;
//! use std::time::{Duration, Instant};
//!
//! assert!(!deadline::expired());
//! let late = deadline::scope(Some(Instant::now()), || {
//!     std::thread::sleep(Duration::from_millis(1));
//!     deadline::expired()
//! });
//! assert!(late);
//! assert!(!deadline::expired()); // restored after the scope
//! let relaxed = deadline::scope(Some(Instant::now() + Duration::from_secs(3600)), deadline::expired);
//! assert!(!relaxed);
//! ```

use std::cell::Cell;
use std::time::Instant;

/// The reason an engine gives when it stops at the deadline (the start of its message).
pub const REASON: &str = "time limit";

/// Engines with cheap steps check the clock once per this many steps (a clock read costs
/// about 20 ns; a step of the Liu model about 250 ns).
pub const CHECK_EVERY: u64 = 64;

thread_local! {
    static AMBIENT: Cell<Option<Instant>> = const { Cell::new(None) };
}

/// The deadline in force on this thread, if any.
pub fn current() -> Option<Instant> {
    AMBIENT.with(Cell::get)
}

/// True when a deadline is in force on this thread and has passed.
pub fn expired() -> bool {
    current().is_some_and(|d| Instant::now() >= d)
}

/// Run `f` with `deadline` in force on this thread (the earlier of it and any enclosing
/// deadline), and restore the previous deadline afterwards, also on panic.
pub fn scope<T>(deadline: Option<Instant>, f: impl FnOnce() -> T) -> T {
    struct Restore(Option<Instant>);
    impl Drop for Restore {
        fn drop(&mut self) {
            AMBIENT.with(|a| a.set(self.0));
        }
    }
    let previous = current();
    let effective = match (previous, deadline) {
        (Some(p), Some(d)) => Some(p.min(d)),
        (p, d) => d.or(p),
    };
    let _restore = Restore(previous);
    AMBIENT.with(|a| a.set(effective));
    f()
}

/// A cheap periodic check for a loop: true every [`CHECK_EVERY`]-th call when the deadline has
/// passed. `counter` is the loop's own step count.
#[inline]
pub fn expired_at_step(counter: u64) -> bool {
    counter % CHECK_EVERY == 0 && expired()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn nested_scopes_take_the_earlier_deadline_and_restore() {
        let far = Instant::now() + Duration::from_secs(3600);
        let past = Instant::now();
        scope(Some(far), || {
            assert_eq!(current(), Some(far));
            scope(Some(past), || assert_eq!(current(), Some(past)));
            // A later inner deadline does not extend the outer one.
            scope(Some(far + Duration::from_secs(1)), || {
                assert_eq!(current(), Some(far))
            });
            scope(None, || assert_eq!(current(), Some(far)));
            assert_eq!(current(), Some(far));
        });
        assert_eq!(current(), None);
    }

    #[test]
    fn a_panic_inside_the_scope_restores_the_deadline() {
        let r = std::panic::catch_unwind(|| scope(Some(Instant::now()), || panic!("boom")));
        assert!(r.is_err());
        assert_eq!(current(), None);
        assert!(!expired());
    }

    #[test]
    fn step_check_fires_only_on_multiples() {
        scope(Some(Instant::now()), || {
            std::thread::sleep(Duration::from_millis(1));
            assert!(expired_at_step(0));
            assert!(!expired_at_step(1));
            assert!(expired_at_step(CHECK_EVERY));
        });
        assert!(!expired_at_step(0));
    }
}
