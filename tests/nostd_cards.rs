//! The generated code of the cards in `eds/` (EDS, ESI, ODVA EDS, GSDML and GSD), with the runtime's object-dictionary trait, builds
//! for `thumbv7em-none-eabihf` (no `std`, no `alloc`).

mod emit_common;
mod process_support;

use emit_common::*;
use process_support::{root, skip};

#[test]
fn cards_build_for_thumbv7em() {
    let installed = std::process::Command::new("rustup")
        .args(["target", "list", "--installed"])
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).contains("thumbv7em-none-eabihf"))
        .unwrap_or(false);
    if !installed {
        skip::<()>(
            "thumbv7em-none-eabihf is not installed (rustup target add thumbv7em-none-eabihf)",
        );
        return;
    }
    let cards = card_files();
    assert_eq!(
        cards.len(),
        9,
        "the five EDS cards, the ESI card and the ODVA EDS, GSDML and GSD cards in eds/"
    );
    let modules: Vec<_> = cards
        .iter()
        .map(|path| {
            let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
            let module = edsgen_codegen::emit::module_name(&stem);
            let code =
                generate(path, &module).unwrap_or_else(|d| panic!("{}: {d:?}", path.display()));
            (module, code)
        })
        .collect();
    // The hand-built module of the codegen tests exercises odd widths, strings and bit-packed PDOs.
    let mut modules = modules;
    modules.push((
        "gd350".to_owned(),
        std::fs::read_to_string(root().join("codegen/tests/generated/gd350.rs")).unwrap(),
    ));
    // The hand-built EtherCAT module: odd widths and offsets, padding, fields over 64 bits.
    modules.push((
        "ec_hand".to_owned(),
        std::fs::read_to_string(root().join("codegen/tests/generated/ec_hand.rs")).unwrap(),
    ));
    // The hand-built ODVA EDS module: identity, two assembly images and a connection.
    modules.push((
        "odva_io".to_owned(),
        std::fs::read_to_string(root().join("codegen/tests/generated/odva_io.rs")).unwrap(),
    ));
    let index = write_modules("nostd-cards", &modules);
    build_compile_check(&index, Some("thumbv7em-none-eabihf"), "nostd-cards");
}
