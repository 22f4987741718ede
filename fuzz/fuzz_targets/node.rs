//! Fuzz target: arbitrary frames, time steps and application calls fed to a device node.
//!
//! The first input byte picks the node's OD: the hand-written test OD, or the value image
//! generated from `eds/cp301.eds` (LowLimit/HighLimit entries, strings) or `eds/goodrive350.eds`
//! (by fuzz/build.rs). Properties: nothing panics, and the OD changes only through legal writes:
//! every write the node makes hits an entry an SDO client or an RPDO may write (or 1001h/1003h,
//! which the node owns), has the entry's size (at most its capacity for a string or domain), and
//! a PDO mapping entry changes only while its PDO is invalid and its sub-index 0 is zero (the
//! CiA 301 procedure).
#![no_main]

use edsgen_runtime::node::{Node, NodeHooks, ResetKind};
use edsgen_runtime::od::{EntryDescriptor, ObjectDictionary, SdoAbort};
use edsgen_runtime::{CanFrame, Instant};
use libfuzzer_sys::fuzz_target;

#[path = "../../runtime/tests/node_support/node_od.rs"]
mod node_od;

edsgen_runtime::include_device!("cp301");
edsgen_runtime::include_device!("goodrive350");

use node_od::TestOd;

/// An OD that can go back to its defaults, as the reset hook needs.
trait Resettable: ObjectDictionary {
    /// Sets every entry in `range` back to its default.
    fn reset_range(&mut self, range: core::ops::RangeInclusive<u16>);
}

impl Resettable for TestOd {
    fn reset_range(&mut self, range: core::ops::RangeInclusive<u16>) {
        TestOd::reset_range(self, range);
    }
}

/// A generated OD: the defaults come from a fresh `Od::new`, entry by entry.
macro_rules! resettable_generated {
    ($($od:ty),*) => {$(
        impl Resettable for $od {
            fn reset_range(&mut self, range: core::ops::RangeInclusive<u16>) {
                let defaults = <$od>::new(NODE_ID);
                let mut buf = [0u8; 256];
                for position in 0..self.entries().len() {
                    let entry = self.entries()[position];
                    if range.contains(&entry.index) {
                        let len = defaults.read_at(position, 0, &mut buf).expect("entry exists");
                        assert!(len < buf.len(), "a default longer than the buffer");
                        self.write_at(position, &buf[..len]).expect("defaults are legal");
                    }
                }
            }
        }
    )*};
}
resettable_generated!(cp301::Od, goodrive350::Od);

/// The node-ID of every node here.
const NODE_ID: u8 = 3;

/// An OD with every write checked against the properties above.
struct Watched<O>(O);

impl<O: ObjectDictionary> Watched<O> {
    fn u32_at(&self, index: u16, sub: u8) -> u32 {
        let mut bytes = [0u8; 4];
        self.0
            .read(index, sub, 0, &mut bytes)
            .expect("entry exists");
        u32::from_le_bytes(bytes)
    }
}

impl<O: ObjectDictionary> ObjectDictionary for Watched<O> {
    fn entries(&self) -> &[EntryDescriptor] {
        self.0.entries()
    }
    fn locate(&self, index: u16, sub: u8) -> Result<usize, SdoAbort> {
        self.0.locate(index, sub)
    }
    fn capacity(&self, position: usize) -> Option<usize> {
        self.0.capacity(position)
    }
    fn value_len(&self, index: u16, sub: u8) -> Result<usize, SdoAbort> {
        self.0.value_len(index, sub)
    }
    fn read(&self, index: u16, sub: u8, offset: usize, buf: &mut [u8]) -> Result<usize, SdoAbort> {
        self.0.read(index, sub, offset, buf)
    }
    fn write(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<(), SdoAbort> {
        let position = self.0.locate(index, sub)?;
        let descriptor = *self.0.find(index, sub)?;
        let capacity = self.0.capacity(position);
        // The state the write meets, judged only if the write changes the OD.
        let mapping = (0x1600..=0x17FF).contains(&index) || (0x1A00..=0x1BFF).contains(&index);
        let pdo_valid = mapping && self.u32_at(index - 0x200, 1) & 0x8000_0000 == 0;
        let mapping_enabled = mapping && self.u32_at(index, 0) != 0;
        let result = self.0.write(index, sub, data);
        if result.is_ok() {
            let node_owned = index == 0x1001 || index == 0x1003;
            assert!(
                descriptor.access.writable() || node_owned,
                "write to non-writable {index:04X}:{sub}"
            );
            assert!(
                !pdo_valid,
                "mapping {index:04X}:{sub} written while the PDO is valid"
            );
            assert!(
                sub == 0 || !mapping_enabled,
                "mapping {index:04X}:{sub} written while enabled"
            );
            match descriptor.data_type.fixed_size() {
                Some(size) => assert_eq!(data.len(), size, "{index:04X}:{sub} size"),
                None => assert!(
                    capacity.is_some_and(|capacity| data.len() <= capacity),
                    "{index:04X}:{sub} over capacity"
                ),
            }
        }
        result
    }
}

struct Hooks;

impl<O: Resettable> NodeHooks<Watched<O>> for Hooks {
    fn reset(&mut self, kind: ResetKind, od: &mut Watched<O>) {
        match kind {
            ResetKind::Node => od.0.reset_range(0x0000..=0xFFFF),
            ResetKind::Communication => od.0.reset_range(0x1000..=0x1FFF),
        }
    }
    fn save(&mut self, _sub: u8, _od: &Watched<O>) -> Result<(), SdoAbort> {
        Ok(())
    }
    fn restore_defaults(&mut self, _sub: u8) -> Result<(), SdoAbort> {
        Ok(())
    }
}

fuzz_target!(|input: &[u8]| {
    let Some((&choice, input)) = input.split_first() else {
        return;
    };
    match choice % 3 {
        0 => run(TestOd::new(NODE_ID), input),
        1 => run(cp301::Od::new(NODE_ID), input),
        _ => run(goodrive350::Od::new(NODE_ID), input),
    }
});

/// Feeds the operations `input` encodes to a node serving `od`.
fn run<O: Resettable>(od: O, input: &[u8]) {
    let mut now = Instant::from_millis(0);
    let Ok(mut node) = Node::<Watched<O>, Hooks>::with_hooks(Watched(od), Hooks, NODE_ID, now)
    else {
        return;
    };
    let mut bytes = input.iter().copied();
    while let Some(op) = bytes.next() {
        match op % 8 {
            // A frame: 11-bit id, flags (bit 0 remote), length, data.
            0..=3 => {
                let id = u16::from_le_bytes([bytes.next().unwrap_or(0), bytes.next().unwrap_or(0)]);
                let flags = bytes.next().unwrap_or(0);
                let len = usize::from(flags >> 4).min(8);
                let data: Vec<u8> = bytes.by_ref().take(len).collect();
                let frame = if flags & 1 == 1 {
                    CanFrame::remote(id, len as u8)
                } else {
                    CanFrame::from_parts(
                        id,
                        {
                            let mut d = [0u8; 8];
                            d[..data.len()].copy_from_slice(&data);
                            d
                        },
                        data.len() as u8,
                    )
                };
                node.handle_frame(now, &frame);
            }
            // Time passes; timers run.
            4 => {
                let step = u64::from(bytes.next().unwrap_or(0)) * 997;
                now = now + edsgen_runtime::Duration::from_micros(step);
                if node.poll_timeout().is_some_and(|at| at <= now) {
                    node.handle_timeout(now);
                }
            }
            // The application raises or clears an error, or triggers a TPDO.
            5 => {
                let code =
                    u16::from_le_bytes([bytes.next().unwrap_or(0), bytes.next().unwrap_or(0)]);
                if code & 1 == 0 {
                    node.raise_error(code, (code >> 8) as u8, [1, 2, 3, 4, 5]);
                } else {
                    node.clear_error(code & !1);
                }
            }
            6 => {
                node.trigger_tpdo(usize::from(bytes.next().unwrap_or(0) % 6));
            }
            // Drain what the node has to say.
            _ => {
                let mut sent = 0;
                while let Some(frame) = node.poll_transmit(now) {
                    assert!(frame.dlc() <= 8);
                    sent += 1;
                    assert!(sent < 64, "poll_transmit never runs dry");
                }
                while node.poll_event().is_some() {}
            }
        }
    }
}
