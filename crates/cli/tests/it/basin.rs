//! `geardyn study` on a `[basin]` file: the cell table, the fractions CSV, the attractor map
//! and one stdout line per attractor.

use std::process::Command;

/// A 2 × 2 Liu basin with short windows (20 periods from the start): a mechanics test.
const STUDY: &str = r#"
name = "basin"
model = "liu2021"
[overrides]
eccentricity = 0.0
[solver]
method = "time-stepping"
[solver.settings]
window_periods = 20
max_transient_periods = 0
transient_periods = 0
[basin]
q = { from = -0.002, to = 0.0, steps = 2 }
q_dot = { from = -0.001, to = 0.001, steps = 2 }
"#;

#[test]
fn a_basin_study_writes_cells_fractions_and_map() {
    let dir = std::env::temp_dir().join(format!("geardyn-basin-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("basin.toml");
    std::fs::write(&file, STUDY).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_geardyn"))
        .arg("study")
        .arg(&file)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let out = dir.join("basin");
    let cells = std::fs::read_to_string(out.join("basin.csv")).unwrap();
    assert!(cells.starts_with("q,q_dot,"), "{cells}");
    assert_eq!(cells.lines().count(), 1 + 4);
    let fractions = std::fs::read_to_string(out.join("basin_fractions.csv")).unwrap();
    assert!(
        fractions.starts_with("attractor,rsv [1],motion,ppv [1]"),
        "{fractions}"
    );
    assert!(
        fractions.lines().last().unwrap().starts_with("failed,"),
        "{fractions}"
    );
    let svg = std::fs::read_to_string(out.join("basin_attractor_map.svg")).unwrap();
    assert!(svg.contains("A0: "), "no legend in the map");
    // one line per attractor: as many as the fractions table has attractor rows
    let n = fractions.lines().count() - 2;
    assert_eq!(
        stdout.lines().filter(|l| l.starts_with("  A")).count(),
        n,
        "{stdout}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
