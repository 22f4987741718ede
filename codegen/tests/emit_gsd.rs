//! The code generated from the Goodrive350 DP card's GSD with its overlay (`[pkw_pzd]`): a
//! snapshot, and the overlay's checks.

use std::path::Path;

use edsgen_codegen::builder::generate_device;
use edsgen_model::overlay;
use edsgen_model::read::read_file;

#[test]
fn the_dp_card_generates() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../eds/goodrive350-dp.gsd");
    let (code, warnings) = generate_device(&path, "goodrive350_dp", &Default::default()).unwrap();
    assert_eq!(warnings, Vec::<String>::new());
    insta::assert_snapshot!(code);
    assert!(code.contains("pub const IDENT_NUMBER: u16 = 0x0350;"));
    assert!(code.contains("pub const CONFIG: [u8; 2] = [0xF3, 0xFB];"));
    // The overlay's [pkw_pzd]: the images convert to the runtime's PKW/PZD images.
    assert!(code.contains("pub fn pkw_pzd(&self) -> ::edsgen_runtime::pkw_pzd::OutputImage"));
    assert!(!code.contains("unsafe"));
}

#[test]
fn the_pkw_pzd_overlay_is_checked() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../eds/goodrive350-dp.gsd");
    let mut device = read_file(&path).unwrap().device;
    let diags = overlay::apply("[pkw_pzd]\nmodule = \"PPO 2\"\n", &mut device);
    let messages: Vec<_> = diags
        .iter()
        .map(|d| (d.rule.code, d.message.as_str()))
        .collect();
    assert_eq!(
        messages,
        [(
            "EDS708",
            "no module \"PPO 2\" of 32 bytes each way whose first identifier is 4 words (PKW1-PKW4)"
        )]
    );
    assert_eq!(device.dp().unwrap().pkw_pzd_module, None);
    let diags = overlay::apply("[pkw_pzd]\nmodule = \"4 PKW + 12 PZD\"\n", &mut device);
    assert_eq!(diags.len(), 0);
    assert_eq!(
        device.dp().cloned().unwrap().pkw_pzd_module.as_deref(),
        Some("4 PKW + 12 PZD")
    );
}
