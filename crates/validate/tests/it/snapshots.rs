//! insta snapshots of the fast studies, against the same files `cargo xtask validate` writes
//! (`validation/snapshots/<id>.snap`, model values rounded relative to their band). Heavy studies are
//! snapshot-checked by `cargo xtask validate --check` only.
//!
//! Under `CI=true` insta never writes and fails on a changed or missing snapshot; locally a
//! mismatch leaves a `.snap.new` next to the snapshot — run `cargo xtask validate` to regenerate
//! and review the diff.

use geardyn_validate::{Cost, all_studies, snapshot_body};

#[test]
fn fast_studies_match_their_snapshots() {
    for study in all_studies().into_iter().filter(|s| s.cost == Cost::Fast) {
        let output = study.execute();
        assert!(
            output.is_ok(),
            "study {} failed: {:?}",
            study.id,
            output.err()
        );
        let mut body = snapshot_body(&study, &output);
        // Figures that render are not noted in the body; a render error would be.
        if let Ok(out) = &output {
            for f in &out.figures {
                if let Err(e) = f.to_svg() {
                    body.push_str(&format!("render error: {e}\n"));
                }
            }
        }
        insta::with_settings!({
            snapshot_path => "../../../../validation/snapshots",
            prepend_module_to_snapshot => false,
            omit_expression => true,
        }, {
            insta::assert_snapshot!(study.id, body);
        });
    }
}

#[test]
fn outputs_are_deterministic() {
    let studies: Vec<_> = all_studies()
        .into_iter()
        .filter(|s| s.cost == Cost::Fast)
        .collect();
    let idx = geardyn_validate::ReadingsIndex::default();
    let a = geardyn_validate::render_all(&geardyn_validate::run_studies(&studies, |_| {}), &idx);
    let b = geardyn_validate::render_all(&geardyn_validate::run_studies(&studies, |_| {}), &idx);
    assert_eq!(a, b);
}

/// The `cargo xtask validate --check` integrity rules (causes named, no shared file names, no
/// verdict from a flagged point) hold for the fast studies.
#[test]
fn fast_studies_pass_the_audit() {
    let studies: Vec<_> = all_studies()
        .into_iter()
        .filter(|s| s.cost == Cost::Fast)
        .collect();
    let results = geardyn_validate::run_studies(&studies, |_| {});
    let problems = geardyn_validate::audit(&results);
    assert!(
        problems.is_empty(),
        "{}",
        problems
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join("\n")
    );
}
