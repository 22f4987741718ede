//! Generates the object dictionaries of two bundled cards for the `node` target, as a firmware's
//! build.rs would: CP301 (LowLimit/HighLimit entries) and Goodrive350 (strings, dummy mappings).
fn main() -> Result<(), edsgen_codegen::builder::BuildError> {
    println!("cargo:rerun-if-changed=build.rs");
    edsgen_codegen::Builder::new()
        .device("../eds/cp301.eds")
        .device("../eds/goodrive350.eds")
        .generate()
}
