//! The Goodrive350 card's communication-loss actions: the class-1 connection writing the drive's
//! image times out and the drive trips with E-EIP, coasts to a stop, shows it to explicit reads,
//! and stays faulted for the next connection until a fault reset; Forward_Close ends it and the
//! drive decelerates to a stop, the next connection starting it from rest.

use edsgen_runtime::enip::wire::connection_manager::{
    network_params, ForwardCloseRepr, ForwardOpenReply, ForwardOpenRepr, Triad, DEFAULT_TICKS,
};
use edsgen_runtime::enip::wire::io::IoDatagram;
use edsgen_runtime::enip::wire::Emit;
use edsgen_runtime::Instant;

use super::device;
use super::driver::{link, Card};
use super::tests_scanner::{send, session};
use super::Adapter;
use crate::drives::pkw_pzd::Bus;

const PATH: [u8; 8] = [0x20, 0x04, 0x24, 0x01, 0x2C, 0x96, 0x2C, 0x64];

const TRIAD: Triad = Triad {
    serial: 9,
    vendor: 0xEDE5,
    originator_serial: 0x0A0B_0C0D,
};

fn at(ms: u64) -> Instant {
    Instant::from_micros(ms * 1000)
}

/// Opens the card's connection (32 bytes each way, RPI 50 ms, timeout 4 x 50 ms, multiplier 0); its O→T ID.
fn open(a: &mut Adapter, s: u32) -> u32 {
    let request = ForwardOpenRepr {
        large: false,
        ticks: DEFAULT_TICKS,
        o_t_id: 0,
        t_o_id: 0x2000_0009,
        triad: TRIAD,
        multiplier: 0,
        o_t_rpi: 50_000,
        o_t_params: network_params(false, 2, 2, false, 38),
        t_o_rpi: 50_000,
        t_o_params: network_params(false, 2, 2, false, 34),
        transport: 0x01,
        path: &PATH,
    }
    .to_vec()
    .expect("fits");
    let reply = send(a, s, &request, &[]);
    assert_eq!(&reply[..4], &[0xD4, 0, 0, 0]);
    ForwardOpenReply::parse(&reply[4..]).expect("reply").o_t_id
}

/// The scanner's image with control word `cw` (word 4, little-endian) and 50.00 Hz, sequence
/// `n`, run.
fn write(a: &mut Adapter, card: &mut Card, id: u32, n: u16, cw: u16, now: Instant) {
    let mut data = n.to_le_bytes().to_vec();
    data.extend_from_slice(&1u32.to_le_bytes());
    let mut image = [0u8; 32];
    image[8..10].copy_from_slice(&cw.to_le_bytes());
    // PZD2, the set frequency: 50.00 Hz.
    image[10..12].copy_from_slice(&5000u16.to_le_bytes());
    data.extend_from_slice(&image);
    let datagram = IoDatagram {
        connection: id,
        sequence: u32::from(n),
        data: &data,
    };
    a.receive_io(9, &datagram.to_vec().expect("fits"), now);
    link(a, Some(card), now, &mut |_| {});
}

/// The state byte of the SW (word 4 of the T→O image): 1 forward, 3 stopped, 4 fault.
fn state(a: &Adapter) -> u8 {
    a.device.assemblies[&100].data[8]
}

/// A drive set to take its frequency from PZD2, connected, run forward for 2 s; the session
/// and the connection's O→T ID.
fn running(a: &mut Adapter, card: &mut Card) -> (u32, u32) {
    // Received PZD2 is the set frequency (function 1).
    let pzd2 = Bus::EthernetIp.received_pzd2();
    assert_eq!(card.drive.set_parameter(pzd2, 1), Ok(()));
    let s = session(a);
    let id = open(a, s);
    for n in 1..=40u16 {
        write(a, card, id, n, 1, at(50 * u64::from(n)));
    }
    assert_eq!(state(a), 1);
    assert!(card.drive.vfd().output_frequency() > 0);
    (s, id)
}

#[test]
fn forward_close_decelerates_the_drive_to_a_stop() {
    let (mut a, mut card) = device::goodrive350([127, 0, 0, 1], at(0));
    let (s, id) = running(&mut a, &mut card);
    let close = ForwardCloseRepr {
        ticks: DEFAULT_TICKS,
        triad: TRIAD,
        path: &PATH,
    }
    .to_vec()
    .expect("fits");
    assert_eq!(&send(&mut a, s, &close, &[])[..4], &[0xCE, 0, 0, 0]);
    let mut log = Vec::new();
    link(&mut a, Some(&mut card), at(2010), &mut |l| log.push(l));
    assert_eq!(
        log,
        [
            format!("connection {id:#010x} closed"),
            "drive decelerates to stop".to_owned()
        ]
    );
    // Without a connection the ramp goes on: explicit reads see the frequency fall to 0 and
    // the SW's state become 3, stopped (no fault).
    let at_close = card.drive.vfd().output_frequency();
    link(&mut a, Some(&mut card), at(3000), &mut |_| {});
    let later = card.drive.vfd().output_frequency();
    assert!(later < at_close, "{later} < {at_close}");
    link(&mut a, Some(&mut card), at(30_000), &mut |_| {});
    assert_eq!((state(&a), card.drive.vfd().output_frequency()), (3, 0));
    assert_eq!(card.drive.vfd().fault(), None);
    // The next connection's run command starts from rest.
    let id = open(&mut a, s);
    write(&mut a, &mut card, id, 1, 1, at(30_050));
    write(&mut a, &mut card, id, 2, 1, at(30_100));
    assert_eq!(state(&a), 1);
    assert!(card.drive.vfd().output_frequency() < at_close);
}

#[test]
fn a_timeout_trips_e_eip_and_the_next_connection_starts_faulted() {
    let (mut a, mut card) = device::goodrive350([127, 0, 0, 1], at(0));
    let (s, id) = running(&mut a, &mut card);
    // Nothing for the timeout (4 x 50 ms): closed, E-EIP; later ticks log nothing more.
    let mut log = Vec::new();
    for ms in [2100, 2200, 2300, 2400] {
        a.handle_timeout(at(ms));
        link(&mut a, Some(&mut card), at(ms), &mut |l| log.push(l));
    }
    assert_eq!(
        log,
        [
            format!("connection {id:#010x} timed out"),
            "drive fault E-EIP".to_owned()
        ]
    );
    // Explicit reads see the fault (SW state 4), the output coasted to 0; P07.27 = 70.
    assert_eq!((state(&a), card.drive.vfd().output_frequency()), (4, 0));
    assert_eq!(card.drive.parameter(0x071B), Some(70));
    // The next connection asks to run: still faulted, not at speed.
    let id = open(&mut a, s);
    for n in 1..=10u16 {
        write(&mut a, &mut card, id, n, 1, at(3000 + 50 * u64::from(n)));
    }
    assert_eq!((state(&a), card.drive.vfd().output_frequency()), (4, 0));
    // A fault reset (command 7), then run: it runs again.
    write(&mut a, &mut card, id, 11, 7, at(3600));
    write(&mut a, &mut card, id, 12, 1, at(3650));
    write(&mut a, &mut card, id, 13, 1, at(3900));
    assert_eq!(state(&a), 1);
}
