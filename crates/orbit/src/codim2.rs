//! Codim-2 continuation: a grazing, fold or period doubling located on a one-parameter
//! shooting branch, continued in two parameters by an augmented shooting system through the
//! one loop [`path::trace`].

use crate::continuation::ShootingPoint;
use crate::error::{OrbitError, Result, check};
use crate::floquet::{Floquet, floquet};
use crate::path::{
    self, Branch, BranchPoint, ContinuationOptions, Corrector, Degeneracy, Extremum, Node,
    SpecialKind, SpecialPoint, StepControl, StopReason, bordered_tangent,
};
use crate::problem::{OrbitProblem, Parameter};
use crate::shooting::ShootingOptions;
use nalgebra::{DMatrix, DVector};
use system::SecondOrderSystem;

/// The codim-2 corrector's part of [`ContinuationOptions`]
/// ([`OrbitProblem::continue_codim2`]): the two parameters, their ranges and scales, the
/// shooting Newton and the degeneracy thresholds.
///
/// The curve is traced in the **second** parameter [`Codim2Correction::parameter`] (the
/// [`Branch`]'s parameter, [`BranchPoint::parameter`]); the **first** parameter
/// [`Codim2Correction::first`] (the one of the branch the special point was located on) is
/// an unknown, reported as [`Codim2Point::first_parameter`].
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Codim2Correction {
    /// The first parameter `λ₁`: the parameter of the branch the special point was found on.
    pub first: Parameter,
    /// The curve stops ([`StopReason::FirstLeftRange`]) when `λ₁` leaves this range.
    pub first_range: [f64; 2],
    /// `λ₁` enters the arclength as `λ₁/first_scale`.
    pub first_scale: f64,
    /// The second (continued) parameter `λ₂`.
    pub parameter: Parameter,
    /// The curve stops when `λ₂` leaves `[range[0], range[1]]`.
    pub range: [f64; 2],
    /// Initial direction of `λ₂`: `+1` or `−1`.
    pub direction: f64,
    /// `λ₂` enters the arclength as `λ₂/parameter_scale`.
    pub parameter_scale: f64,
    /// The state enters the arclength as `x₀/state_scale`.
    pub state_scale: f64,
    /// A corrected point farther than `max_correction · Δs` from its predictor is rejected.
    pub max_correction: f64,
    /// Periods `k`, Newton tolerance (on every row of the augmented residual) and iteration
    /// cap (`segments` must be 1).
    pub shooting: ShootingOptions,
    /// Grazing curves stop ([`Degeneracy::GrazingCurvature`]) where
    /// `|ḧ(t_g)| (kT/2π)² < curvature_tol · ½(max h − min h)` (for a harmonic gap function
    /// the left side equals the right side's half-range: ratio 1).
    pub curvature_tol: f64,
    /// Grazing curves stop ([`Degeneracy::GrazingNotGlobal`]) where the global extremum of
    /// the event function over the orbit passes the tangency value by more than
    /// `tangency_tol · ½(max h − min h)`.
    pub tangency_tol: f64,
    /// Fold and period-doubling curves stop ([`Degeneracy::SingularBordered`]) where the
    /// reciprocal condition number `σ_min/σ_max` of the bordered matrix falls below this.
    pub singular_tol: f64,
    /// Locate the codim-2 points met (Illinois on the test function along the arclength of
    /// the step, re-correcting at every trial); `false`: detected only.
    pub locate: bool,
    /// Codim-2 points are located to this arclength tolerance (scaled variables).
    pub locate_tol: f64,
}

impl Codim2Correction {
    /// Defaults for a curve in `first` (the branch's parameter) and `parameter` (continued):
    /// unbounded ranges, unit scales, increasing `λ₂`, shooting tolerance `1e-9` with 12
    /// iterations, `curvature_tol = 1e-3`, `tangency_tol = 1e-6`, `singular_tol = 1e-12`,
    /// codim-2 points located to `1e-9`.
    pub fn new(first: Parameter, parameter: Parameter) -> Self {
        Self {
            first,
            first_range: [f64::NEG_INFINITY, f64::INFINITY],
            first_scale: 1.0,
            parameter,
            range: [f64::NEG_INFINITY, f64::INFINITY],
            direction: 1.0,
            parameter_scale: 1.0,
            state_scale: 1.0,
            max_correction: 1.0,
            shooting: ShootingOptions {
                max_iter: 12,
                ..ShootingOptions::default()
            },
            curvature_tol: 1e-3,
            tangency_tol: 1e-6,
            singular_tol: 1e-12,
            locate: true,
            locate_tol: 1e-9,
        }
    }

    /// Checks every field.
    ///
    /// # Errors
    /// [`OrbitError::InvalidInput`] naming the field.
    pub fn validate(&self) -> Result<()> {
        self.shooting.validate()?;
        check(
            self.shooting.segments == 1,
            "Codim2Correction::shooting.segments",
            "1",
            self.shooting.segments as f64,
        )?;
        check(
            self.first != self.parameter,
            "Codim2Correction::parameter",
            "a parameter other than Codim2Correction::first",
            f64::NAN,
        )?;
        for (r, name) in [
            (self.range, "Codim2Correction::range"),
            (self.first_range, "Codim2Correction::first_range"),
        ] {
            check(
                !r[0].is_nan() && !r[1].is_nan() && r[0] < r[1],
                name,
                "range[0] < range[1]",
                r[1],
            )?;
        }
        check(
            self.direction.abs().to_bits() == 1.0_f64.to_bits(),
            "Codim2Correction::direction",
            "+1 or -1",
            self.direction,
        )?;
        for (v, name) in [
            (self.first_scale, "Codim2Correction::first_scale"),
            (self.parameter_scale, "Codim2Correction::parameter_scale"),
            (self.state_scale, "Codim2Correction::state_scale"),
            (self.max_correction, "Codim2Correction::max_correction"),
        ] {
            check(v.is_finite() && v > 0.0, name, "> 0 and finite", v)?;
        }
        check(
            self.locate_tol.is_finite() && self.locate_tol > 0.0,
            "Codim2Correction::locate_tol",
            "> 0 and finite",
            self.locate_tol,
        )?;
        for (v, name) in [
            (self.curvature_tol, "Codim2Correction::curvature_tol"),
            (self.tangency_tol, "Codim2Correction::tangency_tol"),
            (self.singular_tol, "Codim2Correction::singular_tol"),
        ] {
            check(
                v.is_finite() && (0.0..1.0).contains(&v),
                name,
                "in [0, 1)",
                v,
            )?;
        }
        Ok(())
    }
}

/// Settings of [`OrbitProblem::continue_codim2`]: the one [`ContinuationOptions`] with the
/// codim-2 corrector's part.
pub type Codim2ContinuationOptions = ContinuationOptions<Codim2Correction>;

impl ContinuationOptions<Codim2Correction> {
    /// The shared defaults (smallest step `1e-7`, as shooting) with
    /// [`Codim2Correction::new`]`(first, parameter)`.
    pub fn codim2(first: Parameter, parameter: Parameter) -> Self {
        Self {
            min_step: 1e-7,
            ..Self::with_corrector(Codim2Correction::new(first, parameter))
        }
    }

    /// Checks every field (the shared ones and the corrector's).
    ///
    /// # Errors
    /// [`OrbitError::InvalidInput`] naming the field.
    pub fn validate(&self) -> Result<()> {
        self.corrector.validate()?;
        self.validate_steps()
    }
}

/// The orbit of a point of a codim-2 curve.
#[derive(Debug, Clone, PartialEq)]
pub struct Codim2Point {
    /// What the curve continues ([`SpecialKind::Grazing`], [`SpecialKind::Fold`],
    /// [`SpecialKind::PeriodDoubling`] or [`SpecialKind::ContactChange`]).
    pub curve: SpecialKind,
    /// The first parameter `λ₁` (the second, `λ₂`, is [`BranchPoint::parameter`]).
    pub first_parameter: f64,
    /// Orbit state on the section.
    pub x0: Vec<f64>,
    /// The orbit period `kT` (it follows `λ` when a parameter is the base frequency).
    pub period: f64,
    /// Grazing curves: the grazing time `t_g ∈ [t₀, t₀ + kT)`.
    pub grazing_time: Option<f64>,
    /// Grazing curves: `d²h/dt²` at `t_g` (its sign: `< 0` at a maximum, `> 0` at a
    /// minimum; its vanishing stops the curve).
    pub curvature: Option<f64>,
    /// Fold and period-doubling curves: the reciprocal condition number of the bordered
    /// matrix `[[Φ ∓ I, b], [cᵀ, 0]]` (its vanishing stops the curve).
    pub bordered_rcond: Option<f64>,
    /// Multipliers and stability of the orbit.
    pub floquet: Floquet,
    /// The monodromy matrix.
    pub monodromy: DMatrix<f64>,
    /// `[min, max]` of every event function over the orbit.
    pub extrema: Vec<[f64; 2]>,
    /// Located events per orbit period, by event index.
    pub event_counts: Vec<usize>,
}

/// A point of a codim-2 curve: [`BranchPoint::parameter`] is the second parameter `λ₂`,
/// [`Codim2Point::first_parameter`] the first.
pub type Codim2BranchPoint = BranchPoint<Codim2Point>;

/// A codim-2 curve: the one [`Branch`] type, traced in the second parameter; its
/// [`Branch::special`] holds the codim-2 points met (a sign change of a test function between
/// two curve points, located by Illinois on the arclength when [`Codim2Correction::locate`];
/// [`SpecialPoint::bracket`] in `λ₂`, [`SpecialPoint::point`] on the curve):
/// * on a grazing curve: [`SpecialKind::Fold`] (`det(Φ − I)` changes sign: the grazing
///   meets a fold), [`SpecialKind::PeriodDoubling`] (`det(Φ + I)`), and
///   [`SpecialKind::Grazing`] of another event function or extremum (a second contact is
///   touched: the grazing flank changes);
/// * on a fold or period-doubling curve: [`SpecialKind::Grazing`] (the orbit at the fold
///   touches a switching surface), and the other of fold / period doubling.
pub type Codim2Branch = Branch<Codim2Point>;

/// `sorted`.
fn sorted(a: f64, b: f64) -> [f64; 2] {
    if a <= b { [a, b] } else { [b, a] }
}

/// What the augmented system defines.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Curve {
    /// `(h_i, ḣ_i)(t_g) = 0`, `sgn = +1` for a maximum, `−1` for a minimum; `local`: a local
    /// extremum (a contact change), which need not be the global one.
    Grazing { event: usize, sgn: f64, local: bool },
    /// `g(Φ − σI) = 0` with `σ = +1` (fold) or `−1` (period doubling).
    Bordered { sigma: f64 },
}

/// One evaluation of the augmented residual.
struct Eval {
    g: DVector<f64>,
    jac: Option<DMatrix<f64>>,
    mono: Option<DMatrix<f64>>,
    /// grazing time and `ḧ` (grazing), `σ_min/σ_max` of the bordered matrix (bordered)
    t_g: f64,
    curvature: f64,
    rcond: f64,
    /// the bordered system's right and left null vectors (bordered, with `jac`)
    null: Option<(DVector<f64>, DVector<f64>)>,
}

/// The codim-2 corrector of [`path::trace`].
struct Augmented<'a, S> {
    problem: &'a mut OrbitProblem<S>,
    opts: &'a Codim2Correction,
    curve: Curve,
    kind: SpecialKind,
    /// borders `b` (column) and `c` (row) of the bordered fold / PD matrix
    borders: (DVector<f64>, DVector<f64>),
}

type Sol = Node<Codim2BranchPoint>;

impl<S: SecondOrderSystem> Augmented<'_, S> {
    fn nn(&self) -> usize {
        self.problem.dim()
    }
    /// Index of `μ₁` in `y` (`μ₂` follows).
    fn i_mu(&self) -> usize {
        self.nn() + usize::from(matches!(self.curve, Curve::Grazing { .. }))
    }

    /// Sets both parameters from `y`; refuses a system whose setting of `λ₂` moved `λ₁` (a
    /// model rebuilt from its own copy of the first parameter would otherwise give a silently
    /// wrong curve).
    fn set(&mut self, y: &DVector<f64>) -> Result<()> {
        let m = self.i_mu();
        let l1 = y[m] * self.opts.first_scale;
        self.problem.set_parameter(&self.opts.first, l1)?;
        self.problem
            .set_parameter(&self.opts.parameter, y[m + 1] * self.opts.parameter_scale)?;
        if let Ok(back) = self.problem.parameter(&self.opts.first) {
            check(
                (back - l1).abs() <= 1e-12 * (1.0 + l1.abs()),
                "Codim2Correction::parameter",
                "a parameter whose setting leaves the first parameter unchanged",
                back,
            )?;
        }
        Ok(())
    }

    /// `ḣ_i(t, x) = ∂h/∂t + ∇h·f(t, x)` by a central difference along the vector field (exact
    /// for gap functions linear in the state, up to rounding).
    fn h_dot(&self, event: usize, t: f64, x: &[f64], dt: f64) -> f64 {
        let mut field = self.problem.field();
        let mut f = vec![0.0; x.len()];
        field.rhs(t, x, &mut f);
        let xp: Vec<f64> = x.iter().zip(&f).map(|(a, b)| a + dt * b).collect();
        let xm: Vec<f64> = x.iter().zip(&f).map(|(a, b)| a - dt * b).collect();
        (field.event(event, t + dt, &xp) - field.event(event, t - dt, &xm)) / (2.0 * dt)
    }

    /// `ḧ_i(t, x)`: a central difference of `ḣ` along the vector field (second order: the
    /// curvature of the trajectory cancels).
    fn h_ddot(&self, event: usize, t: f64, x: &[f64], dt: f64) -> f64 {
        let mut f = vec![0.0; x.len()];
        self.problem.field().rhs(t, x, &mut f);
        let xp: Vec<f64> = x.iter().zip(&f).map(|(a, b)| a + dt * b).collect();
        let xm: Vec<f64> = x.iter().zip(&f).map(|(a, b)| a - dt * b).collect();
        (self.h_dot(event, t + dt, &xp, dt) - self.h_dot(event, t - dt, &xm, dt)) / (2.0 * dt)
    }

    /// The augmented residual at `y` (parameters set from `y`), with its Jacobian if `jac`.
    fn eval(&mut self, y: &DVector<f64>, jac: bool) -> Result<Eval> {
        self.set(y)?;
        let e = match self.curve {
            Curve::Grazing { event, .. } => self.eval_grazing(y, event, jac)?,
            Curve::Bordered { sigma } => self.eval_bordered(y, sigma, jac)?,
        };
        if !jac {
            return Ok(e);
        }
        // parameter columns by central differences of the whole residual
        let mut e = e;
        let m = self.i_mu();
        let ne = e.g.len();
        let mut cols = DMatrix::zeros(ne, 2);
        for (c, idx) in [m, m + 1].into_iter().enumerate() {
            let d = 1e-6 * (1.0 + y[idx].abs());
            let mut yp = y.clone();
            yp[idx] += d;
            let gp = self.eval_plain(&yp)?;
            let mut ym = y.clone();
            ym[idx] -= d;
            let gm = self.eval_plain(&ym)?;
            for r in 0..ne {
                cols[(r, c)] = (gp[r] - gm[r]) / (2.0 * d);
            }
        }
        self.set(y)?;
        if let Some(j) = e.jac.as_mut() {
            j.view_mut((0, m), (ne, 2)).copy_from(&cols);
        }
        Ok(e)
    }

    fn eval_plain(&mut self, y: &DVector<f64>) -> Result<DVector<f64>> {
        self.set(y)?;
        let e = match self.curve {
            Curve::Grazing { event, .. } => self.eval_grazing(y, event, false)?,
            Curve::Bordered { sigma } => self.eval_bordered(y, sigma, false)?,
        };
        Ok(e.g)
    }

    /// `[φ_{kT}(x) − x; h(t_g, x(t_g)); ḣ(t_g, x(t_g)) kT/2π]`, `t_g = t₀ + θ kT` (`θ` taken
    /// modulo 1); the Jacobian's state and `θ` columns (the parameter columns are filled by
    /// [`Self::eval`]).
    fn eval_grazing(&mut self, y: &DVector<f64>, event: usize, jac: bool) -> Result<Eval> {
        let nn = self.nn();
        let sx = self.opts.state_scale;
        let kt = self.opts.shooting.periods as f64 * self.problem.period();
        let t0 = self.problem.phase();
        let x: Vec<f64> = (0..nn).map(|i| y[i] * sx).collect();
        let theta = y[nn].rem_euclid(1.0);
        let d1 = theta * kt;
        let tg = t0 + d1;
        let tiny = 1e-12 * kt;
        let (xg, phi1) = if d1 > tiny {
            let f = self.problem.flow(t0, &x, d1, jac)?;
            (f.state, f.jacobian)
        } else {
            (x.clone(), jac.then(|| DMatrix::identity(nn, nn)))
        };
        let d2 = kt - d1;
        let (xe, phi2) = if d2 > tiny {
            let f = self.problem.flow(tg, &xg, d2, jac)?;
            (f.state, f.jacobian)
        } else {
            (xg.clone(), jac.then(|| DMatrix::identity(nn, nn)))
        };
        let w = kt / (2.0 * std::f64::consts::PI);
        let dt = 1e-5 * w;
        let h = self.problem.field().event(event, tg, &xg);
        let hd = self.h_dot(event, tg, &xg, dt);
        let mut g = DVector::zeros(nn + 2);
        for i in 0..nn {
            g[i] = xe[i] - x[i];
        }
        g[nn] = h;
        g[nn + 1] = hd * w;
        let curvature = self.h_ddot(event, tg, &xg, dt);
        let mut out = Eval {
            g,
            jac: None,
            mono: None,
            t_g: tg,
            curvature,
            rcond: f64::NAN,
            null: None,
        };
        let (Some(p1), Some(p2)) = (phi1, phi2) else {
            return Ok(out);
        };
        let mono = &p2 * &p1;
        let mut j = DMatrix::zeros(nn + 2, nn + 3);
        for r in 0..nn {
            for c in 0..nn {
                j[(r, c)] = (mono[(r, c)] - if r == c { 1.0 } else { 0.0 }) * sx;
            }
        }
        // ∇h and ∇ḣ at x(t_g) by central differences in the state, chained with Φ(t_g, t₀)
        let mut gh = DVector::zeros(nn);
        let mut ghd = DVector::zeros(nn);
        for c in 0..nn {
            let dh = 1e-7 * (1.0 + xg[c].abs());
            let dd = 1e-5 * (1.0 + xg[c].abs());
            let mut xp = xg.clone();
            let mut xm = xg.clone();
            xp[c] += dh;
            xm[c] -= dh;
            {
                let mut field = self.problem.field();
                gh[c] = (field.event(event, tg, &xp) - field.event(event, tg, &xm)) / (2.0 * dh);
            }
            xp[c] = xg[c] + dd;
            xm[c] = xg[c] - dd;
            ghd[c] =
                (self.h_dot(event, tg, &xp, dt) - self.h_dot(event, tg, &xm, dt)) / (2.0 * dd) * w;
        }
        let rh = p1.tr_mul(&gh) * sx;
        let rhd = p1.tr_mul(&ghd) * sx;
        for c in 0..nn {
            j[(nn, c)] = rh[c];
            j[(nn + 1, c)] = rhd[c];
        }
        // θ column: the orbit does not move; t_g = t₀ + θ kT
        j[(nn, nn)] = hd * kt;
        j[(nn + 1, nn)] = curvature * kt * w;
        out.jac = Some(j);
        out.mono = Some(mono);
        Ok(out)
    }

    /// `g` of the bordered matrix `[[Φ − σI, b], [cᵀ, 0]] [v; g] = [0; 1]`, its reciprocal
    /// condition number and null vectors.
    fn bordered(
        &self,
        mono: &DMatrix<f64>,
        sigma: f64,
    ) -> Option<(f64, f64, DVector<f64>, DVector<f64>)> {
        let nn = mono.nrows();
        let (b, c) = &self.borders;
        let mut m = DMatrix::zeros(nn + 1, nn + 1);
        m.view_mut((0, 0), (nn, nn)).copy_from(mono);
        for i in 0..nn {
            m[(i, i)] -= sigma;
            m[(i, nn)] = b[i];
            m[(nn, i)] = c[i];
        }
        // bounded SVD (a non-converging one counts as singular)
        let sv = m
            .clone()
            .try_svd(false, false, f64::EPSILON, 1000)
            .map_or_else(|| DVector::zeros(nn + 1), |d| d.singular_values);
        let (smin, smax) = sv
            .iter()
            .fold((f64::INFINITY, 0.0_f64), |(a, z), v| (a.min(*v), z.max(*v)));
        let rcond = if smax > 0.0 { smin / smax } else { 0.0 };
        let mut rhs = DVector::zeros(nn + 1);
        rhs[nn] = 1.0;
        let lu = m.clone().lu();
        let v = lu.solve(&rhs)?;
        let w = m.transpose().lu().solve(&rhs)?;
        if !v.iter().chain(w.iter()).all(|a| a.is_finite()) {
            return None;
        }
        Some((
            v[nn],
            rcond,
            v.rows(0, nn).into_owned(),
            w.rows(0, nn).into_owned(),
        ))
    }

    /// `[φ_{kT}(x) − x; g(Φ − σI)]`; with `jac`, the state columns (`g`'s by central
    /// differences of the variational flow).
    fn eval_bordered(&mut self, y: &DVector<f64>, sigma: f64, jac: bool) -> Result<Eval> {
        let nn = self.nn();
        let sx = self.opts.state_scale;
        let kt = self.opts.shooting.periods as f64 * self.problem.period();
        let t0 = self.problem.phase();
        let x: Vec<f64> = (0..nn).map(|i| y[i] * sx).collect();
        let f = self.problem.flow(t0, &x, kt, true)?;
        let mono = f.jacobian.ok_or(OrbitError::Singular {
            what: "monodromy of the codim-2 corrector",
        })?;
        let singular = OrbitError::Singular {
            what: "bordered fold / period-doubling matrix",
        };
        let (gval, rcond, v, w) = self.bordered(&mono, sigma).ok_or(singular.clone())?;
        let mut g = DVector::zeros(nn + 1);
        for i in 0..nn {
            g[i] = f.state[i] - x[i];
        }
        g[nn] = gval;
        let mut out = Eval {
            g,
            jac: None,
            mono: Some(mono.clone()),
            t_g: f64::NAN,
            curvature: f64::NAN,
            rcond,
            null: Some((v, w)),
        };
        if !jac {
            return Ok(out);
        }
        let mut j = DMatrix::zeros(nn + 1, nn + 2);
        for r in 0..nn {
            for c in 0..nn {
                j[(r, c)] = (mono[(r, c)] - if r == c { 1.0 } else { 0.0 }) * sx;
            }
        }
        for c in 0..nn {
            let d = 1e-5 * (1.0 + y[c].abs());
            let mut vals = [0.0; 2];
            for (k, sgn) in [1.0, -1.0].into_iter().enumerate() {
                let mut xs = x.clone();
                xs[c] += sgn * d * sx;
                let fl = self.problem.flow(t0, &xs, kt, true)?;
                let ph = fl.jacobian.ok_or(singular.clone())?;
                vals[k] = self.bordered(&ph, sigma).ok_or(singular.clone())?.0;
            }
            j[(nn, c)] = (vals[0] - vals[1]) / (2.0 * d);
        }
        out.jac = Some(j);
        Ok(out)
    }

    /// Newton on the augmented residual bordered by `borderᵀ (y − pred) = 0`.
    fn newton(
        &mut self,
        pred: &DVector<f64>,
        border: &DVector<f64>,
        reference: &DVector<f64>,
    ) -> Result<Sol> {
        let nn = self.nn();
        let tol = self.opts.shooting.tol;
        let max_iter = self.opts.shooting.max_iter;
        let mut y = pred.clone();
        let dim = y.len();
        for it in 0..=max_iter {
            let e = self.eval(&y, true)?;
            let jac = e.jac.clone().ok_or(OrbitError::Singular {
                what: "codim-2 Jacobian",
            })?;
            let a = border.dot(&(&y - pred));
            let res = e.g.amax();
            let xs = y.rows(0, nn).amax() * self.opts.state_scale;
            if res <= tol * (1.0 + xs) && a.abs() <= tol * (1.0 + xs) {
                return self.finish(y, e, jac, reference, it);
            }
            if it == max_iter {
                return Err(OrbitError::NotConverged {
                    what: "codim-2 corrector",
                    iterations: it,
                    residual: res,
                });
            }
            let mut m = DMatrix::zeros(dim, dim);
            m.view_mut((0, 0), (dim - 1, dim)).copy_from(&jac);
            m.row_mut(dim - 1).copy_from(&border.transpose());
            let mut rhs = DVector::zeros(dim);
            rhs.rows_mut(0, dim - 1).copy_from(&(-&e.g));
            rhs[dim - 1] = -a;
            let dy = m
                .lu()
                .solve(&rhs)
                .filter(|d| d.iter().all(|v| v.is_finite()))
                .ok_or(OrbitError::Singular {
                    what: "bordered codim-2 Jacobian",
                })?;
            y += dy;
        }
        Err(OrbitError::NotConverged {
            what: "codim-2 corrector",
            iterations: max_iter,
            residual: f64::NAN,
        })
    }

    fn finish(
        &mut self,
        y: DVector<f64>,
        e: Eval,
        jac: DMatrix<f64>,
        reference: &DVector<f64>,
        iterations: usize,
    ) -> Result<Sol> {
        let nn = self.nn();
        let m = self.i_mu();
        let tangent = bordered_tangent(&jac, reference).ok_or(OrbitError::Singular {
            what: "bordered codim-2 tangent system",
        })?;
        let mono = e.mono.clone().ok_or(OrbitError::Singular {
            what: "monodromy of the codim-2 corrector",
        })?;
        let fl = floquet(&mono)?;
        self.set(&y)?;
        let x: Vec<f64> = (0..nn).map(|i| y[i] * self.opts.state_scale).collect();
        let k = self.opts.shooting.periods;
        let t0 = self.problem.phase();
        let fr = self
            .problem
            .flow_recorded(t0, &x, k as f64 * self.problem.period(), false)?;
        let extrema = crate::flow::extrema(
            self.problem.field(),
            self.problem.flow_options(),
            &fr.pieces,
            (fr.time, &fr.state),
        );
        let grazing = matches!(self.curve, Curve::Grazing { .. });
        let point = BranchPoint {
            parameter: y[m + 1] * self.opts.parameter_scale,
            tangent_parameter: tangent[m + 1],
            stability: Some(fl.stability()),
            orbit: Codim2Point {
                curve: self.kind,
                first_parameter: y[m] * self.opts.first_scale,
                x0: x,
                period: k as f64 * self.problem.period(),
                grazing_time: grazing.then_some(e.t_g),
                curvature: grazing.then_some(e.curvature),
                bordered_rcond: (!grazing).then_some(e.rcond),
                floquet: fl,
                monodromy: mono,
                extrema,
                event_counts: (0..self.problem.system().n_events())
                    .map(|i| fr.events.iter().filter(|ev| ev.index == i).count())
                    .collect(),
            },
        };
        if let Some((v, w)) = e.null {
            // the borders follow the null vectors (kept when degenerate)
            let (nv, nw) = (v.norm(), w.norm());
            if nv > 0.0 && nw > 0.0 && nv.is_finite() && nw.is_finite() {
                self.borders = (w / nw, v / nv);
            }
        }
        Ok(Sol {
            y,
            tangent,
            iterations: iterations as u64,
            raw: point,
        })
    }

    /// The test value of `kind` at `p` (as [`Self::tests`]).
    fn test_of(&self, kind: SpecialKind, p: &Codim2BranchPoint) -> f64 {
        self.tests(p)
            .into_iter()
            .find(|(k, _)| *k == kind)
            .map_or(f64::NAN, |(_, v)| v)
    }

    /// The corrected curve point at arclength `s` of the step from `a` (rejected when the
    /// corrector moved farther than `max_correction · max(s, locate_tol)`).
    fn point_at(&mut self, a: &Sol, s: f64) -> Result<Codim2BranchPoint> {
        let pred = &a.y + &a.tangent * s;
        let borders = self.borders.clone();
        let sol = self.newton(&pred, &a.tangent, &a.tangent);
        // location trials must not move the borders of the curve
        self.borders = borders;
        let sol = sol?;
        let dist = (&sol.y - &pred).norm();
        if dist > self.opts.max_correction * s.max(self.opts.locate_tol) {
            return Err(OrbitError::NotConverged {
                what: "codim-2 point location (corrector left the step)",
                iterations: 0,
                residual: dist,
            });
        }
        Ok(sol.raw)
    }

    /// Illinois on the arclength `s ∈ (0, ds)` of the step from `a` for a sign change of the
    /// test function of `kind` (values `fa`, `fb` at the ends); bisection when a trial lands
    /// outside the bracket. Returns the point, its `λ₂` bracket and whether the arclength
    /// bracket shrank to `locate_tol`.
    fn locate(
        &mut self,
        a: &Sol,
        (fa, fb): (f64, f64),
        ds: f64,
        kind: SpecialKind,
    ) -> Result<(Codim2BranchPoint, [f64; 2], bool)> {
        let (mut lo, mut hi) = (0.0, ds);
        let (mut flo, mut fhi) = (fa, fb);
        let (mut plo, mut phi) = (a.raw.parameter, f64::NAN);
        let mut best = None;
        let mut side = 0i8;
        for _ in 0..60 {
            if hi - lo <= self.opts.locate_tol {
                break;
            }
            let mut s = hi - fhi * (hi - lo) / (fhi - flo);
            if !(s > lo && s < hi) {
                s = 0.5 * (lo + hi);
            }
            let p = self.point_at(a, s)?;
            let f = self.test_of(kind, &p);
            if !f.is_finite() {
                return Err(OrbitError::NonFinite {
                    what: "codim-2 test function",
                    time: self.problem.phase(),
                });
            }
            if f * flo > 0.0 {
                (lo, flo, plo) = (s, f, p.parameter);
                if side == -1 {
                    fhi *= 0.5;
                }
                side = -1;
            } else {
                (hi, fhi, phi) = (s, f, p.parameter);
                if side == 1 {
                    flo *= 0.5;
                }
                side = 1;
            }
            best = Some(p);
        }
        let located = hi - lo <= self.opts.locate_tol;
        let point = best.ok_or(OrbitError::NotConverged {
            what: "codim-2 point location",
            iterations: 0,
            residual: hi - lo,
        })?;
        let phi = if phi.is_nan() { point.parameter } else { phi };
        Ok((point, sorted(plo, phi), located))
    }

    /// The test values that mark codim-2 points on this curve: `(kind, value)`.
    fn tests(&self, p: &Codim2BranchPoint) -> Vec<(SpecialKind, f64)> {
        let mut out = vec![];
        for (i, e) in p.extrema.iter().enumerate() {
            for (slot, ext) in [(0usize, Extremum::Min), (1usize, Extremum::Max)] {
                let kind = SpecialKind::Grazing {
                    event: i,
                    extremum: ext,
                };
                if kind != self.kind {
                    out.push((kind, e[slot]));
                }
            }
        }
        if self.kind != SpecialKind::Fold {
            out.push((SpecialKind::Fold, p.floquet.test_fold));
        }
        if self.kind != SpecialKind::PeriodDoubling {
            out.push((SpecialKind::PeriodDoubling, p.floquet.test_period_doubling));
        }
        out
    }
}

impl<S: SecondOrderSystem> Corrector for Augmented<'_, S> {
    type Raw = Codim2BranchPoint;
    type Point = Codim2Point;
    type Error = OrbitError;

    fn correct(
        &mut self,
        pred: &DVector<f64>,
        border: &DVector<f64>,
        reference: &DVector<f64>,
    ) -> Result<Result<Sol>> {
        Ok(self.newton(pred, border, reference))
    }

    fn accept(&mut self, node: &Sol) -> Result<Codim2BranchPoint> {
        Ok(node.raw.clone())
    }

    fn parameter_scale(&self) -> f64 {
        self.opts.parameter_scale
    }

    fn on_step(&mut self, a: &Sol, b: &Sol, ds: f64, branch: &mut Codim2Branch) -> Result<()> {
        let after = branch.points.len() - 1;
        let (ta, tb) = (self.tests(&a.raw), self.tests(&b.raw));
        let mut found = vec![];
        for ((kind, va), (_, vb)) in ta.into_iter().zip(tb) {
            if va.is_finite() && vb.is_finite() && va * vb < 0.0 {
                let detected = SpecialPoint {
                    kind,
                    point: b.raw.clone(),
                    after,
                    located: false,
                    bracket: sorted(a.raw.parameter, b.raw.parameter),
                };
                let sp = if self.opts.locate {
                    self.locate(a, (va, vb), ds, kind).map_or(
                        detected,
                        |(point, bracket, located)| SpecialPoint {
                            kind,
                            point,
                            after,
                            located,
                            bracket,
                        },
                    )
                } else {
                    detected
                };
                found.push(sp);
            }
        }
        found.sort_by(|x, y| {
            let d = |p: &SpecialPoint<Codim2Point>| (p.point.parameter - a.raw.parameter).abs();
            d(x).total_cmp(&d(y))
        });
        branch.special.extend(found);
        // the borders and the problem's parameters back at b
        self.set(&b.y)?;
        Ok(())
    }

    fn leave_at(&mut self, y: &DVector<f64>) -> Result<()> {
        self.set(y)
    }

    fn stop_after(&mut self, node: &Sol) -> Option<StopReason> {
        stop_reason(self.opts, self.curve, &node.raw)
    }
}

/// The named reason to stop at `p`, if any.
fn stop_reason(opts: &Codim2Correction, curve: Curve, p: &Codim2BranchPoint) -> Option<StopReason> {
    let parameter = p.parameter;
    let first = p.first_parameter;
    if first < opts.first_range[0] || first > opts.first_range[1] {
        return Some(StopReason::FirstLeftRange { parameter, first });
    }
    let degenerate = |condition| {
        Some(StopReason::Degenerate {
            parameter,
            condition,
        })
    };
    match curve {
        Curve::Grazing { event, sgn, local } => {
            let e = p.extrema.get(event).copied().unwrap_or([f64::NAN; 2]);
            let half = 0.5 * (e[1] - e[0]);
            let curv = p.curvature.unwrap_or(f64::NAN);
            let w = p.period / (2.0 * std::f64::consts::PI);
            // a quadratic tangency: ḧ (kT/2π)² of the right sign and not small against the
            // half range of h over the orbit
            let quadratic = sgn * curv * w * w <= -opts.curvature_tol * half;
            if !quadratic {
                return degenerate(Degeneracy::GrazingCurvature);
            }
            let ext = if sgn > 0.0 { e[1] } else { e[0] };
            // the tangency value is 0 to the Newton tolerance
            let xs = p.x0.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            let global = sgn * ext <= opts.tangency_tol * half + opts.shooting.tol * (1.0 + xs);
            if !global && !local {
                return degenerate(Degeneracy::GrazingNotGlobal);
            }
            None
        }
        Curve::Bordered { .. } => {
            let rc = p.bordered_rcond.unwrap_or(f64::NAN);
            let regular = rc >= opts.singular_tol;
            if !regular {
                return degenerate(Degeneracy::SingularBordered);
            }
            None
        }
    }
}

impl<S: SecondOrderSystem> OrbitProblem<S> {
    /// Continues the special point `start` (a [`SpecialKind::Grazing`], [`SpecialKind::Fold`],
    /// [`SpecialKind::PeriodDoubling`] or [`SpecialKind::ContactChange`] — the grazing of a
    /// local extremum, crate docs — located on a shooting branch in
    /// [`Codim2Correction::first`], [`OrbitProblem::continuation`]) in two parameters: the
    /// augmented system of the crate docs ("Codim-2 continuation") is traced by
    /// [`path::trace`] in the second parameter [`Codim2Correction::parameter`] (starting at
    /// its present value in the problem), with the first parameter among the unknowns.
    ///
    /// The first point is corrected from `start` at fixed `λ₂`. Along the curve the orbit's
    /// Floquet multipliers are recorded ([`BranchPoint::stability`]) and the codim-2 points met
    /// are listed in [`Branch::special`] ([`Codim2Branch`]). The curve stops with
    /// [`StopReason::Degenerate`] where its defining condition degenerates,
    /// [`StopReason::FirstLeftRange`] where `λ₁` leaves its range, or the reasons of every
    /// branch. On return the problem's parameters are left at the last point.
    ///
    /// # Errors
    /// Invalid options; a `start` of another kind, of a wrong dimension or event index; the
    /// first point does not converge; for a contact change, no local extremum grazes within
    /// its bracket.
    pub fn continue_codim2(
        &mut self,
        start: &SpecialPoint<ShootingPoint>,
        options: &Codim2ContinuationOptions,
    ) -> Result<Codim2Branch> {
        self.codim2_from(start, options, None)
    }

    /// The grazing phase `θ ∈ [0, 1)` (`t_g = t₀ + θ kT`) of the global extremum of event
    /// `event` (`sgn = +1` maximum, `−1` minimum) over the orbit from `x0` at the present
    /// parameters, over `periods` periods.
    fn grazing_phase(&mut self, x0: &[f64], event: usize, sgn: f64, periods: usize) -> Result<f64> {
        let t0 = self.phase();
        let kt = periods as f64 * self.period();
        let fr = self.flow_recorded(t0, x0, kt, false)?;
        let (tg, _) =
            crate::flow::extremum_at(self.field(), self.flow_options(), &fr.pieces, event, sgn)
                .ok_or(OrbitError::InvalidInput {
                    field: "start (no recorded orbit to locate the grazing time on)",
                    bound: "an orbit with event functions",
                    value: f64::NAN,
                })?;
        Ok(((tg - t0) / kt).rem_euclid(1.0))
    }

    /// [`OrbitProblem::continue_codim2`], a grazing started at the phase `theta` when given
    /// (else at the global extremum of the start's orbit).
    fn codim2_from(
        &mut self,
        start: &SpecialPoint<ShootingPoint>,
        options: &Codim2ContinuationOptions,
        theta: Option<f64>,
    ) -> Result<Codim2Branch> {
        options.validate()?;
        let curve = match start.kind {
            SpecialKind::Grazing { event, extremum } => {
                check(
                    event < self.system().n_events(),
                    "start.kind (grazing event index)",
                    "< n_events",
                    event as f64,
                )?;
                Curve::Grazing {
                    event,
                    sgn: match extremum {
                        Extremum::Max => 1.0,
                        Extremum::Min => -1.0,
                    },
                    local: false,
                }
            }
            SpecialKind::Fold => Curve::Bordered { sigma: 1.0 },
            SpecialKind::PeriodDoubling => Curve::Bordered { sigma: -1.0 },
            SpecialKind::ContactChange { event } => {
                check(
                    event < self.system().n_events(),
                    "start.kind (contact-change event index)",
                    "< n_events",
                    event as f64,
                )?;
                return self.contact_change_curve(start, options, event);
            }
            SpecialKind::NeimarkSacker => {
                return Err(OrbitError::InvalidInput {
                    field: "start.kind",
                    bound: "Grazing, Fold, PeriodDoubling or ContactChange",
                    value: f64::NAN,
                });
            }
        };
        self.codim2_curve(start, options, curve, theta, None)
    }

    /// The curve of a [`SpecialKind::ContactChange`] (a local extremum of event function
    /// `event` touching zero between the two branch points of `start.bracket`): a grazing
    /// curve of that local extremum, where the global-extremum check
    /// ([`Degeneracy::GrazingNotGlobal`]) does not apply. The candidates are the local extrema
    /// of the event function over the orbit of `start.point` other than the global maximum
    /// and minimum, nearest zero first; the first whose corrected first point lies in
    /// `start.bracket` (widened by `locate_tol · first_scale` and [`CONTACT_LAG`]) is
    /// continued. At most [`CONTACT_CANDIDATES`] are tried, each from the problem's second
    /// parameter as it was on entry.
    fn contact_change_curve(
        &mut self,
        start: &SpecialPoint<ShootingPoint>,
        options: &Codim2ContinuationOptions,
        event: usize,
    ) -> Result<Codim2Branch> {
        let opts = &options.corrector;
        self.check_state(&start.point.x0)?;
        let lam2 = self.parameter(&opts.parameter)?;
        check(lam2.is_finite(), "second parameter value", "finite", lam2)?;
        self.set_parameter(&opts.first, start.point.parameter)?;
        let t0 = self.phase();
        let kt = opts.shooting.periods as f64 * self.period();
        let fr = self.flow_recorded(t0, &start.point.x0, kt, false)?;
        let mut ext =
            crate::flow::local_extrema(self.field(), self.flow_options(), &fr.pieces, event);
        let top = ext.iter().map(|e| e.1).fold(f64::NEG_INFINITY, f64::max);
        let bottom = ext.iter().map(|e| e.1).fold(f64::INFINITY, f64::min);
        // not the global extrema (nor their ties to rounding): their zero is a grazing, not a
        // contact change
        let tie = 1e-12 * (top - bottom);
        ext.retain(|e| {
            if e.2 > 0.0 {
                e.1 < top - tie
            } else {
                e.1 > bottom + tie
            }
        });
        ext.sort_by(|a, b| a.1.abs().total_cmp(&b.1.abs()));
        let widen = |l: f64| opts.locate_tol * opts.first_scale + CONTACT_LAG * l.abs();
        let (lo, hi) = (
            start.bracket[0] - widen(start.bracket[0]),
            start.bracket[1] + widen(start.bracket[1]),
        );
        let mut last = OrbitError::NotConverged {
            what: "contact-change curve (no local extremum of the event function to start from)",
            iterations: 0,
            residual: f64::NAN,
        };
        for &(tg, _, sgn) in ext.iter().take(CONTACT_CANDIDATES) {
            self.set_parameter(&opts.parameter, lam2)?;
            let curve = Curve::Grazing {
                event,
                sgn,
                local: true,
            };
            let theta = ((tg - t0) / kt).rem_euclid(1.0);
            match self.codim2_curve(start, options, curve, Some(theta), Some([lo, hi])) {
                Ok(b) => return Ok(b),
                Err(e) => last = e,
            }
        }
        self.set_parameter(&opts.parameter, lam2)?;
        Err(last)
    }

    /// The codim-2 curve `curve` from `start` ([`OrbitProblem::codim2_from`]); with
    /// `first_within`, an error unless the first point's `λ₁` lies in it.
    fn codim2_curve(
        &mut self,
        start: &SpecialPoint<ShootingPoint>,
        options: &Codim2ContinuationOptions,
        curve: Curve,
        theta: Option<f64>,
        first_within: Option<[f64; 2]>,
    ) -> Result<Codim2Branch> {
        let opts = &options.corrector;
        self.check_state(&start.point.x0)?;
        let nn = self.dim();
        let lam1 = start.point.parameter;
        self.set_parameter(&opts.first, lam1)?;
        let lam2 = self.parameter(&opts.parameter)?;
        check(lam2.is_finite(), "second parameter value", "finite", lam2)?;
        let extra = usize::from(matches!(curve, Curve::Grazing { .. }));
        let mut y = DVector::zeros(nn + extra + 2);
        for i in 0..nn {
            y[i] = start.point.x0[i] / opts.state_scale;
        }
        let mut borders = (DVector::zeros(0), DVector::zeros(0));
        match curve {
            Curve::Grazing { event, sgn, .. } => {
                y[nn] = match theta {
                    Some(th) if th.is_finite() => th.rem_euclid(1.0),
                    _ => self.grazing_phase(&start.point.x0, event, sgn, opts.shooting.periods)?,
                };
            }
            Curve::Bordered { sigma } => {
                let mut a = start.point.monodromy.clone();
                check(
                    a.nrows() == nn && a.ncols() == nn,
                    "start.point.monodromy (rows)",
                    "the state dimension",
                    a.nrows() as f64,
                )?;
                for i in 0..nn {
                    a[(i, i)] -= sigma;
                }
                check(
                    a.iter().all(|v| v.is_finite()),
                    "start.point.monodromy",
                    "finite",
                    f64::NAN,
                )?;
                let svd = a
                    .try_svd(true, true, f64::EPSILON, 1000)
                    .ok_or(OrbitError::Eigen)?;
                let (Some(u), Some(vt)) = (svd.u.as_ref(), svd.v_t.as_ref()) else {
                    return Err(OrbitError::Eigen);
                };
                let imin = svd
                    .singular_values
                    .iter()
                    .enumerate()
                    .fold(
                        (0, f64::INFINITY),
                        |(k, m), (i, v)| {
                            if *v < m { (i, *v) } else { (k, m) }
                        },
                    )
                    .0;
                borders = (
                    u.column(imin).into_owned(),
                    vt.row(imin).transpose().into_owned(),
                );
            }
        }
        let m = nn + extra;
        y[m] = lam1 / opts.first_scale;
        y[m + 1] = lam2 / opts.parameter_scale;
        let mut e2 = DVector::zeros(y.len());
        e2[m + 1] = 1.0;
        let mut aug = Augmented {
            problem: self,
            opts,
            curve,
            kind: start.kind,
            borders,
        };
        let reference = &e2 * opts.direction;
        let first = aug.newton(&y, &e2, &reference)?;
        if let Some([lo, hi]) = first_within {
            let l1 = first.raw.first_parameter;
            if !(lo..=hi).contains(&l1) {
                // the residual: how far outside the bracket
                return Err(OrbitError::NotConverged {
                    what: "contact-change curve (the local extremum grazes outside the start's bracket)",
                    iterations: 0,
                    residual: (lo - l1).max(l1 - hi),
                });
            }
        }
        let mut branch = Branch::new(opts.parameter.clone(), opts.shooting.periods);
        branch.points.push(first.raw.clone());
        if let Some(reason) = stop_reason(opts, curve, &first.raw) {
            branch.stop = reason;
            return Ok(branch);
        }
        let control = StepControl::shooting(
            options.initial_step,
            options.min_step,
            options.max_step,
            opts.max_correction,
        );
        let course = options.course(opts.range, opts.direction);
        path::trace(&mut aug, first, &control, &course, &mut branch)?;
        Ok(branch)
    }
}

/// Local extrema tried as the start of a contact-change curve
/// ([`OrbitProblem::continue_codim2`] from a [`SpecialKind::ContactChange`]).
pub const CONTACT_CANDIDATES: usize = 3;

/// Relative widening of a contact change's bracket in `λ₁` before a local grazing is accepted
/// as its start ([`OrbitProblem::continue_codim2`]): the crossing count, on which a contact
/// change is located, changes only once the two crossings near the tangency lie far enough
/// apart for the event detection to resolve them, `7·10⁻⁶` (relative) past the tangency in the
/// closed-form test (`contact_change_curve_matches_closed_form`); `10⁻⁴` leaves more than a
/// factor of ten and still tells apart local extrema that graze elsewhere on the branch.
const CONTACT_LAG: f64 = 1e-4;

/// Most switches [`OrbitProblem::continue_grazing_envelope`] accepts.
pub const MAX_ENVELOPE_SWITCHES: usize = 1000;

/// Hops from extremum to extremum at one restart ([`OrbitProblem::continue_grazing_envelope`]).
const RESTART_HOPS: usize = 4;

/// Bisections of the `λ₂` bracket of a double grazing before a restart (`2⁻¹⁰` of the last
/// step).
const SWITCH_BISECTIONS: usize = 10;

/// How a [`GrazingEnvelope`] ended.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum EnvelopeEnd {
    /// The last piece stopped for a reason other than [`Degeneracy::GrazingNotGlobal`]
    /// (its [`Branch::stop`]: the range's end, a degenerate curvature, the step cap …).
    Stopped,
    /// The switch cap was reached; the last piece stopped at
    /// [`Degeneracy::GrazingNotGlobal`] once more.
    SwitchLimit,
    /// A restart made no progress: its first point is again not the global extremum (the
    /// two extrema cannot be told apart at the stop), so the curve is not continued.
    NoProgress,
    /// The first point of a restart did not converge (the error of
    /// [`OrbitProblem::continue_codim2`]).
    RestartFailed(OrbitError),
    /// The envelope came back to a double grazing it had already passed, travelling the same
    /// way in `λ₂`: the restarts went round a cluster of local extrema that lie close to the
    /// surface together, and would retrace the same pieces again up to the switch cap. The
    /// pieces of the first round are kept; the last one ends at the repeated double grazing.
    Cycle,
}

/// A grazing curve followed along the **global** extremum of its event function
/// ([`OrbitProblem::continue_grazing_envelope`]): the pieces of [`Codim2Branch`] traced one
/// after the other, each started where the one before stopped with
/// [`Degeneracy::GrazingNotGlobal`].
#[derive(Debug, Clone, PartialEq)]
pub struct GrazingEnvelope {
    /// The pieces in the order traced (at least one).
    pub pieces: Vec<Codim2Branch>,
    /// Why the envelope ended.
    pub end: EnvelopeEnd,
}

impl GrazingEnvelope {
    /// The points on the envelope in trace order: every piece's points except the stop point
    /// of a piece that stopped with [`Degeneracy::GrazingNotGlobal`] (there another extremum
    /// already crossed the surface, so that point bounds no contact).
    pub fn points(&self) -> Vec<&Codim2BranchPoint> {
        self.points_by_piece().into_iter().map(|(_, p)| p).collect()
    }

    /// [`GrazingEnvelope::points`] with the index of the piece each lies on: the envelope is
    /// smooth within a piece and has a kink (the double grazing) between two (for
    /// interpolation between the points, or estimates of its curvature, that stay on one
    /// smooth piece).
    pub fn points_by_piece(&self) -> Vec<(usize, &Codim2BranchPoint)> {
        self.pieces
            .iter()
            .enumerate()
            .flat_map(|(k, b)| {
                let past = matches!(
                    b.stop,
                    StopReason::Degenerate {
                        condition: Degeneracy::GrazingNotGlobal,
                        ..
                    }
                );
                b.points[..b.points.len() - usize::from(past && !b.points.is_empty())]
                    .iter()
                    .map(move |p| (k, p))
            })
            .collect()
    }

    /// The switch points: the first point of every piece after the first, where the grazing
    /// moved to another local extremum of the event function (the double grazing lies between
    /// it and the previous piece's last point on the envelope).
    pub fn switches(&self) -> Vec<&Codim2BranchPoint> {
        self.pieces
            .iter()
            .skip(1)
            .filter_map(|b| b.points.first())
            .collect()
    }

    /// The stop reason of the last piece.
    pub fn stop(&self) -> Option<&StopReason> {
        self.pieces.last().map(|b| &b.stop)
    }
}

impl<S: SecondOrderSystem> OrbitProblem<S> {
    /// Continues a grazing curve along the global extremum of its event function: the
    /// boundary of contact in two parameters is the upper (for a maximum) envelope of the
    /// grazing curves of the event function's local extrema, with a kink where two of them
    /// touch the surface at once (a double grazing). [`OrbitProblem::continue_codim2`] traces
    /// one local extremum and stops with [`Degeneracy::GrazingNotGlobal`] past such a kink;
    /// here each such stop starts a new piece on the extremum that is global at the stop point
    /// (its phase located on the stop point's orbit), at most `max_switches` times:
    /// * forward: from the stop point, in the direction of `λ₂` the piece before was
    ///   travelling (the two local-extremum curves cross at the double grazing and the
    ///   envelope goes on along the other one);
    /// * else back: from the piece's last point before the stop (where the old extremum was
    ///   still global), in the opposite direction (the envelope has a corner at the double
    ///   grazing and turns back in `λ₂`).
    ///
    /// A try counts when its first point is the global extremum. Every other stop reason ends
    /// the envelope, and so does a restart whose first point is again not global
    /// ([`EnvelopeEnd::NoProgress`]) or does not converge ([`EnvelopeEnd::RestartFailed`]), and
    /// a double grazing met a second time travelling the same way ([`EnvelopeEnd::Cycle`]: the
    /// bracketed double grazing within `corrector.locate_tol` of an earlier one in the scaled
    /// parameters `λ₁/first_scale`, `λ₂/parameter_scale`): the pieces traced are kept.
    ///
    /// # Errors
    /// `start` is not a [`SpecialKind::Grazing`]; `max_switches > MAX_ENVELOPE_SWITCHES`; the
    /// errors of [`OrbitProblem::continue_codim2`] for the first piece.
    pub fn continue_grazing_envelope(
        &mut self,
        start: &SpecialPoint<ShootingPoint>,
        options: &Codim2ContinuationOptions,
        max_switches: usize,
    ) -> Result<GrazingEnvelope> {
        check(
            max_switches <= MAX_ENVELOPE_SWITCHES,
            "max_switches",
            "<= MAX_ENVELOPE_SWITCHES (1000)",
            max_switches as f64,
        )?;
        let (event, sgn) = match start.kind {
            SpecialKind::Grazing { event, extremum } => (
                event,
                match extremum {
                    Extremum::Max => 1.0,
                    Extremum::Min => -1.0,
                },
            ),
            _ => not_a_grazing()?,
        };
        let mut pieces = vec![self.continue_codim2(start, options)?];
        let mut opts = options.clone();
        let periods = opts.corrector.shooting.periods;
        let not_global = |b: &Codim2Branch| {
            matches!(
                b.stop,
                StopReason::Degenerate {
                    condition: Degeneracy::GrazingNotGlobal,
                    ..
                }
            )
        };
        // the double grazings passed: (λ₁/first_scale, λ₂/parameter_scale, travelling up in
        // λ₂), at most `max_switches` of them
        let mut passed: Vec<(f64, f64, bool)> = Vec::new();
        // each pass pushes one piece or ends: at most `max_switches + 1` pieces
        let end = loop {
            let Some(last) = pieces.last() else {
                break EnvelopeEnd::NoProgress;
            };
            if !not_global(last) {
                break EnvelopeEnd::Stopped;
            }
            if pieces.len() > max_switches {
                break EnvelopeEnd::SwitchLimit;
            }
            let n = last.points.len();
            let Some(mut stop) = last.points.last().cloned() else {
                break EnvelopeEnd::NoProgress;
            };
            let mut prev = n.checked_sub(2).map(|k| last.points[k].clone());
            let travel = prev
                .as_ref()
                .map(|q| stop.parameter - q.parameter)
                .filter(|d| *d != 0.0)
                .map_or(opts.corrector.direction, f64::signum);
            // the double grazing bracketed in λ₂ by bisection on the old extremum's curve: the
            // restarts start next to it, where the new extremum is close to the surface
            if let Some(q) = prev.as_mut() {
                let mut single = opts.clone();
                single.max_points = 1;
                for _ in 0..SWITCH_BISECTIONS {
                    let mid = 0.5 * (q.parameter + stop.parameter);
                    // the phase on the orbit's own period (it follows a base-frequency λ₁)
                    let theta = q.grazing_time.map(|tg| (tg - self.phase()) / q.period);
                    let corrected =
                        self.set_parameter(&opts.corrector.parameter, mid)
                            .and_then(|()| {
                                self.codim2_from(&restart_at(start.kind, q), &single, theta)
                            });
                    let Ok(b) = corrected else { break };
                    let Some(p) = b.points.first() else { break };
                    // a correction that slid to another extremum ends the bisection
                    let t0 = self.phase();
                    let reach = phase_distance(&stop, q, t0);
                    let near = phase_distance(p, q, t0) <= 2.0 * reach + 1e-3;
                    if !near {
                        break;
                    }
                    match &b.stop {
                        _ if not_global(&b) => stop = p.clone(),
                        StopReason::MaxPoints => *q = p.clone(),
                        _ => break,
                    }
                }
                // the last global point of the old extremum closes the piece on the envelope
                // and the bracket's other end replaces the stop point
                if let Some(piece) = pieces.last_mut() {
                    piece.points.pop();
                    if piece
                        .points
                        .last()
                        .is_none_or(|x| x.parameter.to_bits() != q.parameter.to_bits())
                    {
                        piece.points.push(q.clone());
                    }
                    piece.points.push(stop.clone());
                    piece.stop = StopReason::Degenerate {
                        parameter: stop.parameter,
                        condition: Degeneracy::GrazingNotGlobal,
                    };
                }
            }
            // a double grazing passed before, the same way: the restarts go round in a cluster
            let here = (
                stop.first_parameter / opts.corrector.first_scale,
                stop.parameter / opts.corrector.parameter_scale,
                travel > 0.0,
            );
            let tol = opts.corrector.locate_tol;
            if passed.iter().any(|&(a, b, up)| {
                up == here.2 && (a - here.0).abs() <= tol && (b - here.1).abs() <= tol
            }) {
                break EnvelopeEnd::Cycle;
            }
            passed.push(here);
            // the extremum that is global at the stop
            let theta = match self
                .set_parameter(&opts.corrector.first, stop.first_parameter)
                .and_then(|()| self.set_parameter(&opts.corrector.parameter, stop.parameter))
                .and_then(|()| self.grazing_phase(&stop.x0, event, sgn, periods))
            {
                Ok(th) => th,
                Err(e) => break EnvelopeEnd::RestartFailed(e),
            };
            // the envelope goes on past the double grazing (a crossing of the two curves), or
            // turns back there (a corner): forward from the stop point, else back from the last
            // point where the old extremum was still global
            let mut tries = vec![(stop, travel)];
            if let Some(q) = prev {
                tries.push((q, -travel));
            }
            let mut failure = None;
            let mut next = None;
            'tries: for (p, dir) in tries {
                opts.corrector.direction = dir;
                let (mut from, mut th) = (p, theta);
                // several local extrema can lie close to the surface at once: a corrected first
                // point that is again not global hops to the extremum global on its own orbit
                for _ in 0..RESTART_HOPS {
                    let tried = self
                        .set_parameter(&opts.corrector.parameter, from.parameter)
                        .and_then(|()| {
                            self.codim2_from(&restart_at(start.kind, &from), &opts, Some(th))
                        });
                    let b = match tried {
                        Ok(b) => b,
                        Err(e) => {
                            failure = Some(e);
                            continue 'tries;
                        }
                    };
                    if !(b.points.len() <= 1 && not_global(&b)) {
                        next = Some(b);
                        break 'tries;
                    }
                    let Some(f) = b.points.first().cloned() else {
                        continue 'tries;
                    };
                    match self
                        .set_parameter(&opts.corrector.first, f.first_parameter)
                        .and_then(|()| self.set_parameter(&opts.corrector.parameter, f.parameter))
                        .and_then(|()| self.grazing_phase(&f.x0, event, sgn, periods))
                    {
                        Ok(t) => (from, th) = (f, t),
                        Err(e) => {
                            failure = Some(e);
                            continue 'tries;
                        }
                    }
                }
            }
            match (next, failure) {
                (Some(b), _) => pieces.push(b),
                (None, Some(e)) => break EnvelopeEnd::RestartFailed(e),
                (None, None) => break EnvelopeEnd::NoProgress,
            }
        };
        Ok(GrazingEnvelope { pieces, end })
    }
}

/// The start of a restarted grazing piece at a point of the piece before (the section state,
/// `λ₁` and the orbit's data; `λ₂` is set on the problem).
fn restart_at(kind: SpecialKind, p: &Codim2BranchPoint) -> SpecialPoint<ShootingPoint> {
    SpecialPoint {
        kind,
        point: BranchPoint {
            parameter: p.first_parameter,
            tangent_parameter: 0.0,
            stability: p.stability.clone(),
            orbit: ShootingPoint {
                x0: p.x0.clone(),
                floquet: p.floquet.clone(),
                monodromy: p.monodromy.clone(),
                extrema: p.extrema.clone(),
                events: p.event_counts.iter().sum(),
                event_counts: p.event_counts.clone(),
            },
        },
        after: 0,
        located: true,
        bracket: [p.first_parameter; 2],
    }
}

/// The error for a start that is not a grazing.
fn not_a_grazing<T>() -> Result<T> {
    Err(OrbitError::InvalidInput {
        field: "start.kind",
        bound: "Grazing",
        value: f64::NAN,
    })
}

/// The distance on the circle of phases `[0, 1)` between the grazing times of two points of a
/// grazing curve (each on its own period); NaN without grazing times.
fn phase_distance(a: &Codim2BranchPoint, b: &Codim2BranchPoint, t0: f64) -> f64 {
    let phase = |p: &Codim2BranchPoint| {
        p.grazing_time
            .map_or(f64::NAN, |tg| ((tg - t0) / p.period).rem_euclid(1.0))
    };
    let d = (phase(a) - phase(b)).rem_euclid(1.0);
    d.min(1.0 - d)
}
