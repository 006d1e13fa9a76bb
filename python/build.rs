//! Link arguments of the extension module.
//!
//! On ELF platforms the shared library binds its own definitions of the C math symbols (`sin`,
//! `pow`, …, defined by geardyn-math's `c-symbols` feature) at link time (`-Bsymbolic`), so that
//! the libm the Python interpreter has already loaded does not interpose them and the results
//! are the same bits on every platform. Mach-O (two-level namespace) and PE bind to the defining
//! image already.

fn main() {
    let os = std::env::var("CARGO_CFG_TARGET_OS").unwrap_or_default();
    if matches!(
        os.as_str(),
        "linux" | "android" | "freebsd" | "netbsd" | "openbsd" | "dragonfly"
    ) {
        println!("cargo:rustc-cdylib-link-arg=-Wl,-Bsymbolic");
    }
    println!("cargo:rerun-if-changed=build.rs");
}
