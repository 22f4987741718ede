//! Shared helpers of the node tests: the test OD, frame construction and a readable bus log.
#![allow(dead_code)]

pub mod node_od;

use edsgen_runtime::vbus::VirtualBus;
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

/// `(ms, text)` pairs, for writing expectations.
pub fn at_ms(list: &[(u64, &str)]) -> Vec<(u64, String)> {
    list.iter()
        .map(|(t, s)| (t * 1000, s.to_string()))
        .collect()
}
