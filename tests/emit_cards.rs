//! Generated code of the five cards and of six corpus files of different shapes, pinned by insta
//! snapshots; determinism (twice, and with the sections reordered); and the cards' generated
//! code at work through `edsgen_sim::cards` (the Goodrive350 manual's PDO2 frames, OD access).

mod emit_common;
mod process_support;

use std::path::Path;

use edsgen_model::read;
use edsgen_runtime::{ObjectDictionary, PdoError, SdoAbort};
use edsgen_sim::cards;
use emit_common::*;
use process_support::{corpus_dir, root};
use proptest::prelude::*;

const CARDS: [&str; 5] = ["cp301", "goodrive350", "hd1e", "ms300", "rd11"];

/// Corpus files of different shapes, with the snapshot name for each.
const CORPUS_SHAPES: [(&str, &str); 6] = [
    (
        "compact_sub_obj",
        "ros-industrial__ros2_canopen/canopen_core__test__simple.eds",
    ),
    (
        "dcf_parameter_value",
        "ros-industrial__ros2_canopen/canopen_tests__config__robot_control__prbt_0_1.dcf",
    ),
    (
        "xdd",
        "davidsenoner__emec-drv-canopen-tester/doc__Slave_06__emecdrv5.xdd",
    ),
    (
        "cia402_drive",
        "KITmedical__kacanopen_old/master__share__eds_library__cia__402.eds",
    ),
    (
        "sparse_records",
        "CANopenNode__CANopenEditor/demo__eds__demo_drive.eds",
    ),
    (
        "wide_ints_and_strings",
        "lely-industries__lely-core/test__gw_txt-slave.dcf",
    ),
];

fn card_path(name: &str) -> std::path::PathBuf {
    root().join("eds").join(format!("{name}.eds"))
}

/// The file's `[sections]` in reverse order (text before the first section stays first).
fn reverse_sections(text: &str) -> String {
    let mut preamble = String::new();
    let mut sections: Vec<String> = Vec::new();
    for line in text.split_inclusive('\n') {
        if line.trim_start().starts_with('[') {
            sections.push(String::new());
        }
        match sections.last_mut() {
            Some(section) => section.push_str(line),
            None => preamble.push_str(line),
        }
    }
    for section in &mut sections {
        if !section.ends_with('\n') {
            section.push('\n');
        }
    }
    sections.reverse();
    preamble + &sections.concat()
}

fn assert_deterministic(path: &Path, module: &str) -> String {
    let first = generate(path, module).unwrap_or_else(|d| panic!("{}: {d:?}", path.display()));
    let second = generate(path, module).unwrap();
    assert!(first == second, "{}: two runs differ", path.display());
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("eds") || e.eq_ignore_ascii_case("dcf"))
    {
        let text = std::fs::read_to_string(path).unwrap();
        let reordered = reverse_sections(&text);
        assert_ne!(reordered, text);
        let read = with_overlay(path, read::read_bytes(path, reordered.as_bytes()));
        let third = generate_from(read, module)
            .unwrap_or_else(|d| panic!("{}: reordered: {d:?}", path.display()));
        assert!(
            first == third,
            "{}: reordering the sections changed the output",
            path.display()
        );
    }
    first
}

#[test]
fn card_snapshots_and_determinism() {
    for card in CARDS {
        let code = assert_deterministic(&card_path(card), card);
        insta::assert_snapshot!(format!("card_{card}"), code);
    }
}

#[test]
fn corpus_shape_snapshots_and_determinism() {
    let Some(dir) = corpus_dir() else { return };
    for (shape, file) in CORPUS_SHAPES {
        let code = assert_deterministic(&dir.join(file), shape);
        insta::assert_snapshot!(format!("corpus_{shape}"), code);
    }
}

#[test]
fn cli_generate_writes_the_same_code() {
    let out = std::env::temp_dir().join(format!("edsgen-generate-{}.rs", std::process::id()));
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_edsgen"))
        .args(["generate", "eds/hd1e.eds", "-o"])
        .arg(&out)
        .args(["--module", "hd1e"])
        .current_dir(root())
        .status()
        .unwrap();
    assert!(status.success());
    let written = std::fs::read_to_string(&out).unwrap();
    let _ = std::fs::remove_file(&out);
    assert_eq!(written, generate(&card_path("hd1e"), "hd1e").unwrap());
}

#[test]
fn goodrive350_pdo2_rx_encodes_the_manual_frame() {
    use cards::goodrive350::pdo::Rpdo2;
    let rpdo = Rpdo2 {
        control_word: 0x0001,
        setting_2: 5000,
        ..Default::default()
    };
    assert_eq!(
        rpdo.to_bytes(),
        [0x01, 0x00, 0x00, 0x00, 0x88, 0x13, 0x00, 0x00]
    );
    assert_eq!(Rpdo2::cob_id(3), 0x303);
}

#[test]
fn goodrive350_pdo2_tx_decodes_the_manual_frame() {
    use cards::goodrive350::pdo::Tpdo2;
    let tpdo = Tpdo2::from_slice(&[0x01, 0x01, 0x88, 0x13, 0x7C, 0x01, 0x00, 0x00]).unwrap();
    assert_eq!(tpdo.status_word, 0x0101);
    assert_eq!(tpdo.returned_value_1, 5000);
    assert_eq!(tpdo.returned_value_2, 380);
    assert_eq!(tpdo.returned_value_3, 0);
    assert_eq!(Tpdo2::cob_id(3), 0x283);
    assert_eq!(
        Tpdo2::from_slice(&[0x01, 0x01, 0x88]),
        Err(PdoError::WrongLength {
            expected: 8,
            actual: 3
        })
    );
}

proptest! {
    #[test]
    fn goodrive350_pdos_round_trip(payload in any::<[u8; 8]>()) {
        use cards::goodrive350::pdo::{Rpdo2, Tpdo2};
        prop_assert_eq!(Rpdo2::from_slice(&payload).unwrap().to_bytes(), payload);
        prop_assert_eq!(Tpdo2::from_slice(&payload).unwrap().to_bytes(), payload);
    }
}

#[test]
fn goodrive350_od_serves_the_manual_sdo_values() {
    use cards::goodrive350::{od, Od};
    let mut dict = Od::new(3);
    // SDO write 1801h:03 = 1000, then read back (the manual's example).
    assert_eq!(dict.write(0x1801, 3, &1000u16.to_le_bytes()), Ok(()));
    let mut buf = [0u8; 8];
    assert_eq!(dict.read(0x1801, 3, 0, &mut buf), Ok(2));
    assert_eq!(&buf[..2], &[0xE8, 0x03]);
    // A missing object answers 0602 0000.
    assert_eq!(dict.read(0x6000, 0, 0, &mut buf), Err(SdoAbort::NoObject));
    assert_eq!(SdoAbort::NoObject.code(), 0x0602_0000);
    // The typed address names the same entry.
    let tpdo2_inhibit = od::tpdo2_communication_parameter::INHIBIT_TIME;
    assert_eq!((tpdo2_inhibit.index, tpdo2_inhibit.sub), (0x1801, 3));
}

#[test]
fn cards_identity_constants_match_the_od() {
    let checks: [(u32, u32, &dyn ObjectDictionary); 2] = [
        (
            cards::cp301::VENDOR_ID,
            cards::cp301::PRODUCT_CODE,
            &cards::cp301::Od::new(1),
        ),
        (
            cards::goodrive350::VENDOR_ID,
            cards::goodrive350::PRODUCT_CODE,
            &cards::goodrive350::Od::new(1),
        ),
    ];
    for (vendor, product, dict) in checks {
        let mut buf = [0u8; 4];
        assert_eq!(dict.read(0x1018, 1, 0, &mut buf), Ok(4));
        assert_eq!(u32::from_le_bytes(buf), vendor);
        assert_eq!(dict.read(0x1018, 2, 0, &mut buf), Ok(4));
        assert_eq!(u32::from_le_bytes(buf), product);
    }
}
