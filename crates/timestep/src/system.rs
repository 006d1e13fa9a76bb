//! The problem traits: first-order systems with event functions, and second-order systems in
//! explicit form `q'' = a(t, q, q')`; and [`Mechanical`], the adapter that integrates the shared
//! system description `M q'' + C q' + K q + g(t, q, q') = f(t)` of `geardyn-system` (the same
//! model value the harmonic balance engine solves).

pub use ::system::Direction;

/// What the integrator does after an event has been located and the step restarted there.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum EventAction {
    /// Record the event and continue from the event point (switching surface).
    Continue,
    /// Record the event and stop the integration at the event point.
    Stop,
}

/// A first-order system `y' = F(t, y)` with optional event functions `g_i(t, y)`.
///
/// State vectors are plain slices of length [`OdeSystem::dim`], so that the same code serves a
/// 2-state 1-DOF oscillator and a 12-state 6-DOF model without generic dimension parameters and
/// without allocation per step.
///
/// Event functions (switching surfaces such as the backlash gap edges `x = ±b`, or Poincaré
/// surfaces) are located on the integrator's dense output whenever one changes sign in an
/// accepted step; the step is then restarted so that it ends on the surface (see
/// [`crate::integrate`]).
pub trait OdeSystem {
    /// Number of states.
    fn dim(&self) -> usize;

    /// Right-hand side: writes `F(t, y)` into `dydt` (both of length `dim`).
    fn rhs(&self, t: f64, y: &[f64], dydt: &mut [f64]);

    /// Number of event functions (default 0).
    fn n_events(&self) -> usize {
        0
    }

    /// Event functions: writes `g_i(t, y)` into `g` (length [`OdeSystem::n_events`]).
    /// Each must be continuous along a trajectory; its zeros are the events.
    fn events(&self, _t: f64, _y: &[f64], _g: &mut [f64]) {}

    /// Which crossings of event function `index` are located and reported (default both).
    /// Crossings filtered out here do not restart the step.
    fn event_direction(&self, _index: usize) -> Direction {
        Direction::Both
    }

    /// Called once per located event, at the event point. May modify the state (an impact
    /// law such as `v -> -e v`); returns whether to continue. Default: continue, no change.
    fn on_event(&self, _event: &crate::Event, _y: &mut [f64]) -> EventAction {
        EventAction::Continue
    }
}

impl<S: OdeSystem + ?Sized> OdeSystem for &S {
    fn dim(&self) -> usize {
        (**self).dim()
    }
    fn rhs(&self, t: f64, y: &[f64], dydt: &mut [f64]) {
        (**self).rhs(t, y, dydt)
    }
    fn n_events(&self) -> usize {
        (**self).n_events()
    }
    fn events(&self, t: f64, y: &[f64], g: &mut [f64]) {
        (**self).events(t, y, g)
    }
    fn event_direction(&self, index: usize) -> Direction {
        (**self).event_direction(index)
    }
    fn on_event(&self, event: &crate::Event, y: &mut [f64]) -> EventAction {
        (**self).on_event(event, y)
    }
}

/// A second-order system in explicit form, `q'' = a(t, q, q')`, with `n` degrees of freedom:
/// for users who write accelerations directly. (A model written as `M q'' + C q' + K q + g = f`
/// implements `system::SecondOrderSystem` instead and is integrated through [`Mechanical`].)
///
/// Wrap it in [`FirstOrder`] to integrate it; the first-order state is `y = [q; q']`
/// (positions first, then velocities).
pub trait ExplicitSecondOrder {
    /// Number of degrees of freedom `n` (the first-order state has `2n` entries).
    fn ndof(&self) -> usize;

    /// Accelerations: writes `a(t, q, v)` into `acc` (all slices of length `n`).
    fn acceleration(&self, t: f64, q: &[f64], v: &[f64], acc: &mut [f64]);

    /// Number of event functions (default 0).
    fn n_events(&self) -> usize {
        0
    }

    /// Event functions `g_i(t, q, v)`.
    fn events(&self, _t: f64, _q: &[f64], _v: &[f64], _g: &mut [f64]) {}

    /// Direction filter of event `index` (default both).
    fn event_direction(&self, _index: usize) -> Direction {
        Direction::Both
    }

    /// Event hook; may change positions and velocities (impact laws).
    fn on_event(&self, _event: &crate::Event, _q: &mut [f64], _v: &mut [f64]) -> EventAction {
        EventAction::Continue
    }
}

/// Adapter that turns an [`ExplicitSecondOrder`] into an [`OdeSystem`] with `y = [q; q']`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FirstOrder<S>(pub S);

impl<S: ExplicitSecondOrder> OdeSystem for FirstOrder<S> {
    fn dim(&self) -> usize {
        2 * self.0.ndof()
    }
    fn rhs(&self, t: f64, y: &[f64], dydt: &mut [f64]) {
        let n = self.0.ndof();
        let (q, v) = y.split_at(n);
        let (dq, dv) = dydt.split_at_mut(n);
        dq.copy_from_slice(v);
        self.0.acceleration(t, q, v, dv);
    }
    fn n_events(&self) -> usize {
        self.0.n_events()
    }
    fn events(&self, t: f64, y: &[f64], g: &mut [f64]) {
        let n = self.0.ndof();
        let (q, v) = y.split_at(n);
        self.0.events(t, q, v, g)
    }
    fn event_direction(&self, index: usize) -> Direction {
        self.0.event_direction(index)
    }
    fn on_event(&self, event: &crate::Event, y: &mut [f64]) -> EventAction {
        let n = self.0.ndof();
        let (q, v) = y.split_at_mut(n);
        self.0.on_event(event, q, v)
    }
}

pub use ::system::gap_edges;

/// A closure-based [`OdeSystem`] without events: `FnSystem::new(dim, |t, y, dy| ...)`.
#[derive(Debug, Clone, Copy)]
pub struct FnSystem<F> {
    dim: usize,
    f: F,
}

impl<F: Fn(f64, &[f64], &mut [f64])> FnSystem<F> {
    /// Wraps `f(t, y, dydt)` as a system with `dim` states.
    pub fn new(dim: usize, f: F) -> Self {
        Self { dim, f }
    }
}

impl<F: Fn(f64, &[f64], &mut [f64])> OdeSystem for FnSystem<F> {
    fn dim(&self) -> usize {
        self.dim
    }
    fn rhs(&self, t: f64, y: &[f64], dydt: &mut [f64]) {
        (self.f)(t, y, dydt)
    }
}

/// Entries up to which [`Mechanical`] keeps its work vectors on the stack.
const STACK_DOF: usize = 16;

/// Adapter that integrates a model written once for the shared system description
/// [`system::SecondOrderSystem`],
/// `M q'' + C q' + K q + g(t, q, q') = f(t)`, as an [`ExplicitSecondOrder`]
///
/// ```text
/// q'' = M⁻¹ (f(t) − C q' − K q − g(t, q, q'))
/// ```
///
/// with the system's contact-event functions and directions passed through. `M⁻¹`, `C` and `K`
/// are read once in [`Mechanical::new`]; an identity `M` and zero `C`, `K` are recognised and
/// skipped, so a model with `M = I`, `C = K = 0` gets `q'' = f − g` exactly. Wrap the result in
/// [`FirstOrder`] to integrate: `integrate(&FirstOrder(Mechanical::new(model)?), …)`.
#[derive(Debug, Clone, PartialEq)]
pub struct Mechanical<S> {
    system: S,
    n: usize,
    m_inv: Option<Vec<f64>>,
    c: Option<Vec<f64>>,
    k: Option<Vec<f64>>,
}

impl<S: ::system::SecondOrderSystem> Mechanical<S> {
    /// Reads `M`, `C`, `K` of `system` and inverts `M`.
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`](crate::Error::DimensionMismatch) for a matrix that is not
    /// `n × n`, [`Error::NonFinite`](crate::Error::NonFinite) for a NaN or infinite entry, and
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) (name `mass matrix`, value
    /// its determinant) for a singular `M`.
    pub fn new(system: S) -> Result<Self, crate::Error> {
        let n = system.n_dof();
        let read = |name: &'static str, m: nalgebra::DMatrix<f64>| {
            if m.nrows() != n || m.ncols() != n {
                return Err(crate::Error::DimensionMismatch {
                    name,
                    expected: n * n,
                    got: m.nrows() * m.ncols(),
                });
            }
            if let Some(index) = m.iter().position(|x| !x.is_finite()) {
                return Err(crate::Error::NonFinite { name, index });
            }
            Ok(m)
        };
        let m = read("mass matrix", system.mass())?;
        let c = read("damping matrix", system.damping())?;
        let k = read("stiffness matrix", system.stiffness())?;
        let m_inv = if m == nalgebra::DMatrix::identity(n, n) {
            None
        } else {
            let inv = m
                .clone()
                .try_inverse()
                .filter(|i| i.iter().all(|x| x.is_finite()));
            let Some(inv) = inv else {
                return Err(crate::Error::InvalidParameter {
                    name: "mass matrix",
                    bound: "invertible",
                    value: m.determinant(),
                });
            };
            Some(row_major(&inv))
        };
        let nonzero = |m: &nalgebra::DMatrix<f64>| m.iter().any(|&x| x != 0.0);
        Ok(Mechanical {
            n,
            m_inv,
            c: nonzero(&c).then(|| row_major(&c)),
            k: nonzero(&k).then(|| row_major(&k)),
            system,
        })
    }

    /// The wrapped system.
    pub fn system(&self) -> &S {
        &self.system
    }

    /// The wrapped system, by value.
    pub fn into_inner(self) -> S {
        self.system
    }

    fn accelerate(&self, t: f64, q: &[f64], v: &[f64], g: &mut [f64], acc: &mut [f64]) {
        let n = self.n;
        // r = f − C v − K q − g, accumulated in `acc` (in this order), then acc = M⁻¹ r
        self.system.forcing(t, acc);
        self.system.nonlinear_force(t, q, v, g);
        for (matrix, x) in [(&self.c, v), (&self.k, q)] {
            if let Some(m) = matrix {
                for (i, a) in acc.iter_mut().enumerate() {
                    let row = &m[i * n..(i + 1) * n];
                    *a -= row.iter().zip(x).map(|(mij, xj)| mij * xj).sum::<f64>();
                }
            }
        }
        for (a, gi) in acc.iter_mut().zip(g.iter()) {
            *a -= gi;
        }
        if let Some(m_inv) = &self.m_inv {
            g.copy_from_slice(acc);
            for (i, a) in acc.iter_mut().enumerate() {
                let row = &m_inv[i * n..(i + 1) * n];
                *a = row.iter().zip(g.iter()).map(|(mij, rj)| mij * rj).sum();
            }
        }
    }
}

fn row_major(m: &nalgebra::DMatrix<f64>) -> Vec<f64> {
    let (r, c) = m.shape();
    (0..r)
        .flat_map(|i| (0..c).map(move |j| m[(i, j)]))
        .collect()
}

impl<S: ::system::SecondOrderSystem> ExplicitSecondOrder for Mechanical<S> {
    fn ndof(&self) -> usize {
        self.n
    }
    fn acceleration(&self, t: f64, q: &[f64], v: &[f64], acc: &mut [f64]) {
        if self.n <= STACK_DOF {
            let mut g = [0.0; STACK_DOF];
            self.accelerate(t, q, v, &mut g[..self.n], acc);
        } else {
            let mut g = vec![0.0; self.n];
            self.accelerate(t, q, v, &mut g, acc);
        }
    }
    fn n_events(&self) -> usize {
        self.system.n_events()
    }
    fn events(&self, t: f64, q: &[f64], v: &[f64], g: &mut [f64]) {
        self.system.events(t, q, v, g)
    }
    fn event_direction(&self, index: usize) -> Direction {
        self.system.event_direction(index)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use math::DetMath;
    use nalgebra::DMatrix;

    /// `M q'' + C q' + K q + g = f` with full 2 × 2 matrices and a cubic `g`.
    struct TwoDof;
    impl ::system::SecondOrderSystem for TwoDof {
        fn n_dof(&self) -> usize {
            2
        }
        fn mass(&self) -> DMatrix<f64> {
            DMatrix::from_row_slice(2, 2, &[2.0, 0.5, 0.5, 1.0])
        }
        fn damping(&self) -> DMatrix<f64> {
            DMatrix::from_row_slice(2, 2, &[0.1, -0.1, -0.1, 0.2])
        }
        fn stiffness(&self) -> DMatrix<f64> {
            DMatrix::from_row_slice(2, 2, &[3.0, -1.0, -1.0, 2.0])
        }
        fn nonlinear_force(&self, _t: f64, q: &[f64], _qd: &[f64], g: &mut [f64]) {
            g[0] = q[0].powi(3);
            g[1] = 0.0;
        }
        fn forcing(&self, t: f64, f: &mut [f64]) {
            f[0] = t.dcos();
            f[1] = 0.5;
        }
        fn n_events(&self) -> usize {
            2
        }
        fn events(&self, _t: f64, q: &[f64], _qd: &[f64], e: &mut [f64]) {
            gap_edges(q[1], 0.25, e)
        }
    }

    #[test]
    fn mechanical_solves_the_balance_for_the_accelerations() {
        let m = Mechanical::new(TwoDof).unwrap();
        let (t, q, v) = (0.7, [0.3, -0.2], [1.1, 0.4]);
        let mut a = [0.0; 2];
        m.acceleration(t, &q, &v, &mut a);
        // residual of M a + C v + K q + g − f must vanish
        let s = TwoDof;
        let (mm, c, k) = (
            ::system::SecondOrderSystem::mass(&s),
            ::system::SecondOrderSystem::damping(&s),
            ::system::SecondOrderSystem::stiffness(&s),
        );
        let r = &mm * nalgebra::DVector::from_row_slice(&a)
            + &c * nalgebra::DVector::from_row_slice(&v)
            + &k * nalgebra::DVector::from_row_slice(&q);
        let expected = [t.dcos() - q[0].powi(3), 0.5];
        for i in 0..2 {
            assert!((r[i] - expected[i]).abs() < 1e-14, "row {i}: {}", r[i]);
        }
        let mut e = [0.0; 2];
        m.events(t, &q, &v, &mut e);
        assert!(
            (e[0] + 0.45).abs() < 1e-15 && (e[1] - 0.05).abs() < 1e-15,
            "{e:?}"
        );
        assert_eq!(m.n_events(), 2);
        assert_eq!(m.ndof(), 2);
    }

    struct Singular(usize);
    impl ::system::SecondOrderSystem for Singular {
        fn n_dof(&self) -> usize {
            2
        }
        fn mass(&self) -> DMatrix<f64> {
            DMatrix::from_row_slice(2, 2, &[1.0, 1.0, 1.0, 1.0])
        }
        fn damping(&self) -> DMatrix<f64> {
            DMatrix::zeros(self.0, self.0)
        }
        fn nonlinear_force(&self, _t: f64, _q: &[f64], _qd: &[f64], g: &mut [f64]) {
            g.fill(0.0);
        }
        fn forcing(&self, _t: f64, f: &mut [f64]) {
            f.fill(0.0);
        }
    }

    #[test]
    fn mechanical_rejects_bad_matrices() {
        // shapes are checked before M is inverted
        assert!(matches!(
            Mechanical::new(Singular(1)),
            Err(crate::Error::DimensionMismatch {
                name: "damping matrix",
                ..
            })
        ));
        assert!(matches!(
            Mechanical::new(Singular(2)),
            Err(crate::Error::InvalidParameter {
                name: "mass matrix",
                ..
            })
        ));
    }
}
