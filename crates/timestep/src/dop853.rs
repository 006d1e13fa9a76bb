//! This crate's own DOP853: the explicit Runge–Kutta pair of order 8 with error estimators of
//! orders 5 and 3 and a continuous extension of order 7 (Hairer, Nørsett & Wanner, *Solving
//! ODEs I*, 2nd ed., 1993, §II.10, Table 10.3 and the dense output of §II.6; coefficients in
//! [`system::dop853`], as published with Hairer's `dop853.f`).
//!
//! Per accepted step: 12 stages (the first is the previous step's last evaluation, FSAL), one
//! evaluation at the step end (the next step's first stage), and — only when the dense output is
//! read (an event candidate or an output sample inside the step) — 3 more stages for the
//! 7th-order interpolant.
//!
//! The error norm is Hairer's: with `sk_i = atol + rtol·max(|y_i|, |y_new,i|)`, the 5th-order
//! estimate `e5` and the 3rd-order estimate `e3`,
//!
//! ```text
//! err = |h| · Σ(e5_i/sk_i)² / sqrt(n · (Σ(e5_i/sk_i)² + 0.01 · Σ(e3_i/sk_i)²))
//! ```
//!
//! which behaves like `h⁸` for small `h` and stays robust for large `h`. The stepper returns
//! `err²` (no square root on the step's critical path); the controller (`crate::control`, in the
//! shared driver) takes `log₂ err = ½ log₂ err²` and sets `h_new = h · clamp(0.9 / err^(1/8),
//! 0.333, 6)` with `err^(1/8)` from its `log₂`/`2^x` kernels (deterministic on every platform,
//! without libm `pow`).
//!
//! Work buffers are generic over [`Buf`] as for Dormand–Prince 5(4): fixed-size arrays for the
//! small dimensions, `Vec<f64>` otherwise, with the same arithmetic in the same order.

use crate::stepper::{Buf, Stages, Stepper};
use crate::system::OdeSystem;

use system::dop853::*;

/// Hairer's DOP853: 8th order, error estimators of orders 5 and 3, 7th-order dense output.
///
/// Stage buffers: `k[0..12]` the stages 1–12 of a step, `k[12]` the derivative at the step end
/// (the next step's first stage), `k[13..16]` the extra stages 14–16 of the interpolant; `r`
/// the eight coefficient vectors of the interpolant.
#[derive(Debug, Clone)]
pub(crate) struct Dop853<B = Vec<f64>> {
    st: Stages<16, B>,
    r: [B; 8],
}

impl<B: Buf> Dop853<B> {
    pub(crate) fn new(n: usize) -> Self {
        Self {
            st: Stages::new(n),
            r: std::array::from_fn(|_| B::zeros(n)),
        }
    }
}

impl<B: Buf> Stepper for Dop853<B> {
    const ORDER: f64 = 8.0;
    // Hairer's dop853 defaults: fac1 = 0.333, fac2 = 6, beta = 0 (pure I controller)
    const CONTROL: crate::control::ControlParams = crate::control::DOP853_CONTROL;

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
        let [k1, k2, k3, k4, k5, k6, k7, k8, k9, k10, k11, k12, k13, ..] = &mut self.st.k;
        let yt = self.st.ytmp.as_mut();
        // one length for every buffer: a compile-time constant for arrays, and no bounds
        // checks in the loops below
        let n = yt.len();
        let y = &y[..n];
        let (k1, k2, k3, k4) = (
            &mut k1.as_mut()[..n],
            &mut k2.as_mut()[..n],
            &mut k3.as_mut()[..n],
            &mut k4.as_mut()[..n],
        );
        let (k5, k6, k7, k8) = (
            &mut k5.as_mut()[..n],
            &mut k6.as_mut()[..n],
            &mut k7.as_mut()[..n],
            &mut k8.as_mut()[..n],
        );
        let (k9, k10, k11, k12) = (
            &mut k9.as_mut()[..n],
            &mut k10.as_mut()[..n],
            &mut k11.as_mut()[..n],
            &mut k12.as_mut()[..n],
        );
        let k13 = &mut k13.as_mut()[..n];
        for i in 0..n {
            yt[i] = y[i] + h * A21 * k1[i];
        }
        sys.rhs(t + C2 * h, yt, k2);
        for i in 0..n {
            yt[i] = y[i] + h * (A31 * k1[i] + A32 * k2[i]);
        }
        sys.rhs(t + C3 * h, yt, k3);
        for i in 0..n {
            yt[i] = y[i] + h * (A41 * k1[i] + A43 * k3[i]);
        }
        sys.rhs(t + C4 * h, yt, k4);
        for i in 0..n {
            yt[i] = y[i] + h * (A51 * k1[i] + A53 * k3[i] + A54 * k4[i]);
        }
        sys.rhs(t + C5 * h, yt, k5);
        for i in 0..n {
            yt[i] = y[i] + h * (A61 * k1[i] + A64 * k4[i] + A65 * k5[i]);
        }
        sys.rhs(t + C6 * h, yt, k6);
        for i in 0..n {
            yt[i] = y[i] + h * (A71 * k1[i] + A74 * k4[i] + A75 * k5[i] + A76 * k6[i]);
        }
        sys.rhs(t + C7 * h, yt, k7);
        for i in 0..n {
            yt[i] =
                y[i] + h * (A81 * k1[i] + A84 * k4[i] + A85 * k5[i] + A86 * k6[i] + A87 * k7[i]);
        }
        sys.rhs(t + C8 * h, yt, k8);
        for i in 0..n {
            yt[i] = y[i]
                + h * (A91 * k1[i]
                    + A94 * k4[i]
                    + A95 * k5[i]
                    + A96 * k6[i]
                    + A97 * k7[i]
                    + A98 * k8[i]);
        }
        sys.rhs(t + C9 * h, yt, k9);
        for i in 0..n {
            yt[i] = y[i]
                + h * (A101 * k1[i]
                    + A104 * k4[i]
                    + A105 * k5[i]
                    + A106 * k6[i]
                    + A107 * k7[i]
                    + A108 * k8[i]
                    + A109 * k9[i]);
        }
        sys.rhs(t + C10 * h, yt, k10);
        for i in 0..n {
            yt[i] = y[i]
                + h * (A111 * k1[i]
                    + A114 * k4[i]
                    + A115 * k5[i]
                    + A116 * k6[i]
                    + A117 * k7[i]
                    + A118 * k8[i]
                    + A119 * k9[i]
                    + A1110 * k10[i]);
        }
        sys.rhs(t + C11 * h, yt, k11);
        let tph = t + h;
        for i in 0..n {
            yt[i] = y[i]
                + h * (A121 * k1[i]
                    + A124 * k4[i]
                    + A125 * k5[i]
                    + A126 * k6[i]
                    + A127 * k7[i]
                    + A128 * k8[i]
                    + A129 * k9[i]
                    + A1210 * k10[i]
                    + A1211 * k11[i]);
        }
        sys.rhs(tph, yt, k12);
        let yn = &mut self.st.ynew.as_mut()[..n];
        let (mut err5, mut err3) = (0.0, 0.0);
        for i in 0..n {
            let s = B1 * k1[i]
                + B6 * k6[i]
                + B7 * k7[i]
                + B8 * k8[i]
                + B9 * k9[i]
                + B10 * k10[i]
                + B11 * k11[i]
                + B12 * k12[i];
            yn[i] = y[i] + h * s;
            let sk = atol + rtol * y[i].abs().max(yn[i].abs());
            let e3 = s - BHH1 * k1[i] - BHH2 * k9[i] - BHH3 * k12[i];
            err3 += (e3 / sk) * (e3 / sk);
            let e5 = ER1 * k1[i]
                + ER6 * k6[i]
                + ER7 * k7[i]
                + ER8 * k8[i]
                + ER9 * k9[i]
                + ER10 * k10[i]
                + ER11 * k11[i]
                + ER12 * k12[i];
            err5 += (e5 / sk) * (e5 / sk);
        }
        // the derivative at the step end: the next step's first stage (FSAL) and a node of
        // the interpolant; evaluated also for a rejected step (one call in 12)
        sys.rhs(tph, yn, k13);
        self.st.n_rhs += 12;
        let mut deno = err5 + 0.01 * err3;
        if deno <= 0.0 {
            deno = 1.0;
        }
        // err² (the trait's convention: the controller halves its logarithm)
        (h * h) * (err5 * err5) / (n.max(1) as f64 * deno)
    }

    fn y_new(&self) -> &[f64] {
        self.st.ynew.as_ref()
    }

    fn prepare_dense<S: OdeSystem + ?Sized>(&mut self, sys: &S, t: f64, y: &[f64], h: f64) {
        let [
            k1,
            _k2,
            _k3,
            _k4,
            _k5,
            k6,
            k7,
            k8,
            k9,
            k10,
            k11,
            k12,
            k13,
            k14,
            k15,
            k16,
        ] = &mut self.st.k;
        let yt = self.st.ytmp.as_mut();
        let ynew = self.st.ynew.as_ref();
        let n = ynew.len();
        let y = &y[..n];
        let yt = &mut yt[..n];
        let (k1, k6, k7, k8) = (
            &k1.as_ref()[..n],
            &k6.as_ref()[..n],
            &k7.as_ref()[..n],
            &k8.as_ref()[..n],
        );
        let (k9, k10, k11, k12, k13) = (
            &k9.as_ref()[..n],
            &k10.as_ref()[..n],
            &k11.as_ref()[..n],
            &k12.as_ref()[..n],
            &k13.as_ref()[..n],
        );
        let (k14, k15, k16) = (
            &mut k14.as_mut()[..n],
            &mut k15.as_mut()[..n],
            &mut k16.as_mut()[..n],
        );
        for i in 0..n {
            yt[i] = y[i]
                + h * (A141 * k1[i]
                    + A147 * k7[i]
                    + A148 * k8[i]
                    + A149 * k9[i]
                    + A1410 * k10[i]
                    + A1411 * k11[i]
                    + A1412 * k12[i]
                    + A1413 * k13[i]);
        }
        sys.rhs(t + C14 * h, yt, k14);
        for i in 0..n {
            yt[i] = y[i]
                + h * (A151 * k1[i]
                    + A156 * k6[i]
                    + A157 * k7[i]
                    + A158 * k8[i]
                    + A1511 * k11[i]
                    + A1512 * k12[i]
                    + A1513 * k13[i]
                    + A1514 * k14[i]);
        }
        sys.rhs(t + C15 * h, yt, k15);
        for i in 0..n {
            yt[i] = y[i]
                + h * (A161 * k1[i]
                    + A166 * k6[i]
                    + A167 * k7[i]
                    + A168 * k8[i]
                    + A169 * k9[i]
                    + A1613 * k13[i]
                    + A1614 * k14[i]
                    + A1615 * k15[i]);
        }
        sys.rhs(t + C16 * h, yt, k16);
        self.st.n_rhs += 3;
        let [r1, r2, r3, r4, r5, r6, r7, r8] = &mut self.r;
        let (r1, r2, r3, r4) = (
            &mut r1.as_mut()[..n],
            &mut r2.as_mut()[..n],
            &mut r3.as_mut()[..n],
            &mut r4.as_mut()[..n],
        );
        let (r5, r6, r7, r8) = (
            &mut r5.as_mut()[..n],
            &mut r6.as_mut()[..n],
            &mut r7.as_mut()[..n],
            &mut r8.as_mut()[..n],
        );
        for i in 0..n {
            let ydiff = ynew[i] - y[i];
            let bspl = h * k1[i] - ydiff;
            r1[i] = y[i];
            r2[i] = ydiff;
            r3[i] = bspl;
            r4[i] = ydiff - h * k13[i] - bspl;
            r5[i] = h
                * (D41 * k1[i]
                    + D46 * k6[i]
                    + D47 * k7[i]
                    + D48 * k8[i]
                    + D49 * k9[i]
                    + D410 * k10[i]
                    + D411 * k11[i]
                    + D412 * k12[i]
                    + D413 * k13[i]
                    + D414 * k14[i]
                    + D415 * k15[i]
                    + D416 * k16[i]);
            r6[i] = h
                * (D51 * k1[i]
                    + D56 * k6[i]
                    + D57 * k7[i]
                    + D58 * k8[i]
                    + D59 * k9[i]
                    + D510 * k10[i]
                    + D511 * k11[i]
                    + D512 * k12[i]
                    + D513 * k13[i]
                    + D514 * k14[i]
                    + D515 * k15[i]
                    + D516 * k16[i]);
            r7[i] = h
                * (D61 * k1[i]
                    + D66 * k6[i]
                    + D67 * k7[i]
                    + D68 * k8[i]
                    + D69 * k9[i]
                    + D610 * k10[i]
                    + D611 * k11[i]
                    + D612 * k12[i]
                    + D613 * k13[i]
                    + D614 * k14[i]
                    + D615 * k15[i]
                    + D616 * k16[i]);
            r8[i] = h
                * (D71 * k1[i]
                    + D76 * k6[i]
                    + D77 * k7[i]
                    + D78 * k8[i]
                    + D79 * k9[i]
                    + D710 * k10[i]
                    + D711 * k11[i]
                    + D712 * k12[i]
                    + D713 * k13[i]
                    + D714 * k14[i]
                    + D715 * k15[i]
                    + D716 * k16[i]);
        }
    }

    fn dense(&self, theta: f64, out: &mut [f64]) {
        let s1 = 1.0 - theta;
        let [r1, r2, r3, r4, r5, r6, r7, r8] = &self.r;
        let n = r1.as_ref().len();
        let out = &mut out[..n];
        let (r1, r2, r3, r4) = (
            &r1.as_ref()[..n],
            &r2.as_ref()[..n],
            &r3.as_ref()[..n],
            &r4.as_ref()[..n],
        );
        let (r5, r6, r7, r8) = (
            &r5.as_ref()[..n],
            &r6.as_ref()[..n],
            &r7.as_ref()[..n],
            &r8.as_ref()[..n],
        );
        for i in 0..n {
            out[i] = r1[i]
                + theta
                    * (r2[i]
                        + s1 * (r3[i]
                            + theta
                                * (r4[i]
                                    + s1 * (r5[i]
                                        + theta * (r6[i] + s1 * (r7[i] + theta * r8[i]))))));
        }
    }

    fn advance(&mut self) {
        self.st.k.swap(0, 12);
    }

    fn n_rhs(&self) -> u64 {
        self.st.n_rhs
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The stage rows sum to their nodes (`Σ_j a_ij = c_i`), the weights to 1, the error
    /// weights to 0 — a check of the transcription of the published coefficients.
    #[test]
    fn tableau_row_sums() {
        let rows: [(f64, &[f64]); 14] = [
            (C2, &[A21]),
            (C3, &[A31, A32]),
            (C4, &[A41, A43]),
            (C5, &[A51, A53, A54]),
            (C6, &[A61, A64, A65]),
            (C7, &[A71, A74, A75, A76]),
            (C8, &[A81, A84, A85, A86, A87]),
            (C9, &[A91, A94, A95, A96, A97, A98]),
            (C10, &[A101, A104, A105, A106, A107, A108, A109]),
            (C11, &[A111, A114, A115, A116, A117, A118, A119, A1110]),
            (
                1.0,
                &[A121, A124, A125, A126, A127, A128, A129, A1210, A1211],
            ),
            (C14, &[A141, A147, A148, A149, A1410, A1411, A1412, A1413]),
            (C15, &[A151, A156, A157, A158, A1511, A1512, A1513, A1514]),
            (C16, &[A161, A166, A167, A168, A169, A1613, A1614, A1615]),
        ];
        for (k, (c, a)) in rows.iter().enumerate() {
            let s: f64 = a.iter().sum();
            assert!((s - c).abs() < 1e-14, "row {k}: {s} vs {c}");
        }
        let b = B1 + B6 + B7 + B8 + B9 + B10 + B11 + B12;
        assert!((b - 1.0).abs() < 1e-14, "{b}");
        let e5 = ER1 + ER6 + ER7 + ER8 + ER9 + ER10 + ER11 + ER12;
        assert!(e5.abs() < 1e-14, "{e5}");
        let e3 = BHH1 + BHH2 + BHH3;
        assert!((e3 - 1.0).abs() < 1e-14, "{e3}");
    }
}
