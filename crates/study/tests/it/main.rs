//! The integration tests of this crate, one module per former `tests/*.rs` file, built as
//! one test binary (one link of the dependency tree instead of one per file; issue 26).

mod basin;
mod continuation;
mod fuzz;
mod shards;
mod user_study;
