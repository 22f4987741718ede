//! The EC-TX508 served from its ESI (`EsiDevice`) driven frame by frame as a MainDevice drives
//! it: mailbox SyncManagers, Pre-Op, CoE SDO (expedited, normal, complete access, segmented
//! download, aborts with CiA 301 codes, the Pre-Op-only PDO assignment), Safe-Op refused and then
//! accepted with the SyncManager lengths following the assignment, and process data in Op; the
//! ESI's `WriteRestrictions` enforced with 0800 0022.

use std::path::Path;

use edsgen_runtime::Instant;
use edsgen_sim::ethercat::frame::{parse, wkc, Command, FrameBuilder, Parsed};
use edsgen_sim::ethercat::{EsiDevice, SubDevice};

const STATION: u16 = 0x1001;

struct Master {
    device: SubDevice<EsiDevice>,
    counter: u8,
    now: u64,
}

impl Master {
    fn new() -> Self {
        Master::with(&ec_tx508())
    }

    fn with(model: &edsgen_model::model::Device) -> Self {
        let device = EsiDevice::subdevice(model, None).unwrap();
        let mut master = Master {
            device,
            counter: 0,
            now: 0,
        };
        master.one(Command::Apwr, (0, 0x0010), &STATION.to_le_bytes());
        // The SII offered to the device, as SOEM and ethercrab do before Pre-Op.
        master.fpwr(0x0500, &[1]);
        master.fpwr(0x0800, &sm(0x1000, 512, 0x26));
        master.fpwr(0x0808, &sm(0x1400, 512, 0x22));
        master.fpwr(0x0120, &[2, 0]);
        assert_eq!(master.al(), (2, 0));
        master
    }

    fn one(&mut self, command: Command, address: (u16, u16), data: &[u8]) -> (Vec<u8>, u16) {
        self.now += 1_000;
        let mut frame = FrameBuilder::new([0x10; 6])
            .datagram(command, 1, address, data, 0)
            .build();
        assert!(self.device.process_frame(Instant(self.now), &mut frame));
        let Parsed::Datagrams { datagrams, .. } = parse(&frame) else {
            panic!("not EtherCAT");
        };
        (
            frame[datagrams[0].data.clone()].to_vec(),
            wkc(&frame, &datagrams[0]),
        )
    }

    fn fpwr(&mut self, ado: u16, data: &[u8]) -> u16 {
        self.one(Command::Fpwr, (STATION, ado), data).1
    }

    fn al(&mut self) -> (u16, u16) {
        let (d, _) = self.one(Command::Fprd, (STATION, 0x0130), &[0; 6]);
        (
            u16::from_le_bytes([d[0], d[1]]),
            u16::from_le_bytes([d[4], d[5]]),
        )
    }

    /// Sends an SDO request (after the CoE header) and returns the response's SDO part.
    fn sdo(&mut self, body: &[u8]) -> Vec<u8> {
        self.counter = self.counter % 7 + 1;
        let mut message = (2 + body.len() as u16).to_le_bytes().to_vec();
        message.extend_from_slice(&[0, 0, 0, 0x03 | (self.counter << 4), 0x00, 0x20]);
        message.extend_from_slice(body);
        message.resize(512, 0);
        assert_eq!(self.fpwr(0x1000, &message), 1);
        let (status, _) = self.one(Command::Fprd, (STATION, 0x080D), &[0]);
        assert_eq!(status[0] & 0x08, 0x08, "an answer waits");
        let (answer, wkc) = self.one(Command::Fprd, (STATION, 0x1400), &[0; 512]);
        assert_eq!(wkc, 1);
        let len = usize::from(u16::from_le_bytes([answer[0], answer[1]]));
        assert_eq!(
            answer[5],
            0x03 | (self.counter << 4),
            "CoE, the request's counter"
        );
        assert_eq!(answer[6..8], [0x00, 0x30], "SDO response");
        answer[8..6 + len].to_vec()
    }
}

fn ec_tx508() -> edsgen_model::model::Device {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../eds/ec-tx508.xml");
    edsgen_model::read::read_file(&path).unwrap().device
}

fn sm(start: u16, len: u16, control: u8) -> Vec<u8> {
    let mut r = start.to_le_bytes().to_vec();
    r.extend_from_slice(&len.to_le_bytes());
    r.extend_from_slice(&[control, 0, 1, 0]);
    r
}

fn fmmu(logical: u32, len: u16, physical: u16, kind: u8) -> Vec<u8> {
    let mut r = logical.to_le_bytes().to_vec();
    r.extend_from_slice(&len.to_le_bytes());
    r.extend_from_slice(&[0, 7]);
    r.extend_from_slice(&physical.to_le_bytes());
    r.extend_from_slice(&[0, kind, 1, 0, 0, 0]);
    r
}

#[test]
fn expedited_normal_and_complete_access_uploads() {
    let mut m = Master::new();
    // 1018h:01 vendor: expedited, 4 bytes.
    assert_eq!(
        m.sdo(&[0x40, 0x18, 0x10, 1, 0, 0, 0, 0]),
        [0x43, 0x18, 0x10, 1, 0xD8, 0x04, 0, 0]
    );
    // 6060h (1 byte): expedited with 3 unused bytes.
    assert_eq!(m.sdo(&[0x40, 0x60, 0x60, 0, 0, 0, 0, 0])[0], 0x4F);
    // 1018h by complete access: sub 0, a padding byte, four UDINTs: normal upload.
    let answer = m.sdo(&[0x50, 0x18, 0x10, 0, 0, 0, 0, 0]);
    assert_eq!(answer[..8], [0x51, 0x18, 0x10, 0, 18, 0, 0, 0]);
    assert_eq!(answer[8..10], [4, 0]);
    assert_eq!(answer[10..18], [0xD8, 0x04, 0, 0, 0x52, 0x92, 0, 0]);
    assert_eq!(answer.len(), 8 + 18);
}

#[test]
fn aborts_carry_cia301_codes() {
    let mut m = Master::new();
    let abort = |code: u32, index: u16, sub: u8| {
        let mut a = vec![0x80];
        a.extend_from_slice(&index.to_le_bytes());
        a.push(sub);
        a.extend_from_slice(&code.to_le_bytes());
        a
    };
    assert_eq!(
        m.sdo(&[0x40, 0x34, 0x12, 0, 0, 0, 0, 0]),
        abort(0x0602_0000, 0x1234, 0)
    );
    assert_eq!(
        m.sdo(&[0x40, 0x18, 0x10, 9, 0, 0, 0, 0]),
        abort(0x0609_0011, 0x1018, 9)
    );
    // 1018h:01 is read-only.
    assert_eq!(
        m.sdo(&[0x23, 0x18, 0x10, 1, 1, 2, 3, 4]),
        abort(0x0601_0002, 0x1018, 1)
    );
    // 6040h takes 2 bytes, not 4.
    assert_eq!(
        m.sdo(&[0x23, 0x40, 0x60, 0, 1, 2, 3, 4]),
        abort(0x0607_0012, 0x6040, 0)
    );
    // A segment with no transfer, and a command that is none.
    assert_eq!(
        m.sdo(&[0x00, 0, 0, 0, 0, 0, 0, 0]),
        abort(0x0504_0001, 0, 0)
    );
    assert_eq!(
        m.sdo(&[0xE0, 0x40, 0x60, 0, 0, 0, 0, 0]),
        abort(0x0504_0001, 0x6040, 0)
    );
    // 1C12h:01 must name an RxPDO the device has.
    assert_eq!(
        m.sdo(&[0x2B, 0x12, 0x1C, 1, 0x00, 0x1A, 0, 0]),
        abort(0x0609_0030, 0x1C12, 1)
    );
}

#[test]
fn a_segmented_download_writes_at_the_end() {
    let mut m = Master::new();
    // 607Ah (DINT) in a normal download of 4 bytes announced, 2 given, then one segment.
    assert_eq!(
        m.sdo(&[0x21, 0x7A, 0x60, 0, 4, 0, 0, 0, 0x11, 0x22]),
        [0x60, 0x7A, 0x60, 0, 0, 0, 0, 0]
    );
    // A segment with the wrong toggle aborts, naming the transfer's entry 607Ah:00.
    assert_eq!(
        m.sdo(&[0x10 | 0x01 | (5 << 1), 0x33, 0x44, 0, 0, 0, 0, 0]),
        [0x80, 0x7A, 0x60, 0, 0x00, 0x00, 0x03, 0x05]
    );
    m.sdo(&[0x21, 0x7A, 0x60, 0, 4, 0, 0, 0, 0x11, 0x22]);
    assert_eq!(
        m.sdo(&[0x01 | (5 << 1), 0x33, 0x44, 0, 0, 0, 0, 0]),
        [0x20, 0, 0, 0, 0, 0, 0, 0]
    );
    assert_eq!(
        m.sdo(&[0x40, 0x7A, 0x60, 0, 0, 0, 0, 0]),
        [0x43, 0x7A, 0x60, 0, 0x11, 0x22, 0x33, 0x44]
    );
}

#[test]
fn a_pdo_reassignment_in_preop_sets_the_image_sizes_and_is_refused_in_safeop() {
    let mut m = Master::new();
    // Default: 1600h (21 bytes) and 1A00h (23 bytes).
    m.fpwr(0x0810, &sm(0x1800, 6, 0x64));
    m.fpwr(0x0818, &sm(0x1C00, 23, 0x20));
    m.fpwr(0x0120, &[4, 0]);
    assert_eq!(m.al(), (0x12, 0x001D), "SM2 of 6 bytes for a 21-byte image");
    m.fpwr(0x0120, &[0x12, 0]);
    // 1C12h := { 1601h } (6040h, 607Ah: 6 bytes).
    let ok = |index: u16, sub: u8| {
        let [a, b] = index.to_le_bytes();
        vec![0x60, a, b, sub, 0, 0, 0, 0]
    };
    assert_eq!(m.sdo(&[0x2F, 0x12, 0x1C, 0, 0, 0, 0, 0]), ok(0x1C12, 0));
    assert_eq!(
        m.sdo(&[0x2B, 0x12, 0x1C, 1, 0x01, 0x16, 0, 0]),
        ok(0x1C12, 1)
    );
    assert_eq!(m.sdo(&[0x2F, 0x12, 0x1C, 0, 1, 0, 0, 0]), ok(0x1C12, 0));
    m.fpwr(0x0600, &fmmu(0, 6, 0x1800, 2));
    m.fpwr(0x0610, &fmmu(6, 23, 0x1C00, 1));
    m.fpwr(0x0120, &[4, 0]);
    assert_eq!(m.al(), (4, 0));
    let refused = m.sdo(&[0x2F, 0x12, 0x1C, 0, 0, 0, 0, 0]);
    assert_eq!(refused[4..], 0x0800_0022u32.to_le_bytes());
    m.fpwr(0x0120, &[8, 0]);
    assert_eq!(m.al(), (8, 0));
    // Outputs 6040h = 0x000F, 607Ah = 0x01020304 land in the dictionary.
    let (_, wkc) = m.one(Command::Lwr, (0, 0), &[0x0F, 0, 4, 3, 2, 1]);
    assert_eq!(wkc, 1);
    assert_eq!(
        m.sdo(&[0x40, 0x7A, 0x60, 0, 0, 0, 0, 0]),
        [0x43, 0x7A, 0x60, 0, 4, 3, 2, 1]
    );
    let (inputs, wkc) = m.one(Command::Lrd, (6, 0), &[0; 23]);
    assert_eq!((inputs.len(), wkc), (23, 1));
}

#[test]
fn write_restrictions_refuse_writes_in_other_states_with_0800_0022() {
    let mut model = ec_tx508();
    let mut restrict = |index: u16, states: &str| {
        let sub = model
            .objects
            .get_mut(&index)
            .and_then(|o| o.subs.get_mut(&0))
            .unwrap();
        sub.custom
            .push(("WriteRestrictions".to_owned(), states.to_owned()));
    };
    // 6060h (operation mode) only in Pre-Op; 607Ah (target position) only in Safe-Op and Op;
    // 6072h (max. torque) with a text naming no state: not restricted.
    restrict(0x6060, "PreOP");
    restrict(0x607A, "SafeOP_OP");
    restrict(0x6072, "Init");
    let mut m = Master::with(&model);
    let written = |index: u16| {
        let [a, b] = index.to_le_bytes();
        vec![0x60, a, b, 0, 0, 0, 0, 0]
    };
    let refused = |index: u16| {
        let [a, b] = index.to_le_bytes();
        let mut r = vec![0x80, a, b, 0];
        r.extend_from_slice(&0x0800_0022u32.to_le_bytes());
        r
    };
    let mode = [0x2F, 0x60, 0x60, 0, 9, 0, 0, 0];
    let position = [0x23, 0x7A, 0x60, 0, 1, 0, 0, 0];
    let torque = [0x2B, 0x72, 0x60, 0, 0xE8, 0x03, 0, 0];
    assert_eq!(m.sdo(&mode), written(0x6060));
    assert_eq!(m.sdo(&position), refused(0x607A));
    assert_eq!(m.sdo(&torque), written(0x6072));
    m.fpwr(0x0810, &sm(0x1800, 21, 0x64));
    m.fpwr(0x0818, &sm(0x1C00, 23, 0x20));
    m.fpwr(0x0600, &fmmu(0, 21, 0x1800, 2));
    m.fpwr(0x0610, &fmmu(21, 23, 0x1C00, 1));
    m.fpwr(0x0120, &[4, 0]);
    assert_eq!(m.al(), (4, 0));
    assert_eq!(m.sdo(&mode), refused(0x6060));
    assert_eq!(m.sdo(&position), written(0x607A));
    assert_eq!(m.sdo(&torque), written(0x6072));
    // The refused write left 6060h as Pre-Op wrote it.
    assert_eq!(
        m.sdo(&[0x40, 0x60, 0x60, 0, 0, 0, 0, 0]),
        [0x4F, 0x60, 0x60, 0, 9, 0, 0, 0]
    );
}
