//! GSDML configurations chosen in the overlay's `[modules]`: modules a device takes only in
//! `AllowedInSlots` (p-net's sample application) plugged by ID, a non-default access point
//! (SEW's MOVI-C, three of them), what the access point does not allow refused with the line,
//! and the generated `configuration` module. Without the corpus the tests are skipped.

mod process_support;

use edsgen_model::model::Device;
use process_support::gsdml_corpus_dir;

const PNET: &str = "rtlabs-com__p-net/GSDML-V2.4-RT-Labs-P-Net-Sample-App-20230424.xml";
const SEW: &str =
    "HeisenZergA__SEWProfinetLabview/GSDML-V2.34-SEW-MOVI-C-Decentralized-Electronics-20200731-071447.xml";

/// The corpus file's device with `overlay` applied, and the overlay's messages with lines.
fn configured(file: &str, overlay: &str) -> Option<(Device, Vec<String>)> {
    let path = gsdml_corpus_dir()?.join(file);
    let mut device = edsgen_model::read::read_file(&path).unwrap().device;
    let diags = edsgen_model::overlay::apply(overlay, &mut device);
    let messages = diags
        .iter()
        .map(|d| format!("line {}: {}", d.span.map_or(0, |s| s.line), d.message))
        .collect();
    Some((device, messages))
}

#[test]
fn modules_only_allowed_in_slots_are_plugged_by_id() {
    let overlay = "[modules]\nslots = [\"IDM_40\", \"3=IDM_40\"]\n";
    let Some((device, messages)) = configured(PNET, overlay) else {
        return;
    };
    assert_eq!(messages, Vec::<String>::new());
    let pn = device.profinet().unwrap();
    let chosen = pn.chosen.clone().unwrap();
    let slots: Vec<(u16, &str)> = chosen
        .slots
        .iter()
        .map(|p| (p.slot, pn.modules[p.module].id.as_str()))
        .collect();
    assert_eq!(slots, [(1, "IDM_40"), (3, "IDM_40")]);
    // The default (nothing chosen) plugs nothing here: the modules are only allowed.
    assert_eq!(pn.configuration(), chosen);
    let code = edsgen_codegen::emit::generate_module(&device, "pnet")
        .unwrap()
        .code;
    let start = code
        .find("        /// The access point's `ID`.")
        .expect("a configuration");
    let expected = r#"        /// The access point's `ID`.
        pub const ACCESS_POINT: &str = "IDD_1";
        /// The access point's ModuleIdentNumber (slot 0).
        pub const ACCESS_POINT_IDENT: u32 = 0x00000001;
        /// The modules: slot, ModuleIdentNumber and `ID`, in slot order.
        pub const SLOTS: [(u16, u32, &str); 2] = [
            (1, 0x00000040, "IDM_40"),
            (3, 0x00000040, "IDM_40"),
        ];
        /// Slot 1: module `IDM_40`.
        pub use super::modules::setpoint_interface_module as slot_1;
        /// Slot 3: module `IDM_40`.
        pub use super::modules::setpoint_interface_module as slot_3;
    }
}
"#;
    assert_eq!(&code[start..], expected);
}

#[test]
fn what_the_access_point_does_not_allow_is_refused_with_the_line() {
    let overlay = "[modules]\n\nslots = [\"0=IDM_40\", \"5=IDM_40\", \"IDM_41\"]\n";
    let Some((device, messages)) = configured(PNET, overlay) else {
        return;
    };
    assert_eq!(
        messages,
        [
            "line 3: slot 0 is the access point's",
            "line 3: module IDM_40 is not allowed in slot 5 (it may take 1..4)",
            "line 3: no module \"IDM_41\"; did you mean:\n  \"IDM_40\" among access point IDD_1's modules",
        ]
    );
    assert_eq!(device.profinet().unwrap().chosen, None);
}

#[test]
fn a_non_default_access_point_is_chosen() {
    let overlay = "[modules]\naccess_point = \"DFC2xA V4.0\"\nslots = [\"2=1PD_InOut\"]\n";
    let Some((device, messages)) = configured(SEW, overlay) else {
        return;
    };
    assert_eq!(messages, Vec::<String>::new());
    let pn = device.profinet().unwrap();
    assert_eq!(pn.chosen.as_ref().unwrap().access_point, 2);
    let code = edsgen_codegen::emit::generate_module(&device, "sew")
        .unwrap()
        .code;
    assert!(code.contains("pub const ACCESS_POINT: &str = \"DFC2xA V4.0\";"));
    assert!(code.contains("The chosen access point's own submodules (`DFC2xA V4.0`, slot 0)."));
    let (_, messages) = configured(SEW, "[modules]\naccess_point = \"DFC2xA V9.0\"\n").unwrap();
    assert_eq!(
        messages,
        ["line 2: no access point \"DFC2xA V9.0\"; did you mean:\n  \"DFC2xA V1.0\"\n  \"DFC2xA V2.0\"\n  \"DFC2xA V4.0\""]
    );
}
