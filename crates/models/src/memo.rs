//! An in-run memo of expensive responses, so that studies that need the same response compute
//! it once.
//!
//! The validation asks for the same Liu responses more than once in a run: the Fig. 8–10
//! responses at 140, 160 and 180 rad/s lie on the Fig. 11 grid, Table 2's long windows and the
//! parameter sweeps' base points meet the speed sweep's, and so on. The memo is off unless a
//! [`Session`] is open (the validation opens one for its run; a library user who calls
//! [`crate::liu2021::long_window`] gets no hidden cache). While a session is open, the
//! memoised functions look their inputs up before computing:
//!
//! * **Key**: the function's name and the `Debug` text of *all* its inputs (model with its
//!   readings, options). `Debug` writes every `f64` in its shortest round-trip form, so two
//!   inputs share a key exactly when they are equal bit for bit (NaN aside, which no valid
//!   input holds).
//! * **Deterministic**: a memoised function is a pure function of its inputs whose result is the
//!   same bits on any thread and for any thread count (the workspace's rule for every
//!   computation), so a hit returns exactly what a computation would. Which study computes a
//!   shared response first depends on the schedule; what it gets does not. Two studies that
//!   miss at the same time both compute, and the first to finish is kept.
//! * **Bounded**: at most [`Session::capacity`] entries; beyond it the oldest entry is dropped
//!   (first in, first out), which costs a recomputation, never a different result. Errors are
//!   not stored.
//!
//! [`stats`] gives the hits, the misses and the CPU time of the computations per function, for
//! the cost report: it is how the validation tells what share of its CPU the shared responses
//! take, and what the memo saves.

use std::any::Any;
use std::collections::{BTreeMap, HashMap, VecDeque};
use std::sync::{Arc, Mutex, MutexGuard};

/// Entries kept by default (a Liu long-window response is a few hundred bytes; 4096 entries are
/// a few MB at most).
pub const DEFAULT_CAPACITY: usize = 4096;

type Entry = Arc<dyn Any + Send + Sync>;

#[derive(Default)]
struct Store {
    sessions: usize,
    capacity: usize,
    map: HashMap<(&'static str, String), Entry>,
    order: VecDeque<(&'static str, String)>,
    counts: BTreeMap<&'static str, Counts>,
}

/// The counters of one memoised function.
#[derive(Debug, Default, Clone, Copy)]
struct Counts {
    hits: u64,
    misses: u64,
    cpu_seconds: f64,
}

/// What one memoised function cost and saved since the first open session ([`stats`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MemoStats {
    /// The function's name (the `name` of [`cached`]).
    pub name: &'static str,
    /// Calls answered from the memo.
    pub hits: u64,
    /// Calls computed (a failed computation included).
    pub misses: u64,
    /// CPU seconds of the computed calls: each computation runs under a child
    /// ([`system::account::Account::child`]) of the account in force, so this counts its CPU on
    /// every thread of its sweeps, and not the other work a thread ran while it waited inside
    /// the computation (rayon's work stealing). A memoised computation inside another one
    /// counts in both. The study that asked first is charged as without the memo.
    pub cpu_seconds: f64,
}

impl MemoStats {
    /// The CPU seconds the hits would have cost, estimated at the mean of the computed calls
    /// (0 without a computed call).
    pub fn saved_cpu_seconds(&self) -> f64 {
        if self.misses == 0 {
            0.0
        } else {
            self.cpu_seconds * self.hits as f64 / self.misses as f64
        }
    }
}

static STORE: Mutex<Option<Store>> = Mutex::new(None);

fn lock() -> MutexGuard<'static, Option<Store>> {
    // a panic while the lock was held leaves a consistent store (every update is one
    // statement); recover it instead of propagating the poison
    STORE.lock().unwrap_or_else(|p| p.into_inner())
}

/// An open memo session (see the module docs); the memo is cleared when the last open session
/// is dropped.
#[derive(Debug)]
pub struct Session {
    capacity: usize,
}

impl Session {
    /// Open a session keeping at most `capacity` entries (at least 1). Sessions nest: the memo
    /// stays on (with the largest capacity asked for) until every session is dropped.
    pub fn open(capacity: usize) -> Session {
        let capacity = capacity.max(1);
        let mut g = lock();
        let s = g.get_or_insert_with(Store::default);
        s.sessions += 1;
        s.capacity = s.capacity.max(capacity);
        Session { capacity }
    }

    /// The capacity this session asked for.
    pub fn capacity(&self) -> usize {
        self.capacity
    }
}

impl Drop for Session {
    fn drop(&mut self) {
        let mut g = lock();
        if let Some(s) = g.as_mut() {
            s.sessions = s.sessions.saturating_sub(1);
            if s.sessions == 0 {
                *g = None;
            }
        }
    }
}

/// Hits, misses and CPU time per memoised function since the first open session, in name
/// order.
pub fn stats() -> Vec<MemoStats> {
    lock().as_ref().map_or_else(Vec::new, |s| {
        s.counts
            .iter()
            .map(|(k, c)| MemoStats {
                name: k,
                hits: c.hits,
                misses: c.misses,
                cpu_seconds: c.cpu_seconds,
            })
            .collect()
    })
}

/// `compute()` through the memo: with a session open, the stored result for (`name`, `key()`)
/// if there is one, otherwise `compute()`, stored when `Ok`. Without a session: `compute()`.
pub fn cached<V, E>(
    name: &'static str,
    key: impl FnOnce() -> String,
    compute: impl FnOnce() -> Result<V, E>,
) -> Result<V, E>
where
    V: Clone + Send + Sync + 'static,
{
    let open = lock().is_some();
    if !open {
        return compute();
    }
    let key = key();
    {
        let mut g = lock();
        if let Some(s) = g.as_mut() {
            let hit = s
                .map
                .get(&(name, key.clone()))
                .and_then(|e| e.downcast_ref::<V>().cloned());
            let c = s.counts.entry(name).or_default();
            if let Some(v) = hit {
                c.hits += 1;
                return Ok(v);
            }
            c.misses += 1;
        }
    }
    // a part of the work in force (the study that asked first): charged there as before, and
    // counted here across every thread of the computation's sweeps
    let account = match system::account::current() {
        Some(parent) => system::account::Account::child(name, &parent),
        None => system::account::Account::new(name),
    };
    let result = system::account::scope(&account, compute);
    let cpu = account.usage().cpu_seconds;
    let mut g = lock();
    if let Some(s) = g.as_mut() {
        let c = s.counts.entry(name).or_default();
        c.cpu_seconds += cpu;
    }
    let v = result?;
    if let Some(s) = g.as_mut() {
        let k = (name, key);
        if !s.map.contains_key(&k) {
            while s.map.len() >= s.capacity {
                match s.order.pop_front() {
                    Some(old) => {
                        s.map.remove(&old);
                    }
                    None => break,
                }
            }
            s.map.insert(k.clone(), Arc::new(v.clone()));
            s.order.push_back(k);
        }
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicU32, Ordering};
    use system::account::{self, Account};

    /// About `ns` nanoseconds of this thread's CPU, bounded also where the clock reads 0;
    /// returns the CPU nanoseconds it saw pass.
    fn burn_ns(ns: u64) -> f64 {
        let t0 = account::thread_cpu_ns();
        let mut x = 1.0f64;
        for _ in 0..100_000 {
            for _ in 0..1000 {
                x = std::hint::black_box(x.sqrt() + 1.0);
            }
            if account::thread_cpu_ns().saturating_sub(t0) >= ns {
                break;
            }
        }
        std::hint::black_box(x);
        account::thread_cpu_ns().saturating_sub(t0) as f64
    }

    // one test touches the global store, so that tests running in parallel do not share it
    #[test]
    fn session_hits_bounds_and_clears() {
        let calls = AtomicU32::new(0);
        let f = |x: u32| {
            cached::<u32, ()>(
                "square",
                || format!("{x:?}"),
                || {
                    calls.fetch_add(1, Ordering::Relaxed);
                    Ok(x * x)
                },
            )
        };
        // no session: always computed
        assert_eq!(f(3), Ok(9));
        assert_eq!(f(3), Ok(9));
        assert_eq!(calls.load(Ordering::Relaxed), 2);
        {
            let _s = Session::open(2);
            assert_eq!(f(3), Ok(9));
            assert_eq!(f(3), Ok(9));
            assert_eq!(calls.load(Ordering::Relaxed), 3);
            // capacity 2: a third key drops the oldest (3), which is then computed again
            assert_eq!(f(4), Ok(16));
            assert_eq!(f(5), Ok(25));
            assert_eq!(f(3), Ok(9));
            assert_eq!(calls.load(Ordering::Relaxed), 6);
            // errors are not stored
            let e = || cached::<u32, &str>("fails", || "k".into(), || Err("no"));
            assert_eq!(e(), Err("no"));
            let counts: Vec<_> = stats().iter().map(|m| (m.name, m.hits, m.misses)).collect();
            assert_eq!(counts, vec![("fails", 0, 1), ("square", 1, 4)]);
            assert_eq!(e(), Err("no"));
            // the same key under another name is another entry
            let g = cached::<u32, ()>("other", || "3".into(), || Ok(0));
            assert_eq!(g, Ok(0));
            // the CPU time of a computation is counted, that of a hit is not
            let burn = || cached::<f64, ()>("burn", || "1".into(), || Ok(burn_ns(5_000_000)));
            let burnt = |name: &str| stats().into_iter().find(|m| m.name == name).unwrap();
            let seen = burn().unwrap();
            let once = burnt("burn");
            // at least what the computation saw pass (0 where the clock cannot be read)
            assert!(
                once.cpu_seconds * 1e9 >= seen - 1.0,
                "{once:?} against {seen} ns"
            );
            assert_eq!(once.saved_cpu_seconds().to_bits(), 0.0f64.to_bits());
            burn().unwrap();
            let twice = burnt("burn");
            assert_eq!((twice.hits, twice.misses), (1, 1));
            assert_eq!(twice.cpu_seconds.to_bits(), once.cpu_seconds.to_bits());
            assert_eq!(
                twice.saved_cpu_seconds().to_bits(),
                once.cpu_seconds.to_bits()
            );
            // a computation that sweeps: its CPU on every thread of the sweep, charged to the
            // study in force as well
            let study = Account::new("study");
            let seen = account::scope(&study, || {
                cached::<f64, ()>(
                    "sweeps",
                    || "1".into(),
                    || {
                        let ns = system::sweep::sweep(&[0u8; 4], |_| burn_ns(3_000_000), None);
                        Ok(ns.iter().sum())
                    },
                )
            })
            .unwrap();
            let swept = burnt("sweeps");
            assert!(
                swept.cpu_seconds * 1e9 >= seen - 4.0,
                "{swept:?} against {seen} ns"
            );
            let u = study.usage();
            assert_eq!((u.points, u.points_planned), (4, 4));
            assert!(
                u.cpu_seconds >= swept.cpu_seconds,
                "{u:?} against {swept:?}"
            );
        }
        // closed: cleared and off
        assert!(stats().is_empty());
        assert_eq!(f(4), Ok(16));
        assert_eq!(calls.load(Ordering::Relaxed), 7);
    }
}
