//! Slightly non-circular gear pair of Karpov et al. 2017 (Eq. 1–7, Section 4). The paper's
//! Table 1 pair lives with the model, `geardyn_models::karpov2017::pair_table1`.

use math::DetMath;
use std::f64::consts::TAU;

use crate::Error;
use crate::error::{finite, positive};
use system::numeric::{Quadrature, bisect, integrate, maximize_periodic};

/// The relative centrode deviation of Karpov Eq. (1),
/// `g(θ) = B·√(ξ²−1)·sin θ / (ξ + cos θ)` with `θ = j·φ1`, so that `r1 = r·(1 + g)`.
///
/// `max g = B` exactly (at `cos θ = −1/ξ`), `min g = −B`, and `∫₀^{2π} g dθ = 0`. `ξ = +∞` is the
/// sinusoidal limit of Section 4, `g = B sin θ`. This type is all that the mesh-frequency
/// excitation of the Karpov oscillator (Eq. 7–10) needs: it is `Copy`, allocation-free and every
/// method costs one `sin`/`cos` pair (plus a `ln` for [`CentrodeDeviation::integral`]).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(try_from = "CentrodeDeviationParams", into = "CentrodeDeviationParams")
)]
pub struct CentrodeDeviation {
    b: f64,
    xi: f64,
    /// `√(1 − 1/ξ²)` = `√(ξ²−1)/ξ` (1 in the sinusoidal limit).
    s_over_xi: f64,
    /// `1/ξ` (0 in the sinusoidal limit).
    inv_xi: f64,
}

/// Unvalidated serde form of [`CentrodeDeviation`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct CentrodeDeviationParams {
    /// `B`, maximum relative deviation of `r1` (Eq. 1), dimensionless, in `[0, 1)`.
    pub b: f64,
    /// `ξ`, gear-ratio smoothness coefficient (Eq. 1), `> 1`; `+∞` (JSON: omit and use
    /// [`CentrodeDeviation::sinusoidal`]) is the sinusoidal limit.
    pub xi: f64,
}

impl TryFrom<CentrodeDeviationParams> for CentrodeDeviation {
    type Error = Error;
    fn try_from(p: CentrodeDeviationParams) -> Result<Self, Error> {
        Self::new(p.b, p.xi)
    }
}

impl From<CentrodeDeviation> for CentrodeDeviationParams {
    fn from(d: CentrodeDeviation) -> Self {
        Self { b: d.b, xi: d.xi }
    }
}

impl CentrodeDeviation {
    /// Validated deviation: `0 ≤ B < 1` (keeps `r1 > 0`), `ξ > 1` (`ξ = +∞` allowed: the
    /// sinusoidal limit). NaN is rejected.
    pub fn new(b: f64, xi: f64) -> Result<Self, Error> {
        if !(b.is_finite() && (0.0..1.0).contains(&b)) {
            return Err(Error::invalid("b", "in [0, 1) (keeps r1 > 0)", b));
        }
        if xi.is_nan() || xi <= 1.0 {
            return Err(Error::invalid(
                "xi",
                "> 1 (or +inf for the sinusoidal limit)",
                xi,
            ));
        }
        let inv_xi = if xi.is_infinite() { 0.0 } else { 1.0 / xi };
        let s_over_xi = ((1.0 - inv_xi) * (1.0 + inv_xi)).sqrt();
        Ok(Self {
            b,
            xi,
            s_over_xi,
            inv_xi,
        })
    }

    /// The sinusoidal limit `ξ → ∞` of Section 4: `g = B sin θ`.
    pub fn sinusoidal(b: f64) -> Result<Self, Error> {
        Self::new(b, f64::INFINITY)
    }

    /// `B`.
    pub fn b(&self) -> f64 {
        self.b
    }

    /// `ξ` (`+∞` in the sinusoidal limit).
    pub fn xi(&self) -> f64 {
        self.xi
    }

    /// `g(θ) = B√(ξ²−1) sin θ/(ξ + cos θ)`.
    #[inline]
    pub fn value(&self, theta: f64) -> f64 {
        let (s, c) = theta.dsin_cos();
        self.b * self.s_over_xi * s / (1.0 + c * self.inv_xi)
    }

    /// `dg/dθ = B√(ξ²−1)(1 + ξ cos θ)/(ξ + cos θ)²`.
    #[inline]
    pub fn derivative(&self, theta: f64) -> f64 {
        let c = theta.dcos();
        let den = 1.0 + c * self.inv_xi;
        self.b * self.s_over_xi * (self.inv_xi + c) / (den * den)
    }

    /// `G(θ) = ∫₀^θ g dθ' = −B√(ξ²−1)·ln((ξ + cos θ)/(ξ + 1))` (closed form; `B(1 − cos θ)` in
    /// the sinusoidal limit). Always `≥ 0`, periodic with period `2π`.
    #[inline]
    pub fn integral(&self, theta: f64) -> f64 {
        let c = theta.dcos();
        if self.inv_xi == 0.0 {
            return self.b * (1.0 - c);
        }
        // ξ·ln(1 + (cos θ − 1)/(ξ + 1)), written with ln_1p so that large ξ loses nothing.
        let x = (c - 1.0) * self.inv_xi / (1.0 + self.inv_xi);
        -self.b * self.s_over_xi * x.dln_1p() / self.inv_xi
    }

    /// Mesh-frequency factor of Eq. (7): `ω_m/(z1 ω1) = r1/r = 1 + g(θ)`.
    #[inline]
    pub fn mesh_frequency_factor(&self, theta: f64) -> f64 {
        1.0 + self.value(theta)
    }

    /// Dimensionless excitation frequency of Eq. (10), `ω_e(τ) = ω·(1 + g(kωτ))`.
    #[inline]
    pub fn dimensionless_mesh_frequency(&self, tau: f64, omega: f64, k: f64) -> f64 {
        omega * (1.0 + self.value(k * omega * tau))
    }

    /// Dimensionless mesh phase, the integral of Eq. (10):
    /// `Φ(τ) = ∫₀^τ ω_e dτ' = ωτ + G(kωτ)/k` (closed form; `k > 0`).
    #[inline]
    pub fn dimensionless_mesh_phase(&self, tau: f64, omega: f64, k: f64) -> f64 {
        omega * tau + self.integral(k * omega * tau) / k
    }

    /// `mean over θ of 1/(A − g(θ))`, closed form (needs `A > B`).
    fn mean_inverse(&self, a: f64) -> f64 {
        let b = self.b;
        let root = ((a - b) * (a + b)).sqrt();
        if self.inv_xi == 0.0 {
            return 1.0 / root;
        }
        // [A + ξB²s/√(A²−B²)]/(A² + B²s²) divided through by s² = ξ²−1.
        let inv_s2 = self.inv_xi * self.inv_xi / ((1.0 - self.inv_xi) * (1.0 + self.inv_xi));
        let xi_over_s = 1.0 / self.s_over_xi;
        (a * inv_s2 + xi_over_s * b * b / root) / (a * a * inv_s2 + b * b)
    }
}

/// How the centre distance of the Karpov pair is chosen (reading `R-KARPOV-EQ1-CLOSURE`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum CentreDistance {
    /// `a = r(1 + u)` and `r2 = r(u − g)` exactly as Eq. (1) prints them. The output gear then
    /// turns `2π/u + O(B²)` per input revolution, so the output centrode does not close exactly.
    AsPrinted,
    /// `a = r(1 + A)`, `r2 = r(A − g)` with `A ≥ u` solved so that the output turns exactly
    /// `2π/u` per input revolution (closed centrodes; `A − u = O(B²)`). Default.
    #[default]
    Closing,
}

/// Unvalidated serde form of [`KarpovPair`] (SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct KarpovPairParams {
    /// `r`, nominal radius of the input centrode (Eq. 1), m.
    pub r: f64,
    /// `u = z2/z1`, gear teeth ratio (Eq. 1–2), dimensionless, `> 0`.
    pub u: f64,
    /// `B`, maximum relative deviation of `r1` (Eq. 1), in `[0, min(1, u))`.
    pub b: f64,
    /// `ξ`, smoothness coefficient (Eq. 1), `> 1` (`+∞`: sinusoidal limit).
    pub xi: f64,
    /// `j`, ratio-variation cycles per input turn (Eq. 1), `≥ 1`.
    pub j: u32,
    /// `z1`, teeth of the input gear (Eq. 7), `≥ 1`.
    pub z1: u32,
    /// Centre-distance choice (reading `R-KARPOV-EQ1-CLOSURE`).
    #[cfg_attr(feature = "serde", serde(default))]
    pub centre_distance: CentreDistance,
}

/// A validated Karpov et al. 2017 pair of slightly non-circular gears.
///
/// Input centrode `r1(φ1) = r(1 + g(jφ1))`, output `r2(φ1) = r(A − g(jφ1))`, centre distance
/// `a = r1 + r2 = r(1 + A)` constant, with `A = u` ([`CentreDistance::AsPrinted`]) or the closing
/// value ([`CentreDistance::Closing`], default).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(try_from = "KarpovPairParams", into = "KarpovPairParams")
)]
pub struct KarpovPair {
    r: f64,
    u: f64,
    j: u32,
    z1: u32,
    dev: CentrodeDeviation,
    centre_distance: CentreDistance,
    /// `A = r2_nominal/r`.
    a: f64,
}

impl TryFrom<KarpovPairParams> for KarpovPair {
    type Error = Error;
    fn try_from(p: KarpovPairParams) -> Result<Self, Error> {
        Self::new(p)
    }
}

impl From<KarpovPair> for KarpovPairParams {
    fn from(k: KarpovPair) -> Self {
        k.params()
    }
}

/// Which speed-fluctuation expression a design check uses (reading `R-KARPOV-EQ4`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum SpeedFluctuationForm {
    /// `δ = u(max i − min i)` of the exact ratio (Eq. 3).
    Exact,
    /// Leading order of Eq. (3) with the Eq. (2) estimates of `max i`, `min i`:
    /// `δ ≈ 2B(1 + u)/u` (what Eq. 4 should read).
    Linearised,
    /// Eq. (4) exactly as printed, `δ ≈ 2B(1 + u)/u²` (a factor `u` smaller than Eq. 3 implies).
    PrintedEq4,
}

/// Result of the Section 4 design check "δ within δ_max".
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct DesignCheck {
    /// Allowed speed fluctuation `δ_max` (0.001 … 0.2 by mechanism type, Section 4).
    pub delta_max: f64,
    /// Exact `δ` of the pair (Eq. 3).
    pub delta_exact: f64,
    /// Linearised `δ = 2B(1 + u)/u` (consistent Eq. 4).
    pub delta_linear: f64,
    /// `δ` by Eq. (4) as printed, `2B(1 + u)/u²`.
    pub delta_eq4: f64,
    /// `delta_exact ≤ delta_max`.
    pub admissible: bool,
    /// Largest `B` with exact `δ ≤ δ_max` (other parameters kept), by root finding.
    pub b_max_exact: f64,
    /// Largest `B` by the linearised form: `δ_max u/(2(1 + u))` (capped below `min(1, u)`).
    pub b_max_linear: f64,
    /// Largest `B` by Eq. (4) as printed: `δ_max u²/(2(1 + u))` (capped below `min(1, u)`).
    pub b_max_eq4: f64,
}

impl KarpovPair {
    /// Validate and build. Errors name the field: `r > 0`, `u > 0`, `0 ≤ B < min(1, u)`,
    /// `ξ > 1`, `j ≥ 1`, `z1 ≥ 1`.
    pub fn new(p: KarpovPairParams) -> Result<Self, Error> {
        let r = positive("r", p.r)?;
        let u = positive("u", p.u)?;
        if !(p.b.is_finite() && p.b >= 0.0 && p.b < u.min(1.0)) {
            return Err(Error::invalid(
                "b",
                "in [0, min(1, u)) (keeps r1, r2 > 0)",
                p.b,
            ));
        }
        let dev = CentrodeDeviation::new(p.b, p.xi)?;
        if p.j < 1 {
            return Err(Error::invalid("j", ">= 1", f64::from(p.j)));
        }
        if p.z1 < 1 {
            return Err(Error::invalid("z1", ">= 1", f64::from(p.z1)));
        }
        let a = match p.centre_distance {
            CentreDistance::AsPrinted => u,
            CentreDistance::Closing => closing_ratio(&dev, u)?,
        };
        Ok(Self {
            r,
            u,
            j: p.j,
            z1: p.z1,
            dev,
            centre_distance: p.centre_distance,
            a,
        })
    }

    /// The parameters this pair was built from.
    pub fn params(&self) -> KarpovPairParams {
        KarpovPairParams {
            r: self.r,
            u: self.u,
            b: self.dev.b,
            xi: self.dev.xi,
            j: self.j,
            z1: self.z1,
            centre_distance: self.centre_distance,
        }
    }

    /// Same pair with another `B` (validated).
    pub fn with_b(&self, b: f64) -> Result<Self, Error> {
        Self::new(KarpovPairParams { b, ..self.params() })
    }

    /// Same pair with another centre-distance choice.
    pub fn with_centre_distance(&self, c: CentreDistance) -> Result<Self, Error> {
        Self::new(KarpovPairParams {
            centre_distance: c,
            ..self.params()
        })
    }

    /// The deviation function `g` (what the Karpov oscillator needs).
    pub fn deviation(&self) -> CentrodeDeviation {
        self.dev
    }

    /// `r`, m.
    pub fn r(&self) -> f64 {
        self.r
    }
    /// `u`.
    pub fn u(&self) -> f64 {
        self.u
    }
    /// `B`.
    pub fn b(&self) -> f64 {
        self.dev.b
    }
    /// `ξ`.
    pub fn xi(&self) -> f64 {
        self.dev.xi
    }
    /// `j`.
    pub fn j(&self) -> u32 {
        self.j
    }
    /// `z1`.
    pub fn z1(&self) -> u32 {
        self.z1
    }
    /// `k = j/z1`, the parameter of Eq. (10).
    pub fn k(&self) -> f64 {
        f64::from(self.j) / f64::from(self.z1)
    }
    /// Centre-distance choice.
    pub fn centre_distance_choice(&self) -> CentreDistance {
        self.centre_distance
    }
    /// `A = a/r − 1` (equals `u` for [`CentreDistance::AsPrinted`]).
    pub fn output_radius_ratio(&self) -> f64 {
        self.a
    }
    /// Centre distance `a = r1 + r2 = r(1 + A)`, m (constant in `φ1`).
    pub fn centre_distance(&self) -> f64 {
        self.r * (1.0 + self.a)
    }

    #[inline]
    fn theta(&self, phi1: f64) -> f64 {
        f64::from(self.j) * phi1
    }

    /// Input centrode radius `r1(φ1) = r(1 + g(jφ1))` (Eq. 1), m.
    #[inline]
    pub fn r1(&self, phi1: f64) -> f64 {
        self.r * (1.0 + self.dev.value(self.theta(phi1)))
    }

    /// Output centrode radius at the contact point, `r2(φ1) = r(A − g(jφ1))` (Eq. 1), m.
    #[inline]
    pub fn r2(&self, phi1: f64) -> f64 {
        self.r * (self.a - self.dev.value(self.theta(phi1)))
    }

    /// Exact gear ratio `i = ω2/ω1 = r1/r2 = (1 + g)/(A − g)` (Eq. 2, left).
    #[inline]
    pub fn ratio(&self, phi1: f64) -> f64 {
        let g = self.dev.value(self.theta(phi1));
        (1.0 + g) / (self.a - g)
    }

    /// Approximate ratio of Eq. (2), `1/u + (1 + u)g/u²` (error `O(B²)`).
    #[inline]
    pub fn ratio_eq2(&self, phi1: f64) -> f64 {
        let g = self.dev.value(self.theta(phi1));
        1.0 / self.u + (1.0 + self.u) * g / (self.u * self.u)
    }

    /// Exact output angle `φ2(φ1) = ∫₀^φ1 i dφ1`, closed form (rad).
    ///
    /// With `θ = jφ1`, `b = B√(ξ²−1)`, `D = A(ξ + cos θ) − b sin θ`:
    /// `jφ2 = −θ + (A + 1)[αθ + β ln(D(θ)/D(0)) + γ ∫₀^θ dθ'/D]`, `α = A/(A² + b²)`,
    /// `β = −b/(A² + b²)`, `γ = ξb²/(A² + b²)`, the last integral by the half-angle substitution
    /// with branch unwrapping. Agrees with [`KarpovPair::output_angle_quadrature`] to ~1e-15.
    pub fn output_angle(&self, phi1: f64) -> f64 {
        let theta = self.theta(phi1);
        let a = self.a;
        let bb = self.dev.b;
        let h_int = if self.dev.inv_xi == 0.0 {
            // ∫ dθ/(A − B sin θ)
            let k = ((a - bb) * (a + bb)).sqrt();
            int_inverse_trig(theta, a, 0.0, -bb, k)
        } else {
            // Everything divided by ξ to stay finite for large ξ: D/ξ = A(1 + c/ξ) − B(s/ξ) sin.
            let b = bb * self.dev.s_over_xi; // b/ξ
            let den = a * a * self.dev.inv_xi * self.dev.inv_xi + b * b; // (A² + b²)/ξ²
            let alpha = a * self.dev.inv_xi * self.dev.inv_xi / den;
            let beta = -b * self.dev.inv_xi / den;
            let gamma = b * b / den; // γ/ξ
            let (s, c) = theta.dsin_cos();
            let d = a * (1.0 + c * self.dev.inv_xi) - b * s;
            let d0 = a * (1.0 + self.dev.inv_xi);
            let k = self.dev.s_over_xi * ((a - bb) * (a + bb)).sqrt(); // K/ξ
            // ∫ dθ/(D/ξ) with P = A, Q = A/ξ, R = −b/ξ.
            let phi = int_inverse_trig(theta, a, a * self.dev.inv_xi, -b, k);
            alpha * theta + beta * (d / d0).dln() + gamma * phi
        };
        (-theta + (a + 1.0) * h_int) / f64::from(self.j)
    }

    /// Output angle by adaptive 20-point Gauss–Legendre quadrature of the exact ratio to absolute
    /// tolerance `tol` (rad). Independent check of [`KarpovPair::output_angle`].
    pub fn output_angle_quadrature(&self, phi1: f64, tol: f64) -> Quadrature {
        integrate(|p| self.ratio(p), 0.0, phi1, tol)
    }

    /// Approximate output angle (printed after Eq. 2):
    /// `φ1/u − B(1 + u)√(ξ²−1)/(j u²)·ln((ξ + cos jφ1)/(ξ + 1))` (error `O(B²)`).
    #[inline]
    pub fn output_angle_approx(&self, phi1: f64) -> f64 {
        let u = self.u;
        phi1 / u + (1.0 + u) * self.dev.integral(self.theta(phi1)) / (f64::from(self.j) * u * u)
    }

    /// Exact speed fluctuation `δ = u(max i − min i)` (Eq. 3), closed form: `g` spans
    /// `[−B, B]` and `i` is increasing in `g`, so `δ = u[(1 + B)/(A − B) − (1 − B)/(A + B)]`
    /// (`= 2Bu(1 + u)/(u² − B²)` for `A = u`).
    pub fn speed_fluctuation(&self) -> f64 {
        let (a, b) = (self.a, self.dev.b);
        self.u * ((1.0 + b) / (a - b) - (1.0 - b) / (a + b))
    }

    /// Exact speed fluctuation found numerically: `max i` and `min i` of the exact ratio over a
    /// period by sampling + golden section (value accurate to rounding).
    pub fn speed_fluctuation_numeric(&self) -> f64 {
        let n = sample_count(self.dev.xi);
        let f = |t: f64| {
            let g = self.dev.value(t);
            (1.0 + g) / (self.a - g)
        };
        let (_, max) = maximize_periodic(f, TAU, n);
        let (_, neg_min) = maximize_periodic(|t| -f(t), TAU, n);
        self.u * (max + neg_min)
    }

    /// Leading-order speed fluctuation implied by Eq. (3) and the estimates of `max i`, `min i`
    /// printed before Eq. (4): `δ ≈ 2B(1 + u)/u` (relative error `B²/u²` for `A = u`).
    pub fn speed_fluctuation_linear(&self) -> f64 {
        2.0 * self.dev.b * (1.0 + self.u) / self.u
    }

    /// Speed fluctuation by Eq. (4) exactly as printed, `δ ≈ 2B(1 + u)/u²`: a factor `u` below
    /// the exact value as `B → 0` (reading `R-KARPOV-EQ4`).
    pub fn speed_fluctuation_eq4(&self) -> f64 {
        2.0 * self.dev.b * (1.0 + self.u) / (self.u * self.u)
    }

    /// Exact output angular acceleration `ε2 = ω1² di/dφ1` for a constant input speed `ω1`
    /// (rad/s), Eq. (5) left: `ε2 = j ω1² (1 + A) g'(θ)/(A − g)²`, rad/s².
    #[inline]
    pub fn acceleration(&self, phi1: f64, omega1: f64) -> f64 {
        let t = self.theta(phi1);
        let g = self.dev.value(t);
        let d = self.a - g;
        f64::from(self.j) * omega1 * omega1 * (1.0 + self.a) * self.dev.derivative(t) / (d * d)
    }

    /// Approximate `ε2` of Eq. (5) right: `j ω1² (1 + u) g'(θ)/u²`, rad/s².
    #[inline]
    pub fn acceleration_eq5_approx(&self, phi1: f64, omega1: f64) -> f64 {
        let t = self.theta(phi1);
        let u = self.u;
        f64::from(self.j) * omega1 * omega1 * (1.0 + u) * self.dev.derivative(t) / (u * u)
    }

    /// Exact `ε_max = max |ε2|` over a revolution, found numerically (rad/s²).
    pub fn max_acceleration(&self, omega1: f64) -> f64 {
        let n = sample_count(self.dev.xi);
        let j = f64::from(self.j);
        let (_, v) = maximize_periodic(|t| self.acceleration(t / j, omega1).abs(), TAU, n);
        v
    }

    /// `ε_max` by Eq. (6): `B j ω1² (1 + u)√(ξ + 1)/(u²√(ξ − 1))` (`ξ = ∞`: `Bjω1²(1 + u)/u²`).
    pub fn max_acceleration_eq6(&self, omega1: f64) -> f64 {
        let u = self.u;
        let shape = if self.dev.inv_xi == 0.0 {
            1.0
        } else {
            ((1.0 + self.dev.inv_xi) / (1.0 - self.dev.inv_xi)).sqrt()
        };
        self.dev.b * f64::from(self.j) * omega1 * omega1 * (1.0 + u) * shape / (u * u)
    }

    /// Instantaneous angular mesh frequency of Eq. (7), `ω_m = r1 z1 ω1/r` (rad/s) at input angle
    /// `φ1` and constant input speed `ω1`.
    #[inline]
    pub fn mesh_frequency(&self, phi1: f64, omega1: f64) -> f64 {
        f64::from(self.z1) * omega1 * self.dev.mesh_frequency_factor(self.theta(phi1))
    }

    /// Mesh phase `∫ ω_m dt = z1(φ1 + G(jφ1)/j)` (rad), closed form, for constant `ω1`.
    /// Increases by exactly `2π z1` per input revolution.
    #[inline]
    pub fn mesh_phase(&self, phi1: f64) -> f64 {
        let j = f64::from(self.j);
        f64::from(self.z1) * (phi1 + self.dev.integral(j * phi1) / j)
    }

    /// Section 4 design check: is the exact `δ ≤ δ_max`, and the largest admissible `B` (other
    /// parameters kept), by bisection on the exact `δ(B)`, by the linearised form and by Eq. (4)
    /// as printed. `δ_max` in `(0, ∞)`.
    pub fn design_check(&self, delta_max: f64) -> Result<DesignCheck, Error> {
        let delta_max = positive("delta_max", delta_max)?;
        Ok(DesignCheck {
            delta_max,
            delta_exact: self.speed_fluctuation(),
            delta_linear: self.speed_fluctuation_linear(),
            delta_eq4: self.speed_fluctuation_eq4(),
            admissible: self.speed_fluctuation() <= delta_max,
            b_max_exact: self.max_admissible_b(delta_max, SpeedFluctuationForm::Exact)?,
            b_max_linear: self.max_admissible_b(delta_max, SpeedFluctuationForm::Linearised)?,
            b_max_eq4: self.max_admissible_b(delta_max, SpeedFluctuationForm::PrintedEq4)?,
        })
    }

    /// Largest `B` with `δ(B) ≤ δ_max` (other parameters kept). `Exact` root-finds the exact `δ`
    /// (bisection to 1e-15, re-solving the closing centre distance at every trial `B`);
    /// `Linearised` is `δ_max u/(2(1 + u))`, `PrintedEq4` is `δ_max u²/(2(1 + u))`. All are
    /// capped just below the validity bound `min(1, u)`.
    pub fn max_admissible_b(
        &self,
        delta_max: f64,
        form: SpeedFluctuationForm,
    ) -> Result<f64, Error> {
        let delta_max = positive("delta_max", delta_max)?;
        let cap = self.u.min(1.0) * (1.0 - 1e-12);
        match form {
            SpeedFluctuationForm::Linearised => {
                Ok((delta_max * self.u / (2.0 * (1.0 + self.u))).min(cap))
            }
            SpeedFluctuationForm::PrintedEq4 => {
                Ok((delta_max * self.u * self.u / (2.0 * (1.0 + self.u))).min(cap))
            }
            SpeedFluctuationForm::Exact => {
                let delta = |b: f64| -> f64 {
                    self.with_b(b)
                        .map(|p| p.speed_fluctuation())
                        .unwrap_or(f64::INFINITY)
                };
                if delta(cap) <= delta_max {
                    return Ok(cap);
                }
                bisect(|b| delta(b) - delta_max, 0.0, cap, 1e-15).map_err(Error::from)
            }
        }
    }
}

/// Continuous `∫₀^θ dθ'/(P + Q cos θ' + R sin θ')` for `P > √(Q² + R²)`, `K = √(P² − Q² − R²)`:
/// half-angle substitution `(2/K)·atan(((P − Q) tan(θ/2) + R)/K)` unwrapped by whole periods.
#[inline]
fn int_inverse_trig(theta: f64, p: f64, q: f64, r: f64, k: f64) -> f64 {
    let n = (theta / TAU).round();
    let tr = theta - n * TAU;
    let g = |t: f64| 2.0 / k * (((p - q) * (0.5 * t).dtan() + r) / k).datan();
    n * TAU / k + g(tr) - g(0.0)
}

/// Samples per period for the maximisers: resolve the peak width `~(ξ − 1)` near `θ = π`.
fn sample_count(xi: f64) -> usize {
    if xi.is_infinite() {
        return 256;
    }
    let n = (40.0 / (xi - 1.0)).ceil();
    if n.is_finite() {
        (n as usize).clamp(256, 400_000)
    } else {
        400_000
    }
}

/// Solve `(A + 1)·mean(1/(A − g)) = (1 + u)/u` for `A ≥ u` (closed output centrode).
fn closing_ratio(dev: &CentrodeDeviation, u: f64) -> Result<f64, Error> {
    if dev.b == 0.0 {
        return Ok(u);
    }
    let target = (1.0 + u) / u;
    let f = |a: f64| (a + 1.0) * dev.mean_inverse(a) - target;
    let mut width = u * dev.b * dev.b + 1e-300;
    let mut hi = u + width;
    let mut tries = 0;
    while f(hi) > 0.0 {
        width *= 4.0;
        hi = u + width;
        tries += 1;
        if tries > 200 || !hi.is_finite() {
            return Err(Error::NoConvergence {
                what: "closing centre distance (bracket)",
                iterations: tries,
                residual: f(hi),
            });
        }
    }
    let lo = u;
    if f(lo) <= 0.0 {
        return Ok(u);
    }
    let a = bisect(f, lo, hi, 4.0 * f64::EPSILON * u)?;
    finite("closing centre distance", a)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pair(b: f64, xi: f64, j: u32, c: CentreDistance) -> KarpovPair {
        KarpovPair::new(KarpovPairParams {
            r: 0.05,
            u: 2.0,
            b,
            xi,
            j,
            z1: 32,
            centre_distance: c,
        })
        .unwrap()
    }

    #[test]
    fn deviation_extremes_and_integral() {
        for xi in [1.1, 2.0, 10.0, f64::INFINITY] {
            let d = CentrodeDeviation::new(0.01, xi).unwrap();
            let (_, max) = maximize_periodic(|t| d.value(t), TAU, 4096);
            assert!((max - 0.01).abs() < 1e-15, "xi={xi}: {max}");
            let q = integrate(|t| d.value(t), 0.0, 1.3, 1e-15);
            assert!((q.value - d.integral(1.3)).abs() < 1e-15);
            let h = 1e-6;
            let fd = (d.value(0.7 + h) - d.value(0.7 - h)) / (2.0 * h);
            assert!((fd - d.derivative(0.7)).abs() < 1e-10);
        }
    }

    #[test]
    fn validation_names_fields() {
        let bad = |p: KarpovPairParams| KarpovPair::new(p).unwrap_err().to_string();
        let ok = pair(0.01, 2.0, 4, CentreDistance::Closing).params();
        assert!(bad(KarpovPairParams { r: -1.0, ..ok }).starts_with("r must be"));
        assert!(bad(KarpovPairParams { u: f64::NAN, ..ok }).starts_with("u must be"));
        assert!(bad(KarpovPairParams { b: 1.0, ..ok }).starts_with("b must be"));
        assert!(
            bad(KarpovPairParams {
                b: 0.5,
                u: 0.4,
                ..ok
            })
            .starts_with("b must be")
        );
        assert!(bad(KarpovPairParams { xi: 1.0, ..ok }).starts_with("xi must be"));
        assert!(bad(KarpovPairParams { xi: f64::NAN, ..ok }).starts_with("xi must be"));
        assert!(bad(KarpovPairParams { j: 0, ..ok }).starts_with("j must be"));
        assert!(bad(KarpovPairParams { z1: 0, ..ok }).starts_with("z1 must be"));
    }

    #[test]
    fn closed_form_output_angle_matches_quadrature() {
        for c in [CentreDistance::AsPrinted, CentreDistance::Closing] {
            for xi in [1.05, 2.0, 30.0, f64::INFINITY] {
                let p = pair(0.3, xi, 3, c);
                for phi in [0.0, 0.4, 1.9, 3.3, 6.0, 13.0] {
                    let q = p.output_angle_quadrature(phi, 1e-14);
                    let e = p.output_angle(phi);
                    assert!(
                        (q.value - e).abs() < 2e-13,
                        "xi={xi} phi={phi}: {} vs {e}",
                        q.value
                    );
                }
            }
        }
    }

    #[test]
    fn numeric_speed_fluctuation_matches_closed_form() {
        for xi in [1.02, 2.0, f64::INFINITY] {
            let p = pair(0.05, xi, 2, CentreDistance::Closing);
            let (a, b) = (p.speed_fluctuation(), p.speed_fluctuation_numeric());
            assert!(((a - b) / a).abs() < 1e-13, "{a} {b}");
        }
    }

    #[test]
    fn mesh_phase_is_integral_of_mesh_frequency() {
        let p = pair(0.01, 2.0, 4, CentreDistance::Closing);
        let q = integrate(|t| p.mesh_frequency(t, 1.0), 0.0, 2.1, 1e-13);
        assert!((q.value - p.mesh_phase(2.1)).abs() < 1e-11);
        assert!((p.mesh_phase(TAU) - TAU * 32.0).abs() < 1e-11);
    }
}
