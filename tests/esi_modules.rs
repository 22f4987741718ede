//! ESI module instances chosen in the overlay's `[modules]`: UTRIO's UC20 coupler (modules only,
//! one `Slots/Slot` taking them by class) plugged with two output modules and an input module,
//! their PDOs moved by `SlotPdoIncrement` and in the generated process images; what the slots do
//! not allow is refused with the line. Without the corpus the tests are skipped.

mod process_support;

use edsgen_model::model::Device;
use process_support::esi_corpus_dir;

const UC20: &str =
    "linuxcnc-ethercat__linuxcnc-ethercat/scripts__esi__UTRIO-UC20-RTU-EC-A_20251104.xml";

fn configured(overlay: &str) -> Option<(Device, Vec<String>)> {
    let path = esi_corpus_dir()?.join(UC20);
    let mut device = edsgen_model::read::read_file(&path).unwrap().device;
    let diags = edsgen_model::overlay::apply(overlay, &mut device);
    let messages = diags
        .iter()
        .map(|d| format!("line {}: {}", d.span.map_or(0, |s| s.line), d.message))
        .collect();
    Some((device, messages))
}

#[test]
fn chosen_modules_add_their_pdos_to_the_images() {
    let overlay = "[modules]\nslots = [\"UC20-16DO-P\", \"UC20-8DI-NP\", \"1=UC20-16DO-N\"]\n";
    let Some((device, messages)) = configured(overlay) else {
        return;
    };
    assert_eq!(messages, Vec::<String>::new());
    let ec = device.ethercat().unwrap();
    assert!(ec.rx_pdos.is_empty() && ec.tx_pdos.is_empty());
    let plugged = ec.configured();
    let indices = |pdos: &[edsgen_model::model::EcPdo]| -> Vec<(u16, Option<u8>)> {
        pdos.iter().map(|p| (p.index, p.sm)).collect()
    };
    // Instances 0, 1, 2 in the order chosen: the PDOs move by 1 per instance.
    assert_eq!(
        indices(&plugged.rx_pdos),
        [(0x1600, Some(2)), (0x1602, Some(2))]
    );
    assert_eq!(indices(&plugged.tx_pdos), [(0x1A01, Some(3))]);
    let code = edsgen_codegen::emit::generate_module(&device, "uc20")
        .unwrap()
        .code;
    let start = code.find("pub struct Outputs").expect("an output image");
    let outputs = &code[start..start + code[start..].find('}').unwrap()];
    assert!(
        outputs.contains("pdo_1600") && outputs.contains("pdo_1602"),
        "{outputs}"
    );
    assert!(code.contains("pub struct Inputs"), "{code}");
    // Nothing chosen: the device as described, no image.
    let (device, _) = configured("").unwrap();
    let code = edsgen_codegen::emit::generate_module(&device, "uc20")
        .unwrap()
        .code;
    assert!(!code.contains("pub struct Outputs"));
}

#[test]
fn what_the_slots_do_not_allow_is_refused_with_the_line() {
    let overlay = "[modules]\nslots = [\n\"2=UC20-16DO-P\",\n\"UC20-16DO\"]\n";
    let Some((device, messages)) = configured(overlay) else {
        return;
    };
    assert_eq!(
        messages,
        [
            "line 2: slot 2: the device has slots 1 to 1",
            "line 2: no module \"UC20-16DO\"; did you mean:\n  \"UC20-16DO-P\"\n  \"UC20-16DO-N\"\n  \"UC20-16DI-NP\"",
        ]
    );
    assert_eq!(device.ethercat().unwrap().chosen, None);
}
