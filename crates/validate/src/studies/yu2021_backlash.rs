//! Yu 2021 Fig. 4: constant part of the backlash b_s against the fractal parameters D and G
//! (backlash crate, Eq. 4–5).

use crate::{
    Claim, Cost, Error, Evidence, Figure, Paper, ResultExt, Series, Study, StudyOutput, Table,
    Verdict, fmt_sig, fmt6, published,
};

/// The studies of this file.
pub fn studies() -> Vec<Study> {
    vec![Study {
        id: "yu2021-fig4-constant-backlash",
        paper: Paper::Yu2021,
        source: "Fig. 4, Eq. (4)-(5), Sect. 2.1",
        title: "Constant part of the backlash b_s vs fractal dimension D and roughness G",
        description: "b_s = b0 − b_p − b_g with b_i the mean absolute W-M profile height (Eq. 4), \
            on the grid D = 1.2 … 1.8, G = 1e-12 … 1e-11 m, with the parameters the Yu model chooses \
            for Fig. 4 (`models::yu2021::fig4`; the paper prints none: b0 = 30 µm, λ = 1.5, L = 1 mm). Fig. 4 \
            prints no numbers in the seed, so only the text's claims are checked and the curves \
            snapshotted.",
        cost: Cost::Fast,
        run: yu_fig4,
    }]
}

fn yu_fig4() -> Result<StudyOutput, Error> {
    let paper = published!("yu2021.toml")?;
    let bound = paper.value("fig4.bs-d12-bound")?.value; // µm
    let data = models::yu2021::fig4().context("Fig. 4 grid")?;
    let claims = models::yu2021::fig4_claims(&data).context("Fig. 4 claims")?;
    let mut out = StudyOutput::new();
    let mut cols: Vec<(String, &str)> = vec![("D".to_owned(), "1")];
    for g in &data.g {
        cols.push((format!("b_s at G={}", fmt_sig(*g, 3)), "um"));
    }
    let cols_ref: Vec<(&str, &str)> = cols.iter().map(|(a, b)| (a.as_str(), *b)).collect();
    let mut t = Table::new("bs-grid", &cols_ref);
    for (i, d) in data.d.iter().enumerate() {
        let mut row = vec![*d];
        row.extend(data.b_s[i].iter().map(|b| 1e6 * b));
        t.push_nums(&row)?;
    }
    out.table(t);
    let mut fig = Figure::new(
        "bs-vs-d",
        "Yu Fig. 4: constant backlash b_s vs D (b0 = 30 µm)",
        ("D", "1"),
        ("b_s", "µm"),
    );
    for (j, g) in data.g.iter().enumerate() {
        let pts = data
            .d
            .iter()
            .zip(&data.b_s)
            .map(|(d, row)| (*d, 1e6 * row[j]))
            .collect();
        fig.push(Series::line(format!("G = {} m", fmt_sig(*g, 3)), pts));
    }
    out.figure(fig);
    let b0 = 1e6 * data.params.b0;
    // Range over D (at fixed G) and over G (at fixed D), largest of each.
    let nd = data.d.len();
    let ng = data.g.len();
    let range_d = (0..ng)
        .map(|j| (data.b_s[nd - 1][j] - data.b_s[0][j]).abs())
        .fold(0.0, f64::max);
    let range_g = (0..nd)
        .map(|i| (data.b_s[i][0] - data.b_s[i][ng - 1]).abs())
        .fold(0.0, f64::max);
    out.claim(Claim::published(
        paper.claim("fig4.d-strong")?,
        format!(
            "b_s changes by up to {} µm from D = 1.2 to 1.8 at fixed G, against up to {} µm across \
             the G range at fixed D",
            fmt6(1e6 * range_d),
            fmt6(1e6 * range_g)
        ),
        Verdict::from_bool(range_d > range_g),
    ));
    out.claim(Claim::published(
        paper.claim("fig4.d12")?,
        format!(
            "at D = 1.2, b_s ∈ [{}, {}] µm over G (bound {} µm; a negative b_s means the asperities \
             close the gap)",
            fmt6(1e6 * claims.min_b_s_at_d12),
            fmt6(1e6 * claims.max_b_s_at_d12),
            fmt6(bound)
        ),
        Verdict::from_bool(1e6 * claims.max_b_s_at_d12 < bound),
    ));
    out.claim(
        Claim::published(
            paper.claim("fig4.d18")?,
            format!(
                "at D = 1.8, |b_s − b0|/b0 ≤ {}% (b0 = {} µm)",
                fmt_sig(100.0 * claims.max_rel_dev_at_d18, 3),
                fmt6(b0)
            ),
            Verdict::from_bool(claims.max_rel_dev_at_d18 < 0.01),
        )
        .reading("R-YU-FIG4"),
    );
    out.claim(Claim::published(
        paper.claim("fig4.g")?,
        format!(
            "b_s non-increasing in G for every D: {}; non-decreasing in D for every G: {}; G \
             effect (≤ {} µm) smaller than D effect (≤ {} µm)",
            claims.falls_with_g,
            claims.rises_with_d,
            fmt6(1e6 * range_g),
            fmt6(1e6 * range_d)
        ),
        Verdict::from_bool(claims.falls_with_g && claims.rises_with_d && range_g < range_d),
    ));
    // The paper gives no parameters for Fig. 4 (b0, λ, L); the ones used were picked so that
    // its statements hold, so these claims are calibration, not reproduction.
    for c in &mut out.claims {
        c.class = Evidence::Calibration(
            "Fig. 4 surface parameters b0, λ, L (not given by the paper) chosen here".to_owned(),
        );
    }
    Ok(out)
}
