//! The Goodrive350 EtherNet/IP card (`eds/goodrive350-enip.eds`, manual chapter 5): the EDS says
//! what the manual says, table by table; its generated module (`edsgen_sim::cards::goodrive350_enip`)
//! lays the 16 words out little-endian, as the EDS decides, and types them through
//! `edsgen_runtime::pkw_pzd`; and the drive behind the card answers the generated images.

mod card_support;

use card_support::pkw_pzd_drive::drive_answers;
use card_support::root;
use edsgen_model::model::{CipNumber, FieldRef, TriggerTransport};
use edsgen_model::{read, validate};
use edsgen_runtime::pkw_pzd::{
    ByteOrder, Command, ControlWord, OutputImage, PkwRequest, WordLayout,
};
use edsgen_sim::cards::goodrive350_enip as card;
use edsgen_sim::drives::pkw_pzd::Bus;

fn model() -> edsgen_model::model::Cip {
    let read = read::read_file(&root().join("eds/goodrive350-enip.eds")).expect("the card's EDS");
    assert_eq!(read.diagnostics, vec![]);
    assert_eq!(validate::validate(&read.device), vec![]);
    read.device.cip().cloned().expect("an ODVA EDS")
}

fn param_name(cip: &edsgen_model::model::Cip, member: &FieldRef) -> String {
    match member {
        FieldRef::Param(n) => cip.params[n].name.clone(),
        other => panic!("{other:?}"),
    }
}

#[test]
fn identity_as_chosen_and_recorded() {
    let cip = model();
    let id = &cip.identity;
    assert_eq!(id.vendor_code.as_ref().map(|v| v.value), Some(0));
    assert_eq!(id.product_type.as_ref().map(|v| v.value), Some(12));
    assert_eq!(id.product_code.as_ref().map(|v| v.value), Some(350));
    assert_eq!(
        (
            id.major_revision.as_ref().map(|v| v.value),
            id.minor_revision.as_ref().map(|v| v.value)
        ),
        (Some(1), Some(10))
    );
    assert_eq!(
        (card::VENDOR_ID, card::DEVICE_TYPE, card::PRODUCT_CODE),
        (0, 12, 350)
    );
    assert_eq!((card::MAJOR_REVISION, card::MINOR_REVISION), (1, 10));
    assert_eq!(card::PRODUCT_NAME, "Goodrive350 EtherNet/IP card");
}

/// 5.4.4, the Studio 5000 dialog: input 100 and output 150 of 16 words, configuration 1 of
/// size 0, RPI 50.0 ms in 1.0-3200.0 ms, path 20 04 24 01 2C 96 2C 64.
#[test]
fn the_dialog_of_5_4_4() {
    let cip = model();
    let size = |n: u32| cip.assemblies[&n].size.as_ref().map(|s| s.value);
    assert_eq!(
        (size(100), size(150), size(1)),
        (Some(32), Some(32), Some(0))
    );
    let c = &cip.connections[&1];
    assert_eq!(c.name, "Exclusive Owner");
    let tt = c.trigger_transport.as_ref().expect("word").value;
    assert_eq!(tt, TriggerTransport(0x8401_0002));
    assert_eq!(tt.application_types(), vec!["exclusive-owner"]);
    assert_eq!(c.o_t.format.value, FieldRef::Assem(150));
    assert_eq!(c.t_o.format.value, FieldRef::Assem(100));
    assert_eq!(c.config2.format.value, FieldRef::Assem(1));
    let rpi = &cip.params[&1];
    assert_eq!(
        (
            rpi.min.as_ref().map(|v| v.value),
            rpi.max.as_ref().map(|v| v.value),
            rpi.default.as_ref().map(|v| v.value)
        ),
        (
            Some(CipNumber::Int(1_000)),
            Some(CipNumber::Int(3_200_000)),
            Some(CipNumber::Int(50_000))
        )
    );
    let conn = card::EXCLUSIVE_OWNER;
    assert_eq!(
        (conn.o_t_assembly, conn.t_o_assembly, conn.config_assembly),
        (Some(150), Some(100), Some(1))
    );
    assert_eq!(
        (conn.o_t_size, conn.t_o_size, conn.rpi_us),
        (32, 32, 50_000)
    );
    assert_eq!(conn.path, &[0x20, 0x04, 0x24, 0x01, 0x2C, 0x96, 0x2C, 0x64]);
    assert_eq!((card::Output::INSTANCE, card::Output::SIZE), (150, 32));
    assert_eq!((card::Input::INSTANCE, card::Input::SIZE), (100, 32));
    assert_eq!(
        (card::Configuration::INSTANCE, card::Configuration::SIZE),
        (1, 0)
    );
}

/// Figure 5-5: one parameter per word, PKW1-PKW4, CW or SW, PZD2-PZD12.
#[test]
fn one_parameter_per_word_in_figure_5_5_order() {
    let cip = model();
    let names = |n: u32| -> Vec<String> {
        cip.assemblies[&n]
            .members
            .iter()
            .map(|m| {
                assert_eq!(m.bits, Some(16));
                param_name(&cip, &m.member)
            })
            .collect()
    };
    let mut output = vec![
        "PKW1 task",
        "PKW2 address",
        "PKW3 value high",
        "PKW4 value low",
        "CW",
    ]
    .into_iter()
    .map(String::from)
    .collect::<Vec<_>>();
    output.extend((2..=12).map(|i| format!("Received PZD{i}")));
    assert_eq!(names(150), output);
    let mut input = vec![
        "PKW1 response",
        "PKW2 address",
        "PKW3 value high",
        "PKW4 value low",
        "SW",
    ]
    .into_iter()
    .map(String::from)
    .collect::<Vec<_>>();
    input.extend((2..=12).map(|i| format!("Transmitted PZD{i}")));
    assert_eq!(names(100), input);
    // The drive's words are read only for the scanner (descriptor bit 4).
    for m in &cip.assemblies[&100].members {
        let FieldRef::Param(n) = m.member else {
            unreachable!()
        };
        assert!(cip.params[&n].read_only(), "Param{n}");
    }
}

/// Tables 5-7 and 5-10: PZD2 carries choice 1 (0.01 Hz); every PZD's help names its function
/// code.
#[test]
fn tables_5_7_and_5_10_pzd_functions() {
    let cip = model();
    for (param, units) in [(7, "Hz"), (23, "Hz")] {
        let p = &cip.params[&param];
        assert_eq!(p.units, units);
        assert_eq!(p.scaling, [Some(1), Some(100), Some(1), Some(0)]);
        assert_eq!(p.decimals, Some(2));
    }
    for i in 2..=12u32 {
        assert!(
            cip.params[&(5 + i)]
                .help
                .contains(&format!("P16.{}", 30 + i)),
            "PZD{i}"
        );
        assert!(
            cip.params[&(21 + i)]
                .help
                .contains(&format!("P16.{}", 41 + i)),
            "PZD{i}"
        );
    }
}

/// Tables 5-11 and 5-12: the task and response codes as enumerations.
#[test]
fn tables_5_11_and_5_12_codes() {
    let cip = model();
    let texts = |n: u32| -> Vec<(i64, String)> { cip.enums[&n].values.clone() };
    assert_eq!(
        texts(2),
        vec![
            (0, "No task".to_owned()),
            (1, "Read a parameter".to_owned()),
            (2, "Write one word (RAM)".to_owned()),
            (3, "Write two words (RAM)".to_owned()),
            (4, "Write one word (RAM and EEPROM)".to_owned()),
            (5, "Write two words (RAM and EEPROM)".to_owned()),
        ]
    );
    assert_eq!(
        texts(18),
        vec![
            (0, "No response".to_owned()),
            (1, "Value, one word".to_owned()),
            (2, "Value, two words".to_owned()),
            (3, "Refused (error in PKW3)".to_owned()),
        ]
    );
}

/// The byte order decision: every word little-endian. A read of P00.10 (task 1, address 10; the
/// manual's §2.6 prints "00 01 | 00 10" in decimal) with CW "run forward" by byte (Table 5-5)
/// and 50.00 Hz in PZD2 (5000 = 0x1388).
#[test]
fn output_image_little_endian() {
    let image = OutputImage {
        pkw: PkwRequest::read(10),
        control: ControlWord::new(Command::RunForward, WordLayout::ByByte),
        pzd: [5000, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
    };
    let output = card::Output::from_pkw_pzd(&image);
    assert_eq!(
        (output.pkw1_task, output.pkw2_address, output.cw),
        (1, 10, 1)
    );
    assert_eq!(output.received_pzd2, 5000);
    let mut bytes = [0u8; 32];
    bytes[..10].copy_from_slice(&[0x01, 0x00, 0x0A, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01, 0x00]);
    bytes[10..12].copy_from_slice(&[0x88, 0x13]);
    assert_eq!(output.to_bytes(), bytes);
    assert_eq!(output.pkw_pzd(), image);
    assert_eq!(image.emit(ByteOrder::LittleEndian), bytes);
}

/// Table 5-6 (P16.56 = 1): run forward is bit 0, so the CW word is 0x0001 too; jog forward is
/// 0x10 by bit and 3 by byte.
#[test]
fn table_5_6_by_bit() {
    let by_bit = ControlWord::new(Command::JogForward, WordLayout::ByBit);
    let by_byte = ControlWord::new(Command::JogForward, WordLayout::ByByte);
    let image = |control| OutputImage {
        pkw: PkwRequest::from_words([0; 4]),
        control,
        pzd: [0; 11],
    };
    assert_eq!(
        card::Output::from_pkw_pzd(&image(by_bit)).to_bytes()[8..10],
        [0x10, 0x00]
    );
    assert_eq!(
        card::Output::from_pkw_pzd(&image(by_byte)).to_bytes()[8..10],
        [0x03, 0x00]
    );
}

/// The card's images against the drive: PKW read of P00.10, a refused write (Table 5-12 error 7,
/// read only), run forward with the frequency from PZD2, SW running (Table 5-8) and the
/// transmitted PZD2 ramping.
#[test]
fn the_drive_answers_the_generated_images() {
    let answers = drive_answers(
        Bus::EthernetIp,
        ByteOrder::LittleEndian,
        |image| card::Output::from_pkw_pzd(image).to_bytes(),
        |bytes| card::Input::from_slice(bytes).expect("32 bytes"),
        |input| input.pkw_pzd().expect("a response"),
    );
    let (read, refused) = (&answers.read, &answers.refused);
    assert_eq!((read.pkw1_response, read.pkw2_address), (1, 10));
    assert_eq!(read.pkw4_value_low, answers.keypad);
    assert_eq!((refused.pkw1_response, refused.pkw3_value_high), (3, 7));
    let (first, later) = (&answers.first, &answers.later);
    assert!(later.transmitted_pzd2 > first.transmitted_pzd2, "ramping");
    assert!(later.transmitted_pzd2 <= 2500);
}

/// The generated module, byte for byte (with the overlay, as `sim/build.rs` generates it).
#[test]
fn generated_module_snapshot() {
    let path = root().join("eds/goodrive350-enip.eds");
    let mut read = read::read_file(&path).expect("the card's EDS");
    let overlay = std::fs::read_to_string(edsgen_model::overlay::path_for(&path))
        .expect("eds/goodrive350-enip.toml");
    assert_eq!(
        edsgen_model::overlay::apply(&overlay, &mut read.device),
        vec![]
    );
    let generated =
        edsgen_codegen::emit::generate_module(&read.device, "goodrive350_enip").expect("generates");
    assert_eq!(generated.diagnostics, vec![]);
    insta::assert_snapshot!("goodrive350_enip_module", generated.code);
}

/// Tables 5-11 and 5-12 as the generated enums of `Enum2` and `Enum18`: every task code the
/// EDS names is the runtime's task of the same number, and the four response codes convert both
/// ways; an undefined code comes back as the error.
#[test]
fn task_and_response_enums_follow_tables_5_11_and_5_12() {
    use edsgen_runtime::pkw_pzd::Task;
    let tasks = [
        (card::Pkw1Task::NoTask, Task::None),
        (card::Pkw1Task::ReadAParameter, Task::Read),
        (card::Pkw1Task::WriteOneWordRam, Task::WriteRam),
        (card::Pkw1Task::WriteTwoWordsRam, Task::WriteRamDouble),
        (card::Pkw1Task::WriteOneWordRamAndEeprom, Task::WriteEeprom),
        (
            card::Pkw1Task::WriteTwoWordsRamAndEeprom,
            Task::WriteEepromDouble,
        ),
    ];
    for (generated, runtime) in tasks {
        assert_eq!(generated.raw(), runtime.code());
        assert_eq!(card::Pkw1Task::try_from(runtime.code()), Ok(generated));
    }
    assert_eq!(card::Pkw1Task::try_from(6), Err(6));
    let responses = [
        (card::Pkw1Response::NoResponse, 0u16),
        (card::Pkw1Response::ValueOneWord, 1),
        (card::Pkw1Response::ValueTwoWords, 2),
        (card::Pkw1Response::RefusedErrorInPkw3, 3),
    ];
    for (generated, code) in responses {
        assert_eq!(u16::from(generated), code);
        assert_eq!(card::Pkw1Response::try_from(code), Ok(generated));
    }
    assert_eq!(card::Pkw1Response::try_from(4), Err(4));
    let request = card::Output {
        pkw1_task: card::Pkw1Task::ReadAParameter.into(),
        pkw2_address: 10,
        ..card::Output::default()
    };
    assert_eq!(request.pkw_pzd().pkw, PkwRequest::read(10));
}
