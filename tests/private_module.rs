//! `include_device!` where firmware usually puts it, inside a private module that uses none of
//! it: the seven cards' modules compile there under `-D warnings` (no dead-code warnings).

mod emit_common;
mod process_support;

use emit_common::*;

#[test]
fn generated_modules_in_a_private_module_compile_without_warnings() {
    let modules: Vec<_> = card_files()
        .iter()
        .map(|path| {
            let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
            let module = edsgen_codegen::emit::module_name(&stem);
            let code =
                generate(path, &module).unwrap_or_else(|d| panic!("{}: {d:?}", path.display()));
            (module, code)
        })
        .collect();
    assert_eq!(
        modules.len(),
        9,
        "the five EDS cards, the ESI card and the ODVA EDS, GSDML and GSD cards in eds/"
    );
    let index = write_modules("private-module", &modules);
    build_compile_check_with(&index, None, "private-module", &["private"]);
}
