//! Fig. 12–14: rattle state and ppv against e_r, ε and a_k.

use super::{Point, first_at_least, flags_of, sig, sweep, sweep_figures, sweep_table};
use crate::{Claim, Cost, Error, Paper, Study, StudyOutput, Verdict};

pub(super) fn study() -> Study {
    Study {
        id: "liu2021-fig12-14-parameter-sweeps",
        paper: Paper::Liu2021,
        source: "Fig. 12, 13, 14, Sect. 3.4-3.6",
        title: "Rattle state and ppv against e_r, ε and a_k (at ω1 = 140 and 160 rad/s)",
        description: "Time integration (judged) and harmonic balance (paper basis cold/warm, \
            full basis K = 65 warm; shown; table columns) over e_r = 0–40 µm, ε = 0–0.3 and \
            a_k = k_r/k0 = 0.05–0.8, the other parameters from Table 1. Claims: the succession \
            no → unilateral → bilateral rattle with e_r and ε, a ppv jump at the onset of \
            bilateral rattle, and the paper's statement that a_k changes the rattle state little \
            (unilateral throughout at 160, no rattle throughout at 140).",
        cost: Cost::Heavy,
        run,
    }
}

/// Claim that the time-integration states are non-decreasing and pass through all three.
fn succession_claim(out: &mut StudyOutput, text: &str, source: &str, unit: &str, pts: &[Point]) {
    let monotone = pts.windows(2).all(|w| w[1].rsv() >= w[0].rsv());
    let uni = first_at_least(pts, 1);
    let bi = first_at_least(pts, 2);
    let all = pts.first().is_some_and(|p| p.rsv() == 0) && bi.x.is_finite();
    out.claim(
        Claim::new(
            text,
            source,
            format!(
                "time integration: unilateral from {} {unit}, bilateral from {} {unit}; states {}",
                sig(uni.x),
                sig(bi.x),
                if monotone {
                    "non-decreasing"
                } else {
                    "not monotone (coexisting responses)"
                }
            ),
            Verdict::from_bool(all),
        )
        .cause("succession of time-integration rattle states along the sweep")
        .flagged_all(bi.flags),
    );
    let jump = pts.windows(2).find(|w| w[0].rsv() < 2 && w[1].rsv() == 2);
    out.claim(
        Claim::new(
            "As the bilateral rattle arises, ppv increases suddenly.",
            source,
            jump.map_or("no onset of bilateral rattle".to_owned(), |w| {
                format!(
                    "ppv ratio across the onset ×{} ('suddenly' read as ×3 within one step)",
                    sig(w[1].ppv() / w[0].ppv())
                )
            }),
            Verdict::from_bool(jump.is_some_and(|w| w[1].ppv() > 3.0 * w[0].ppv())),
        )
        .cause("ppv ratio across the time-integration onset of bilateral rattle")
        .flagged_all(jump.map_or_else(|| flags_of(pts), flags_of)),
    );
}

fn run() -> Result<StudyOutput, Error> {
    let mut out = StudyOutput::new();
    let er: Vec<f64> = (0..=40).map(|i| 1e-6 * f64::from(i)).collect();
    let pts = sweep(&er, |p, x| p.er = x)?;
    succession_claim(
        &mut out,
        "As e_r increases, the NFG undergoes non-rattle, unilateral rattle and bilateral rattle in succession.",
        "Sect. 3.4, Fig. 12",
        "m",
        &pts,
    );
    out.table(sweep_table("er", ("e_r", "m"), &pts)?);
    sweep_figures(&mut out, "er", ("e_r", "m"), &pts);

    let eps: Vec<f64> = (0..=30).map(|i| 0.01 * f64::from(i)).collect();
    let pts = sweep(&eps, |p, x| p.eccentricity = x)?;
    succession_claim(
        &mut out,
        "The NFG also undergoes the three rattle states with the increase in eccentric ratio.",
        "Sect. 3.5, Fig. 13",
        "",
        &pts,
    );
    out.table(sweep_table("eps", ("epsilon", "1"), &pts)?);
    sweep_figures(&mut out, "eps", ("epsilon", "1"), &pts);

    let ak: Vec<f64> = (1..=16).map(|i| 0.05 * f64::from(i)).collect();
    for (w, expected) in [(160.0, 1u8), (140.0, 0u8)] {
        let pts = sweep(&ak, |p, x| {
            p.omega1 = w;
            p.kr = x * p.k0;
        })?;
        let states: Vec<u8> = pts.iter().map(Point::rsv).collect();
        let same = states.iter().all(|&s| s == expected);
        let (p0, p1) = (
            pts.first().map_or(f64::NAN, Point::ppv),
            pts.last().map_or(f64::NAN, Point::ppv),
        );
        let flags = flags_of(&pts);
        out.claim(
            Claim::new(
                &format!(
                    "At ω1 = {w} rad/s the rattle state stays {} for a_k = 0.1–0.8.",
                    if expected == 1 {
                        "unilateral"
                    } else {
                        "non-rattle"
                    }
                ),
                "Sect. 3.6, Fig. 14a",
                format!("time-integration rsv over a_k = 0.05…0.8: {states:?}"),
                Verdict::from_bool(same),
            )
            .reading("R-LIU-AK")
            .flagged_all(flags.clone()),
        );
        out.claim(
            Claim::new(
                &format!("At ω1 = {w} rad/s ppv rises as a_k increases."),
                "Sect. 3.6, Fig. 14b",
                format!(
                    "time-integration ppv {} at a_k = 0.05 → {} at 0.8",
                    sig(p0),
                    sig(p1)
                ),
                Verdict::from_bool(p1 > p0),
            )
            .reading("R-LIU-AK")
            .flagged_all(flags),
        );
        let name = format!("ak_{w}");
        out.table(sweep_table(&name, ("a_k", "1"), &pts)?);
        sweep_figures(&mut out, &name, ("a_k", "1"), &pts);
    }
    Ok(out)
}

