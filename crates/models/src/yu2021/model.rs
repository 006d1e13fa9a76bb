//! Dimensionless Yu 2021 models, their right-hand sides and the closed-loop time integration.

use backlash::BacklashLaw;
use math::DetMath;
use mesh_stiffness::StiffnessLaw;
use serde::{Deserialize, Serialize};

use crate::Error;

use super::params::Yu2021Params;

/// Which of the three spur-pair models of Yu's comparison (Sec. 4.4) to solve.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[non_exhaustive]
pub enum ModelKind {
    /// Kahraman & Singh 1991: 1-DOF torsional DTE, constant backlash `b_s`.
    KahramanSingh,
    /// Chen et al.: 1-DOF torsional DTE with time-varying fractal backlash
    /// `B(t) = b_s + a_z z(ω_h t)`, `z` of Eq. (3).
    ChenFractal,
    /// Yu et al. 2021: 6-DOF transverse-torsional pair, Eq. (12)–(16), dynamic backlash Eq. (11).
    #[default]
    Yu,
}

/// Which dimensionless equations to integrate (reading R-YU-EQ19).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[non_exhaustive]
pub enum EquationForm {
    /// Derived from Eq. (12)–(15): the state is the relative torsional displacement
    /// `u = R_p θ_p − R_g θ_g` plus the four centre coordinates, `δ` of Eq. (15) is evaluated
    /// algebraically, so the bearing forces, the `m_e(1/m_p+1/m_g)` mesh-force term, `α̇` and
    /// `ë = −ω*² e` all enter. For the torsional models the STE forcing is `ω*² ē cos(ω* τ + φ_0)`.
    #[default]
    Consistent,
    /// Eq. (19) as printed: `δ*` is a state and obeys a 1-DOF equation with right-hand side
    /// `T* + T_ah`, `T_ah = e/b_n` (no `ω*²`), uncoupled from the centre motion.
    Printed,
}

/// When the dynamic backlash `B(t)` of Eq. (11) is evaluated (Fig. 8).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[non_exhaustive]
pub enum BacklashUpdate {
    /// Fig. 8 as printed: `B` is computed from the centre displacements at the start of each
    /// step ("obtained by past step") and held over the step.
    PreviousStep,
    /// `B(x_p, y_p, x_g, y_g)` is a function of the state, evaluated inside every right-hand
    /// side call.
    #[default]
    InRhs,
}

/// Law for the operating pressure angle `α` (Eq. 16, reading R-YU-EQ16): the `backlash`
/// leaf's one enum, [`backlash::PressureAngleLaw`] (`Involute`, formerly the model's own
/// `Operating`, is the model's default).
pub use backlash::PressureAngleLaw;

/// Law for the dynamic part `b_dy` of the backlash (reading R-YU-EQ6).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[non_exhaustive]
pub enum DynamicBacklashLaw {
    /// Eq. (10): `b_dy = sqrt(Δa² − Δp²)` with `Δp = R_pb/2 (β_c² − β_0²)`, `β = tan α`
    /// (never negative; clamped to 0 when `Δp² > Δa²`).
    #[default]
    Eq10,
    /// Signed involute geometry, `b_dy = Δa sin α`: the play along the line of action grows
    /// when the centres separate and shrinks when they approach.
    Involute,
    /// `b_dy = 0`: constant backlash with the 6-DOF dynamics.
    Off,
}

/// Sign of the centre separation in the centre distance, Eq. (8)–(9) (reading R-YU-EQ8): the
/// `backlash` leaf's one enum, [`backlash::CentreDistanceForm`]. The model's default is
/// [`CentreDistanceForm::Consistent`] (the frame of Eq. 12 and 15, in which a growing
/// `x_p − x_g` compresses the mesh), passed explicitly by [`Options::default`]; the leaf's own
/// default is the printed form.
pub use backlash::CentreDistanceForm;

/// Model options. `Options::default()` is Yu's 6-DOF model in the consistent form.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Options {
    /// Which model.
    pub kind: ModelKind,
    /// Consistent (derived) or printed Eq. (19).
    pub form: EquationForm,
    /// Fig. 8 as printed or state-dependent backlash.
    pub update: BacklashUpdate,
    /// Pressure-angle law.
    pub pressure_angle: PressureAngleLaw,
    /// Dynamic-backlash law.
    pub dynamic_backlash: DynamicBacklashLaw,
    /// Sign convention of the centre distance, Eq. (8).
    pub centre_distance: CentreDistanceForm,
    /// Lock the four centre coordinates (infinitely stiff bearings): the 6-DOF model reduces
    /// to the torsional one and `B = b_s`.
    pub lock_centres: bool,
}

impl Default for Options {
    /// Yu's 6-DOF model, consistent form: the operating pressure angle
    /// ([`PressureAngleLaw::Involute`]) and the consistent Eq. (8) sign
    /// ([`CentreDistanceForm::Consistent`], not the leaf's default), both given explicitly.
    fn default() -> Self {
        Options {
            kind: ModelKind::default(),
            form: EquationForm::default(),
            update: BacklashUpdate::default(),
            pressure_angle: PressureAngleLaw::Involute,
            dynamic_backlash: DynamicBacklashLaw::default(),
            centre_distance: CentreDistanceForm::Consistent,
            lock_centres: false,
        }
    }
}

impl Options {
    /// The Kahraman–Singh reference model (consistent forcing).
    pub fn kahraman_singh() -> Self {
        Options {
            kind: ModelKind::KahramanSingh,
            ..Options::default()
        }
    }
    /// Chen's fractal-backlash model (consistent forcing).
    pub fn chen() -> Self {
        Options {
            kind: ModelKind::ChenFractal,
            ..Options::default()
        }
    }
    /// Yu's model exactly as printed: Eq. (19), Eq. (16), Eq. (10), Fig. 8 update.
    pub fn yu_as_printed() -> Self {
        Options {
            kind: ModelKind::Yu,
            form: EquationForm::Printed,
            update: BacklashUpdate::PreviousStep,
            pressure_angle: PressureAngleLaw::PrintedEq16,
            dynamic_backlash: DynamicBacklashLaw::Eq10,
            centre_distance: CentreDistanceForm::PrintedEq8,
            lock_centres: false,
        }
    }
}

/// The dimensionless Yu 2021 parameters, built from [`Yu2021Params`] in one place
/// ([`Yu2021Dimensionless::from_params`]). Time `τ = ω_n t`, lengths over `b_n`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Yu2021Dimensionless {
    /// `ω_n = sqrt(k_am/m_e)` (rad/s).
    pub omega_n: f64,
    /// `m_e` (kg).
    pub m_e: f64,
    /// `b_n` (m).
    pub b_n: f64,
    /// `F_s = T_p/R_p` (N).
    pub f_s: f64,
    /// `T* = F_s/(k_am b_n)`.
    pub load: f64,
    /// `ζ = c_m/(ω_n m_e) = 2 ξ_c`.
    pub zeta: f64,
    /// `ε`.
    pub epsilon: f64,
    /// `ē = e_r/b_n`.
    pub ste: f64,
    /// `φ_0` (rad).
    pub phase: f64,
    /// `[m_e/m_p, m_e/m_g]`.
    pub mass_ratio: [f64; 2],
    /// `[κ_px, κ_py, κ_gx, κ_gy]`, `κ_ij = k_ij/(m_i ω_n²)`.
    pub kappa: [f64; 4],
    /// `[ζ_px, ζ_py, ζ_gx, ζ_gy]`, `ζ_ij = c_ij/(m_i ω_n) = 2 ξ_b sqrt(κ_ij)`.
    pub zeta_bearing: [f64; 4],
    /// `a_0/b_n`, `a_0 = R_p + R_g`.
    pub centre_distance: f64,
    /// `R_pb/b_n`, `R_pb = R_p cos α_0`.
    pub base_radius_p: f64,
    /// `α_0` (rad).
    pub alpha0: f64,
    /// `b_s/b_n`.
    pub backlash: f64,
    /// `a_z/b_n` (Chen).
    pub chen_amplitude: f64,
    /// `D` of Chen's Eq. (3).
    pub chen_dimension: f64,
}

impl Yu2021Dimensionless {
    /// Dimensional → dimensionless (validates the parameters first).
    pub fn from_params(p: &Yu2021Params) -> Result<Self, Error> {
        p.validate()?;
        let m_e = p.equivalent_mass();
        let omega_n = p.natural_frequency();
        let b_n = p.nominal_length;
        let f_s = p.static_force();
        let masses = [p.mass_p, p.mass_p, p.mass_g, p.mass_g];
        let mut kappa = [0.0; 4];
        let mut zeta_bearing = [0.0; 4];
        for i in 0..4 {
            kappa[i] = p.bearing_stiffness[i] / (masses[i] * omega_n * omega_n);
            zeta_bearing[i] = 2.0 * p.bearing_damping_ratio * kappa[i].sqrt();
        }
        Ok(Yu2021Dimensionless {
            omega_n,
            m_e,
            b_n,
            f_s,
            load: f_s / (p.mesh_stiffness * b_n),
            zeta: 2.0 * p.mesh_damping_ratio,
            epsilon: p.stiffness_ratio,
            ste: p.ste_amplitude / b_n,
            phase: p.phase,
            mass_ratio: [m_e / p.mass_p, m_e / p.mass_g],
            kappa,
            zeta_bearing,
            centre_distance: (p.radius_p + p.radius_g) / b_n,
            base_radius_p: p.radius_p * p.pressure_angle.dcos() / b_n,
            alpha0: p.pressure_angle,
            backlash: p.backlash.constant_part()? / b_n,
            chen_amplitude: p.chen_amplitude / b_n,
            chen_dimension: p.chen_dimension,
        })
    }
}

/// Number of state entries: `[q, x_p, y_p, x_g, y_g, q', x_p', y_p', x_g', y_g']`, `q = u`
/// (consistent 6-DOF) or `q = δ*` (printed and torsional models).
pub const STATE_LEN: usize = 10;

/// The dead zone of Eq. (14): `f(δ) = δ − B` above `B`, `δ + B` below `−B`, 0 between.
/// (Re-export of [`backlash::dead_zone`]; a negative `b` is treated as 0.)
pub fn dead_zone(delta: f64, b: f64) -> f64 {
    backlash::dead_zone(delta, b)
}

/// Geometry of the current state: pressure angle, its rate and the dynamic backlash.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MeshGeometry {
    /// Operating pressure angle `α` (rad).
    pub alpha: f64,
    /// `dα/dτ`.
    pub alpha_rate: f64,
    /// Centre-distance change `Δa/b_n`, Eq. (9).
    pub centre_change: f64,
    /// Dynamic part `b_dy/b_n`, Eq. (10).
    pub dynamic_part: f64,
    /// Complete backlash `B/b_n = max(b_s + b_dy, 0)`, Eq. (11).
    pub backlash: f64,
}

/// The terms of [`Yu2021Model::rhs`] that depend on `τ` and the displacements alone (not on
/// the velocities), for callers that vary only the velocities or `u` (the 6-DOF system's
/// finite-difference Jacobian).
#[derive(Debug, Clone, Copy)]
pub(crate) struct PositionTerms {
    /// The half gap before the clamp at 0.
    gap: f64,
    /// `gap − b_s`.
    dynamic_part: f64,
    /// The line of action's position part (Yu's model; `None` for the torsional ones).
    line: Option<crate::pair::mesh::LinePosition>,
    /// `α₀`, the angle without a line.
    alpha0: f64,
    /// `(sin α, cos α)` where the right-hand side reads them.
    sin_cos: Option<(f64, f64)>,
}

impl PositionTerms {
    /// The geometry of the state `s` (its velocities `s[6..10]` complete the line).
    #[inline]
    fn geometry(&self, s: &[f64; STATE_LEN]) -> MeshGeometry {
        let (alpha, alpha_rate, centre_change) = match &self.line {
            Some(l) => {
                let line = l.with_velocity(&s[6..10]);
                (line.alpha, line.alpha_rate, line.centre_change)
            }
            None => (self.alpha0, 0.0, 0.0),
        };
        MeshGeometry {
            alpha,
            alpha_rate,
            centre_change,
            dynamic_part: self.dynamic_part,
            backlash: self.gap.max(0.0),
        }
    }
}

/// The terms of [`Yu2021Model::rhs`] that depend on `τ` alone.
#[derive(Debug, Clone, Copy)]
pub(crate) struct TimeTerms {
    /// `k/k_am` of Eq. (17).
    stiffness: f64,
    /// `(e, e')` of the static error where the DTE is on the line of action.
    static_error: Option<(f64, f64)>,
}

/// A dimensionless Yu 2021 model: parameters plus options. `Send + Sync + Copy`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Yu2021Model {
    /// Dimensionless parameters.
    pub params: Yu2021Dimensionless,
    /// Model options.
    pub options: Options,
}

/// Most steps (transient and recorded) of one run; larger runs are refused with an error.
pub const MAX_RUN_STEPS: u64 = 10_000_000_000;
/// Most recorded samples of one run (five series of `f64` are kept: 400 MB at the bound).
pub const MAX_RECORDED_SAMPLES: u64 = 10_000_000;

/// Settings of one steady-state run at the dimensionless mesh frequency `ω* = ω_h/ω_n`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RunSettings {
    /// `ω*` (–).
    pub omega: f64,
    /// Mesh periods discarded as transient.
    pub transient_periods: usize,
    /// Mesh periods recorded.
    pub record_periods: usize,
    /// Minimum RK4 steps per mesh period (raised automatically so that `Δτ ≤ 0.2/ω_max`).
    pub steps_per_period: usize,
}

impl RunSettings {
    /// 200 transient + 20 recorded periods, 256 steps per period.
    pub fn new(omega: f64) -> Self {
        RunSettings {
            omega,
            transient_periods: 200,
            record_periods: 20,
            steps_per_period: 256,
        }
    }
}

/// A recorded steady-state response (dimensionless; multiply lengths by `b_n`, forces by
/// `k_am b_n`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Response {
    /// `ω*` of the run.
    pub omega: f64,
    /// Samples per mesh period.
    pub steps_per_period: usize,
    /// `T*`, for the dynamic factor.
    pub load: f64,
    /// Dimensionless time of each sample.
    pub tau: Vec<f64>,
    /// DTE `δ*` of Eq. (15).
    pub dte: Vec<f64>,
    /// Mesh force `F_m/(k_am b_n)`, Eq. (13).
    pub force: Vec<f64>,
    /// Backlash `B/b_n`, Eq. (11).
    pub backlash: Vec<f64>,
    /// Pressure angle `α` (rad).
    pub alpha: Vec<f64>,
    /// State at the end of the run.
    pub final_state: [f64; STATE_LEN],
    /// Work counters of the whole run (transient and record). Fixed-step RK4: every step
    /// accepted, none rejected, four right-hand sides per step, no events; Dormand–Prince:
    /// the engine's counters (absent in data written before it existed: zeros).
    #[serde(default)]
    pub stats: timestep::Stats,
}

impl Response {
    /// Dynamic factor, Eq. (20): `max F_m / F_s` ([`crate::response::dynamic_factor`]; NaN for an
    /// empty or non-finite record).
    pub fn dynamic_factor(&self) -> f64 {
        crate::response::dynamic_factor(&self.force, self.load).unwrap_or(f64::NAN)
    }

    /// Amplitudes `A_i` (units of `b_n`) of the first `n` mesh harmonics of the DTE, from the
    /// Fourier projection over the recorded whole periods
    /// ([`timestep::fourier_projection`]; zeros for an empty record).
    pub fn harmonic_amplitudes(&self, n: usize) -> Vec<f64> {
        timestep::harmonic_amplitudes_of_projection(&self.fourier_coefficients(n))
    }

    /// Fourier coefficients `[c_0, a_1, b_1, …, a_h, b_h]` of the DTE over the recorded
    /// whole periods (the layout of [`super::HbmSolution::coefficients`]; a harmonic-balance
    /// starting guess), by [`timestep::fourier_projection`]; zeros for an empty record, NaN
    /// for a non-finite one.
    pub fn fourier_coefficients(&self, h: usize) -> Vec<f64> {
        if self.dte.is_empty() {
            return vec![0.0; 2 * h + 1];
        }
        timestep::fourier_projection(&self.tau, &self.dte, self.omega, h)
            .unwrap_or_else(|_| vec![f64::NAN; 2 * h + 1])
    }

    /// RMS of Eq. (21): `sqrt(Σ A_i²/n)` over the first `n` mesh harmonics (units of `b_n`),
    /// [`crate::response::rms_of_harmonics`]; 0 for `n = 0`, NaN for a non-finite record.
    pub fn rms(&self, n: usize) -> f64 {
        if n == 0 {
            return 0.0;
        }
        crate::response::rms_of_harmonics(&self.harmonic_amplitudes(n)).unwrap_or(f64::NAN)
    }

    /// Mean of a series.
    fn mean(v: &[f64]) -> f64 {
        if v.is_empty() {
            0.0
        } else {
            v.iter().sum::<f64>() / v.len() as f64
        }
    }

    /// Mean DTE `δ*`.
    pub fn mean_dte(&self) -> f64 {
        Self::mean(&self.dte)
    }

    /// Mean backlash `B/b_n` (Fig. 9).
    pub fn mean_backlash(&self) -> f64 {
        Self::mean(&self.backlash)
    }

    /// Peak-to-peak DTE.
    pub fn dte_peak_to_peak(&self) -> f64 {
        let max = self.dte.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let min = self.dte.iter().copied().fold(f64::INFINITY, f64::min);
        max - min
    }
}

impl Yu2021Model {
    /// Build from dimensional parameters (validated) and options.
    pub fn new(params: &Yu2021Params, options: Options) -> Result<Self, Error> {
        Ok(Yu2021Model {
            params: Yu2021Dimensionless::from_params(params)?,
            options,
        })
    }

    fn six_dof(&self) -> bool {
        self.options.kind == ModelKind::Yu && !self.options.lock_centres
    }

    /// The mesh stiffness of Eq. (17), `k/k_am = 1 + ε sin(ω*τ + φ_0)`, as the `mesh-stiffness`
    /// leaf's law at `ω*` (dimensionless: `k_0 = 1`, `k_r = ε`).
    #[inline]
    pub fn mesh_stiffness_law(&self, omega: f64) -> mesh_stiffness::SingleHarmonicStiffness {
        mesh_stiffness::SingleHarmonicStiffness {
            k0: 1.0,
            k_r: self.params.epsilon,
            omega_e: omega,
            phi_m: self.params.phase,
            waveform: mesh_stiffness::Waveform::Sine,
        }
    }

    /// The dynamic-backlash law of this model as the `backlash` leaf's [`backlash::DynamicBacklash`]
    /// (lengths over `b_n`): pair radii from `a_0` and `R_pb`, the pressure-angle law, the
    /// Eq. (8) sign and the dynamic form of [`Options`]. `Eq10` takes β_0 from the law at rest
    /// ([`backlash::Beta0::LawAtRest`]) and clamps a negative radicand to 0; `Involute` is the
    /// leaf's [`backlash::DynamicForm::LineOfAction`] (`Δa sin α`, a half-gap change); `Off`
    /// is never evaluated. The same numbers as the leaf by construction (test
    /// `leaf_and_model_dynamic_backlash_are_the_same_number`).
    pub fn dynamic_backlash_law(&self) -> backlash::DynamicBacklash {
        let p = &self.params;
        let r_p = p.base_radius_p / system::involute::cos_standard_angle(p.alpha0);
        backlash::DynamicBacklash {
            geometry: backlash::PairGeometry {
                r_p,
                r_g: p.centre_distance - r_p,
                alpha0: p.alpha0,
            },
            b_s: p.backlash,
            form: match self.options.dynamic_backlash {
                DynamicBacklashLaw::Eq10 => backlash::DynamicForm::YuEq10,
                DynamicBacklashLaw::Involute | DynamicBacklashLaw::Off => {
                    backlash::DynamicForm::LineOfAction
                }
            },
            law: self.options.pressure_angle,
            policy: backlash::RadicandPolicy::ClampZero,
            centre_distance: self.options.centre_distance,
            beta0: backlash::Beta0::LawAtRest,
        }
    }

    /// The backlash law of this model at `ω*` as the `backlash` leaf's [`backlash::Backlash`]
    /// (lengths over `b_n`, time `τ`): Kahraman–Singh a constant `b_s`; Chen
    /// [`backlash::ChenBacklash`] `b_s + a_z z(ω*τ)` (`λ = 1.5`, 12 terms, as [`chen_z`](super::chen_z)); Yu
    /// the dynamic law [`Yu2021Model::dynamic_backlash_law`] (a constant `b_s` for
    /// [`DynamicBacklashLaw::Off`]). [`Yu2021Model::geometry`] evaluates it through
    /// [`backlash::BacklashLaw`].
    pub fn backlash_law(&self, omega: f64) -> backlash::Backlash {
        let p = &self.params;
        match self.options.kind {
            ModelKind::KahramanSingh => backlash::Backlash::Constant { b: p.backlash },
            ModelKind::ChenFractal => backlash::Backlash::Chen(backlash::ChenBacklash {
                b_s: p.backlash,
                amplitude: p.chen_amplitude,
                omega,
                fractal: super::fractal::chen_fractal(p.chen_dimension),
            }),
            ModelKind::Yu => match self.options.dynamic_backlash {
                DynamicBacklashLaw::Off => backlash::Backlash::Constant { b: p.backlash },
                _ => backlash::Backlash::Dynamic(self.dynamic_backlash_law()),
            },
        }
    }

    /// Pressure angle and backlash of a state (Eq. 9–11, 16). For the torsional models and
    /// locked centres the centre terms vanish. The half gap is [`Yu2021Model::backlash_law`]'s
    /// ([`backlash::BacklashLaw::half_gap`]), clamped at 0; a non-finite state gives a
    /// non-finite backlash (the engines report it).
    pub fn geometry(&self, omega: f64, tau: f64, s: &[f64; STATE_LEN]) -> MeshGeometry {
        self.position_terms(omega, tau, s, false).geometry(s)
    }

    /// The terms of the right-hand side that depend on `τ` and the displacements `s[1..5]`
    /// alone: the half gap, the line of action's position part, and with `sin_cos` the angle's
    /// `(sin α, cos α)` where the right-hand side reads them.
    pub(crate) fn position_terms(
        &self,
        omega: f64,
        tau: f64,
        s: &[f64; STATE_LEN],
        sin_cos: bool,
    ) -> PositionTerms {
        let p = &self.params;
        let c = backlash::CentreDisplacement::new(s[1], s[2], s[3], s[4]);
        // A dynamic backlash's evaluation has computed the centre distance and the angle of
        // the line of action already: the line reads them (the same numbers, Eq. 8–9, 16)
        let (gap, line) = match self.backlash_law(omega) {
            backlash::Backlash::Dynamic(law) => match law.eval(&c) {
                Ok(e) => (e.b, crate::pair::mesh::line_position_from(&law, &e)),
                Err(_) => (f64::NAN, None),
            },
            other => (other.half_gap(tau, &c).map_or(f64::NAN, |g| g.b), None),
        };
        let line = match self.options.kind {
            ModelKind::KahramanSingh | ModelKind::ChenFractal => None,
            ModelKind::Yu => {
                // Eq. (8)–(9), (16): the pair's one mesh kinematics on the leaf's geometry
                Some(line.unwrap_or_else(|| {
                    let law = self.dynamic_backlash_law();
                    crate::pair::mesh::line_position(
                        &law.geometry,
                        law.centre_distance,
                        law.law,
                        &c,
                    )
                }))
            }
        };
        let alpha = line.map_or(p.alpha0, |l| l.alpha);
        let sin_cos = sin_cos.then(|| alpha.dsin_cos());
        PositionTerms {
            gap,
            dynamic_part: gap - p.backlash,
            line,
            alpha0: p.alpha0,
            sin_cos,
        }
    }

    /// Whether the right-hand side reads `(sin α, cos α)`: for the transmission error or the
    /// force directions.
    pub(crate) fn rhs_reads_sin_cos(&self) -> bool {
        self.six_dof() || self.transmission_error_on_line()
    }

    /// Whether the DTE is the line-of-action projection of Eq. (13)–(15) (Yu's consistent
    /// form) rather than the state's own coordinate.
    fn transmission_error_on_line(&self) -> bool {
        self.options.kind == ModelKind::Yu && self.options.form == EquationForm::Consistent
    }

    /// The terms of the right-hand side that depend on `τ` alone: the mesh stiffness of
    /// Eq. (17) and the static error.
    #[inline]
    pub(crate) fn time_terms(&self, omega: f64, tau: f64) -> TimeTerms {
        TimeTerms {
            stiffness: self.mesh_stiffness_law(omega).stiffness(tau),
            static_error: self.static_error_on_line(omega, tau),
        }
    }

    /// `(e, e')` of the static error where the DTE is on the line of action, else `None`.
    #[inline]
    fn static_error_on_line(&self, omega: f64, tau: f64) -> Option<(f64, f64)> {
        let p = &self.params;
        self.transmission_error_on_line()
            .then(|| crate::pair::mesh::static_error(p.ste, omega, p.phase, tau))
    }

    /// DTE `δ*`, its rate, and the mesh force `F*` for a state and a backlash `b` (Eq. 13–15).
    pub fn mesh(
        &self,
        omega: f64,
        tau: f64,
        s: &[f64; STATE_LEN],
        g: &MeshGeometry,
        b: f64,
    ) -> (f64, f64, f64) {
        // `(sin α, cos α)`: computed by [`Self::dte`] where the DTE is on the line of action
        self.mesh_with(s, g, b, &self.time_terms(omega, tau), None)
    }

    /// The DTE `δ*` of a state and its backlash `B` (the event functions' inputs): what
    /// [`Self::geometry`] and [`Self::mesh`] give, without the mesh stiffness.
    pub(crate) fn dte_and_backlash(
        &self,
        omega: f64,
        tau: f64,
        s: &[f64; STATE_LEN],
    ) -> (f64, f64) {
        let g = self.position_terms(omega, tau, s, false).geometry(s);
        let static_error = self.static_error_on_line(omega, tau);
        (self.dte(s, &g, static_error, None).0, g.backlash)
    }

    /// [`Self::mesh`] from the time terms and `(sin α, cos α)`.
    #[inline]
    fn mesh_with(
        &self,
        s: &[f64; STATE_LEN],
        g: &MeshGeometry,
        b: f64,
        time: &TimeTerms,
        sin_cos: Option<(f64, f64)>,
    ) -> (f64, f64, f64) {
        let p = &self.params;
        let (delta, delta_rate) = self.dte(s, g, time.static_error, sin_cos);
        (
            delta,
            delta_rate,
            time.stiffness * dead_zone(delta, b) + p.zeta * delta_rate,
        )
    }

    /// `(δ*, δ*')` of Eq. (13)–(15) from the geometry and the static error (given exactly where
    /// the DTE is on the line of action), with `(sin α, cos α)` if the caller has them (computed
    /// here if not); the state's own `(q, q')` else.
    #[inline]
    fn dte(
        &self,
        s: &[f64; STATE_LEN],
        g: &MeshGeometry,
        static_error: Option<(f64, f64)>,
        sin_cos: Option<(f64, f64)>,
    ) -> (f64, f64) {
        match static_error {
            // given exactly where the DTE is on the line of action ([`Self::time_terms`],
            // [`Self::dte_and_backlash`]); `(sin α, cos α)` computed here if not given
            Some(static_error) => {
                let sin_cos = sin_cos.unwrap_or_else(|| g.alpha.dsin_cos());
                // Eq. (13)–(15): the pair's one mesh kinematics (`crate::pair::mesh`)
                let line = crate::pair::mesh::LineOfAction {
                    alpha: g.alpha,
                    alpha_rate: g.alpha_rate,
                    centre_change: g.centre_change,
                };
                crate::pair::mesh::transmission_error_sin_cos(
                    (s[0], s[5]),
                    &s[1..5],
                    &s[6..10],
                    &line,
                    sin_cos,
                    static_error,
                )
            }
            None => (s[0], s[5]),
        }
    }

    /// Right-hand side `ds/dτ`. `held` is the backlash held over a step (Fig. 8 as printed);
    /// `None` evaluates `B` from the state.
    pub fn rhs(
        &self,
        omega: f64,
        tau: f64,
        s: &[f64; STATE_LEN],
        held: Option<f64>,
    ) -> [f64; STATE_LEN] {
        let position = self.position_terms(omega, tau, s, self.rhs_reads_sin_cos());
        self.rhs_with(omega, tau, s, held, &self.time_terms(omega, tau), &position)
    }

    /// [`Self::rhs`] from its time and position terms (of the same `τ` and `s[1..5]`).
    pub(crate) fn rhs_with(
        &self,
        omega: f64,
        tau: f64,
        s: &[f64; STATE_LEN],
        held: Option<f64>,
        time: &TimeTerms,
        position: &PositionTerms,
    ) -> [f64; STATE_LEN] {
        let p = &self.params;
        let g = position.geometry(s);
        let b = held.unwrap_or(g.backlash);
        let (_, _, force) = self.mesh_with(s, &g, b, time, position.sin_cos);
        let w = omega;
        let mut d = [0.0; STATE_LEN];
        d[..5].copy_from_slice(&s[5..]);
        let consistent = self.options.form == EquationForm::Consistent;
        d[5] = match (self.options.kind, consistent) {
            (ModelKind::Yu, true) => p.load - force,
            (_, true) => p.load + w * w * p.ste * (w * tau + p.phase).dcos() - force,
            (_, false) => p.load + p.ste * (w * tau + p.phase).dcos() - force,
        };
        if self.six_dof() {
            // computed with the position terms ([`Self::rhs_reads_sin_cos`]), else here
            let (sa, ca) = position.sin_cos.unwrap_or_else(|| g.alpha.dsin_cos());
            let dirs = [sa, ca, -sa, -ca];
            let mu = [
                p.mass_ratio[0],
                p.mass_ratio[0],
                p.mass_ratio[1],
                p.mass_ratio[1],
            ];
            for i in 0..4 {
                d[6 + i] =
                    -p.zeta_bearing[i] * s[6 + i] - p.kappa[i] * s[1 + i] - mu[i] * force * dirs[i];
            }
        } else {
            d[1..5].fill(0.0);
            d[6..].fill(0.0);
        }
        d
    }

    /// Static-contact initial state: `q = b_s + T*`, centres at rest at the origin.
    pub fn initial_state(&self) -> [f64; STATE_LEN] {
        let mut s = [0.0; STATE_LEN];
        s[0] = self.params.backlash + self.params.load;
        s
    }

    /// Largest natural frequency estimate (Gershgorin bound) used to limit the step.
    fn omega_max(&self) -> f64 {
        let p = &self.params;
        let mut m = 1.0 + 2.0 * p.zeta;
        if self.six_dof() {
            m += p.mass_ratio[0] + p.mass_ratio[1];
            for i in 0..4 {
                m = m.max(p.kappa[i] + p.zeta_bearing[i] + p.mass_ratio[i / 2] * (1.0 + p.zeta));
            }
        }
        m.sqrt()
    }

    /// Validates `ω*` and the recorded periods and returns the samples (RK4 steps) per mesh
    /// period: `steps_per_period`, at least 8, raised so that `Δτ ≤ 0.2/ω_max`.
    pub(super) fn samples_per_period(&self, settings: &RunSettings) -> Result<usize, Error> {
        let w = settings.omega;
        if !(w > 0.0 && w.is_finite()) {
            return Err(Error::invalid("yu2021.omega", "> 0 and finite", w));
        }
        if settings.record_periods == 0 {
            return Err(Error::invalid("yu2021.record_periods", ">= 1", 0.0));
        }
        let period = std::f64::consts::TAU / w;
        let dt_max = 0.2 / self.omega_max();
        // Sizes in f64 first: nothing below may overflow or allocate beyond the bounds.
        let n = (settings.steps_per_period.max(8) as f64).max((period / dt_max).ceil());
        let periods = settings.transient_periods as f64 + settings.record_periods as f64;
        let total = periods * n;
        if total.is_nan() || total > MAX_RUN_STEPS as f64 {
            return Err(Error::invalid(
                "yu2021.steps",
                format!(
                    "<= {MAX_RUN_STEPS} steps per run ((transient_periods + record_periods) × \
                     steps per period, the latter raised to {n:.3e} so that Δτ ≤ 0.2/ω_max)"
                ),
                total,
            ));
        }
        let recorded = settings.record_periods as f64 * n;
        if recorded.is_nan() || recorded > MAX_RECORDED_SAMPLES as f64 {
            return Err(Error::invalid(
                "yu2021.record_periods",
                format!("such that record_periods × steps per period <= {MAX_RECORDED_SAMPLES}"),
                settings.record_periods as f64,
            ));
        }
        Ok(n as usize)
    }

    /// Total RK4 steps (samples) of one run with these settings, checked against
    /// [`MAX_RUN_STEPS`] and [`MAX_RECORDED_SAMPLES`] before anything is allocated.
    pub fn run_steps(&self, settings: &RunSettings) -> Result<usize, Error> {
        let n = self.samples_per_period(settings)?;
        Ok((settings.transient_periods + settings.record_periods) * n)
    }

    /// Integrate to steady state with fixed-step RK4 and record the response.
    ///
    /// Errors on a non-positive or non-finite `ω*`, zero recorded periods, or a non-finite
    /// state (reported as [`Error::Solver`]).
    pub fn simulate(
        &self,
        settings: &RunSettings,
        initial: Option<[f64; STATE_LEN]>,
    ) -> Result<Response, Error> {
        let w = settings.omega;
        let n = self.samples_per_period(settings)?;
        let model = self;
        let period = std::f64::consts::TAU / w;
        let h = period / n as f64;
        let mut s = initial.unwrap_or_else(|| model.initial_state());
        let total = (settings.transient_periods + settings.record_periods) * n;
        let start_rec = settings.transient_periods * n;
        let cap = settings.record_periods * n;
        let mut out = Response {
            omega: w,
            steps_per_period: n,
            load: model.params.load,
            tau: Vec::with_capacity(cap),
            dte: Vec::with_capacity(cap),
            force: Vec::with_capacity(cap),
            backlash: Vec::with_capacity(cap),
            alpha: Vec::with_capacity(cap),
            final_state: s,
            stats: timestep::Stats {
                n_rhs: 4 * total as u64,
                n_accepted: total as u64,
                ..timestep::Stats::default()
            },
        };
        for step in 0..total {
            let tau = step as f64 * h;
            if ::system::deadline::expired_at_step(step as u64) {
                return Err(Error::Solver(format!(
                    "{}: yu2021 stopped at tau = {tau} (step {step} of {total})",
                    ::system::deadline::REASON
                )));
            }
            let g = model.geometry(w, tau, &s);
            if step >= start_rec {
                let (delta, _, force) = model.mesh(w, tau, &s, &g, g.backlash);
                out.tau.push(tau);
                out.dte.push(delta);
                out.force.push(force);
                out.backlash.push(g.backlash);
                out.alpha.push(g.alpha);
            }
            let held = match self.options.update {
                BacklashUpdate::PreviousStep => Some(g.backlash),
                BacklashUpdate::InRhs => None,
            };
            s = model.rk4(w, tau, &s, h, held);
            if !s.iter().all(|v| v.is_finite()) {
                return Err(Error::Solver(format!(
                    "yu2021: non-finite state at tau = {tau}"
                )));
            }
        }
        out.final_state = s;
        Ok(out)
    }

    /// One step of the workspace's classical RK4 ([`::system::rk4::rk4_step`]) of [`Self::rhs`].
    fn rk4(
        &self,
        w: f64,
        t: f64,
        s: &[f64; STATE_LEN],
        h: f64,
        held: Option<f64>,
    ) -> [f64; STATE_LEN] {
        let rhs = |t: f64, y: &[f64], d: &mut [f64]| {
            let mut state = [0.0; STATE_LEN];
            state.copy_from_slice(y);
            d.copy_from_slice(&self.rhs(w, t, &state, held));
        };
        let k1 = self.rhs(w, t, s, held);
        let (mut k2, mut k3, mut k4) = ([0.0; STATE_LEN], [0.0; STATE_LEN], [0.0; STATE_LEN]);
        let (mut stage, mut r) = ([0.0; STATE_LEN], [0.0; STATE_LEN]);
        let stages = ::system::rk4::Rk4Stages {
            k1: &k1,
            k2: &mut k2,
            k3: &mut k3,
            k4: &mut k4,
            stage: &mut stage,
        };
        ::system::rk4::rk4_step(rhs, t, h, s, stages, &mut r);
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `Options::default()` keeps the model's defaults (`Involute`, the consistent Eq. 8
    /// sign), not the leaf's (`PrintedEq8`), and round-trips through serde.
    #[test]
    fn options_default_is_the_models() {
        let o = Options::default();
        assert_eq!(o.pressure_angle, PressureAngleLaw::Involute);
        assert_eq!(o.centre_distance, CentreDistanceForm::Consistent);
        assert_ne!(CentreDistanceForm::default(), o.centre_distance);
        let back: Options = serde_json::from_value(serde_json::to_value(o).unwrap()).unwrap();
        assert_eq!(back, o);
    }

    fn state(x_p: f64, y_p: f64, x_g: f64, y_g: f64) -> [f64; STATE_LEN] {
        let mut s = [0.0; STATE_LEN];
        s[1..5].copy_from_slice(&[x_p, y_p, x_g, y_g]);
        s[6..].copy_from_slice(&[0.3, -0.1, 0.2, 0.05]);
        s
    }

    /// Every pressure-angle law and Eq. (8) sign under each of the `dynamic` backlash laws.
    fn option_grid(dynamic: &[DynamicBacklashLaw]) -> Vec<Options> {
        let mut out = Vec::new();
        for &dynamic_backlash in dynamic {
            for pressure_angle in [
                PressureAngleLaw::Involute,
                PressureAngleLaw::PrintedEq16,
                PressureAngleLaw::Constant,
            ] {
                for centre_distance in [
                    CentreDistanceForm::Consistent,
                    CentreDistanceForm::PrintedEq8,
                ] {
                    out.push(Options {
                        dynamic_backlash,
                        pressure_angle,
                        centre_distance,
                        ..Options::default()
                    });
                }
            }
        }
        out
    }

    /// The geometry reads the line of action from the dynamic backlash's evaluation: the
    /// numbers of the two separate constructions (the half gap of [`Yu2021Model::backlash_law`]
    /// and [`crate::pair::mesh::line_of_action`]), bit for bit, for every dynamic law,
    /// pressure-angle law and Eq. (8) sign, centres that move apart and together, the
    /// angle clamped (at and below the law's `c`), and a non-finite state.
    #[test]
    fn geometry_is_the_separate_constructions_bit_for_bit() {
        let params = Yu2021Params::table1();
        let bits = |g: &MeshGeometry| {
            [
                g.alpha,
                g.alpha_rate,
                g.centre_change,
                g.dynamic_part,
                g.backlash,
            ]
            .map(f64::to_bits)
        };
        let all = [
            DynamicBacklashLaw::Eq10,
            DynamicBacklashLaw::Involute,
            DynamicBacklashLaw::Off,
        ];
        for o in option_grid(&all) {
            let m = Yu2021Model::new(&params, o).unwrap();
            let a0 = m.params.centre_distance;
            for centres in [
                [0.4, -0.2, -0.3, 0.1],
                [-0.4, 0.2, 0.3, -0.1],
                [1e-9, 0.0, 0.0, 0.0],
                [0.0; 4],
                // the centres pulled together by a tenth of a0: below the involute
                // law's c = a0 cos α0, where the angle is clamped
                [0.05 * a0, 0.0, -0.05 * a0, 0.0],
                [-0.05 * a0, 0.0, 0.05 * a0, 0.0],
                [f64::NAN, 0.0, 0.0, 0.0],
            ] {
                let mut s = state(centres[0], centres[1], centres[2], centres[3]);
                s[0] = 0.7;
                let c = backlash::CentreDisplacement::new(
                    centres[0], centres[1], centres[2], centres[3],
                );
                let gap = m
                    .backlash_law(1.3)
                    .half_gap(0.4, &c)
                    .map_or(f64::NAN, |g| g.b);
                let law = m.dynamic_backlash_law();
                let line = crate::pair::mesh::line_of_action(
                    &law.geometry,
                    law.centre_distance,
                    law.law,
                    &c,
                    &s[6..10],
                );
                let want = MeshGeometry {
                    alpha: line.alpha,
                    alpha_rate: line.alpha_rate,
                    centre_change: line.centre_change,
                    dynamic_part: gap - m.params.backlash,
                    backlash: gap.max(0.0),
                };
                let got = m.geometry(1.3, 0.4, &s);
                assert_eq!(bits(&got), bits(&want), "{o:?} {centres:?}");
            }
        }
    }

    /// The model's dynamic backlash is the `backlash` leaf's number (the half gap), for every
    /// law and both Eq. (8) signs, and the line-of-action form agrees with the leaf's exact
    /// involute half gap to second order in Δa (R-BACKLASH-HALF-GAP).
    #[test]
    fn leaf_and_model_dynamic_backlash_are_the_same_number() {
        let params = Yu2021Params::table1();
        for o in option_grid(&[DynamicBacklashLaw::Eq10, DynamicBacklashLaw::Involute]) {
            let m = Yu2021Model::new(&params, o).unwrap();
            let s = state(0.4, -0.2, -0.3, 0.1);
            let g = m.geometry(1.0, 0.0, &s);
            let leaf = m
                .dynamic_backlash_law()
                .eval(&backlash::CentreDisplacement::new(0.4, -0.2, -0.3, 0.1))
                .unwrap();
            assert!(
                (g.dynamic_part - leaf.b_dy).abs() <= 1e-15 * m.params.backlash,
                "{o:?}"
            );
            assert_eq!(g.centre_change.to_bits(), leaf.delta_a.to_bits());
            assert_eq!(
                g.backlash.to_bits(),
                (m.params.backlash + leaf.b_dy).max(0.0).to_bits()
            );
        }
        // half gap: the model's Δa sin α and the leaf's exact involute half change
        // (R_pb + R_gb)(inv α' − inv α_0) agree to O(Δa²); the full gap change is twice that.
        let o = Options {
            dynamic_backlash: DynamicBacklashLaw::Involute,
            ..Options::default()
        };
        let m = Yu2021Model::new(&params, o).unwrap();
        let exact = backlash::DynamicBacklash {
            form: backlash::DynamicForm::Involute,
            ..m.dynamic_backlash_law()
        };
        for x in [-0.5, -0.05, 0.05, 0.5] {
            // consistent sign: x_g > 0 moves the centres apart by x (units of b_n)
            let g = m.geometry(1.0, 0.0, &state(0.0, 0.0, x, 0.0));
            let e = exact
                .eval(&backlash::CentreDisplacement::new(0.0, 0.0, x, 0.0))
                .unwrap();
            assert!((g.centre_change - x).abs() < 1e-9 * x.abs());
            let lin = x * m.params.alpha0.dsin();
            // second-order terms: Δa² cos α_0 α'(a_0) (line of action) and half of it (exact
            // involute), α'(a_0) = cot α_0 / a_0, so cos²α_0/sin α_0 = 2.58 at 20°; plus rounding
            let a0 = m.params.centre_distance;
            let bound = 3.0 * x * x / a0 + 1e-12 * x.abs();
            assert!((g.dynamic_part - lin).abs() <= bound, "{x}");
            assert!((e.b_dy - lin).abs() <= bound, "{x}: {} vs {lin}", e.b_dy);
        }
    }

    /// Chen's and Kahraman–Singh's backlash are the leaf's laws: the same number as the
    /// closed forms `b_s + a_z z(ω*τ)` (with the model's `z`) and `b_s`.
    #[test]
    fn leaf_and_model_time_varying_backlash_are_the_same_number() {
        let params = Yu2021Params::table1();
        let chen = Yu2021Model::new(&params, Options::chen()).unwrap();
        let ks = Yu2021Model::new(&params, Options::kahraman_singh()).unwrap();
        let p = chen.params;
        let s = [0.0; STATE_LEN];
        for (w, tau) in [(0.9, 0.0), (1.3, 0.77), (0.4, 31.0)] {
            let want =
                p.backlash + p.chen_amplitude * super::super::chen_z(p.chen_dimension, tau * w);
            assert_eq!(
                chen.geometry(w, tau, &s).backlash.to_bits(),
                want.max(0.0).to_bits()
            );
            assert_eq!(
                ks.geometry(w, tau, &s).backlash.to_bits(),
                p.backlash.to_bits()
            );
        }
    }

    /// The response metrics are the `timestep` metrics on the same samples (one
    /// implementation), and exact on a trigonometric polynomial sampled over whole periods.
    #[test]
    fn response_metrics_are_the_timestep_metrics() {
        let (w, n) = (1.3, 128);
        let tau: Vec<f64> = (0..3 * n)
            .map(|i| i as f64 * std::f64::consts::TAU / (w * n as f64))
            .collect();
        let dte: Vec<f64> = tau
            .iter()
            .map(|t| 0.5 + 0.2 * (w * t).dcos() + 0.1 * (2.0 * w * t).dsin())
            .collect();
        let force: Vec<f64> = dte.iter().map(|d| 2.0 * d).collect();
        let r = Response {
            omega: w,
            steps_per_period: n,
            load: 0.8,
            tau: tau.clone(),
            dte: dte.clone(),
            force: force.clone(),
            backlash: vec![1.0; tau.len()],
            alpha: vec![0.3; tau.len()],
            final_state: [0.0; STATE_LEN],
            stats: timestep::Stats::default(),
        };
        let c = timestep::fourier_projection(&tau, &dte, w, 2).unwrap();
        assert_eq!(r.fourier_coefficients(2), c);
        let a = timestep::harmonic_amplitudes_of_projection(&c);
        assert_eq!(r.harmonic_amplitudes(2), a);
        assert_eq!(
            r.rms(2).to_bits(),
            crate::response::rms_of_harmonics(&a).unwrap().to_bits()
        );
        assert_eq!(
            r.dynamic_factor().to_bits(),
            crate::response::dynamic_factor(&force, 0.8)
                .unwrap()
                .to_bits()
        );
        assert!((a[0] - 0.2).abs() < 1e-13 && (a[1] - 0.1).abs() < 1e-13);
        assert!((r.rms(2) - (0.05f64 / 2.0).sqrt()).abs() < 1e-13);
        let nan = Response {
            dte: vec![f64::NAN; tau.len()],
            ..r.clone()
        };
        assert!(nan.rms(2).is_nan());
        assert_eq!(r.rms(0).to_bits(), 0.0f64.to_bits());
    }

    /// The mesh force uses the `mesh-stiffness` leaf's Eq. (17) law (Yu's `k_am` form) and the
    /// `backlash` leaf's dead zone: the same number as the leaves.
    #[test]
    fn leaf_and_model_mesh_stiffness_are_the_same_number() {
        let m = Yu2021Model::new(&Yu2021Params::table1(), Options::kahraman_singh()).unwrap();
        let p = m.params;
        let w = 0.9;
        let k_am = 3.0e8;
        let leaf =
            mesh_stiffness::SingleHarmonicStiffness::yu2021(k_am, p.epsilon, w, p.phase).unwrap();
        let mut s = [0.0; STATE_LEN];
        s[0] = p.backlash + 0.7;
        s[5] = 0.2;
        for tau in [0.0, 0.4, 2.3] {
            let g = m.geometry(w, tau, &s);
            let (delta, rate, force) = m.mesh(w, tau, &s, &g, g.backlash);
            let k = leaf.eval(tau) / k_am;
            assert!((m.mesh_stiffness_law(w).stiffness(tau) - k).abs() < 1e-15);
            let want = k * backlash::dead_zone(delta, g.backlash) + p.zeta * rate;
            assert!(
                (force - want).abs() < 1e-14 * (1.0 + want.abs()),
                "{force} vs {want}"
            );
        }
    }
}
