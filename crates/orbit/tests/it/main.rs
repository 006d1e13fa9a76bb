//! The integration tests of this crate, one module per former `tests/*.rs` file, built as
//! one test binary (one link of the dependency tree instead of one per file; issue 26).

mod codim2;
mod common;
mod hbm_branch;
mod hostile;
mod impact;
mod linear;
mod liu;
mod lyapunov;
mod methods;
mod models;
mod piecewise;
mod smooth_and_grazing;
