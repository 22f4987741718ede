//! Datagram-level tests of the SubDevice: each command and working-counter rule, the registers a
//! master reads and writes, the SII interface, the AL state machine's refusals and
//! acknowledgement, the mailbox states and repeat toggle, the FMMUs and the outputs watchdog.

use edsgen_runtime::ethercat::esc::Esc;
use edsgen_runtime::Instant;

use super::frame::{parse, Command, FrameBuilder, Parsed};
use super::{AlState, Application, SubDevice};

const MAC: [u8; 6] = [0x10; 6];
const STATION: u16 = 0x1001;

/// An application with a 4-byte outputs image and a 2-byte inputs image, which answers a
/// mailbox message with its first 6 bytes reversed, and counts the times it was asked for its
/// inputs.
#[derive(Debug, Default)]
pub(super) struct TestApp {
    pub(super) outputs: Vec<u8>,
    pub(super) inputs: [u8; 2],
    pub(super) inputs_asked: usize,
    changes: Vec<(AlState, AlState)>,
}

impl Application for TestApp {
    fn mailbox(&mut self, _state: AlState, request: &[u8], answer: &mut [u8]) -> usize {
        for (a, r) in answer.iter_mut().zip(request[..6].iter().rev()) {
            *a = *r;
        }
        6
    }
    fn image_sizes(&self) -> (usize, usize) {
        (4, 2)
    }
    fn outputs(&mut self, _now: Instant, outputs: &[u8]) {
        self.outputs = outputs.to_vec();
    }
    fn inputs(&mut self, _now: Instant, inputs: &mut [u8]) {
        self.inputs_asked += 1;
        inputs.copy_from_slice(&self.inputs);
    }
    fn state_changed(&mut self, _now: Instant, from: AlState, to: AlState) {
        self.changes.push((from, to));
    }
}

/// An SII image: word 4 the alias 0x00AA, word 8 the vendor 0x04D8, and the SyncM category
/// (words 0x40–0x52): SM0 mailbox out at 0x1000 and SM1 mailbox in at 0x1080, 128 bytes each,
/// SM2 outputs, SM3 inputs.
pub(super) fn sii() -> Vec<u8> {
    let mut sii = vec![0u8; 0x80];
    sii[8] = 0xAA;
    sii[16] = 0xD8;
    sii[17] = 0x04;
    sii.extend_from_slice(&[41, 0, 16, 0]);
    sii.extend_from_slice(&[0x00, 0x10, 128, 0, 0x26, 0, 1, 1]);
    sii.extend_from_slice(&[0x80, 0x10, 128, 0, 0x22, 0, 1, 2]);
    sii.extend_from_slice(&[0x00, 0x11, 4, 0, 0x64, 0, 1, 3]);
    sii.extend_from_slice(&[0x80, 0x11, 2, 0, 0x20, 0, 1, 4]);
    sii.extend_from_slice(&[0xFF, 0xFF]);
    sii
}

/// A SubDevice whose master has offered it the SII (as SOEM and ethercrab do before Pre-Op).
fn device() -> SubDevice<TestApp> {
    let mut d = SubDevice::new(sii(), TestApp::default());
    one(&mut d, Command::Bwr, (0, 0x0500), &[1]);
    d
}

/// One datagram of a frame sent to `device` at `now`: the data and working counter that came
/// back, and the ADP.
fn one_at(
    device: &mut SubDevice<TestApp>,
    now: u64,
    command: Command,
    address: (u16, u16),
    data: &[u8],
) -> (Vec<u8>, u16, u16) {
    let mut frame = FrameBuilder::new(MAC)
        .datagram(command, 0x42, address, data, 0)
        .build();
    assert!(device.process_frame(Instant(now), &mut frame));
    let Parsed::Datagrams { datagrams, .. } = parse(&frame) else {
        panic!("not EtherCAT on the way back");
    };
    let d = &datagrams[0];
    assert_eq!(d.header.index, 0x42);
    (
        frame[d.data.clone()].to_vec(),
        super::frame::wkc(&frame, d),
        d.header.adp,
    )
}

fn one(
    device: &mut SubDevice<TestApp>,
    command: Command,
    address: (u16, u16),
    data: &[u8],
) -> (Vec<u8>, u16) {
    let (data, wkc, _) = one_at(device, 0, command, address, data);
    (data, wkc)
}

/// 8 bytes of SyncManager registers: start, length, control, status 0, activate, PDI 0.
pub(super) fn sm(start: u16, len: u16, control: u8, activate: u8) -> Vec<u8> {
    let mut r = start.to_le_bytes().to_vec();
    r.extend_from_slice(&len.to_le_bytes());
    r.extend_from_slice(&[control, 0, activate, 0]);
    r
}

/// 16 bytes of FMMU registers, byte-aligned.
pub(super) fn fmmu(logical: u32, len: u16, physical: u16, kind: u8) -> Vec<u8> {
    let mut r = logical.to_le_bytes().to_vec();
    r.extend_from_slice(&len.to_le_bytes());
    r.extend_from_slice(&[0, 7]);
    r.extend_from_slice(&physical.to_le_bytes());
    r.extend_from_slice(&[0, kind, 1, 0, 0, 0]);
    r
}

fn fpwr(device: &mut SubDevice<TestApp>, ado: u16, data: &[u8]) -> u16 {
    one(device, Command::Fpwr, (STATION, ado), data).1
}

fn al_status(device: &mut SubDevice<TestApp>) -> (u16, u16) {
    let (data, _) = one(device, Command::Fprd, (STATION, 0x0130), &[0; 6]);
    (
        u16::from_le_bytes([data[0], data[1]]),
        u16::from_le_bytes([data[4], data[5]]),
    )
}

/// A device at station 0x1001 with its mailbox configured, in Pre-Op.
fn in_preop() -> SubDevice<TestApp> {
    let mut d = device();
    assert_eq!(
        one(&mut d, Command::Apwr, (0, 0x0010), &STATION.to_le_bytes()).1,
        1
    );
    assert_eq!(fpwr(&mut d, 0x0800, &sm(0x1000, 128, 0x26, 1)), 1);
    assert_eq!(fpwr(&mut d, 0x0808, &sm(0x1080, 128, 0x22, 1)), 1);
    assert_eq!(fpwr(&mut d, 0x0120, &[2, 0]), 1);
    assert_eq!(al_status(&mut d), (2, 0));
    d
}

/// A device in Safe-Op with SM2 (outputs, watchdog on) and SM3 mapped by FMMU 0 (logical
/// 0x10000, write) and FMMU 1 (logical 0x10004, read).
fn in_safeop() -> SubDevice<TestApp> {
    let mut d = in_preop();
    assert_eq!(fpwr(&mut d, 0x0810, &sm(0x1100, 4, 0x64, 1)), 1);
    assert_eq!(fpwr(&mut d, 0x0818, &sm(0x1180, 2, 0x20, 1)), 1);
    assert_eq!(fpwr(&mut d, 0x0600, &fmmu(0x10000, 4, 0x1100, 2)), 1);
    assert_eq!(fpwr(&mut d, 0x0610, &fmmu(0x10004, 2, 0x1180, 1)), 1);
    assert_eq!(fpwr(&mut d, 0x0120, &[4, 0]), 1);
    assert_eq!(al_status(&mut d), (4, 0));
    d
}

#[test]
fn auto_increment_reaches_position_zero_only_and_counts_adp_up() {
    let mut d = device();
    let (data, wkc, adp) = one_at(&mut d, 0, Command::Aprd, (0, 0x0004), &[0; 4]);
    assert_eq!((data, wkc, adp), (vec![8, 8, 60, 0x0F], 1, 1));
    // Position 1 (ADP 0xFFFF) is another SubDevice: nothing read, nothing counted.
    let (data, wkc, adp) = one_at(&mut d, 0, Command::Aprd, (0xFFFF, 0x0004), &[0; 4]);
    assert_eq!((data, wkc, adp), (vec![0; 4], 0, 0));
    let (_, wkc, adp) = one_at(&mut d, 0, Command::Apwr, (0xFFFF, 0x0010), &[1, 0]);
    assert_eq!((wkc, adp), (0, 0));
    let (data, wkc, _) = one_at(&mut d, 0, Command::Aprw, (0, 0x0010), &[0x34, 0x12]);
    assert_eq!((data, wkc), (vec![0, 0], 3));
    assert_eq!(d.esc().u16(0x0010), 0x1234);
}

#[test]
fn configured_address_and_alias() {
    let mut d = device();
    one(&mut d, Command::Apwr, (0, 0x0010), &STATION.to_le_bytes());
    assert_eq!(
        one(&mut d, Command::Fprd, (STATION, 0x0012), &[0; 2]),
        (vec![0xAA, 0], 1)
    );
    assert_eq!(
        one(&mut d, Command::Fprd, (0x1002, 0x0012), &[0; 2]),
        (vec![0; 2], 0)
    );
    // The alias answers only once DL control bit 24 enables it.
    assert_eq!(one(&mut d, Command::Fprd, (0x00AA, 0x0130), &[0; 2]).1, 0);
    assert_eq!(fpwr(&mut d, 0x0100, &[0, 0, 0, 1]), 1);
    assert_eq!(
        one(&mut d, Command::Fprd, (0x00AA, 0x0130), &[0; 2]),
        (vec![1, 0], 1)
    );
    assert_eq!(
        one(&mut d, Command::Fprw, (STATION, 0x0010), &[5, 0]),
        (vec![0x01, 0x10], 3)
    );
    assert_eq!(d.esc().u16(0x0010), 5);
}

#[test]
fn broadcast_reads_or_in_and_every_command_counts_once() {
    let mut d = device();
    // AL status 0x0001 ORed into 0x80.
    assert_eq!(
        one(&mut d, Command::Brd, (0, 0x0130), &[0x80, 0]),
        (vec![0x81, 0], 1)
    );
    assert_eq!(
        one(&mut d, Command::Bwr, (0, 0x0010), &[7, 0]),
        (vec![7, 0], 1)
    );
    let (data, wkc) = one(&mut d, Command::Brw, (0, 0x0010), &[8, 0]);
    assert_eq!((data, wkc), (vec![0x0F, 0], 3));
    assert_eq!(d.esc().u16(0x0010), 8);
}

#[test]
fn read_only_registers_keep_their_value_but_the_write_counts() {
    let mut d = device();
    assert_eq!(one(&mut d, Command::Bwr, (0, 0x0004), &[0xFF; 4]).1, 1);
    assert_eq!(
        one(&mut d, Command::Brd, (0, 0x0004), &[0; 4]).0,
        vec![8, 8, 60, 0x0F]
    );
    assert_eq!(one(&mut d, Command::Bwr, (0, 0x0130), &[8, 0]).1, 1);
    assert_eq!(d.esc().u16(0x0130), 1);
}

#[test]
fn out_of_range_unknown_and_nop_datagrams_gain_nothing() {
    let mut d = device();
    assert_eq!(
        one(&mut d, Command::Brd, (0, 0xFFFF), &[0; 2]),
        (vec![0; 2], 0)
    );
    assert_eq!(
        one(&mut d, Command::Nop, (0, 0x0130), &[0; 2]),
        (vec![0; 2], 0)
    );
    let mut frame = FrameBuilder::new(MAC)
        .datagram(Command::Brd, 1, (0, 0x0130), &[0; 2], 5)
        .build();
    frame[16] = 0x20; // not a command
    let before = frame.clone();
    assert!(d.process_frame(Instant(0), &mut frame));
    assert_eq!(frame[16..], before[16..]);
}

#[test]
fn working_counters_add_to_what_came() {
    let mut d = device();
    let mut frame = FrameBuilder::new(MAC)
        .datagram(Command::Brd, 1, (0, 0x0130), &[0; 2], 5)
        .datagram(Command::Brw, 2, (0, 0x0100), &[0; 2], 0xFFFF)
        .build();
    assert!(d.process_frame(Instant(0), &mut frame));
    let Parsed::Datagrams { datagrams, .. } = parse(&frame) else {
        panic!()
    };
    assert_eq!(super::frame::wkc(&frame, &datagrams[0]), 6);
    assert_eq!(super::frame::wkc(&frame, &datagrams[1]), 2);
    assert_eq!(frame[6], 0x12, "source address marked on the way back");
}

#[test]
fn other_frames_are_ignored_and_a_malformed_datagram_is_not_answered() {
    let mut d = device();
    let mut ip = vec![0u8; 60];
    ip[12] = 0x08;
    let before = ip.clone();
    assert!(!d.process_frame(Instant(0), &mut ip));
    assert_eq!(ip, before);
    let mut frame = FrameBuilder::new(MAC)
        .datagram(Command::Brd, 1, (0, 0x0130), &[0; 2], 0)
        .datagram(Command::Brd, 2, (0, 0x0130), &[0; 2], 0)
        .build();
    frame[30 + 6] = 0xFF; // the second claims 255 bytes
    assert!(d.process_frame(Instant(0), &mut frame));
    assert_eq!(frame[26..30], [1, 0, 1, 0], "the first is answered");
    assert_eq!(frame[40..44], [0, 0, 0, 0], "the second is not");
}

#[test]
fn armw_and_frmw_read_at_the_addressed_one_and_write_elsewhere() {
    let mut d = device();
    one(&mut d, Command::Apwr, (0, 0x0010), &STATION.to_le_bytes());
    assert_eq!(
        one(&mut d, Command::Armw, (0, 0x0010), &[0; 2]),
        (vec![0x01, 0x10], 1)
    );
    assert_eq!(
        one(&mut d, Command::Frmw, (STATION, 0x1F00), &[9; 4]),
        (vec![0; 4], 1)
    );
    assert_eq!(one(&mut d, Command::Frmw, (0x2000, 0x1F00), &[9; 4]).1, 1);
    assert_eq!(
        d.esc().memory(0x1F00, 4),
        [9; 4],
        "written where not addressed"
    );
    assert_eq!(one(&mut d, Command::Armw, (0xFFFF, 0x1F00), &[3; 4]).1, 1);
    assert_eq!(d.esc().memory(0x1F00, 4), [3; 4]);
}

#[test]
fn sii_reads_eight_bytes_and_refuses_writes_without_enable() {
    let mut d = SubDevice::new(sii(), TestApp::default());
    // Read command at word address 7 (control 0x0100, address 7).
    assert_eq!(
        one(&mut d, Command::Bwr, (0, 0x0502), &[0, 1, 7, 0, 0, 0]).1,
        1
    );
    let (data, wkc) = one(&mut d, Command::Brd, (0, 0x0502), &[0; 14]);
    assert_eq!(wkc, 1);
    assert_eq!(data[..2], [0x40, 0], "not busy, 8-byte reads");
    assert_eq!(data[6..], [0, 0, 0xD8, 0x04, 0, 0, 0, 0]);
    // The SyncM category's last word, the end marker, then past the end: 0xFFFF.
    one(&mut d, Command::Bwr, (0, 0x0502), &[0, 1, 0x51, 0, 0, 0]);
    assert_eq!(
        one(&mut d, Command::Brd, (0, 0x0508), &[0; 8]).0,
        [1, 4, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF]
    );
    // A write without write enable: error bit 14, nothing written.
    one(&mut d, Command::Bwr, (0, 0x0508), &[0x55, 0x55]);
    one(&mut d, Command::Bwr, (0, 0x0502), &[0, 2, 8, 0, 0, 0]);
    assert_eq!(d.esc().u16(0x0502), 0x4040);
    assert_eq!(d.esc().sii_word(8), 0x04D8);
    one(&mut d, Command::Bwr, (0, 0x0502), &[1, 2, 8, 0, 0, 0]);
    assert_eq!(d.esc().sii_word(8), 0x5555);
    // The PDI takes the SII only when the master offers it.
    d.esc_mut().write(0x0501, &[1]);
    assert_eq!(d.esc().u8(0x0501), 0);
    one(&mut d, Command::Bwr, (0, 0x0500), &[1]);
    d.esc_mut().write(0x0501, &[1]);
    assert_eq!(d.esc().u8(0x0501), 1);
    // While the PDI holds the SII, the master's commands do nothing; the PDI's run.
    one(&mut d, Command::Bwr, (0, 0x0502), &[0, 1, 4, 0, 0, 0]);
    assert_eq!(
        one(&mut d, Command::Brd, (0, 0x0508), &[0; 2]).0,
        [0x55, 0x55]
    );
    d.esc_mut().write(0x0504, &[4, 0, 0, 0]);
    d.esc_mut().write(0x0502, &[0, 1]);
    assert_eq!(d.esc().memory(0x0508, 2), [0xAA, 0]);
    // Force ECAT access (bit 1) takes it from the PDI.
    one(&mut d, Command::Bwr, (0, 0x0500), &[3]);
    assert_eq!(d.esc().u8(0x0501), 0);
}

#[test]
fn preop_needs_the_sii_offered_once() {
    let mut d = SubDevice::new(sii(), TestApp::default());
    one(&mut d, Command::Apwr, (0, 0x0010), &STATION.to_le_bytes());
    fpwr(&mut d, 0x0800, &sm(0x1000, 128, 0x26, 1));
    fpwr(&mut d, 0x0808, &sm(0x1080, 128, 0x22, 1));
    fpwr(&mut d, 0x0120, &[2, 0]);
    assert_eq!(al_status(&mut d), (0x11, 0x0050), "EEPROM no access");
    fpwr(&mut d, 0x0500, &[1]);
    fpwr(&mut d, 0x0120, &[0x12, 0]);
    assert_eq!(al_status(&mut d), (2, 0));
    assert_eq!(d.esc().u8(0x0501), 0, "the PDI gave the SII back");
    // Back in Init with the SII taken back: the SII read before stands.
    fpwr(&mut d, 0x0500, &[0]);
    fpwr(&mut d, 0x0120, &[1, 0]);
    fpwr(&mut d, 0x0120, &[2, 0]);
    assert_eq!(al_status(&mut d), (2, 0));
}

#[test]
fn preop_needs_the_mailbox_sync_managers() {
    let mut d = device();
    one(&mut d, Command::Apwr, (0, 0x0010), &STATION.to_le_bytes());
    fpwr(&mut d, 0x0800, &sm(0x1000, 64, 0x26, 1)); // too short
    fpwr(&mut d, 0x0808, &sm(0x1080, 128, 0x22, 1));
    fpwr(&mut d, 0x0120, &[2, 0]);
    assert_eq!(al_status(&mut d), (0x11, 0x0016));
    // Not acknowledged: a new request for Pre-Op is ignored.
    fpwr(&mut d, 0x0800, &sm(0x1000, 128, 0x26, 1));
    fpwr(&mut d, 0x0120, &[2, 0]);
    assert_eq!(al_status(&mut d), (0x11, 0x0016));
    fpwr(&mut d, 0x0120, &[0x12, 0]);
    assert_eq!(al_status(&mut d), (2, 0));
    assert_eq!(d.app().changes, [(AlState::Init, AlState::PreOp)]);
}

#[test]
fn skipping_a_state_is_refused_with_0x0011_and_acknowledged() {
    let mut d = in_preop();
    fpwr(&mut d, 0x0120, &[8, 0]);
    assert_eq!(al_status(&mut d), (0x12, 0x0011));
    fpwr(&mut d, 0x0120, &[0x12, 0]);
    assert_eq!(al_status(&mut d), (2, 0));
    fpwr(&mut d, 0x0120, &[3, 0]);
    assert_eq!(al_status(&mut d), (0x12, 0x0013));
    // Going down needs no acknowledgement.
    fpwr(&mut d, 0x0120, &[1, 0]);
    assert_eq!(al_status(&mut d), (1, 0));
}

#[test]
fn safeop_needs_process_data_sync_managers_of_the_image_sizes() {
    let mut d = in_preop();
    fpwr(&mut d, 0x0810, &sm(0x1100, 3, 0x64, 1));
    fpwr(&mut d, 0x0818, &sm(0x1180, 2, 0x20, 1));
    fpwr(&mut d, 0x0120, &[4, 0]);
    assert_eq!(al_status(&mut d), (0x12, 0x001D));
    fpwr(&mut d, 0x0810, &sm(0x1100, 4, 0x64, 1));
    fpwr(&mut d, 0x0818, &sm(0x1180, 2, 0x24, 1)); // written by the master: wrong way
    fpwr(&mut d, 0x0120, &[0x14, 0]);
    assert_eq!(al_status(&mut d), (0x12, 0x001E));
    fpwr(&mut d, 0x0818, &sm(0x1180, 2, 0x20, 1));
    fpwr(&mut d, 0x0120, &[0x14, 0]);
    assert_eq!(al_status(&mut d), (4, 0));
}

#[test]
fn logical_commands_go_through_the_fmmus_in_safeop_and_op() {
    let mut d = in_preop();
    fpwr(&mut d, 0x0810, &sm(0x1100, 4, 0x64, 1));
    fpwr(&mut d, 0x0818, &sm(0x1180, 2, 0x20, 1));
    fpwr(&mut d, 0x0600, &fmmu(0x10000, 4, 0x1100, 2));
    fpwr(&mut d, 0x0610, &fmmu(0x10004, 2, 0x1180, 1));
    // Pre-Op: the device keeps its process-data SyncManagers off.
    assert_eq!(one(&mut d, Command::Lrw, (0, 1), &[0; 6]).1, 0);
    let mut d = in_safeop();
    d.app_mut().inputs = [0xAB, 0xCD];
    let (data, wkc) = one(&mut d, Command::Lrw, (0, 1), &[1, 2, 3, 4, 9, 9]);
    assert_eq!((data, wkc), (vec![1, 2, 3, 4, 0xAB, 0xCD], 3));
    assert!(d.app().outputs.is_empty(), "Safe-Op: outputs not applied");
    fpwr(&mut d, 0x0120, &[8, 0]);
    assert_eq!(al_status(&mut d), (8, 0));
    assert_eq!(one(&mut d, Command::Lwr, (0, 1), &[5, 6, 7, 8]).1, 1);
    assert_eq!(d.app().outputs, [5, 6, 7, 8]);
    assert_eq!(
        one(&mut d, Command::Lrd, (4, 1), &[0; 2]),
        (vec![0xAB, 0xCD], 1)
    );
    // Beyond every FMMU: nothing.
    assert_eq!(one(&mut d, Command::Lrw, (0, 2), &[0; 2]).1, 0);
    // A read over the outputs FMMU only (a write FMMU): no read counted, data unchanged.
    assert_eq!(one(&mut d, Command::Lrd, (0, 1), &[0; 4]), (vec![0; 4], 0));
}

#[test]
fn an_lrw_writes_the_data_as_it_came_and_reads_memory_as_it_was() {
    let mut d = in_safeop();
    fpwr(&mut d, 0x0120, &[8, 0]);
    d.app_mut().inputs = [0xAB, 0xCD];
    // Inputs over the outputs' logical bytes, as SOEM's overlapping images have them: the
    // outputs are the data as it came, the inputs read into the same bytes.
    fpwr(&mut d, 0x0620, &fmmu(0x30000, 4, 0x1100, 2));
    fpwr(&mut d, 0x0630, &fmmu(0x30000, 2, 0x1180, 1));
    let (data, wkc) = one(&mut d, Command::Lrw, (0, 3), &[1, 2, 3, 4]);
    assert_eq!((data, wkc), (vec![0xAB, 0xCD, 3, 4], 3));
    assert_eq!(d.app().outputs, [1, 2, 3, 4]);
    // A read FMMU over the memory a write FMMU of the same datagram changes (logical 0x10006
    // reads the outputs buffer that 0x10000 writes): it reads the memory as it was.
    fpwr(&mut d, 0x0620, &fmmu(0x10006, 4, 0x1100, 1));
    fpwr(&mut d, 0x0630, &[0; 16]);
    let (data, wkc) = one(
        &mut d,
        Command::Lrw,
        (0, 1),
        &[9, 9, 9, 9, 0, 0, 0, 0, 0, 0],
    );
    assert_eq!((data, wkc), (vec![9, 9, 9, 9, 0xAB, 0xCD, 1, 2, 3, 4], 3));
    assert_eq!(d.app().outputs, [9, 9, 9, 9]);
    assert_eq!(d.esc().memory(0x1100, 4), [9, 9, 9, 9]);
}

#[test]
fn a_bit_fmmu_maps_single_bits() {
    let mut d = in_safeop();
    // FMMU 2: logical 0x20000 bits 3..=4 → physical 0x1180 bits 0..=1 (inputs), read.
    let mut f = fmmu(0x20000, 1, 0x1180, 1);
    f[6] = 3;
    f[7] = 4;
    fpwr(&mut d, 0x0620, &f);
    d.app_mut().inputs = [0b0000_0010, 0];
    let (data, wkc) = one(&mut d, Command::Lrd, (0, 2), &[0xFF]);
    assert_eq!((data, wkc), (vec![0b1111_0111], 1));
}

#[test]
fn the_mailbox_fills_empties_and_repeats() {
    let mut d = in_preop();
    let mut request = vec![0u8; 128];
    request[..6].copy_from_slice(&[1, 2, 3, 4, 5, 6]);
    assert_eq!(fpwr(&mut d, 0x1000, &request), 1);
    // The answer waits in SM1: status bit 3.
    assert_eq!(
        one(&mut d, Command::Fprd, (STATION, 0x080D), &[0]).0,
        [0x08]
    );
    // The master may not write the device's mailbox, nor read its own.
    assert_eq!(fpwr(&mut d, 0x1080, &[0; 128]), 0);
    assert_eq!(one(&mut d, Command::Fprd, (STATION, 0x1000), &[0; 2]).1, 0);
    let (answer, wkc) = one(&mut d, Command::Fprd, (STATION, 0x1080), &[0; 128]);
    assert_eq!((&answer[..6], wkc), (&[6, 5, 4, 3, 2, 1][..], 1));
    assert_eq!(one(&mut d, Command::Fprd, (STATION, 0x080D), &[0]).0, [0]);
    // Empty: a read is refused.
    assert_eq!(
        one(&mut d, Command::Fprd, (STATION, 0x1080), &[0; 128]).1,
        0
    );
    // The repeat toggle brings the last answer back and is acknowledged in PDI control.
    assert_eq!(fpwr(&mut d, 0x080E, &[0x03]), 1);
    assert_eq!(
        one(&mut d, Command::Fprd, (STATION, 0x080D), &[0; 3]).0,
        [0x08, 0x03, 0x02]
    );
    let (again, wkc) = one(&mut d, Command::Fprd, (STATION, 0x1080), &[0; 128]);
    assert_eq!((again, wkc), (answer, 1));
}

#[test]
fn the_outputs_watchdog_drops_op_to_safeop_with_0x001b() {
    let mut d = in_safeop();
    fpwr(&mut d, 0x0120, &[8, 0]);
    one_at(&mut d, 50_000, Command::Lwr, (0, 1), &[1, 2, 3, 4]);
    // 100 ms after the last outputs: still Op.
    let (data, _, _) = one_at(&mut d, 150_000, Command::Fprd, (STATION, 0x0130), &[0; 2]);
    assert_eq!(data, [8, 0]);
    let (data, _, _) = one_at(&mut d, 150_001, Command::Fprd, (STATION, 0x0130), &[0; 6]);
    assert_eq!(data, [0x14, 0, 0, 0, 0x1B, 0]);
}

/// Found by hostile frames (issue 34): a mailbox SyncManager configured over the registers
/// refused every write to them, its own configuration and AL control included, until the
/// simulator was restarted. SyncManagers govern the digital I/O registers and the process
/// memory only.
#[test]
fn a_sync_manager_over_the_registers_does_not_lock_the_master_out() {
    let mut d = device();
    one(&mut d, Command::Apwr, (0, 0x0010), &STATION.to_le_bytes());
    // SM1, device to master (0x22), enabled, over 0x0000-0x0FFF: empty, so never written.
    assert_eq!(
        fpwr(
            &mut d,
            0x0808,
            &[0x00, 0x00, 0x00, 0x10, 0x22, 0x00, 0x01, 0x00]
        ),
        1
    );
    assert_eq!(fpwr(&mut d, 0x0120, &[0x11, 0x00]), 1, "AL control");
    assert_eq!(fpwr(&mut d, 0x0808, &[0; 8]), 1, "SM1 cleared");
    let (data, wkc) = one(&mut d, Command::Fprd, (STATION, 0x0808), &[0xEE; 8]);
    assert_eq!((data, wkc), (vec![0; 8], 1));
}
