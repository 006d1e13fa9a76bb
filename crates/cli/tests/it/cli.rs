//! The generated model reference of docs/studies.md.

#[test]
fn the_model_reference_in_the_docs_is_current() {
    // `cargo xtask validate` writes it; GEARDYN_BLESS=1 writes it from this test.
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let bless = std::env::var_os("GEARDYN_BLESS").is_some();
    match geardyn_cli::sync_models_doc(&root, !bless) {
        Ok(_) => {}
        Err(e) => panic!("{}", e.message),
    }
    let text = std::fs::read_to_string(root.join(geardyn_cli::MODELS_DOC)).unwrap();
    // every registered model has its section, generated from the same source as `geardyn models`
    for m in study::REGISTRY.iter() {
        assert!(
            text.contains(&format!("### `{}`", m.name())),
            "{}",
            m.name()
        );
    }
    assert!(geardyn_cli::models_markdown().contains("| `omega1` | rad/s |"));
}

#[test]
fn a_stale_model_reference_fails_the_check() {
    let dir = std::env::temp_dir().join(format!("geardyn-models-doc-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("docs")).unwrap();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let text = std::fs::read_to_string(root.join(geardyn_cli::MODELS_DOC)).unwrap();
    let stale = text.replacen("| `omega1` | rad/s |", "| `omega1` | rpm |", 1);
    assert!(stale != text, "the reference lists omega1 in rad/s");
    std::fs::write(dir.join(geardyn_cli::MODELS_DOC), &stale).unwrap();
    let e = geardyn_cli::sync_models_doc(&dir, true).unwrap_err();
    assert!(
        e.message.contains("model reference is stale"),
        "{}",
        e.message
    );
    // regenerating restores it
    assert!(geardyn_cli::sync_models_doc(&dir, false).unwrap());
    let fixed = std::fs::read_to_string(dir.join(geardyn_cli::MODELS_DOC)).unwrap();
    assert!(
        fixed == text,
        "regenerated differs from the committed reference"
    );
    assert!(!geardyn_cli::sync_models_doc(&dir, true).unwrap());
    // missing markers: an error, not a silent rewrite
    std::fs::write(dir.join(geardyn_cli::MODELS_DOC), "no markers\n").unwrap();
    assert!(geardyn_cli::sync_models_doc(&dir, false).is_err());
    let _ = std::fs::remove_dir_all(&dir);
}
