//! Harmonic balance of Eq. (9) through the `hbm` engine, Eq. (13)–(17).
//!
//! All frequencies of the response are integer multiples of `ω̄_c` because `ω̄_e = Z₂ ω̄_c`
//! (Sect. 2.4), so one period `T = 2π/ω̄_c` carries every basis function. The basis is a set of
//! harmonic indices `k` of `ω̄_c`: the paper's sparse set (Eq. 13) or all `k ≤ K`.

use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

use super::model::{Model, Rattle};
use crate::Error;

/// Harmonic basis of the periodic response `q(τ)` (multiples of `ω̄_c`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum Basis {
    /// The paper's Eq. (13): `0, ω̄_c, 2ω̄_c` and `rω̄_e, rω̄_e ± ω̄_c, rω̄_e ± 2ω̄_c` for
    /// `r = 1..=R` (`R = 1` gives 15 unknowns).
    Sparse {
        /// Number of mesh harmonics `R` (≥ 1).
        r: usize,
    },
    /// Every harmonic `k ω̄_c`, `k = 0..=K` (`2K + 1` unknowns).
    Full {
        /// Highest harmonic index `K` (`R Z₂ + 2` covers the sparse set of the same `R`).
        max_harmonic: usize,
    },
}

impl Basis {
    /// The paper's basis, `R = 1` (15 unknowns).
    pub const PAPER: Basis = Basis::Sparse { r: 1 };

    /// The `hbm` basis for an NFG with `z2` teeth.
    pub fn to_hbm(&self, z2: u32) -> Result<hbm::Basis, Error> {
        let b = match *self {
            Basis::Sparse { r } => hbm::Basis::liu_multifrequency(r, z2 as usize),
            Basis::Full { max_harmonic } => hbm::Basis::full(max_harmonic),
        };
        b.map_err(Error::from)
    }
}

/// Settings of the harmonic-balance solve.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct HbmOptions {
    /// Harmonic basis.
    pub basis: Basis,
    /// AFT samples per period (Eq. 15, `M`); `None`: the smallest power of two ≥ 8 × the
    /// highest harmonic (the dead zone is not smooth, so more than the engine's default).
    pub samples: Option<usize>,
    /// Convergence: `‖s‖₂ ≤ tol × (B₀ + |B₁| + |B₂| + B₃ + b̄)` (relative to the forcing scale).
    pub tol: f64,
    /// Maximum Newton iterations.
    pub max_iter: u64,
}

impl Default for HbmOptions {
    fn default() -> Self {
        Self {
            basis: Basis::PAPER,
            samples: None,
            tol: 1e-9,
            max_iter: 60,
        }
    }
}

impl HbmOptions {
    /// Full basis `K = R Z₂ + 2` covering the paper's basis of the same `R`.
    pub fn full(model: &Model, r: usize) -> Self {
        Self {
            basis: Basis::Full {
                max_harmonic: r * model.z2 as usize + 2,
            },
            ..Self::default()
        }
    }
}

/// A harmonic-balance solution of Eq. (9) with its rattle metrics.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HbmResponse {
    /// The engine's periodic solution (coefficients, convergence, residual, iterations).
    pub solution: hbm::PeriodicSolution,
    /// Rattle state and ppv of `q` sampled at `max(4096, 32 k_max)` points.
    pub rattle: Rattle,
}

impl HbmResponse {
    /// Whether the engine met the tolerance.
    pub fn converged(&self) -> bool {
        self.solution.converged
    }

    /// `q(τ)`.
    pub fn eval(&self, tau: f64) -> f64 {
        self.solution.state_at(tau).0[0]
    }

    /// Amplitude of harmonic `k` of `ω̄_c` (0 if not in the basis).
    pub fn amplitude(&self, k: usize) -> f64 {
        self.solution
            .harmonic_amplitudes(0)
            .iter()
            .find(|a| a.harmonic == k)
            .map_or(0.0, |a| a.amplitude)
    }
}

/// Eq. (9) as the shared system description, solved by both engines (`hbm` directly, `timestep`
/// through [`timestep::Mechanical`]): `M = 1`, `C = 2ζ`, `g = F(τ) f(q, b̄(τ))`, the forcing
/// of Eq. (9), and the gap edges `q = ±b̄(τ)` as events.
///
/// Every time function here (forcing, time table, force, Jacobian, events) comes from one
/// evaluation, `Model::time_functions_short` (three short `sin_cos`), so the separate and the
/// shared forms agree bit for bit; they equal the inherent [`Model::stiffness`],
/// [`Model::backlash_at`] and [`Model::forcing`] to rounding (tested). The harmonic-balance
/// grid of the engine's own frequency is tabulated from one quarter circle instead
/// (`tabulate_grid`).
impl system::SecondOrderSystem for Model {
    fn n_dof(&self) -> usize {
        1
    }
    fn mass(&self) -> DMatrix<f64> {
        DMatrix::identity(1, 1)
    }
    fn damping(&self) -> DMatrix<f64> {
        DMatrix::from_element(1, 1, 2.0 * self.zeta)
    }
    fn nonlinear_force(&self, t: f64, q: &[f64], _qd: &[f64], g: &mut [f64]) {
        let [stiffness, backlash, _] = self.time_functions_short(t);
        g[0] = Model::restoring_of(stiffness, backlash, q[0]);
    }
    fn forcing(&self, t: f64, f: &mut [f64]) {
        f[0] = self.time_functions_short(t)[2];
    }
    fn force_jacobian(&self, t: f64, q: &[f64], _qd: &[f64], dq: &mut [f64], dv: &mut [f64]) {
        let [stiffness, backlash, _] = self.time_functions_short(t);
        dq[0] = Model::restoring_slope_of(stiffness, backlash, q[0]);
        dv[0] = 0.0;
    }
    fn n_events(&self) -> usize {
        2
    }
    fn events(&self, t: f64, q: &[f64], _qd: &[f64], e: &mut [f64]) {
        system::gap_edges(q[0], self.time_functions_short(t)[1], e);
    }
    /// The gap edges from the row's `b̄(τ)` (the same value as `events` reads).
    fn events_tabulated(&self, _t: f64, row: &[f64], q: &[f64], _qd: &[f64], e: &mut [f64]) {
        system::gap_edges(q[0], row[1], e);
    }
    /// Row `[F(τ), b̄(τ)]`: the time-varying stiffness and half backlash of Eq. (9).
    fn time_table_len(&self) -> usize {
        2
    }
    fn fill_time_table(&self, t: f64, row: &mut [f64]) {
        let [stiffness, backlash, _] = self.time_functions_short(t);
        row[0] = stiffness;
        row[1] = backlash;
    }
    /// `f_r(τ)` and `[F(τ), b̄(τ)]` from one evaluation: the values of `forcing` and
    /// `fill_time_table` bit for bit.
    fn fill_time_functions(&self, t: f64, f: &mut [f64], row: &mut [f64]) {
        let [stiffness, backlash, forcing] = self.time_functions_short(t);
        f[0] = forcing;
        row[0] = stiffness;
        row[1] = backlash;
    }
    /// On the engine's grid of `ω = ω̄_c` (every harmonic balance of this model) the time
    /// functions come from one quarter of the unit circle (`Model::tabulate_period`); any
    /// other grid is tabulated sample by sample.
    fn tabulate_grid(&self, omega: f64, n_grid: usize, forcing: &mut [f64], table: &mut [f64]) {
        if omega.to_bits() == self.omega_c.to_bits() // the grid of this very model
            && n_grid % 4 == 0
            && forcing.len() >= n_grid
            && table.len() >= 2 * n_grid
        {
            self.tabulate_period(n_grid, &mut forcing[..n_grid], &mut table[..2 * n_grid]);
        } else {
            system::tabulate_pointwise(self, omega, n_grid, forcing, table);
        }
    }
    fn nonlinear_force_tabulated(
        &self,
        _t: f64,
        row: &[f64],
        q: &[f64],
        _qd: &[f64],
        g: &mut [f64],
    ) {
        g[0] = Model::restoring_of(row[0], row[1], q[0]);
    }
    fn force_jacobian_tabulated(
        &self,
        _t: f64,
        row: &[f64],
        q: &[f64],
        _qd: &[f64],
        dq: &mut [f64],
        dv: &mut [f64],
    ) {
        dq[0] = Model::restoring_slope_of(row[0], row[1], q[0]);
        dv[0] = 0.0;
    }
    fn set_base_frequency(&mut self, omega: f64) -> Result<(), system::SystemError> {
        *self = self
            .with_omega_c(omega)
            .map_err(|_| system::SystemError::invalid("liu2021.omega_c", "> 0", omega))?;
        Ok(())
    }
}

/// Rattle metrics of an engine solution.
pub(super) fn rattle_of(model: &Model, sol: &hbm::PeriodicSolution) -> Rattle {
    let n = (32 * sol.basis.max_harmonic()).max(4096);
    // the displacement only, by one inverse FFT; the times as in `time_series`
    let q = sol.displacement_samples(0, n).unwrap_or_default();
    let period = sol.period();
    model.rattle_of_period(period, &q)
}

/// The engine problem of `model` on `basis` (AFT grid per [`HbmOptions::samples`]).
pub(super) fn problem_of(
    model: &Model,
    basis: hbm::Basis,
    samples: Option<usize>,
) -> Result<hbm::HbmProblem<Model>, Error> {
    let kmax = basis.max_harmonic().max(1);
    let n_grid = samples.unwrap_or_else(|| (8 * kmax).next_power_of_two());
    hbm::HbmProblem::with_grid_size(*model, basis, model.omega_c, n_grid).map_err(Error::from)
}

/// Residual scale of the convergence test: `B₀ + |B₁| + |B₂| + B₃ + b̄`.
pub(super) fn residual_scale(model: &Model) -> f64 {
    (model.b0.abs() + model.b1.abs() + model.b2.abs() + model.b3.abs() + model.backlash)
        .max(f64::MIN_POSITIVE)
}

fn solve_once(
    model: &Model,
    basis: hbm::Basis,
    samples: Option<usize>,
    z0: Option<Vec<f64>>,
    options: &HbmOptions,
) -> Result<hbm::PeriodicSolution, Error> {
    let mut problem = problem_of(model, basis, samples)?;
    solve_on(&mut problem, model, z0, options)
}

/// Newton on a built problem of `model` from `z0` (default: the quasi-static contact position).
fn solve_on(
    problem: &mut hbm::HbmProblem<Model>,
    model: &Model,
    z0: Option<Vec<f64>>,
    options: &HbmOptions,
) -> Result<hbm::PeriodicSolution, Error> {
    let z0 = z0.unwrap_or_else(|| {
        let mut z = problem.zero_guess();
        z[0] = -model.backlash - model.b0;
        z
    });
    let so = hbm::SolverOptions {
        method: hbm::Method::Newton,
        tolerance: options.tol * residual_scale(model),
        max_iters: options.max_iter,
    };
    problem.solve(&z0, &so).map_err(Error::from)
}

/// Harmonic coefficients of one recorded period of a time response, in the layout of `basis`
/// (trapezoidal projection over the first whole period of the samples): a start value that
/// puts harmonic balance on the branch the time integration settled on.
pub fn coefficients_from_time_response(
    model: &Model,
    response: &super::integrate::TimeResponse,
    basis: &Basis,
) -> Result<Vec<f64>, Error> {
    let b = basis.to_hbm(model.z2)?;
    let t0 = *response
        .tau
        .first()
        .ok_or_else(|| Error::Solver("liu2021: empty time response".into()))?;
    let period = model.period();
    let n = response
        .tau
        .iter()
        .take_while(|&&t| t < t0 + period - 1e-9)
        .count();
    if n < 2 * b.max_harmonic() + 1 {
        return Err(Error::Solver(format!(
            "liu2021: {n} samples per period cannot resolve harmonic {}",
            b.max_harmonic()
        )));
    }
    let q = response
        .q
        .get(..n)
        .ok_or_else(|| Error::Solver("liu2021: fewer displacements than times".into()))?;
    timestep::fourier_projection_at(&response.tau[..n], q, model.omega_c, b.harmonics())
        .map_err(Error::from)
}

/// Where the harmonic-balance Newton iteration of [`solve_hbm_with`] starts.
///
/// Several periodic responses coexist near the onset of bilateral rattle; Newton converges to
/// the one nearest its start, so the start chooses the branch.
#[derive(Debug, Clone, Copy)]
#[non_exhaustive]
pub enum HbmStart<'a> {
    /// Quasi-static contact position `q = −b̄ − B₀` (first Newton step: the linear,
    /// always-in-contact solution); a full basis starts from the converged paper-basis
    /// solution. Finds the no-rattle/unilateral branch.
    Cold,
    /// Warm start: the harmonics of one recorded period of a time integration
    /// ([`coefficients_from_time_response`]), i.e. the branch the time integration settled on.
    FromTimeResponse(&'a super::integrate::TimeResponse),
    /// A previous solution (e.g. the neighbouring point of a sweep: sequential continuation),
    /// embedded into the requested basis.
    Given(&'a HbmResponse),
}

/// [`solve_hbm`] started from the harmonics of a time response
/// ([`HbmStart::FromTimeResponse`]); use it on multivalued (rattling) branches.
pub fn solve_hbm_from_time_response(
    model: &Model,
    options: &HbmOptions,
    response: &super::integrate::TimeResponse,
) -> Result<HbmResponse, Error> {
    solve_hbm_with(model, options, HbmStart::FromTimeResponse(response))
}

/// Solve Eq. (9) by harmonic balance (Eq. 13–17) with the `hbm` engine (AFT, Newton with the
/// exact AFT Jacobian and a line search instead of the paper's Broyden update).
///
/// `guess` (e.g. the previous point of a sweep) is embedded into the requested basis. Without
/// it the solve starts from the quasi-static contact position `q = −b̄ − B₀` (whose first
/// Newton step is the linear, always-in-contact solution); a full basis is then started from
/// the converged sparse (`R = 1`) solution, which is much more robust than a cold start.
/// Same as [`solve_hbm_with`] with [`HbmStart::Given`] or [`HbmStart::Cold`].
///
/// Non-convergence is reported in [`HbmResponse::converged`], not as an error.
pub fn solve_hbm(
    model: &Model,
    options: &HbmOptions,
    guess: Option<&HbmResponse>,
) -> Result<HbmResponse, Error> {
    solve_hbm_with(
        model,
        options,
        guess.map_or(HbmStart::Cold, HbmStart::Given),
    )
}

/// Solve Eq. (9) by harmonic balance from the chosen [`HbmStart`].
///
/// Non-convergence is reported in [`HbmResponse::converged`], not as an error.
pub fn solve_hbm_with(
    model: &Model,
    options: &HbmOptions,
    start: HbmStart<'_>,
) -> Result<HbmResponse, Error> {
    if options.tol.is_nan() || options.tol <= 0.0 {
        return Err(Error::invalid("liu2021.hbm.tol", "> 0", options.tol));
    }
    let basis = options.basis.to_hbm(model.z2)?;
    let z0 = match (start, options.basis) {
        (HbmStart::Given(g), _) => Some(g.solution.embed(&basis)),
        (HbmStart::FromTimeResponse(r), _) => {
            Some(coefficients_from_time_response(model, r, &options.basis)?)
        }
        (HbmStart::Cold, Basis::Full { .. }) => {
            let sparse = HbmOptions {
                basis: Basis::PAPER,
                samples: None,
                ..*options
            };
            let s = solve_once(model, Basis::PAPER.to_hbm(model.z2)?, None, None, &sparse)?;
            s.converged.then(|| s.embed(&basis))
        }
        (HbmStart::Cold, _) => None,
    };
    let solution = solve_once(model, basis, options.samples, z0, options)?;
    let rattle = rattle_of(model, &solution);
    Ok(HbmResponse { solution, rattle })
}

/// A Liu harmonic-balance problem prepared once and solved at new parameter values: the sweep
/// form of [`solve_hbm_with`].
///
/// What does not depend on the speed or the load is kept between solves: the basis, the AFT
/// grid, the FFT plans (complex and real-to-complex) and every work buffer of the engine's
/// problem; each [`PreparedHbm::solve`] re-reads only the model (its matrices and the time
/// tables of Eq. (9) on the grid, [`hbm::HbmProblem::set_system`]). A model with another `Z₂`
/// (another basis) rebuilds the problem. The results are those of [`solve_hbm_with`] with the
/// same options, bit for bit (tests).
///
/// ```
/// use geardyn_models::liu2021::{self, HbmOptions, HbmStart, PreparedHbm};
/// let mut p = liu2021::table1();
/// let mut hbm = PreparedHbm::new(&p.model()?, &HbmOptions::default())?;
/// for omega1 in [100.0, 110.0, 120.0] {
///     p.omega1 = omega1;
///     let r = hbm.solve(&p.model()?, HbmStart::Cold)?;
///     assert!(r.converged());
/// }
/// # Ok::<(), geardyn_models::Error>(())
/// ```
pub struct PreparedHbm {
    options: HbmOptions,
    basis: hbm::Basis,
    z2: u32,
    problem: hbm::HbmProblem<Model>,
    /// The paper-basis problem of a cold start on a full basis (built on first use).
    sparse: Option<hbm::HbmProblem<Model>>,
}

impl PreparedHbm {
    /// Prepare the problem of `model` with `options` (validated as by [`solve_hbm_with`]).
    ///
    /// # Errors
    /// `options.tol` not > 0; an invalid basis or grid for `model`.
    pub fn new(model: &Model, options: &HbmOptions) -> Result<Self, Error> {
        if options.tol.is_nan() || options.tol <= 0.0 {
            return Err(Error::invalid("liu2021.hbm.tol", "> 0", options.tol));
        }
        let basis = options.basis.to_hbm(model.z2)?;
        let problem = problem_of(model, basis.clone(), options.samples)?;
        Ok(Self {
            options: *options,
            basis,
            z2: model.z2,
            problem,
            sparse: None,
        })
    }

    /// The options every solve uses.
    pub fn options(&self) -> &HbmOptions {
        &self.options
    }

    /// Solve Eq. (9) of `model` from `start`, as [`solve_hbm_with`] with this object's options.
    ///
    /// Non-convergence is reported in [`HbmResponse::converged`], not as an error.
    ///
    /// # Errors
    /// As [`solve_hbm_with`].
    pub fn solve(&mut self, model: &Model, start: HbmStart<'_>) -> Result<HbmResponse, Error> {
        if model.z2 != self.z2 {
            *self = Self::new(model, &self.options)?;
        }
        let options = self.options;
        let z0 = match (start, options.basis) {
            (HbmStart::Given(g), _) => Some(g.solution.embed(&self.basis)),
            (HbmStart::FromTimeResponse(r), _) => {
                Some(coefficients_from_time_response(model, r, &options.basis)?)
            }
            (HbmStart::Cold, Basis::Full { .. }) => {
                let sparse_options = HbmOptions {
                    basis: Basis::PAPER,
                    samples: None,
                    ..options
                };
                let sparse = match &mut self.sparse {
                    Some(p) => {
                        set_model(p, model)?;
                        p
                    }
                    None => {
                        self.sparse
                            .insert(problem_of(model, Basis::PAPER.to_hbm(model.z2)?, None)?)
                    }
                };
                let s = solve_on(sparse, model, None, &sparse_options)?;
                s.converged.then(|| s.embed(&self.basis))
            }
            (HbmStart::Cold, _) => None,
        };
        set_model(&mut self.problem, model)?;
        let solution = solve_on(&mut self.problem, model, z0, &options)?;
        let rattle = rattle_of(model, &solution);
        Ok(HbmResponse { solution, rattle })
    }
}

thread_local! {
    /// The prepared problem of this thread ([`PreparedHbm::per_thread`]).
    static PER_THREAD: std::cell::RefCell<Option<PreparedHbm>> =
        const { std::cell::RefCell::new(None) };
}

impl PreparedHbm {
    /// This thread's prepared problem for `options` (built on first use, or when the options
    /// differ from those it was built with), lent until the returned guard is dropped: the
    /// per-worker form of [`PreparedHbm::new`] for parallel sweeps (`timestep::sweep`), whose
    /// points each solve on the problem their worker thread prepared for an earlier point.
    ///
    /// The results do not depend on which thread solved which point, or on what that thread
    /// solved before: a prepared solve equals a fresh one ([`solve_hbm_with`]) bit for bit, so
    /// a sweep gives the same results for any thread count (tests). A nested call on the same
    /// thread while a guard is alive gets a problem of its own. The problem stays allocated
    /// with the thread (its grid buffers and FFT plans, ~100 kB at the paper basis).
    ///
    /// # Errors
    /// As [`PreparedHbm::new`].
    pub fn per_thread(model: &Model, options: &HbmOptions) -> Result<PerThreadHbm, Error> {
        let cached = PER_THREAD.with(|c| c.borrow_mut().take());
        let hbm = match cached {
            Some(h) if h.options == *options => h,
            _ => Self::new(model, options)?,
        };
        Ok(PerThreadHbm(Some(hbm)))
    }
}

/// A thread's prepared problem on loan from [`PreparedHbm::per_thread`] (dereferences to
/// [`PreparedHbm`]); returned to the thread when dropped.
pub struct PerThreadHbm(Option<PreparedHbm>);

impl std::ops::Deref for PerThreadHbm {
    type Target = PreparedHbm;
    fn deref(&self) -> &PreparedHbm {
        self.0.as_ref().expect("present until dropped")
    }
}

impl std::ops::DerefMut for PerThreadHbm {
    fn deref_mut(&mut self) -> &mut PreparedHbm {
        self.0.as_mut().expect("present until dropped")
    }
}

impl Drop for PerThreadHbm {
    fn drop(&mut self) {
        if let Some(h) = self.0.take() {
            // `try_with`: nothing to return to while the thread itself is being torn down
            let _ = PER_THREAD.try_with(|c| *c.borrow_mut() = Some(h));
        }
    }
}

impl std::fmt::Debug for PerThreadHbm {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_tuple("PerThreadHbm").field(&self.0).finish()
    }
}

impl std::fmt::Debug for PreparedHbm {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PreparedHbm")
            .field("options", &self.options)
            .field("z2", &self.z2)
            .field("unknowns", &self.problem.n_unknowns())
            .field("grid", &self.problem.grid_size())
            .finish_non_exhaustive()
    }
}

/// Put `model` into a prepared problem (nothing to do when it is already there).
fn set_model(problem: &mut hbm::HbmProblem<Model>, model: &Model) -> Result<(), Error> {
    if problem.system() != model || problem.omega().to_bits() != model.omega_c.to_bits() {
        problem
            .set_system(*model, model.omega_c)
            .map_err(Error::from)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::params::table1;
    use super::*;

    #[test]
    fn prepared_solves_equal_fresh_ones_bit_for_bit() {
        let mut p = table1();
        p.readings.base_radius = super::super::params::BaseRadius::Mean;
        let first = p.model().unwrap();
        for options in [HbmOptions::default(), HbmOptions::full(&first, 1)] {
            let mut hbm = PreparedHbm::new(&first, &options).unwrap();
            let mut previous: Option<HbmResponse> = None;
            // speeds up and down, and a load change (B₀) at the same speed
            for (omega1, load) in [(120.0, 1.0), (160.0, 1.0), (140.0, 1.0), (140.0, 1.7)] {
                p.omega1 = omega1;
                let mut m = p.model().unwrap();
                m.b0 *= load;
                let given = previous.take();
                let mut last = None;
                for start in [
                    HbmStart::Cold,
                    given.as_ref().map_or(HbmStart::Cold, HbmStart::Given),
                ] {
                    let fresh = solve_hbm_with(&m, &options, start).unwrap();
                    let prepared = hbm.solve(&m, start).unwrap();
                    assert_eq!(
                        serde_json::to_string(&fresh).unwrap(),
                        serde_json::to_string(&prepared).unwrap(),
                        "omega1 = {omega1}, load ×{load}"
                    );
                    assert!(fresh.converged());
                    last = Some(prepared);
                }
                previous = last;
            }
        }
        let bad = HbmOptions {
            tol: 0.0,
            ..HbmOptions::default()
        };
        assert!(PreparedHbm::new(&first, &bad).is_err());
    }

    /// A sweep on per-thread prepared problems gives the fresh solves' results bit for bit,
    /// on one thread and on two (whatever each worker solved before).
    #[test]
    fn per_thread_sweep_equals_fresh_solves_for_any_thread_count() {
        let mut p = table1();
        p.readings.base_radius = super::super::params::BaseRadius::Mean;
        let options = HbmOptions::default();
        let models: Vec<Model> = [150.0, 175.0, 120.0, 160.0, 140.0, 165.0]
            .iter()
            .map(|&w| {
                p.omega1 = w;
                p.model().unwrap()
            })
            .collect();
        let json = |r: &HbmResponse| serde_json::to_string(r).unwrap();
        let fresh: Vec<String> = models
            .iter()
            .map(|m| json(&solve_hbm_with(m, &options, HbmStart::Cold).unwrap()))
            .collect();
        let solve = |m: &Model| {
            let mut hbm = PreparedHbm::per_thread(m, &options).unwrap();
            json(&hbm.solve(m, HbmStart::Cold).unwrap())
        };
        for threads in [1, 2] {
            let swept = timestep::sweep_with_threads(threads, &models, solve, None).unwrap();
            assert_eq!(swept, fresh, "{threads} thread(s)");
        }
        // a nested loan and other options on the same thread
        let m = &models[0];
        let mut outer = PreparedHbm::per_thread(m, &options).unwrap();
        let full = HbmOptions::full(m, 1);
        let mut inner = PreparedHbm::per_thread(m, &full).unwrap();
        assert_eq!(inner.options(), &full);
        assert_eq!(
            json(&inner.solve(m, HbmStart::Cold).unwrap()),
            json(&solve_hbm_with(m, &full, HbmStart::Cold).unwrap())
        );
        assert_eq!(json(&outer.solve(m, HbmStart::Cold).unwrap()), fresh[0]);
    }

    #[test]
    fn paper_basis_has_15_unknowns() {
        let m = table1().model().unwrap();
        let b = Basis::PAPER.to_hbm(m.z2).unwrap();
        assert_eq!(b.harmonics(), &[1, 2, 61, 62, 63, 64, 65]);
        assert_eq!(b.n_coefficients(), 15);
    }

    #[test]
    fn no_rattle_point_converges_on_paper_basis() {
        let mut p = table1();
        p.omega1 = 120.0;
        p.readings.base_radius = super::super::params::BaseRadius::Mean;
        let m = p.model().unwrap();
        let s = solve_hbm(&m, &HbmOptions::default(), None).unwrap();
        assert!(s.converged(), "{:?}", s.solution.termination);
        assert_eq!(s.rattle.state.rsv(), 0);
        let t = 123.4;
        let g = m.restoring(t, s.eval(t));
        assert!(g < 0.0, "in contact on the drive flank");
    }

    #[test]
    fn tabulated_force_equals_direct() {
        use hbm::SecondOrderSystem;
        for base_radius in [
            super::super::params::BaseRadius::TimeVarying,
            super::super::params::BaseRadius::Mean,
        ] {
            let mut p = table1();
            p.readings.base_radius = base_radius;
            let m = p.model().unwrap();
            let mut row = [0.0; 2];
            assert_eq!(m.time_table_len(), 2);
            for i in 0..50 {
                let t = 0.37 * f64::from(i);
                let q = [-2.0 + 0.09 * f64::from(i)];
                m.fill_time_table(t, &mut row);
                let (mut g, mut gt) = ([0.0], [0.0]);
                m.nonlinear_force(t, &q, &[0.0], &mut g);
                m.nonlinear_force_tabulated(t, &row, &q, &[0.0], &mut gt);
                assert_eq!(g[0].to_bits(), gt[0].to_bits());
                let (mut a, mut b, mut at, mut bt) = ([0.0], [0.0], [1.0], [1.0]);
                m.force_jacobian(t, &q, &[0.0], &mut a, &mut b);
                m.force_jacobian_tabulated(t, &row, &q, &[0.0], &mut at, &mut bt);
                assert_eq!(
                    (a[0].to_bits(), b[0].to_bits()),
                    (at[0].to_bits(), bt[0].to_bits())
                );
            }
        }
    }

    #[test]
    fn grid_tabulation_equals_pointwise_for_every_reading() {
        use hbm::SecondOrderSystem;
        for readings in super::super::params::Readings::all() {
            let mut p = table1();
            p.readings = readings;
            let m = p.model().unwrap();
            let n = 1024;
            let (mut f, mut t) = (vec![0.0; n], vec![0.0; 2 * n]);
            let (mut fp, mut tp) = (vec![0.0; n], vec![0.0; 2 * n]);
            m.tabulate_grid(m.omega_c, n, &mut f, &mut t);
            system::tabulate_pointwise(&m, m.omega_c, n, &mut fp, &mut tp);
            // round-off of angles up to 2π Z₂ (~1e-13) times the forcing scale
            let fs = residual_scale(&m);
            for i in 0..n {
                assert!((f[i] - fp[i]).abs() < 1e-12 * fs, "{i}: {} {}", f[i], fp[i]);
            }
            for i in 0..2 * n {
                assert!((t[i] - tp[i]).abs() < 1e-12, "{i}: {} {}", t[i], tp[i]);
            }
            // another grid (not a multiple of 4) goes sample by sample: equal bits
            let (mut f3, mut t3) = (vec![0.0; 998], vec![0.0; 2 * 998]);
            m.tabulate_grid(m.omega_c, 998, &mut f3, &mut t3);
            system::tabulate_pointwise(&m, m.omega_c, 998, &mut fp, &mut tp);
            assert_eq!(f3[..], fp[..998]);
        }
    }

    /// The shared time functions and the tabulated events are the separate direct evaluations
    /// bit for bit, in every reading (the orbit flow takes its forcing, time table and events
    /// from them: a difference would move every shooting result).
    #[test]
    fn shared_time_functions_and_tabulated_events_equal_the_direct_ones_for_every_reading() {
        use hbm::SecondOrderSystem;
        for readings in super::super::params::Readings::all() {
            let mut p = table1();
            p.readings = readings;
            p.phase_error = 0.4;
            let m = p.model().unwrap();
            for i in 0..400 {
                // up to τ ≈ 3·10⁵ (about 2·10⁴ periods), past the transient windows of the
                // studies
                let t = 1.9 * f64::from(i) * f64::from(i) - 3.0;
                let (mut f, mut row) = ([0.0], [0.0; 2]);
                let (mut fs, mut rows) = ([1.0], [1.0; 2]);
                m.fill_time_functions(t, &mut fs, &mut rows);
                SecondOrderSystem::forcing(&m, t, &mut f);
                m.fill_time_table(t, &mut row);
                assert_eq!(
                    fs[0].to_bits(),
                    f[0].to_bits(),
                    "{readings:?}: forcing at {t}"
                );
                assert_eq!(
                    rows.map(f64::to_bits),
                    row.map(f64::to_bits),
                    "{readings:?}: {t}"
                );
                let b = m.backlash;
                for q in [-1.5 * b, -b, 0.3 * b, b, 2.0 * b] {
                    let (mut e, mut et) = ([0.0; 2], [1.0; 2]);
                    m.events(t, &[q], &[0.0], &mut e);
                    m.events_tabulated(t, &row, &[q], &[0.0], &mut et);
                    assert_eq!(e.map(f64::to_bits), et.map(f64::to_bits), "{t} {q}");
                }
            }
        }
    }

    #[test]
    fn bad_tolerance_is_an_error() {
        let m = table1().model().unwrap();
        let o = HbmOptions {
            tol: f64::NAN,
            ..HbmOptions::default()
        };
        assert!(solve_hbm(&m, &o, None).is_err());
    }

    #[test]
    fn projection_of_a_sampled_solution_recovers_its_coefficients() {
        // A band-limited periodic signal sampled uniformly over one whole period (offset start)
        // is projected exactly by the rectangle rule: the warm start of an HBM solution's own
        // time series is that solution.
        let mut p = table1();
        p.omega1 = 120.0;
        p.readings.base_radius = super::super::params::BaseRadius::Mean;
        let m = p.model().unwrap();
        let s = solve_hbm(&m, &HbmOptions::default(), None).unwrap();
        let (t0, n) = (3.7, 512);
        let tau: Vec<f64> = (0..=n)
            .map(|i| t0 + m.period() * i as f64 / n as f64)
            .collect();
        let q: Vec<f64> = tau.iter().map(|&t| s.eval(t)).collect();
        let r = super::super::integrate::TimeResponse {
            v: vec![0.0; q.len()],
            rattle: m.rattle(tau.iter().copied().zip(q.iter().copied())),
            tau,
            q,
            contact_events: 0,
            rhs_evaluations: 0,
            stats: timestep::Stats::default(),
        };
        let z = coefficients_from_time_response(&m, &r, &Basis::PAPER).unwrap();
        let scale = s
            .solution
            .coefficients
            .iter()
            .fold(0.0f64, |a, c| a.max(c.abs()));
        for (a, b) in z.iter().zip(&s.solution.coefficients) {
            assert!((a - b).abs() < 1e-10 * scale, "{a} vs {b}");
        }
        let warm = solve_hbm_with(&m, &HbmOptions::default(), HbmStart::FromTimeResponse(&r));
        let warm = warm.unwrap();
        assert!(warm.converged());
        assert!(
            warm.solution.iterations <= 2,
            "{}",
            warm.solution.iterations
        );
        // too few samples for the basis is an error, not a panic
        let short = super::super::integrate::TimeResponse {
            tau: r.tau[..8].to_vec(),
            q: r.q[..8].to_vec(),
            ..r
        };
        assert!(coefficients_from_time_response(&m, &short, &Basis::PAPER).is_err());
    }
}
