//! The integration tests of this crate, one module per former `tests/*.rs` file, built as
//! one test binary (one link of the dependency tree instead of one per file; issue 26).

mod bifurcation;
mod dop853;
mod integrators;
mod proptest_events;
mod steady;
