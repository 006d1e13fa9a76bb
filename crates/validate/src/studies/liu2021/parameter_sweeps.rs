//! Fig. 12–14: rattle state and ppv against e_r, ε and a_k.

use models::liu2021::Parameters;

use super::{
    Point, Threshold, always, any_unsettled, at, base, first_at_least, flags_of, refine,
    rise_claim, seeds_table, sig, sig_u, sweep, sweep_figures, sweep_table,
};
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

/// The unilateral and bilateral onsets of a sweep as intervals ([`refine`]: bisected below the
/// grid step `step`, widened over the undecided readings and the rattle depth).
fn onsets(
    pts: &[Point],
    set: &dyn Fn(&mut Parameters, f64),
    step: f64,
) -> Result<(Threshold, Threshold), Error> {
    Ok((
        refine(first_at_least(pts, 1), set, step, |r| r >= 1, true)?,
        refine(first_at_least(pts, 2), set, step, |r| r >= 2, false)?,
    ))
}

/// Claim that the time-integration states are non-decreasing and pass through all three; the
/// onsets are reported as intervals (the paper prints no number to compare them with).
fn succession_claim(
    out: &mut StudyOutput,
    text: &str,
    source: &str,
    unit: &str,
    pts: &[Point],
    set: &dyn Fn(&mut Parameters, f64),
    step: f64,
    coexistence: Option<&str>,
) -> Result<(), Error> {
    let monotone = pts.windows(2).all(|w| w[1].rsv() >= w[0].rsv());
    let (uni, bi) = onsets(pts, set, step)?;
    let all = pts.first().is_some_and(|p| p.rsv() == 0) && bi.x.is_finite();
    let first: Vec<&Point> = pts.first().into_iter().collect();
    let mut needs: Vec<f64> = first.iter().map(|p| p.x).collect();
    needs.extend(&bi.needs);
    let mut flags = flags_of(first);
    flags.extend(bi.flags.iter().cloned());
    out.claim(
        Claim::new(
            text,
            source,
            format!(
                "long-window rattle state: unilateral from {} {unit} (onset in [{}, {}]), bilateral from {} {unit} (onset in [{}, {}]); states {}",
                at(uni.x),
                sig_u(uni.lo, uni.unsettled),
                sig_u(uni.hi, uni.unsettled),
                at(bi.x),
                sig_u(bi.lo, bi.unsettled),
                sig_u(bi.hi, bi.unsettled),
                if monotone {
                    "non-decreasing"
                } else {
                    "not monotone (coexisting responses)"
                }
            ) + &coexistence.map_or_else(String::new, |c| format!("; {c}")),
            Verdict::from_bool(all),
        )
        .cause("succession of long-window rattle states along the sweep (the first point and the bilateral onset are needed)")
        .needs(needs)
        .flagged_all(flags),
    );
    let jump = pts.windows(2).find(|w| w[0].rsv() < 2 && w[1].rsv() == 2);
    out.claim(
        Claim::new(
            "As the bilateral rattle arises, ppv increases suddenly.",
            source,
            jump.map_or("no onset of bilateral rattle".to_owned(), |w| {
                format!(
                    "ppv ratio across the onset ×{} ('suddenly' read as ×3 within one step)",
                    sig_u(w[1].ppv() / w[0].ppv(), any_unsettled(w))
                )
            }),
            Verdict::from_bool(jump.is_some_and(|w| w[1].ppv() > 3.0 * w[0].ppv())),
        )
        .cause("long-window ppv ratio across the onset of bilateral rattle (the two points across it are needed)")
        .needs(jump.map_or_else(Vec::new, |w| w.iter().map(|p| p.x).collect()))
        .flagged_all(jump.map_or_else(
            || flags_of(pts.iter().filter(|p| p.rsv_range().1 == 2)),
            flags_of,
        )),
    );
    out.note(format!(
        "{text} — onsets as intervals: unilateral {}; bilateral {}",
        uni.note, bi.note
    ));
    Ok(())
}

fn run() -> Result<StudyOutput, Error> {
    let mut out = StudyOutput::new();
    // i / 10⁶ (not i · 10⁻⁶): the nearest double to each decimal grid value, printed as swept
    let er: Vec<f64> = (0..=40).map(|i| f64::from(i) / 1e6).collect();
    let set_er = |p: &mut Parameters, x: f64| p.er = x;
    let pts = sweep(&er, set_er)?;
    succession_claim(
        &mut out,
        "As e_r increases, the NFG undergoes non-rattle, unilateral rattle and bilateral rattle in succession.",
        "Sect. 3.4, Fig. 12",
        "m",
        &pts,
        &set_er,
        1e-6,
        None,
    )?;
    // Fig. 12b: ppv grows slightly before the bilateral onset, then slowly rises after it
    let onset = pts.iter().position(|p| p.rsv() == 2).unwrap_or(pts.len());
    out.claim(rise_claim(
        "in the process of non-rattle and unilateral rattle vibration, the ppv of the NFG grows slightly with the increase in e_r",
        "Sect. 3.4, Fig. 12b",
        "e_r before the first bilateral point",
        &pts[..onset],
    ));
    let tail = &pts[onset..];
    let (stays, tail_flags) = always(tail, |r| r == 2);
    out.claim(
        Claim::new(
            "As e_r increases, the NFG maintains the bilateral vibration state in the end.",
            "Sect. 3.4, Fig. 12a",
            format!(
                "long-window rsv from the first bilateral point ({}) to the end of the sweep: {:?}",
                at(tail.first().map_or(f64::NAN, |p| p.x)),
                tail.iter().map(Point::rsv).collect::<Vec<_>>()
            ),
            Verdict::from_bool(!tail.is_empty() && stays),
        )
        .cause("a robust non-bilateral point after the onset refutes 'maintains'")
        .needs(tail.iter().map(|p| p.x))
        .flagged_all(tail_flags),
    );
    out.claim(rise_claim(
        "Then, as the amplitude of transmission error continues to increase, the ppv slowly rises.",
        "Sect. 3.4, Fig. 12b",
        "e_r from the first bilateral point on",
        &pts[onset..],
    ));
    out.table(sweep_table("er", ("e_r", "m"), &pts)?);
    out.table(seeds_table("er", ("e_r", "m"), &pts)?);
    sweep_figures(&mut out, "er", ("e_r", "m"), &pts);

    let eps: Vec<f64> = (0..=30).map(|i| f64::from(i) / 100.0).collect();
    let set_eps = |p: &mut Parameters, x: f64| p.eccentricity = x;
    let pts = sweep(&eps, set_eps)?;
    // the responses coexisting at ε = 0, 160 rad/s (the two starts of the variants disagree
    // there): their basin fractions, from the liu2021-basins study (memoised); the succession
    // needs no rattle at the first point
    let basins = super::basins::evidence(|a| a.state == 0);
    succession_claim(
        &mut out,
        "The NFG also undergoes the three rattle states with the increase in eccentric ratio.",
        "Sect. 3.5, Fig. 13",
        "",
        &pts,
        &set_eps,
        0.01,
        Some(&basins),
    )?;
    out.table(sweep_table("eps", ("epsilon", "1"), &pts)?);
    out.table(seeds_table("eps", ("epsilon", "1"), &pts)?);
    sweep_figures(&mut out, "eps", ("epsilon", "1"), &pts);

    // Fig. 13b: the circular face gear (ε = 0) against the NFG of Table 1, at 160 rad/s
    let eps0 = base().eccentricity;
    if let (Some(c), Some(nfg)) = (pts.first(), pts.iter().find(|p| (p.x - eps0).abs() < 1e-9)) {
        // per attractor at ε = 0: its ppv below half the NFG's
        let basins = super::basins::evidence(|a| a.ppv < 0.5 * nfg.ppv());
        out.claim(
            Claim::new(
                "Comparing it to Fig. 8a, the vibration amplitude of the circular face gear is much less than that of the NFG.",
                "Sect. 3.5, Fig. 13b",
                format!(
                    "time integration at ω1 = 160 rad/s: ppv {} at ε = 0 against {} at ε = {} (ratio {}); 'much less' read as below half; {basins}",
                    c.ppv_text(),
                    nfg.ppv_text(),
                    sig(eps0),
                    sig_u(c.ppv() / nfg.ppv(), any_unsettled([c, nfg]))
                ),
                Verdict::from_bool(c.ppv() < 0.5 * nfg.ppv()),
            )
            .cause("long-window ppv at ε = 0 and at Table 1's ε")
            .needs([c.x, nfg.x])
            .flagged_all([c, nfg].into_iter().filter_map(|p| p.ppv_flag(0.5))),
        );
    }
    // Sect. 3.5: rattle appears more easily in the NFG than in the circular gear, and the more
    // so the greater ε: the long-window rsv at 160 rad/s against ε (robust points only)
    if let (Some(c), Some(nfg)) = (pts.first(), pts.iter().find(|p| (p.x - eps0).abs() < 1e-9)) {
        let robust = |p: &Point| p.flag().is_none();
        let more = c.rsv() < nfg.rsv();
        // per attractor at ε = 0: a rattle state below the NFG's
        let basins = super::basins::evidence(|a| i16::from(a.state) < i16::from(nfg.rsv()));
        out.claim(
            Claim::new(
                "The rattle vibration appears more easily in the noncircular face gear than in the circular gear.",
                "Sect. 3.5, Fig. 13",
                format!(
                    "long-window rsv at ω1 = 160 rad/s: {} at ε = 0 (circular), {} at ε = {} (Table 1); {basins}",
                    c.rsv(),
                    nfg.rsv(),
                    at(nfg.x)
                ),
                Verdict::from_bool(more),
            )
            .cause("rattle state of the circular and the Table 1 gear at the same speed")
            .needs([c.x, nfg.x])
            .flagged_all([c, nfg].into_iter().filter(|p| !robust(p)).filter_map(Point::flag)),
        );
        // 'the greater ε, the easier it rattles': the first ε with rsv ≥ 1 and with rsv = 2
        // exist and the state never falls robustly below an earlier robust state
        let robust_states: Vec<u8> = pts.iter().filter(|p| robust(p)).map(Point::rsv).collect();
        let never_falls = robust_states.windows(2).all(|w| w[1] >= w[0]);
        out.claim(
            Claim::new(
                "The greater the eccentricity is, the easier the NFG is to rattle.",
                "Sect. 3.5, Fig. 13a",
                format!(
                    "long-window rsv at ω1 = 160 rad/s over ε = 0…0.3 (robust points): {robust_states:?}"
                ),
                Verdict::from_bool(never_falls && robust_states.last().is_some_and(|&r| r > robust_states[0])),
            )
            .cause("the rattle state at fixed speed does not fall robustly as ε grows, and rises over the range")
            .needs(pts.iter().map(|p| p.x)),
        );
    }
    // Fig. 13c: ppv grows with ε before bilateral rattle, then drops while still bilateral
    let onset = pts.iter().position(|p| p.rsv() == 2).unwrap_or(pts.len());
    out.claim(rise_claim(
        "The peak-to-peak value of the NFG grows with the increase in ε when it undergoes non-rattle and unilateral rattle vibration.",
        "Sect. 3.5, Fig. 13c",
        "ε before the first bilateral point",
        &pts[..onset],
    ));
    let bil = &pts[onset..];
    let peak = bil.iter().map(Point::ppv).fold(f64::NAN, f64::max);
    let last = bil.last().map_or(f64::NAN, Point::ppv);
    let (all_bi, bi_flags) = always(bil, |r| r == 2);
    let still_bi = !bil.is_empty() && all_bi;
    let peak_pt = bil.iter().max_by(|a, b| a.ppv().total_cmp(&b.ppv()));
    // the largest ppv moves with every unsettled point (any of them could be the largest)
    let peak_u = any_unsettled(bil);
    let last_u = any_unsettled(bil.last());
    let mut drop_flags = bi_flags;
    drop_flags.extend(
        peak_pt
            .into_iter()
            .chain(bil.last())
            .filter_map(|p| p.ppv_flag(0.5)),
    );
    out.claim(
        Claim::new(
            "Then, as the eccentric ratio increases, the ppv of the NFG drops significantly. However, it is still in the bilateral rattle state.",
            "Sect. 3.5, Fig. 13c",
            format!(
                "long-window statistics after the bilateral onset: largest ppv {}, ppv at the end of the sweep {} (ratio {}), bilateral throughout: {still_bi}; 'drops significantly' read as below half the peak",
                sig_u(peak, peak_u),
                sig_u(last, last_u),
                sig_u(last / peak, peak_u || last_u)
            ),
            Verdict::from_bool(still_bi && last < 0.5 * peak),
        )
        .cause("long-window ppv and rattle state beyond the bilateral onset (a robust non-bilateral point refutes 'still bilateral')")
        .needs(bil.iter().map(|p| p.x))
        .flagged_all(drop_flags),
    );

    let ak: Vec<f64> = (1..=16).map(|i| f64::from(i) / 20.0).collect();
    // None: the critical speed at which the text says a_k changes the state
    for (w, expected) in [(160.0, Some(1u8)), (140.0, Some(0u8)), (145.0, None)] {
        let set_ak = move |p: &mut Parameters, x: f64| {
            p.omega1 = w;
            p.kr = x * p.k0;
        };
        let pts = sweep(&ak, set_ak)?;
        let (uni, bi) = onsets(&pts, &set_ak, 0.05)?;
        out.note(format!(
            "a_k at ω1 = {w} rad/s — onsets as intervals: unilateral in [{}, {}] ({}); bilateral in [{}, {}] ({})",
            sig_u(uni.lo, uni.unsettled),
            sig_u(uni.hi, uni.unsettled),
            uni.note,
            sig_u(bi.lo, bi.unsettled),
            sig_u(bi.hi, bi.unsettled),
            bi.note
        ));
        // the text's range is a_k = 0.1–0.8 (the 0.05 point is shown, not judged)
        let judged: Vec<Point> = pts.iter().filter(|p| p.x >= 0.1 - 1e-12).cloned().collect();
        let states: Vec<u8> = judged.iter().map(Point::rsv).collect();
        let needs: Vec<f64> = judged.iter().map(|p| p.x).collect();
        match expected {
            Some(e) => {
                let (same, flags) = always(&judged, |r| r == e);
                out.claim(
                    Claim::new(
                        &format!(
                            "At ω1 = {w} rad/s the rattle state stays {} for a_k = 0.1–0.8.",
                            if e == 1 { "unilateral" } else { "non-rattle" }
                        ),
                        "Sect. 3.6, Fig. 14a",
                        format!("long-window rsv over a_k = 0.1…0.8: {states:?}"),
                        Verdict::from_bool(same),
                    )
                    .reading("R-LIU-EQ21")
                    .cause("the model's speed thresholds sit below the paper's (R-LIU-EQ21), so 140 and 160 rad/s lie closer to a state change and a_k moves the state there; a robust counterexample refutes 'stays'")
                    .needs(needs.clone())
                    .flagged_all(flags),
                );
            }
            None => {
                // a change needs two robust points in different states
                let robust: Vec<u8> = judged
                    .iter()
                    .filter(|p| p.flag().is_none())
                    .map(Point::rsv)
                    .collect();
                let changes = robust.windows(2).any(|s| s[0] != s[1]);
                let flags = if changes {
                    Vec::new()
                } else {
                    flags_of(&judged)
                };
                out.claim(
                    Claim::new(
                        "Under some critical conditions such as ω1 = 145 rad/s, the variation in a_k could lead to a change in the rattle state.",
                        "Sect. 3.6, Fig. 14a",
                        format!("long-window rsv over a_k = 0.1…0.8 at 145 rad/s: {states:?}"),
                        Verdict::from_bool(changes),
                    )
                    .cause("a change between two points whose long-window state is robust")
                    .needs(needs.clone())
                    .flagged_all(flags),
                );
            }
        }
        out.claim(
            rise_claim(
                &format!(
                    "At ω1 = {w} rad/s the vibrational amplitudes of the NFG rise obviously as a_k increases."
                ),
                "Sect. 3.6, Fig. 14b",
                "a_k = 0.1…0.8",
                &judged,
            ),
        );
        let name = format!("ak_{w}");
        out.table(sweep_table(&name, ("a_k", "1"), &pts)?);
        out.table(seeds_table(&name, ("a_k", "1"), &pts)?);
        sweep_figures(&mut out, &name, ("a_k", "1"), &pts);
    }
    Ok(out)
}
