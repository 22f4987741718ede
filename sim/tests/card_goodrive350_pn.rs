//! The Goodrive350 PROFINET card's generated code (`eds/goodrive350-pn.xml` with
//! `eds/goodrive350-pn.toml`, through the sim crate's build.rs, reached as
//! `edsgen_sim::cards::goodrive350_pn`): identity constants, the 16-word images big-endian with their
//! IOPS and typed through `edsgen_runtime::pkw_pzd` (the manual's §2.6 PKW examples byte for
//! byte), the CW/SW bit masks of Tables 4-5/4-7, the PZD parameter records of Tables 4-6/4-8,
//! the drive behind the card answering the generated images, and a snapshot of the whole module.

mod card_support;

use card_support::pkw_pzd_drive::drive_answers;
use card_support::root;
use edsgen_runtime::pkw_pzd::control::{cw_bit, sw_bit};
use edsgen_runtime::pkw_pzd::{
    ByteOrder, Command, ControlWord, InputImage, OutputImage, PkwRequest, PkwResponse,
    ResponseError, RunState, RunStopMode, StatusWord, Task, WordLayout,
};
use edsgen_sim::cards::goodrive350_pn as card;
use edsgen_sim::drives::pkw_pzd::Bus;

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
    assert_eq!(Output::SIZE, 32);
    // §2.6's example as PROFINET carries it: a PKW read (task 1) of P00.10, CW 1 (run forward)
    // and PZD2 5000 (50.00 Hz once P16.32 = 1).
    let out = Output {
        pkw1_task_identification: 1,
        pkw2_parameter_address: 10,
        cw_control_word: 0x0001,
        pzd2_reference_value_p16_32: 5000,
        ..Output::default()
    };
    let bytes = out.to_bytes_with_iops(card::IOXS_GOOD);
    assert_eq!(
        bytes[..12],
        [0x00, 0x01, 0x00, 0x0A, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01, 0x13, 0x88]
    );
    assert!(bytes[12..32].iter().all(|&b| b == 0));
    assert_eq!(bytes[32], 0x80);
    assert_eq!(Output::from_bytes_with_iops(&bytes), (out, 0x80));
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
    // The GSDML's named bits are the runtime's typed ones.
    assert_eq!(
        [
            Output::CW_CONTROL_WORD_ENABLE_WRITING_PKW,
            Output::CW_CONTROL_WORD_CONTROL_MODE_SWITCHING,
            Output::CW_CONTROL_WORD_RESET_POWER_CONSUMPTION_TO_ZERO,
            Output::CW_CONTROL_WORD_PRE_EXCITATION,
            Output::CW_CONTROL_WORD_DC_BRAKING,
            Output::CW_CONTROL_WORD_HEARTBEAT_REFERENCE,
        ],
        [
            cw_bit::ENABLE_WRITE,
            cw_bit::CONTROL_MODE_SWITCH,
            cw_bit::RESET_POWER_CONSUMPTION,
            cw_bit::PRE_EXCITATION,
            cw_bit::DC_BRAKING,
            cw_bit::HEARTBEAT,
        ]
    );
    assert_eq!(
        [
            Input::SW_STATUS_WORD_BUS_VOLTAGE_ESTABLISHED_READY_TO_RUN,
            Input::SW_STATUS_WORD_MOTOR_TYPE_FEEDBACK_SYNCHRONOUS,
            Input::SW_STATUS_WORD_OVERLOAD_PRE_ALARM,
            Input::SW_STATUS_WORD_HEARTBEAT_FEEDBACK,
        ],
        [
            sw_bit::READY,
            sw_bit::SYNCHRONOUS_MOTOR,
            sw_bit::OVERLOAD_PRE_ALARM,
            sw_bit::HEARTBEAT,
        ]
    );
    let input = Input::from_bytes(&{
        let mut b = [0u8; 32];
        b[8] = 0x01; // SW high byte: ready to run
        b[9] = 0x03; // SW low byte: state 3, stopped
        b
    });
    assert_eq!(input.sw_status_word, 0x0103);
}

/// §2.6 PKW example 1 (chapter 4 has the same PKW tables, 4-9/4-10, and no examples of its own)
/// as PROFINET carries it. The manual prints the request "00 01 | 00 10 | 00 00 | 00 00" in
/// decimal: task 1 (read), address 10 (P00.10, the keypad frequency); on the wire, big-endian,
/// 00 01 00 0A 00 00 00 00, then the CW and PZD2-PZD12, then the IOPS.
#[test]
fn pkw_example_1_read_request() {
    let image = OutputImage {
        pkw: PkwRequest::read(10),
        control: ControlWord(0),
        pzd: [0; 11],
    };
    let output = Output::from_pkw_pzd(&image);
    assert_eq!(
        (
            output.pkw1_task_identification,
            output.pkw2_parameter_address
        ),
        (1, 10)
    );
    let mut frame = [0u8; 33];
    frame[..8].copy_from_slice(&[0x00, 0x01, 0x00, 0x0A, 0x00, 0x00, 0x00, 0x00]);
    frame[32] = 0x80;
    assert_eq!(output.to_bytes_with_iops(card::IOXS_GOOD), frame);
    let (decoded, iops) = Output::from_bytes_with_iops(&frame);
    assert_eq!((decoded.pkw_pzd(), iops), (image, 0x80));
    assert_eq!(decoded.pkw_pzd().pkw.task, Task::Read);
}

/// §2.6 PKW example 1, the response "00 01 | 00 10 | 00 00 | 50 00": response 1 (one word),
/// address 10, value 5000 (50.00 Hz), which is 0x1388 on the wire: 00 01 00 0A 00 00 13 88.
/// The SW beside it: ready to run (bit 8) and state 3, stopped (Table 4-7).
#[test]
fn pkw_example_1_read_response() {
    let mut frame = [0u8; 33];
    frame[..10].copy_from_slice(&[0x00, 0x01, 0x00, 0x0A, 0x00, 0x00, 0x13, 0x88, 0x01, 0x03]);
    frame[32] = 0x80;
    let (input, iops) = Input::from_bytes_with_iops(&frame);
    assert_eq!(iops, card::IOXS_GOOD);
    assert_eq!(
        (
            input.pkw1_response_identification,
            input.pkw2_parameter_address,
            input.pkw4_value_low_word
        ),
        (1, 10, 5000)
    );
    let image = input.pkw_pzd().expect("response 1");
    assert_eq!(
        image.pkw,
        PkwResponse::Word {
            address: 10,
            value: 5000
        }
    );
    assert_eq!(image.status, StatusWord(0x0103));
    assert_eq!(
        image.status.state(WordLayout::ByByte),
        Some(RunState::Stopped)
    );
    assert!(image.status.ready());
    assert_eq!(
        Input::from_pkw_pzd(&image).to_bytes_with_iops(card::IOXS_GOOD),
        frame
    );
}

/// §2.6 PKW example 2: "00 04 | 00 10 | 00 00 | 50 00" writes 5000 (50.00 Hz) to address 10 in
/// RAM and EEPROM (task 4): 00 04 00 0A 00 00 13 88 on the wire, with the CW's "enable writing"
/// (bit 8, Table 4-5) set; the drive answers as in example 1.
#[test]
fn pkw_example_2_write() {
    let image = OutputImage {
        pkw: PkwRequest::write(10, 5000),
        control: ControlWord(0).with(Output::CW_CONTROL_WORD_ENABLE_WRITING_PKW, true),
        pzd: [0; 11],
    };
    let bytes = Output::from_pkw_pzd(&image).to_bytes();
    assert_eq!(
        bytes[..10],
        [0x00, 0x04, 0x00, 0x0A, 0x00, 0x00, 0x13, 0x88, 0x01, 0x00]
    );
    assert_eq!(
        Output::from_bytes(&bytes).pkw_pzd().pkw.task,
        Task::WriteEeprom
    );
}

/// The CW of Table 4-5 typed: run forward (command 1 in bits 0-7) with the heartbeat (bit 15)
/// is 0x8001, high byte first; PZD2-PZD12 follow in order, PZD12 in the last two bytes.
#[test]
fn cw_command_and_pzd_words_in_place() {
    let mut pzd = [0u16; 11];
    pzd[0] = 5000;
    pzd[10] = 0xBEEF;
    let image = OutputImage {
        pkw: PkwRequest::from_words([0; 4]),
        control: ControlWord::new(Command::RunForward, WordLayout::ByByte)
            .with(Output::CW_CONTROL_WORD_HEARTBEAT_REFERENCE, true),
        pzd,
    };
    let output = Output::from_pkw_pzd(&image);
    assert_eq!(output.cw_control_word, 0x8001);
    assert_eq!(output.pzd2_reference_value_p16_32, 5000);
    assert_eq!(output.pzd12_reference_value_p16_42, 0xBEEF);
    let bytes = output.to_bytes();
    assert_eq!(bytes[8..12], [0x80, 0x01, 0x13, 0x88]);
    assert_eq!(bytes[30..], [0xBE, 0xEF]);
    assert_eq!(
        output.pkw_pzd().control.command(WordLayout::ByByte),
        Some(Command::RunForward)
    );
}

/// The SW of Table 4-7 typed: running forward (state 1), ready, run/stop mode 2
/// (communication, bits 13-14), overload pre-alarm (bit 12).
#[test]
fn sw_state_and_mode() {
    let mut bytes = [0u8; 32];
    bytes[8..10].copy_from_slice(&[0x51, 0x01]);
    let status = Input::from_bytes(&bytes)
        .pkw_pzd()
        .expect("no response")
        .status;
    assert_eq!(status, StatusWord(0x5101));
    assert_eq!(status.state(WordLayout::ByByte), Some(RunState::Forward));
    assert_eq!(status.run_stop_mode(), RunStopMode::Communication);
    assert!(status.has(Input::SW_STATUS_WORD_OVERLOAD_PRE_ALARM));
}

/// PKW1 holding a response code Table 4-10 does not define (9) is an error, not a guess.
#[test]
fn undefined_response_code_is_an_error() {
    let mut bytes = [0u8; 32];
    bytes[1] = 9;
    assert_eq!(
        Input::from_bytes(&bytes).pkw_pzd(),
        Err(ResponseError::UnknownResponse(9))
    );
}

/// The card's images against the drive (bus PROFINET, big-endian): a PKW read of P00.10, a
/// refused write (error 7, read only), then run forward with the frequency from PZD2: the SW
/// says forward and the transmitted PZD2 ramps.
#[test]
fn the_drive_answers_the_generated_images() {
    let answers = drive_answers(
        Bus::Profinet,
        ByteOrder::BigEndian,
        |image| Output::from_pkw_pzd(image).to_bytes(),
        Input::from_bytes,
        |input| input.pkw_pzd().expect("a response"),
    );
    assert_eq!(answers.read.pkw4_value_low_word, answers.keypad);
    let refused = &answers.refused;
    assert_eq!(
        (
            refused.pkw1_response_identification,
            refused.pkw3_value_high_word_or_error_number
        ),
        (3, 7)
    );
    let (first, later) = (&answers.first, &answers.later);
    assert!(
        later.pzd2_actual_value_p16_43 > first.pzd2_actual_value_p16_43,
        "ramping"
    );
    assert!(later.pzd2_actual_value_p16_43 <= 2500);
    assert_eq!(
        InputImage::parse(&later.to_bytes(), ByteOrder::BigEndian),
        later.pkw_pzd()
    );
}

#[test]
fn the_pzd_records_default_to_invalid() {
    assert_eq!((record_256::INDEX, record_256::LENGTH), (256, 22));
    assert_eq!((record_257::INDEX, record_257::LENGTH), (257, 22));
    assert_eq!(record_256::DEFAULT, [0u8; 22]);
    assert_eq!(record_256::P16_32_RECEIVED_PZD2_BYTE_OFFSET, 0);
    assert_eq!(record_257::P16_53_TRANSMITTED_PZD12_BYTE_OFFSET, 20);
    let rx = record_256::Record {
        p16_33_received_pzd3: record_256::P1633ReceivedPzd3Values::SetFrequency0Fmax001Hz.raw(),
        ..Default::default()
    };
    assert_eq!(rx.to_bytes()[..4], [0x00, 0x00, 0x00, 0x01]);
    assert_eq!(record_256::Record::from_bytes(&rx.to_bytes()), rx);
    assert_eq!(
        rx.p16_33_received_pzd3_value(),
        Ok(record_256::P1633ReceivedPzd3Values::SetFrequency0Fmax001Hz)
    );
}

/// The generated module, byte for byte (with the overlay, as `sim/build.rs` generates it).
#[test]
fn generated_module_snapshot() {
    let path = root().join("eds/goodrive350-pn.xml");
    let mut read = edsgen_model::read::read_file(&path).expect("readable");
    let overlay = std::fs::read_to_string(edsgen_model::overlay::path_for(&path))
        .expect("eds/goodrive350-pn.toml");
    assert_eq!(
        edsgen_model::overlay::apply(&overlay, &mut read.device),
        vec![]
    );
    let code = edsgen_codegen::emit::generate(&read.device, "goodrive350_pn").expect("generates");
    insta::assert_snapshot!("goodrive350_pn_module", code);
}
