//! Frames through a segment of three SubDevices: the ADP each command brings back, the working
//! counters every addressed SubDevice adds, and the data each one reads or writes on the way.

use edsgen_runtime::Instant;

use super::frame::{parse, wkc, Command, FrameBuilder, Parsed};
use super::segment::Segment;
use super::tests::{fmmu, sii, TestApp};
use super::SubDevice;

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
