//! The dimensionless NFG model of Eq. (9)–(12) and (22), built from [`Parameters`] in one place.

use math::DetMath;
use mesh_stiffness::StiffnessLaw;
use serde::{Deserialize, Serialize};

use super::params::{BaseRadius, ErrorTerm, Parameters, Readings, RigidAcceleration, RigidSeries};
use crate::Error;
use backlash::{BacklashLaw, dead_zone};

/// The dimensionless single-degree-of-freedom NFG model (Eq. 9):
///
/// `q'' + 2ζ q' + F(τ) f(q; b̄(τ)) = f_r(τ)`, `τ = ω_n t`,
///
/// with `F(τ) = (k_m/k₀)(r_b2/L)² / (1 + β²/2)` and
/// `f_r = −B₀ − d²θ₂/dτ² + d²ē/dτ²` (Eq. 22). Every field is dimensionless unless stated.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Model {
    /// Natural frequency `ω_n` \[rad/s\], Eq. (10).
    pub omega_n: f64,
    /// `ω̄_c = ω_c/ω_n`, instantaneous-centre frequency.
    pub omega_c: f64,
    /// `ω̄_e = ω_e/ω_n = Z₂ ω̄_c`, mesh frequency.
    pub omega_e: f64,
    /// Number of NFG teeth `Z₂ = ω̄_e/ω̄_c`.
    pub z2: u32,
    /// Damping ratio `ζ`.
    pub zeta: f64,
    /// Eccentric ratio `ε` (Eq. 18).
    pub eccentricity: f64,
    /// Base-radius change rate `β` (Eq. 8).
    pub beta: f64,
    /// Mean base radius `L` \[m\] (Eq. 8), kept to scale back to metres.
    pub mean_base_radius: f64,
    /// Stiffness amplitude coefficient `a_k = k_r/k₀` (Sect. 3.6).
    pub ak: f64,
    /// Stiffness phase `φ_m` \[rad\].
    pub phase_stiffness: f64,
    /// Error phase `φ_e` \[rad\].
    pub phase_error: f64,
    /// Mean dimensionless half backlash `b/L`.
    pub backlash: f64,
    /// Dimensionless error amplitude `e_r/L`.
    pub error: f64,
    /// `B₀ = T₂/(I₂ ω_n²)`, Eq. (22).
    pub b0: f64,
    /// `B₁`, first Fourier amplitude of d²θ₂/dτ² (Eq. 22; depends on the Eq. 20 reading).
    pub b1: f64,
    /// `B₂`, second Fourier amplitude of d²θ₂/dτ² (Eq. 22).
    pub b2: f64,
    /// `B₃ = (e_r/L) ω̄_e²`, amplitude of the error forcing (Eq. 22).
    pub b3: f64,
    /// The readings in force.
    pub readings: Readings,
}

impl Parameters {
    /// Build the dimensionless model (the only place where SI becomes dimensionless).
    pub fn model(&self) -> Result<Model, Error> {
        Model::new(self)
    }
}

impl Model {
    /// Nondimensionalise validated parameters (Eq. 8, 10, 11, 12, 20–22).
    pub fn new(p: &Parameters) -> Result<Self, Error> {
        p.validate()?;
        let omega_n = p.omega_n()?;
        let wc = p.omega_c() / omega_n;
        let z2 = p.z2();
        let we = f64::from(z2) * wc;
        let e = p.eccentricity;
        let l = p.mean_base_radius()?;
        let pair = p.pair()?;
        let form = p.readings.rigid_acceleration;
        // The leaf enum is non-exhaustive: the matches below treat every form other than
        // `PrintedEq20` as `Derived`, so any other form is rejected here.
        if !matches!(
            form,
            RigidAcceleration::Derived | RigidAcceleration::PrintedEq20
        ) {
            return Err(Error::UnsupportedReading {
                field: "liu2021.readings.rigid_acceleration",
                reading: format!("{form:?}"),
            });
        }
        // derived: -2 wc^2 sum n(-e)^n sin(nx); printed: (-e)^(n-1)(1-e^2) 2 wc e
        let b1 = pair.rigid_acceleration_coefficient(form, 1, wc);
        let b2 = pair.rigid_acceleration_coefficient(form, 2, wc);
        let model = Self {
            omega_n,
            omega_c: wc,
            omega_e: we,
            z2,
            zeta: p.damping_ratio,
            eccentricity: e,
            beta: p.base_radius_rate()?,
            mean_base_radius: l,
            ak: p.kr / p.k0,
            phase_stiffness: p.phase_stiffness,
            phase_error: p.phase_error,
            backlash: p.half_backlash / l,
            error: p.er / l,
            b0: p.load_torque / (p.inertia * omega_n * omega_n),
            b1,
            b2,
            b3: p.er / l * we * we,
            readings: p.readings,
        };
        if !(model.omega_n.is_finite() && model.b0.is_finite() && model.b3.is_finite()) {
            return Err(Error::invalid("liu2021.omega_n", "finite", model.omega_n));
        }
        Ok(model)
    }

    /// The same model at another speed: `ω̄_c → omega_c` with `ω̄_e = Z₂ ω̄_c` and the Eq. (22)
    /// amplitudes at that speed (`B₁`, `B₂ ∝ ω̄_c²` derived or `∝ ω̄_c` printed Eq. 20;
    /// `B₃ = (e_r/L) ω̄_e²`), computed from the model's eccentric ratio and error amplitude by
    /// the formulas of [`Model::new`]: bit for bit the model built at that speed, whatever
    /// speeds the model had before. (Scaling the present amplitudes by the ratio of the speeds
    /// would carry the rounding of every earlier change into the next, so a continuation's
    /// model would depend on how many corrector and location steps had set the speed.)
    /// `ω₁` scales with `ω̄_c` (`ω̄_c = ω₁/(i_j ω_n)`); used by frequency continuation.
    pub fn with_omega_c(&self, omega_c: f64) -> Result<Model, Error> {
        if !(omega_c > 0.0 && omega_c.is_finite()) {
            return Err(Error::invalid("liu2021.omega_c", "> 0", omega_c));
        }
        let form = self.readings.rigid_acceleration;
        let coefficient =
            |n| gear_geometry::rigid_acceleration_coefficient(self.eccentricity, form, n, omega_c);
        let omega_e = f64::from(self.z2) * omega_c;
        Ok(Model {
            omega_c,
            omega_e,
            b1: coefficient(1),
            b2: coefficient(2),
            b3: self.error * omega_e * omega_e,
            ..*self
        })
    }

    /// Period of the steady response, `T = 2π/ω̄_c` (Sect. 2.4).
    pub fn period(&self) -> f64 {
        2.0 * std::f64::consts::PI / self.omega_c
    }

    /// The mesh stiffness `k_m/k₀ = 1 + a_k sin(ω̄_e τ + φ_m)` of Eq. (19) as the
    /// `mesh-stiffness` leaf's law (dimensionless: `k₀ = 1`, `k_r = a_k`).
    #[inline]
    pub fn mesh_stiffness_law(&self) -> mesh_stiffness::SingleHarmonicStiffness {
        mesh_stiffness::SingleHarmonicStiffness {
            k0: 1.0,
            k_r: self.ak,
            omega_e: self.omega_e,
            phi_m: self.phase_stiffness,
            waveform: mesh_stiffness::Waveform::Sine,
        }
    }

    /// Base radius ratio `r_b2(τ)/L = 1 + β cos(ω̄_c τ)` (Eq. 8).
    #[inline]
    pub fn radius_ratio(&self, tau: f64) -> f64 {
        1.0 + self.beta * (self.omega_c * tau).dcos()
    }

    /// Combined parametric function `F(τ) = (k_m/k₀)(r_b2/L)²/(1 + β²/2)` (Eq. 9–10 with 8, 19).
    /// Its mean is 1 when `k_m` and `r_b2` share no frequency.
    #[inline]
    pub fn stiffness(&self, tau: f64) -> f64 {
        let km = self.mesh_stiffness_law().stiffness(tau);
        self.parametric(km, (self.omega_c * tau).dcos())
    }

    /// `F = (k_m/k₀)(r_b2/L)²/(1 + β²/2)` from `k_m/k₀` and `cos(ω̄_c τ)` (`r_b2/L = 1 + β cos`,
    /// Eq. 8): the one place of this formula, for [`stiffness`](Self::stiffness) and the time
    /// functions of the time stepping and the harmonic-balance grid.
    #[inline]
    fn parametric(&self, km: f64, cos_c: f64) -> f64 {
        let r = 1.0 + self.beta * cos_c;
        km * r * r / (1.0 + 0.5 * self.beta * self.beta)
    }

    /// The half backlash of Eq. (11)–(12) as the `backlash` leaf's law:
    /// `b̄(τ) = (b/L)/(1 + β cos(ω̄_c τ))` ([`BaseRadius::TimeVarying`]) or `b/L`
    /// ([`BaseRadius::Mean`], `β = 0` in the law).
    #[inline]
    pub fn backlash_law(&self) -> backlash::RadiusModulatedBacklash {
        backlash::RadiusModulatedBacklash {
            b: self.backlash,
            beta: match self.readings.base_radius {
                BaseRadius::TimeVarying => self.beta,
                BaseRadius::Mean => 0.0,
            },
            omega: self.omega_c,
        }
    }

    /// Dimensionless half backlash `b̄(τ)` (Eq. 12), per the [`BaseRadius`] reading, from
    /// [`Model::backlash_law`] (NaN for a non-finite `τ`).
    #[inline]
    pub fn backlash_at(&self, tau: f64) -> f64 {
        self.backlash_law()
            .half_gap(tau, &backlash::CentreDisplacement::default())
            .map_or(f64::NAN, |g| g.b)
    }

    /// Rigid angular acceleration `d²θ₂/dτ²` (Eq. 20) per the readings.
    pub fn rigid_acceleration(&self, tau: f64) -> f64 {
        let x = self.omega_c * tau;
        match self.readings.rigid_series {
            RigidSeries::TwoTerms => self.rigid_acceleration_trig(x.dsin(), 0.0, (2.0 * x).dsin()),
            RigidSeries::Exact => self.rigid_acceleration_trig(x.dsin(), x.dcos(), 0.0),
        }
    }

    /// [`rigid_acceleration`](Self::rigid_acceleration) from `sin x`, `cos x` and `sin 2x`,
    /// `x = ω̄_c τ` (`cos x` is used by the exact series only, `sin 2x` by the two terms only).
    #[inline]
    fn rigid_acceleration_trig(&self, sx: f64, cx: f64, s2x: f64) -> f64 {
        match self.readings.rigid_series {
            RigidSeries::TwoTerms => self.b1 * sx + self.b2 * s2x,
            RigidSeries::Exact => {
                let e = self.eccentricity;
                let d = 1.0 + 2.0 * e * cx + e * e;
                let num = 2.0 * e * (1.0 - e * e) * sx;
                match self.readings.rigid_acceleration {
                    RigidAcceleration::PrintedEq20 => self.omega_c * num / d,
                    // Derived (others are rejected by `Model::new`)
                    _ => self.omega_c * self.omega_c * num / (d * d),
                }
            }
        }
    }

    /// Transmission-error term `d²ē/dτ²` as it enters the right side of Eq. (9).
    pub fn error_acceleration(&self, tau: f64) -> f64 {
        let ph = self.omega_e * tau + self.phase_error;
        let x = self.omega_c * tau;
        match (self.readings.error_term, self.readings.base_radius) {
            (_, BaseRadius::Mean) => self.error_acceleration_trig(ph.dsin(), 0.0, 0.0, 0.0),
            (ErrorTerm::Printed, BaseRadius::TimeVarying) => {
                self.error_acceleration_trig(ph.dsin(), 0.0, 0.0, x.dcos())
            }
            (ErrorTerm::Derived, BaseRadius::TimeVarying) => {
                self.error_acceleration_trig(ph.dsin(), ph.dcos(), x.dsin(), x.dcos())
            }
        }
    }

    /// [`error_acceleration`](Self::error_acceleration) from `sin φ`, `cos φ`
    /// (`φ = ω̄_e τ + φ_e`), `sin x` and `cos x` (`x = ω̄_c τ`); each reading reads only the
    /// values it needs.
    #[inline]
    fn error_acceleration_trig(&self, sph: f64, cph: f64, sx: f64, cx: f64) -> f64 {
        match (self.readings.error_term, self.readings.base_radius) {
            (ErrorTerm::Printed, BaseRadius::Mean) => self.b3 * sph,
            (ErrorTerm::Printed, BaseRadius::TimeVarying) => self.b3 * sph / (1.0 + self.beta * cx),
            (ErrorTerm::Derived, BaseRadius::Mean) => -self.b3 * sph,
            (ErrorTerm::Derived, BaseRadius::TimeVarying) => {
                // e/L = a sin(ph), r = 1 + beta cos(wc tau): (e/r)'' exactly
                let a = self.error;
                let (we, wc, be) = (self.omega_e, self.omega_c, self.beta);
                let e = a * sph;
                let de = a * we * cph;
                let dde = -a * we * we * sph;
                let r = 1.0 + be * cx;
                let dr = -be * wc * sx;
                let ddr = -be * wc * wc * cx;
                // (e/r)'' = e''/r − 2e'r'/r² + e(2r'²/r³ − r''/r²), nested on 1/r: one
                // division instead of four on the right-hand side's critical path
                let ir = 1.0 / r;
                ir * (dde + ir * (e * (2.0 * dr * dr * ir - ddr) - 2.0 * de * dr))
            }
        }
    }

    /// `[F(τ), b̄(τ), f_r(τ)]`: [`stiffness`](Self::stiffness),
    /// [`backlash_at`](Self::backlash_at) and [`forcing`](Self::forcing) at one `τ`, bit for
    /// bit, with every `sin`/`cos` taken once (`sin x`, `cos x` of `x = ω̄_c τ` serve all
    /// three; `sin 2x` and `cos φ_e` only where the readings read them): four or five
    /// transcendental calls instead of eight to ten. The time-only part of the right-hand side
    /// of the time stepping ([`super::TimeSystem`] with [`super::Trig::Libm`]).
    pub fn time_functions(&self, tau: f64) -> [f64; 3] {
        let x = self.omega_c * tau;
        let (sx, cx) = x.dsin_cos();
        let s2x = match self.readings.rigid_series {
            RigidSeries::TwoTerms => (2.0 * x).dsin(),
            RigidSeries::Exact => 0.0,
        };
        let ph = self.omega_e * tau + self.phase_error;
        let (sph, cph) = match (self.readings.error_term, self.readings.base_radius) {
            (ErrorTerm::Derived, BaseRadius::TimeVarying) => ph.dsin_cos(),
            _ => (ph.dsin(), 0.0),
        };
        self.time_functions_of(&TimeTrig {
            sx,
            cx,
            s2x,
            sin_stiffness: (self.omega_e * tau + self.phase_stiffness).dsin(),
            sph,
            cph,
        })
    }

    /// [`time_functions`](Self::time_functions) from two short `sin_cos` (of `ω̄_c τ` and
    /// `ω̄_e τ`) and the addition theorems (`sin 2x = 2 sin x cos x`, the phases `φ_m`, `φ_e`
    /// from `phases = [sin φ_m, cos φ_m, sin φ_e, cos φ_e]`): the same formulas, different
    /// from the direct evaluation at rounding level ([`super::Trig::Kernel`]).
    pub(super) fn time_functions_kernel(&self, tau: f64, phases: &[f64; 4]) -> [f64; 3] {
        let (sx, cx) = crate::trig::sin_cos(self.omega_c * tau);
        let (sz, cz) = crate::trig::sin_cos(self.omega_e * tau);
        let [spm, cpm, spe, cpe] = *phases;
        self.time_functions_of(&TimeTrig {
            sx,
            cx,
            s2x: 2.0 * sx * cx,
            sin_stiffness: sz * cpm + cz * spm,
            sph: sz * cpe + cz * spe,
            cph: cz * cpe - sz * spe,
        })
    }

    /// [`time_functions`](Self::time_functions) from three short `sin_cos` (of `ω̄_c τ`,
    /// `ω̄_e τ + φ_m` and `ω̄_e τ + φ_e`, the same arguments as the direct evaluation) and
    /// `sin 2x = 2 sin x cos x`: the time functions of the model as a
    /// [`system::SecondOrderSystem`] (shooting flows, the generic adapters), equal to
    /// [`time_functions`](Self::time_functions) to rounding and about three times cheaper
    /// than the C-library-free `sin`/`cos` of `geardyn-math` that it reads.
    pub(super) fn time_functions_short(&self, tau: f64) -> [f64; 3] {
        let (sx, cx) = crate::trig::sin_cos(self.omega_c * tau);
        let we = self.omega_e * tau;
        let (sin_stiffness, _) = crate::trig::sin_cos(we + self.phase_stiffness);
        let (sph, cph) = crate::trig::sin_cos(we + self.phase_error);
        self.time_functions_of(&TimeTrig {
            sx,
            cx,
            s2x: 2.0 * sx * cx,
            sin_stiffness,
            sph,
            cph,
        })
    }

    /// [`time_functions`](Self::time_functions) with the phases carried in double-double:
    /// `ω̄_c τ` and `ω̄_e τ + φ` as error-free products and sums `hi + lo`, their sines as
    /// `sin hi + lo cos hi` (and the cosines alike). The direct evaluation rounds each phase
    /// argument to its last place (an error `ε ω̄_e τ` that grows along the period); this one
    /// keeps the phase to about `ε²ω̄_e τ` and so the values to a few units in the last place
    /// over a whole period: the samples of [`super::TimeTable`].
    /// At `τ = tau + tau_lo` (a double-double time).
    pub(super) fn time_functions_accurate_at(&self, tau: f64, tau_lo: f64) -> [f64; 3] {
        let sin_cos = |(hi, lo): (f64, f64)| {
            let (s, c) = hi.dsin_cos();
            (s + c * lo, c - s * lo)
        };
        let times = |w: f64| {
            let (p, e) = super::table::two_product(w, tau);
            (p, e + w * tau_lo)
        };
        let x = times(self.omega_c);
        let (sx, cx) = sin_cos(x);
        let (s2x, _) = sin_cos((2.0 * x.0, 2.0 * x.1));
        let we = times(self.omega_e);
        let phase = |phi: f64| {
            let (h, l) = super::table::two_sum(we.0, phi);
            (h, l + we.1)
        };
        let (sin_stiffness, _) = sin_cos(phase(self.phase_stiffness));
        let (sph, cph) = sin_cos(phase(self.phase_error));
        self.time_functions_of(&TimeTrig {
            sx,
            cx,
            s2x,
            sin_stiffness,
            sph,
            cph,
        })
    }

    /// `[F, b̄, f_r]` from the sines and cosines at one `τ` (the one place of these formulas
    /// for the time stepping and the harmonic-balance grid). A non-finite `τ` gives NaN
    /// through `cos x`, as [`backlash_at`](Self::backlash_at).
    #[inline]
    fn time_functions_of(&self, t: &TimeTrig) -> [f64; 3] {
        // F(τ): the leaf's law (k₀ = 1, k_r = a_k, sine: the cosine of its phase is not
        // read) times the radius term
        let km = self
            .mesh_stiffness_law()
            .eval_at_phase(t.sin_stiffness, f64::NAN);
        let stiffness = self.parametric(km, t.cx);
        // b̄(τ): the backlash leaf's law (β = 0 for the mean reading)
        let backlash = self.backlash_law().half_gap_at_phase(t.cx);
        let forcing = -self.b0 - self.rigid_acceleration_trig(t.sx, t.cx, t.s2x)
            + self.error_acceleration_trig(t.sph, t.cph, t.sx, t.cx);
        [stiffness, backlash, forcing]
    }

    /// `[F(τ_m), b̄(τ_m)]` and `f_r(τ_m)` on the grid `τ_m = m T / N`, `T = 2π/ω̄_c`
    /// (`N` a multiple of 4): the same functions as [`stiffness`](Self::stiffness),
    /// [`backlash_at`](Self::backlash_at) and [`forcing`](Self::forcing), equal to round-off,
    /// but with every `sin`/`cos` taken from one quarter of the unit circle
    /// (`ω̄_e τ_m = 2π Z₂ m/N`, phases by the addition theorem): `N/4` `sin_cos` calls instead
    /// of about six transcendental calls per sample.
    pub(super) fn tabulate_period(&self, n_grid: usize, forcing: &mut [f64], table: &mut [f64]) {
        let quarter = n_grid / 4;
        let mut circle = vec![(0.0, 0.0); n_grid];
        for r in 0..quarter {
            let (s, c) = (2.0 * std::f64::consts::PI * r as f64 / n_grid as f64).dsin_cos();
            circle[r] = (s, c);
            circle[r + quarter] = (c, -s);
            circle[r + 2 * quarter] = (-s, -c);
            circle[r + 3 * quarter] = (-c, s);
        }
        let (spm, cpm) = self.phase_stiffness.dsin_cos();
        let (spe, cpe) = self.phase_error.dsin_cos();
        let z2 = self.z2 as usize;
        for (m, (f, row)) in forcing
            .iter_mut()
            .zip(table.chunks_exact_mut(2))
            .enumerate()
        {
            let (sx, cx) = circle[m];
            let (sz, cz) = circle[(z2 * m) % n_grid];
            let [stiffness, backlash, forcing] = self.time_functions_of(&TimeTrig {
                sx,
                cx,
                s2x: circle[(2 * m) % n_grid].0,
                sin_stiffness: sz * cpm + cz * spm,
                sph: sz * cpe + cz * spe,
                cph: cz * cpe - sz * spe,
            });
            row[0] = stiffness;
            row[1] = backlash;
            *f = forcing;
        }
    }

    /// Right-hand side of Eq. (9): `f_r(τ) = −B₀ − d²θ₂/dτ² + d²ē/dτ²` (Eq. 22).
    pub fn forcing(&self, tau: f64) -> f64 {
        -self.b0 - self.rigid_acceleration(tau) + self.error_acceleration(tau)
    }

    /// Restoring term `F(τ) f(q; b̄(τ))` of Eq. (9).
    #[inline]
    pub fn restoring(&self, tau: f64, q: f64) -> f64 {
        Self::restoring_of(self.stiffness(tau), self.backlash_at(tau), q)
    }

    /// `g = F f(q; b̄)` from the time functions `F`, `b̄` at one `τ`: the one place of the
    /// restoring force, for [`restoring`](Self::restoring), the tabulated evaluation of the
    /// harmonic balance and the time stepping ([`super::TimeSystem`]).
    #[inline]
    pub fn restoring_of(stiffness: f64, backlash: f64, q: f64) -> f64 {
        stiffness * dead_zone(q, backlash)
    }

    /// `∂g/∂q = F f'(q; b̄)`, the slope of [`restoring_of`](Self::restoring_of) (the force
    /// Jacobian of the harmonic balance, pointwise and tabulated).
    #[inline]
    pub fn restoring_slope_of(stiffness: f64, backlash: f64, q: f64) -> f64 {
        stiffness * backlash::dead_zone_dx(q, backlash)
    }

    /// Acceleration `q'' = f_r − 2ζ q' − F f(q)`: the plain right-hand side of Eq. (9).
    #[inline]
    pub fn acceleration(&self, tau: f64, q: f64, v: f64) -> f64 {
        self.acceleration_of(self.time_functions(tau), q, v)
    }

    /// The right-hand side of Eq. (9), `q'' = f_r − 2ζ q' − F f(q; b̄)`, from the time
    /// functions `[F, b̄, f_r]` at one `τ` ([`time_functions`](Self::time_functions), or the
    /// kernel evaluation of [`super::Trig::Kernel`]): the one right-hand side of the time
    /// stepping, in the order of the generic adapter `timestep::Mechanical`
    /// (`a = f − C v − g`, a zero damping skipped as it skips a zero matrix).
    #[inline]
    pub fn acceleration_of(&self, time_functions: [f64; 3], q: f64, v: f64) -> f64 {
        let [stiffness, backlash, forcing] = time_functions;
        let mut a = forcing;
        let damping = 2.0 * self.zeta;
        if damping != 0.0 {
            a -= damping * v;
        }
        a - Self::restoring_of(stiffness, backlash, q)
    }

    /// Quasi-static contact position `q = −b̄ − B₀/F` at `τ` (start value for the solvers).
    pub fn static_position(&self, tau: f64) -> f64 {
        -self.backlash_at(tau) - self.b0 / self.stiffness(tau)
    }
}

/// The sines and cosines the time functions of Eq. (9) read at one `τ`: `x = ω̄_c τ`
/// (`sin x`, `cos x`, `sin 2x`), `sin(ω̄_e τ + φ_m)` and `φ_e = ω̄_e τ + φ_e` (`sin`, `cos`);
/// a value a reading does not read may be anything.
#[derive(Debug, Clone, Copy)]
struct TimeTrig {
    sx: f64,
    cx: f64,
    s2x: f64,
    sin_stiffness: f64,
    sph: f64,
    cph: f64,
}

/// Rattle state value `rsv` (Sect. 3.2): the workspace's one [`crate::response::RattleState`]. This
/// model's classifier ([`Model::rattle`]) knows the drive flank (`q < −b̄`): `NoRattle` when
/// `q < −b̄` throughout, `Unilateral` when the flanks separate (`q ≥ −b̄` somewhere) but never
/// reach the back flank, `Bilateral` when back-flank contact `q > b̄` occurs; never
/// `NoContact`.
pub use crate::response::RattleState;

/// The state of one sample `q` in a gap of half width `b` (Liu's flank convention): back flank
/// (`q > b`, bilateral), in the gap (`−b ≤ q ≤ b`, unilateral), drive flank (no rattle). The
/// state of a period is the largest over its samples, so with a constant `b` it is the state of
/// `max q`.
#[inline]
fn rattle_of_sample(q: f64, b: f64) -> RattleState {
    if q > b {
        RattleState::Bilateral
    } else if q >= -b {
        RattleState::Unilateral
    } else {
        RattleState::NoRattle
    }
}

/// Rattle state and peak-to-peak value of one steady period.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Rattle {
    /// Rattle state (rsv).
    pub state: RattleState,
    /// Peak-to-peak value `ppv = max q − min q` (dimensionless, as in Fig. 11b).
    pub ppv: f64,
    /// Minimum of `q`.
    pub q_min: f64,
    /// Maximum of `q`.
    pub q_max: f64,
}

impl Model {
    /// [`rattle`](Self::rattle) of samples `q[m]` at `τ_m = m T / M` (`M = q.len()`) of one
    /// period `T`. With a constant backlash ([`BaseRadius::Mean`]) the state follows from the
    /// extrema alone (`q_max > b̄`: bilateral, `q_max ≥ −b̄`: unilateral), the same result
    /// without a comparison per sample.
    pub fn rattle_of_period(&self, period: f64, q: &[f64]) -> Rattle {
        let n = q.len();
        match self.readings.base_radius {
            BaseRadius::Mean => {
                let (q_min, q_max) = q
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                        (a.min(x), b.max(x))
                    });
                Rattle {
                    state: rattle_of_sample(q_max, self.backlash),
                    ppv: q_max - q_min,
                    q_min,
                    q_max,
                }
            }
            BaseRadius::TimeVarying => self.rattle(
                q.iter()
                    .enumerate()
                    .map(|(m, &q)| (period * m as f64 / n as f64, q)),
            ),
        }
    }

    /// Classify samples `(τ, q)` of one steady period (Sect. 3.2).
    pub fn rattle<I: IntoIterator<Item = (f64, f64)>>(&self, samples: I) -> Rattle {
        let mut q_min = f64::INFINITY;
        let mut q_max = f64::NEG_INFINITY;
        let mut state = RattleState::NoRattle;
        for (tau, q) in samples {
            q_min = q_min.min(q);
            q_max = q_max.max(q);
            state = state.max(rattle_of_sample(q, self.backlash_at(tau)));
        }
        Rattle {
            state,
            ppv: q_max - q_min,
            q_min,
            q_max,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::params::table1;
    use super::*;

    fn fourier_sin(f: impl Fn(f64) -> f64, k: usize, n: usize) -> f64 {
        let two_pi = 2.0 * std::f64::consts::PI;
        (0..n)
            .map(|i| {
                let x = two_pi * i as f64 / n as f64;
                f(x) * (k as f64 * x).dsin()
            })
            .sum::<f64>()
            * 2.0
            / n as f64
    }

    #[test]
    fn two_term_amplitudes_are_fourier_coefficients_of_exact_form() {
        for ra in [RigidAcceleration::Derived, RigidAcceleration::PrintedEq20] {
            let mut p = table1();
            p.readings.rigid_acceleration = ra;
            p.readings.rigid_series = RigidSeries::Exact;
            let m = p.model().unwrap();
            let f = |x: f64| m.rigid_acceleration(x / m.omega_c);
            let s1 = fourier_sin(f, 1, 2048);
            let s2 = fourier_sin(f, 2, 2048);
            assert!((s1 / m.b1 - 1.0).abs() < 1e-10, "{ra:?}: {s1} vs {}", m.b1);
            assert!((s2 / m.b2 - 1.0).abs() < 1e-10, "{ra:?}: {s2} vs {}", m.b2);
        }
    }

    #[test]
    fn derived_rigid_acceleration_is_derivative_of_eq18_speed() {
        // d(omega2/omega_n)/dtau by central differences against the closed form.
        let mut p = table1();
        p.readings.rigid_series = RigidSeries::Exact;
        let m = p.model().unwrap();
        let pair = p.pair().unwrap();
        let w = |tau: f64| p.omega1 / pair.ratio(m.omega_c * tau) / m.omega_n;
        for tau in [10.0, 333.0, 900.0, 1500.0] {
            let h = 1e-2;
            let fd = (w(tau + h) - w(tau - h)) / (2.0 * h);
            let exact = m.rigid_acceleration(tau);
            assert!(
                (fd - exact).abs() < 1e-6 * exact.abs().max(1e-12),
                "{fd} {exact}"
            );
        }
    }

    #[test]
    fn derived_error_term_is_second_derivative() {
        let p = table1();
        let m = p.model().unwrap();
        let ebar =
            |tau: f64| m.error * (m.omega_e * tau + m.phase_error).dsin() / m.radius_ratio(tau);
        for tau in [1.0, 77.0, 401.0] {
            let h = 1e-3;
            let fd = (ebar(tau + h) - 2.0 * ebar(tau) + ebar(tau - h)) / (h * h);
            let exact = m.error_acceleration(tau);
            assert!((fd - exact).abs() < 1e-5 * m.b3, "{fd} {exact}");
        }
    }

    #[test]
    fn stiffness_is_the_leaf_law_times_the_radius_term() {
        let m = table1().model().unwrap();
        let leaf = mesh_stiffness::SingleHarmonicStiffness::new(
            1.0,
            m.ak,
            m.omega_e,
            m.phase_stiffness,
            mesh_stiffness::Waveform::Sine,
        )
        .unwrap();
        for tau in [0.0, 0.37, 5.1] {
            let r = m.radius_ratio(tau);
            let want = leaf.eval(tau) * r * r / (1.0 + 0.5 * m.beta * m.beta);
            assert_eq!(m.stiffness(tau).to_bits(), want.to_bits());
        }
    }

    /// The model's `b̄(τ)` is the leaf's law, and equals the closed form `(b/L)/(r_b2/L)` of
    /// Eq. (11)–(12) under both readings.
    #[test]
    fn leaf_and_model_backlash_are_the_same_number() {
        for base_radius in [BaseRadius::TimeVarying, BaseRadius::Mean] {
            let mut p = table1();
            p.readings.base_radius = base_radius;
            let m = p.model().unwrap();
            for tau in [0.0, 0.37, 5.1, 123.4] {
                let want = match base_radius {
                    BaseRadius::TimeVarying => m.backlash / m.radius_ratio(tau),
                    _ => m.backlash,
                };
                let b = m.backlash_at(tau);
                assert!((b - want).abs() <= 1e-15 * want, "{base_radius:?} {tau}");
                let leaf = backlash::RadiusModulatedBacklash::new(
                    p.half_backlash / p.mean_base_radius().unwrap(),
                    m.backlash_law().beta,
                    m.omega_c,
                )
                .unwrap();
                let g = leaf
                    .half_gap(tau, &backlash::CentreDisplacement::default())
                    .unwrap();
                assert_eq!(g.b.to_bits(), b.to_bits());
            }
        }
    }

    #[test]
    fn rattle_of_period_equals_the_sample_loop() {
        for base_radius in [BaseRadius::Mean, BaseRadius::TimeVarying] {
            let mut p = table1();
            p.readings.base_radius = base_radius;
            let m = p.model().unwrap();
            let b = m.backlash;
            let t = m.period();
            // no rattle, unilateral, bilateral, and a NaN sample
            for (mean, amp) in [(-3.0 * b, 0.5 * b), (-b, 0.5 * b), (0.0, 2.0 * b)] {
                let mut q: Vec<f64> = (0..256)
                    .map(|i| mean + amp * (0.3 * f64::from(i)).dsin())
                    .collect();
                for extra in [None, Some(f64::NAN)] {
                    if let Some(x) = extra {
                        q[7] = x;
                    }
                    let fast = m.rattle_of_period(t, &q);
                    let slow = m.rattle(
                        q.iter()
                            .enumerate()
                            .map(|(i, &q)| (t * i as f64 / 256.0, q)),
                    );
                    assert_eq!(fast, slow, "{base_radius:?} {mean} {amp}");
                }
            }
        }
    }

    #[test]
    fn stiffness_has_unit_mean() {
        let m = table1().model().unwrap();
        let n = 8192;
        let t = m.period();
        let mean: f64 = (0..n)
            .map(|i| m.stiffness(t * i as f64 / n as f64))
            .sum::<f64>()
            / n as f64;
        assert!((mean - 1.0).abs() < 1e-12);
    }

    #[test]
    fn with_omega_c_matches_a_fresh_model() {
        for ra in [RigidAcceleration::Derived, RigidAcceleration::PrintedEq20] {
            let mut p = table1();
            p.readings.rigid_acceleration = ra;
            let m = p.model().unwrap();
            p.omega1 = 217.0;
            let fresh = p.model().unwrap();
            let moved = m.with_omega_c(fresh.omega_c).unwrap();
            // bit for bit the fresh model, also after a detour through other speeds (the
            // rounding of earlier changes is not carried: a continuation's model is a function
            // of its present speed)
            let mut detour = m;
            for w in [150.0, 100.1, 219.9, 133.3] {
                p.omega1 = w;
                detour = detour.with_omega_c(p.model().unwrap().omega_c).unwrap();
            }
            let detour = detour.with_omega_c(fresh.omega_c).unwrap();
            for other in [moved, detour] {
                assert_eq!(
                    serde_json::to_string(&other).unwrap(),
                    serde_json::to_string(&fresh).unwrap(),
                    "{ra:?}"
                );
                for (a, b) in [
                    (other.omega_e, fresh.omega_e),
                    (other.b1, fresh.b1),
                    (other.b2, fresh.b2),
                    (other.b3, fresh.b3),
                ] {
                    assert_eq!(a.to_bits(), b.to_bits(), "{ra:?}: {a} vs {b}");
                }
            }
        }
        assert!(table1().model().unwrap().with_omega_c(f64::NAN).is_err());
        assert!(table1().model().unwrap().with_omega_c(-1.0).is_err());
        assert!(table1().model().unwrap().with_omega_c(0.0).is_err());
    }
}
