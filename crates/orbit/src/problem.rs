//! [`OrbitProblem`]: a system, its forcing period, an optional impact law and the flow.

use crate::error::{OrbitError, Result, check};
use crate::flow::{self, Field, Flow, FlowOptions, Matrices};
use crate::impact::ImpactLaw;
use crate::lyapunov::{LyapunovOptions, LyapunovSpectrum, WindowMap, lyapunov_qr};
use system::SecondOrderSystem;

/// The continuation (or sweep) parameter.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Parameter {
    /// A named model parameter ([`SecondOrderSystem::set_parameter`]); the forcing period stays.
    Named(String),
    /// The base (forcing) frequency `ω` ([`SecondOrderSystem::set_base_frequency`]); the forcing
    /// period follows as `T = 2π/ω`.
    BaseFrequency,
}

/// A periodically forced system whose periodic orbits are sought: `M q'' + C q' + K q +
/// g(t, q, q') = f(t)` with forcing period `T`, Poincaré section `t = t₀ (mod T)`, and an
/// optional [`ImpactLaw`].
pub struct OrbitProblem<S> {
    system: S,
    impacts: Option<Box<dyn ImpactLaw + Send + Sync>>,
    period: f64,
    t0: f64,
    options: FlowOptions,
    mats: Matrices,
}

impl<S: std::fmt::Debug> std::fmt::Debug for OrbitProblem<S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("OrbitProblem")
            .field("system", &self.system)
            .field("impacts", &self.impacts.is_some())
            .field("period", &self.period)
            .field("t0", &self.t0)
            .field("options", &self.options)
            .finish()
    }
}

impl<S: SecondOrderSystem> OrbitProblem<S> {
    /// A problem with forcing period `period` (section at `t₀ = 0`, default [`FlowOptions`]).
    ///
    /// # Errors
    /// Non-positive or non-finite period, `n_dof = 0`, wrongly sized or singular matrices.
    pub fn new(system: S, period: f64) -> Result<Self> {
        check(
            period.is_finite() && period > 0.0,
            "period",
            "> 0 and finite",
            period,
        )?;
        let mats = Matrices::of(&system)?;
        Ok(Self {
            system,
            impacts: None,
            period,
            t0: 0.0,
            options: FlowOptions::default(),
            mats,
        })
    }

    /// Adds an impact law (resets at its events).
    pub fn with_impacts(mut self, law: impl ImpactLaw + Send + Sync + 'static) -> Self {
        self.impacts = Some(Box::new(law));
        self
    }

    /// Moves the Poincaré section to `t₀`.
    ///
    /// # Errors
    /// Non-finite `t0`.
    pub fn with_phase(mut self, t0: f64) -> Result<Self> {
        check(t0.is_finite(), "t0", "finite", t0)?;
        self.t0 = t0;
        Ok(self)
    }

    /// Replaces the integrator settings.
    ///
    /// # Errors
    /// Invalid options ([`FlowOptions::validate`]).
    pub fn with_flow_options(mut self, options: FlowOptions) -> Result<Self> {
        options.validate()?;
        self.options = options;
        Ok(self)
    }

    /// The system.
    pub fn system(&self) -> &S {
        &self.system
    }
    /// The forcing period `T`.
    pub fn period(&self) -> f64 {
        self.period
    }
    /// The section time `t₀`.
    pub fn phase(&self) -> f64 {
        self.t0
    }
    /// The integrator settings.
    pub fn flow_options(&self) -> &FlowOptions {
        &self.options
    }
    /// State dimension `2n`.
    pub fn dim(&self) -> usize {
        2 * self.system.n_dof()
    }

    /// Sets the forcing period.
    ///
    /// # Errors
    /// Non-positive or non-finite period.
    pub fn set_period(&mut self, period: f64) -> Result<()> {
        check(
            period.is_finite() && period > 0.0,
            "period",
            "> 0 and finite",
            period,
        )?;
        self.period = period;
        Ok(())
    }

    /// Sets a parameter (and the period, for [`Parameter::BaseFrequency`]); the matrices are
    /// re-read from the system.
    ///
    /// # Errors
    /// Non-finite value, the system's rejection, a singular mass matrix.
    pub fn set_parameter(&mut self, parameter: &Parameter, value: f64) -> Result<()> {
        check(value.is_finite(), "parameter value", "finite", value)?;
        match parameter {
            Parameter::Named(name) => self.system.set_parameter(name, value)?,
            Parameter::BaseFrequency => {
                check(value > 0.0, "base frequency", "> 0", value)?;
                self.system.set_base_frequency(value)?;
                self.period = 2.0 * std::f64::consts::PI / value;
            }
        }
        self.mats = Matrices::of(&self.system)?;
        Ok(())
    }

    /// Reads a parameter.
    ///
    /// # Errors
    /// The system does not know it.
    pub fn parameter(&self, parameter: &Parameter) -> Result<f64> {
        match parameter {
            Parameter::Named(name) => Ok(self.system.parameter(name)?),
            Parameter::BaseFrequency => Ok(2.0 * std::f64::consts::PI / self.period),
        }
    }

    pub(crate) fn field(&self) -> Field<'_, S> {
        let law: Option<&dyn ImpactLaw> = match &self.impacts {
            Some(b) => Some(b.as_ref()),
            None => None,
        };
        Field::new(&self.system, &self.mats, law)
    }

    pub(crate) fn check_state(&self, x: &[f64]) -> Result<()> {
        if x.len() != self.dim() {
            return Err(OrbitError::DimensionMismatch {
                what: "state (q, q')",
                expected: self.dim(),
                got: x.len(),
            });
        }
        if x.iter().any(|v| !v.is_finite()) {
            return Err(OrbitError::NonFinite {
                what: "initial state",
                time: self.t0,
            });
        }
        Ok(())
    }

    /// The event-located flow from `(t0, x0)` over `duration`; with `variational`, its Jacobian
    /// `∂x(t0 + duration)/∂x0` (variational equations composed with saltation matrices).
    ///
    /// # Errors
    /// Invalid input, integration failures.
    pub fn flow(&self, t0: f64, x0: &[f64], duration: f64, variational: bool) -> Result<Flow> {
        self.check_state(x0)?;
        flow::integrate(
            self.field(),
            &self.options,
            t0,
            x0,
            duration,
            variational,
            false,
        )
    }

    pub(crate) fn flow_recorded(
        &self,
        t0: f64,
        x0: &[f64],
        duration: f64,
        variational: bool,
    ) -> Result<Flow> {
        self.check_state(x0)?;
        flow::integrate(
            self.field(),
            &self.options,
            t0,
            x0,
            duration,
            variational,
            true,
        )
    }

    /// The Lyapunov spectrum of the flow from `(t0, x0)` ([`lyapunov_qr`] on this problem's
    /// event-located variational flow): `opts.windows` windows of length `opts.window`, each a
    /// [`flow`](Self::flow) with its Jacobian (saltation matrices at every event: `S = I` at
    /// the kinks of a continuous force, the impact law's `S` at resets). Start `x0` on the
    /// attractor (after the transient). Returns the spectrum and the final state.
    ///
    /// # Errors
    /// Invalid options or state, integration failures (each window is capped by
    /// [`FlowOptions::max_steps`] and [`FlowOptions::max_events`]), a non-finite tangent map.
    pub fn lyapunov(
        &self,
        t0: f64,
        x0: &[f64],
        opts: &LyapunovOptions,
    ) -> Result<(LyapunovSpectrum, Vec<f64>)> {
        check(t0.is_finite(), "t0", "finite", t0)?;
        self.check_state(x0)?;
        let mut x = x0.to_vec();
        let spec = lyapunov_qr(self.dim(), opts, |j| {
            let f = self.flow(t0 + j as f64 * opts.window, &x, opts.window, true)?;
            x = f.state;
            let jacobian = f.jacobian.ok_or(OrbitError::NonFinite {
                what: "window Jacobian",
                time: f.time,
            })?;
            Ok(WindowMap {
                jacobian,
                events: f.events.len(),
                impacts: f.events.iter().filter(|e| e.impact).count(),
            })
        })?;
        Ok((spec, x))
    }

    /// `[min, max]` of every event function (gap function) along the flow from `(t₀, x0)` over
    /// `periods` forcing periods: a grazing is a zero of one of them.
    ///
    /// # Errors
    /// Invalid input, integration failures.
    pub fn event_extrema(&self, x0: &[f64], periods: usize) -> Result<Vec<[f64; 2]>> {
        check(periods >= 1, "periods", ">= 1", periods as f64)?;
        let f = self.flow_recorded(self.t0, x0, periods as f64 * self.period, false)?;
        Ok(flow::extrema(
            self.field(),
            &self.options,
            &f.pieces,
            (f.time, &f.state),
        ))
    }
}
