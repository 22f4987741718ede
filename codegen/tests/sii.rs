//! SII images built from ESI files (`edsgen_model::sii::build`) compared byte for byte with
//! images written out here by hand from the ETG.2010 layout, for the test drive (tests/esi/
//! drive.xml) and the EC-TX508 (eds/ec-tx508.xml); and read back (`read::sii`) into the same
//! EtherCAT model the ESI gives.

use std::path::Path;

use edsgen_model::model::Format;
use edsgen_model::read::{read_bytes, read_file};
use edsgen_model::sii::build;

/// A category: type, length in words, data padded to a word.
fn category(kind: u16, data: &[u8]) -> Vec<u8> {
    let mut out = kind.to_le_bytes().to_vec();
    out.extend_from_slice(&(data.len().div_ceil(2) as u16).to_le_bytes());
    out.extend_from_slice(data);
    if data.len() % 2 == 1 {
        out.push(0);
    }
    out
}

/// The Strings category's data.
fn strings(list: &[&str]) -> Vec<u8> {
    let mut out = vec![list.len() as u8];
    for s in list {
        out.push(s.len() as u8);
        out.extend_from_slice(s.as_bytes());
    }
    out
}

/// A PDO category's 8-byte header.
fn pdo(index: u16, entries: u8, sm: u8, name: u8, flags: u16) -> Vec<u8> {
    let mut out = index.to_le_bytes().to_vec();
    out.extend_from_slice(&[entries, sm, 0, name]);
    out.extend_from_slice(&flags.to_le_bytes());
    out
}

/// A PDO entry's 8 bytes.
fn entry(index: u16, name: u8, data_type: u8, bits: u8) -> [u8; 8] {
    let [lo, hi] = index.to_le_bytes();
    [lo, hi, 0, name, data_type, bits, 0, 0]
}

/// Words 0x00-0x3F, the size word left 0.
fn header(identity: [u32; 3], mailbox: [u16; 4]) -> Vec<u8> {
    let mut out = vec![0u8; 128];
    // Configuration area: PDI control 0x0005, the rest 0, CRC-8 of bytes 0-13 (0x07, 0xFF).
    out[0] = 0x05;
    out[14] = 0x48;
    for (n, value) in identity.iter().enumerate() {
        out[16 + 4 * n..20 + 4 * n].copy_from_slice(&value.to_le_bytes());
    }
    for (n, value) in mailbox.iter().enumerate() {
        out[0x30 + 2 * n..0x32 + 2 * n].copy_from_slice(&value.to_le_bytes());
    }
    out[0x38] = 0x04; // CoE
    out[0x7E] = 1; // version
    out
}

/// The general category: order and name strings 1 and 2, CoE details, ports 0 and 1 MII.
fn general(coe: u8) -> Vec<u8> {
    let mut out = vec![0u8; 32];
    out[2] = 1;
    out[3] = 2;
    out[5] = coe;
    out[14] = 0x11;
    out
}

fn sync_m(sms: &[(u16, u16, u8, u8)]) -> Vec<u8> {
    let mut out = Vec::new();
    for &(start, len, control, kind) in sms {
        out.extend_from_slice(&start.to_le_bytes());
        out.extend_from_slice(&len.to_le_bytes());
        out.extend_from_slice(&[control, 0, 1, kind]);
    }
    out
}

/// Ends the image and sets the size word (kbit - 1).
fn finish(mut image: Vec<u8>) -> Vec<u8> {
    image.extend_from_slice(&[0xFF, 0xFF]);
    let kbit = (image.len() * 8).div_ceil(1024);
    image[0x7C] = (kbit - 1) as u8;
    image
}

fn built(path: &str) -> Vec<u8> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(path);
    let read = read_file(&path).expect("readable");
    build(&read.device).expect("an EtherCAT device")
}

#[test]
fn the_test_drive_image_is_etg2010s_layout() {
    let mut image = header([0x1234, 0x9252, 1], [0x1000, 128, 0x1080, 128]);
    image.extend(category(
        10,
        &strings(&[
            "TD-1",
            "Test drive",
            "Inputs",
            "Statusword",
            "Outputs",
            "Controlword",
            "Modes of operation",
            "Target position",
            "Outputs (short)",
        ]),
    ));
    // CoE: SDO, SDO info, complete access.
    image.extend(category(30, &general(0x23)));
    image.extend(category(40, &[1, 2, 3]));
    image.extend(category(
        41,
        &sync_m(&[
            (0x1000, 128, 0x26, 1),
            (0x1080, 128, 0x22, 2),
            (0x1100, 7, 0x64, 3),
            (0x1180, 2, 0x20, 4),
        ]),
    ));
    // TxPDO 1A00h: fixed, assigned to SM3.
    let mut tx = pdo(0x1A00, 1, 3, 3, 0x0012);
    tx.extend(entry(0x6041, 4, 0x06, 16));
    image.extend(category(50, &tx));
    // RxPDO 1600h: mandatory, fixed, assigned to SM2.
    let mut rx = pdo(0x1600, 3, 2, 5, 0x0013);
    rx.extend(entry(0x6040, 6, 0x06, 16));
    rx.extend(entry(0x6060, 7, 0x02, 8));
    rx.extend(entry(0x607A, 8, 0x04, 32));
    image.extend(category(51, &rx));
    // RxPDO 1601h: not assigned.
    let mut rx = pdo(0x1601, 1, 0xFF, 9, 0);
    rx.extend(entry(0x6040, 6, 0x06, 16));
    image.extend(category(51, &rx));
    let expected = finish(image);
    assert_eq!(expected.len(), 396);
    assert_eq!(built("tests/esi/drive.xml"), expected);
}

#[test]
fn the_ec_tx508_image_is_etg2010s_layout() {
    let mut image = header([0x04D8, 0x9252, 1], [0x1000, 512, 0x1400, 512]);
    image.extend(category(
        10,
        &strings(&[
            "EC-TX508",
            "EC-TX508 EtherCAT communication card (Goodrive350)",
            "TX PDO1 mapping parameter",
            "Status word",
            "Position actual value",
            "Actual speed",
            "Actual torque",
            "Position deviation",
            "Operation mode display",
            "Probe status",
            "Probe position rising edge",
            "TX PDO2 mapping parameter",
            "TX PDO3 mapping parameter",
            "TX PDO4 mapping parameter",
            "RX PDO1 mapping parameter",
            "Control word",
            "Target position",
            "Target speed",
            "Target torque",
            "Max. torque",
            "Operation mode",
            "Speed in industrial regulations",
            "Probe control",
            "RX PDO2 mapping parameter",
            "RX PDO3 mapping parameter",
            "RX PDO4 mapping parameter",
        ]),
    ));
    // CoE: SDO, PDO assign, PDO config.
    image.extend(category(30, &general(0x0D)));
    image.extend(category(40, &[1, 2, 3]));
    image.extend(category(
        41,
        &sync_m(&[
            (0x1000, 512, 0x26, 1),
            (0x1400, 512, 0x22, 2),
            (0x1800, 128, 0x64, 3),
            (0x1C00, 128, 0x20, 4),
        ]),
    ));
    let (uint, int, dint, udint, sint) = (0x06, 0x03, 0x04, 0x07, 0x02);
    let mut tx = pdo(0x1A00, 8, 3, 3, 0x0002);
    for e in [
        entry(0x6041, 4, uint, 16),
        entry(0x6064, 5, dint, 32),
        entry(0x606C, 6, dint, 32),
        entry(0x6077, 7, int, 16),
        entry(0x60F4, 8, dint, 32),
        entry(0x6061, 9, sint, 8),
        entry(0x60B9, 10, uint, 16),
        entry(0x60BA, 11, dint, 32),
    ] {
        tx.extend(e);
    }
    image.extend(category(50, &tx));
    for (index, name) in [(0x1A01, 12), (0x1A02, 13), (0x1A03, 14)] {
        let mut tx = pdo(index, 2, 0xFF, name, 0);
        tx.extend(entry(0x6041, 4, uint, 16));
        tx.extend(entry(0x6064, 5, dint, 32));
        image.extend(category(50, &tx));
    }
    let mut rx = pdo(0x1600, 8, 2, 15, 0x0002);
    for e in [
        entry(0x6040, 16, uint, 16),
        entry(0x607A, 17, dint, 32),
        entry(0x60FF, 18, dint, 32),
        entry(0x6071, 19, int, 16),
        entry(0x6072, 20, uint, 16),
        entry(0x6060, 21, sint, 8),
        entry(0x6081, 22, udint, 32),
        entry(0x60B8, 23, uint, 16),
    ] {
        rx.extend(e);
    }
    image.extend(category(51, &rx));
    for (index, name) in [(0x1601, 24), (0x1602, 25), (0x1603, 26)] {
        let mut rx = pdo(index, 2, 0xFF, name, 0);
        rx.extend(entry(0x6040, 16, uint, 16));
        rx.extend(entry(0x607A, 17, dint, 32));
        image.extend(category(51, &rx));
    }
    assert_eq!(built("../eds/ec-tx508.xml"), finish(image));
}

#[test]
fn a_model_without_its_ethercat_part_has_no_image() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../eds/cp301.eds");
    let read = read_file(&path).expect("readable");
    assert_eq!(
        build(&read.device),
        Err("not an EtherCAT device: an SII image is built from an ESI file".to_owned())
    );
}

/// What of an ESI's EtherCAT part an image keeps: identity, names, CoE details, SyncManagers
/// and PDOs (without Exclude, spans and the objects).
#[test]
fn images_read_back_as_their_esi() {
    for path in ["tests/esi/drive.xml", "../eds/ec-tx508.xml"] {
        let esi = read_file(&Path::new(env!("CARGO_MANIFEST_DIR")).join(path)).expect("readable");
        let image = build(&esi.device).expect("an EtherCAT device");
        let back = read_bytes(Path::new("eeprom.bin"), &image);
        assert_eq!(back.diagnostics, vec![], "{path}");
        let (want, got) = (&esi.device, &back.device);
        assert_eq!(
            got.device_info.vendor_number.as_ref().map(|n| n.value),
            want.device_info.vendor_number.as_ref().map(|n| n.value)
        );
        assert_eq!(
            got.device_info.product_number.as_ref().map(|n| n.value),
            want.device_info.product_number.as_ref().map(|n| n.value)
        );
        assert_eq!(
            got.device_info.revision_number.as_ref().map(|n| n.value),
            want.device_info.revision_number.as_ref().map(|n| n.value)
        );
        assert_eq!(got.device_info.product_name, want.device_info.product_name);
        let (want, got) = (want.ethercat().unwrap(), got.ethercat().unwrap());
        assert_eq!(got.type_name, want.type_name);
        let sms = |ec: &edsgen_model::model::EtherCat| {
            ec.sync_managers
                .iter()
                .map(|sm| {
                    (
                        sm.kind.clone(),
                        sm.start_address,
                        sm.default_size,
                        sm.control_byte,
                        sm.enable,
                    )
                })
                .collect::<Vec<_>>()
        };
        assert_eq!(sms(got), sms(want), "{path}");
        let pdos = |pdos: &[edsgen_model::model::EcPdo]| {
            pdos.iter()
                .map(|p| {
                    let entries: Vec<_> = p
                        .entries
                        .iter()
                        .map(|e| {
                            (
                                e.index,
                                e.sub,
                                e.bit_len,
                                e.name.clone(),
                                e.data_type.clone(),
                            )
                        })
                        .collect();
                    (p.index, p.name.clone(), p.sm, p.fixed, p.mandatory, entries)
                })
                .collect::<Vec<_>>()
        };
        assert_eq!(pdos(&got.tx_pdos), pdos(&want.tx_pdos), "{path}");
        assert_eq!(pdos(&got.rx_pdos), pdos(&want.rx_pdos), "{path}");
        let coe = |c: &edsgen_model::model::CoeMailbox| {
            (c.sdo_info, c.pdo_assign, c.pdo_config, c.complete_access)
        };
        assert_eq!(
            got.coe.as_ref().map(coe),
            want.coe.as_ref().map(coe),
            "{path}"
        );
        assert!(back.device.objects.is_empty());
        assert_eq!(back.device.source.format, Format::Esi);
    }
}

#[test]
fn a_broken_image_says_what_is_wrong_and_keeps_what_it_read() {
    let esi = read_file(&Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/esi/drive.xml"))
        .expect("readable");
    let mut image = build(&esi.device).expect("an EtherCAT device");
    image[14] ^= 0xFF;
    image.truncate(image.len() - 2);
    let back = read_bytes(Path::new("eeprom.BIN"), &image);
    let messages: Vec<_> = back
        .diagnostics
        .iter()
        .map(|d| (d.rule.code, d.message.clone()))
        .collect();
    assert_eq!(
        messages,
        [
            (
                "EDS818",
                "the configuration area's CRC (word 7) is 0xB7, but words 0-6 give 0x48".to_owned()
            ),
            (
                "EDS818",
                "no end marker (0xFFFF): the image ends at byte 394".to_owned()
            ),
        ]
    );
    assert_eq!(back.device.ethercat().cloned().unwrap().rx_pdos.len(), 2);
    let short = read_bytes(Path::new("x.sii"), &[0; 10]);
    assert_eq!(
        short.diagnostics[0].message,
        "an SII image of 10 bytes: shorter than its 64-word header"
    );
}
