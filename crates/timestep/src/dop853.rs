//! This crate's own DOP853: the explicit Runge–Kutta pair of order 8 with error estimators of
//! orders 5 and 3 and a continuous extension of order 7 (Hairer, Nørsett & Wanner, *Solving
//! ODEs I*, 2nd ed., 1993, §II.10, Table 10.3 and the dense output of §II.6; coefficients as
//! published with Hairer's `dop853.f`).
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
//! which behaves like `h⁸` for small `h` and stays robust for large `h`. The controller (in the
//! shared driver) uses `h_new = h / clamp(err^(1/8) / 0.9, 1/6, 1/0.333)`; `err^(1/8)` is
//! computed as three square roots (correctly rounded each, so within 1.75 ulp of the exact
//! power, deterministic on every platform, and without libm `pow`).
//!
//! Work buffers are generic over [`Buf`] as for Dormand–Prince 5(4): fixed-size arrays for the
//! small dimensions, `Vec<f64>` otherwise, with the same arithmetic in the same order.

// The coefficients keep the published digits (the compiler rounds them to nearest f64).
#![allow(clippy::excessive_precision)]

use crate::stepper::{Buf, Stages, Stepper};
use crate::system::OdeSystem;

// nodes
const C2: f64 = 0.526001519587677318785587544488e-01;
const C3: f64 = 0.789002279381515978178381316732e-01;
const C4: f64 = 0.118350341907227396726757197510e+00;
const C5: f64 = 0.281649658092772603273242802490e+00;
const C6: f64 = 0.333333333333333333333333333333e+00;
const C7: f64 = 0.25e+00;
const C8: f64 = 0.307692307692307692307692307692e+00;
const C9: f64 = 0.651282051282051282051282051282e+00;
const C10: f64 = 0.6e+00;
const C11: f64 = 0.857142857142857142857142857142e+00;
const C14: f64 = 0.1e+00;
const C15: f64 = 0.2e+00;
const C16: f64 = 0.777777777777777777777777777778e+00;
// 8th-order weights
const B1: f64 = 5.42937341165687622380535766363e-2;
const B6: f64 = 4.45031289275240888144113950566e0;
const B7: f64 = 1.89151789931450038304281599044e0;
const B8: f64 = -5.8012039600105847814672114227e0;
const B9: f64 = 3.1116436695781989440891606237e-1;
const B10: f64 = -1.52160949662516078556178806805e-1;
const B11: f64 = 2.01365400804030348374776537501e-1;
const B12: f64 = 4.47106157277725905176885569043e-2;
// 3rd-order error estimator (weights of the embedded 3rd-order solution)
const BHH1: f64 = 0.244094488188976377952755905512e+00;
const BHH2: f64 = 0.733846688281611857341361741547e+00;
const BHH3: f64 = 0.220588235294117647058823529412e-01;
// 5th-order error estimator
const ER1: f64 = 0.1312004499419488073250102996e-01;
const ER6: f64 = -0.1225156446376204440720569753e+01;
const ER7: f64 = -0.4957589496572501915214079952e+00;
const ER8: f64 = 0.1664377182454986536961530415e+01;
const ER9: f64 = -0.3503288487499736816886487290e+00;
const ER10: f64 = 0.3341791187130174790297318841e+00;
const ER11: f64 = 0.8192320648511571246570742613e-01;
const ER12: f64 = -0.2235530786388629525884427845e-01;
// stage coefficients
const A21: f64 = 5.26001519587677318785587544488e-2;
const A31: f64 = 1.97250569845378994544595329183e-2;
const A32: f64 = 5.91751709536136983633785987549e-2;
const A41: f64 = 2.95875854768068491816892993775e-2;
const A43: f64 = 8.87627564304205475450678981324e-2;
const A51: f64 = 2.41365134159266685502369798665e-1;
const A53: f64 = -8.84549479328286085344864962717e-1;
const A54: f64 = 9.24834003261792003115737966543e-1;
const A61: f64 = 3.7037037037037037037037037037e-2;
const A64: f64 = 1.70828608729473871279604482173e-1;
const A65: f64 = 1.25467687566822425016691814123e-1;
const A71: f64 = 3.7109375e-2;
const A74: f64 = 1.70252211019544039314978060272e-1;
const A75: f64 = 6.02165389804559606850219397283e-2;
const A76: f64 = -1.7578125e-2;
const A81: f64 = 3.70920001185047927108779319836e-2;
const A84: f64 = 1.70383925712239993810214054705e-1;
const A85: f64 = 1.07262030446373284651809199168e-1;
const A86: f64 = -1.53194377486244017527936158236e-2;
const A87: f64 = 8.27378916381402288758473766002e-3;
const A91: f64 = 6.24110958716075717114429577812e-1;
const A94: f64 = -3.36089262944694129406857109825e0;
const A95: f64 = -8.68219346841726006818189891453e-1;
const A96: f64 = 2.75920996994467083049415600797e1;
const A97: f64 = 2.01540675504778934086186788979e1;
const A98: f64 = -4.34898841810699588477366255144e1;
const A101: f64 = 4.77662536438264365890433908527e-1;
const A104: f64 = -2.48811461997166764192642586468e0;
const A105: f64 = -5.90290826836842996371446475743e-1;
const A106: f64 = 2.12300514481811942347288949897e1;
const A107: f64 = 1.52792336328824235832596922938e1;
const A108: f64 = -3.32882109689848629194453265587e1;
const A109: f64 = -2.03312017085086261358222928593e-2;
const A111: f64 = -9.3714243008598732571704021658e-1;
const A114: f64 = 5.18637242884406370830023853209e0;
const A115: f64 = 1.09143734899672957818500254654e0;
const A116: f64 = -8.14978701074692612513997267357e0;
const A117: f64 = -1.85200656599969598641566180701e1;
const A118: f64 = 2.27394870993505042818970056734e1;
const A119: f64 = 2.49360555267965238987089396762e0;
const A1110: f64 = -3.0467644718982195003823669022e0;
const A121: f64 = 2.27331014751653820792359768449e0;
const A124: f64 = -1.05344954667372501984066689879e1;
const A125: f64 = -2.00087205822486249909675718444e0;
const A126: f64 = -1.79589318631187989172765950534e1;
const A127: f64 = 2.79488845294199600508499808837e1;
const A128: f64 = -2.85899827713502369474065508674e0;
const A129: f64 = -8.87285693353062954433549289258e0;
const A1210: f64 = 1.23605671757943030647266201528e1;
const A1211: f64 = 6.43392746015763530355970484046e-1;
// extra stages of the continuous extension
const A141: f64 = 5.61675022830479523392909219681e-2;
const A147: f64 = 2.53500210216624811088794765333e-1;
const A148: f64 = -2.46239037470802489917441475441e-1;
const A149: f64 = -1.24191423263816360469010140626e-1;
const A1410: f64 = 1.5329179827876569731206322685e-1;
const A1411: f64 = 8.20105229563468988491666602057e-3;
const A1412: f64 = 7.56789766054569976138603589584e-3;
const A1413: f64 = -8.298e-3;
const A151: f64 = 3.18346481635021405060768473261e-2;
const A156: f64 = 2.83009096723667755288322961402e-2;
const A157: f64 = 5.35419883074385676223797384372e-2;
const A158: f64 = -5.49237485713909884646569340306e-2;
const A1511: f64 = -1.08347328697249322858509316994e-4;
const A1512: f64 = 3.82571090835658412954920192323e-4;
const A1513: f64 = -3.40465008687404560802977114492e-4;
const A1514: f64 = 1.41312443674632500278074618366e-1;
const A161: f64 = -4.28896301583791923408573538692e-1;
const A166: f64 = -4.69762141536116384314449447206e0;
const A167: f64 = 7.68342119606259904184240953878e0;
const A168: f64 = 4.06898981839711007970213554331e0;
const A169: f64 = 3.56727187455281109270669543021e-1;
const A1613: f64 = -1.39902416515901462129418009734e-3;
const A1614: f64 = 2.9475147891527723389556272149e0;
const A1615: f64 = -9.15095847217987001081870187138e0;
// dense-output coefficients (rows 4..7 of Hairer's `d`)
const D41: f64 = -0.84289382761090128651353491142e+01;
const D46: f64 = 0.56671495351937776962531783590e+00;
const D47: f64 = -0.30689499459498916912797304727e+01;
const D48: f64 = 0.23846676565120698287728149680e+01;
const D49: f64 = 0.21170345824450282767155149946e+01;
const D410: f64 = -0.87139158377797299206789907490e+00;
const D411: f64 = 0.22404374302607882758541771650e+01;
const D412: f64 = 0.63157877876946881815570249290e+00;
const D413: f64 = -0.88990336451333310820698117400e-01;
const D414: f64 = 0.18148505520854727256656404962e+02;
const D415: f64 = -0.91946323924783554000451984436e+01;
const D416: f64 = -0.44360363875948939664310572000e+01;
const D51: f64 = 0.10427508642579134603413151009e+02;
const D56: f64 = 0.24228349177525818288430175319e+03;
const D57: f64 = 0.16520045171727028198505394887e+03;
const D58: f64 = -0.37454675472269020279518312152e+03;
const D59: f64 = -0.22113666853125306036270938578e+02;
const D510: f64 = 0.77334326684722638389603898808e+01;
const D511: f64 = -0.30674084731089398182061213626e+02;
const D512: f64 = -0.93321305264302278729567221706e+01;
const D513: f64 = 0.15697238121770843886131091075e+02;
const D514: f64 = -0.31139403219565177677282850411e+02;
const D515: f64 = -0.93529243588444783865713862664e+01;
const D516: f64 = 0.35816841486394083752465898540e+02;
const D61: f64 = 0.19985053242002433820987653617e+02;
const D66: f64 = -0.38703730874935176555105901742e+03;
const D67: f64 = -0.18917813819516756882830838328e+03;
const D68: f64 = 0.52780815920542364900561016686e+03;
const D69: f64 = -0.11573902539959630126141871134e+02;
const D610: f64 = 0.68812326946963000169666922661e+01;
const D611: f64 = -0.10006050966910838403183860980e+01;
const D612: f64 = 0.77771377980534432092869265740e+00;
const D613: f64 = -0.27782057523535084065932004339e+01;
const D614: f64 = -0.60196695231264120758267380846e+02;
const D615: f64 = 0.84320405506677161018159903784e+02;
const D616: f64 = 0.11992291136182789328035130030e+02;
const D71: f64 = -0.25693933462703749003312586129e+02;
const D76: f64 = -0.15418974869023643374053993627e+03;
const D77: f64 = -0.23152937917604549567536039109e+03;
const D78: f64 = 0.35763911791061412378285349910e+03;
const D79: f64 = 0.93405324183624310003907691704e+02;
const D710: f64 = -0.37458323136451633156875139351e+02;
const D711: f64 = 0.10409964950896230045147246184e+03;
const D712: f64 = 0.29840293426660503123344363579e+02;
const D713: f64 = -0.43533456590011143754432175058e+02;
const D714: f64 = 0.96324553959188282948394950600e+02;
const D715: f64 = -0.39177261675615439165231486172e+02;
const D716: f64 = -0.14972683625798562581422125276e+03;

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
        h.abs() * err5 * (1.0 / (n.max(1) as f64 * deno)).sqrt()
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
