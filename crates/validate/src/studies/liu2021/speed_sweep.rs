//! Fig. 11: rattle state and ppv against the input speed ω1.

use super::{
    HBM_KINDS, Point, any_unsettled, at, converged_note, first_at_least, first_hbm, flags_of,
    refine, rise_claim, seeds_table, sig_u, speed_tolerance, sweep, sweep_figures, sweep_table,
};
use crate::{Claim, Comparison, Cost, Error, Paper, Study, StudyOutput, Verdict, published};
use math::DetMath;

pub(super) fn study() -> Study {
    Study {
        id: "liu2021-fig11-speed-sweep",
        paper: Paper::Liu2021,
        source: "Fig. 11, Sect. 3.3",
        title: "Rattle state and ppv against input speed ω1 (100–250 rad/s)",
        description: "rsv and ppv (peak-to-peak of q over one period 2π/ω̄_c) from time \
            integration (judged; each point with its Poincaré motion type and a 100×-tighter \
            repeat) and from harmonic balance (paper basis cold and warm-started from the \
            time-integrated period; full basis K = 65 warm-started; shown), 61 speeds. \
            Thresholds: the first speed with rsv ≥ 1 and with rsv = 2 from each method, against \
            the text's 150 and 170 rad/s; tolerance ±5 rad/s (round numbers on a 10 rad/s \
            resolution). Claims: ppv jumps at the onset of bilateral rattle; the succession of \
            states.",
        cost: Cost::Heavy,
        run,
    }
}

fn run() -> Result<StudyOutput, Error> {
    let paper = published!("liu2021.toml")?;
    let xs: Vec<f64> = (0..=60).map(|i| 100.0 + 2.5 * f64::from(i)).collect();
    let pts = sweep(&xs, |p, x| p.omega1 = x)?;
    let mut out = StudyOutput::new();
    let uni_p = paper.value("sect34.unilateral-onset")?;
    let bi_p = paper.value("sect34.bilateral-onset")?;
    let set = |p: &mut models::liu2021::Parameters, x: f64| p.omega1 = x;
    let uni = refine(first_at_least(&pts, 1), &set, 2.5, |r| r >= 1, true)?;
    let bi = refine(first_at_least(&pts, 2), &set, 2.5, |r| r >= 2, false)?;
    out.compare(
        Comparison::published(uni_p, uni.x)?
            .with_tolerance(speed_tolerance(&uni_p.printed))
            .within(uni.lo, uni.hi)
            .reading("R-LIU-EQ21")
            .needs(uni.needs.clone())
            .flagged_all(uni.flags.clone())
            .note(&format!(
                "first ω1 with long-window rsv ≥ 1 on the 2.5 rad/s grid; {}",
                uni.note
            )),
    );
    out.compare(
        Comparison::published(bi_p, bi.x)?
            .with_tolerance(speed_tolerance(&bi_p.printed))
            .within(bi.lo, bi.hi)
            .reading("R-LIU-EQ21")
            .needs(bi.needs.clone())
            .flagged_all(bi.flags.clone())
            .note(&format!(
                "first ω1 with long-window rsv = 2 on the 2.5 rad/s grid; {}",
                bi.note
            )),
    );
    for (i, (label, kind)) in HBM_KINDS.into_iter().enumerate() {
        let n_conv = converged_note(&pts, kind);
        out.compare(
            Comparison::published(uni_p, first_hbm(&pts, i, |h| h.rattle.state.rsv() >= 1).0)?
                .unsettled_if(first_hbm(&pts, i, |h| h.rattle.state.rsv() >= 1).1)
                .with_tolerance(speed_tolerance(&uni_p.printed))
                .reading("R-LIU-HBM")
                .shown_only()
                .note(&format!("first usable ω1 with rsv ≥ 1, {label} ({n_conv})")),
        );
        out.compare(
            Comparison::published(bi_p, first_hbm(&pts, i, |h| h.rattle.state.rsv() == 2).0)?
                .unsettled_if(first_hbm(&pts, i, |h| h.rattle.state.rsv() == 2).1)
                .with_tolerance(speed_tolerance(&bi_p.printed))
                .reading("R-LIU-HBM")
                .shown_only()
                .note(&format!(
                    "first usable ω1 with rsv = 2, {label} (NaN: none; {n_conv})"
                )),
        );
    }
    // ppv jump at the onset of bilateral rattle (time integration)
    let jump = pts.windows(2).find(|w| w[0].rsv() < 2 && w[1].rsv() == 2);
    let (evidence, ok, flags) = match jump {
        Some(w) => (
            format!(
                "long-window ppv {} at {} rad/s → {} at {} rad/s (×{}); 'sudden' read as ×3 within one 2.5 rad/s step",
                w[0].ppv_text(),
                at(w[0].x),
                w[1].ppv_text(),
                at(w[1].x),
                sig_u(w[1].ppv() / w[0].ppv(), any_unsettled(w))
            ),
            w[1].ppv() > 3.0 * w[0].ppv(),
            w.iter().filter_map(|p| p.ppv_flag(0.5)).collect::<Vec<_>>(),
        ),
        None => (
            "no onset of bilateral rattle in the sweep".to_owned(),
            false,
            flags_of(pts.iter().filter(|p| p.rsv_range().1 == 2)),
        ),
    };
    out.claim(
        Claim::new(
            "At the start of the bilateral rattle, a sudden increase occurs in the curve of ppv.",
            "Sect. 3.3, Fig. 11b",
            evidence,
            Verdict::from_bool(ok),
        )
        .cause("long-window ppv jump at the first bilateral point of the sweep (the two points across it are needed)")
        .needs(jump.map_or_else(Vec::new, |w| w.iter().map(|p| p.x).collect()))
        .flagged_all(flags),
    );
    let order_ok = uni.hi.is_finite() && bi.lo.is_finite() && uni.hi < bi.lo;
    let mut order_needs = uni.needs.clone();
    order_needs.extend(&bi.needs);
    let mut order_flags = uni.flags.clone();
    order_flags.extend(bi.flags.iter().cloned());
    out.claim(
        Claim::new(
            "With increasing ω1 the NFG passes through no rattle, unilateral and bilateral rattle.",
            "Sect. 3.3, Fig. 11a",
            format!(
                "long-window rattle state: unilateral onset in [{}, {}] rad/s, bilateral onset in [{}, {}] rad/s",
                sig_u(uni.lo, uni.unsettled),
                sig_u(uni.hi, uni.unsettled),
                sig_u(bi.lo, bi.unsettled),
                sig_u(bi.hi, bi.unsettled)
            ),
            Verdict::from_bool(order_ok),
        )
        .cause("order of the two onset intervals (disjoint and in this order)")
        .needs(order_needs)
        .flagged_all(order_flags),
    );
    // Fig. 11b: gradual growth before the bilateral onset, quicker growth after it
    let onset = pts.iter().position(|p| p.rsv() == 2).unwrap_or(pts.len());
    out.claim(rise_claim(
        "In the non-rattle and unilateral rattle vibration, ppv grows gradually with the increase of the input speed.",
        "Sect. 3.3, Fig. 11b",
        "ω1 before the first bilateral point",
        &pts[..onset],
    ));
    let slope = |q: &[Point]| super::ppv_slope(q).unwrap_or((f64::NAN, f64::NAN));
    let ((s_before, se_before), (s_after, se_after)) = (slope(&pts[..onset]), slope(&pts[onset..]));
    // quicker: the difference of the fitted slopes exceeds twice its standard error
    let quicker = s_after - s_before >= 2.0 * se_before.dhypot(se_after);
    let (u_before, u_after) = (any_unsettled(&pts[..onset]), any_unsettled(&pts[onset..]));
    out.claim(
        Claim::new(
            "In the bilateral rattle state, the vibrational amplitude increases more quickly.",
            "Sect. 3.3, Fig. 11b",
            format!(
                "long-window ppv: fitted slope {} ± {} per rad/s before the bilateral onset, {} ± {} per rad/s after it; 'more quickly' read as a difference of at least 2 SE",
                sig_u(s_before, u_before),
                sig_u(se_before, u_before),
                sig_u(s_after, u_after),
                sig_u(se_after, u_after)
            ),
            Verdict::from_bool(quicker),
        )
        .cause("fitted long-window ppv slopes on either side of the onset")
        .needs(pts.iter().map(|p| p.x)),
    );
    out.table(sweep_table("sweep", ("omega1", "rad/s"), &pts)?);
    out.table(seeds_table("sweep", ("omega1", "rad/s"), &pts)?);
    sweep_figures(&mut out, "omega1", ("omega1", "rad/s"), &pts);
    Ok(out)
}
