//! Generates the typed bindings of the bundled cards from `../eds/` (five EDS files, one ESI and one GSD), exactly as a user's build.rs
//! would: one `.device()` line per card. An error in a card's EDS fails the build with the
//! rendered diagnostics; warnings show as cargo warnings.

fn main() -> Result<(), edsgen_codegen::builder::BuildError> {
    edsgen_codegen::Builder::new()
        .device("../eds/cp301.eds")
        .device("../eds/goodrive350.eds")
        .device("../eds/hd1e.eds")
        .device("../eds/ms300.eds")
        .device("../eds/rd11.eds")
        // The EC-TX508 EtherCAT card (an ESI file): its CoE dictionary and process images.
        .device("../eds/ec-tx508.xml")
        // The Goodrive350's EtherNet/IP card (an ODVA EDS, with goodrive350-enip.toml): identity,
        // the assemblies' images typed through edsgen_runtime::pkw_pzd, its connection.
        .device("../eds/goodrive350-enip.eds")
        // The Goodrive350's PROFINET card (a GSDML file, with goodrive350-pn.toml): identity,
        // its module's images typed through edsgen_runtime::pkw_pzd, its PZD parameter records.
        .device("../eds/goodrive350-pn.xml")
        // The Goodrive350's PROFIBUS-DP card (a GSD file): identity, Chk_Cfg bytes, images.
        .device("../eds/goodrive350-dp.gsd")
        // Goodrive350 and HD1-E keep a 16-bit value in sub-index 0 of 2000h/2100h (their manuals
        // say so); the EDS files document it and the card tests pin the warning.
        .allow("EDS308")
        .generate()
}
