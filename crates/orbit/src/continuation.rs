//! Pseudo-arclength continuation of periodic orbits in one parameter, with detection and
//! location of grazing, period doubling, folds and Neimark–Sacker points, and branch switching
//! at a period doubling.

use crate::error::{OrbitError, Result, check};
use crate::floquet::{Crossing, Floquet, classify_crossing, floquet, real_eigenvector};
use crate::path::{
    self, Branch, BranchPoint, ContinuationOptions, Corrector, Extremum, Node, SpecialKind,
    SpecialPoint, StepControl, StopReason, bordered_tangent,
};
use crate::problem::{OrbitProblem, Parameter};
use crate::shooting::{PeriodicOrbit, ShootingOptions};
use nalgebra::{DMatrix, DVector};
use system::SecondOrderSystem;

/// The shooting corrector's part of [`ContinuationOptions`] ([`OrbitProblem::continuation`]):
/// the parameter and its range, the scaling of the arclength, the correction limit, the
/// shooting Newton and the location of special points.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ShootingCorrection {
    /// The parameter `λ`.
    pub parameter: Parameter,
    /// The branch stops when `λ` leaves `[range[0], range[1]]`.
    pub range: [f64; 2],
    /// Initial direction of `λ`: `+1` (increasing) or `−1`.
    pub direction: f64,
    /// `λ` enters the arclength as `λ/parameter_scale`.
    pub parameter_scale: f64,
    /// The state enters the arclength as `x₀/state_scale` (choose both scales so that a typical
    /// step changes both by comparable amounts, e.g. the backlash for the state).
    pub state_scale: f64,
    /// A corrected point farther than `max_correction · Δs` from its predictor is rejected and
    /// the step halved (guards against jumping to another branch).
    pub max_correction: f64,
    /// Periods `k` (period-`k` orbits), Newton tolerance and corrector iteration cap
    /// (`segments` must be 1: the continuation shoots singly).
    pub shooting: ShootingOptions,
    /// Locate special points (secant/bisection on the test function along the arclength).
    pub locate: bool,
    /// Special points are located to this arclength tolerance (scaled variables).
    pub locate_tol: f64,
    /// Also locate [`SpecialKind::ContactChange`] points (bisection on the crossing count; an
    /// orbit spanning many mesh cycles can have dozens per branch, so off by default).
    pub locate_contact_changes: bool,
    /// Locate only special points of these kinds; the others are detected (the step that
    /// holds them, [`SpecialPoint::located`] false) but not located. A caller that reads
    /// only some kinds (say, the grazings of one event function) saves the corrector runs
    /// of the rest: locating a period doubling or a fold on a non-smooth branch can cost
    /// more than the branch. `None` (default): every kind (contact changes as
    /// [`locate_contact_changes`](Self::locate_contact_changes) says). The branch's points
    /// and its folds from the tangent ([`Branch::folds`](crate::Branch::folds)) are the same
    /// either way when the system's parameter setting depends on the value alone (a location
    /// sets the parameter back and forth; a system that carried rounding from one setting to
    /// the next would continue from a different model). A [`stop_at`](Self::stop_at) kind
    /// that is not located stops the branch at the detected point (the end of the step).
    #[cfg_attr(feature = "serde", serde(default))]
    pub locate_only: Option<Vec<SpecialKind>>,
    /// Before locating, the step is sampled at this many equal arclength pieces and the
    /// location runs in the first piece where the test function (crossing count) has left
    /// `a`'s side: on a non-smooth branch a multiplier can cross `−1` several times within one
    /// step (it jumps at every contact change), and this picks the first crossing down to the
    /// piece length. `1`: no sampling.
    pub locate_samples: usize,
    /// Stop the branch at the first special point of one of these kinds
    /// ([`StopReason::SpecialPoint`], after the step that
    /// contains it), like AUTO's `STOP` list: a branch that is wanted only up to its fold
    /// need not go on into what lies past it. Empty (default): no such stop.
    #[cfg_attr(feature = "serde", serde(default))]
    pub stop_at: Vec<SpecialKind>,
    /// Stop the branch at its first unstable point after a stable one
    /// ([`StopReason::LostStability`], with that point the branch's last): a branch wanted
    /// only up to where its orbits stop being attractors (a limit of stable orbits) need not
    /// go on into the unstable tangle past it. The special points of the step that contains
    /// the loss are still detected and located. `false` (default): no such stop.
    #[cfg_attr(feature = "serde", serde(default))]
    pub stop_at_instability: bool,
}

impl Default for ShootingCorrection {
    fn default() -> Self {
        Self {
            parameter: Parameter::BaseFrequency,
            range: [f64::NEG_INFINITY, f64::INFINITY],
            direction: 1.0,
            parameter_scale: 1.0,
            state_scale: 1.0,
            max_correction: 1.0,
            shooting: ShootingOptions {
                max_iter: 12,
                ..ShootingOptions::default()
            },
            locate: true,
            locate_tol: 1e-8,
            locate_contact_changes: false,
            locate_only: None,
            locate_samples: 1,
            stop_at: Vec::new(),
            stop_at_instability: false,
        }
    }
}

impl ShootingCorrection {
    /// Checks every field.
    ///
    /// # Errors
    /// [`OrbitError::InvalidInput`] naming the field.
    pub fn validate(&self) -> Result<()> {
        self.shooting.validate()?;
        check(
            self.shooting.segments == 1,
            "ShootingCorrection::shooting.segments",
            "1",
            self.shooting.segments as f64,
        )?;
        check(
            !self.range[0].is_nan() && !self.range[1].is_nan() && self.range[0] < self.range[1],
            "ShootingCorrection::range",
            "range[0] < range[1]",
            self.range[1],
        )?;
        check(
            self.direction.abs().to_bits() == 1.0_f64.to_bits(),
            "ShootingCorrection::direction",
            "+1 or -1",
            self.direction,
        )?;
        check(
            self.parameter_scale.is_finite() && self.parameter_scale > 0.0,
            "ShootingCorrection::parameter_scale",
            "> 0 and finite",
            self.parameter_scale,
        )?;
        check(
            self.state_scale.is_finite() && self.state_scale > 0.0,
            "ShootingCorrection::state_scale",
            "> 0 and finite",
            self.state_scale,
        )?;
        check(
            self.max_correction > 0.0,
            "ShootingCorrection::max_correction",
            "> 0",
            self.max_correction,
        )?;
        check(
            (1..=1000).contains(&self.locate_samples),
            "ShootingCorrection::locate_samples",
            "in [1, 1000]",
            self.locate_samples as f64,
        )?;
        check(
            self.locate_tol.is_finite() && self.locate_tol > 0.0,
            "ShootingCorrection::locate_tol",
            "> 0 and finite",
            self.locate_tol,
        )
    }
}

/// Settings of [`OrbitProblem::continuation`]: the one [`ContinuationOptions`] with the
/// shooting corrector's part.
pub type ShootingContinuationOptions = ContinuationOptions<ShootingCorrection>;

impl Default for ContinuationOptions<ShootingCorrection> {
    /// The shared defaults with the smallest step `1e-7` (scaled shooting variables).
    fn default() -> Self {
        Self {
            min_step: 1e-7,
            ..Self::with_corrector(ShootingCorrection::default())
        }
    }
}

impl ContinuationOptions<ShootingCorrection> {
    /// Checks every field (the shared ones and the shooting corrector's).
    ///
    /// # Errors
    /// [`OrbitError::InvalidInput`] naming the field.
    pub fn validate(&self) -> Result<()> {
        self.corrector.validate()?;
        self.validate_steps()
    }
}

/// The orbit of a shooting branch point.
#[derive(Debug, Clone, PartialEq)]
pub struct ShootingPoint {
    /// Orbit state on the section.
    pub x0: Vec<f64>,
    /// Multipliers and stability.
    pub floquet: Floquet,
    /// The monodromy matrix.
    pub monodromy: DMatrix<f64>,
    /// `[min, max]` of every event function over the orbit.
    pub extrema: Vec<[f64; 2]>,
    /// Located events per orbit period.
    pub events: usize,
    /// Located events per orbit period, by event index.
    pub event_counts: Vec<usize>,
}

/// A point of a shooting branch.
pub type ShootingBranchPoint = BranchPoint<ShootingPoint>;

/// A continued branch of period-`k` orbits by shooting.
pub type ShootingBranch = Branch<ShootingPoint>;

/// Sorted pair.
fn sorted(a: f64, b: f64) -> [f64; 2] {
    if a <= b { [a, b] } else { [b, a] }
}

/// An arclength bracket `[lo, hi]` inside a step with its two corrected points.
#[derive(Clone)]
struct Bracket {
    lo: f64,
    hi: f64,
    lo_pt: ShootingBranchPoint,
    hi_pt: ShootingBranchPoint,
}

/// A converged point with what the next step needs.
type Sol = Node<ShootingBranchPoint>;

/// The shooting corrector of the one continuation ([`path::trace`]).
struct Shooter<'a, S> {
    problem: &'a mut OrbitProblem<S>,
    opts: &'a ShootingCorrection,
    /// The stop at a special point of [`ShootingCorrection::stop_at`] found by the last step.
    stop: Option<StopReason>,
}

impl<S: SecondOrderSystem> Corrector for Shooter<'_, S> {
    type Raw = ShootingBranchPoint;
    type Point = ShootingPoint;
    type Error = OrbitError;

    fn correct(
        &mut self,
        pred: &DVector<f64>,
        border: &DVector<f64>,
        reference: &DVector<f64>,
    ) -> Result<Result<Sol>> {
        Ok(self.problem.correct(self.opts, pred, border, reference))
    }

    fn accept(&mut self, node: &Sol) -> Result<ShootingBranchPoint> {
        Ok(node.raw.clone())
    }

    fn parameter_scale(&self) -> f64 {
        self.opts.parameter_scale
    }

    fn on_step(&mut self, a: &Sol, b: &Sol, ds: f64, branch: &mut ShootingBranch) -> Result<()> {
        let before = branch.special.len();
        self.problem.detect(self.opts, a, b, ds, branch);
        self.stop = branch.special[before..]
            .iter()
            .find(|sp| self.opts.stop_at.contains(&sp.kind))
            .map(|sp| StopReason::SpecialPoint {
                parameter: sp.point.parameter,
                kind: sp.kind,
            });
        if self.stop.is_none()
            && self.opts.stop_at_instability
            && a.raw.floquet.stable
            && !b.raw.floquet.stable
        {
            self.stop = Some(StopReason::LostStability {
                parameter: b.raw.parameter,
            });
        }
        Ok(())
    }

    fn stop_after(&mut self, _node: &Sol) -> Option<StopReason> {
        self.stop.take()
    }
}

impl<S: SecondOrderSystem> OrbitProblem<S> {
    fn set_mu(&mut self, opts: &ShootingCorrection, mu: f64) -> Result<()> {
        self.set_parameter(&opts.parameter, mu * opts.parameter_scale)
    }

    /// Residual `φ_{kT}(x) − x` at `μ`, and `[Φ − I | F_μ]` if `jac`.
    fn residual(
        &mut self,
        opts: &ShootingCorrection,
        z: &DVector<f64>,
        jac: bool,
    ) -> Result<(DVector<f64>, Option<DMatrix<f64>>)> {
        let nn = self.dim();
        let k = opts.shooting.periods as f64;
        let mu = z[nn];
        let x: Vec<f64> = z.rows(0, nn).iter().map(|v| v * opts.state_scale).collect();
        self.set_mu(opts, mu)?;
        let f = self.flow(self.phase(), &x, k * self.period(), jac)?;
        let r = DVector::from_fn(nn, |i, _| f.state[i] - x[i]);
        let Some(phi) = f.jacobian else {
            return Ok((r, None));
        };
        // F_μ by central differences of the flow in μ
        let d = 1e-6 * (1.0 + mu.abs());
        let mut col = vec![0.0; nn];
        let mut ok = true;
        for (sgn, w) in [(1.0, 0.5 / d), (-1.0, -0.5 / d)] {
            let res = self
                .set_mu(opts, mu + sgn * d)
                .and_then(|_| self.flow(self.phase(), &x, k * self.period(), false));
            match res {
                Ok(fl) => {
                    for i in 0..nn {
                        col[i] += w * fl.state[i];
                    }
                }
                Err(_) => ok = false,
            }
        }
        self.set_mu(opts, mu)?;
        if !ok {
            return Err(OrbitError::NonFinite {
                what: "parameter derivative of the flow",
                time: self.phase(),
            });
        }
        let mut j = DMatrix::zeros(nn, nn + 1);
        // ∂r/∂ξ = (Φ − I) σ for the scaled state ξ = x/σ
        j.view_mut((0, 0), (nn, nn)).copy_from(&phi);
        for i in 0..nn {
            j[(i, i)] -= 1.0;
        }
        j.view_mut((0, 0), (nn, nn)).scale_mut(opts.state_scale);
        for i in 0..nn {
            j[(i, nn)] = col[i];
        }
        Ok((r, Some(j)))
    }

    /// Unit null vector of `jac` (`N × (N+1)`), oriented along `reference`.
    fn tangent_of(jac: &DMatrix<f64>, reference: &DVector<f64>) -> Result<DVector<f64>> {
        bordered_tangent(jac, reference).ok_or(OrbitError::Singular {
            what: "bordered continuation Jacobian",
        })
    }

    /// Newton corrector on `F(z) = 0`, `tᵀ(z − z_pred) = 0`; the tangent at the solution is
    /// oriented along `reference`.
    fn correct(
        &mut self,
        opts: &ShootingCorrection,
        z_pred: &DVector<f64>,
        t: &DVector<f64>,
        reference: &DVector<f64>,
    ) -> Result<Sol> {
        let nn = self.dim();
        let mut z = z_pred.clone();
        let tol = opts.shooting.tol;
        for it in 0..=opts.shooting.max_iter {
            let (r, jac) = self.residual(opts, &z, true)?;
            let jac = jac.ok_or(OrbitError::Singular {
                what: "continuation Jacobian",
            })?;
            let a = t.dot(&(&z - z_pred));
            let res = r.amax();
            let xs = z.rows(0, nn).amax() * opts.state_scale;
            if res <= tol * (1.0 + xs) && a.abs() <= tol * (1.0 + xs) {
                return self.finish_point(opts, z, jac, reference);
            }
            if it == opts.shooting.max_iter {
                return Err(OrbitError::NotConverged {
                    what: "continuation corrector",
                    iterations: it,
                    residual: res,
                });
            }
            let mut m = DMatrix::zeros(nn + 1, nn + 1);
            m.view_mut((0, 0), (nn, nn + 1)).copy_from(&jac);
            m.row_mut(nn).copy_from(&t.transpose());
            let mut rhs = DVector::zeros(nn + 1);
            rhs.rows_mut(0, nn).copy_from(&(-&r));
            rhs[nn] = -a;
            let dz = m
                .lu()
                .solve(&rhs)
                .filter(|d| d.iter().all(|v| v.is_finite()))
                .ok_or(OrbitError::Singular {
                    what: "bordered continuation Jacobian",
                })?;
            z += dz;
        }
        Err(OrbitError::NotConverged {
            what: "continuation corrector",
            iterations: opts.shooting.max_iter,
            residual: f64::NAN,
        })
    }

    fn finish_point(
        &mut self,
        opts: &ShootingCorrection,
        z: DVector<f64>,
        jac: DMatrix<f64>,
        t_ref: &DVector<f64>,
    ) -> Result<Sol> {
        let nn = self.dim();
        let tangent = Self::tangent_of(&jac, t_ref)?;
        let mut mono = jac.view((0, 0), (nn, nn)).into_owned() / opts.state_scale;
        for i in 0..nn {
            mono[(i, i)] += 1.0;
        }
        let fl = floquet(&mono)?;
        self.set_mu(opts, z[nn])?;
        let x: Vec<f64> = z.rows(0, nn).iter().map(|v| v * opts.state_scale).collect();
        let k = opts.shooting.periods;
        let fr = self.flow_recorded(self.phase(), &x, k as f64 * self.period(), false)?;
        let extrema = crate::flow::extrema(
            self.field(),
            self.flow_options(),
            &fr.pieces,
            (fr.time, &fr.state),
        );
        let point = BranchPoint {
            parameter: z[nn] * opts.parameter_scale,
            tangent_parameter: tangent[nn],
            stability: Some(fl.stability()),
            orbit: ShootingPoint {
                x0: x,
                floquet: fl,
                monodromy: mono,
                extrema,
                events: fr.events.len(),
                event_counts: (0..self.system().n_events())
                    .map(|i| fr.events.iter().filter(|e| e.index == i).count())
                    .collect(),
            },
        };
        Ok(Sol {
            y: z,
            tangent,
            iterations: 0,
            raw: point,
        })
    }

    /// Pseudo-arclength continuation of the period-`k` orbit through `x0` (a guess, refined by
    /// shooting first) at `λ = lambda0`, in [`ShootingCorrection::parameter`].
    ///
    /// Predictor `z + Δs t`, corrector Newton on `φ_{kT}(x; λ) − x = 0` bordered by
    /// `tᵀ(z − z_pred) = 0` (`z = (x/state_scale, λ/parameter_scale)`, `t` the unit tangent),
    /// step halved on failure or on a correction longer than `max_correction · Δs`, grown by
    /// 1.5 after success. Between consecutive points the test functions
    /// are checked for sign changes: the extrema of every event function (grazing), `det(Φ + I)`
    /// (period doubling), `dλ/ds` (fold) and the unit-circle count (Neimark–Sacker); each is
    /// located by Illinois on the arclength of the step (re-correcting at every trial).
    ///
    /// On return the problem's parameter is left at the last point.
    ///
    /// # Errors
    /// Invalid options or input; the first orbit does not converge.
    pub fn continuation(
        &mut self,
        x0: &[f64],
        lambda0: f64,
        options: &ShootingContinuationOptions,
    ) -> Result<ShootingBranch> {
        options.validate()?;
        let opts = &options.corrector;
        self.check_state(x0)?;
        check(lambda0.is_finite(), "lambda0", "finite", lambda0)?;
        let nn = self.dim();
        self.set_parameter(&opts.parameter, lambda0)?;
        let orbit = self.shoot(x0, &opts.shooting)?;
        let mu0 = lambda0 / opts.parameter_scale;
        let mut z = DVector::zeros(nn + 1);
        for i in 0..nn {
            z[i] = orbit.x0[i] / opts.state_scale;
        }
        z[nn] = mu0;
        let (_, jac) = self.residual(opts, &z, true)?;
        let jac = jac.ok_or(OrbitError::Singular {
            what: "continuation Jacobian",
        })?;
        let mut e = DVector::zeros(nn + 1);
        e[nn] = opts.direction;
        let first = self.finish_point(opts, z, jac, &e)?;
        let mut branch = Branch::new(opts.parameter.clone(), opts.shooting.periods);
        branch.points.push(first.raw.clone());
        let control = StepControl::shooting(
            options.initial_step,
            options.min_step,
            options.max_step,
            opts.max_correction,
        );
        let course = options.course(opts.range, opts.direction);
        let mut shooter = Shooter {
            problem: self,
            opts,
            stop: None,
        };
        path::trace(&mut shooter, first, &control, &course, &mut branch)?;
        Ok(branch)
    }

    /// Sign changes of the test functions between `a` and `b` (one step `ds` apart).
    fn detect(
        &mut self,
        opts: &ShootingCorrection,
        a: &Sol,
        b: &Sol,
        ds: f64,
        branch: &mut ShootingBranch,
    ) {
        let after = branch.points.len() - 1;
        let mut found: Vec<(f64, SpecialKind)> = vec![];
        let (pa, pb) = (&a.raw, &b.raw);
        for (i, (ea, eb)) in pa.extrema.iter().zip(&pb.extrema).enumerate() {
            for (slot, ext) in [(0usize, Extremum::Min), (1usize, Extremum::Max)] {
                if ea[slot].is_finite() && eb[slot].is_finite() && ea[slot] * eb[slot] < 0.0 {
                    found.push((
                        0.0,
                        SpecialKind::Grazing {
                            event: i,
                            extremum: ext,
                        },
                    ));
                }
            }
        }
        for (i, (ca, cb)) in pa.event_counts.iter().zip(&pb.event_counts).enumerate() {
            let grazed = found
                .iter()
                .any(|(_, k)| matches!(k, SpecialKind::Grazing { event, .. } if *event == i));
            if ca != cb && !grazed {
                found.push((0.0, SpecialKind::ContactChange { event: i }));
            }
        }
        if pa.floquet.test_period_doubling * pb.floquet.test_period_doubling < 0.0 {
            found.push((0.0, SpecialKind::PeriodDoubling));
        }
        if pa.tangent_parameter * pb.tangent_parameter < 0.0 {
            found.push((0.0, SpecialKind::Fold));
        }
        let tol = crate::floquet::STABILITY_TOLERANCE;
        if classify_crossing(&pa.floquet.multipliers, &pb.floquet.multipliers, tol)
            .contains(&Crossing::NeimarkSacker)
        {
            found.push((0.0, SpecialKind::NeimarkSacker));
        }
        let mut located = vec![];
        for (_, kind) in found {
            let detected = SpecialPoint {
                kind,
                point: b.raw.clone(),
                after,
                located: false,
                bracket: sorted(pa.parameter, pb.parameter),
            };
            let wanted = opts.locate
                && (opts.locate_contact_changes
                    || !matches!(kind, SpecialKind::ContactChange { .. }))
                && opts.locate_only.as_ref().is_none_or(|k| k.contains(&kind));
            let sp = if wanted {
                self.locate_special(opts, (a, b), ds, kind).map_or(
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
            located.push(sp);
        }
        // arclength order within the step
        located.sort_by(|x, y| {
            let d = |p: &SpecialPoint<ShootingPoint>| (p.point.parameter - a.raw.parameter).abs();
            d(x).total_cmp(&d(y))
        });
        branch.special.extend(located);
        // leave the problem at b's parameter
        let _ = self.set_mu(opts, b.y[self.dim()]);
    }

    fn test_value(kind: SpecialKind, p: &ShootingBranchPoint) -> f64 {
        match kind {
            SpecialKind::Grazing { event, extremum } => {
                let e = p.extrema.get(event).copied().unwrap_or([f64::NAN; 2]);
                match extremum {
                    Extremum::Min => e[0],
                    Extremum::Max => e[1],
                }
            }
            SpecialKind::PeriodDoubling => p.floquet.test_period_doubling,
            SpecialKind::Fold => p.tangent_parameter,
            SpecialKind::NeimarkSacker => p.floquet.test_neimark_sacker,
            SpecialKind::ContactChange { .. } => f64::NAN,
        }
    }

    /// Locates a special point inside the step `s ∈ (0, ds)` from `a`: Illinois on the test
    /// function, and, when that fails (a test function that jumps at a contact change, a
    /// corrector failure inside the step) or for a [`SpecialKind::ContactChange`], bisection
    /// on the sign of the test function (the crossing count). Returns the point, the parameter
    /// bracket and whether the arclength bracket shrank to `locate_tol`.
    fn locate_special(
        &mut self,
        opts: &ShootingCorrection,
        (a, b): (&Sol, &Sol),
        ds: f64,
        kind: SpecialKind,
    ) -> Result<(ShootingBranchPoint, [f64; 2], bool)> {
        // the first sampled piece [lo, hi] whose end has left a's side
        let (mut lo, mut lo_pt) = (0.0, a.raw.clone());
        let (mut hi, mut hi_pt) = (ds, b.raw.clone());
        for k in 1..opts.locate_samples {
            let s = ds * k as f64 / opts.locate_samples as f64;
            let Ok(p) = self.point_at(opts, a, s) else {
                continue;
            };
            match Self::same_side(kind, &a.raw, &p) {
                Some(true) => {
                    lo = s;
                    lo_pt = p;
                }
                Some(false) => {
                    hi = s;
                    hi_pt = p;
                    break;
                }
                None => {}
            }
        }
        let bracket = Bracket {
            lo,
            hi,
            lo_pt,
            hi_pt,
        };
        if !matches!(kind, SpecialKind::ContactChange { .. }) {
            if let Ok(r) = self.illinois(opts, a, bracket.clone(), kind) {
                return Ok(r);
            }
        }
        self.bisect(opts, a, bracket, kind)
    }

    /// Whether `p` is on the same side of the test function (crossing count) as `a`; `None`
    /// when undecidable (NaN).
    fn same_side(
        kind: SpecialKind,
        a: &ShootingBranchPoint,
        p: &ShootingBranchPoint,
    ) -> Option<bool> {
        match kind {
            SpecialKind::ContactChange { event } => {
                Some(p.event_counts.get(event)? == a.event_counts.get(event)?)
            }
            _ => {
                let v = Self::test_value(kind, a) * Self::test_value(kind, p);
                v.is_finite().then_some(v > 0.0)
            }
        }
    }

    /// The corrected point at arclength `s` of the step from `a`.
    /// The corrected point at arclength `s` of the step from `a`, rejected (like a step) when
    /// the corrector moved farther than `max_correction · max(s, locate_tol)` from the
    /// predictor (it jumped to another branch).
    fn point_at(
        &mut self,
        opts: &ShootingCorrection,
        a: &Sol,
        s: f64,
    ) -> Result<ShootingBranchPoint> {
        let pred = &a.y + &a.tangent * s;
        let sol = self.correct(opts, &pred, &a.tangent, &a.tangent)?;
        let dist = (&sol.y - &pred).norm();
        if dist > opts.max_correction * s.max(opts.locate_tol) {
            return Err(OrbitError::NotConverged {
                what: "special point location (corrector left the step)",
                iterations: 0,
                residual: dist,
            });
        }
        Ok(sol.raw)
    }

    /// Illinois on the arclength bracket of the step from `a`.
    fn illinois(
        &mut self,
        opts: &ShootingCorrection,
        a: &Sol,
        br: Bracket,
        kind: SpecialKind,
    ) -> Result<(ShootingBranchPoint, [f64; 2], bool)> {
        let (mut lo, mut hi) = (br.lo, br.hi);
        let mut flo = Self::test_value(kind, &br.lo_pt);
        let mut best = br.hi_pt;
        let mut fhi = Self::test_value(kind, &best);
        let (mut plo, mut phi) = (br.lo_pt.parameter, best.parameter);
        if flo * fhi >= 0.0 || (flo * fhi).is_nan() {
            return Err(OrbitError::NotConverged {
                what: "special point location (no sign change)",
                iterations: 0,
                residual: fhi,
            });
        }
        let mut side = 0i8;
        for _ in 0..60 {
            if hi - lo <= opts.locate_tol {
                return Ok((best, sorted(plo, phi), true));
            }
            let mut s = hi - fhi * (hi - lo) / (fhi - flo);
            if !(s > lo && s < hi) {
                s = 0.5 * (lo + hi);
            }
            let p = self.point_at(opts, a, s)?;
            let f = Self::test_value(kind, &p);
            if f.is_nan() {
                return Err(OrbitError::NonFinite {
                    what: "test function",
                    time: self.phase(),
                });
            }
            if f.to_bits() == 0.0_f64.to_bits() {
                let l = p.parameter;
                return Ok((p, [l, l], true));
            }
            if f * flo > 0.0 {
                lo = s;
                flo = f;
                plo = p.parameter;
                if side == -1 {
                    fhi *= 0.5;
                }
                side = -1;
            } else {
                hi = s;
                fhi = f;
                phi = p.parameter;
                if side == 1 {
                    flo *= 0.5;
                }
                side = 1;
            }
            best = p;
        }
        // a test function that jumps (non-smooth) converges slowly: hand over to bisection
        Err(OrbitError::NotConverged {
            what: "special point location (Illinois)",
            iterations: 60,
            residual: hi - lo,
        })
    }

    /// Bisection on the arclength bracket of the step from `a`: the indicator is the side of
    /// the test function (for a contact change: whether the crossing count still equals
    /// `a`'s). A corrector failure at every trial point stops the bisection with the bracket
    /// reached so far.
    fn bisect(
        &mut self,
        opts: &ShootingCorrection,
        a: &Sol,
        br: Bracket,
        kind: SpecialKind,
    ) -> Result<(ShootingBranchPoint, [f64; 2], bool)> {
        let mut hi_pt = br.hi_pt;
        if Self::same_side(kind, &a.raw, &hi_pt) != Some(false) {
            return Err(OrbitError::NotConverged {
                what: "special point location (no change across the step)",
                iterations: 0,
                residual: f64::NAN,
            });
        }
        let (mut lo, mut hi) = (br.lo, br.hi);
        let mut plo = br.lo_pt.parameter;
        for _ in 0..80 {
            if hi - lo <= opts.locate_tol {
                let b = sorted(plo, hi_pt.parameter);
                return Ok((hi_pt, b, true));
            }
            // Newton can stall next to a grazing (the flow is only C¹ there): try other
            // interior points of the bracket before giving up
            let trial = [0.5, 0.3, 0.7, 0.15, 0.85].into_iter().find_map(|f| {
                let s = lo + f * (hi - lo);
                self.point_at(opts, a, s).ok().map(|p| (s, p))
            });
            let Some((s, p)) = trial else {
                break;
            };
            match Self::same_side(kind, &a.raw, &p) {
                Some(true) => {
                    lo = s;
                    plo = p.parameter;
                }
                Some(false) => {
                    hi = s;
                    hi_pt = p;
                }
                None => break,
            }
        }
        let b = sorted(plo, hi_pt.parameter);
        Ok((hi_pt, b, hi - lo <= opts.locate_tol))
    }

    /// Branch switching at a period doubling of a period-`k` branch: with `v` the eigenvector
    /// of the monodromy for the multiplier `−1`, shoots a period-`2k` orbit from
    /// `x_PD ± h v` at `λ_PD ± offset` (trying both sides of the parameter, both signs and
    /// `h`, `4h`, `16h`) and
    /// returns the first orbit that is not the period-`k` orbit, with its `λ`. The problem is
    /// left at that `λ`.
    ///
    /// # Errors
    /// Invalid input, eigenvector failure, or no period-`2k` orbit found.
    pub fn switch_at_period_doubling(
        &mut self,
        pd: &ShootingBranchPoint,
        parameter: &Parameter,
        periods: usize,
        h: f64,
        offset: f64,
        shooting: &ShootingOptions,
    ) -> Result<(f64, PeriodicOrbit)> {
        check(h.is_finite() && h > 0.0, "h", "> 0 and finite", h)?;
        check(
            offset.is_finite() && offset > 0.0,
            "offset",
            "> 0 and finite",
            offset,
        )?;
        self.check_state(&pd.x0)?;
        let v = real_eigenvector(&pd.monodromy, -1.0)?;
        let opts2 = ShootingOptions {
            periods: 2 * periods,
            ..*shooting
        };
        let mut last = OrbitError::NotConverged {
            what: "period-doubling branch switch",
            iterations: 0,
            residual: f64::NAN,
        };
        let trials = [offset, -offset]
            .into_iter()
            .flat_map(|dl| [h, 4.0 * h, 16.0 * h].map(move |hh| (dl, hh)))
            .flat_map(|(dl, hh)| [(dl, hh, 1.0), (dl, hh, -1.0)]);
        for (dl, hh, sgn) in trials {
            let lam = pd.parameter + dl;
            self.set_parameter(parameter, lam)?;
            {
                let x: Vec<f64> = pd
                    .x0
                    .iter()
                    .zip(v.iter())
                    .map(|(a, b)| a + sgn * hh * b)
                    .collect();
                match self.shoot(&x, &opts2) {
                    Ok(o) => {
                        let f =
                            self.flow(self.phase(), &o.x0, periods as f64 * self.period(), false)?;
                        let gap = f
                            .state
                            .iter()
                            .zip(&o.x0)
                            .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
                        let scale = o.x0.iter().fold(1.0_f64, |m, a| m.max(a.abs()));
                        if gap > 1e3 * shooting.tol * scale {
                            return Ok((lam, o));
                        }
                    }
                    Err(e) => last = e,
                }
            }
        }
        Err(last)
    }
}
