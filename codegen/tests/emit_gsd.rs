//! The code generated from the Goodrive350 DP card's GSD: a snapshot, and its images read and
//! written as big-endian words.

use std::path::Path;

use edsgen_codegen::emit::generate;
use edsgen_codegen::read::read_file;

#[test]
fn the_dp_card_generates() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../eds/goodrive350-dp.gsd");
    let device = read_file(&path).unwrap().device;
    let code = generate(&device, "goodrive350_dp").unwrap();
    insta::assert_snapshot!(code);
    assert!(code.contains("pub const IDENT_NUMBER: u16 = 0x0350;"));
    assert!(code.contains("pub const CONFIG: [u8; 2] = [0xF3, 0xFB];"));
    assert!(!code.contains("unsafe"));
}
