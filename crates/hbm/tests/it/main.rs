//! The integration tests of this crate, one module per former `tests/*.rs` file, built as
//! one test binary (one link of the dependency tree instead of one per file; issue 26).

mod accuracy;
mod common;
mod deadzone;
mod duffing;
mod jacobian;
mod krylov;
mod linear;
mod lu;
mod solvers;
mod tables;
