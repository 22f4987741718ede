//! Puts memory.x and device.x where the cortex-m-rt linker script finds them, and generates the CP301 card's
//! object dictionary from `eds/cp301.eds` for the `cp301` example and the EC-TX508's from
//! `eds/ec-tx508.xml` for the `ec_tx508` example, as any firmware's build.rs would.
use std::{env, fs, path::PathBuf};

fn main() -> Result<(), edsgen_codegen::builder::BuildError> {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    fs::copy("memory.x", out.join("memory.x")).expect("memory.x is readable");
    fs::copy("device.x", out.join("device.x")).expect("device.x is readable");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=device.x");
    println!("cargo:rerun-if-changed=build.rs");
    edsgen_codegen::Builder::new()
        .device("../eds/cp301.eds")
        .device("../eds/ec-tx508.xml")
        .generate()
}
