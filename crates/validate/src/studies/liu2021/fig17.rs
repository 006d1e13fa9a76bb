//! Fig. 17: the spectrum of the theoretical response at 864 rpm (belt drive, 3 N·m), its
//! dominant frequencies and the combination frequencies the text names.

use models::liu2021::Rig;

use super::sig;
use super::table2::rig_spectrum;
use crate::{
    Claim, Comparison, Cost, Error, Evidence, Figure, Paper, Series, Study, StudyOutput, Table,
    Tolerance, Verdict, published,
};

pub(super) fn study() -> Study {
    Study {
        id: "liu2021-fig17-spectrum",
        paper: Paper::Liu2021,
        source: "Fig. 17, Sect. 3.8",
        title: "Spectrum of the theoretical response at 864 rpm: dominant and combination frequencies",
        description: "Model: Table 1 with T2 = 3 N·m, the rig of the Table 2 study (belt 21/16 — \
            printed 1.3 —, Z1 = 18, Z2 = 64, R-LIU-TABLE2) at the motor speed 864 rpm; time \
            integration (the Liu verdict rule: Poincaré motion type and 100×-tighter repeat), \
            one steady excitation period 1/f_c sampled at 4096 points, amplitude spectrum of \
            the displacement q (bin k = k f_c). A *line* is a bin above 1 % of the largest \
            (visible on the paper's linear amplitude axis). Checked: the largest line below \
            f_e/2 and the largest above it against the text's theoretical 3 Hz and 192 Hz \
            (their frequencies follow from the calibrated rig: calibration class), and the \
            presence of the combination lines 2f_c and f_e ± f_c that the text names.",
        cost: Cost::Heavy,
        run,
    }
}

/// A bin counts as a line above this fraction of the largest line.
const LINE_FRACTION: f64 = 0.01;

/// The committed spectrum lines are written to 10^-2 of the largest line. Under a solver retune
/// every line moves by about 1e-4 of the largest (an absolute noise floor: the small lines move
/// by up to 5 % of themselves, the large ones by 0.02 %; docs/examples/validate-diff.md), and the
/// claims read which lines dominate, at a few per cent.
const SPECTRUM_DECADES: i32 = 2;

fn run() -> Result<StudyOutput, Error> {
    let paper = published!("liu2021.toml")?;
    let rig = Rig::table2();
    let rpm = paper.value("sect38.motor-rpm")?.value;
    let (_, time, sp, _, _) = rig_spectrum(&rig, rpm)?;
    let fc = rig.centre_frequency(rpm);
    let z2 = rig.z2 as usize;
    let amp = |k: usize| sp.amplitude.get(k).copied().unwrap_or(f64::NAN);
    let top = (1..sp.amplitude.len()).map(amp).fold(0.0, f64::max);
    let flags: Vec<String> = time.flag().into_iter().collect();
    let mut out = StudyOutput::new();
    // A one-record spectrum of a non-periodic orbit goes to validation/stats/ only (issue 28);
    // the line rows below judge it.
    // (also when the time reference is flagged: not reproducible under the 100× tighter
    // tolerance, so its one-record spectrum moves with the integrator's step sequence)
    let non_periodic =
        !matches!(time.motion, timestep::Motion::Periodic(_)) || time.flag().is_some();
    let mut t = Table::new(
        "spectrum",
        &[
            ("frequency", "Hz"),
            ("bin k", "1"),
            ("amplitude q", "1"),
            ("amplitude q / largest", "1"),
        ],
    )
    .non_periodic_record(non_periodic)
    .reproducible_decades(SPECTRUM_DECADES);
    let kmax = (3 * z2).min(sp.amplitude.len() - 1);
    for k in 1..=kmax {
        t.push_nums(&[k as f64 * fc, k as f64, amp(k), amp(k) / top])?;
    }
    out.table(t);
    let mut fig = Figure::new(
        "spectrum_curve",
        "Liu Fig. 17(a): amplitude spectrum of q at 864 rpm, 3 N·m (model)",
        ("f", "Hz"),
        ("amplitude of q", "1"),
    )
    .non_periodic_record(non_periodic)
    .reproducible_decades(SPECTRUM_DECADES);
    fig.push(Series::line(
        "model, time integration",
        (1..=kmax).map(|k| (k as f64 * fc, amp(k))).collect(),
    ));
    out.figure(fig);
    // dominant lines: largest below f_e/2 and largest above it
    let largest = |range: std::ops::RangeInclusive<usize>| {
        range.map(|k| (k, amp(k))).fold(
            (0usize, f64::NEG_INFINITY),
            |b, x| if x.1 > b.1 { x } else { b },
        )
    };
    let low = largest(1..=z2 / 2);
    let high = largest(z2 / 2 + 1..=kmax);
    // the Table 2 speed whose rig mesh frequency is nearest the text's f_e (cause of a deviation)
    let fe_text = paper.value("sect38.fe-theory")?.value;
    let nearest = paper
        .values_with_prefix("table2.rpm.")
        .map(|v| (v.value, rig.mesh_frequency(v.value)))
        .fold((f64::NAN, f64::INFINITY), |b, x| {
            if (x.1 - fe_text).abs() < (b.1 - fe_text).abs() {
                x
            } else {
                b
            }
        });
    let fe_cause = format!(
        "at the text's {} rpm the calibrated rig gives f_e = {} Hz; the text's f_e is the rig's value at the Table 2 speed {} rpm ({} Hz): the text's frequencies belong to another speed than the one it states",
        sig(rpm),
        sig(rig.mesh_frequency(rpm)),
        sig(nearest.0),
        sig(nearest.1)
    );
    for (id, line, what) in [
        ("sect38.fc-theory", low, "largest line below f_e/2"),
        ("sect38.fe-theory", high, "largest line above f_e/2"),
    ] {
        let v = paper.value(id)?;
        out.compare(
            Comparison::published(v, line.0 as f64 * fc)?
                .with_tolerance(Tolerance::printed(&v.printed)?)
                .class(Evidence::Calibration(
                    "belt 21/16, Z2 = 64 fitted on Table 2: the bin frequencies are k·f_c of the rig".to_owned(),
                ))
                .reading("R-LIU-TABLE2")
                .cause(if id == "sect38.fe-theory" { &fe_cause } else { "" })
                .flagged_all(flags.clone())
                .note(&format!(
                    "{what}: bin {} (amplitude {} of the largest)",
                    line.0,
                    sig(line.1 / top)
                )),
        );
    }
    // combination lines named by the text
    let named = [
        ("2f_c", 2usize),
        ("f_e − f_c", z2 - 1),
        ("f_e + f_c", z2 + 1),
    ];
    let present: Vec<(String, f64)> = named
        .iter()
        .map(|(n, k)| ((*n).to_owned(), amp(*k) / top))
        .collect();
    let all = present.iter().all(|(_, r)| *r >= LINE_FRACTION);
    out.claim(
        Claim::new(
            "the double frequency of the time-varying instantaneous center, the sum and difference frequency of time-varying instantaneous center and the meshing stiffness in Fig. 17a are close to those in Fig. 17b",
            "Sect. 3.8, Fig. 17",
            format!(
                "model spectrum at 864 rpm ({}, {}): lines relative to the largest: {}; all above {} %: {all}",
                time.motion.label(),
                if time.reproducible { "reproducible at 100× tighter tolerance" } else { "not reproducible" },
                present
                    .iter()
                    .map(|(n, r)| format!("{n} {}", sig(*r)))
                    .collect::<Vec<_>>()
                    .join(", "),
                LINE_FRACTION * 100.0
            ),
            Verdict::from_bool(all),
        )
        .cause("presence of the named lines in the model's theoretical spectrum (the experimental spectrum is not digitised)")
        .flagged_all(flags),
    );
    Ok(out)
}
