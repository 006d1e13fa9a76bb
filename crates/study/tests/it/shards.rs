//! Shards and resumable runs: a 2-D map study sharded three ways and merged is byte-identical
//! to the unsharded run; a run stopped part-way resumes without recomputing finished points.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use geardyn_study::shard::{self, Journal, PointRecord, ShardSpec};
use geardyn_study::{
    Progress, UserStudy, compute_records, merge_from_str, merge_study_files, prepare,
    run_shard_from_str, run_study_file, run_study_shard_file,
};

const MAP: &str = r#"
name = "map"
model = "karpov2017-kinematics"

[overrides]
j = 2
omega1 = 10.0

[sweep]
parameter = "b"
from = 0.001
to = 0.03
steps = 9

[sweep2]
parameter = "xi"
values = [1.5, 2.0, 3.0, 5.0]

[solver]
method = "kinematics"
"#;

struct Count(AtomicUsize);
impl Progress for Count {
    fn start(&self, _total: usize) {}
    fn point(&self, _done: usize, _total: usize) {
        self.0.fetch_add(1, Ordering::Relaxed);
    }
    fn finish(&self) {}
}

fn scratch(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("geardyn-shards-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Every regular file directly in `dir` (not the shards), by name.
fn files(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .map(|p| {
            (
                p.file_name().unwrap().to_string_lossy().into_owned(),
                std::fs::read(&p).unwrap(),
            )
        })
        .collect()
}

#[test]
fn sharded_map_merges_to_the_unsharded_outputs() {
    let root = scratch("merge");
    let file = root.join("map.toml");
    std::fs::write(&file, MAP).unwrap();
    let whole = root.join("whole");
    let sharded = root.join("sharded");
    let n = Count(AtomicUsize::new(0));
    run_study_file(&file, Some(&whole), &n).unwrap();
    assert_eq!(n.0.load(Ordering::Relaxed), 36);

    let parts: Vec<PathBuf> = (1..=3)
        .map(|i| {
            run_study_shard_file(&file, Some(&sharded), ShardSpec::new(i, 3).unwrap(), &n).unwrap()
        })
        .collect();
    // merging two of three is refused: a point is missing
    let e = merge_study_files(&file, Some(&sharded), &parts[..2]).unwrap_err();
    assert!(e.to_string().contains("missing"), "{e}");
    merge_study_files(&file, Some(&sharded), &parts).unwrap();

    let (a, b) = (files(&whole), files(&sharded));
    assert!(a.contains_key("map.csv") && a.contains_key("map.json"));
    assert!(
        a.keys().any(|k| k.ends_with("_map.svg")),
        "a 2-D study draws heat maps: {:?}",
        a.keys()
    );
    assert_eq!(a.keys().collect::<Vec<_>>(), b.keys().collect::<Vec<_>>());
    for (k, v) in &a {
        assert!(
            v == &b[k],
            "{k} differs between the whole and the merged run"
        );
    }

    // the in-memory path (as the Python package's Dask runner uses it) agrees too
    let texts: Vec<String> = (1..=3)
        .map(|i| run_shard_from_str(MAP, ShardSpec::new(i, 3).unwrap()).unwrap())
        .collect();
    let merged = merge_from_str(MAP, &texts).unwrap();
    assert_eq!(merged.table.to_csv().as_bytes(), &a["map.csv"][..]);

    // partial results of another study are refused
    let other = MAP.replace("steps = 9", "steps = 8");
    assert!(merge_from_str(&other, &texts).is_err());
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn a_stopped_run_resumes_without_recomputing_finished_points() {
    let root = scratch("resume");
    let file = root.join("map.toml");
    std::fs::write(&file, MAP).unwrap();
    let out = root.join("out");

    // Simulate a run killed after 10 points: its journal, with a torn last line.
    let study = UserStudy::parse(MAP).unwrap();
    let prepared = prepare(&study).unwrap();
    let (plan, all) = compute_records(prepared, ShardSpec::whole(), Vec::new(), None, None);
    let journal = root.join(".out.journal");
    let (j, done) = Journal::open(&journal, &plan.header(None)).unwrap();
    assert!(done.is_empty());
    for r in all.iter().take(10) {
        j.record(r).unwrap();
    }
    drop(j);
    let mut text = std::fs::read_to_string(&journal).unwrap();
    text.push_str(&shard::record_line(&plan.fingerprint(), &all[10])[..12]);
    std::fs::write(&journal, text).unwrap();

    let n = Count(AtomicUsize::new(0));
    run_study_file(&file, Some(&out), &n).unwrap();
    assert_eq!(
        n.0.load(Ordering::Relaxed),
        26,
        "only the 26 unfinished points are computed"
    );
    assert!(
        !journal.exists(),
        "the journal goes once the outputs are written"
    );

    // and the outputs equal a fresh run's
    let fresh = root.join("fresh");
    run_study_file(&file, Some(&fresh), &n).unwrap();
    assert_eq!(files(&out), files(&fresh));

    // a journal from a different study is not used
    let (j, _) = Journal::open(&journal, &plan.header(None)).unwrap();
    j.record(&PointRecord::ok(
        0,
        vec![1.0; plan.header(None).outputs.len()],
    ))
    .unwrap();
    drop(j);
    std::fs::write(&file, MAP.replace("omega1 = 10.0", "omega1 = 11.0")).unwrap();
    let n = Count(AtomicUsize::new(0));
    run_study_file(&file, Some(&out), &n).unwrap();
    assert_eq!(
        n.0.load(Ordering::Relaxed),
        36,
        "a changed study starts afresh"
    );
    let _ = std::fs::remove_dir_all(&root);
}

/// A small bifurcation study of the Liu model (4 speeds across the rattle onset, few periods:
/// a plumbing check, not a converged diagram).
const BIFURCATION: &str = r#"
name = "bif"
model = "liu2021"

[overrides]
load_torque = 30.0

[sweep]
parameter = "omega1"
values = [140.0, 160.0, 170.0, 190.0]

[bifurcation]
points = 4
max_period = 2
transient_periods = 3
lyapunov_intervals = 2

[solver]
method = "time-stepping"
"#;

#[test]
fn sharded_bifurcation_study_merges_to_the_unsharded_outputs() {
    let root = scratch("bifurcation");
    let file = root.join("bif.toml");
    std::fs::write(&file, BIFURCATION).unwrap();
    let whole = root.join("whole");
    let sharded = root.join("sharded");
    let n = Count(AtomicUsize::new(0));
    run_study_file(&file, Some(&whole), &n).unwrap();
    let parts: Vec<PathBuf> = (1..=3)
        .map(|i| {
            run_study_shard_file(&file, Some(&sharded), ShardSpec::new(i, 3).unwrap(), &n).unwrap()
        })
        .collect();
    merge_study_files(&file, Some(&sharded), &parts).unwrap();
    let (a, b) = (files(&whole), files(&sharded));
    assert_eq!(
        a.keys().collect::<Vec<_>>(),
        [
            ".geardyn-study",
            "bif.csv",
            "bif.json",
            "bif_bifurcation.svg"
        ]
    );
    assert_eq!(a.keys().collect::<Vec<_>>(), b.keys().collect::<Vec<_>>());
    for (k, v) in &a {
        assert!(
            v == &b[k],
            "{k} differs between the whole and the merged run"
        );
    }
    let csv = String::from_utf8(a["bif.csv"].clone()).unwrap();
    let header = csv.lines().next().unwrap();
    assert_eq!(
        header,
        "omega1 [rad/s],motion,period [1],lambda [1],q_1 [1],q_2 [1],q_3 [1],q_4 [1]"
    );
    // every row has a motion label
    for line in csv.lines().skip(1) {
        let motion = line.split(',').nth(1).unwrap();
        assert!(
            motion.starts_with("period-") || motion == "quasi-periodic" || motion == "chaotic",
            "{line}"
        );
    }
    let _ = std::fs::remove_dir_all(&root);
}

/// A small time-stepping map of the Liu model (2 × 2 points, few periods): its step-statistic
/// columns (integers carried as numbers) survive the shard journals and the merge byte for
/// byte, and draw no figure.
const STEPPED: &str = r#"
name = "stepped"
model = "liu2021"

[sweep]
parameter = "omega1"
values = [140.0, 160.0]

[sweep2]
parameter = "load_torque"
values = [30.0, 40.0]

[solver]
method = "time-stepping"

[solver.settings]
settle = "fixed"
transient_periods = 1.0
record_periods = 1.0
"#;

#[test]
fn sharded_time_stepping_study_keeps_its_step_statistics() {
    let root = scratch("stepped");
    let file = root.join("stepped.toml");
    std::fs::write(&file, STEPPED).unwrap();
    let whole = root.join("whole");
    let sharded = root.join("sharded");
    let n = Count(AtomicUsize::new(0));
    run_study_file(&file, Some(&whole), &n).unwrap();
    let parts: Vec<PathBuf> = (1..=2)
        .map(|i| {
            run_study_shard_file(&file, Some(&sharded), ShardSpec::new(i, 2).unwrap(), &n).unwrap()
        })
        .collect();
    merge_study_files(&file, Some(&sharded), &parts).unwrap();
    let (a, b) = (files(&whole), files(&sharded));
    assert_eq!(a.keys().collect::<Vec<_>>(), b.keys().collect::<Vec<_>>());
    for (k, v) in &a {
        assert!(
            v == &b[k],
            "{k} differs between the whole and the merged run"
        );
    }
    let csv = String::from_utf8(a["stepped.csv"].clone()).unwrap();
    assert!(
        csv.lines()
            .next()
            .unwrap()
            .ends_with(",steps_accepted [1],steps_rejected [1],rhs_calls [1],events [1]"),
        "{csv}"
    );
    // counts: integers, written in full
    for line in csv.lines().skip(1) {
        let accepted = line.split(',').rev().nth(3).unwrap();
        assert!(accepted.parse::<u64>().unwrap() > 0, "{line}");
    }
    assert!(
        a.keys().any(|k| k.ends_with("_ppv_map.svg"))
            && !a.keys().any(|k| k.contains("steps") || k.contains("rhs")),
        "{:?}",
        a.keys()
    );
    let _ = std::fs::remove_dir_all(&root);
}

/// `text` with one bit flipped in the first value of line `line` (1-based).
fn flip_value(text: &str, line: usize) -> String {
    let mut out = String::new();
    for (k, l) in text.split_inclusive('\n').enumerate() {
        if k + 1 == line {
            let at = l.find("\"v\":[\"").expect("a record with values") + 6;
            let mut b = l.as_bytes().to_vec();
            b[at + 3] ^= 0x01; // one bit of the mantissa's leading digits
            out.push_str(std::str::from_utf8(&b).unwrap());
        } else {
            out.push_str(l);
        }
    }
    out
}

#[test]
fn a_damaged_journal_record_is_dropped_named_and_recomputed() {
    let root = scratch("damaged-journal");
    let file = root.join("map.toml");
    std::fs::write(&file, MAP).unwrap();
    let out = root.join("out");
    let study = UserStudy::parse(MAP).unwrap();
    let (plan, all) = compute_records(
        prepare(&study).unwrap(),
        ShardSpec::whole(),
        Vec::new(),
        None,
        None,
    );
    let journal = root.join(".out.journal");
    let (j, _) = Journal::open(&journal, &plan.header(None)).unwrap();
    for r in all.iter().take(10) {
        j.record(r).unwrap();
    }
    drop(j);
    // line 4 holds point 2: flip a bit of its first value
    let text = std::fs::read_to_string(&journal).unwrap();
    let damaged = flip_value(&text, 4);
    assert_ne!(damaged, text);
    std::fs::write(&journal, &damaged).unwrap();

    // the lenient reader names the file, the line and the point
    let (_, recs, dropped) = shard::read_points_lenient(&damaged, "j").unwrap();
    assert_eq!(recs.len(), 9);
    assert_eq!(dropped.len(), 1, "{dropped:?}");
    assert!(
        dropped[0].starts_with("j, line 4 (point 2?): checksum mismatch"),
        "{}",
        dropped[0]
    );
    // the strict reader (merge) refuses it, naming the line
    let e = shard::read_points(&damaged, "j").unwrap_err().to_string();
    assert!(e.contains("j, line 4: checksum mismatch"), "{e}");

    // the resumed run recomputes exactly the damaged point and the 26 never done
    let n = Count(AtomicUsize::new(0));
    run_study_file(&file, Some(&out), &n).unwrap();
    assert_eq!(n.0.load(Ordering::Relaxed), 27);
    let fresh = root.join("fresh");
    run_study_file(&file, Some(&fresh), &n).unwrap();
    assert_eq!(files(&out), files(&fresh));
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn a_damaged_part_is_refused_by_merge_naming_file_and_line() {
    let root = scratch("damaged-part");
    let file = root.join("map.toml");
    std::fs::write(&file, MAP).unwrap();
    let out = root.join("out");
    let n = Count(AtomicUsize::new(0));
    let parts: Vec<PathBuf> = (1..=3)
        .map(|i| {
            run_study_shard_file(&file, Some(&out), ShardSpec::new(i, 3).unwrap(), &n).unwrap()
        })
        .collect();
    merge_study_files(&file, Some(&out), &parts).unwrap();
    // every kind of damage: a value bit, the point index, an error message, a line moved to
    // another study's part
    let text = std::fs::read_to_string(&parts[1]).unwrap();
    let damages = [
        flip_value(&text, 2),
        text.replacen("{\"i\":4,", "{\"i\":7,", 1),
        text.replacen("\"v\":[\"", "\"v\":[\"\u{e9}", 1),
    ];
    for d in &damages {
        assert_ne!(d, &text);
        std::fs::write(&parts[1], d).unwrap();
        let e = merge_study_files(&file, Some(&out), &parts)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(&format!("{}, line ", parts[1].display())) && e.contains("checksum"),
            "{e}"
        );
    }
    // a record copied from another study's part (valid JSON, valid checksum there)
    let other = MAP.replace("omega1 = 10.0", "omega1 = 11.0");
    let other_part = run_shard_from_str(&other, ShardSpec::new(2, 3).unwrap()).unwrap();
    let moved: Vec<&str> = text
        .lines()
        .take(1)
        .chain(other_part.lines().skip(1))
        .collect();
    std::fs::write(&parts[1], moved.join("\n") + "\n").unwrap();
    let e = merge_study_files(&file, Some(&out), &parts)
        .unwrap_err()
        .to_string();
    assert!(e.contains("line 2: checksum mismatch"), "{e}");
    let _ = std::fs::remove_dir_all(&root);
}

/// One Liu point of 10⁴ transient periods (tens of seconds in release, far more in debug).
const ENDLESS: &str = r#"
name = "endless"
model = "liu2021"

[sweep]
parameter = "omega1"
values = [160.0, 170.0]

[solver]
method = "time-stepping"

[solver.settings]
transient_periods = 10000.0
record_periods = 1.0

[limits]
max_seconds_per_point = 0.2
"#;

#[test]
fn the_integrator_stops_itself_at_the_time_limit() {
    // The integrator checks the deadline between steps and stops; the point is a failed row
    // that names the solver's own report, not a watchdog that abandoned a running thread.
    let study = UserStudy::parse(ENDLESS).unwrap();
    let (_, recs) = compute_records(
        prepare(&study).unwrap(),
        ShardSpec::whole(),
        Vec::new(),
        None,
        None,
    );
    assert_eq!(recs.len(), 2);
    for r in &recs {
        let e = r.error.as_deref().expect("stopped at the limit");
        assert!(e.starts_with("time limit: "), "{e}");
        assert!(e.contains("stopped by its solver"), "{e}");
        assert!(e.contains("TimeLimit"), "{e}");
        assert!(!e.contains("abandoned"), "{e}");
    }
}

#[test]
fn a_time_limit_fails_the_point_and_the_study_goes_on() {
    // The limit is far below any point's time; every point is stopped, none is lost.
    let toml = format!("{MAP}\n[limits]\nmax_seconds_per_point = 1e-9\n");
    let study = UserStudy::parse(&toml).unwrap();
    let (_, recs) = compute_records(
        prepare(&study).unwrap(),
        ShardSpec::whole(),
        Vec::new(),
        None,
        None,
    );
    assert_eq!(recs.len(), 36);
    // A nanosecond: every point ends after its deadline, so every point is a failed row.
    for r in &recs {
        let e = r
            .error
            .as_deref()
            .expect("a point over its time limit fails");
        assert!(e.starts_with("time limit: "), "{e}");
    }
    // a generous limit changes nothing
    let toml = format!("{MAP}\n[limits]\nmax_seconds_per_point = 600\n");
    let limited = geardyn_study::run_study_from_str(&toml, &Default::default()).unwrap();
    let free = geardyn_study::run_study_from_str(MAP, &Default::default()).unwrap();
    assert_eq!(limited.table.to_csv(), free.table.to_csv());
    // out of bounds: named with the bound
    for bad in ["0", "-1", "1e9", "nan"] {
        let toml = format!("{MAP}\n[limits]\nmax_seconds_per_point = {bad}\n");
        let e = UserStudy::parse(&toml).unwrap_err().to_string();
        assert!(
            e.contains("limits.max_seconds_per_point must be in (0, 604800]"),
            "{e}"
        );
    }
}
