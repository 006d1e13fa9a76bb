//! The published gear-dynamics models of geardyn.
//!
//! * [`liu2021`] — noncircular face gear (NFG) rattle under multifrequency parametric
//!   excitation (Liu, Lv, Zhao 2021, Mech. Sci. 12:361).
//! * [`karpov2017`] — oscillator excited at the variable mesh frequency of slightly non-circular
//!   gears (Karpov et al. 2017, MMT 114:1).
//! * [`yu2021`] — spur pair with dynamic, fractal backlash, 6-DOF transverse-torsional
//!   (Yu, Sun, Li, Wu 2021).
//! * [`pair`] — a generic spur pair composed from a geometry, a stiffness law, a backlash law
//!   and the degrees of freedom; the papers' models are presets of it where the physics allows.
//!
//! * [`contract`] — what every model offers its front ends: the [`contract::Model`] trait
//!   (self-description, solve a point by a method into a [`contract::Record`]), the one
//!   tolerance check and the [`contract::REGISTRY`] (one line per model; each model's
//!   implementation is the `registry` module of its folder).
//!
//! Each model: a dimensional parameter struct (SI, serde, validated), the paper's parameter set
//! as a named constructor, the dimensionless form built in one place, and adapters to both
//! engines ([`hbm`] and [`timestep`]).

pub mod contract;
mod error;
pub(crate) mod fastlog;

pub mod karpov2017;
pub mod liu2021;
pub mod memo;
pub mod motion;
pub mod pair;
pub mod response;
pub(crate) mod trig;
pub mod yu2021;

pub use error::Error;

/// The README's example, compiled and run as a doctest so that it cannot rot.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
