//! geardyn project automation.
fn main() {}
