//! Fig. 11: rattle state and ppv against the input speed ω1.

use super::{
    HBM_KINDS, Point, converged_note, first_at_least, first_hbm, flags_of, rise_claim, sig,
    speed_tolerance, sweep, sweep_figures, sweep_table,
};
use crate::{Claim, Comparison, Cost, Error, Paper, Study, StudyOutput, Verdict, published};

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
    let uni = first_at_least(&pts, 1);
    let bi = first_at_least(&pts, 2);
    out.compare(
        Comparison::published(uni_p, uni.x)?
            .with_tolerance(speed_tolerance(&uni_p.printed))
            .reading("R-LIU-EQ11")
            .flagged_all(uni.flags.clone())
            .note("first ω1 with rsv ≥ 1, time integration, 2.5 rad/s grid"),
    );
    out.compare(
        Comparison::published(bi_p, bi.x)?
            .with_tolerance(speed_tolerance(&bi_p.printed))
            .reading("R-LIU-EQ11")
            .flagged_all(bi.flags.clone())
            .note("first ω1 with rsv = 2, time integration, 2.5 rad/s grid"),
    );
    for (label, kind) in HBM_KINDS {
        let n_conv = converged_note(&pts, kind);
        out.compare(
            Comparison::published(uni_p, first_hbm(&pts, kind, |h| h.rattle.state.rsv() >= 1))?
                .with_tolerance(speed_tolerance(&uni_p.printed))
                .reading("R-LIU-HBM")
                .shown_only()
                .note(&format!("first usable ω1 with rsv ≥ 1, {label} ({n_conv})")),
        );
        out.compare(
            Comparison::published(bi_p, first_hbm(&pts, kind, |h| h.rattle.state.rsv() == 2))?
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
                "ppv {} at {} rad/s → {} at {} rad/s (×{}); 'sudden' read as ×3 within one 2.5 rad/s step",
                sig(w[0].ppv()),
                sig(w[0].x),
                sig(w[1].ppv()),
                sig(w[1].x),
                sig(w[1].ppv() / w[0].ppv())
            ),
            w[1].ppv() > 3.0 * w[0].ppv(),
            flags_of(w),
        ),
        None => (
            "no onset of bilateral rattle in the sweep".to_owned(),
            false,
            flags_of(&pts),
        ),
    };
    out.claim(
        Claim::new(
            "At the start of the bilateral rattle, a sudden increase occurs in the curve of ppv.",
            "Sect. 3.3, Fig. 11b",
            evidence,
            Verdict::from_bool(ok),
        )
        .cause("ppv jump at the first bilateral point of the time-integration sweep")
        .flagged_all(flags),
    );
    let order_ok = uni.x.is_finite() && bi.x.is_finite() && uni.x < bi.x;
    out.claim(
        Claim::new(
            "With increasing ω1 the NFG passes through no rattle, unilateral and bilateral rattle.",
            "Sect. 3.3, Fig. 11a",
            format!(
                "time integration: unilateral from {} rad/s, bilateral from {} rad/s",
                sig(uni.x),
                sig(bi.x)
            ),
            Verdict::from_bool(order_ok),
        )
        .cause("order of the time-integration thresholds")
        .flagged_all(bi.flags),
    );
    // Fig. 11b: gradual growth before the bilateral onset, quicker growth after it
    let onset = pts.iter().position(|p| p.rsv() == 2).unwrap_or(pts.len());
    out.claim(rise_claim(
        "In the non-rattle and unilateral rattle vibration, ppv grows gradually with the increase of the input speed.",
        "Sect. 3.3, Fig. 11b",
        "ω1 before the first bilateral point",
        &pts[..onset],
    ));
    let slope = |q: &[Point]| match (q.first(), q.last()) {
        (Some(a), Some(b)) if b.x > a.x => (b.ppv() - a.ppv()) / (b.x - a.x),
        _ => f64::NAN,
    };
    let (s_before, s_after) = (slope(&pts[..onset]), slope(&pts[onset..]));
    out.claim(
        Claim::new(
            "In the bilateral rattle state, the vibrational amplitude increases more quickly.",
            "Sect. 3.3, Fig. 11b",
            format!(
                "time integration: mean ppv slope {} per rad/s before the bilateral onset, {} per rad/s after it",
                sig(s_before),
                sig(s_after)
            ),
            Verdict::from_bool(s_after > s_before),
        )
        .cause("mean ppv slopes of the time-integration reference on either side of the onset")
        .flagged_all(flags_of(&pts)),
    );
    out.table(sweep_table("sweep", ("omega1", "rad/s"), &pts)?);
    sweep_figures(&mut out, "omega1", ("omega1", "rad/s"), &pts);
    Ok(out)
}
