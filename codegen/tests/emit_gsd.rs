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

/// A modular station of three slots, slot 1 for the PPO modules (as a MICROMASTER's), 2 and 3
/// for I/O modules (the model's fixture, shared with its tests and the DP simulator's).
const MODULAR: &str = include_str!("../../model/src/model/modules/modular.gsd");

fn modular(overlay_text: &str) -> (edsgen_model::model::Device, Vec<String>) {
    let mut device =
        edsgen_model::read::read_bytes(Path::new("modular.gsd"), MODULAR.as_bytes()).device;
    let diags = overlay::apply(overlay_text, &mut device);
    let messages = diags
        .iter()
        .map(|d| {
            let line = d.span.map_or(0, |s| s.line);
            format!("{} line {line}: {}", d.rule.code, d.message)
        })
        .collect();
    (device, messages)
}

#[test]
fn a_chosen_configuration_generates_the_whole_slaves_images() {
    let (device, messages) =
        modular("[modules]\nslots = [\"4 PKW, 2 PZD (PPO 1)\", \"3=16 words out\"]\n");
    assert_eq!(messages, Vec::<String>::new());
    let code = edsgen_codegen::emit::generate_module(&device, "modular")
        .unwrap()
        .code;
    let start = code
        .find("    /// The configuration chosen")
        .expect("a configuration");
    insta::assert_snapshot!(&code[start..]);
    // Without [modules], no configuration (the default is unchanged).
    let (device, _) = modular("");
    let code = edsgen_codegen::emit::generate_module(&device, "modular")
        .unwrap()
        .code;
    assert!(!code.contains("pub mod configuration"));
}

#[test]
fn the_modules_overlay_is_checked_with_lines() {
    let (device, messages) = modular("[modules]\nslots = [\n  \"8 DI\",\n  \"PPO 9\",\n]\n");
    assert_eq!(
        messages,
        [
            "EDS708 line 2: slot 2: no module \"PPO 9\"; did you mean:\n  \"8 DI\"\n  \"16 words out\"\n  \"4 PKW, 2 PZD (PPO 1)\"",
            "EDS708 line 2: slot 1 (\"Drive\") does not take module \"8 DI\"",
        ]
    );
    assert_eq!(device.dp().unwrap().chosen, None);
    let (_, messages) = modular("[modules]\nslots = [\"1=\"]\nplugs = 1\n");
    assert_eq!(
        messages,
        [
            "EDS708 line 2: `1=`: no module named (write SLOT=NAME or NAME)",
            "EDS708 line 3: `plugs` is not a key of [modules] (slots = [\"NAME\", ...], access_point = \"ID\")",
        ]
    );
}
