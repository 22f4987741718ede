//! Shared by the simulated-drive tests (`tests/drive_*.rs`): a drive on the in-memory bus with the
//! bus's clock, and frames written and shown as the manuals print them (`183: 01 00 00 00`).
// Each drive test is a crate of its own and uses only some of these helpers.
#![allow(dead_code)]

use edsgen_host::vbus::{BusDevice, VirtualBus};
use edsgen_runtime::{CanFrame, Instant};

/// The instant `millis` ms after the bus started.
pub fn ms(millis: u64) -> Instant {
    Instant::from_millis(millis)
}

/// A frame as the manuals print it: `183: 01 00 00 00 01 00 00 00`.
pub fn show(frame: &CanFrame) -> String {
    let bytes: Vec<String> = frame.data().iter().map(|b| format!("{b:02X}")).collect();
    format!("{:03X}: {}", frame.std_id().unwrap_or(0), bytes.join(" "))
}

/// A frame from the manuals' notation.
pub fn frame(text: &str) -> CanFrame {
    let (id, bytes) = text.split_once(": ").expect("ID: bytes");
    let id = u16::from_str_radix(id, 16).expect("hex ID");
    let data: Vec<u8> = bytes
        .split(' ')
        .map(|b| u8::from_str_radix(b, 16).expect("hex byte"))
        .collect();
    CanFrame::new(id, &data).expect("a valid frame")
}

/// (ms, frame) pairs from the manuals' notation, to compare with [`Bench::run`].
pub fn timed(list: &[(u64, &str)]) -> Vec<(u64, String)> {
    list.iter().map(|(t, s)| (*t, s.to_string())).collect()
}

/// A simulated drive alone on the in-memory bus with a test master that injects frames.
pub struct Bench<D> {
    /// The drive.
    pub drive: D,
    /// The bus, whose clock the drive runs on.
    pub bus: VirtualBus,
}

impl<D: BusDevice> Bench<D> {
    /// The drive powered up at 0, its boot-up sent and forgotten.
    pub fn booted(drive: D) -> Self {
        let mut bench = Bench {
            drive,
            bus: VirtualBus::new(ms(0)),
        };
        bench.run(0);
        bench
    }

    /// Runs the bus to `until` ms; what the drive sent since the last look, as (ms, frame).
    pub fn run(&mut self, until: u64) -> Vec<(u64, String)> {
        self.bus.run_until(ms(until), &mut [&mut self.drive]);
        self.bus
            .take_log()
            .into_iter()
            .filter(|(_, sender, _)| *sender == 0)
            .map(|(at, _, f)| (at.as_micros() / 1000, show(&f)))
            .collect()
    }

    /// [`run`](Self::run), the frames only.
    pub fn frames_until(&mut self, until: u64) -> Vec<String> {
        self.run(until).into_iter().map(|(_, f)| f).collect()
    }

    /// Injects `frame` at `at` ms (what the drive sent before is forgotten); what the drive sent
    /// in answer at that instant.
    pub fn inject(&mut self, at: u64, frame: CanFrame) -> Vec<String> {
        self.run(at);
        self.bus.inject(frame, &mut [&mut self.drive]);
        self.frames_until(at)
    }

    /// [`inject`](Self::inject) of `data` on `id`.
    pub fn send(&mut self, at: u64, id: u16, data: &[u8]) -> Vec<String> {
        self.inject(at, CanFrame::new(id, data).expect("a valid frame"))
    }

    /// Injects a frame in the manuals' notation at `at` ms and runs to `until`; what the drive
    /// sent, as (ms, frame).
    pub fn exchange(&mut self, at: u64, request: &str, until: u64) -> Vec<(u64, String)> {
        let answer = self.inject(at, frame(request));
        let mut sent: Vec<(u64, String)> = answer.into_iter().map(|f| (at, f)).collect();
        sent.extend(self.run(until));
        sent
    }

    /// An SDO request to `node` at `at` ms; the response's bytes.
    pub fn sdo(&mut self, at: u64, node: u8, request: [u8; 8]) -> [u8; 8] {
        let response = format!("{:03X}: ", 0x580 + u16::from(node));
        let sent = self.send(at, 0x600 + u16::from(node), &request);
        let answer = sent
            .iter()
            .find(|f| f.starts_with(&response))
            .expect("an SDO response");
        frame(answer).data().try_into().expect("8 bytes")
    }
}
