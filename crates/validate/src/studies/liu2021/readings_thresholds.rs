//! Which reading of Eq. (11), (20), (21) reproduces the Fig. 11 thresholds.

use models::liu2021::{self, BaseRadius, ErrorTerm, Readings, RigidAcceleration};

use super::{at, base, model, speed_tolerance};
use crate::{
    Comparison, Cost, Error, Evidence, Paper, ResultExt, Study, StudyOutput, Table, published,
};

pub(super) fn study() -> Study {
    Study {
        id: "liu2021-readings-speed-thresholds",
        paper: Paper::Liu2021,
        source: "Eq. (11), (20), (21); Fig. 11",
        title: "Which reading reproduces the Fig. 11 thresholds",
        description: "The ω1 sweep (time integration, 100–250 rad/s, step 5) under five reading \
            sets: consistent (time-varying b̄), constant b̄, constant b̄ with the printed error \
            sign, constant b̄ with the printed Eq. (20), and everything as printed. Rows: first \
            speed with unilateral and with bilateral rattle against the text's 150 and \
            170 rad/s (±5 rad/s: round numbers on a 10 rad/s resolution). Evidence for \
            R-LIU-EQ11/EQ20/EQ21: every row is a reading variant (listed apart, not counted as a \
            reproduction; the constant-b̄ rows repeat `liu2021-fig11-speed-sweep`).",
        cost: Cost::Heavy,
        run,
    }
}

fn run() -> Result<StudyOutput, Error> {
    let paper = published!("liu2021.toml")?;
    let mean = Readings {
        base_radius: BaseRadius::Mean,
        ..Readings::default()
    };
    let sets: [(&str, Readings, &str); 5] = [
        (
            "consistent (time-varying b̄)",
            Readings::default(),
            "R-LIU-EQ11",
        ),
        ("constant b̄", mean, "R-LIU-EQ11"),
        (
            "constant b̄, printed Eq. (21) sign",
            Readings {
                error_term: ErrorTerm::Printed,
                ..mean
            },
            "R-LIU-EQ21",
        ),
        (
            "constant b̄, printed Eq. (20)",
            Readings {
                rigid_acceleration: RigidAcceleration::PrintedEq20,
                ..mean
            },
            "R-LIU-EQ20",
        ),
        ("all as printed", Readings::printed(), "R-LIU-EQ20"),
    ];
    let xs: Vec<f64> = (0..=30).map(|i| 100.0 + 5.0 * f64::from(i)).collect();
    let mut out = StudyOutput::new();
    let mut t = Table::new(
        "thresholds",
        &[
            ("reading_set", "-"),
            ("unilateral_from", "rad/s"),
            ("bilateral_from", "rad/s"),
        ],
    );
    for (label, readings, id) in sets {
        let pts: Vec<(f64, u8, Option<String>)> = timestep::sweep(
            &xs,
            |&x| {
                let mut p = base();
                p.readings = readings;
                p.omega1 = x;
                let m = model(&p)?;
                let (r, _) =
                    liu2021::time_reference(&m, &models::liu2021::SweepStrategy::default())
                        .context("integration")?;
                Ok((
                    x,
                    r.rattle.state.rsv(),
                    r.flag().map(|f| format!("at {}: {f}", at(x))),
                ))
            },
            None,
        )
        .into_iter()
        .collect::<Result<_, Error>>()?;
        // claim-local: only the two grid points that bracket the onset are needed
        let first = |rsv: u8| {
            let idx = pts.iter().position(|p| p.1 >= rsv);
            let used = idx.map_or(&pts[..0], |i| &pts[i.saturating_sub(1)..=i]);
            (
                idx.map_or(f64::NAN, |i| pts[i].0),
                used.iter().filter_map(|p| p.2.clone()).collect::<Vec<_>>(),
                used.iter().map(|p| p.0).collect::<Vec<_>>(),
            )
        };
        let (uni, uni_flags, uni_needs) = first(1);
        let (bi, bi_flags, bi_needs) = first(2);
        let class = Evidence::ReadingVariant(format!("{id}: {label}"));
        let (uni_p, bi_p) = (
            paper.value("sect34.unilateral-onset")?,
            paper.value("sect34.bilateral-onset")?,
        );
        out.compare(
            Comparison::published(uni_p, uni)?
                .with_tolerance(speed_tolerance(&uni_p.printed))
                .reading(id)
                .class(class.clone())
                .needs(uni_needs)
                .flagged_all(uni_flags)
                .note(&format!(
                    "{label}: first ω1 with rsv ≥ 1 (time integration, step 5)"
                )),
        );
        out.compare(
            Comparison::published(bi_p, bi)?
                .with_tolerance(speed_tolerance(&bi_p.printed))
                .reading(id)
                .class(class)
                .needs(bi_needs)
                .flagged_all(bi_flags)
                .note(&format!(
                    "{label}: first ω1 with rsv = 2 (time integration, step 5)"
                )),
        );
        t.push(vec![label.into(), uni.into(), bi.into()])?;
    }
    out.table(t);
    Ok(out)
}
