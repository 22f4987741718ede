//! Shared helpers of the node tests (node_*.rs): the test OD, frame construction and a readable bus log.
#![allow(dead_code)]

pub mod node_od;

use edsgen_host::vbus::VirtualBus;
use edsgen_runtime::{CanFrame, Instant};

/// A data frame.
pub fn frame(id: u16, data: &[u8]) -> CanFrame {
    CanFrame::new(id, data).unwrap()
}

/// Milliseconds as an instant.
pub fn ms(millis: u64) -> Instant {
    Instant::from_millis(millis)
}

/// A frame as the manuals print it: `703: 85`, `583: 60 01 18 03 00 00 00 00`, `703: RTR`.
pub fn show(frame: &CanFrame) -> String {
    let id = frame.std_id().unwrap();
    if frame.is_remote() {
        return format!("{id:03X}: RTR");
    }
    let bytes: Vec<String> = frame.data().iter().map(|b| format!("{b:02X}")).collect();
    if bytes.is_empty() {
        format!("{id:03X}:")
    } else {
        format!("{id:03X}: {}", bytes.join(" "))
    }
}

/// The bus log since the last call, as (microseconds, frame text), without injected frames.
pub fn sent(bus: &mut VirtualBus) -> Vec<(u64, String)> {
    bus.take_log()
        .into_iter()
        .filter(|(_, sender, _)| *sender != usize::MAX)
        .map(|(at, _, f)| (at.as_micros(), show(&f)))
        .collect()
}

/// What the device at `sender` (its place in `run_until`'s list) sent since the last call, as
/// (microseconds, frame text).
pub fn sent_by(bus: &mut VirtualBus, sender: usize) -> Vec<(u64, String)> {
    bus.take_log()
        .into_iter()
        .filter(|(_, from, _)| *from == sender)
        .map(|(at, _, f)| (at.as_micros(), show(&f)))
        .collect()
}

/// `(ms, text)` pairs, for writing expectations.
pub fn at_ms(list: &[(u64, &str)]) -> Vec<(u64, String)> {
    list.iter()
        .map(|(t, s)| (t * 1000, s.to_string()))
        .collect()
}

/// An expedited SDO download request to node 3 with a value of `len` bytes.
pub fn sdo_write(index: u16, sub: u8, value: u32, len: usize) -> CanFrame {
    let command = match len {
        1 => 0x2F,
        2 => 0x2B,
        3 => 0x27,
        _ => 0x23,
    };
    let i = index.to_le_bytes();
    let v = value.to_le_bytes();
    frame(0x603, &[command, i[0], i[1], sub, v[0], v[1], v[2], v[3]])
}

/// An SDO upload request to node 3.
pub fn sdo_read(index: u16, sub: u8) -> CanFrame {
    let i = index.to_le_bytes();
    frame(0x603, &[0x40, i[0], i[1], sub, 0, 0, 0, 0])
}

/// The server's answer to a download, as text.
pub fn sdo_ok(index: u16, sub: u8) -> String {
    let i = index.to_le_bytes();
    format!("583: 60 {:02X} {:02X} {sub:02X} 00 00 00 00", i[0], i[1])
}

/// The server's abort, as text.
pub fn sdo_abort(index: u16, sub: u8, code: u32) -> String {
    let i = index.to_le_bytes();
    let c = code.to_le_bytes();
    format!(
        "583: 80 {:02X} {:02X} {sub:02X} {:02X} {:02X} {:02X} {:02X}",
        i[0], i[1], c[0], c[1], c[2], c[3]
    )
}
