//! # geardyn-orbit
//!
//! Periodic orbits of rattling and impacting systems (docs below are expanded later).

#![deny(missing_docs)]

mod continuation;
mod error;
mod floquet;
mod flow;
mod impact;
mod problem;
mod shooting;

pub use continuation::{
    Branch, BranchPoint, ContinuationOptions, Extremum, SpecialKind, SpecialPoint, StopReason,
};
pub use error::{OrbitError, Result};
pub use floquet::{
    Crossing, Floquet, OutsideCount, STABILITY_TOLERANCE, classify_crossing, floquet,
    real_eigenvector,
};
pub use flow::{EventRecord, Flow, FlowOptions};
pub use impact::{ImpactLaw, Restitution};
pub use problem::{OrbitProblem, Parameter};
pub use shooting::{PeriodicOrbit, ShootingOptions};
