//! This crate's own one-step schemes: embedded Dormand–Prince 5(4) with dense output and
//! classical RK4 (the workspace's one step, `geardyn_system::rk4`) with cubic Hermite dense
//! output. Work buffers are allocated once per
//! integration, never per step.
//!
//! The work buffers are generic over [`Buf`]: a `Vec<f64>` for any dimension, or a fixed-size
//! array `[f64; N]` for the small dimensions the driver dispatches on (1-DOF and 2-DOF models),
//! where the stage loops unroll and lose their bounds checks. Both perform the same arithmetic
//! in the same order, so the results are bit-identical.

use crate::system::OdeSystem;

/// Storage of one state-sized work vector.
pub(crate) trait Buf: Clone + AsRef<[f64]> + AsMut<[f64]> {
    /// A zero vector of length `n` (a fixed-size array ignores `n`; the driver only picks one
    /// whose length is `n`).
    fn zeros(n: usize) -> Self;
}

impl Buf for Vec<f64> {
    fn zeros(n: usize) -> Self {
        vec![0.0; n]
    }
}

impl<const N: usize> Buf for [f64; N] {
    fn zeros(_n: usize) -> Self {
        [0.0; N]
    }
}

/// A one-step scheme with dense output, driven by [`crate::integrate`].
pub(crate) trait Stepper {
    /// Order of the propagated solution (Hairer's `hinit` uses it for the starting step).
    const ORDER: f64;
    /// The constants of its step-size controller ([`crate::control::PiController`]).
    const CONTROL: crate::control::ControlParams;
    /// Sets `f0 = F(t, y)` (call at the start and after a state change).
    fn init<S: OdeSystem + ?Sized>(&mut self, sys: &S, t: f64, y: &[f64]);
    /// Attempts a step of size `h` from `(t, y)` (with `f0 = F(t, y)` already set). Writes the
    /// new state internally and returns the *square* of the scaled error norm (0 for fixed-step
    /// schemes): the controller needs only `log₂ err = ½ log₂ err²` and the test `err ≤ 1`,
    /// so a square root on every step's critical path is saved.
    fn attempt<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &S,
        t: f64,
        y: &[f64],
        h: f64,
        rtol: f64,
        atol: f64,
    ) -> f64;
    /// The state computed by the last `attempt`.
    fn y_new(&self) -> &[f64];
    /// Builds the dense-output coefficients of the last attempted step from `(t, y)` of size
    /// `h` (after acceptance). Schemes whose continuous extension needs extra stages evaluate
    /// them here (and count them in [`Stepper::n_rhs`]).
    fn prepare_dense<S: OdeSystem + ?Sized>(&mut self, sys: &S, t: f64, y: &[f64], h: f64);
    /// Evaluates the dense output at `theta` in [0, 1] of the prepared step.
    fn dense(&self, theta: f64, out: &mut [f64]);
    /// Makes `F(t+h, y_new)` the `f0` of the next step (first-same-as-last).
    fn advance(&mut self);
    /// Number of right-hand-side evaluations so far.
    fn n_rhs(&self) -> u64;
}

// Dormand–Prince 5(4) coefficients (Hairer, Nørsett & Wanner, Solving ODEs I, Table 5.2)
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const B1: f64 = 35.0 / 384.0;
const B3: f64 = 500.0 / 1113.0;
const B4: f64 = 125.0 / 192.0;
const B5: f64 = -2187.0 / 6784.0;
const B6: f64 = 11.0 / 84.0;
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
// dense output (Hairer's DOPRI5 `contd5`)
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

/// Work buffers shared by the explicit Runge–Kutta steppers: `S` stage derivatives (`k[0]` is
/// `F(t, y)` at the start of a step), a stage state, the new state and the evaluation count.
#[derive(Debug, Clone)]
pub(crate) struct Stages<const S: usize, B> {
    pub(crate) k: [B; S],
    pub(crate) ytmp: B,
    pub(crate) ynew: B,
    pub(crate) n_rhs: u64,
}

impl<const S: usize, B: Buf> Stages<S, B> {
    pub(crate) fn new(n: usize) -> Self {
        Self {
            k: std::array::from_fn(|_| B::zeros(n)),
            ytmp: B::zeros(n),
            ynew: B::zeros(n),
            n_rhs: 0,
        }
    }

    /// `k[0] = F(t, y)` ([`Stepper::init`]).
    pub(crate) fn init<Sys: OdeSystem + ?Sized>(&mut self, sys: &Sys, t: f64, y: &[f64]) {
        sys.rhs(t, y, self.k[0].as_mut());
        self.n_rhs += 1;
    }
}

/// Embedded Dormand–Prince 5(4), FSAL, 4th-order continuous extension.
#[derive(Debug, Clone)]
pub(crate) struct DormandPrince<B = Vec<f64>> {
    st: Stages<7, B>,
    r: [B; 5],
}

impl<B: Buf> DormandPrince<B> {
    pub(crate) fn new(n: usize) -> Self {
        Self {
            st: Stages::new(n),
            r: std::array::from_fn(|_| B::zeros(n)),
        }
    }
}

impl<B: Buf> Stepper for DormandPrince<B> {
    const ORDER: f64 = 5.0;
    const CONTROL: crate::control::ControlParams = crate::control::DOPRI5_CONTROL;

    fn init<S: OdeSystem + ?Sized>(&mut self, sys: &S, t: f64, y: &[f64]) {
        self.st.init(sys, t, y);
    }

    fn attempt<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &S,
        t: f64,
        y: &[f64],
        h: f64,
        rtol: f64,
        atol: f64,
    ) -> f64 {
        let [k1, k2, k3, k4, k5, k6, k7] = &mut self.st.k;
        let (k1, k2, k3, k4) = (k1.as_mut(), k2.as_mut(), k3.as_mut(), k4.as_mut());
        let (k5, k6, k7) = (k5.as_mut(), k6.as_mut(), k7.as_mut());
        let yt = self.st.ytmp.as_mut();
        // one length for every buffer: a compile-time constant for arrays, and no bounds
        // checks in the loops below
        let n = yt.len();
        let y = &y[..n];
        let (k1, k2, k3, k4) = (&mut k1[..n], &mut k2[..n], &mut k3[..n], &mut k4[..n]);
        let (k5, k6, k7) = (&mut k5[..n], &mut k6[..n], &mut k7[..n]);
        for i in 0..n {
            yt[i] = y[i] + h * A21 * k1[i];
        }
        sys.rhs(t + C2 * h, yt, k2);
        for i in 0..n {
            yt[i] = y[i] + h * (A31 * k1[i] + A32 * k2[i]);
        }
        sys.rhs(t + C3 * h, yt, k3);
        for i in 0..n {
            yt[i] = y[i] + h * (A41 * k1[i] + A42 * k2[i] + A43 * k3[i]);
        }
        sys.rhs(t + C4 * h, yt, k4);
        for i in 0..n {
            yt[i] = y[i] + h * (A51 * k1[i] + A52 * k2[i] + A53 * k3[i] + A54 * k4[i]);
        }
        sys.rhs(t + C5 * h, yt, k5);
        for i in 0..n {
            yt[i] =
                y[i] + h * (A61 * k1[i] + A62 * k2[i] + A63 * k3[i] + A64 * k4[i] + A65 * k5[i]);
        }
        sys.rhs(t + h, yt, k6);
        let yn = &mut self.st.ynew.as_mut()[..n];
        for i in 0..n {
            yn[i] = y[i] + h * (B1 * k1[i] + B3 * k3[i] + B4 * k4[i] + B5 * k5[i] + B6 * k6[i]);
        }
        sys.rhs(t + h, yn, k7);
        self.st.n_rhs += 6;
        let mut err = 0.0;
        for i in 0..n {
            let e =
                h * (E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i] + E7 * k7[i]);
            let sk = atol + rtol * y[i].abs().max(yn[i].abs());
            err += (e / sk) * (e / sk);
        }
        // err² (the trait's convention)
        err / n.max(1) as f64
    }

    fn y_new(&self) -> &[f64] {
        self.st.ynew.as_ref()
    }

    fn prepare_dense<S: OdeSystem + ?Sized>(&mut self, _sys: &S, _t: f64, y: &[f64], h: f64) {
        let ynew = self.st.ynew.as_ref();
        let n = ynew.len();
        let y = &y[..n];
        let [k1, _k2, k3, k4, k5, k6, k7] = &self.st.k;
        let (k1, k3, k4) = (&k1.as_ref()[..n], &k3.as_ref()[..n], &k4.as_ref()[..n]);
        let (k5, k6, k7) = (&k5.as_ref()[..n], &k6.as_ref()[..n], &k7.as_ref()[..n]);
        let [r1, r2, r3, r4, r5] = &mut self.r;
        let (r1, r2, r3) = (
            &mut r1.as_mut()[..n],
            &mut r2.as_mut()[..n],
            &mut r3.as_mut()[..n],
        );
        let (r4, r5) = (&mut r4.as_mut()[..n], &mut r5.as_mut()[..n]);
        for i in 0..n {
            let ydiff = ynew[i] - y[i];
            let bspl = h * k1[i] - ydiff;
            r1[i] = y[i];
            r2[i] = ydiff;
            r3[i] = bspl;
            r4[i] = ydiff - h * k7[i] - bspl;
            r5[i] =
                h * (D1 * k1[i] + D3 * k3[i] + D4 * k4[i] + D5 * k5[i] + D6 * k6[i] + D7 * k7[i]);
        }
    }

    fn dense(&self, theta: f64, out: &mut [f64]) {
        let th1 = 1.0 - theta;
        let [r1, r2, r3, r4, r5] = &self.r;
        let n = r1.as_ref().len();
        let out = &mut out[..n];
        let (r1, r2, r3) = (&r1.as_ref()[..n], &r2.as_ref()[..n], &r3.as_ref()[..n]);
        let (r4, r5) = (&r4.as_ref()[..n], &r5.as_ref()[..n]);
        for i in 0..n {
            out[i] = r1[i] + theta * (r2[i] + th1 * (r3[i] + theta * (r4[i] + th1 * r5[i])));
        }
    }

    fn advance(&mut self) {
        self.st.k.swap(0, 6);
    }

    fn n_rhs(&self) -> u64 {
        self.st.n_rhs
    }
}

/// Classical RK4 with a cubic Hermite interpolant (5 evaluations per step: the end-point
/// derivative is needed for the interpolant and reused as the next step's first stage).
#[derive(Debug, Clone)]
pub(crate) struct ClassicRk4 {
    st: Stages<5, Vec<f64>>,
    y0: Vec<f64>,
    h: f64,
}

impl ClassicRk4 {
    pub(crate) fn new(n: usize) -> Self {
        Self {
            st: Stages::new(n),
            y0: vec![0.0; n],
            h: 0.0,
        }
    }
}

/// Fixed steps: the controller constants are never read (the driver skips step control).
impl Stepper for ClassicRk4 {
    const ORDER: f64 = 5.0;
    const CONTROL: crate::control::ControlParams = crate::control::DOPRI5_CONTROL;

    fn init<S: OdeSystem + ?Sized>(&mut self, sys: &S, t: f64, y: &[f64]) {
        self.st.init(sys, t, y);
    }

    fn attempt<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &S,
        t: f64,
        y: &[f64],
        h: f64,
        _rtol: f64,
        _atol: f64,
    ) -> f64 {
        let [k1, k2, k3, k4, k5] = &mut self.st.k;
        let stages = ::system::rk4::Rk4Stages {
            k1,
            k2,
            k3,
            k4,
            stage: &mut self.st.ytmp,
        };
        let yn = &mut self.st.ynew;
        ::system::rk4::rk4_step(|t, y, d| sys.rhs(t, y, d), t, h, y, stages, yn);
        sys.rhs(t + h, yn, k5);
        self.st.n_rhs += 4;
        if yn.iter().all(|v| v.is_finite()) {
            0.0
        } else {
            f64::NAN
        }
    }

    fn y_new(&self) -> &[f64] {
        &self.st.ynew
    }

    fn prepare_dense<S: OdeSystem + ?Sized>(&mut self, _sys: &S, _t: f64, y: &[f64], h: f64) {
        self.y0.copy_from_slice(y);
        self.h = h;
    }

    fn dense(&self, theta: f64, out: &mut [f64]) {
        let k = &self.st.k;
        hermite(theta, self.h, &self.y0, &k[0], &self.st.ynew, &k[4], out);
    }

    fn advance(&mut self) {
        self.st.k.swap(0, 4);
    }

    fn n_rhs(&self) -> u64 {
        self.st.n_rhs
    }
}

/// Cubic Hermite interpolation between `(y0, f0)` and `(y1, f1)` over a step `h`.
pub(crate) fn hermite(
    theta: f64,
    h: f64,
    y0: &[f64],
    f0: &[f64],
    y1: &[f64],
    f1: &[f64],
    out: &mut [f64],
) {
    let t2 = theta * theta;
    let t3 = t2 * theta;
    let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
    let h10 = t3 - 2.0 * t2 + theta;
    let h01 = -2.0 * t3 + 3.0 * t2;
    let h11 = t3 - t2;
    for i in 0..out.len() {
        out[i] = h00 * y0[i] + h10 * h * f0[i] + h01 * y1[i] + h11 * h * f1[i];
    }
}
