//! `cargo xtask study <file.toml>`.

use std::path::Path;

use indicatif::{ProgressBar, ProgressStyle};
use validate::UserStudy;

pub fn run(file: &Path, out: Option<&Path>) -> Result<(), String> {
    let text = std::fs::read_to_string(file).map_err(|e| format!("{}: {e}", file.display()))?;
    let study = UserStudy::parse(&text).map_err(|e| format!("{}: {e}", file.display()))?;
    let n = study
        .sweep
        .as_ref()
        .map_or(Ok(1), |s| s.points().map(|p| p.len()))
        .map_err(|e| e.to_string())?
        * study
            .sweep2
            .as_ref()
            .map_or(Ok(1), |s| s.points().map(|p| p.len()))
            .map_err(|e| e.to_string())?;
    let pb = ProgressBar::new(n as u64);
    pb.set_style(
        ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} points (eta {eta})")
            .map_err(|e| e.to_string())?
            .progress_chars("=> "),
    );
    let result = validate::run_user_study(&study, || pb.inc(1)).map_err(|e| e.to_string())?;
    pb.finish_and_clear();

    let dir = match out {
        Some(d) => d.to_path_buf(),
        None => file.parent().unwrap_or(Path::new(".")).join(&study.name),
    };
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let write = |name: String, bytes: &[u8]| -> Result<(), String> {
        let p = dir.join(name);
        std::fs::write(&p, bytes).map_err(|e| format!("{}: {e}", p.display()))?;
        println!("wrote {}", p.display());
        Ok(())
    };
    write(
        format!("{}.csv", study.name),
        result.table.to_csv().as_bytes(),
    )?;
    for f in &result.figures {
        let svg = f.to_svg().map_err(|e| e.to_string())?;
        write(format!("{}.svg", f.name), svg.as_bytes())?;
    }
    let json = serde_json::to_string_pretty(&result.summary).map_err(|e| e.to_string())?;
    write(
        format!("{}.json", study.name),
        format!("{json}\n").as_bytes(),
    )?;
    let failed = result.summary["failed_points"]
        .as_array()
        .map_or(0, Vec::len);
    if failed > 0 {
        eprintln!("warning: {failed} point(s) failed; see the JSON summary");
    }
    Ok(())
}
