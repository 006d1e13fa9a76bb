//! Faults of a real `geardyn` process: a run killed with SIGKILL mid-study is started again
//! with no manual step and ends byte-identical to an uninterrupted run; a live run still
//! refuses a second one on the same output directory; a damaged journal record is recomputed
//! with a warning; a damaged partial result is refused by `geardyn merge`.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

/// 200 points of the Liu model by harmonic balance: each point takes milliseconds to tens of
/// milliseconds, so that a run on one thread is long enough to be killed in the middle.
const STUDY: &str = r#"
name = "killed"
model = "liu2021"

[overrides]
readings = "printed"

[sweep]
parameter = "omega1"
from = 100.0
to = 300.0
steps = 200

[solver]
method = "hbm"

[solver.settings]
stability = "off"      # the Floquet verdict would double each point's cost; not under test
"#;

fn geardyn() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_geardyn"));
    // one thread: the points finish one by one, so the kill lands in the middle
    c.env("RAYON_NUM_THREADS", "1");
    c
}

fn scratch(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("geardyn-faults-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Every regular file in `dir`, by name.
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

fn run(c: &mut Command) -> Output {
    let o = c.output().unwrap();
    assert!(
        o.status.success(),
        "{:?} failed: {}",
        c,
        String::from_utf8_lossy(&o.stderr)
    );
    o
}

/// Lines in `path` (0 if absent).
fn lines(path: &Path) -> usize {
    std::fs::read(path).map_or(0, |b| b.iter().filter(|&&c| c == b'\n').count())
}

/// Start `geardyn study FILE --out OUT` and wait until its journal holds `records` finished
/// points (the header is one more line). Not a timing assertion: the wait ends when the
/// records are there; it fails only if the run ends first or after a generous 10 minutes.
fn start_and_wait(file: &Path, out: &Path, journal: &Path, records: usize) -> Child {
    let mut child = geardyn()
        .args(["study"])
        .arg(file)
        .arg("--out")
        .arg(out)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while lines(journal) < records + 1 {
        if let Some(s) = child.try_wait().unwrap() {
            panic!("the study ended ({s}) before {records} points were journaled");
        }
        assert!(
            start.elapsed() < Duration::from_secs(600),
            "no progress in 10 minutes"
        );
        std::thread::sleep(Duration::from_millis(1));
    }
    child
}

#[test]
fn a_killed_run_restarts_and_ends_byte_identical() {
    let root = scratch("kill");
    let file = root.join("killed.toml");
    std::fs::write(&file, STUDY).unwrap();

    // the uninterrupted run
    let reference = root.join("reference");
    run(geardyn()
        .arg("study")
        .arg(&file)
        .arg("--out")
        .arg(&reference));

    // a run killed with SIGKILL after 5 points
    let out = root.join("out");
    let journal = root.join(".out.journal");
    let lock = root.join(".out.lock");
    let mut child = start_and_wait(&file, &out, &journal, 5);
    child.kill().unwrap(); // SIGKILL on Unix
    child.wait().unwrap();
    assert!(lock.exists(), "the killed run's lock file is still there");
    assert!(!out.exists(), "no output of the killed run");
    let done = lines(&journal) - 1;
    assert!((5..200).contains(&done), "{done} points journaled");

    // started again: no manual step, the journal's points are taken, the result is identical
    let o = run(geardyn().arg("study").arg(&file).arg("--out").arg(&out));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(stderr.contains("resuming killed"), "{stderr}");
    assert_eq!(files(&out), files(&reference));
    assert!(!journal.exists() && !lock.exists());
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn a_live_run_refuses_a_second_one() {
    let root = scratch("live");
    let file = root.join("killed.toml");
    std::fs::write(&file, STUDY).unwrap();
    let out = root.join("out");
    let journal = root.join(".out.journal");
    let mut first = start_and_wait(&file, &out, &journal, 1);
    let second = geardyn()
        .arg("study")
        .arg(&file)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    first.kill().unwrap();
    first.wait().unwrap();
    assert_eq!(second.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&second.stderr);
    assert!(stderr.contains("is locked by a running study"), "{stderr}");
    assert!(stderr.contains(&format!("pid {}", first.id())), "{stderr}");
    let _ = std::fs::remove_dir_all(&root);
}

/// Flip bits of the first hexadecimal value of line `line` (1-based) of `path`.
fn flip_value(path: &Path, line: usize) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut out = String::new();
    for (k, l) in text.split_inclusive('\n').enumerate() {
        if k + 1 == line {
            let at = l.find("\"v\":[\"").expect("a record with values") + 6;
            let mut b = l.as_bytes().to_vec();
            // '3' ↔ '7' in the leading hex digit: one bit of the exponent
            b[at] ^= 0x04;
            out.push_str(std::str::from_utf8(&b).unwrap());
        } else {
            out.push_str(l);
        }
    }
    std::fs::write(path, out).unwrap();
}

#[test]
fn a_damaged_part_is_refused_by_merge_naming_file_and_line() {
    let root = scratch("merge");
    let file = root.join("killed.toml");
    std::fs::write(&file, STUDY.replace("steps = 200", "steps = 6")).unwrap();
    let out = root.join("out");
    let mut parts = Vec::new();
    for i in 1..=2 {
        let o = run(geardyn()
            .arg("study")
            .arg(&file)
            .arg("--out")
            .arg(&out)
            .args(["--shard", &format!("{i}/2")]));
        assert!(o.status.success());
        parts.push(root.join(format!("out-shards/killed.shard-{i}-of-2.part")));
    }
    // intact parts merge
    run(geardyn()
        .arg("merge")
        .arg(&file)
        .arg("--out")
        .arg(&out)
        .args(&parts));
    let good = files(&out);
    // one flipped bit in a value of part 2, line 3
    flip_value(&parts[1], 3);
    let o = geardyn()
        .arg("merge")
        .arg(&file)
        .arg("--out")
        .arg(&out)
        .args(&parts)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains("killed.shard-2-of-2.part, line 3: checksum mismatch"),
        "{stderr}"
    );
    assert_eq!(files(&out), good, "the outputs are untouched");
    let _ = std::fs::remove_dir_all(&root);
}
