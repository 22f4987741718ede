//! The Goodrive350 PROFINET card's generated code (`eds/goodrive350-pn.xml` through the sim
//! crate's build.rs, reached as `edsgen::cards::goodrive350_pn`): identity constants, the
//! 16-word images big-endian with their IOPS, the CW/SW bit masks of Tables 4-5/4-7, the PZD
//! parameter records of Tables 4-6/4-8, and a snapshot of the whole module.

mod process_support;

use edsgen::cards::goodrive350_pn as card;
use process_support::root;

use card::modules::pkw_pzd_16_words::subslot_1::{record_256, record_257, Input, Output};

#[test]
fn identity_is_the_gsdml_s() {
    assert_eq!(card::VENDOR_ID, 0x0350);
    assert_eq!(card::DEVICE_ID, 0x0350);
    assert_eq!(card::DAP_MODULE_IDENT, 1);
    assert_eq!(card::DNS_COMPATIBLE_NAME, "goodrive350-pn");
    assert_eq!(card::MIN_DEVICE_INTERVAL, 32);
    assert_eq!(card::modules::pkw_pzd_16_words::MODULE_IDENT, 0x10);
    assert_eq!(
        card::modules::pkw_pzd_16_words::subslot_1::SUBMODULE_IDENT,
        0x10
    );
    assert_eq!(card::modules::access_point::subslot_1::SUBMODULE_IDENT, 1);
}

#[test]
fn output_image_is_16_big_endian_words_then_the_iops() {
    assert_eq!(Output::LEN, 32);
    // §2.6's example as PROFINET carries it: a PKW read (task 1) of P00.10, CW 1 (run forward)
    // and PZD2 5000 (50.00 Hz once P16.32 = 1).
    let out = Output {
        pkw1_task_identification: 1,
        pkw2_parameter_address: 10,
        cw_control_word: 0x0001,
        pzd2_reference_value_p16_32: 5000,
        ..Output::default()
    };
    let bytes = out.encode_with_iops(card::IOXS_GOOD);
    assert_eq!(
        bytes[..12],
        [0x00, 0x01, 0x00, 0x0A, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01, 0x13, 0x88]
    );
    assert!(bytes[12..32].iter().all(|&b| b == 0));
    assert_eq!(bytes[32], 0x80);
    assert_eq!(Output::decode_with_iops(&bytes), (out, 0x80));
}

#[test]
fn cw_and_sw_bits_are_tables_4_5_and_4_7() {
    assert_eq!(Output::CW_CONTROL_WORD_ENABLE_WRITING_PKW, 0x0100);
    assert_eq!(Output::CW_CONTROL_WORD_HEARTBEAT_REFERENCE, 0x8000);
    assert_eq!(
        Input::SW_STATUS_WORD_BUS_VOLTAGE_ESTABLISHED_READY_TO_RUN,
        0x0100
    );
    assert_eq!(Input::SW_STATUS_WORD_OVERLOAD_PRE_ALARM, 0x1000);
    let input = Input::decode(&{
        let mut b = [0u8; 32];
        b[8] = 0x01; // SW high byte: ready to run
        b[9] = 0x03; // SW low byte: state 3, stopped
        b
    });
    assert_eq!(input.sw_status_word, 0x0103);
}

#[test]
fn the_pzd_records_default_to_invalid() {
    assert_eq!((record_256::INDEX, record_256::LENGTH), (256, 22));
    assert_eq!((record_257::INDEX, record_257::LENGTH), (257, 22));
    assert_eq!(record_256::DEFAULT, [0u8; 22]);
    assert_eq!(record_256::P16_32_RECEIVED_PZD2_BYTE_OFFSET, 0);
    assert_eq!(record_257::P16_53_TRANSMITTED_PZD12_BYTE_OFFSET, 20);
}

#[test]
fn generated_module_snapshot() {
    let path = root().join("eds/goodrive350-pn.xml");
    let read = edsgen_codegen::read::read_file(&path).expect("readable");
    let code = edsgen_codegen::emit::generate(&read.device, "goodrive350_pn").expect("generates");
    insta::assert_snapshot!("goodrive350_pn_module", code);
}
