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
use super::tests_scanner::{send, session};
use super::tests_support::events;
use super::{Adapter, EnipApplication};
use crate::drives::pkw_pzd::{Bus, PkwPzdDrive};

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
fn open<A: EnipApplication>(a: &mut Adapter<A>, s: u32) -> u32 {
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
fn write(a: &mut Adapter<PkwPzdDrive>, id: u32, n: u16, cw: u16, now: Instant) {
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
    a.io(9, &datagram.to_vec().expect("fits"), now);
    a.handle_timeout(now);
    events(a);
}

/// The state byte of the SW (word 4 of the T→O image): 1 forward, 3 stopped, 4 fault.
fn state(a: &Adapter<PkwPzdDrive>) -> u8 {
    a.device.assemblies[&100].data[8]
}

/// A drive set to take its frequency from PZD2, connected, run forward for 2 s; the session
/// and the connection's O→T ID.
fn running(a: &mut Adapter<PkwPzdDrive>) -> (u32, u32) {
    // Received PZD2 is the set frequency (function 1).
    let pzd2 = Bus::EthernetIp.received_pzd2();
    assert_eq!(a.app_mut().set_parameter(pzd2, 1), Ok(()));
    let s = session(a);
    let id = open(a, s);
    for n in 1..=40u16 {
        write(a, id, n, 1, at(50 * u64::from(n)));
    }
    assert_eq!(state(a), 1);
    assert!(a.app().vfd().output_frequency() > 0);
    (s, id)
}

/// The lines a driver logs for the events since the last call.
fn lines(a: &mut Adapter<PkwPzdDrive>) -> Vec<String> {
    events(a).iter().filter_map(|e| e.log_line()).collect()
}

#[test]
fn forward_close_decelerates_the_drive_to_a_stop() {
    let mut a = device::goodrive350([127, 0, 0, 1], at(0));
    let (s, id) = running(&mut a);
    let close = ForwardCloseRepr {
        ticks: DEFAULT_TICKS,
        triad: TRIAD,
        path: &PATH,
    }
    .to_vec()
    .expect("fits");
    assert_eq!(&send(&mut a, s, &close, &[])[..4], &[0xCE, 0, 0, 0]);
    a.handle_timeout(at(2010));
    assert_eq!(
        lines(&mut a),
        [
            format!("connection {id:#010x} closed"),
            "drive decelerates to stop".to_owned()
        ]
    );
    // Without a connection the ramp goes on: explicit reads see the frequency fall to 0 and
    // the SW's state become 3, stopped (no fault).
    let at_close = a.app().vfd().output_frequency();
    a.handle_timeout(at(3000));
    let later = a.app().vfd().output_frequency();
    assert!(later < at_close, "{later} < {at_close}");
    a.handle_timeout(at(30_000));
    assert_eq!((state(&a), a.app().vfd().output_frequency()), (3, 0));
    assert_eq!(a.app().vfd().fault(), None);
    // The next connection's run command starts from rest.
    let id = open(&mut a, s);
    write(&mut a, id, 1, 1, at(30_050));
    write(&mut a, id, 2, 1, at(30_100));
    assert_eq!(state(&a), 1);
    assert!(a.app().vfd().output_frequency() < at_close);
}

#[test]
fn a_timeout_trips_e_eip_and_the_next_connection_starts_faulted() {
    let mut a = device::goodrive350([127, 0, 0, 1], at(0));
    let (s, id) = running(&mut a);
    // Nothing for the timeout (4 x 50 ms): closed, E-EIP; later ticks log nothing more.
    let mut log = Vec::new();
    for ms in [2100, 2200, 2300, 2400] {
        a.handle_timeout(at(ms));
        log.extend(lines(&mut a));
    }
    assert_eq!(
        log,
        [
            format!("connection {id:#010x} timed out"),
            "drive fault E-EIP".to_owned()
        ]
    );
    // Explicit reads see the fault (SW state 4), the output coasted to 0; P07.27 = 70.
    assert_eq!((state(&a), a.app().vfd().output_frequency()), (4, 0));
    assert_eq!(a.app().parameter(0x071B), Some(70));
    // The next connection asks to run: still faulted, not at speed.
    let id = open(&mut a, s);
    for n in 1..=10u16 {
        write(&mut a, id, n, 1, at(3000 + 50 * u64::from(n)));
    }
    assert_eq!((state(&a), a.app().vfd().output_frequency()), (4, 0));
    // A fault reset (command 7), then run: it runs again.
    write(&mut a, id, 11, 7, at(3600));
    write(&mut a, id, 12, 1, at(3650));
    write(&mut a, id, 13, 1, at(3900));
    assert_eq!(state(&a), 1);
}
