//! A hand-written object dictionary for the node tests, the fuzz target and the benchmarks: the
//! CiA 301 communication objects of a device with 4 RPDOs and 4 TPDOs, a few application
//! entries, and a log of what was written.
#![allow(dead_code)]

use edsgen_runtime::node::{NodeHooks, ResetKind};
use edsgen_runtime::od::{
    Access, DataType, EntryDescriptor, EntryKind, ObjectDictionary, SdoAbort,
};

/// The test device's OD: a sorted table of descriptors and one 8-byte slot per entry.
#[derive(Debug, Clone)]
pub struct TestOd {
    entries: Vec<EntryDescriptor>,
    /// `index << 8 | sub` of each entry, for a tight binary search.
    keys: Vec<u32>,
    values: Vec<[u8; 8]>,
    defaults: Vec<[u8; 8]>,
    /// (index, sub, highest value): writes above it are refused with 0609 0031, as a
    /// generated dictionary refuses a value above its HighLimit.
    limits: Vec<(u16, u8, i64)>,
}

fn entry(
    index: u16,
    sub: u8,
    data_type: DataType,
    access: Access,
    pdo_mappable: bool,
) -> EntryDescriptor {
    EntryDescriptor::new(index, sub, data_type, access, pdo_mappable)
}

fn key(index: u16, sub: u8) -> u32 {
    u32::from(index) << 8 | u32::from(sub)
}

use Access::{Const, Ro, Rw, Rwr, Rww};
use DataType::{Integer16, Unsigned16, Unsigned32, Unsigned8};

impl TestOd {
    /// The device with node-ID `node_id` and its default mappings:
    /// RPDO1 (200h+id) = 2000h:00 (u16), event-driven; RPDO2 (300h+id) = 6040h (u16) + 6042h
    /// (i16), synchronous (type 1); RPDO3/4 invalid.
    /// TPDO1 (180h+id) = 6041h (u16), type 255; TPDO2 (280h+id) = 2001h:00 (u32), type 1;
    /// TPDO3/4 invalid.
    pub fn new(node_id: u8) -> Self {
        Self::build(node_id, false)
    }

    /// The same device with a second SDO server (1201h) on 640h/5C0h.
    pub fn with_second_sdo(node_id: u8) -> Self {
        Self::build(node_id, true)
    }

    fn build(node_id: u8, second_sdo: bool) -> Self {
        let id = u64::from(node_id);
        let mut table: Vec<(EntryDescriptor, u64)> = vec![
            (entry(0x1000, 0, Unsigned32, Ro, false), 0x0000_0191),
            (entry(0x1001, 0, Unsigned8, Ro, false), 0),
            (entry(0x1003, 0, Unsigned8, Rw, false), 0),
            (entry(0x1005, 0, Unsigned32, Rw, false), 0x80),
            (entry(0x1006, 0, Unsigned32, Rw, false), 0),
            (entry(0x1007, 0, Unsigned32, Rw, false), 0),
            (entry(0x100C, 0, Unsigned16, Rw, false), 0),
            (entry(0x100D, 0, Unsigned8, Rw, false), 0),
            (entry(0x1010, 0, Unsigned8, Ro, false), 1),
            (entry(0x1010, 1, Unsigned32, Rw, false), 1),
            (entry(0x1011, 0, Unsigned8, Ro, false), 1),
            (entry(0x1011, 1, Unsigned32, Rw, false), 1),
            (entry(0x1012, 0, Unsigned32, Rw, false), 0x100),
            (entry(0x1014, 0, Unsigned32, Rw, false), 0x80 + id),
            (entry(0x1015, 0, Unsigned16, Rw, false), 0),
            (entry(0x1016, 0, Unsigned8, Ro, false), 2),
            (entry(0x1016, 1, Unsigned32, Rw, false), 0),
            (entry(0x1016, 2, Unsigned32, Rw, false), 0),
            (entry(0x1017, 0, Unsigned16, Rw, false), 0),
            (entry(0x1018, 0, Unsigned8, Ro, false), 1),
            (entry(0x1018, 1, Unsigned32, Ro, false), 0x0000_04D8),
            (entry(0x1019, 0, Unsigned8, Rw, false), 0),
            (entry(0x1200, 0, Unsigned8, Ro, false), 2),
            (entry(0x1200, 1, Unsigned32, Ro, false), 0x600 + id),
            (entry(0x1200, 2, Unsigned32, Ro, false), 0x580 + id),
            (entry(0x2000, 0, Unsigned16, Rww, true), 0),
            (entry(0x2001, 0, Unsigned32, Rwr, true), 0),
            (entry(0x2002, 0, Unsigned8, Rw, false), 0),
            (entry(0x2003, 0, Unsigned32, Const, false), 0x1234_5678),
            (entry(0x6040, 0, Unsigned16, Rww, true), 0),
            (entry(0x6041, 0, Unsigned16, Ro, true), 0),
            (entry(0x6042, 0, Integer16, Rww, true), 0),
        ];
        if second_sdo {
            table.push((entry(0x1201, 0, Unsigned8, Ro, false), 2));
            table.push((entry(0x1201, 1, Unsigned32, Rw, false), 0x640));
            table.push((entry(0x1201, 2, Unsigned32, Rw, false), 0x5C0));
        }
        let rpdo_maps: [&[u32]; 4] = [&[0x2000_0010], &[0x6040_0010, 0x6042_0010], &[], &[]];
        let rpdo_types = [255u64, 1, 255, 255];
        let tpdo_maps: [&[u32]; 4] = [&[0x6041_0010], &[0x2001_0020], &[], &[]];
        let tpdo_types = [255u64, 1, 255, 255];
        for n in 0..4u16 {
            let valid_r = if rpdo_maps[n as usize].is_empty() {
                0x8000_0000
            } else {
                0
            };
            let comm = 0x1400 + n;
            table.push((entry(comm, 0, Unsigned8, Ro, false), 5));
            table.push((
                entry(comm, 1, Unsigned32, Rw, false),
                valid_r | (0x200 + 0x100 * u64::from(n) + id),
            ));
            table.push((entry(comm, 2, Unsigned8, Rw, false), rpdo_types[n as usize]));
            table.push((entry(comm, 5, Unsigned16, Rw, false), 0));
            let map = 0x1600 + n;
            table.push((
                entry(map, 0, Unsigned8, Rw, false),
                rpdo_maps[n as usize].len() as u64,
            ));
            for sub in 1..=8u8 {
                let value = rpdo_maps[n as usize]
                    .get(sub as usize - 1)
                    .copied()
                    .unwrap_or(0);
                table.push((entry(map, sub, Unsigned32, Rw, false), u64::from(value)));
            }
            let valid_t = if tpdo_maps[n as usize].is_empty() {
                0x8000_0000
            } else {
                0
            };
            let comm = 0x1800 + n;
            table.push((entry(comm, 0, Unsigned8, Ro, false), 6));
            table.push((
                entry(comm, 1, Unsigned32, Rw, false),
                valid_t | (0x180 + 0x100 * u64::from(n) + id),
            ));
            table.push((entry(comm, 2, Unsigned8, Rw, false), tpdo_types[n as usize]));
            table.push((entry(comm, 3, Unsigned16, Rw, false), 0));
            table.push((entry(comm, 5, Unsigned16, Rw, false), 0));
            table.push((entry(comm, 6, Unsigned8, Rw, false), 0));
            let map = 0x1A00 + n;
            table.push((
                entry(map, 0, Unsigned8, Rw, false),
                tpdo_maps[n as usize].len() as u64,
            ));
            for sub in 1..=8u8 {
                let value = tpdo_maps[n as usize]
                    .get(sub as usize - 1)
                    .copied()
                    .unwrap_or(0);
                table.push((entry(map, sub, Unsigned32, Rw, false), u64::from(value)));
            }
        }
        for sub in 1..=4u8 {
            table.push((entry(0x1003, sub, Unsigned32, Ro, false), 0));
        }
        table.sort_by_key(|(e, _)| (e.index(), e.sub()));
        let entries: Vec<EntryDescriptor> = table.iter().map(|(e, _)| *e).collect();
        let keys = entries.iter().map(|e| key(e.index(), e.sub())).collect();
        let values: Vec<[u8; 8]> = table.iter().map(|(_, v)| v.to_le_bytes()).collect();
        TestOd {
            entries,
            keys,
            defaults: values.clone(),
            values,
            limits: Vec::new(),
        }
    }

    /// The same device with a serial number (1018h:04), as LSS slaves need to differ.
    pub fn with_serial(mut self, serial: u32) -> Self {
        let Err(pos) = self.keys.binary_search(&key(0x1018, 4)) else {
            panic!("1018h:04 exists already");
        };
        self.entries
            .insert(pos, entry(0x1018, 4, Unsigned32, Ro, false));
        self.keys.insert(pos, key(0x1018, 4));
        self.values.insert(pos, u64::from(serial).to_le_bytes());
        self.defaults.insert(pos, u64::from(serial).to_le_bytes());
        self
    }

    /// Refuses writes of values above `high` to (index, sub) with 0609 0031 (a signed value for
    /// an INTEGERn entry).
    /// The same device without the objects `indices` (a dictionary lacking them).
    pub fn without(mut self, indices: &[u16]) -> Self {
        let keep: Vec<bool> = self
            .entries
            .iter()
            .map(|e| !indices.contains(&e.index()))
            .collect();
        let mut kept = keep.iter().copied();
        self.entries.retain(|_| kept.next().unwrap());
        let mut kept = keep.iter().copied();
        self.keys.retain(|_| kept.next().unwrap());
        let mut kept = keep.iter().copied();
        self.values.retain(|_| kept.next().unwrap());
        let mut kept = keep.iter().copied();
        self.defaults.retain(|_| kept.next().unwrap());
        self
    }

    pub fn with_high_limit(mut self, index: u16, sub: u8, high: i64) -> Self {
        self.limits.push((index, sub, high));
        self
    }

    fn position(&self, index: u16, sub: u8) -> Result<usize, SdoAbort> {
        match self.keys.binary_search(&key(index, sub)) {
            Ok(pos) => Ok(pos),
            Err(_) => Err(self.find(index, sub).err().unwrap_or(SdoAbort::NoObject)),
        }
    }

    /// The value of an entry as an unsigned integer (tests only: panics if it is absent).
    pub fn get(&self, index: u16, sub: u8) -> u64 {
        let pos = self.position(index, sub).expect("entry exists");
        u64::from_le_bytes(self.values[pos])
    }

    /// Sets an entry, as the application would (no checks but the size).
    pub fn set(&mut self, index: u16, sub: u8, value: u64) {
        let pos = self.position(index, sub).expect("entry exists");
        self.values[pos] = value.to_le_bytes();
    }

    /// Sets every entry in `range` back to its default.
    pub fn reset_range(&mut self, range: core::ops::RangeInclusive<u16>) {
        for (i, e) in self.entries.iter().enumerate() {
            if range.contains(&e.index()) {
                self.values[i] = self.defaults[i];
            }
        }
    }

    /// Every entry whose value differs from `other`'s.
    pub fn diff(&self, other: &TestOd) -> Vec<EntryDescriptor> {
        self.entries
            .iter()
            .zip(self.values.iter().zip(&other.values))
            .filter(|(_, (a, b))| a != b)
            .map(|(e, _)| *e)
            .collect()
    }
}

impl ObjectDictionary for TestOd {
    fn entry_count(&self) -> usize {
        self.entries.len()
    }

    fn entry(&self, position: usize) -> Option<EntryDescriptor> {
        self.entries.get(position).copied()
    }

    fn kind(&self, position: usize) -> Option<EntryKind> {
        Some(self.entries.get(position)?.kind())
    }

    /// The search generated dictionaries make, on the table here.
    fn locate(&self, index: u16, sub: u8) -> Result<usize, SdoAbort> {
        edsgen_runtime::support::position(&self.entries, index, sub)
    }

    fn find(&self, index: u16, sub: u8) -> Result<EntryDescriptor, SdoAbort> {
        match self.keys.binary_search(&key(index, sub)) {
            Ok(pos) => Ok(self.entries[pos]),
            Err(pos) => {
                let index_exists = self.entries.get(pos).is_some_and(|e| e.index() == index)
                    || (pos > 0 && self.entries[pos - 1].index() == index);
                Err(if index_exists {
                    SdoAbort::NoSubIndex
                } else {
                    SdoAbort::NoObject
                })
            }
        }
    }

    fn value_len(&self, index: u16, sub: u8) -> Result<usize, SdoAbort> {
        let pos = self.position(index, sub)?;
        Ok(self.entries[pos].data_type().fixed_size().unwrap_or(8))
    }

    fn read(&self, index: u16, sub: u8, offset: usize, buf: &mut [u8]) -> Result<usize, SdoAbort> {
        let pos = self.position(index, sub)?;
        let size = self.entries[pos].data_type().fixed_size().unwrap_or(8);
        let value = &self.values[pos][..size];
        let rest = value.get(offset..).unwrap_or(&[]);
        let n = rest.len().min(buf.len());
        buf[..n].copy_from_slice(&rest[..n]);
        Ok(n)
    }

    fn restore_defaults(&mut self, indices: core::ops::RangeInclusive<u16>, _node_id: u8) -> bool {
        self.reset_range(indices);
        true
    }

    fn write(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<(), SdoAbort> {
        let pos = self.position(index, sub)?;
        let size = self.entries[pos].data_type().fixed_size().unwrap_or(8);
        if data.len() > size {
            return Err(SdoAbort::LengthTooHigh);
        }
        if data.len() < size {
            return Err(SdoAbort::LengthTooLow);
        }
        let mut value = [0u8; 8];
        value[..size].copy_from_slice(data);
        if let Some(&(_, _, high)) = self
            .limits
            .iter()
            .find(|&&(i, s, _)| (i, s) == (index, sub))
        {
            let number = match self.entries[pos].data_type() {
                Integer16 => i64::from(i16::from_le_bytes([value[0], value[1]])),
                _ => u64::from_le_bytes(value) as i64,
            };
            if number > high {
                return Err(SdoAbort::ValueTooHigh);
            }
        }
        self.values[pos] = value;
        Ok(())
    }
}

/// Hooks that record what the node asked for; a reset restores the test OD's defaults of the
/// re-initialised area.
#[derive(Debug, Default, Clone)]
pub struct RecordingHooks {
    pub resets: Vec<ResetKind>,
    pub saved: Vec<u8>,
    pub restored: Vec<u8>,
}

impl NodeHooks<TestOd> for RecordingHooks {
    fn reset(&mut self, kind: ResetKind, od: &mut TestOd) {
        self.resets.push(kind);
        match kind {
            ResetKind::Node => od.reset_range(0x0000..=0xFFFF),
            ResetKind::Communication => od.reset_range(0x1000..=0x1FFF),
        }
    }

    fn save(&mut self, sub: u8, _od: &TestOd) -> Result<(), SdoAbort> {
        self.saved.push(sub);
        Ok(())
    }

    fn restore_defaults(&mut self, sub: u8) -> Result<(), SdoAbort> {
        self.restored.push(sub);
        Ok(())
    }
}
