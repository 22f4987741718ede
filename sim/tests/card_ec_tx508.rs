//! `eds/ec-tx508.xml` (INVT EC-TX508 EtherCAT card on Goodrive350 VFDs, an ESI file) checked
//! against its manual (seed 002, chapter 6 and Appendix B) through the ESI reader: the
//! SyncManagers of Table 6-4 row by row, the default PDOs of Appendix B and section 6.4.4 row by
//! row, the CoE dictionary object by object, the synchronisation modes of Table 6-1, the
//! validator's verdict, and the generated module (snapshot) with its process images.

mod card_support;

use card_support::{
    check_rows, integer_default, read, row, warnings_and_errors, DefaultValue, Row,
};
use edsgen_model::model::{AccessType, BasicType, Device, EcPdo, EtherCat, SmKind, SyncManager};
use edsgen_runtime::ethercat::ProcessData;
use edsgen_sim::cards::ec_tx508::{ethercat, od};

use AccessType::{Ro, Rw, Rwr, Rww};
use BasicType::{
    Integer16 as I16, Integer32 as I32, Integer8 as I8, Unsigned16 as U16, Unsigned32 as U32,
    Unsigned8 as U8, VisibleString as Str,
};
use DefaultValue::{Absent, Int, Text};

/// The ESI under test, relative to the package root.
const ESI: &str = "eds/ec-tx508.xml";

fn device() -> Device {
    read(ESI).device
}

fn ethercat_of(device: &Device) -> &EtherCat {
    device
        .ethercat()
        .expect("an ESI device has its EtherCAT side")
}

/// SyncManager `n` as (kind, start address, size, control byte, enabled).
fn sm(n: usize) -> (SmKind, u16, Option<u16>, u8, bool) {
    let device = device();
    let SyncManager {
        kind,
        start_address,
        default_size,
        control_byte,
        enable,
        ..
    } = ethercat_of(&device).sync_managers[n].clone();
    (kind, start_address, default_size, control_byte, enable)
}

// Table 6-4, one test per row. Control bytes are not in the manual: the ETG.2000 values the file
// records in its comment.

#[test]
fn table_6_4_sync_manager_0_receives_sdo_512_bytes_at_1000h() {
    assert_eq!(sm(0), (SmKind::MailboxOut, 0x1000, Some(512), 0x26, true));
}

#[test]
fn table_6_4_sync_manager_1_sends_sdo_512_bytes_at_1400h() {
    assert_eq!(sm(1), (SmKind::MailboxIn, 0x1400, Some(512), 0x22, true));
}

#[test]
fn table_6_4_sync_manager_2_receives_pdo_128_bytes_at_1800h() {
    assert_eq!(sm(2), (SmKind::Outputs, 0x1800, Some(128), 0x64, true));
}

#[test]
fn table_6_4_sync_manager_3_sends_pdo_128_bytes_at_1c00h() {
    assert_eq!(sm(3), (SmKind::Inputs, 0x1C00, Some(128), 0x20, true));
    assert_eq!(ethercat_of(&device()).sync_managers.len(), 4);
}

/// A PDO's entries as (index, sub, bit length), and its default SyncManager.
fn pdo(pdos: &[EcPdo], index: u16) -> (Vec<(u16, u8, u16)>, Option<u8>) {
    let pdo = pdos
        .iter()
        .find(|p| p.index == index)
        .unwrap_or_else(|| panic!("{index:04X}h"));
    let entries = pdo
        .entries
        .iter()
        .map(|e| (e.index, e.sub, e.bit_len))
        .collect();
    (entries, pdo.sm)
}

/// The mapping object's defaults (index << 16 | sub << 8 | bits), as (index, sub, bits).
fn mapping_object(device: &Device, index: u16) -> Vec<(u16, u8, u16)> {
    let count = integer_default(device, index, 0).expect("sub 0");
    (1..=count as u8)
        .map(|sub| {
            let raw = integer_default(device, index, sub).expect("mapping entry") as u32;
            ((raw >> 16) as u16, (raw >> 8) as u8, (raw & 0xFF) as u16)
        })
        .collect()
}

/// Appendix B, 1600h: the default RxPDO (section 6.4.4's figure names the same objects).
const RX_1600: &[(u16, u8, u16)] = &[
    (0x6040, 0, 16),
    (0x607A, 0, 32),
    (0x60FF, 0, 32),
    (0x6071, 0, 16),
    (0x6072, 0, 16),
    (0x6060, 0, 8),
    (0x6081, 0, 32),
    (0x60B8, 0, 16),
];

/// Appendix B, 1A00h: the default TxPDO. Sub 7 is 60B9h; section 6.4.4's figure shows 603Fh
/// there, and the file follows Appendix B (its comment says why).
const TX_1A00: &[(u16, u8, u16)] = &[
    (0x6041, 0, 16),
    (0x6064, 0, 32),
    (0x606C, 0, 32),
    (0x6077, 0, 16),
    (0x60F4, 0, 32),
    (0x6061, 0, 8),
    (0x60B9, 0, 16),
    (0x60BA, 0, 32),
];

#[test]
fn rx_pdo_1600_maps_the_eight_objects_of_appendix_b_on_sm2() {
    let device = device();
    assert_eq!(
        pdo(&ethercat_of(&device).rx_pdos, 0x1600),
        (RX_1600.to_vec(), Some(2))
    );
    assert_eq!(mapping_object(&device, 0x1600), RX_1600);
    let bits: u16 = RX_1600.iter().map(|e| e.2).sum();
    assert_eq!(bits, 168);
}

#[test]
fn tx_pdo_1a00_maps_the_eight_objects_of_appendix_b_on_sm3() {
    let device = device();
    assert_eq!(
        pdo(&ethercat_of(&device).tx_pdos, 0x1A00),
        (TX_1A00.to_vec(), Some(3))
    );
    assert_eq!(mapping_object(&device, 0x1A00), TX_1A00);
    let bits: u16 = TX_1A00.iter().map(|e| e.2).sum();
    assert_eq!(bits, 184);
}

#[test]
fn rx_pdos_1601_to_1603_map_control_word_and_target_position_unassigned() {
    let device = device();
    for index in 0x1601..=0x1603 {
        let expected = vec![(0x6040, 0, 16), (0x607A, 0, 32)];
        assert_eq!(
            pdo(&ethercat_of(&device).rx_pdos, index),
            (expected.clone(), None)
        );
        assert_eq!(mapping_object(&device, index), expected, "{index:04X}h");
    }
}

#[test]
fn tx_pdos_1a01_to_1a03_map_status_word_and_position_unassigned() {
    // Appendix B prints sub 0 = 8 but lists two entries; the file counts the two.
    let device = device();
    for index in 0x1A01..=0x1A03 {
        let expected = vec![(0x6041, 0, 16), (0x6064, 0, 32)];
        assert_eq!(
            pdo(&ethercat_of(&device).tx_pdos, index),
            (expected.clone(), None)
        );
        assert_eq!(mapping_object(&device, index), expected, "{index:04X}h");
    }
}

#[test]
fn pdo_assignment_1c12h_and_1c13h_match_the_sm_attributes() {
    let device = device();
    assert_eq!(integer_default(&device, 0x1C12, 0), Some(1));
    assert_eq!(integer_default(&device, 0x1C12, 1), Some(0x1600));
    assert_eq!(integer_default(&device, 0x1C13, 0), Some(1));
    assert_eq!(integer_default(&device, 0x1C13, 1), Some(0x1A00));
}

#[rustfmt::skip]
/// Appendix B. Access `rw` with `PdoMapping` R reads as CiA 306's `rww`, with T as `rwr`.
const ROWS: &[Row] = &[
    row(0x1000, 0, U32, Ro, Int(0x192), false, "App. B: Device type"),
    row(0x1001, 0, U8, Ro, Int(0), false, "App. B: Error register"),
    row(0x1008, 0, Str, Ro, Text("INVT-EtherCAT"), false, "App. B: Factory device name"),
    row(0x1009, 0, Str, Ro, Absent, false, "App. B: Factory hardware version"),
    row(0x100A, 0, Str, Ro, Absent, false, "App. B: Factory software version"),
    row(0x1018, 0x00, U8, Ro, Int(4), false, "App. B: Included max. sub-index"),
    row(0x1018, 0x01, U32, Ro, Int(0x4D8), false, "App. B: Supplier ID"),
    row(0x1018, 0x02, U32, Ro, Int(0x9252), false, "App. B: Product code"),
    row(0x1018, 0x03, U32, Ro, Int(1), false, "App. B: Revision number"),
    row(0x1018, 0x04, U32, Ro, Int(1), false, "App. B: Serial number"),
    row(0x1C00, 0x00, U8, Ro, Int(4), false, "App. B: Max. sub-index"),
    row(0x1C00, 0x01, U8, Ro, Int(1), false, "App. B: SM0 communication type"),
    row(0x1C00, 0x02, U8, Ro, Int(2), false, "App. B: SM1 communication type"),
    row(0x1C00, 0x03, U8, Ro, Int(3), false, "App. B: SM2 communication type"),
    row(0x1C00, 0x04, U8, Ro, Int(4), false, "App. B: SM3 communication type"),
    row(0x1C12, 0x00, U8, Rw, Int(1), false, "App. B: Max. sub-index"),
    row(0x1C12, 0x01, U16, Rw, Int(0x1600), false, "App. B: RxPDO assigned object index"),
    row(0x1C13, 0x00, U8, Rw, Int(1), false, "App. B: Max. sub-index"),
    row(0x1C13, 0x01, U16, Rw, Int(0x1A00), false, "App. B: TxPDO assigned object index"),
    row(0x1C32, 0x00, U8, Ro, Int(0x20), false, "App. B: Max. sub-index"),
    row(0x1C32, 0x01, U16, Rw, Int(2), false, "App. B: Synchronization mode"),
    row(0x1C32, 0x02, U32, Ro, Int(0), false, "App. B: Cycle time"),
    row(0x1C32, 0x03, U32, Ro, Int(0), false, "App. B: Switching time"),
    row(0x1C32, 0x04, U16, Ro, Int(0x4006), false, "App. B: Supported synchronization type"),
    row(0x1C32, 0x05, U32, Ro, Int(0x3D090), false, "App. B: Min. periodic time"),
    row(0x1C32, 0x06, U32, Ro, Int(0), false, "App. B: Calculation and replication time"),
    row(0x1C32, 0x07, U32, Rw, Int(0), false, "App. B: Reserved"),
    row(0x1C32, 0x08, U16, Rw, Int(0), false, "App. B: Obtained periodic time"),
    row(0x1C32, 0x09, U32, Ro, Int(0), false, "App. B: Delay time"),
    row(0x1C32, 0x0A, U32, Rw, Int(0), false, "App. B: Sync0 time"),
    row(0x1C32, 0x0B, U32, Ro, Int(0), false, "App. B: SM event loss counter"),
    row(0x1C32, 0x0C, U32, Ro, Int(0), false, "App. B: Circulation timeout counter"),
    row(0x1C32, 0x0D, U32, Ro, Int(0), false, "App. B: Counter of too short switching"),
    row(0x1C32, 0x20, U8, Ro, Int(0), false, "App. B: Synchronization error"),
    row(0x1C33, 0x00, U8, Ro, Int(0x20), false, "App. B: Max. sub-index"),
    row(0x1C33, 0x01, U16, Rw, Int(2), false, "App. B: Synchronization mode"),
    row(0x1C33, 0x02, U32, Ro, Int(0), false, "App. B: Cycle time"),
    row(0x1C33, 0x03, U32, Ro, Int(0), false, "App. B: Switching time"),
    row(0x1C33, 0x04, U16, Ro, Int(0x4006), false, "App. B: Supported synchronization type"),
    row(0x1C33, 0x05, U32, Ro, Int(0x3D090), false, "App. B: Min. periodic time"),
    row(0x1C33, 0x06, U32, Ro, Int(0), false, "App. B: Calculation and replication time"),
    row(0x1C33, 0x07, U32, Rw, Int(0), false, "App. B: Reserved"),
    row(0x1C33, 0x08, U16, Rw, Int(0), false, "App. B: Obtained periodic time"),
    row(0x1C33, 0x09, U32, Ro, Int(0), false, "App. B: Delay time"),
    row(0x1C33, 0x0A, U32, Rw, Int(0), false, "App. B: Sync0 time"),
    row(0x1C33, 0x0B, U32, Ro, Int(0), false, "App. B: SM event loss counter"),
    row(0x1C33, 0x0C, U32, Ro, Int(0), false, "App. B: Circulation timeout counter"),
    row(0x1C33, 0x0D, U32, Ro, Int(0), false, "App. B: Counter of too short switching"),
    row(0x1C33, 0x20, U8, Ro, Int(0), false, "App. B: Synchronization error"),
    row(0x2000, 0, U32, Rw, Int(0), false, "App. B: Read function codes"),
    row(0x2001, 0, U32, Ro, Int(0), false, "App. B: Read response"),
    row(0x2002, 0, U32, Rw, Int(0), false, "App. B: Write function codes"),
    row(0x2003, 0, U32, Ro, Int(0), false, "App. B: Write response"),
    row(0x603F, 0, U16, Ro, Int(0), true, "App. B: Error code"),
    row(0x6040, 0, U16, Rww, Int(0), true, "App. B: Control word"),
    row(0x6041, 0, U16, Ro, Int(0), true, "App. B: Status word"),
    row(0x605D, 0, I16, Rw, Int(0), false, "App. B: Suspension mode"),
    row(0x6060, 0, I8, Rww, Int(0), true, "App. B; 1600h sub 6 maps 8 bits: INT8 (CiA 402), not UINT16"),
    row(0x6061, 0, I8, Ro, Int(0), true, "App. B; 1A00h sub 6 maps 8 bits: INT8 (CiA 402), not UINT16"),
    row(0x6062, 0, I32, Ro, Int(0), false, "App. B: Position command"),
    row(0x6063, 0, I32, Ro, Int(0), false, "App. B: Position feedback"),
    row(0x6064, 0, I32, Ro, Int(0), true, "App. B 'Position feedback'; 6.5.2.1 names it"),
    row(0x6065, 0, U32, Rw, Int(0), false, "App. B: Position deviation range"),
    row(0x6066, 0, U16, Rw, Int(0), false, "App. B: Too-large position deviation timeout"),
    row(0x6067, 0, U32, Rw, Int(0), false, "App. B: Position pulse range"),
    row(0x606C, 0, I32, Rwr, Int(0), true, "App. B: RW as printed (CiA 402: ro)"),
    row(0x6071, 0, I16, Rww, Int(0), true, "App. B: Target torque"),
    row(0x6072, 0, U16, Rww, Int(0), true, "App. B: Max. torque"),
    row(0x6073, 0, U16, Ro, Int(0), false, "App. B: Max. current"),
    row(0x6075, 0, U32, Ro, Int(0), false, "App. B: Motor rated current"),
    row(0x6076, 0, U32, Ro, Int(0), false, "App. B: Motor rated torque"),
    row(0x6077, 0, I16, Ro, Int(0), true, "App. B: Actual torque"),
    row(0x6078, 0, I16, Ro, Int(0), false, "App. B: Actual current"),
    row(0x6079, 0, U32, Ro, Int(0), false, "App. B: Bus voltage"),
    row(0x607A, 0, I32, Rww, Int(0), true, "App. B; 1600h sub 2 maps 32 bits: INT32 (CiA 402), not INT16"),
    row(0x607B, 0x00, U8, Ro, Int(2), false, "App. B prints RW; the fixed count, ro (CiA 301)"),
    row(0x607B, 0x01, I32, Rw, Int(0), false, "App. B: Min. position range limit"),
    row(0x607B, 0x02, I32, Rw, Int(0), false, "App. B: Max. position range limit"),
    row(0x607C, 0, I32, Rw, Int(0), false, "App. B: Coordinate deviation"),
    row(0x6081, 0, U32, Rww, Int(0), true, "App. B: Speed in industrial regulations"),
    row(0x6083, 0, U32, Rw, Int(0), false, "App. B: ACC in industrial regulations"),
    row(0x6084, 0, U32, Rw, Int(0), false, "App. B: DEC in industrial regulations"),
    row(0x6091, 0x00, U8, Ro, Int(2), false, "App. B prints RW; the fixed count, ro (CiA 301)"),
    row(0x6091, 0x01, U32, Rw, Int(1), false, "App. B: Motor resolution"),
    row(0x6091, 0x02, U32, Rw, Int(1), false, "App. B: Bearing axle resolution"),
    row(0x6093, 0x00, U8, Ro, Int(2), false, "App. B prints RW; the fixed count, ro (CiA 301)"),
    row(0x6093, 0x01, U32, Rw, Int(1), false, "App. B: Molecule"),
    row(0x6093, 0x02, U32, Rw, Int(1), false, "App. B: Set constant"),
    row(0x6098, 0, I16, Rw, Int(0), false, "App. B: Zeroing mode"),
    row(0x6099, 0x00, U8, Ro, Int(2), false, "App. B prints RW; the fixed count, ro (CiA 301)"),
    row(0x6099, 0x01, U32, Rw, Int(0), false, "App. B: Search limit switch speed"),
    row(0x6099, 0x02, U32, Rw, Int(0), false, "App. B: Search zero-phase speed"),
    row(0x60B8, 0, U16, Rww, Int(0), true, "App. B: Probe control"),
    row(0x60B9, 0, U16, Ro, Int(0), true, "App. B: Probe status"),
    row(0x60BA, 0, I32, Ro, Int(0), true, "App. B: Probe position rising edge"),
    row(0x60F4, 0, I32, Ro, Int(0), true, "App. B: Position deviation"),
    row(0x60FD, 0, U32, Ro, Int(0), false, "App. B: Digital input"),
    row(0x60FE, 0, I32, Ro, Int(0), false, "App. B: Digital output"),
    row(0x60FF, 0, I32, Rww, Int(0), true, "App. B: Target speed"),
    row(0x6502, 0, U32, Ro, Int(0x3A5), false, "App. B: Drive mode"),
];

#[test]
fn coe_dictionary_matches_appendix_b() {
    check_rows(&device(), ROWS);
}

#[test]
fn identity_and_profile_match_1018h_and_1000h() {
    let device = device();
    let info = &device.device_info;
    assert_eq!(
        info.vendor_number.as_ref().map(|s| s.value),
        Some(0x0000_04D8)
    );
    assert_eq!(
        info.product_number.as_ref().map(|s| s.value),
        Some(0x0000_9252)
    );
    assert_eq!(info.revision_number.as_ref().map(|s| s.value), Some(1));
    let ec = ethercat_of(&device);
    assert_eq!(ec.type_name, "EC-TX508");
    assert_eq!(ec.profiles, [402]);
    assert_eq!(integer_default(&device, 0x1000, 0), Some(0x192));
}

#[test]
fn table_6_1_cycles_are_the_dc_sync0_modes_besides_free_run() {
    let device = device();
    let modes: Vec<(&str, u16, u32)> = ethercat_of(&device)
        .op_modes
        .iter()
        .map(|m| (m.name.as_str(), m.assign_activate, m.cycle_time_sync0))
        .collect();
    assert_eq!(
        modes,
        [
            ("FreeRun", 0, 0),
            ("DC250", 0x300, 250_000),
            ("DC500", 0x300, 500_000),
            ("DC1000", 0x300, 1_000_000),
            ("DC2000", 0x300, 2_000_000),
        ]
    );
    // 1C32h/1C33h sub 5: the shortest cycle, 250 us, in ns.
    assert_eq!(integer_default(&device, 0x1C32, 5), Some(250_000));
}

#[test]
fn coe_mailbox_offers_pdo_assignment_and_configuration() {
    let device = device();
    let coe = ethercat_of(&device).coe.clone().expect("CoE");
    assert_eq!(
        (
            coe.sdo_info,
            coe.pdo_assign,
            coe.pdo_config,
            coe.complete_access,
            coe.segmented_sdo
        ),
        (false, true, true, false, true)
    );
    assert!(coe.init_cmds.is_empty());
}

#[test]
fn validates_clean() {
    assert_eq!(warnings_and_errors(&read(ESI)), vec![]);
}

#[test]
fn generated_module_snapshot() {
    let read = read(ESI);
    let code = edsgen_codegen::emit::generate(&read.device, "ec_tx508").expect("generates");
    insta::assert_snapshot!("ec_tx508_module", code);
}

#[test]
fn generated_images_have_the_default_assignment_s_lengths() {
    assert_eq!(ethercat::Outputs::LEN, 21);
    assert_eq!(<ethercat::Outputs as ProcessData>::BITS, 168);
    assert_eq!(ethercat::Inputs::LEN, 23);
    assert_eq!(<ethercat::Inputs as ProcessData>::BITS, 184);
    assert_eq!(ethercat::SM2.start_address, 0x1800);
    assert_eq!(ethercat::SM3.start_address, 0x1C00);
    assert!(ethercat::IDENTITY.matches_exactly(0x4D8, 0x9252, 1));
    let _: edsgen_runtime::Entry<i8, edsgen_sim::cards::ec_tx508::Od> = od::OPERATION_MODE;
}

#[test]
fn csv_mode_outputs_encode_as_the_manual_lays_them_out() {
    // 6.5.2.4: 6060h = 9, 6040h = 0x0F, 60FFh the speed in rpm (here -1500, reverse).
    let mut outputs = ethercat::Outputs::default();
    outputs.rx_pdo_1600.control_word = 0x000F;
    outputs.rx_pdo_1600.target_speed = -1500;
    outputs.rx_pdo_1600.operation_mode = 9;
    let mut expected = [0u8; 21];
    expected[0] = 0x0F; // 6040h, bytes 0-1
    expected[6..10].copy_from_slice(&(-1500i32).to_le_bytes()); // 60FFh, bytes 6-9
    expected[14] = 9; // 6060h, byte 14
    assert_eq!(outputs.to_bytes(), expected);
    assert_eq!(ethercat::Outputs::from_slice(&expected), Ok(outputs));
}

#[test]
fn status_inputs_decode_from_the_manual_layout() {
    // 6041h = 0x0637 (operation enabled, remote, target reached), 606Ch = 1500, 6061h = 9.
    let mut bytes = [0u8; 23];
    bytes[0..2].copy_from_slice(&0x0637u16.to_le_bytes());
    bytes[6..10].copy_from_slice(&1500i32.to_le_bytes());
    bytes[16] = 9;
    let inputs = ethercat::Inputs::from_slice(&bytes).expect("23 bytes");
    let tx = inputs.tx_pdo_1a00;
    assert_eq!(
        (tx.status_word, tx.actual_speed, tx.operation_mode_display),
        (0x0637, 1500, 9)
    );
    assert_eq!(
        ethercat::Inputs::from_slice(&bytes[..22]),
        Err(edsgen_runtime::PdoError::WrongLength {
            expected: 23,
            actual: 22
        })
    );
}
