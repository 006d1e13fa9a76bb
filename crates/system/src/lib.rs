//! # geardyn-system
//!
//! The one description of a mechanical model that every geardyn engine solves: an `n`-DOF
//! second-order system
//!
//! ```text
//! M q'' + C q' + K q + g(t, q, q') = f(t)
//! ```
//!
//! with constant matrices `M` (invertible), `C`, `K`, a nonlinear and/or time-varying force `g`
//! with its Jacobians `∂g/∂q`, `∂g/∂q'`, an external forcing `f`, contact-event (gap) functions
//! `e_i(t, q, q')` whose zeros are the switching surfaces of `g` (backlash edges), and named
//! parameters for continuation and sweeps.
//!
//! A model implements [`SecondOrderSystem`] once; the harmonic balance engine (`geardyn-hbm`)
//! takes it as is (its `SecondOrderSystem` *is* this trait), and the time-stepping engine
//! (`geardyn-timestep`) integrates it through its `Mechanical` adapter, which forms
//! `q'' = M⁻¹ (f − C q' − K q − g)` and locates the events. Neither engine depends on the
//! other, and this crate depends on neither: it holds only the trait, its error type, the
//! event direction, two helpers ([`finite_difference_force_jacobian`], [`gap_edges`]) and the
//! workspace's one classical RK4 step ([`rk4::rk4_step`]) and small numerical tools
//! ([`numeric`]: Gauss–Legendre quadrature, a periodic maximiser, bisection), and the one
//! spur-pair pressure-angle law and centre-distance form ([`involute`]) that the geometry and
//! backlash leaves share.
//!
//! ## Optional hooks
//!
//! * [`SecondOrderSystem::force_jacobian`] defaults to central finite differences.
//! * [`SecondOrderSystem::set_base_frequency`] is told the fundamental frequency `ω` of the
//!   periodic response an engine seeks (systems whose excitation is tied to `ω` store it).
//! * Time tables: a system whose `g` contains functions of `t` alone (a mesh stiffness `k(t)`,
//!   a time-varying backlash `b(t)`) may declare [`time_table_len`](SecondOrderSystem::time_table_len)
//!   `> 0` values per time, fill them in [`fill_time_table`](SecondOrderSystem::fill_time_table),
//!   and evaluate `g` from them in [`nonlinear_force_tabulated`](SecondOrderSystem::nonlinear_force_tabulated)
//!   and [`force_jacobian_tabulated`](SecondOrderSystem::force_jacobian_tabulated) (and the
//!   events in [`events_tabulated`](SecondOrderSystem::events_tabulated)). An engine
//!   that samples the same times again and again (the AFT grid of harmonic balance) may then
//!   tabulate them once; one that needs the forcing and the row at each new time (the
//!   orbit flow) takes both from [`fill_time_functions`](SecondOrderSystem::fill_time_functions),
//!   which a system overrides when the two share `sin`/`cos`. The defaults (length 0,
//!   untabulated evaluation) are always correct.
//!
//! ## Example
//!
//! ```
//! use geardyn_system::{SecondOrderSystem, gap_edges};
//! use nalgebra::DMatrix;
//!
//! /// q'' + 2ζ q' + k(t) d(q, b) = F, d the dead zone of half-width b.
//! struct Rattle { zeta: f64, b: f64, force: f64 }
//!
//! impl SecondOrderSystem for Rattle {
//!     fn n_dof(&self) -> usize { 1 }
//!     fn mass(&self) -> DMatrix<f64> { DMatrix::identity(1, 1) }
//!     fn damping(&self) -> DMatrix<f64> { DMatrix::from_element(1, 1, 2.0 * self.zeta) }
//!     fn nonlinear_force(&self, t: f64, q: &[f64], _qd: &[f64], g: &mut [f64]) {
//!         let d = if q[0] > self.b { q[0] - self.b } else if q[0] < -self.b { q[0] + self.b } else { 0.0 };
//!         g[0] = (1.0 + 0.1 * t.cos()) * d;
//!     }
//!     fn forcing(&self, _t: f64, f: &mut [f64]) { f[0] = self.force; }
//!     fn n_events(&self) -> usize { 2 }
//!     fn events(&self, _t: f64, q: &[f64], _qd: &[f64], e: &mut [f64]) { gap_edges(q[0], self.b, e) }
//! }
//!
//! let s = Rattle { zeta: 0.05, b: 1.0, force: 0.1 };
//! let (mut dq, mut dv) = ([0.0], [0.0]);
//! s.force_jacobian(0.0, &[2.0], &[0.0], &mut dq, &mut dv); // finite differences by default
//! assert!((dq[0] - 1.1).abs() < 1e-6);
//! assert!(s.parameter("zeta").is_err()); // no named parameters unless the model offers them
//! ```

#![deny(missing_docs)]

use math::DetMath;
pub mod account;
pub mod deadline;
pub mod dop853;
pub mod format;
pub mod involute;
pub mod numeric;
pub mod problems;
pub mod rk4;
pub mod sweep;

pub use involute::{
    Beta0, CentreDisplacement, CentreDistanceForm, GeometryField, InvalidGeometry, PairGeometry,
    PressureAngleLaw,
};

/// The workspace's one Floquet stability threshold: a periodic solution is stable when its
/// largest multiplier modulus is `≤ 1 + STABILITY_TOLERANCE` ([`is_stable_multiplier`]). The
/// harmonic-balance stability (`geardyn-hbm`), the shooting multipliers (`geardyn-orbit`) and
/// the models' stability policies all judge with it.
pub const STABILITY_TOLERANCE: f64 = 1e-6;

/// `max |μ| ≤ 1 + STABILITY_TOLERANCE`: the one stability verdict on a largest multiplier
/// modulus (NaN: not stable).
#[inline]
pub fn is_stable_multiplier(max_modulus: f64) -> bool {
    max_modulus <= 1.0 + STABILITY_TOLERANCE
}

/// The one stability type of a periodic orbit: its Floquet multipliers (complex, as
/// `[Re μ, Im μ]`), the largest modulus ([`max_modulus`]) and the verdict
/// `max |μ| ≤ 1 + STABILITY_TOLERANCE` ([`is_stable_multiplier`]), whatever computed the
/// multipliers: the harmonic-balance variational equation (`hbm`, which returns this type), the
/// shooting monodromy (`orbit::Floquet::stability`; `orbit` re-exports it as
/// `orbit::Stability`) or a model's own period map, through [`Stability::from_multipliers`].
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Stability {
    /// Multipliers `μ` as `[Re μ, Im μ]`, in the order given.
    pub multipliers: Vec<[f64; 2]>,
    /// `max |μ|` (0 for no multipliers).
    pub max_modulus: f64,
    /// `max |μ| ≤ 1 + STABILITY_TOLERANCE`.
    pub stable: bool,
}

impl Stability {
    /// The verdict on `multipliers` (`[Re μ, Im μ]`).
    pub fn from_multipliers(multipliers: Vec<[f64; 2]>) -> Self {
        let max_modulus = max_modulus(&multipliers);
        Self {
            multipliers,
            max_modulus,
            stable: is_stable_multiplier(max_modulus),
        }
    }
}

/// `max |μ|` over Floquet multipliers given as `[Re μ, Im μ]` (`|μ| = hypot(Re μ, Im μ)`; 0 for
/// none): the one largest-modulus rule behind [`is_stable_multiplier`], shared by the
/// harmonic-balance stability (`geardyn-hbm`), the orbit stability type (`geardyn-orbit`) and
/// the models' shooting multipliers.
#[inline]
pub fn max_modulus(multipliers: &[[f64; 2]]) -> f64 {
    multipliers
        .iter()
        .map(|z| z[0].dhypot(z[1]))
        .fold(0.0, f64::max)
}

use nalgebra::DMatrix;

/// Errors a [`SecondOrderSystem`] reports through its setters.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SystemError {
    /// The system does not know the named parameter.
    #[error("unknown parameter `{name}`")]
    UnknownParameter {
        /// The name that was asked for.
        name: String,
    },
    /// A parameter (or base frequency) value is outside what the model can take.
    #[error("{name} must be {bound}, got {}", shown(*value))]
    InvalidParameter {
        /// Name of the parameter (dotted path, e.g. `liu2021.omega_c`).
        name: String,
        /// The admissible range, in words.
        bound: &'static str,
        /// The offending value.
        value: f64,
    },
}

/// A value in a message: as Rust prints it, in scientific notation beyond `1e16` or below
/// `1e-5` in magnitude (`1e300`, not three hundred digits).
fn shown(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-5..1e16).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

impl SystemError {
    /// An [`SystemError::InvalidParameter`].
    pub fn invalid(name: impl Into<String>, bound: &'static str, value: f64) -> Self {
        SystemError::InvalidParameter {
            name: name.into(),
            bound,
            value,
        }
    }
}

/// Direction of a zero crossing of an event function.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Direction {
    /// The function goes from negative to positive.
    Rising,
    /// The function goes from positive to negative.
    Falling,
    /// Either direction (used as a filter only).
    Both,
}

impl Direction {
    /// True if a crossing in direction `actual` passes this filter.
    pub fn accepts(self, actual: Direction) -> bool {
        matches!(self, Direction::Both) || self == actual
    }
}

/// The earliest zero crossing over one step `[t, t + h]` of event functions, estimated by
/// linear interpolation (the retry rule of a step rejected across a switching surface, shared by
/// `geardyn-timestep`'s driver and `geardyn-orbit`'s flows): for every function `i` that starts
/// strictly on its side `side[i]` (`±1`; `0`: none yet) with `g0[i]` and ends on the other side
/// or on zero with `g1[i]`, in a direction that `accepts(i, direction)` admits,
/// `θᵢ = g0ᵢ/(g0ᵢ − g1ᵢ)`. Returns the least `θᵢ ∈ (0, 1]`, or `None` (also for non-finite
/// values, which give no `θᵢ` in that interval).
pub fn earliest_crossing(
    side: &[f64],
    g0: &[f64],
    g1: &[f64],
    accepts: impl Fn(usize, Direction) -> bool,
) -> Option<f64> {
    let mut best: Option<f64> = None;
    for (i, ((&s, &ga), &gb)) in side.iter().zip(g0).zip(g1).enumerate() {
        if s == 0.0 || gb * s > 0.0 || gb.is_nan() || ga * s <= 0.0 {
            continue;
        }
        let dir = if s > 0.0 {
            Direction::Falling
        } else {
            Direction::Rising
        };
        if !accepts(i, dir) {
            continue;
        }
        let th = ga / (ga - gb);
        if th > 0.0 && th <= 1.0 {
            best = Some(best.map_or(th, |x: f64| x.min(th)));
        }
    }
    best
}

/// An `n`-DOF second-order system `M q'' + C q' + K q + g(t, q, q') = f(t)`.
///
/// `M`, `C`, `K` are constant matrices; everything time-varying (parametric stiffness,
/// transmission errors, …) and everything nonlinear lives in `g` and `f`. For harmonic balance
/// `g` and `f` must be periodic with the period `2π/ω` of the base frequency `ω`.
///
/// Required: [`n_dof`](Self::n_dof), [`mass`](Self::mass), [`damping`](Self::damping),
/// [`nonlinear_force`](Self::nonlinear_force), [`forcing`](Self::forcing). Everything else has a
/// correct default (see the crate docs).
pub trait SecondOrderSystem {
    /// Number of degrees of freedom `n`.
    fn n_dof(&self) -> usize;
    /// Mass matrix `M` (`n × n`, invertible).
    fn mass(&self) -> DMatrix<f64>;
    /// Damping matrix `C` (`n × n`).
    fn damping(&self) -> DMatrix<f64>;
    /// Linear stiffness matrix `K` (`n × n`); zero by default (put it in `g` or here).
    fn stiffness(&self) -> DMatrix<f64> {
        DMatrix::zeros(self.n_dof(), self.n_dof())
    }
    /// Nonlinear (and/or time-varying) force `g(t, q, q')`, written into `g` (length `n`).
    fn nonlinear_force(&self, t: f64, q: &[f64], qd: &[f64], g: &mut [f64]);
    /// External forcing `f(t)`, written into `f` (length `n`).
    fn forcing(&self, t: f64, f: &mut [f64]);
    /// Jacobians `∂g/∂q` and `∂g/∂q'`, row-major `n × n` (`dg_dq[i*n + j] = ∂g_i/∂q_j`).
    ///
    /// Default: central finite differences of [`nonlinear_force`](Self::nonlinear_force)
    /// ([`finite_difference_force_jacobian`]).
    fn force_jacobian(&self, t: f64, q: &[f64], qd: &[f64], dg_dq: &mut [f64], dg_dqd: &mut [f64]) {
        finite_difference_force_jacobian(self, t, q, qd, dg_dq, dg_dqd);
    }

    /// Number of time-only values per sample time that [`fill_time_table`](Self::fill_time_table)
    /// writes (default 0: nothing to tabulate).
    fn time_table_len(&self) -> usize {
        0
    }
    /// Writes the time-only values at `t` (length [`time_table_len`](Self::time_table_len)),
    /// e.g. `[k(t), b(t)]`. Default: nothing.
    fn fill_time_table(&self, t: f64, row: &mut [f64]) {
        let _ = (t, row);
    }
    /// The forcing `f(t)` and the time-table row at one `t` in one call: must write what
    /// [`forcing`](Self::forcing) and [`fill_time_table`](Self::fill_time_table) write, bit for
    /// bit. Default: calls the two. Override it when they share work (the same `sin`/`cos` of
    /// `t`); an engine that needs both at a new time calls this instead of the two.
    fn fill_time_functions(&self, t: f64, f: &mut [f64], row: &mut [f64]) {
        self.forcing(t, f);
        self.fill_time_table(t, row);
    }
    /// `g(t, q, q')` from a row written by [`fill_time_table`](Self::fill_time_table) at the same
    /// `t`; must equal [`nonlinear_force`](Self::nonlinear_force). Default: ignores the row.
    fn nonlinear_force_tabulated(&self, t: f64, row: &[f64], q: &[f64], qd: &[f64], g: &mut [f64]) {
        let _ = row;
        self.nonlinear_force(t, q, qd, g);
    }
    /// Jacobians from a tabulated row; must equal [`force_jacobian`](Self::force_jacobian).
    /// Default: ignores the row.
    fn force_jacobian_tabulated(
        &self,
        t: f64,
        row: &[f64],
        q: &[f64],
        qd: &[f64],
        dg_dq: &mut [f64],
        dg_dqd: &mut [f64],
    ) {
        let _ = row;
        self.force_jacobian(t, q, qd, dg_dq, dg_dqd);
    }

    /// Tabulates the forcing and the time table on the harmonic balance grid
    /// `t_m = 2π m / (N ω)` ([`grid_time`]), `m = 0..N`: `forcing[m·n + i] = f_i(t_m)` and
    /// `table[m·L + l]` = row `l` of [`fill_time_table`](Self::fill_time_table) at `t_m`
    /// (`L` = [`time_table_len`](Self::time_table_len)).
    ///
    /// Default: sample by sample ([`tabulate_pointwise`]). Override it when the time functions
    /// are cheaper on the whole grid (e.g. `sin(2π k m/N)` from one table of the unit circle
    /// instead of a `sin` call per function and sample); the values must equal the pointwise
    /// ones to round-off.
    fn tabulate_grid(&self, omega: f64, n_grid: usize, forcing: &mut [f64], table: &mut [f64]) {
        tabulate_pointwise(self, omega, n_grid, forcing, table);
    }

    /// Number of contact-event (gap) functions (default 0).
    fn n_events(&self) -> usize {
        0
    }
    /// Event functions `e_i(t, q, q')` (length [`n_events`](Self::n_events)): continuous along a
    /// trajectory, zero on the switching surfaces of `g` (e.g. [`gap_edges`]). A time-stepping
    /// engine locates their zeros so that no step straddles a contact switch.
    fn events(&self, t: f64, q: &[f64], qd: &[f64], e: &mut [f64]) {
        let _ = (t, q, qd, e);
    }
    /// [`events`](Self::events) from a row written by [`fill_time_table`](Self::fill_time_table)
    /// at the same `t` (e.g. the gap edges `q = ±b(t)` from a tabulated `b(t)`); must equal
    /// [`events`](Self::events) bit for bit. Default: ignores the row.
    fn events_tabulated(&self, t: f64, row: &[f64], q: &[f64], qd: &[f64], e: &mut [f64]) {
        let _ = row;
        self.events(t, q, qd, e);
    }
    /// Which crossings of event `index` matter (default both).
    fn event_direction(&self, index: usize) -> Direction {
        let _ = index;
        Direction::Both
    }

    /// Told the base frequency `ω` of the periodic response an engine seeks (harmonic balance
    /// calls it whenever its `ω` is set). Systems whose excitation frequency is tied to `ω`
    /// store it here; the default ignores it.
    ///
    /// # Errors
    /// Implementation-defined (an `ω` the model cannot take).
    fn set_base_frequency(&mut self, omega: f64) -> Result<(), SystemError> {
        let _ = omega;
        Ok(())
    }
    /// Set a named parameter (for continuation and sweeps). Default: unknown.
    ///
    /// # Errors
    /// [`SystemError::UnknownParameter`], or a value the model cannot take.
    fn set_parameter(&mut self, name: &str, value: f64) -> Result<(), SystemError> {
        let _ = value;
        Err(SystemError::UnknownParameter {
            name: name.to_string(),
        })
    }
    /// Read a named parameter. Default: unknown.
    ///
    /// # Errors
    /// [`SystemError::UnknownParameter`].
    fn parameter(&self, name: &str) -> Result<f64, SystemError> {
        Err(SystemError::UnknownParameter {
            name: name.to_string(),
        })
    }
}

/// Sample `m` of the harmonic balance grid of `n_grid` points per period `2π/ω`:
/// `t_m = 2π m / (N ω)`.
#[inline]
pub fn grid_time(omega: f64, n_grid: usize, m: usize) -> f64 {
    2.0 * std::f64::consts::PI * m as f64 / (n_grid as f64 * omega)
}

/// The default of [`SecondOrderSystem::tabulate_grid`]: [`forcing`](SecondOrderSystem::forcing)
/// and [`fill_time_table`](SecondOrderSystem::fill_time_table) at every [`grid_time`].
/// Slices shorter than `N n` and `N L` are filled as far as they reach.
pub fn tabulate_pointwise<S: SecondOrderSystem + ?Sized>(
    system: &S,
    omega: f64,
    n_grid: usize,
    forcing: &mut [f64],
    table: &mut [f64],
) {
    let (n, len) = (system.n_dof(), system.time_table_len());
    for m in 0..n_grid {
        let t = grid_time(omega, n_grid, m);
        if let Some(f) = forcing.get_mut(m * n..(m + 1) * n) {
            system.forcing(t, f);
        }
        if len > 0 {
            if let Some(row) = table.get_mut(m * len..(m + 1) * len) {
                system.fill_time_table(t, row);
            }
        }
    }
}

/// Central finite-difference Jacobians of `g` (the default of
/// [`SecondOrderSystem::force_jacobian`]); step [`finite_difference_step`].
pub fn finite_difference_force_jacobian<S: SecondOrderSystem + ?Sized>(
    system: &S,
    t: f64,
    q: &[f64],
    qd: &[f64],
    dg_dq: &mut [f64],
    dg_dqd: &mut [f64],
) {
    let n = q.len();
    let mut x = q.to_vec();
    let mut v = qd.to_vec();
    let mut gp = vec![0.0; n];
    let mut gm = vec![0.0; n];
    for j in 0..n {
        let h = finite_difference_step(q[j]);
        x[j] = q[j] + h;
        system.nonlinear_force(t, &x, qd, &mut gp);
        x[j] = q[j] - h;
        system.nonlinear_force(t, &x, qd, &mut gm);
        x[j] = q[j];
        for i in 0..n {
            dg_dq[i * n + j] = (gp[i] - gm[i]) / (2.0 * h);
        }
        let h = finite_difference_step(qd[j]);
        v[j] = qd[j] + h;
        system.nonlinear_force(t, q, &v, &mut gp);
        v[j] = qd[j] - h;
        system.nonlinear_force(t, q, &v, &mut gm);
        v[j] = qd[j];
        for i in 0..n {
            dg_dqd[i * n + j] = (gp[i] - gm[i]) / (2.0 * h);
        }
    }
}

/// The step `6e-6 (1 + |x|)` of [`finite_difference_force_jacobian`] in the coordinate or
/// velocity `x`: a system's own Jacobian that reproduces the default's bits (computing fixed
/// terms once) takes its steps from here.
#[inline]
pub fn finite_difference_step(x: f64) -> f64 {
    6e-6 * (1.0 + x.abs())
}

/// Event functions of a symmetric gap (backlash, dead zone) of half-width `b` in the
/// coordinate `x`: `e[0] = x − b` (upper edge) and `e[1] = x + b` (lower edge).
pub fn gap_edges(x: f64, b: f64, e: &mut [f64]) {
    e[0] = x - b;
    e[1] = x + b;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_invalid_value_is_shown_short() {
        let e = |v: f64| SystemError::invalid("x", "> 0", v).to_string();
        assert_eq!(e(-2e300), "x must be > 0, got -2e300");
        assert_eq!(e(0.584504), "x must be > 0, got 0.584504");
        assert_eq!(e(-1.0), "x must be > 0, got -1");
        assert_eq!(e(1e-300), "x must be > 0, got 1e-300");
        assert_eq!(e(f64::NAN), "x must be > 0, got NaN");
    }

    struct Cubic;
    impl SecondOrderSystem for Cubic {
        fn n_dof(&self) -> usize {
            1
        }
        fn mass(&self) -> DMatrix<f64> {
            DMatrix::identity(1, 1)
        }
        fn damping(&self) -> DMatrix<f64> {
            DMatrix::zeros(1, 1)
        }
        fn nonlinear_force(&self, _t: f64, q: &[f64], qd: &[f64], g: &mut [f64]) {
            g[0] = q[0].powi(3) + q[0] * qd[0];
        }
        fn forcing(&self, _t: f64, f: &mut [f64]) {
            f[0] = 0.0;
        }
    }

    #[test]
    fn default_jacobian_is_finite_differences() {
        let (mut a, mut b) = ([0.0], [0.0]);
        Cubic.force_jacobian(0.0, &[2.0], &[3.0], &mut a, &mut b);
        assert!((a[0] - (12.0 + 3.0)).abs() < 1e-6);
        assert!((b[0] - 2.0).abs() < 1e-6);
    }

    #[test]
    fn defaults_are_neutral() {
        let mut c = Cubic;
        assert!(matches!(
            c.parameter("x"),
            Err(SystemError::UnknownParameter { .. })
        ));
        assert!(c.set_parameter("x", 1.0).is_err());
        assert!(c.set_base_frequency(2.0).is_ok());
        assert_eq!(c.time_table_len(), 0);
        assert_eq!(c.n_events(), 0);
        assert_eq!(c.stiffness(), DMatrix::zeros(1, 1));
        let (mut g1, mut g2) = ([0.0], [0.0]);
        c.nonlinear_force(0.3, &[1.5], &[0.5], &mut g1);
        c.nonlinear_force_tabulated(0.3, &[], &[1.5], &[0.5], &mut g2);
        assert_eq!(g1[0].to_bits(), g2[0].to_bits());
        assert_eq!(Cubic.event_direction(0), Direction::Both);
    }

    #[test]
    fn gap_edges_vanish_on_the_edges_and_directions_filter() {
        let mut e = [0.0; 2];
        gap_edges(1.0, 1.0, &mut e);
        assert!(e[0].abs() < 1e-15 && (e[1] - 2.0).abs() < 1e-15);
        gap_edges(-1.0, 1.0, &mut e);
        assert!((e[0] + 2.0).abs() < 1e-15 && e[1].abs() < 1e-15);
        assert!(Direction::Both.accepts(Direction::Rising));
        assert!(Direction::Rising.accepts(Direction::Rising));
        assert!(!Direction::Rising.accepts(Direction::Falling));
    }
}

/// The README's example, compiled and run as a doctest so that it cannot rot.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctest;
