//! The error type of the `models` crate.

/// Everything that can go wrong when building or solving a published model.
///
/// A failure inside a leaf crate (geometry, stiffness, backlash) or an engine (harmonic balance,
/// time stepping) keeps the leaf's typed error as its [`std::error::Error::source`], so callers
/// can walk the chain or downcast to e.g. [`hbm::HbmError`]. The `Display` text also repeats
/// the leaf's message after a context prefix, so a single `{}` stays informative.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A parameter is outside its admissible range (or NaN).
    #[error("{field} must be {bound}, got {value}")]
    InvalidParameter {
        /// Name of the offending field, as in the parameter struct (e.g. `"liu2021.e_r"`).
        field: String,
        /// The bound it violates, in words (e.g. `"> 0"`, `"in [0, 1)"`).
        bound: String,
        /// The value that was given.
        value: f64,
    },
    /// A reading (printed-vs-consistent choice) of a leaf crate that this model does not
    /// implement (the leaf enums are `#[non_exhaustive]`).
    #[error("{field}: reading {reading} is not implemented by this model")]
    UnsupportedReading {
        /// The readings field (e.g. `"liu2021.readings.rigid_acceleration"`).
        field: &'static str,
        /// The variant, as `Debug` prints it.
        reading: String,
    },
    /// The gear-geometry leaf rejected a derived input.
    #[error("gear geometry: {0}")]
    Geometry(#[from] gear_geometry::Error),
    /// The mesh-stiffness leaf rejected a derived input.
    #[error("{context}: {source}")]
    Stiffness {
        /// What the model was doing.
        context: &'static str,
        /// The leaf's error.
        #[source]
        source: mesh_stiffness::Error,
    },
    /// The backlash leaf rejected a derived input.
    #[error("{context}: {source}")]
    Backlash {
        /// What the model was doing.
        context: &'static str,
        /// The leaf's error.
        #[source]
        source: backlash::Error,
    },
    /// The harmonic balance engine failed (a non-converged solve is reported in the result,
    /// not here).
    #[error("solver: {context}{source}")]
    Hbm {
        /// What the model was doing, ending in `": "` (may be empty).
        context: &'static str,
        /// The engine's error.
        #[source]
        source: hbm::HbmError,
    },
    /// The time-stepping engine failed.
    #[error("solver: {context}{source}")]
    Timestep {
        /// What the model was doing, ending in `": "` (may be empty).
        context: &'static str,
        /// The engine's error.
        #[source]
        source: timestep::Error,
    },
    /// The periodic-orbit crate failed (an event-located flow with its variational equations,
    /// shooting, multipliers).
    #[error("solver: {context}{source}")]
    Orbit {
        /// What the model was doing, ending in `": "` (may be empty).
        context: &'static str,
        /// The crate's error.
        #[source]
        source: orbit::OrbitError,
    },
    /// A solver-level failure of the model itself (no underlying leaf error): an integration
    /// that did not complete, an empty response, a non-periodic state.
    #[error("solver: {0}")]
    Solver(String),
    /// A quadrature ran out of its panel budget, could not advance, or did not reach its
    /// tolerance.
    #[error("quadrature at τ = {at}: {reason}")]
    Quadrature {
        /// What went wrong, with the bound that was hit.
        reason: String,
        /// Where (the integration variable) it happened.
        at: f64,
    },
}

impl Error {
    /// Shorthand for [`Error::InvalidParameter`].
    pub fn invalid(field: impl Into<String>, bound: impl Into<String>, value: f64) -> Self {
        Error::InvalidParameter {
            field: field.into(),
            bound: bound.into(),
            value,
        }
    }

    /// Wrap a harmonic balance error with a context prefix (`"yu2021 hbm engine: "`, or `""`).
    pub fn hbm(context: &'static str) -> impl FnOnce(hbm::HbmError) -> Self {
        move |source| Error::Hbm { context, source }
    }

    /// Wrap a time-stepping error with a context prefix (`"yu2021 timestep engine: "`, or `""`).
    pub fn timestep(context: &'static str) -> impl FnOnce(timestep::Error) -> Self {
        move |source| Error::Timestep { context, source }
    }
}

/// `v` finite and `> 0`; the error names `field`.
pub(crate) fn check_pos(field: &str, v: f64) -> Result<(), Error> {
    if v > 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(Error::invalid(field, "> 0 and finite", v))
    }
}

/// `v` finite and `>= 0`; the error names `field`.
pub(crate) fn check_nonneg(field: &str, v: f64) -> Result<(), Error> {
    if v >= 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(Error::invalid(field, ">= 0 and finite", v))
    }
}

/// `Ok` if a `timestep` run completed, else [`Error::Solver`] naming `who` and the status.
pub(crate) fn completed(s: &timestep::Solution, who: &str) -> Result<(), Error> {
    if s.status.is_success() {
        Ok(())
    } else {
        Err(Error::Solver(format!(
            "{who} timestep engine stopped: {:?}",
            s.status
        )))
    }
}

/// The work counters of consecutive `timestep` runs (a transient and its recorded window),
/// summed field by field.
pub(crate) fn total_stats(runs: &[&timestep::Solution]) -> timestep::Stats {
    runs.iter().fold(timestep::Stats::default(), |mut a, s| {
        a.add(&s.stats);
        a
    })
}

impl From<hbm::HbmError> for Error {
    fn from(source: hbm::HbmError) -> Self {
        Error::Hbm {
            context: "",
            source,
        }
    }
}

impl From<orbit::OrbitError> for Error {
    fn from(source: orbit::OrbitError) -> Self {
        Error::Orbit {
            context: "",
            source,
        }
    }
}

impl From<timestep::Error> for Error {
    fn from(source: timestep::Error) -> Self {
        Error::Timestep {
            context: "",
            source,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::error::Error as _;

    #[test]
    fn leaf_errors_are_kept_as_sources() {
        let leaf = gear_geometry::CentrodeDeviation::new(2.0, 2.0).unwrap_err();
        let e = Error::from(leaf.clone());
        let src = e.source().expect("geometry error has a source");
        assert_eq!(
            src.downcast_ref::<gear_geometry::Error>(),
            Some(&leaf),
            "the source is the leaf's typed error"
        );
        assert_eq!(e.to_string(), format!("gear geometry: {leaf}"));

        let h = hbm::HbmError::Singular {
            what: "mass matrix",
        };
        let e = Error::hbm("yu2021 hbm engine: ")(h.clone());
        assert_eq!(
            e.source().unwrap().downcast_ref::<hbm::HbmError>(),
            Some(&h)
        );
        assert_eq!(
            e.to_string(),
            "solver: yu2021 hbm engine: singular matrix: mass matrix"
        );

        let t = timestep::Error::InvalidParameter {
            name: "rtol",
            bound: "> 0",
            value: -1.0,
        };
        let e: Error = t.clone().into();
        assert_eq!(
            e.source().unwrap().downcast_ref::<timestep::Error>(),
            Some(&t)
        );

        // errors without an underlying leaf error end the chain
        assert!(Error::invalid("x", "> 0", -1.0).source().is_none());
        assert!(Error::Solver("empty".into()).source().is_none());
    }
}
