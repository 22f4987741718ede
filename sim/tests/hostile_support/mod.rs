//! Hostile EtherCAT frames for the simulator's tests (in process, `sim/tests/ethercat_hostile.rs`,
//! and over a veth pair, `tests/ethercat_wire.rs`): a master's start-up of the EC-TX508 recorded
//! frame by frame ([`StartUp`]), and frames mutated from it with a deterministic seed
//! ([`mutate`]).
#![allow(dead_code)]

use edsgen_runtime::Instant;
use edsgen_sim::ethercat::frame::{parse, wkc, Command, FrameBuilder, Parsed};
use edsgen_sim::ethercat::{EsiDevice, SubDevice};

const STATION: u16 = 0x1001;

/// A master's start-up, frame by frame, recorded.
pub struct StartUp<'a> {
    pub device: &'a mut SubDevice<EsiDevice>,
    pub now: &'a mut u64,
    pub frames: Vec<Vec<u8>>,
}

impl StartUp<'_> {
    fn send(&mut self, command: Command, address: (u16, u16), data: &[u8]) -> (Vec<u8>, u16) {
        *self.now += 1_000;
        let frame = FrameBuilder::new([0x10; 6])
            .datagram(command, 1, address, data, 0)
            .build();
        self.frames.push(frame.clone());
        let mut frame = frame;
        assert!(self.device.process_frame(Instant(*self.now), &mut frame));
        let Parsed::Datagrams { datagrams, .. } = parse(&frame) else {
            panic!("not EtherCAT on the way back");
        };
        (
            frame[datagrams[0].data.clone()].to_vec(),
            wkc(&frame, &datagrams[0]),
        )
    }

    fn fpwr(&mut self, ado: u16, data: &[u8]) -> u16 {
        self.send(Command::Fpwr, (STATION, ado), data).1
    }

    fn al(&mut self) -> (u16, u16) {
        let (d, _) = self.send(Command::Fprd, (STATION, 0x0130), &[0; 6]);
        (
            u16::from_le_bytes([d[0], d[1]]),
            u16::from_le_bytes([d[4], d[5]]),
        )
    }

    /// The whole start-up to Op; panics with the step that failed.
    pub fn run(&mut self) {
        self.send(Command::Bwr, (0, 0x0120), &[0x11, 0]);
        self.send(Command::Bwr, (0, 0x0200), &[0; 4]);
        self.send(Command::Bwr, (0, 0x0400), &[0; 0x44]);
        self.send(Command::Bwr, (0, 0x0600), &[0; 256]);
        self.send(Command::Bwr, (0, 0x0800), &[0; 64]);
        self.send(Command::Bwr, (0, 0x0500), &[0]);
        assert_eq!(
            self.send(Command::Apwr, (0, 0x0010), &STATION.to_le_bytes())
                .1,
            1,
            "station address"
        );
        // The SII's vendor ID (word 8) through the EEPROM interface.
        self.send(Command::Fpwr, (STATION, 0x0502), &[0, 1, 8, 0, 0, 0]);
        let (sii, _) = self.send(Command::Fprd, (STATION, 0x0508), &[0; 4]);
        assert_eq!(sii, [0xD8, 0x04, 0, 0], "the SII's vendor ID");
        self.fpwr(0x0800, &sm(0x1000, 512, 0x26));
        self.fpwr(0x0808, &sm(0x1400, 512, 0x22));
        self.fpwr(0x0500, &[1]);
        self.fpwr(0x0120, &[0x12, 0]);
        assert_eq!(self.al(), (2, 0), "Pre-Op");
        // 1018h:01 by an expedited upload.
        let mut message = vec![10, 0, 0, 0, 0, 0x13, 0x00, 0x20, 0x40, 0x18, 0x10, 1];
        message.resize(512, 0);
        assert_eq!(
            self.fpwr(0x1000, &message),
            1,
            "the mailbox takes the request"
        );
        let (answer, wkc) = self.send(Command::Fprd, (STATION, 0x1400), &[0; 512]);
        assert_eq!(wkc, 1, "the answer waits");
        assert_eq!(answer[8..16], [0x43, 0x18, 0x10, 1, 0xD8, 0x04, 0, 0]);
        self.fpwr(0x0810, &sm(0x1800, 21, 0x64));
        self.fpwr(0x0818, &sm(0x1C00, 23, 0x20));
        self.fpwr(0x0600, &fmmu(0, 21, 0x1800, 2));
        self.fpwr(0x0610, &fmmu(21, 23, 0x1C00, 1));
        self.fpwr(0x0120, &[4, 0]);
        assert_eq!(self.al(), (4, 0), "Safe-Op");
        self.send(Command::Lrw, (0, 0), &[0; 44]);
        self.fpwr(0x0120, &[8, 0]);
        assert_eq!(self.al(), (8, 0), "Op");
        assert_eq!(self.send(Command::Lrw, (0, 0), &[0; 44]).1, 3, "LRW");
    }
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

/// xorshift64*: the same frames for the same seed.
pub struct Rng(pub u64);

impl Rng {
    pub fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// A frame from `good` changed: bytes flipped after the Ethernet header, cut short, or all
/// random after it.
pub fn mutate(rng: &mut Rng, good: &[Vec<u8>]) -> Vec<u8> {
    let mut frame = good[rng.below(good.len())].clone();
    match rng.below(4) {
        0 => {
            let len = 14 + rng.below(frame.len() - 13);
            frame.truncate(len);
        }
        1 => {
            for b in &mut frame[14..] {
                *b = rng.next() as u8;
            }
        }
        _ => {
            for _ in 0..1 + rng.below(4) {
                let at = 14 + rng.below(frame.len() - 14);
                frame[at] = rng.next() as u8;
            }
        }
    }
    frame
}

/// The frames of a good start-up, recorded against `device` (an EC-TX508) in process.
pub fn recorded_start_up(mut device: SubDevice<EsiDevice>) -> Vec<Vec<u8>> {
    let mut now = 0;
    let mut start_up = StartUp {
        device: &mut device,
        now: &mut now,
        frames: Vec::new(),
    };
    start_up.run();
    start_up.frames
}
