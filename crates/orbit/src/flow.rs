//! The event-located flow of `M q'' + C q' + K q + g(t, q, q') = f(t)` with its variational
//! equations (adaptive Dormand–Prince 5(4) or DOP853, [`FlowMethod`]).
//!
//! * **Steps.** Each step carries the variational matrix `Φ` through the same stages (the exact
//!   derivative of the discrete step). The controller takes `h·clamp(0.9 err^(−1/(q+1)), …)`
//!   (DP5: `q = 4`, factors in `[0.2, 5]`; DOP853: `q = 7`, `[1/3, 6]`, Hairer's), and an
//!   accepted step right after a rejection does not grow.
//! * **Events.** A sign change of an event function between step ends (in a direction the
//!   system accepts) is located by Illinois regula falsi on re-computed steps `[t, t + θh]`, to
//!   [`FlowOptions::event_tol`]; the step then ends just past the surface, the state is reset
//!   ([`crate::ImpactLaw`]) and `Φ` is multiplied by the saltation matrix.
//! * **Steps across a switching surface.** A trial step across a surface carries the kink in
//!   its error estimate and is usually rejected; the shrink factor alone then takes several
//!   rejections to step off it. Optionally ([`FlowOptions::crossing_retry`], off by default)
//!   the retry ends instead just past the crossing estimated by linear interpolation of the
//!   event functions, `θ = g(t)/(g(t) − g(t+h))`, at `(θ + 10⁻³) h` — the rule of
//!   `geardyn-timestep`'s driver until it began to locate the crossing on the rejected
//!   step's dense output, which the flows do not have — if that shortens the step by 10 % or
//!   more, at most four times between located events. It is off because the steps that then
//!   end at the events are longer, and the variational equations lose accuracy across contact
//!   events with a time-dependent gap: the monodromy of the rattling spur pair against finite
//!   differences of the time stepping, 1.4e-4 without the retry, 1.1e-3 with it. On Liu's
//!   bilateral period-1 orbits (160–220 rad/s, one period) the no-growth rule alone removes
//!   40–44 % of the rejections (11 % of the attempted steps at 220 rad/s), the retry another
//!   22 % of them.

use crate::error::{OrbitError, Result, check};
use crate::impact::ImpactLaw;
use nalgebra::DMatrix;
use system::{Direction, SecondOrderSystem};

/// Settings of the integrator behind every flow, shooting and continuation.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FlowOptions {
    /// Relative tolerance of the pair's error estimate (state only).
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
    /// Largest step, as a fraction of the flow's duration (`(0, 1]`). Bounds the step so that an
    /// event function cannot leave and re-enter its sign within one step unseen.
    pub max_step_fraction: f64,
    /// Cap on accepted plus rejected steps of one flow.
    pub max_steps: usize,
    /// Cap on located events of one flow (guards against chattering).
    pub max_events: usize,
    /// Event times are located to this absolute tolerance (times `max(1, |t|)`).
    pub event_tol: f64,
    /// The Runge–Kutta pair (default Dormand–Prince 5(4)).
    #[cfg_attr(feature = "serde", serde(default))]
    pub method: FlowMethod,
    /// Retry a step rejected across a switching surface to just past the crossing estimated
    /// by linear interpolation of the event functions (module docs; default off: fewer
    /// rejections, but a less accurate variational matrix across contact events).
    #[cfg_attr(feature = "serde", serde(default))]
    pub crossing_retry: bool,
}

impl Default for FlowOptions {
    fn default() -> Self {
        Self {
            rtol: 1e-10,
            atol: 1e-12,
            max_step_fraction: 0.02,
            max_steps: 2_000_000,
            max_events: 100_000,
            event_tol: 1e-13,
            method: FlowMethod::DormandPrince54,
            crossing_retry: false,
        }
    }
}

impl FlowOptions {
    /// Checks every field.
    ///
    /// # Errors
    /// [`OrbitError::InvalidInput`] naming the field.
    pub fn validate(&self) -> Result<()> {
        check(
            self.rtol.is_finite() && self.rtol > 0.0 && self.rtol < 1.0,
            "FlowOptions::rtol",
            "in (0, 1)",
            self.rtol,
        )?;
        check(
            self.atol.is_finite() && self.atol > 0.0,
            "FlowOptions::atol",
            "> 0 and finite",
            self.atol,
        )?;
        check(
            self.max_step_fraction > 0.0 && self.max_step_fraction <= 1.0,
            "FlowOptions::max_step_fraction",
            "in (0, 1]",
            self.max_step_fraction,
        )?;
        check(
            self.max_steps >= 1,
            "FlowOptions::max_steps",
            ">= 1",
            self.max_steps as f64,
        )?;
        check(
            self.event_tol.is_finite() && self.event_tol > 0.0,
            "FlowOptions::event_tol",
            "> 0 and finite",
            self.event_tol,
        )
    }
}

/// One located event along a flow.
#[derive(Debug, Clone, PartialEq)]
pub struct EventRecord {
    /// Index of the event function.
    pub index: usize,
    /// Event time.
    pub time: f64,
    /// State on arrival (before any reset), `(q, q')`.
    pub state: Vec<f64>,
    /// Direction of the crossing.
    pub direction: Direction,
    /// True if an [`ImpactLaw`] reset the state here.
    pub impact: bool,
    /// `‖S − G‖_F`: how far the saltation matrix is from the reset Jacobian (`G = I` for a force
    /// law that only switches). Zero up to the event-location tolerance for a continuous force.
    pub saltation_jump: f64,
}

/// A smooth piece of a flow: one step of the flow's pair of length `h` from `(t, x)`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Piece {
    pub t: f64,
    pub x: Vec<f64>,
    pub h: f64,
    /// The state at `t + h` from this step (before any reset): kept so that the extrema need
    /// not step the piece again.
    pub x_end: Vec<f64>,
}

/// The result of a flow.
#[derive(Debug, Clone, PartialEq)]
pub struct Flow {
    /// Final state `(q, q')`.
    pub state: Vec<f64>,
    /// Final time.
    pub time: f64,
    /// `∂x(t_end)/∂x(t_0)` from the variational equations composed with the saltation matrices
    /// (if asked for).
    pub jacobian: Option<DMatrix<f64>>,
    /// Located events in time order.
    pub events: Vec<EventRecord>,
    /// Accepted steps.
    pub steps: usize,
    /// Rejected steps.
    pub rejected: usize,
    pub(crate) pieces: Vec<Piece>,
}

/// `(M⁻¹, C, K)` of a system.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Matrices {
    pub minv: DMatrix<f64>,
    pub c: DMatrix<f64>,
    pub k: DMatrix<f64>,
}

impl Matrices {
    pub fn of<S: SecondOrderSystem + ?Sized>(s: &S) -> Result<Self> {
        let n = s.n_dof();
        check(n >= 1, "n_dof", ">= 1", n as f64)?;
        let (m, c, k) = (s.mass(), s.damping(), s.stiffness());
        for (what, a) in [
            ("mass matrix", &m),
            ("damping matrix", &c),
            ("stiffness matrix", &k),
        ] {
            if a.nrows() != n || a.ncols() != n {
                return Err(OrbitError::DimensionMismatch {
                    what,
                    expected: n * n,
                    got: a.len(),
                });
            }
            if a.iter().any(|v| !v.is_finite()) {
                return Err(OrbitError::NonFinite { what, time: 0.0 });
            }
        }
        let minv = m
            .lu()
            .try_inverse()
            .filter(|x| x.iter().all(|v| v.is_finite()))
            .ok_or(OrbitError::Singular {
                what: "mass matrix",
            })?;
        Ok(Self { minv, c, k })
    }
}

// Dormand–Prince 5(4) tableau.
const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
const B: [f64; 7] = [
    35.0 / 384.0,
    0.0,
    500.0 / 1113.0,
    125.0 / 192.0,
    -2187.0 / 6784.0,
    11.0 / 84.0,
    0.0,
];
const BSTAR: [f64; 7] = [
    5179.0 / 57600.0,
    0.0,
    7571.0 / 16695.0,
    393.0 / 640.0,
    -92097.0 / 339200.0,
    187.0 / 2100.0,
    1.0 / 40.0,
];

/// Dormand–Prince 5(4): 7 stages (the last, at `t + h`, is the solution's; its weight is zero),
/// the embedded 4th-order error estimate, `h_new = h · clamp(0.9 err^(−1/5), 0.2, 5)`.
const DP54: Tableau = Tableau {
    c: &C,
    a: &[&A[0], &A[1], &A[2], &A[3], &A[4], &A[5], &A[6]],
    b: &B,
    derivative_needed: &[true, true, true, true, true, true, false],
    solution_is_last_stage: true,
    estimate: ErrorEstimate::Embedded(&BSTAR),
    exponent: 0.2,
    shrink: 0.2,
    grow: 5.0,
};

// DOP853 (Hairer): the 12 stages of a step; coefficients from `system::dop853`.
mod d8 {
    pub use system::dop853::*;
    pub const C: [f64; 12] = [0.0, C2, C3, C4, C5, C6, C7, C8, C9, C10, C11, 1.0];
    pub const B: [f64; 12] = [B1, 0.0, 0.0, 0.0, 0.0, B6, B7, B8, B9, B10, B11, B12];
    pub const E5: [f64; 12] = [
        ER1, 0.0, 0.0, 0.0, 0.0, ER6, ER7, ER8, ER9, ER10, ER11, ER12,
    ];
    pub const A2: [f64; 1] = [A21];
    pub const A3: [f64; 2] = [A31, A32];
    pub const A4: [f64; 3] = [A41, 0.0, A43];
    pub const A5: [f64; 4] = [A51, 0.0, A53, A54];
    pub const A6: [f64; 5] = [A61, 0.0, 0.0, A64, A65];
    pub const A7: [f64; 6] = [A71, 0.0, 0.0, A74, A75, A76];
    pub const A8: [f64; 7] = [A81, 0.0, 0.0, A84, A85, A86, A87];
    pub const A9: [f64; 8] = [A91, 0.0, 0.0, A94, A95, A96, A97, A98];
    pub const A10: [f64; 9] = [A101, 0.0, 0.0, A104, A105, A106, A107, A108, A109];
    pub const A11: [f64; 10] = [A111, 0.0, 0.0, A114, A115, A116, A117, A118, A119, A1110];
    pub const A12: [f64; 11] = [
        A121, 0.0, 0.0, A124, A125, A126, A127, A128, A129, A1210, A1211,
    ];
}

/// Hairer's DOP853: 12 stages, the 8th-order solution `x + h Σ bᵢkᵢ`, Hairer's error norm from
/// the 5th- and 3rd-order estimates `e5`, `e3`,
/// `err = |h| Σ(e5/sk)² / sqrt(n (Σ(e5/sk)² + 0.01 Σ(e3/sk)²))`, and his step factors
/// `h_new = h · clamp(0.9 err^(−1/8), 1/3, 6)`.
const DOP853: Tableau = Tableau {
    c: &d8::C,
    a: &[
        &[],
        &d8::A2,
        &d8::A3,
        &d8::A4,
        &d8::A5,
        &d8::A6,
        &d8::A7,
        &d8::A8,
        &d8::A9,
        &d8::A10,
        &d8::A11,
        &d8::A12,
    ],
    b: &d8::B,
    derivative_needed: &[true; 12],
    solution_is_last_stage: false,
    estimate: ErrorEstimate::Dop853 {
        e5: &d8::E5,
        bhh: [d8::BHH1, d8::BHH2, d8::BHH3],
    },
    exponent: 0.125,
    shrink: 1.0 / 3.0,
    grow: 6.0,
};

/// How a pair estimates its local error.
enum ErrorEstimate {
    /// `h Σ (bᵢ − b*ᵢ) kᵢ` against the embedded weights `b*`, in the RMS norm.
    Embedded(&'static [f64]),
    /// Hairer's DOP853 norm from the 5th-order estimate `Σ e5ᵢ kᵢ` and the 3rd-order one
    /// `Σ bᵢkᵢ − bhh₁k₁ − bhh₂k₉ − bhh₃k₁₂`.
    Dop853 { e5: &'static [f64], bhh: [f64; 3] },
}

/// An explicit Runge–Kutta pair of the flows.
struct Tableau {
    c: &'static [f64],
    /// Row `s` holds `a[s][j]`, `j < s`.
    a: &'static [&'static [f64]],
    b: &'static [f64],
    /// Stages whose slope enters the solution or a later stage (their variational slope is
    /// carried).
    derivative_needed: &'static [bool],
    /// The last stage's point is the solution (DP5's FSAL row `a[6] = b`).
    solution_is_last_stage: bool,
    estimate: ErrorEstimate,
    /// `1/(q + 1)` of the controller, `q` the order of the error estimate.
    exponent: f64,
    /// Least factor of a rejected step.
    shrink: f64,
    /// Largest factor of an accepted step.
    grow: f64,
}

/// The Runge–Kutta pair behind [`FlowOptions`].
///
/// Dormand–Prince 5(4) is the default: on the rattling gear the step is limited by the
/// absolute tolerance on the small velocity and by the events, hardly by `rtol` (DP5 takes 6546
/// steps a period at 100 rad/s at rtol 1e-10, 6189 at 1e-8), and in rattle DOP853's 12 stages
/// (each with its variational slope) and its rejections at the events cost more than its fewer
/// steps save. CPU time of one period of Liu's period-1 orbit with the variational equations at
/// the default tolerances, DOP853 over DP5: 0.77 at 100 rad/s (no contact loss), 0.78 at 140
/// (unilateral, 36 events), 0.97 at 160, 1.42 at 180 and 1.41 at 220 rad/s (bilateral, 244 and
/// 252 events; `docs/performance.md`, "Shooting flows").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum FlowMethod {
    /// Dormand–Prince 5(4): 7 stages per step, 6 of them with a variational slope.
    #[default]
    DormandPrince54,
    /// Hairer's DOP853 (order 8, error estimators of orders 5 and 3): 12 stages per step, each
    /// with a variational slope.
    Dop853,
}

impl FlowMethod {
    fn tableau(self) -> &'static Tableau {
        match self {
            FlowMethod::DormandPrince54 => &DP54,
            FlowMethod::Dop853 => &DOP853,
        }
    }
}

/// The vector field, its Jacobian and the event functions of one system.
///
/// The time-only parts are evaluated once per sample time and reused while `t` is the same
/// (bit for bit): the forcing `f(t)` and the system's time table
/// ([`SecondOrderSystem::fill_time_table`], e.g. Liu's `[F(τ), b̄(τ)]`), from which the force
/// and its Jacobian are taken ([`SecondOrderSystem::nonlinear_force_tabulated`], which the
/// trait requires to equal the direct evaluation). A Runge–Kutta stage evaluates the field and
/// its Jacobian at the same `t`, Dormand–Prince's last two stages share `t + h`, and the first
/// stage of a step is the last of the previous one: a step with its variational equation
/// evaluates the time functions at 5 new times instead of 13 (table) and 7 (forcing). At a
/// new time the forcing and the row come from one
/// [`SecondOrderSystem::fill_time_functions`] (Liu's model takes each `sin`/`cos` of `τ` once
/// there), and the events read the row ([`SecondOrderSystem::events_tabulated`]; a step's end
/// is its last stage time, so the row is kept). This drops repeated `sin`/`cos` without
/// changing a bit: the same functions at the same arguments.
pub(crate) struct Field<'a, S: ?Sized> {
    pub sys: &'a S,
    pub mats: &'a Matrices,
    pub impacts: Option<&'a dyn ImpactLaw>,
    n: usize,
    g: Vec<f64>,
    /// `f(t)` at `f_at` (the bits of `t`; `None`: not yet evaluated).
    f: Vec<f64>,
    f_at: Option<u64>,
    /// The time table at `row_at` (empty when the system has none).
    row: Vec<f64>,
    row_at: Option<u64>,
    jq: Vec<f64>,
    jv: Vec<f64>,
    e: Vec<f64>,
}

impl<'a, S: SecondOrderSystem + ?Sized> Field<'a, S> {
    pub fn new(sys: &'a S, mats: &'a Matrices, impacts: Option<&'a dyn ImpactLaw>) -> Self {
        let n = sys.n_dof();
        Self {
            sys,
            mats,
            impacts,
            n,
            g: vec![0.0; n],
            f: vec![0.0; n],
            f_at: None,
            row: vec![0.0; sys.time_table_len()],
            row_at: None,
            jq: vec![0.0; n * n],
            jv: vec![0.0; n * n],
            e: vec![0.0; sys.n_events()],
        }
    }

    pub fn n_events(&self) -> usize {
        self.e.len()
    }

    /// The time table at `t` (kept while `t` is unchanged).
    fn time_row(&mut self, t: f64) {
        if !self.row.is_empty() && self.row_at != Some(t.to_bits()) {
            self.sys.fill_time_table(t, &mut self.row);
            self.row_at = Some(t.to_bits());
        }
    }

    /// The forcing and the time table at `t` (each kept while `t` is unchanged; both new at
    /// once through [`SecondOrderSystem::fill_time_functions`], which shares their `sin`/`cos`).
    fn time_functions(&mut self, t: f64) {
        let at = Some(t.to_bits());
        let new_row = !self.row.is_empty() && self.row_at != at;
        let new_f = self.f_at != at;
        if new_row && new_f {
            self.sys.fill_time_functions(t, &mut self.f, &mut self.row);
            (self.f_at, self.row_at) = (at, at);
        } else if new_row {
            self.time_row(t);
        } else if new_f {
            self.sys.forcing(t, &mut self.f);
            self.f_at = at;
        }
    }

    /// `x' = (q', M⁻¹ (f − C q' − K q − g))`.
    pub fn rhs(&mut self, t: f64, x: &[f64], out: &mut [f64]) {
        let n = self.n;
        let (q, v) = x.split_at(n);
        self.time_functions(t);
        self.sys
            .nonlinear_force_tabulated(t, &self.row, q, v, &mut self.g);
        let m = self.mats;
        for i in 0..n {
            let mut r = self.f[i] - self.g[i];
            for j in 0..n {
                r -= m.c[(i, j)] * v[j] + m.k[(i, j)] * q[j];
            }
            self.g[i] = r; // reuse as the force balance
        }
        for i in 0..n {
            out[i] = v[i];
            let mut a = 0.0;
            for j in 0..n {
                a += m.minv[(i, j)] * self.g[j];
            }
            out[n + i] = a;
        }
    }

    /// `A = [[0, I], [−M⁻¹(K + ∂g/∂q), −M⁻¹(C + ∂g/∂q')]]`.
    pub fn jacobian(&mut self, t: f64, x: &[f64], a: &mut DMatrix<f64>) {
        let n = self.n;
        let (q, v) = x.split_at(n);
        self.time_row(t);
        self.sys
            .force_jacobian_tabulated(t, &self.row, q, v, &mut self.jq, &mut self.jv);
        let m = self.mats;
        a.fill(0.0);
        for i in 0..n {
            a[(i, n + i)] = 1.0;
            for j in 0..n {
                let (mut sk, mut sc) = (0.0, 0.0);
                for l in 0..n {
                    sk += m.minv[(i, l)] * (m.k[(l, j)] + self.jq[l * n + j]);
                    sc += m.minv[(i, l)] * (m.c[(l, j)] + self.jv[l * n + j]);
                }
                a[(n + i, j)] = -sk;
                a[(n + i, n + j)] = -sc;
            }
        }
    }

    /// The event functions at `(t, x)`; from the time table where the system has one (the
    /// events of a step's end come at the time of its last stage, whose row is kept).
    pub fn events(&mut self, t: f64, x: &[f64]) -> &[f64] {
        let n = self.n;
        if !self.e.is_empty() {
            if self.row.is_empty() {
                self.sys.events(t, &x[..n], &x[n..], &mut self.e);
            } else {
                self.time_row(t);
                self.sys
                    .events_tabulated(t, &self.row, &x[..n], &x[n..], &mut self.e);
            }
        }
        &self.e
    }

    pub fn event(&mut self, i: usize, t: f64, x: &[f64]) -> f64 {
        self.events(t, x)[i]
    }
}

/// One step of the flow's Runge–Kutta pair ([`FlowMethod`]); `phi` is carried along by the
/// same stages (the exact derivative of the discrete step for an exact Jacobian).
pub(crate) struct Stepper<'a, S: ?Sized> {
    pub field: Field<'a, S>,
    tab: &'static Tableau,
    k: Vec<Vec<f64>>,
    kp: Vec<DMatrix<f64>>,
    y: Vec<f64>,
    a: DMatrix<f64>,
    yp: DMatrix<f64>,
    pub rtol: f64,
    pub atol: f64,
}

impl<'a, S: SecondOrderSystem + ?Sized> Stepper<'a, S> {
    /// The stepper of `opts` (its pair resolved at its `rtol`).
    pub fn new(field: Field<'a, S>, opts: &FlowOptions) -> Self {
        let m = 2 * field.n;
        let tab = opts.method.tableau();
        let stages = tab.c.len();
        Self {
            field,
            tab,
            k: vec![vec![0.0; m]; stages],
            kp: vec![DMatrix::zeros(m, m); stages],
            y: vec![0.0; m],
            a: DMatrix::zeros(m, m),
            yp: DMatrix::zeros(m, m),
            rtol: opts.rtol,
            atol: opts.atol,
        }
    }

    /// Step `(t, x) → x_new`; returns the scaled error norm. `phi` is advanced in place.
    pub fn step(
        &mut self,
        t: f64,
        x: &[f64],
        h: f64,
        x_new: &mut [f64],
        phi: Option<&mut DMatrix<f64>>,
        guard: Option<(usize, f64)>,
    ) -> f64 {
        let m = x.len();
        let tab = self.tab;
        let stages = tab.c.len();
        for s in 0..stages {
            let row = tab.a[s];
            for i in 0..m {
                let mut acc = 0.0;
                for j in 0..s {
                    acc += row[j] * self.k[j][i];
                }
                self.y[i] = x[i] + h * acc;
            }
            let ts = t + tab.c[s] * h;
            let mut ks = std::mem::take(&mut self.k[s]);
            self.field.rhs(ts, &self.y, &mut ks);
            self.k[s] = ks;
            if tab.derivative_needed[s] {
                if let Some(p) = phi.as_deref() {
                    self.yp.copy_from(p);
                    for j in 0..s {
                        if row[j] != 0.0 {
                            let c = h * row[j];
                            self.yp.zip_apply(&self.kp[j], |d, k| *d += c * k);
                        }
                    }
                    let mut yj = std::mem::take(&mut self.y);
                    if let Some((ev, side)) = guard {
                        // one-sided Jacobian: a stage point that overshot the located switching
                        // surface is pulled back along the chord to the pre-event side
                        let mut d = 1e-9;
                        let y0 = yj.clone();
                        while self.field.event(ev, ts, &yj) * side <= 0.0 && d < 0.5 {
                            for i in 0..m {
                                yj[i] = y0[i] + d * (x[i] - y0[i]);
                            }
                            d *= 4.0;
                        }
                        self.field.jacobian(ts, &yj, &mut self.a);
                        yj.copy_from_slice(&y0);
                    } else {
                        self.field.jacobian(ts, &yj, &mut self.a);
                    }
                    self.y = yj;
                    system::numeric::product_into(&self.a, &self.yp, &mut self.kp[s]);
                }
            }
        }
        if tab.solution_is_last_stage {
            x_new.copy_from_slice(&self.y);
        } else {
            for i in 0..m {
                let mut acc = 0.0;
                for j in 0..stages {
                    acc += tab.b[j] * self.k[j][i];
                }
                // kept for DOP853's 3rd-order estimate (`self.y` is free after the last stage)
                self.y[i] = acc;
                x_new[i] = x[i] + h * acc;
            }
        }
        if let Some(p) = phi {
            for j in 0..stages {
                if tab.b[j] != 0.0 {
                    let c = h * tab.b[j];
                    p.zip_apply(&self.kp[j], |d, k| *d += c * k);
                }
            }
        }
        match tab.estimate {
            ErrorEstimate::Embedded(bstar) => {
                let mut err = 0.0;
                for i in 0..m {
                    let mut e = 0.0;
                    for j in 0..stages {
                        e += (tab.b[j] - bstar[j]) * self.k[j][i];
                    }
                    let sc = self.atol + self.rtol * x[i].abs().max(x_new[i].abs());
                    err += (h * e / sc).powi(2);
                }
                (err / m as f64).sqrt()
            }
            ErrorEstimate::Dop853 { e5, bhh } => {
                let (mut err5, mut err3) = (0.0, 0.0);
                let last = stages - 1;
                for i in 0..m {
                    // Σ bⱼkⱼ of the solution (above; a tableau with this estimate does not
                    // take its solution from the last stage)
                    let sb = self.y[i];
                    let mut s5 = 0.0;
                    for j in 0..stages {
                        s5 += e5[j] * self.k[j][i];
                    }
                    let sk = self.atol + self.rtol * x[i].abs().max(x_new[i].abs());
                    let e3 = sb
                        - bhh[0] * self.k[0][i]
                        - bhh[1] * self.k[8][i]
                        - bhh[2] * self.k[last][i];
                    err3 += (e3 / sk) * (e3 / sk);
                    err5 += (s5 / sk) * (s5 / sk);
                }
                let mut deno = err5 + 0.01 * err3;
                if deno <= 0.0 {
                    deno = 1.0;
                }
                h.abs() * err5 * (1.0 / (m.max(1) as f64 * deno)).sqrt()
            }
        }
    }

    /// State only, for event location and extrema.
    pub fn state_at(&mut self, t: f64, x: &[f64], h: f64) -> Vec<f64> {
        let mut out = vec![0.0; x.len()];
        if h != 0.0 {
            self.step(t, x, h, &mut out, None, None);
        } else {
            out.copy_from_slice(x);
        }
        out
    }

    /// The factor of the next step after an accepted step with error `err`:
    /// `min(0.9 err^(−1/(q+1)), grow)` (`err ≥ 1e-10`).
    fn accept_factor(&self, err: f64) -> f64 {
        (0.9 * err_pow(err.max(1e-10), self.tab.exponent)).min(self.tab.grow)
    }

    /// The factor of the retried step after a rejection: `max(0.9 err^(−1/(q+1)), shrink)`, and
    /// 0.25 for a non-finite error.
    fn reject_factor(&self, err: f64) -> f64 {
        if err.is_finite() {
            (0.9 * err_pow(err, self.tab.exponent)).max(self.tab.shrink)
        } else {
            0.25
        }
    }
}

/// `err^(−e)` of the step-size controller, without the C math library's `pow`
/// (`system::numeric::{log2_approx, exp2_approx}`: relative error below 1e-8, deterministic on
/// every platform).
#[inline]
fn err_pow(err: f64, e: f64) -> f64 {
    system::numeric::exp2_approx(-e * system::numeric::log2_approx(err))
}

/// How far past the linearly estimated crossing a retried step ends, as a fraction of the
/// rejected step. This was the time stepping's rule until `geardyn-timestep` began to locate
/// the crossing on the rejected step's dense output (its crate docs, "Steps across a switching
/// surface"); the flows have no dense output (they locate events by stepping again), and
/// their retry is off by default.
const CROSSING_MARGIN: f64 = 1e-3;

/// Retries capped at an estimated crossing between two located events: an estimate that keeps
/// falling short (a grazing approach) goes back to the controller's own shrink.
const MAX_CAPS: u32 = 4;

fn all_finite(x: &[f64]) -> bool {
    x.iter().all(|v| v.is_finite())
}

/// Integrates from `(t0, x0)` over `duration`, locating events, optionally with the
/// variational equations and a record of the smooth pieces.
pub(crate) fn integrate<S: SecondOrderSystem + ?Sized>(
    field: Field<'_, S>,
    opts: &FlowOptions,
    t0: f64,
    x0: &[f64],
    duration: f64,
    variational: bool,
    record: bool,
) -> Result<Flow> {
    let m = x0.len();
    check(t0.is_finite(), "t0", "finite", t0)?;
    check(
        duration.is_finite() && duration > 0.0,
        "duration",
        "> 0 and finite",
        duration,
    )?;
    if !all_finite(x0) {
        return Err(OrbitError::NonFinite {
            what: "initial state",
            time: t0,
        });
    }
    let mut st = Stepper::new(field, opts);
    let mut f0 = vec![0.0; m];
    st.field.rhs(t0, x0, &mut f0);
    if !all_finite(&f0) {
        return Err(OrbitError::NonFinite {
            what: "right-hand side",
            time: t0,
        });
    }
    let ne = st.field.n_events();
    let t_end = t0 + duration;
    let hmax = opts.max_step_fraction * duration;
    let mut t = t0;
    let mut x = x0.to_vec();
    let mut phi = variational.then(|| DMatrix::<f64>::identity(m, m));
    let mut e_now = st.field.events(t, &x).to_vec();
    if !all_finite(&e_now) {
        return Err(OrbitError::NonFinite {
            what: "event function",
            time: t,
        });
    }
    let mut side: Vec<f64> = e_now
        .iter()
        .map(|&e| if e >= 0.0 { 1.0 } else { -1.0 })
        .collect();
    // initial step from the scale of the state and its rate
    let mut h = {
        let xs = x.iter().fold(0.0_f64, |a, v| a.max(v.abs())) + opts.atol;
        let fs = f0.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
        let guess = if fs > 0.0 { 0.01 * xs / fs } else { hmax };
        guess.min(hmax).max(1e-6 * hmax)
    };
    let mut flow = Flow {
        state: vec![],
        time: t0,
        jacobian: None,
        events: vec![],
        steps: 0,
        rejected: 0,
        pieces: vec![],
    };
    let mut x_new = vec![0.0; m];
    let mut phi_new = phi.clone();
    let mut rejected_last = false;
    // retries capped at an estimated crossing since the last located event
    let mut caps = 0u32;
    let t_snap = 1e-13 * t_end.abs().max(duration);
    loop {
        let remaining = t_end - t;
        if remaining <= t_snap {
            break;
        }
        if flow.steps + flow.rejected >= opts.max_steps {
            return Err(OrbitError::TooManySteps {
                limit: opts.max_steps,
                time: t,
            });
        }
        if system::deadline::expired_at_step((flow.steps + flow.rejected) as u64) {
            return Err(OrbitError::TimeLimit { time: t });
        }
        let mut hh = h.min(hmax);
        let last = hh >= remaining;
        if last {
            hh = remaining;
        }
        if hh <= 8.0 * f64::EPSILON * t.abs().max(duration) {
            return Err(OrbitError::StepSizeUnderflow { time: t, step: hh });
        }
        if let (Some(p), Some(pn)) = (phi.as_ref(), phi_new.as_mut()) {
            pn.copy_from(p);
        }
        let err = st.step(t, &x, hh, &mut x_new, phi_new.as_mut(), None);
        if !err.is_finite() || !all_finite(&x_new) || err > 1.0 {
            flow.rejected += 1;
            h = hh * st.reject_factor(err);
            if opts.crossing_retry
                && ne > 0
                && caps < MAX_CAPS
                && err.is_finite()
                && all_finite(&x_new)
            {
                // a rejected step across a switching surface: retry to just past the crossing
                // estimated by linear interpolation of the event functions (module docs)
                let e_try = st.field.events(t + hh, &x_new).to_vec();
                let sys = st.field.sys;
                let accepts = |i: usize, dir| sys.event_direction(i).accepts(dir);
                if let Some(th) = system::earliest_crossing(&side, &e_now, &e_try, accepts) {
                    let cap = (th + CROSSING_MARGIN).min(1.0) * hh;
                    if cap <= 0.9 * hh {
                        h = cap;
                        caps += 1;
                    }
                }
            }
            rejected_last = true;
            continue;
        }
        // events at the end of the trial step
        let e_end = st.field.events(t + hh, &x_new).to_vec();
        if !all_finite(&e_end) {
            return Err(OrbitError::NonFinite {
                what: "event function",
                time: t + hh,
            });
        }
        let mut first: Option<(usize, f64, f64)> = None; // (index, θ_lo, θ_hi)
        for i in 0..ne {
            if e_end[i] * side[i] < 0.0 {
                let dir = if side[i] > 0.0 {
                    Direction::Falling
                } else {
                    Direction::Rising
                };
                if st.field.sys.event_direction(i).accepts(dir) {
                    let (lo, hi) = locate(&mut st, i, t, &x, hh, side[i], e_now[i], e_end[i], opts);
                    if first.is_none_or(|(_, _, h0)| hi < h0) {
                        first = Some((i, lo, hi));
                    }
                }
            }
        }
        match first {
            None => {
                if record {
                    flow.pieces.push(Piece {
                        t,
                        x: x.clone(),
                        h: hh,
                        x_end: x_new.clone(),
                    });
                }
                for i in 0..ne {
                    if e_end[i] * side[i] < 0.0 {
                        side[i] = -side[i];
                    }
                }
                t = if last { t_end } else { t + hh };
                std::mem::swap(&mut x, &mut x_new);
                std::mem::swap(&mut phi, &mut phi_new);
                e_now = e_end;
                flow.steps += 1;
                h = hh * st.accept_factor(err);
                if rejected_last {
                    h = h.min(hh);
                }
                rejected_last = false;
            }
            Some((i, lo, hi)) => {
                let dt = hi * hh;
                st.step(t, &x, dt, &mut x_new, phi.as_mut(), Some((i, side[i])));
                if record {
                    flow.pieces.push(Piece {
                        t,
                        x: x.clone(),
                        h: dt,
                        x_end: x_new.clone(),
                    });
                }
                let t_e = t + dt;
                let t_l = t + lo * hh;
                let x_l = st.state_at(t, &x, lo * hh);
                flow.steps += 1;
                let dir = if side[i] > 0.0 {
                    Direction::Falling
                } else {
                    Direction::Rising
                };
                let (x_plus, salt, jump, impact) =
                    event_map(&mut st.field, i, t_l, &x_l, t_e, &x_new, variational)?;
                if let (Some(p), Some(s)) = (phi.as_mut(), salt) {
                    *p = s * &*p;
                }
                flow.events.push(EventRecord {
                    index: i,
                    time: t_e,
                    state: x_new.clone(),
                    direction: dir,
                    impact,
                    saltation_jump: jump,
                });
                if flow.events.len() > opts.max_events {
                    return Err(OrbitError::TooManyEvents {
                        limit: opts.max_events,
                        time: t_e,
                    });
                }
                side[i] = -side[i];
                caps = 0;
                t = t_e;
                x = x_plus;
                e_now = st.field.events(t, &x).to_vec();
                for j in 0..ne {
                    if j != i && e_now[j] * side[j] < 0.0 {
                        side[j] = -side[j];
                    }
                }
                h = hh.max(dt);
            }
        }
    }
    flow.state = x;
    flow.time = t;
    flow.jacobian = phi;
    Ok(flow)
}

/// Illinois (modified regula falsi) on the fraction `θ` of the step where event `i` crosses;
/// returns the bracket `(θ_lo, θ_hi)`: `θ_lo` before, `θ_hi` after the crossing.
fn locate<S: SecondOrderSystem + ?Sized>(
    st: &mut Stepper<'_, S>,
    i: usize,
    t: f64,
    x: &[f64],
    h: f64,
    side: f64,
    e0: f64,
    e1: f64,
    opts: &FlowOptions,
) -> (f64, f64) {
    let (mut lo, mut hi, mut elo, mut ehi) = (0.0_f64, 1.0_f64, e0, e1);
    let tol = opts.event_tol * t.abs().max(1.0) / h.abs();
    let mut last = 0i8;
    for _ in 0..200 {
        if hi - lo <= tol {
            break;
        }
        let mut th = hi - ehi * (hi - lo) / (ehi - elo);
        if !(th > lo && th < hi) {
            th = 0.5 * (lo + hi);
        }
        let xt = st.state_at(t, x, th * h);
        let e = st.field.event(i, t + th * h, &xt);
        if !e.is_finite() {
            hi = th; // shrink from above; the flow is checked again by the caller's step
            continue;
        }
        if e * side >= 0.0 {
            // not yet strictly past: the post-event end of the bracket is strictly past the
            // surface, so the force law (and its Jacobian) there is the post-event one
            lo = th;
            elo = e;
            if last == -1 {
                ehi *= 0.5;
            }
            last = -1;
        } else {
            hi = th;
            ehi = e;
            if last == 1 {
                elo *= 0.5;
            }
            last = 1;
        }
    }
    (lo, hi)
}

/// `(x⁺, S, ‖S − G‖_F, impact)` of an event.
type EventMap = (Vec<f64>, Option<DMatrix<f64>>, f64, bool);

/// Reset and saltation matrix at a located event: returns `(x⁺, S, ‖S − G‖_F, impact)`.
fn event_map<S: SecondOrderSystem + ?Sized>(
    field: &mut Field<'_, S>,
    i: usize,
    t_l: f64,
    x_l: &[f64],
    t_e: f64,
    x_e: &[f64],
    variational: bool,
) -> Result<EventMap> {
    let m = x_e.len();
    let impact = field.impacts.is_some_and(|l| l.is_impact(i));
    let mut x_plus = x_e.to_vec();
    let mut g = DMatrix::<f64>::identity(m, m);
    if impact {
        if let Some(law) = field.impacts {
            law.reset(i, t_e, x_e, &mut x_plus);
            law.reset_jacobian(i, t_e, x_e, &mut g);
        }
        if !all_finite(&x_plus) || g.iter().any(|v| !v.is_finite()) {
            return Err(OrbitError::NonFinite {
                what: "impact reset",
                time: t_e,
            });
        }
    }
    if !variational {
        return Ok((x_plus, None, 0.0, impact));
    }
    let s = saltation(field, i, t_l, x_l, t_e, &x_plus, &g)?;
    let jump = (&s - &g).norm();
    Ok((x_plus, Some(s), jump, impact))
}

/// `S = G + (f⁺ − G f⁻) ∇hᵀ / (∇hᵀ f⁻ + ∂h/∂t)`, `f⁻` on the pre-event side `(t_l, x_l)`,
/// `f⁺` after the reset `(t_e, x⁺)`, `∇h` and `∂h/∂t` by central differences at the event.
pub(crate) fn saltation<S: SecondOrderSystem + ?Sized>(
    field: &mut Field<'_, S>,
    i: usize,
    t_l: f64,
    x_l: &[f64],
    t_e: f64,
    x_plus: &[f64],
    g: &DMatrix<f64>,
) -> Result<DMatrix<f64>> {
    let m = x_l.len();
    let mut fm = vec![0.0; m];
    let mut fp = vec![0.0; m];
    field.rhs(t_l, x_l, &mut fm);
    field.rhs(t_e, x_plus, &mut fp);
    let fm_v = nalgebra::DVector::from_column_slice(&fm);
    let num = nalgebra::DVector::from_column_slice(&fp) - g * &fm_v;
    if num.iter().all(|&v| v == 0.0) {
        return Ok(g.clone());
    }
    // ∇h and ∂h/∂t at the pre-event point (h is continuous across the event)
    let mut xp = x_l.to_vec();
    let mut grad = nalgebra::DVector::zeros(m);
    for j in 0..m {
        let d = 1e-7 * (1.0 + x_l[j].abs());
        xp[j] = x_l[j] + d;
        let a = field.event(i, t_l, &xp);
        xp[j] = x_l[j] - d;
        let b = field.event(i, t_l, &xp);
        xp[j] = x_l[j];
        grad[j] = (a - b) / (2.0 * d);
    }
    let d = 1e-7 * (1.0 + t_l.abs());
    let dht = (field.event(i, t_l + d, x_l) - field.event(i, t_l - d, x_l)) / (2.0 * d);
    let denom = grad.dot(&fm_v) + dht;
    if denom == 0.0 || !denom.is_finite() {
        return Err(OrbitError::TangentialEvent {
            index: i,
            time: t_e,
        });
    }
    let s = g + num * grad.transpose() / denom;
    if s.iter().any(|v| !v.is_finite()) {
        return Err(OrbitError::NonFinite {
            what: "saltation matrix",
            time: t_e,
        });
    }
    Ok(s)
}

/// Minimum and maximum of every event function along recorded pieces (the gap function's
/// extrema, for grazing detection): sampled at the piece ends, refined by golden-section search
/// inside the two pieces around each sampled extremum.
pub(crate) fn extrema<S: SecondOrderSystem + ?Sized>(
    field: Field<'_, S>,
    opts: &FlowOptions,
    pieces: &[Piece],
    end: (f64, &[f64]),
) -> Vec<[f64; 2]> {
    let mut st = Stepper::new(field, opts);
    let ne = st.field.n_events();
    let np = pieces.len();
    let mut out = vec![[f64::INFINITY, f64::NEG_INFINITY]; ne];
    if np == 0 || ne == 0 {
        return out;
    }
    // samples: piece starts, and each piece's end (events may sit between pieces)
    let mut starts = vec![vec![0.0; ne]; np];
    let mut ends = vec![vec![0.0; ne]; np];
    for (k, p) in pieces.iter().enumerate() {
        starts[k] = st.field.events(p.t, &p.x).to_vec();
        // the piece's own end state: the same bits as stepping the piece again
        let xe = if k + 1 == np { end.1 } else { &p.x_end };
        ends[k] = st.field.events(p.t + p.h, xe).to_vec();
    }
    for i in 0..ne {
        for (sgn, slot) in [(1.0, 1usize), (-1.0, 0usize)] {
            // largest of sgn·e over all samples
            let (mut best, mut kbest) = (f64::NEG_INFINITY, 0);
            for k in 0..np {
                let v = (sgn * starts[k][i]).max(sgn * ends[k][i]);
                if v > best {
                    best = v;
                    kbest = k;
                }
            }
            let lo = kbest.saturating_sub(1);
            let hi = (kbest + 1).min(np - 1);
            for k in lo..=hi {
                let p = &pieces[k];
                let v = golden(&mut st, i, sgn, p);
                if v > best {
                    best = v;
                }
            }
            out[i][slot] = sgn * best;
        }
    }
    out
}

/// Every local extremum of event function `i` along recorded pieces of one orbit as
/// `(t, value, sgn)` (`sgn = +1` a maximum, `−1` a minimum): the pieces sampled at their start
/// and three interior points, a sample above (below) both neighbours — the first and last
/// samples neighbours of each other, the orbit being periodic — refined by golden-section
/// search inside its piece and the pieces on either side. Extrema of one kind refined to
/// within `10⁻⁹` of the span of one another are listed once. Empty without pieces or events.
pub(crate) fn local_extrema<S: SecondOrderSystem + ?Sized>(
    field: Field<'_, S>,
    opts: &FlowOptions,
    pieces: &[Piece],
    i: usize,
) -> Vec<(f64, f64, f64)> {
    const SAMPLES: usize = 4;
    let mut st = Stepper::new(field, opts);
    let np = pieces.len();
    if np == 0 || i >= st.field.n_events() {
        return Vec::new();
    }
    let mut s = Vec::with_capacity(np * SAMPLES);
    for p in pieces {
        for j in 0..SAMPLES {
            let th = j as f64 / SAMPLES as f64;
            let x = st.state_at(p.t, &p.x, th * p.h);
            let v = st.field.event(i, p.t + th * p.h, &x);
            s.push(if v.is_finite() { v } else { f64::NAN });
        }
    }
    let n = s.len();
    let span = pieces[np - 1].t + pieces[np - 1].h - pieces[0].t;
    let mut out: Vec<(f64, f64, f64)> = Vec::new();
    for j in 0..n {
        let (a, b, c) = (s[(j + n - 1) % n], s[j], s[(j + 1) % n]);
        for sgn in [1.0, -1.0] {
            if !(sgn * b > sgn * a && sgn * b >= sgn * c) {
                continue;
            }
            let k = j / SAMPLES;
            let (mut best, mut tbest) = (f64::NEG_INFINITY, f64::NAN);
            for q in &pieces[k.saturating_sub(1)..=(k + 1).min(np - 1)] {
                let (th, v) = golden_at(&mut st, i, sgn, q);
                if v > best {
                    (best, tbest) = (v, q.t + th * q.h);
                }
            }
            // found in time order: a duplicate is among the last found, or (across the
            // orbit's wrap) the first
            let dup = out
                .iter()
                .rev()
                .take(4)
                .chain(out.iter().take(4))
                .any(|e| (e.2 - sgn).abs() < 1.0 && (e.0 - tbest).abs() <= 1e-9 * span);
            if best.is_finite() && !dup {
                out.push((tbest, sgn * best, sgn));
            }
        }
    }
    out
}

/// The time and value of the minimum (`sgn = −1`) or maximum (`sgn = +1`) of event function
/// `i` along recorded pieces: the sampled extremum refined by golden-section search inside the
/// pieces around it (as [`extrema`]). `None` without pieces or events.
pub(crate) fn extremum_at<S: SecondOrderSystem + ?Sized>(
    field: Field<'_, S>,
    opts: &FlowOptions,
    pieces: &[Piece],
    i: usize,
    sgn: f64,
) -> Option<(f64, f64)> {
    let mut st = Stepper::new(field, opts);
    if pieces.is_empty() || i >= st.field.n_events() {
        return None;
    }
    let (mut best, mut tbest, mut kbest) = (f64::NEG_INFINITY, pieces[0].t, 0);
    for (k, p) in pieces.iter().enumerate() {
        let v = sgn * st.field.event(i, p.t, &p.x);
        if v > best {
            (best, tbest, kbest) = (v, p.t, k);
        }
    }
    let lo = kbest.saturating_sub(1);
    let hi = (kbest + 1).min(pieces.len() - 1);
    for p in &pieces[lo..=hi] {
        let (th, v) = golden_at(&mut st, i, sgn, p);
        if v > best {
            (best, tbest) = (v, p.t + th * p.h);
        }
    }
    best.is_finite().then_some((tbest, sgn * best))
}

/// `max_θ sgn·e_i(x(t + θh))` on one piece by golden-section search.
fn golden<S: SecondOrderSystem + ?Sized>(
    st: &mut Stepper<'_, S>,
    i: usize,
    sgn: f64,
    p: &Piece,
) -> f64 {
    let (_, v) = golden_at(st, i, sgn, p);
    v
}

/// `(θ*, max_θ sgn·e_i(x(t + θh)))` on one piece by golden-section search.
fn golden_at<S: SecondOrderSystem + ?Sized>(
    st: &mut Stepper<'_, S>,
    i: usize,
    sgn: f64,
    p: &Piece,
) -> (f64, f64) {
    let r = 0.5 * (5.0_f64.sqrt() - 1.0);
    let f = |th: f64, st: &mut Stepper<'_, S>| -> f64 {
        let x = st.state_at(p.t, &p.x, th * p.h);
        let v = sgn * st.field.event(i, p.t + th * p.h, &x);
        if v.is_finite() { v } else { f64::NEG_INFINITY }
    };
    let (mut a, mut b) = (0.0_f64, 1.0_f64);
    let mut c = b - r * (b - a);
    let mut d = a + r * (b - a);
    let (mut fc, mut fd) = (f(c, st), f(d, st));
    for _ in 0..60 {
        if b - a < 1e-9 {
            break;
        }
        if fc > fd {
            b = d;
            d = c;
            fd = fc;
            c = b - r * (b - a);
            fc = f(c, st);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + r * (b - a);
            fd = f(d, st);
        }
    }
    // the value as `fc.max(fd)` (bit-identical to the extrema of earlier rounds)
    (if fc > fd { c } else { d }, fc.max(fd))
}

#[cfg(test)]
mod tests {
    use super::*;
    use math::DetMath;
    use std::cell::Cell;

    /// A 1-DOF system `q'' + 0.1 q' + q + k(t) q³ = cos t` with the time table `[k(t)]`,
    /// `k(t) = 1 + 0.5 sin 3t`, counting its time-function evaluations.
    struct Counted {
        tables: Cell<usize>,
        forcings: Cell<usize>,
        /// calls of `fill_time_functions` (both at once)
        shared: Cell<usize>,
        /// calls of `events_tabulated`
        tabulated_events: Cell<usize>,
    }

    impl Counted {
        fn new() -> Self {
            Self {
                tables: Cell::new(0),
                forcings: Cell::new(0),
                shared: Cell::new(0),
                tabulated_events: Cell::new(0),
            }
        }
    }

    impl SecondOrderSystem for Counted {
        fn n_dof(&self) -> usize {
            1
        }
        fn mass(&self) -> DMatrix<f64> {
            DMatrix::identity(1, 1)
        }
        fn damping(&self) -> DMatrix<f64> {
            DMatrix::from_element(1, 1, 0.1)
        }
        fn stiffness(&self) -> DMatrix<f64> {
            DMatrix::identity(1, 1)
        }
        fn nonlinear_force(&self, t: f64, q: &[f64], _qd: &[f64], g: &mut [f64]) {
            g[0] = (1.0 + 0.5 * (3.0 * t).dsin()) * q[0].powi(3);
        }
        fn forcing(&self, t: f64, f: &mut [f64]) {
            self.forcings.set(self.forcings.get() + 1);
            f[0] = t.dcos();
        }
        fn force_jacobian(&self, t: f64, q: &[f64], _qd: &[f64], dq: &mut [f64], dv: &mut [f64]) {
            dq[0] = 3.0 * (1.0 + 0.5 * (3.0 * t).dsin()) * q[0] * q[0];
            dv[0] = 0.0;
        }
        fn time_table_len(&self) -> usize {
            1
        }
        fn fill_time_table(&self, t: f64, row: &mut [f64]) {
            self.tables.set(self.tables.get() + 1);
            row[0] = 1.0 + 0.5 * (3.0 * t).dsin();
        }
        fn fill_time_functions(&self, t: f64, f: &mut [f64], row: &mut [f64]) {
            self.shared.set(self.shared.get() + 1);
            self.forcing(t, f);
            self.fill_time_table(t, row);
        }
        fn n_events(&self) -> usize {
            1
        }
        /// `q = 0.5 k(t)`
        fn events(&self, t: f64, q: &[f64], _qd: &[f64], e: &mut [f64]) {
            e[0] = q[0] - 0.5 * (1.0 + 0.5 * (3.0 * t).dsin());
        }
        fn events_tabulated(&self, _t: f64, row: &[f64], q: &[f64], _qd: &[f64], e: &mut [f64]) {
            self.tabulated_events.set(self.tabulated_events.get() + 1);
            e[0] = q[0] - 0.5 * row[0];
        }
        fn nonlinear_force_tabulated(
            &self,
            _t: f64,
            row: &[f64],
            q: &[f64],
            _qd: &[f64],
            g: &mut [f64],
        ) {
            g[0] = row[0] * q[0].powi(3);
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
            dq[0] = 3.0 * row[0] * q[0] * q[0];
            dv[0] = 0.0;
        }
    }

    /// A recorded piece keeps the end state of its own step: the same bits as stepping the
    /// piece again (what the extrema did before), for ordinary and event-ending pieces, with
    /// and without the variational equations, on both pairs.
    #[test]
    fn recorded_piece_ends_are_the_restepped_ends() {
        let sys = Counted::new();
        let mats = Matrices::of(&sys).unwrap();
        for method in [FlowMethod::DormandPrince54, FlowMethod::Dop853] {
            for variational in [false, true] {
                let opts = FlowOptions {
                    method,
                    ..FlowOptions::default()
                };
                let f = integrate(
                    Field::new(&sys, &mats, None),
                    &opts,
                    0.0,
                    &[0.3, -0.2],
                    20.0,
                    variational,
                    true,
                )
                .unwrap();
                assert!(f.events.len() >= 4, "{method:?}: {} events", f.events.len());
                let mut st = Stepper::new(Field::new(&sys, &mats, None), &opts);
                for p in &f.pieces {
                    let again = st.state_at(p.t, &p.x, p.h);
                    for (a, b) in again.iter().zip(&p.x_end) {
                        assert_eq!(a.to_bits(), b.to_bits(), "{method:?} at t = {}", p.t);
                    }
                }
            }
        }
    }

    /// The cached time functions give the direct evaluation bit for bit, and a step with its
    /// variational equation evaluates them once per distinct stage time, not once per call
    /// (7 field evaluations and 6 Jacobians per step): the stage times `t + c h` with
    /// `c = 0, 1/5, 3/10, 4/5, 8/9, 1, 1` are 6 distinct ones, and the first is the previous
    /// step's last, so 5 new ones per step.
    #[test]
    fn time_functions_are_evaluated_once_per_stage_time_and_equal_the_direct_ones() {
        let sys = Counted::new();
        let mats = Matrices::of(&sys).unwrap();
        let opts = FlowOptions {
            rtol: 1e-9,
            atol: 1e-12,
            method: FlowMethod::DormandPrince54,
            ..FlowOptions::default()
        };
        let mut st = Stepper::new(Field::new(&sys, &mats, None), &opts);
        let (mut t, h) = (0.0, 0.05);
        let mut x = vec![0.3, -0.2];
        let mut x_new = vec![0.0; 2];
        let mut phi = DMatrix::<f64>::identity(2, 2);
        let steps = 10;
        for _ in 0..steps {
            st.step(t, &x, h, &mut x_new, Some(&mut phi), None);
            x.copy_from_slice(&x_new);
            t += h;
        }
        // before the cache: 7 forcings and 7 + 6 tables per step
        assert_eq!(sys.forcings.get(), 1 + 5 * steps);
        assert_eq!(sys.tables.get(), 1 + 5 * steps);
        // every new stage time needs both: one shared call each
        assert_eq!(sys.shared.get(), 1 + 5 * steps);

        // the events at the step's end read the kept row (no new table); at a new time one
        // table, not the forcing; equal to the direct events bit for bit
        let tables = sys.tables.get();
        for (tt, new_table) in [(t, false), (t + 0.013, true), (t + 0.013, false)] {
            let before = sys.tables.get();
            let e = st.field.events(tt, &x).to_vec();
            let mut direct = [0.0];
            sys.events(tt, &x[..1], &x[1..], &mut direct);
            assert_eq!(e[0].to_bits(), direct[0].to_bits(), "t = {tt}");
            assert_eq!(
                sys.tables.get() - before,
                usize::from(new_table),
                "t = {tt}"
            );
        }
        assert_eq!(sys.tables.get(), tables + 1);
        assert_eq!(sys.tabulated_events.get(), 3);
        assert_eq!(sys.forcings.get(), 1 + 5 * steps);

        // against the direct evaluation at scattered times and states, both orders of calls
        let mut direct = [0.0; 2];
        let mut a_cached = DMatrix::zeros(2, 2);
        for (i, &tt) in [0.0, 0.37, 0.37, 1.9, -2.5, 1e3].iter().enumerate() {
            let y = [0.1 * i as f64 - 0.2, 0.05 * i as f64];
            let mut out = [0.0; 2];
            st.field.rhs(tt, &y, &mut out);
            st.field.jacobian(tt, &y, &mut a_cached);
            let mut g = [0.0];
            sys.nonlinear_force(tt, &y[..1], &y[1..], &mut g);
            direct[0] = y[1];
            direct[1] = tt.dcos() - 0.1 * y[1] - y[0] - g[0];
            assert_eq!(out[0].to_bits(), direct[0].to_bits());
            assert_eq!(out[1].to_bits(), direct[1].to_bits(), "t = {tt}");
            let (mut dq, mut dv) = ([0.0], [0.0]);
            sys.force_jacobian(tt, &y[..1], &y[1..], &mut dq, &mut dv);
            assert_eq!(a_cached[(1, 0)].to_bits(), (-(1.0 + dq[0])).to_bits());
            assert_eq!(a_cached[(1, 1)].to_bits(), (-(0.1 + dv[0])).to_bits());
        }
    }
}
