//! Frames through a segment of three SubDevices: the ADP each command brings back, the working
//! counters every addressed SubDevice adds, the data each one reads or writes on the way, and
//! the inputs each one prepares only for the frames that read them.

use edsgen_runtime::Instant;

use super::frame::{parse, wkc, Command, FrameBuilder, Parsed};
use super::segment::Segment;
use super::tests::{fmmu, sii, sm, TestApp};
use super::{AlState, SubDevice};

const MAC: [u8; 6] = [0x10; 6];

/// Three SubDevices in line, their station addresses still 0.
fn three() -> Segment<TestApp> {
    Segment::new(
        (0..3)
            .map(|_| SubDevice::new(sii(), TestApp::default()))
            .collect(),
    )
}

/// One datagram sent through `segment`: the data, working counter and ADP that came back.
fn send(
    segment: &mut Segment<TestApp>,
    command: Command,
    address: (u16, u16),
    data: &[u8],
) -> (Vec<u8>, u16, u16) {
    let mut frame = FrameBuilder::new(MAC)
        .datagram(command, 0x42, address, data, 0)
        .build();
    assert!(segment.process_frame(Instant(0), &mut frame));
    assert_eq!(
        frame[6], 0x12,
        "the source address's locally administered bit"
    );
    let Parsed::Datagrams { datagrams, .. } = parse(&frame) else {
        panic!("not EtherCAT on the way back");
    };
    let d = &datagrams[0];
    (frame[d.data.clone()].to_vec(), wkc(&frame, d), d.header.adp)
}

/// Three SubDevices given station addresses 0x1001, 0x1002 and 0x1003 by position.
fn addressed() -> Segment<TestApp> {
    let mut segment = three();
    for (position, station) in [(0u16, 0x1001u16), (1, 0x1002), (2, 0x1003)] {
        let adp = 0u16.wrapping_sub(position);
        let (_, wkc, adp) = send(
            &mut segment,
            Command::Apwr,
            (adp, 0x0010),
            &station.to_le_bytes(),
        );
        // Each of the three counted the ADP up once.
        assert_eq!((wkc, adp), (1, 3 - position));
    }
    segment
}

#[test]
fn aprd_reaches_the_subdevice_whose_adp_comes_to_zero() {
    let mut segment = addressed();
    assert_eq!(
        send(&mut segment, Command::Aprd, (0xFFFE, 0x0010), &[0, 0]),
        (vec![0x03, 0x10], 1, 1)
    );
    assert_eq!(
        send(&mut segment, Command::Aprd, (0, 0x0010), &[0, 0]),
        (vec![0x01, 0x10], 1, 3)
    );
    // Position 3 is past the end: nobody answers, the ADP comes back 0.
    assert_eq!(
        send(&mut segment, Command::Aprd, (0xFFFD, 0x0010), &[0xEE, 0xEE]),
        (vec![0xEE, 0xEE], 0, 0)
    );
    // APRW: read +1, write +2, on the one addressed only.
    assert_eq!(
        send(&mut segment, Command::Aprw, (0xFFFF, 0x0F80), &[7, 8]),
        (vec![0, 0], 3, 2)
    );
    assert_eq!(
        send(&mut segment, Command::Fprd, (0x1002, 0x0F80), &[0, 0]),
        (vec![7, 8], 1, 0x1002)
    );
}

#[test]
fn broadcasts_are_counted_by_every_subdevice() {
    let mut segment = addressed();
    // BRD: each ORs its memory into the data and counts the ADP up.
    assert_eq!(
        send(&mut segment, Command::Brd, (0, 0x0010), &[0, 0]),
        (vec![0x03, 0x10], 3, 3)
    );
    assert_eq!(
        send(&mut segment, Command::Bwr, (0, 0x0F80), &[0x55]),
        (vec![0x55], 3, 3)
    );
    // BRW: read +1 and write +2 on each of three.
    assert_eq!(
        send(&mut segment, Command::Brw, (0, 0x0F80), &[0x0A]),
        (vec![0x5F], 9, 3)
    );
    // Each writes the data as it reached it: the first the master's, the others the OR so far.
    for (station, value) in [(0x1001, 0x0A), (0x1002, 0x5F), (0x1003, 0x5F)] {
        assert_eq!(
            send(&mut segment, Command::Fprd, (station, 0x0F80), &[0]),
            (vec![value], 1, station)
        );
    }
}

#[test]
fn fprd_reaches_its_station_only() {
    let mut segment = addressed();
    assert_eq!(
        send(&mut segment, Command::Fprd, (0x1002, 0x0010), &[0, 0]),
        (vec![0x02, 0x10], 1, 0x1002)
    );
    assert_eq!(
        send(&mut segment, Command::Fpwr, (0x1003, 0x0F80), &[9]),
        (vec![9], 1, 0x1003)
    );
    assert_eq!(
        send(&mut segment, Command::Fprd, (0x1009, 0x0010), &[0xEE, 0xEE]),
        (vec![0xEE, 0xEE], 0, 0x1009)
    );
    assert_eq!(segment.devices()[2].esc().u8(0x0F80), 9);
    assert_eq!(segment.devices()[1].esc().u8(0x0F80), 0);
}

#[test]
fn armw_reads_at_the_addressed_one_and_writes_at_the_others() {
    let mut segment = addressed();
    segment
        .device_mut(1)
        .expect("position 1")
        .esc_mut()
        .write_memory(0x0F80, &[1, 2, 3, 4]);
    // Position 0 writes what came (zeros), position 1 reads its value into the datagram,
    // position 2 writes that value: three SubDevices count.
    assert_eq!(
        send(&mut segment, Command::Armw, (0xFFFF, 0x0F80), &[0; 4]),
        (vec![1, 2, 3, 4], 3, 2)
    );
    let memory = |segment: &Segment<TestApp>, n: usize| {
        segment.devices()[n].esc().memory(0x0F80, 4).to_vec()
    };
    assert_eq!(memory(&segment, 0), [0; 4]);
    assert_eq!(memory(&segment, 2), [1, 2, 3, 4]);
    // FRMW: station 0x1003 reads, the others write.
    segment
        .device_mut(2)
        .expect("position 2")
        .esc_mut()
        .write_memory(0x0F80, &[9, 9, 9, 9]);
    assert_eq!(
        send(&mut segment, Command::Frmw, (0x1003, 0x0F80), &[5; 4]),
        (vec![9; 4], 3, 0x1003)
    );
    assert_eq!(memory(&segment, 0), [5; 4]);
    assert_eq!(memory(&segment, 1), [5; 4]);
}

#[test]
fn lrw_goes_through_each_subdevices_fmmus() {
    let mut segment = addressed();
    // SubDevice k: logical 6k..6k+4 its outputs (physical 0x1100, written), 6k+4..6k+6 its
    // inputs (physical 0x1180, read).
    for k in 0..3u16 {
        let station = 0x1001 + k;
        let logical = 6 * u32::from(k);
        let mut fmmus = fmmu(logical, 4, 0x1100, 2);
        fmmus.extend(fmmu(logical + 4, 2, 0x1180, 1));
        assert_eq!(
            send(&mut segment, Command::Fpwr, (station, 0x0600), &fmmus).1,
            1
        );
        let device = segment.device_mut(usize::from(k)).expect("a SubDevice");
        device
            .esc_mut()
            .write_memory(0x1180, &[0xA0 + k as u8, 0xB0 + k as u8]);
    }
    let outputs: Vec<u8> = (1..=18).collect();
    let (data, wkc, adp) = send(&mut segment, Command::Lrw, (0, 0), &outputs);
    assert_eq!(
        data,
        [1, 2, 3, 4, 0xA0, 0xB0, 7, 8, 9, 10, 0xA1, 0xB1, 13, 14, 15, 16, 0xA2, 0xB2]
    );
    // Read +1 and write +2 on each of the three.
    assert_eq!((wkc, adp), (9, 0));
    for (k, written) in [[1, 2, 3, 4], [7, 8, 9, 10], [13, 14, 15, 16]]
        .iter()
        .enumerate()
    {
        assert_eq!(segment.devices()[k].esc().memory(0x1100, 4), written);
    }
    // An LRD of the second one's inputs only: it alone counts.
    assert_eq!(
        send(&mut segment, Command::Lrd, (10, 0), &[0, 0]),
        (vec![0xA1, 0xB1], 1, 10)
    );
    // An LWR past every FMMU: nobody counts.
    assert_eq!(send(&mut segment, Command::Lwr, (40, 0), &[1]).1, 0);
}

/// One frame of several datagrams through `segment`: each one's data, working counter and ADP.
fn send_frame(
    segment: &mut Segment<TestApp>,
    datagrams: &[(Command, (u16, u16), &[u8])],
) -> Vec<(Vec<u8>, u16, u16)> {
    let mut builder = FrameBuilder::new(MAC);
    for (n, (command, address, data)) in datagrams.iter().enumerate() {
        builder = builder.datagram(*command, n as u8, *address, data, 0);
    }
    let mut frame = builder.build();
    assert!(segment.process_frame(Instant(0), &mut frame));
    let Parsed::Datagrams { datagrams, .. } = parse(&frame) else {
        panic!("not EtherCAT on the way back");
    };
    datagrams
        .iter()
        .map(|d| (frame[d.data.clone()].to_vec(), wkc(&frame, d), d.header.adp))
        .collect()
}

/// Three SubDevices in Op, SubDevice k with its outputs (SM2, 0x1100, 4 bytes) at logical
/// 6k..6k+4 and its inputs (SM3, 0x1180, 2 bytes: 0xA0+k, 0xB0+k) at 6k+4..6k+6; how many
/// times each was asked for its inputs is then set back to 0.
fn in_op() -> Segment<TestApp> {
    let mut segment = addressed();
    // The master offers the SII to the devices, which read their layout from it.
    assert_eq!(send(&mut segment, Command::Bwr, (0, 0x0500), &[1]).1, 3);
    for k in 0..3u16 {
        let station = 0x1001 + k;
        let logical = 6 * u32::from(k);
        let mut outputs_inputs = fmmu(logical, 4, 0x1100, 2);
        outputs_inputs.extend(fmmu(logical + 4, 2, 0x1180, 1));
        for (register, value) in [
            (0x0800, sm(0x1000, 128, 0x26, 1)),
            (0x0808, sm(0x1080, 128, 0x22, 1)),
            (0x0120, vec![2, 0]),
            (0x0810, sm(0x1100, 4, 0x64, 1)),
            (0x0818, sm(0x1180, 2, 0x20, 1)),
            (0x0600, outputs_inputs),
            (0x0120, vec![4, 0]),
            (0x0120, vec![8, 0]),
        ] {
            assert_eq!(
                send(&mut segment, Command::Fpwr, (station, register), &value).1,
                1
            );
        }
        let device = segment.device_mut(usize::from(k)).expect("a SubDevice");
        device.app_mut().inputs = [0xA0 + k as u8, 0xB0 + k as u8];
        device.app_mut().inputs_asked = 0;
    }
    assert!(segment.devices().iter().all(|d| d.state() == AlState::Op));
    segment
}

/// How many times each SubDevice was asked for its inputs.
fn asked(segment: &Segment<TestApp>) -> Vec<usize> {
    segment
        .devices()
        .iter()
        .map(|d| d.app().inputs_asked)
        .collect()
}

/// What each SubDevice's application has of its outputs.
fn outputs(segment: &Segment<TestApp>) -> Vec<Vec<u8>> {
    segment
        .devices()
        .iter()
        .map(|d| d.app().outputs.clone())
        .collect()
}

#[test]
fn a_subdevice_prepares_its_inputs_only_for_a_frame_that_reads_them() {
    let mut segment = in_op();
    // An LRW of the second one's images: it alone counts (3), is asked for its inputs and
    // takes its outputs.
    assert_eq!(
        send(&mut segment, Command::Lrw, (6, 0), &[1, 2, 3, 4, 9, 9]),
        (vec![1, 2, 3, 4, 0xA1, 0xB1], 3, 6)
    );
    assert_eq!(asked(&segment), [0, 1, 0]);
    assert_eq!(outputs(&segment), [vec![], vec![1, 2, 3, 4], vec![]]);
    // An LWR of every image: each counts once and takes its outputs; nobody's inputs are read.
    let written: Vec<u8> = (1..=18).collect();
    assert_eq!(
        send(&mut segment, Command::Lwr, (0, 0), &written),
        (written.clone(), 3, 0)
    );
    assert_eq!(asked(&segment), [0, 1, 0]);
    assert_eq!(
        outputs(&segment),
        [[1, 2, 3, 4], [7, 8, 9, 10], [13, 14, 15, 16]]
    );
    // An LRD of the third one's outputs (a write FMMU only): nothing counts or changes.
    assert_eq!(
        send(&mut segment, Command::Lrd, (12, 0), &[0xEE; 4]),
        (vec![0xEE; 4], 0, 12)
    );
    assert_eq!(asked(&segment), [0, 1, 0]);
    // Registers and memory outside the inputs: nobody is asked.
    assert_eq!(
        send(&mut segment, Command::Brd, (0, 0x0130), &[0, 0]),
        (vec![8, 0], 3, 3)
    );
    assert_eq!(
        send(&mut segment, Command::Fprd, (0x1002, 0x1100), &[0; 4]),
        (vec![7, 8, 9, 10], 1, 0x1002)
    );
    assert_eq!(asked(&segment), [0, 1, 0]);
    // A physical read of the inputs reaches the addressed one's, fresh.
    segment.device_mut(2).expect("position 2").app_mut().inputs = [0xC2, 0xD2];
    assert_eq!(
        send(&mut segment, Command::Fprd, (0x1003, 0x1180), &[0, 0]),
        (vec![0xC2, 0xD2], 1, 0x1003)
    );
    assert_eq!(asked(&segment), [0, 1, 1]);
    // An LRD of every image: each one's inputs, asked once; the outputs' bytes as they came.
    segment.device_mut(0).expect("position 0").app_mut().inputs = [0xC0, 0xD0];
    let (data, wkc, _) = send(&mut segment, Command::Lrd, (0, 0), &[0; 18]);
    assert_eq!(
        data,
        [0, 0, 0, 0, 0xC0, 0xD0, 0, 0, 0, 0, 0xA1, 0xB1, 0, 0, 0, 0, 0xC2, 0xD2]
    );
    assert_eq!(wkc, 3);
    assert_eq!(asked(&segment), [1, 2, 2]);
    // Two datagrams of one frame reading the inputs: asked once per frame.
    let answers = send_frame(
        &mut segment,
        &[
            (Command::Lrd, (4, 0), &[0, 0]),
            (Command::Lrw, (0, 0), &[0; 6]),
        ],
    );
    assert_eq!(answers[0], (vec![0xC0, 0xD0], 1, 4));
    assert_eq!(answers[1], (vec![0, 0, 0, 0, 0xC0, 0xD0], 3, 0));
    assert_eq!(asked(&segment), [2, 2, 2]);
}

#[test]
fn inputs_mapped_earlier_in_the_frame_are_prepared_before_they_are_read() {
    let mut segment = in_op();
    segment.device_mut(1).expect("position 1").app_mut().inputs = [0x5A, 0xA5];
    // FMMU 2 of the second one maps logical 0x100 onto its inputs; the LRD after it in the
    // same frame reads them as they are now.
    let answers = send_frame(
        &mut segment,
        &[
            (Command::Fpwr, (0x1002, 0x0620), &fmmu(0x100, 2, 0x1180, 1)),
            (Command::Lrd, (0x100, 0), &[0, 0]),
        ],
    );
    assert_eq!(answers[0].1, 1);
    assert_eq!(answers[1], (vec![0x5A, 0xA5], 1, 0x100));
    assert_eq!(asked(&segment), [0, 1, 0]);
}

#[test]
fn the_dl_status_shows_port_1_open_up_to_the_last() {
    let segment = three();
    let ports: Vec<u16> = segment
        .devices()
        .iter()
        .map(|d| d.esc().u16(0x0110))
        .collect();
    assert_eq!(ports, [0x5A31, 0x5A31, 0x5611]);
}

#[test]
fn a_frame_that_is_not_ethercat_or_an_empty_segment_is_not_answered() {
    let mut segment = three();
    let mut ip = vec![0u8; 60];
    ip[12] = 0x08;
    assert!(!segment.process_frame(Instant(0), &mut ip));
    assert_eq!(ip[6], 0, "left as it came");
    let mut empty = Segment::<TestApp>::new(Vec::new());
    let mut frame = FrameBuilder::new(MAC)
        .datagram(Command::Brd, 1, (0, 0), &[0], 0)
        .build();
    assert!(!empty.process_frame(Instant(0), &mut frame));
    assert!(empty.is_empty());
    assert_eq!(segment.len(), 3);
}
