//! Fuzz target: arbitrary frames, time steps and application calls fed to a device node.
//!
//! The first input byte picks the node's OD: the hand-written test OD, or the value image
//! generated from `eds/cp301.eds` (LowLimit/HighLimit entries, strings) or `eds/goodrive350.eds`
//! (by fuzz/build.rs), or the codegen tests' `gd350` (writable strings, staged by SDO
//! downloads). Properties: nothing panics, and the OD changes only through legal writes:
//! every write the node makes hits an entry an SDO client or an RPDO may write (or 1001h/1003h,
//! which the node owns), has the entry's size (at most its capacity for a string or domain), and
//! a PDO mapping entry changes only while its PDO is invalid and its sub-index 0 is zero (the
//! CiA 301 procedure). And downloads apply all or nothing: the streaming steps other than a
//! successful commit (begin, write, abort, a refused commit) change no value, and after each
//! operation every entry whose value changed is accounted for by an event of that operation (a
//! `Written` event of its index, an RPDO's, an NMT reset) or is one the node owns (1001h,
//! 1003h): no broken download leaves a trace.
#![no_main]

use edsgen_runtime::node::{Event, Node, NodeHooks, ResetKind};
use edsgen_runtime::od::{EntryDescriptor, ObjectDictionary, SdoAbort};
use edsgen_runtime::{CanFrame, Instant};
use libfuzzer_sys::fuzz_target;

#[path = "../../runtime/tests/node_support/node_od.rs"]
mod node_od;

edsgen_runtime::include_device!("cp301");
edsgen_runtime::include_device!("goodrive350");

/// The codegen tests' generated `gd350`: a generated `Od` with writable strings.
#[allow(dead_code)]
mod fixture {
    include!("../../codegen/tests/generated/gd350.rs");
}

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
                for (position, entry) in edsgen_runtime::od::descriptors(&*self).collect::<Vec<_>>() {
                    if range.contains(&entry.index()) {
                        let len = defaults.read_at(position, 0, &mut buf).expect("entry exists");
                        assert!(len < buf.len(), "a default longer than the buffer");
                        self.write_at(position, &buf[..len]).expect("defaults are legal");
                    }
                }
            }
        }
    )*};
}
resettable_generated!(cp301::Od, goodrive350::Od, fixture::gd350::Od);

/// The node-ID of every node here.
const NODE_ID: u8 = 3;

/// An OD with every write checked against the properties above.
struct Watched<O>(O);

impl<O: ObjectDictionary> Watched<O> {
    /// The value of the entry at `position`.
    fn value_at(&self, position: usize) -> Vec<u8> {
        let mut buf = [0u8; 512];
        let len = self.0.read_at(position, 0, &mut buf).unwrap_or(0);
        buf[..len].to_vec()
    }

    /// Every entry's value.
    fn values(&self) -> Vec<Vec<u8>> {
        (0..self.0.entry_count())
            .map(|p| self.value_at(p))
            .collect()
    }

    /// Runs a streaming step that must leave the value of the entry at `position` as it was.
    fn unchanged<T>(&mut self, position: usize, step: &str, f: impl FnOnce(&mut O) -> T) -> T {
        let before = self.values();
        let result = f(&mut self.0);
        assert!(
            self.values() == before,
            "{step} at position {position} changed the OD"
        );
        result
    }

    fn u32_at(&self, index: u16, sub: u8) -> u32 {
        let mut bytes = [0u8; 4];
        self.0
            .read(index, sub, 0, &mut bytes)
            .expect("entry exists");
        u32::from_le_bytes(bytes)
    }
}

impl<O: ObjectDictionary> ObjectDictionary for Watched<O> {
    fn entry_count(&self) -> usize {
        self.0.entry_count()
    }

    fn entry(&self, position: usize) -> Option<EntryDescriptor> {
        self.0.entry(position)
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
    fn begin_write(&mut self, position: usize) -> Result<(), SdoAbort> {
        self.unchanged(position, "begin_write", |od| od.begin_write(position))
    }
    fn write_part(&mut self, position: usize, offset: usize, data: &[u8]) -> Result<(), SdoAbort> {
        self.unchanged(position, "write_part", |od| {
            od.write_part(position, offset, data)
        })
    }
    fn commit_write(&mut self, position: usize, len: usize) -> Result<(), SdoAbort> {
        let before = self.values();
        let result = self.0.commit_write(position, len);
        let after = self.values();
        if result.is_err() {
            assert!(
                after == before,
                "a refused commit at {position} changed the OD"
            );
        } else {
            let entry = self.0.entry(position).expect("entry exists");
            assert!(
                entry.access().writable(),
                "commit to non-writable {position}"
            );
            assert_eq!(after[position].len(), len, "commit length at {position}");
            let others = (0..after.len()).filter(|&p| p != position);
            assert!(
                others.into_iter().all(|p| after[p] == before[p]),
                "a commit at {position} changed another entry"
            );
        }
        result
    }
    fn abort_write(&mut self, position: usize) {
        self.unchanged(position, "abort_write", |od| od.abort_write(position))
    }
    fn write(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<(), SdoAbort> {
        let position = self.0.locate(index, sub)?;
        let descriptor = self.0.find(index, sub)?;
        let capacity = self.0.capacity(position);
        // The state the write meets, judged only if the write changes the OD.
        let mapping = (0x1600..=0x17FF).contains(&index) || (0x1A00..=0x1BFF).contains(&index);
        let pdo_valid = mapping && self.u32_at(index - 0x200, 1) & 0x8000_0000 == 0;
        let mapping_enabled = mapping && self.u32_at(index, 0) != 0;
        let result = self.0.write(index, sub, data);
        if result.is_ok() {
            let node_owned = index == 0x1001 || index == 0x1003;
            assert!(
                descriptor.access().writable() || node_owned,
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
            match descriptor.data_type().fixed_size() {
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
    match choice % 4 {
        0 => run(TestOd::new(NODE_ID), input),
        1 => run(cp301::Od::new(NODE_ID), input),
        2 => run(goodrive350::Od::new(NODE_ID), input),
        _ => run(fixture::gd350::Od::new(NODE_ID), input),
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
        let before = node.od().values();
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
            // Drain what the node has to send.
            _ => {
                let mut sent = 0;
                while let Some(frame) = node.poll_transmit(now) {
                    assert!(frame.dlc() <= 8);
                    sent += 1;
                    assert!(sent < 64, "poll_transmit never runs dry");
                }
            }
        }
        accounted(&mut node, &before);
    }
}

/// Takes the node's events and checks that every entry whose value differs from `before` is
/// accounted for by one of them, or is one the node writes itself.
fn accounted<O: Resettable>(node: &mut Node<Watched<O>, Hooks>, before: &[Vec<u8>]) {
    let (mut written, mut rpdo, mut reset) = (Vec::new(), false, false);
    while let Some(event) = node.poll_event() {
        match event {
            Event::Written { index, .. } => written.push(index),
            Event::RpdoReceived { .. } => rpdo = true,
            Event::Reset(_) => reset = true,
            _ => {}
        }
    }
    // A reset restores defaults and an RPDO writes whatever its mapping names: the write
    // checks above judge those.
    if reset || rpdo || node.events_lost() > 0 {
        return;
    }
    let after = node.od().values();
    for (position, entry) in edsgen_runtime::od::descriptors(node.od()) {
        if after[position] == before[position] {
            continue;
        }
        // Save (1010h) and restore (1011h) act through the hooks, not the OD; 1001h and 1003h
        // the node keeps; an SDO write to a communication object may change others of its index.
        let explained =
            written.contains(&entry.index()) || matches!(entry.index(), 0x1001 | 0x1003);
        assert!(
            explained,
            "{:04X}:{} changed without an event that accounts for it",
            entry.index(),
            entry.sub()
        );
    }
}
