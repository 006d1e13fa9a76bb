//! A generic spur pair composed from the leaves: geometry (`gear_geometry::SpurPair`), any
//! mesh-stiffness law (`mesh_stiffness::StiffnessLaw`), any backlash law
//! (`backlash::BacklashLaw`) and the degrees of freedom ([`Dofs`]). One
//! `system::SecondOrderSystem`, so both engines solve it: `hbm::HbmProblem`
//! ([`GearPair::hbm_problem`]) and `timestep` through `timestep::Mechanical`
//! ([`GearPair::time_response`]).
//!
//! # Equations (any consistent units)
//!
//! Coordinates `q = [u]` (1-DOF torsional) or `q = [u, x_p, y_p, x_g, y_g]` (6-DOF
//! transverse-torsional), `u = R_p θ_p − R_g θ_g`, with the static balance `T_g = T_p R_g/R_p`:
//!
//! ```text
//! m_e u''   + F                              = F_s          m_e = (R_p²/I_p + R_g²/I_g)⁻¹
//! m_p x_p'' + c_px x_p' + k_px x_p + F sin α = 0            (y_p: cos α)
//! m_g x_g'' + c_gx x_g' + k_gx x_g − F sin α = 0            (y_g: cos α)
//! F = k(t) f(δ; b(t, c)) + c_m δ'                            f: dead zone, b: half gap
//! δ = u + (x_p − x_g) sin α + (y_p − y_g) cos α − e(t),      e = e_r cos(ω_e t + φ_e)
//! α = α(a(c)) (operating pressure angle, or α_0),            c = (x_p, y_p, x_g, y_g)
//! ```
//!
//! `δ'` includes the `α'` term. Events: the gap edges `δ = ±b`.
//!
//! # Presets: where the papers' models are this pair, and where not
//!
//! The pair stands under the papers and imports none of them: each preset is written in its
//! paper's folder (`yu2021/presets.rs`, `liu2021/presets.rs`), and the 6-DOF mesh kinematics
//! that Yu's model shares with the pair is [`mesh`].
//!
//! * **Yu 2021, 6-DOF, consistent form** ([`PairParams::yu2021`]): the same right-hand side
//!   in Yu's dimensionless units (`m_e = 1`, `m_i = 1/μ_i`, `k_ij = κ_ij m_i`,
//!   `c_ij = ζ_ij m_i`, `F_s = T*`), stiffness Eq. (17), backlash the model's leaf law (every
//!   dynamic-backlash option). Not covered: Eq. (19) as printed (`δ*` as a state, uncoupled from
//!   the centres) and Fig. 8's previous-step backlash update (not a function of the state).
//! * **Yu 2021, Kahraman–Singh and Chen (1-DOF)**: the torsional pair with `u = δ* + e`: Yu's
//!   `δ*'' = u'' + ω*² ē cos(ω*τ + φ_0)`; the printed Eq. (19) forcing `ē cos` (no `ω*²`) is
//!   not a spur-pair physics and is not covered.
//! * **Liu 2021** ([`PairParams::liu2021`]): only the circular limit `ε = 0`: then Eq. (9)
//!   is `q'' + 2ζ q' + k(τ) f(q; b̄) = −B₀ + d²ē/dτ²`, the torsional pair with `δ = q`,
//!   `F_s = −B₀`, `c_m = 2ζ`, `e = −ē`. For `ε > 0` the NFG's rigid-body acceleration
//!   (Eq. 20) and the `(r_b2/L)²` factor of the stiffness (Eq. 9) are no spur-pair physics;
//!   use `liu2021::Model`.
//! * **Karpov 2017** (`X'' + X = F(τ)`, no gap) is a linear oscillator with variable mesh
//!   frequency, not a pair with backlash: not a preset.

use math::DetMath;
use mesh_stiffness::{Stiffness, StiffnessLaw};
use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

use backlash::{Backlash, BacklashLaw, CentreDisplacement, CentreDistanceForm, PressureAngleLaw};

use crate::Error;

pub mod mesh;
pub mod registry;

/// Degrees of freedom of the pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Dofs {
    /// One coordinate `u` (rigid bearings).
    #[default]
    Torsional,
    /// `u` and the four centre translations.
    TransverseTorsional,
}

impl Dofs {
    /// Number of coordinates: 1 or 5.
    pub fn n(self) -> usize {
        match self {
            Dofs::Torsional => 1,
            Dofs::TransverseTorsional => 5,
        }
    }
}

/// Serde parameters of a [`GearPair`] (any consistent units; SI for a dimensional pair).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PairParams {
    /// Reference radii and nominal pressure angle.
    pub geometry: gear_geometry::SpurPairParams,
    /// Degrees of freedom.
    #[serde(default)]
    pub dofs: Dofs,
    /// Equivalent mass `m_e` (> 0), e.g. [`equivalent_mass`].
    pub equivalent_mass: f64,
    /// Masses `[m_p, m_g]` (> 0 for [`Dofs::TransverseTorsional`]).
    #[serde(default)]
    pub masses: [f64; 2],
    /// Bearing stiffnesses `[k_px, k_py, k_gx, k_gy]` (≥ 0).
    #[serde(default)]
    pub bearing_stiffness: [f64; 4],
    /// Bearing damping `[c_px, c_py, c_gx, c_gy]` (≥ 0).
    #[serde(default)]
    pub bearing_damping: [f64; 4],
    /// Mesh damping `c_m` (≥ 0).
    pub mesh_damping: f64,
    /// Static mesh force `F_s = T_p/R_p` (finite).
    pub static_force: f64,
    /// Static transmission error amplitude `e_r` (≥ 0).
    #[serde(default)]
    pub ste_amplitude: f64,
    /// STE phase `φ_e`.
    #[serde(default)]
    pub ste_phase: f64,
    /// Mesh frequency `ω_e` (> 0): the base frequency of a periodic response; the stiffness
    /// law is evaluated at it (its own `ω_e` is replaced).
    pub mesh_frequency: f64,
    /// Mesh-stiffness law.
    pub stiffness: Stiffness,
    /// Backlash law (a time-varying law keeps its frequency; [`GearPair::set_mesh_frequency`]
    /// scales it with the mesh frequency).
    pub backlash: Backlash,
    /// Operating pressure angle law `α(a)` (6-DOF; the 1-DOF pair uses `α_0`).
    #[serde(default)]
    pub pressure_angle: PressureAngleLaw,
    /// Sign of the centre separation in `a` (Yu Eq. 8); the frame of the equations above is
    /// [`CentreDistanceForm::Consistent`].
    #[serde(default = "consistent")]
    pub centre_distance: CentreDistanceForm,
}

fn consistent() -> CentreDistanceForm {
    CentreDistanceForm::Consistent
}

/// `m_e = (R_p²/I_p + R_g²/I_g)⁻¹`.
pub fn equivalent_mass(inertia_p: f64, inertia_g: f64, r_p: f64, r_g: f64) -> f64 {
    1.0 / (r_p * r_p / inertia_p + r_g * r_g / inertia_g)
}

/// A gear pair built from a stiffness law `S` and a backlash law `B`.
#[derive(Debug, Clone, PartialEq)]
pub struct GearPair<S = Stiffness, B = Backlash> {
    geometry: system::PairGeometry,
    dofs: Dofs,
    mass: [f64; 5],
    bearing_stiffness: [f64; 4],
    bearing_damping: [f64; 4],
    mesh_damping: f64,
    static_force: f64,
    ste: (f64, f64),
    omega: f64,
    pressure_angle: PressureAngleLaw,
    centre_distance: CentreDistanceForm,
    stiffness: S,
    backlash: B,
}

fn check(field: &str, v: f64, ok: bool, bound: &str) -> Result<(), Error> {
    if v.is_finite() && ok {
        Ok(())
    } else {
        Err(Error::invalid(format!("pair.{field}"), bound, v))
    }
}

impl GearPair<Stiffness, Backlash> {
    /// Build from serde parameters (validated).
    pub fn from_params(p: &PairParams) -> Result<Self, Error> {
        p.stiffness.validate().map_err(|source| Error::Stiffness {
            context: "pair.stiffness",
            source,
        })?;
        p.backlash.validate().map_err(|source| Error::Backlash {
            context: "pair.backlash",
            source,
        })?;
        let stiffness = p
            .stiffness
            .at_mesh_frequency(p.mesh_frequency)
            .map_err(|source| Error::Stiffness {
                context: "pair.stiffness",
                source,
            })?;
        GearPair::new(p, stiffness, p.backlash)
    }
}

impl<S: StiffnessLaw, B: BacklashLaw> GearPair<S, B> {
    /// Build from the numbers of `p` (its `stiffness` and `backlash` fields are ignored) and
    /// the laws `stiffness`, `backlash`. Every number is checked; the error names the field.
    pub fn new(p: &PairParams, stiffness: S, backlash: B) -> Result<Self, Error> {
        // the one spur-pair geometry (`system::PairGeometry`), validated by the geometry leaf
        let geometry = gear_geometry::SpurPair::new(p.geometry)?.geometry();
        check(
            "equivalent_mass",
            p.equivalent_mass,
            p.equivalent_mass > 0.0,
            "> 0",
        )?;
        let six = p.dofs == Dofs::TransverseTorsional;
        for (i, m) in p.masses.iter().enumerate() {
            check(&format!("masses[{i}]"), *m, !six || *m > 0.0, "> 0 (6-DOF)")?;
        }
        for i in 0..4 {
            check(
                &format!("bearing_stiffness[{i}]"),
                p.bearing_stiffness[i],
                p.bearing_stiffness[i] >= 0.0,
                ">= 0",
            )?;
            check(
                &format!("bearing_damping[{i}]"),
                p.bearing_damping[i],
                p.bearing_damping[i] >= 0.0,
                ">= 0",
            )?;
        }
        check(
            "mesh_damping",
            p.mesh_damping,
            p.mesh_damping >= 0.0,
            ">= 0",
        )?;
        check("static_force", p.static_force, true, "finite")?;
        check(
            "ste_amplitude",
            p.ste_amplitude,
            p.ste_amplitude >= 0.0,
            ">= 0",
        )?;
        check("ste_phase", p.ste_phase, true, "finite")?;
        check(
            "mesh_frequency",
            p.mesh_frequency,
            p.mesh_frequency > 0.0,
            "> 0",
        )?;
        let gap = backlash
            .half_gap(0.0, &CentreDisplacement::default())
            .map_err(|source| Error::Backlash {
                context: "pair.backlash",
                source,
            })?;
        check("backlash (half gap at rest)", gap.b, true, "finite")?;
        check(
            "stiffness (k at t = 0)",
            stiffness.stiffness(0.0),
            true,
            "finite",
        )?;
        Ok(Self {
            geometry,
            dofs: p.dofs,
            mass: [
                p.equivalent_mass,
                p.masses[0],
                p.masses[0],
                p.masses[1],
                p.masses[1],
            ],
            bearing_stiffness: p.bearing_stiffness,
            bearing_damping: p.bearing_damping,
            mesh_damping: p.mesh_damping,
            static_force: p.static_force,
            ste: (p.ste_amplitude, p.ste_phase),
            omega: p.mesh_frequency,
            pressure_angle: p.pressure_angle,
            centre_distance: p.centre_distance,
            stiffness,
            backlash,
        })
    }

    /// Degrees of freedom.
    pub fn dofs(&self) -> Dofs {
        self.dofs
    }

    /// The mesh frequency `ω_e`.
    pub fn mesh_frequency(&self) -> f64 {
        self.omega
    }

    /// The stiffness law.
    pub fn stiffness_law(&self) -> &S {
        &self.stiffness
    }

    /// The backlash law.
    pub fn backlash_law(&self) -> &B {
        &self.backlash
    }

    /// `diag(0, v)` over the pair's coordinates (bearings act on the centres only).
    fn bearing_matrix(&self, v: &[f64; 4]) -> DMatrix<f64> {
        let n = self.dofs.n();
        DMatrix::from_fn(n, n, |i, j| if i == j && i > 0 { v[i - 1] } else { 0.0 })
    }

    fn centres(&self, q: &[f64]) -> CentreDisplacement {
        match self.dofs {
            Dofs::Torsional => CentreDisplacement::default(),
            Dofs::TransverseTorsional => CentreDisplacement::new(q[1], q[2], q[3], q[4]),
        }
    }

    /// The mesh at `(t, q, q')`: `(δ, δ', F, b, α)`. A law error (non-finite state) gives NaN.
    pub fn mesh(&self, t: f64, q: &[f64], qd: &[f64]) -> MeshState {
        let (er, phi) = self.ste;
        let (e, e_rate) = mesh::static_error(er, self.omega, phi, t);
        let c = self.centres(q);
        let (alpha, delta, delta_rate) = match self.dofs {
            Dofs::Torsional => (self.geometry.alpha0, q[0] - e, qd[0] - e_rate),
            Dofs::TransverseTorsional => {
                let line = mesh::line_of_action(
                    &self.geometry,
                    self.centre_distance,
                    self.pressure_angle,
                    &c,
                    &qd[1..5],
                );
                let (delta, delta_rate) = mesh::transmission_error(
                    (q[0], qd[0]),
                    &q[1..5],
                    &qd[1..5],
                    &line,
                    (e, e_rate),
                );
                (line.alpha, delta, delta_rate)
            }
        };
        let gap = self.backlash.half_gap(t, &c).map_or(f64::NAN, |g| g.b);
        let k = self.stiffness.stiffness(t);
        let f = self.backlash.dead_zone().value(delta, gap);
        MeshState {
            delta,
            delta_rate,
            force: k * f + self.mesh_damping * delta_rate,
            half_gap: gap,
            alpha,
        }
    }

    /// Set the mesh frequency: the stiffness law and the STE move to `omega`, a time-varying
    /// backlash law keeps its ratio to the mesh frequency.
    pub fn set_mesh_frequency(&mut self, omega: f64) -> Result<(), Error>
    where
        S: Retime,
        B: Retime,
    {
        check("mesh_frequency", omega, omega > 0.0, "> 0")?;
        let r = omega / self.omega;
        self.stiffness = self.stiffness.retimed(omega, r)?;
        self.backlash = self.backlash.retimed(omega, r)?;
        self.omega = omega;
        Ok(())
    }

    /// The `hbm` engine problem on the full basis `0..H` of `ω_e` with `samples` AFT points.
    pub fn hbm_problem(
        self,
        harmonics: usize,
        samples: usize,
    ) -> Result<hbm::HbmProblem<Self>, Error>
    where
        S: Retime,
        B: Retime,
    {
        let basis = hbm::Basis::full(harmonics).map_err(hbm_error)?;
        let w = self.omega;
        hbm::HbmProblem::with_grid_size(self, basis, w, samples).map_err(hbm_error)
    }

    /// Static contact state (rest, drive flank loaded by `F_s`, mean stiffness at `t = 0`):
    /// `u = b + F_s/k(0) + e(0)` (centres at 0).
    pub fn static_state(&self) -> Vec<f64> {
        let mut q = vec![0.0; self.dofs.n()];
        let b = self
            .backlash
            .half_gap(0.0, &CentreDisplacement::default())
            .map_or(0.0, |g| g.b.max(0.0));
        let k = self.stiffness.stiffness(0.0);
        let sign = if self.static_force < 0.0 { -1.0 } else { 1.0 };
        q[0] = sign * b + self.static_force / k + self.ste.0 * self.ste.1.dcos();
        q
    }

    /// A steady time response on the `timestep` engine (Dormand–Prince 5(4), gap edges as
    /// events): `transient` mesh periods discarded, then `record` periods sampled at
    /// `samples_per_period` points each; from `initial` (`[q, q']`) or the static state.
    pub fn time_response(
        &self,
        settings: &TimeSettings,
        initial: Option<&[f64]>,
    ) -> Result<PairResponse, Error>
    where
        S: Clone + Retime,
        B: Clone + Retime,
    {
        let n = self.dofs.n();
        let e = ts_error;
        if settings.samples_per_period < 4 || settings.record_periods == 0 {
            return Err(Error::invalid(
                "pair.time.samples_per_period/record_periods",
                ">= 4 and >= 1",
                settings.samples_per_period.min(settings.record_periods) as f64,
            ));
        }
        let period = std::f64::consts::TAU / self.omega;
        let sys = timestep::FirstOrder(timestep::Mechanical::new(self.clone()).map_err(e)?);
        let y0 = match initial {
            Some(v) if v.len() == 2 * n => v.to_vec(),
            Some(v) => {
                return Err(Error::invalid(
                    "pair.initial length",
                    "= 2 n_dof",
                    v.len() as f64,
                ));
            }
            None => {
                let mut y = self.static_state();
                y.resize(2 * n, 0.0);
                y
            }
        };
        let opts = timestep::Options::default()
            .with_tol(settings.rtol, settings.atol)
            .with_events(true)
            .with_h_max(period / 8.0)
            .with_output(timestep::Output::Final);
        let ok = |s: &timestep::Solution| crate::error::completed(s, "pair");
        let t0 = settings.transient_periods as f64 * period;
        let tr = timestep::integrate(&sys, 0.0, &y0, t0, &opts).map_err(e)?;
        ok(&tr)?;
        let m = settings.record_periods * settings.samples_per_period;
        let h = period / settings.samples_per_period as f64;
        let times: Vec<f64> = (0..m).map(|k| t0 + k as f64 * h).collect();
        let rec = timestep::integrate(
            &sys,
            t0,
            &tr.y_final,
            t0 + m as f64 * h,
            &opts.with_output(timestep::Output::Times(times)),
        )
        .map_err(e)?;
        ok(&rec)?;
        let mut out = PairResponse {
            omega: self.omega,
            t: Vec::with_capacity(m),
            delta: Vec::with_capacity(m),
            force: Vec::with_capacity(m),
            final_state: rec.y_final.clone(),
            stats: crate::error::total_stats(&[&tr, &rec]),
        };
        for i in 0..rec.len() {
            let y = rec.state(i);
            let ms = self.mesh(rec.t[i], &y[..n], &y[n..]);
            out.t.push(rec.t[i]);
            out.delta.push(ms.delta);
            out.force.push(ms.force);
        }
        Ok(out)
    }
}

/// The mesh at one state (see [`GearPair::mesh`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshState {
    /// Dynamic transmission error `δ`.
    pub delta: f64,
    /// `δ'`.
    pub delta_rate: f64,
    /// Mesh force `F`.
    pub force: f64,
    /// Half gap `b(t, c)` (unclamped).
    pub half_gap: f64,
    /// Pressure angle `α`.
    pub alpha: f64,
}

/// Settings of [`GearPair::time_response`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TimeSettings {
    /// Mesh periods discarded.
    pub transient_periods: usize,
    /// Mesh periods recorded (≥ 1).
    pub record_periods: usize,
    /// Samples per recorded period (≥ 4).
    pub samples_per_period: usize,
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
}

impl Default for TimeSettings {
    fn default() -> Self {
        Self {
            transient_periods: 200,
            record_periods: 20,
            samples_per_period: 64,
            rtol: 1e-9,
            atol: 1e-12,
        }
    }
}

/// A recorded time response of the pair.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PairResponse {
    /// Mesh frequency.
    pub omega: f64,
    /// Sample times.
    pub t: Vec<f64>,
    /// DTE `δ`.
    pub delta: Vec<f64>,
    /// Mesh force `F`.
    pub force: Vec<f64>,
    /// `[q, q']` at the end.
    pub final_state: Vec<f64>,
    /// Work counters of the whole run (transient and record): accepted and rejected steps,
    /// right-hand-side evaluations, located gap-edge events (absent in data written before it
    /// existed: zeros).
    #[serde(default)]
    pub stats: timestep::Stats,
}

impl PairResponse {
    /// Dynamic factor `max F / F_s` ([`crate::response::dynamic_factor`]; NaN if undefined).
    pub fn dynamic_factor(&self, static_force: f64) -> f64 {
        crate::response::dynamic_factor(&self.force, static_force).unwrap_or(f64::NAN)
    }

    /// Fourier coefficients `[c_0, a_1, b_1, …]` of `δ` over the record
    /// ([`timestep::fourier_projection`]; NaN if undefined).
    pub fn fourier_coefficients(&self, h: usize) -> Vec<f64> {
        timestep::fourier_projection(&self.t, &self.delta, self.omega, h)
            .unwrap_or_else(|_| vec![f64::NAN; 2 * h + 1])
    }
}

/// A law whose time scale can be moved with the mesh frequency (for sweeps and continuation).
pub trait Retime: Sized {
    /// The law at mesh frequency `omega`, `ratio` = new/old mesh frequency.
    fn retimed(&self, omega: f64, ratio: f64) -> Result<Self, Error>;
}

impl Retime for f64 {
    fn retimed(&self, _omega: f64, _ratio: f64) -> Result<Self, Error> {
        Ok(*self)
    }
}

impl Retime for Stiffness {
    fn retimed(&self, omega: f64, _ratio: f64) -> Result<Self, Error> {
        self.at_mesh_frequency(omega)
            .map_err(|source| Error::Stiffness {
                context: "pair.stiffness",
                source,
            })
    }
}

impl Retime for mesh_stiffness::SingleHarmonicStiffness {
    fn retimed(&self, omega: f64, _ratio: f64) -> Result<Self, Error> {
        Ok(Self {
            omega_e: omega,
            ..*self
        })
    }
}

impl Retime for Backlash {
    fn retimed(&self, _omega: f64, ratio: f64) -> Result<Self, Error> {
        Ok(match *self {
            Backlash::Chen(l) => Backlash::Chen(backlash::ChenBacklash {
                omega: l.omega * ratio,
                ..l
            }),
            Backlash::RadiusModulated(l) => {
                Backlash::RadiusModulated(backlash::RadiusModulatedBacklash {
                    omega: l.omega * ratio,
                    ..l
                })
            }
            other => other,
        })
    }
}

impl<S: StiffnessLaw + Retime, B: BacklashLaw + Retime> system::SecondOrderSystem
    for GearPair<S, B>
{
    fn n_dof(&self) -> usize {
        self.dofs.n()
    }
    fn mass(&self) -> DMatrix<f64> {
        let n = self.dofs.n();
        DMatrix::from_fn(n, n, |i, j| if i == j { self.mass[i] } else { 0.0 })
    }
    fn damping(&self) -> DMatrix<f64> {
        self.bearing_matrix(&self.bearing_damping)
    }
    fn stiffness(&self) -> DMatrix<f64> {
        self.bearing_matrix(&self.bearing_stiffness)
    }
    fn nonlinear_force(&self, t: f64, q: &[f64], qd: &[f64], g: &mut [f64]) {
        let m = self.mesh(t, q, qd);
        g[0] = m.force;
        if self.dofs == Dofs::TransverseTorsional {
            let (sa, ca) = m.alpha.dsin_cos();
            g[1] = m.force * sa;
            g[2] = m.force * ca;
            g[3] = -m.force * sa;
            g[4] = -m.force * ca;
        }
    }
    fn forcing(&self, _t: f64, f: &mut [f64]) {
        f.fill(0.0);
        f[0] = self.static_force;
    }
    /// Torsional pair: analytic, `∂F/∂q = k(t) ∂f/∂δ` (1 outside the gap, 0 inside) and
    /// `∂F/∂q' = c`. The default central differences step by `6e-6 (1 + |q|)`, which in SI
    /// units (q ~ 10 µm, b ~ 50 µm) straddles the gap edge; the transverse-torsional pair keeps
    /// them (its geometry terms have no closed form here).
    fn force_jacobian(&self, t: f64, q: &[f64], qd: &[f64], dg_dq: &mut [f64], dg_dqd: &mut [f64]) {
        if self.dofs != Dofs::Torsional {
            system::finite_difference_force_jacobian(self, t, q, qd, dg_dq, dg_dqd);
            return;
        }
        let m = self.mesh(t, q, qd);
        let slope = self.backlash.dead_zone().eval(m.delta, m.half_gap).df_dx;
        dg_dq[0] = self.stiffness.stiffness(t) * slope;
        dg_dqd[0] = self.mesh_damping;
    }
    fn n_events(&self) -> usize {
        2
    }
    fn events(&self, t: f64, q: &[f64], qd: &[f64], e: &mut [f64]) {
        let m = self.mesh(t, q, qd);
        system::gap_edges(m.delta, m.half_gap, e);
    }
    fn set_base_frequency(&mut self, omega: f64) -> Result<(), system::SystemError> {
        self.set_mesh_frequency(omega)
            .map_err(|e| system::SystemError::invalid(e.to_string(), "> 0", omega))
    }
}

impl PairParams {
    /// A 1-DOF spur pair in SI units, not from a paper: Yu Table 1 geometry (R = 94 mm, 20°),
    /// inertias 1.15e-3 kg·m², tooth-pair stiffness (ε_α = 1.6, 2e8 N/m per pair, smoothed),
    /// 5 % mesh damping, 50 µm half backlash, 10 µm STE, 100 N·m on the pinion, mesh frequency
    /// 2000 rad/s.
    pub fn example_spur() -> Self {
        let geometry = gear_geometry::SpurPairParams {
            rp: 0.094,
            rg: 0.094,
            pressure_angle: 20f64.to_radians(),
        };
        let m_e = equivalent_mass(1.15e-3, 1.15e-3, 0.094, 0.094);
        let curve = mesh_stiffness::ToothPairStiffness::from_pair_stiffness(1.6, 2e8, 0.1)
            .unwrap_or_else(|_| unreachable_curve());
        let k0 = curve.mean();
        Self {
            geometry,
            dofs: Dofs::Torsional,
            equivalent_mass: m_e,
            masses: [0.5, 0.5],
            bearing_stiffness: [1e8; 4],
            bearing_damping: [2.0 * 0.02 * (1e8f64 * 0.5).sqrt(); 4],
            mesh_damping: 2.0 * 0.05 * (k0 * m_e).sqrt(),
            static_force: 100.0 / 0.094,
            ste_amplitude: 10e-6,
            ste_phase: 0.0,
            mesh_frequency: 2000.0,
            stiffness: Stiffness::ToothPair(mesh_stiffness::MeshTimed {
                curve,
                omega_e: 2000.0,
            }),
            backlash: Backlash::Constant { b: 50e-6 },
            pressure_angle: PressureAngleLaw::Involute,
            centre_distance: CentreDistanceForm::Consistent,
        }
    }
}

fn hbm_error(source: hbm::HbmError) -> Error {
    Error::Hbm {
        context: "pair hbm engine: ",
        source,
    }
}

fn ts_error(source: timestep::Error) -> Error {
    Error::Timestep {
        context: "pair timestep engine: ",
        source,
    }
}

fn unreachable_curve() -> mesh_stiffness::ToothPairStiffness {
    // the literal inputs of `example_spur` are valid; this is never reached
    mesh_stiffness::ToothPairStiffness {
        contact_ratio: 1.6,
        k_single: 2e8,
        k_double: 4e8,
        smoothing: 0.0,
    }
}

/// Helpers of the tests that hold the papers' models against their pair presets.
#[cfg(test)]
pub(crate) mod test_support {
    use system::SecondOrderSystem;

    /// `q'' = M⁻¹(f − C q' − K q − g)` of a diagonal-mass system.
    pub(crate) fn accel<T: SecondOrderSystem>(sys: &T, t: f64, q: &[f64], qd: &[f64]) -> Vec<f64> {
        let n = sys.n_dof();
        let (m, c, k) = (sys.mass(), sys.damping(), sys.stiffness());
        let (mut g, mut f) = (vec![0.0; n], vec![0.0; n]);
        sys.nonlinear_force(t, q, qd, &mut g);
        sys.forcing(t, &mut f);
        (0..n)
            .map(|i| {
                let lin: f64 = (0..n).map(|j| c[(i, j)] * qd[j] + k[(i, j)] * q[j]).sum();
                (f[i] - lin - g[i]) / m[(i, i)]
            })
            .collect()
    }

    pub(crate) fn close(a: f64, b: f64, scale: f64) -> bool {
        (a - b).abs() <= 1e-12 * (scale + a.abs().max(b.abs()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn linear_pair(dofs: Dofs, gap: f64) -> PairParams {
        PairParams {
            geometry: gear_geometry::SpurPairParams {
                rp: 20.0,
                rg: 30.0,
                pressure_angle: 20f64.to_radians(),
            },
            dofs,
            equivalent_mass: 1.0,
            masses: [2.0, 3.0],
            bearing_stiffness: [1.5, 1.2, 2.0, 1.8],
            bearing_damping: [0.05; 4],
            mesh_damping: 0.1,
            static_force: 0.5,
            ste_amplitude: 0.05,
            ste_phase: 0.3,
            mesh_frequency: 0.7,
            stiffness: Stiffness::Constant { k: 1.0 },
            backlash: Backlash::Constant { b: gap },
            pressure_angle: PressureAngleLaw::Constant,
            centre_distance: CentreDistanceForm::Consistent,
        }
    }

    /// Zero gap, constant stiffness: `m u'' + c u' + k u = F_s + k e + c e'`, steady state
    /// `u = F_s/k + Re[(k + icω) e_r e^{i(ωt+φ)} / (k − mω² + icω)]`; both engines against it.
    #[test]
    fn linear_pair_matches_the_exact_solution_on_both_engines() {
        let p = linear_pair(Dofs::Torsional, 0.0);
        let (k, c, m, w, er, phi): (f64, f64, f64, f64, f64, f64) = (1.0, 0.1, 1.0, 0.7, 0.05, 0.3);
        // U = (k + icω) e_r e^{iφ} / (k − mω² + icω)
        let (nr, ni) = (k * er, c * w * er);
        let (dr, di) = (k - m * w * w, c * w);
        let den = dr * dr + di * di;
        let (ur, ui) = ((nr * dr + ni * di) / den, (ni * dr - nr * di) / den);
        let (zr, zi) = (
            ur * phi.dcos() - ui * phi.dsin(),
            ur * phi.dsin() + ui * phi.dcos(),
        );
        // u = c0 + a1 cos ωt + b1 sin ωt, a1 = Re Z, b1 = −Im Z
        let exact = [p.static_force / k, zr, -zi];
        let pair = GearPair::from_params(&p).unwrap();
        let mut hb = pair.clone().hbm_problem(1, 16).unwrap();
        let sol = hb
            .solve(&[0.0, 0.0, 0.0], &hbm::SolverOptions::default())
            .unwrap();
        assert!(sol.converged);
        for i in 0..3 {
            assert!((sol.coefficients[i] - exact[i]).abs() < 1e-10, "hbm {i}");
        }
        let settings = TimeSettings {
            transient_periods: 60,
            ..TimeSettings::default()
        };
        let r = pair.time_response(&settings, None).unwrap();
        // the work of both runs is reported
        assert!(r.stats.n_accepted > 100 && r.stats.n_rhs >= 6 * r.stats.n_accepted);
        // u = δ + e: project u
        let u: Vec<f64> =
            r.t.iter()
                .zip(&r.delta)
                .map(|(t, d)| d + er * (w * t + phi).dcos())
                .collect();
        let cf = timestep::fourier_projection(&r.t, &u, w, 1).unwrap();
        // transient decays as e^{−ζ ω_n t}, ζ = 0.05: e^{−0.05·60·2π/0.7} ≈ 2e-12; rtol 1e-9
        for i in 0..3 {
            assert!(
                (cf[i] - exact[i]).abs() < 1e-7,
                "timestep {i}: {} vs {}",
                cf[i],
                exact[i]
            );
        }
    }

    /// A 6-DOF pair without contact loss: harmonic balance and time stepping agree.
    #[test]
    fn hbm_and_time_stepping_agree_without_contact_loss() {
        let mut p = linear_pair(Dofs::TransverseTorsional, 1.0);
        p.stiffness = Stiffness::SingleHarmonic(
            mesh_stiffness::SingleHarmonicStiffness::new(
                1.0,
                0.2,
                0.7,
                0.0,
                mesh_stiffness::Waveform::Sine,
            )
            .unwrap(),
        );
        p.pressure_angle = PressureAngleLaw::Involute;
        let pair = GearPair::from_params(&p).unwrap();
        let r = pair
            .time_response(
                &TimeSettings {
                    // the lightly damped bearing modes (ζ ≈ 0.014) need ~400 periods to decay
                    // below the 1e-6 comparison (150 periods left 1.3e-5)
                    transient_periods: 400,
                    ..TimeSettings::default()
                },
                None,
            )
            .unwrap();
        // no contact loss: δ stays above the gap
        assert!(r.delta.iter().all(|d| *d > 1.0), "contact lost");
        let h = 8;
        let n = 5;
        // coefficient c of dof i at c·n + i: the static contact state as the constant term
        let mut start = vec![0.0; n * (2 * h + 1)];
        start[0] = pair.static_state()[0];
        let mut hb = pair.clone().hbm_problem(h, 64).unwrap();
        let sol = hb.solve(&start, &hbm::SolverOptions::default()).unwrap();
        assert!(sol.converged);
        let t_end = *r.t.last().unwrap();
        let y = &r.final_state;
        // the recorded δ against δ from the HBM coordinates at the same times
        for (i, &t) in r.t.iter().enumerate().step_by(37) {
            let (q, qd) = sol.state_at(t);
            let hd = pair.mesh(t, &q, &qd).delta;
            assert!(
                (hd - r.delta[i]).abs() < 1e-6,
                "t = {t}: {hd} vs {}",
                r.delta[i]
            );
        }
        assert!(y.iter().all(|v| v.is_finite()) && t_end > 0.0);
    }

    #[test]
    fn params_round_trip_and_are_checked() {
        let p = PairParams::example_spur();
        let j = serde_json::to_string(&p).unwrap();
        let back: PairParams = serde_json::from_str(&j).unwrap();
        assert_eq!(back, p);
        GearPair::from_params(&p).unwrap();
        let mut bad = p.clone();
        bad.equivalent_mass = -1.0;
        let e = GearPair::from_params(&bad).unwrap_err().to_string();
        assert!(e.contains("equivalent_mass"), "{e}");
        let mut bad = p.clone();
        bad.dofs = Dofs::TransverseTorsional;
        bad.masses = [0.0, 1.0];
        assert!(GearPair::from_params(&bad).is_err());
        let mut bad = p.clone();
        bad.mesh_frequency = f64::NAN;
        assert!(GearPair::from_params(&bad).is_err());
        // laws from serde are checked with their constructors
        let mut bad = p.clone();
        bad.backlash = Backlash::RadiusModulated(backlash::RadiusModulatedBacklash {
            b: 1.0,
            beta: 1.0,
            omega: 1.0,
        });
        let e = GearPair::from_params(&bad).unwrap_err().to_string();
        assert!(e.contains("beta"), "{e}");
        let mut bad = p;
        bad.stiffness = Stiffness::SingleHarmonic(mesh_stiffness::SingleHarmonicStiffness {
            k0: 1.0,
            k_r: -1.0,
            omega_e: 1.0,
            phi_m: 0.0,
            waveform: mesh_stiffness::Waveform::Sine,
        });
        assert!(GearPair::from_params(&bad).is_err());
    }
}
