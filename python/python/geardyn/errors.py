"""Typed exceptions raised by geardyn, mapped from the Rust error types.

* :class:`ParameterError` — bad input: an unknown parameter, setting, preset or method, or a
  value outside its admissible range (the message names the field and the bound).
  ``geardyn_models::Error::{InvalidParameter, UnsupportedReading, Geometry, Stiffness, Backlash}``.
* :class:`SolverError` — an engine failed (harmonic balance or time stepping); a solve that did
  not converge is *not* an error, it is reported in the result's ``converged`` field.
  ``geardyn_models::Error::{Hbm, Timestep, Solver}``.
* :class:`StudyError` — a study file could not be read or run (``geardyn_validate::Error``).

* :class:`ReliabilityWarning` — not an error: a warning (``warnings.warn``) that a result holds
  points that are not settled, not converged or not stable (the columns ``settled``,
  ``converged``, ``stable`` say which). Turn it into an error with
  ``warnings.simplefilter("error", geardyn.ReliabilityWarning)``.

``err.chain`` lists the messages of the Rust ``source()`` chain (leaf errors first-to-last).
"""


class GeardynError(Exception):
    """Base class of every geardyn error."""

    def __init__(self, message, chain=()):
        super().__init__(message)
        self.chain = list(chain)


class ParameterError(GeardynError, ValueError):
    """Invalid input (unknown name, value out of range)."""


class SolverError(GeardynError, RuntimeError):
    """A harmonic-balance or time-stepping engine failed."""


class StudyError(GeardynError, ValueError):
    """A study could not be read or run."""


class ReliabilityWarning(UserWarning):
    """A returned point is not settled, not converged or not stable: its numbers are not what
    the validation would judge. The point is still returned, marked by its flag column."""


_KINDS = {
    "ParameterError": ParameterError,
    "SolverError": SolverError,
    "StudyError": StudyError,
}


def _raise(error):
    cls = _KINDS.get(error.get("kind"), GeardynError)
    raise cls(error.get("message", "unknown error"), error.get("chain", ()))
