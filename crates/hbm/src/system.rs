//! The system trait: `M q'' + C q' + K q + g(t, q, q') = f(t)`.
//!
//! `hbm` solves the shared system description of `geardyn-system`: [`SecondOrderSystem`] is
//! that crate's trait, re-exported, so a model written once for it is solved here and by the
//! time-stepping engine alike. The harmonic balance calls
//! [`SecondOrderSystem::set_base_frequency`] whenever a [`HbmProblem`](crate::HbmProblem) is
//! built or its `ω` changes, and [`SecondOrderSystem::set_parameter`] for continuation in a
//! named parameter; a [`SystemError`] from either arrives as [`HbmError`](crate::HbmError)
//! (`UnknownParameter` keeps its variant, the rest becomes `HbmError::System`).

pub use system::{SecondOrderSystem, SystemError, finite_difference_force_jacobian};

impl From<SystemError> for crate::HbmError {
    fn from(e: SystemError) -> Self {
        match e {
            SystemError::UnknownParameter { name } => crate::HbmError::UnknownParameter { name },
            other => crate::HbmError::System(other),
        }
    }
}
