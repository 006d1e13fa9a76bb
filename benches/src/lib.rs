//! Empty: the benches live in `benches/` (see `Cargo.toml`).
