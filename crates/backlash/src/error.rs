//! The crate's error type.

use thiserror::Error;

/// Everything that can go wrong in `backlash`.
///
/// Every variant carries the offending number so that the message explains itself, e.g.
/// `D must be in (1, 2), got 2.3`.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum Error {
    /// A parameter is outside its admissible range (NaN is always outside).
    #[error("{name} must be {bound}, got {value}")]
    InvalidParameter {
        /// Paper symbol or field name of the parameter.
        name: &'static str,
        /// The admissible range, in words (e.g. `"in (1, 2)"`, `"> 0"`).
        bound: &'static str,
        /// The value that was given.
        value: f64,
    },
    /// Two parameters are inconsistent with each other (e.g. smallest wavelength larger than
    /// the largest one).
    #[error("{what}: {detail}")]
    Inconsistent {
        /// Which parameters disagree.
        what: &'static str,
        /// Explanation with the numbers.
        detail: String,
    },
    /// A requested resolution would need more work than the stated limit.
    #[error("{what} needs {needed} evaluations, more than the limit {limit}")]
    ResolutionTooFine {
        /// Which computation.
        what: &'static str,
        /// How many evaluations the settings imply.
        needed: f64,
        /// The limit.
        limit: usize,
    },
    /// The radicand of Yu Eq. (6), Δa² − Δp², is negative and the policy is
    /// [`RadicandPolicy::Reject`](crate::RadicandPolicy::Reject).
    #[error(
        "Yu Eq. (6): Δa² − Δp² = {radicand} m² is negative (Δa = {delta_a} m, Δp = {delta_p} m)"
    )]
    NegativeRadicand {
        /// Δa² − Δp² in m².
        radicand: f64,
        /// Δa in m (Eq. 9).
        delta_a: f64,
        /// Δp in m (Eq. 7).
        delta_p: f64,
    },
}

/// The spur-pair geometry's range errors ([`system::PairGeometry::new`]) in this crate's words:
/// `R_p`, `R_g` finite and > 0, `alpha0` in (0, π/2) rad.
impl From<system::InvalidGeometry> for Error {
    fn from(e: system::InvalidGeometry) -> Self {
        let (name, bound) = match e.field {
            system::GeometryField::PinionRadius => ("R_p", "finite and > 0"),
            system::GeometryField::GearRadius => ("R_g", "finite and > 0"),
            system::GeometryField::PressureAngle => ("alpha0", "in (0, π/2) rad"),
        };
        Error::InvalidParameter {
            name,
            bound,
            value: e.value,
        }
    }
}

/// Check that `value` is finite; `name` names it in the error.
pub(crate) fn finite(name: &'static str, value: f64) -> Result<f64, Error> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Error::InvalidParameter {
            name,
            bound: "finite",
            value,
        })
    }
}

/// Check `value > 0` (and finite).
pub(crate) fn positive(name: &'static str, value: f64) -> Result<f64, Error> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(Error::InvalidParameter {
            name,
            bound: "finite and > 0",
            value,
        })
    }
}

/// Check `value >= 0` (and finite).
pub(crate) fn non_negative(name: &'static str, value: f64) -> Result<f64, Error> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(Error::InvalidParameter {
            name,
            bound: "finite and >= 0",
            value,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_carry_numbers() {
        let e = Error::InvalidParameter {
            name: "D",
            bound: "in (1, 2)",
            value: 2.3,
        };
        assert_eq!(e.to_string(), "D must be in (1, 2), got 2.3");
        assert!(finite("x", f64::NAN).is_err());
        assert!(positive("G", 0.0).is_err());
        assert!(non_negative("b", -1e-5).is_err());
        assert!(non_negative("b", 0.0).is_ok());
    }
}
