//! The object dictionary of the minimal node: the CiA 301 communication objects only (NMT,
//! heartbeat, SDO server, 4 RPDOs + 4 TPDOs, SYNC, EMCY), written by hand as a sorted `const`
//! table and one 32-bit slot per entry.

use edsgen_runtime::od::{
    Access, DataType, EntryDescriptor, EntryKind, ObjectDictionary, SdoAbort, Services,
};

const fn e(index: u16, sub: u8, data_type: DataType, access: Access) -> EntryDescriptor {
    EntryDescriptor::new(index, sub, data_type, access, false)
}

const fn m(index: u16, sub: u8, data_type: DataType, access: Access) -> EntryDescriptor {
    EntryDescriptor::new(index, sub, data_type, access, true)
}

use Access::{Ro, Rw, Rwr, Rww};
use DataType::{Unsigned16, Unsigned32, Unsigned8};

macro_rules! pdo_objects {
    ($comm:expr, $map:expr, $tx:expr) => {
        [
            e($comm, 0, Unsigned8, Ro),
            e($comm, 1, Unsigned32, Rw),
            e($comm, 2, Unsigned8, Rw),
            e($comm, 3, Unsigned16, Rw),
            e($comm, 5, Unsigned16, Rw),
            e($map, 0, Unsigned8, Rw),
            e($map, 1, Unsigned32, Rw),
            e($map, 2, Unsigned32, Rw),
            e($map, 3, Unsigned32, Rw),
            e($map, 4, Unsigned32, Rw),
        ]
    };
}

const HEAD: [EntryDescriptor; 16] = [
    e(0x1000, 0, Unsigned32, Ro),
    e(0x1001, 0, Unsigned8, Ro),
    e(0x1003, 0, Unsigned8, Rw),
    e(0x1003, 1, Unsigned32, Ro),
    e(0x1003, 2, Unsigned32, Ro),
    e(0x1005, 0, Unsigned32, Rw),
    e(0x1006, 0, Unsigned32, Rw),
    e(0x1014, 0, Unsigned32, Rw),
    e(0x1015, 0, Unsigned16, Rw),
    e(0x1017, 0, Unsigned16, Rw),
    e(0x1018, 0, Unsigned8, Ro),
    e(0x1018, 1, Unsigned32, Ro),
    e(0x1019, 0, Unsigned8, Rw),
    e(0x1200, 0, Unsigned8, Ro),
    e(0x1200, 1, Unsigned32, Ro),
    e(0x1200, 2, Unsigned32, Ro),
];

const APP: [EntryDescriptor; 4] = [
    m(0x6040, 0, Unsigned16, Rww),
    m(0x6041, 0, Unsigned16, Rwr),
    m(0x6042, 0, DataType::Integer16, Rww),
    m(0x6044, 0, DataType::Integer16, Rwr),
];

/// Entries: the head, RPDO 1400h–1403h, RPDO mapping 1600h–1603h, TPDO 1800h–1803h,
/// TPDO mapping 1A00h–1A03h, then the application objects.
const COUNT: usize = HEAD.len() + 8 * 10 + APP.len();

const fn build() -> [EntryDescriptor; COUNT] {
    let mut table = [HEAD[0]; COUNT];
    let mut n = 0;
    let mut i = 0;
    while i < HEAD.len() {
        table[n] = HEAD[i];
        n += 1;
        i += 1;
    }
    // Sorted order: 1400h..1403h (comm, 4 each), 1600h..1603h (map, 5 each), same for TPDOs.
    let mut pass = 0;
    while pass < 2 {
        let base = if pass == 0 { 0x1400 } else { 0x1800 };
        let mut k = 0;
        while k < 4 {
            let objects = pdo_objects!(base + k, base + 0x200 + k, pass == 1);
            let mut j = 0;
            while j < 5 {
                table[n] = objects[j];
                n += 1;
                j += 1;
            }
            k += 1;
        }
        let mut k = 0;
        while k < 4 {
            let objects = pdo_objects!(base + k, base + 0x200 + k, pass == 1);
            let mut j = 5;
            while j < 10 {
                table[n] = objects[j];
                n += 1;
                j += 1;
            }
            k += 1;
        }
        pass += 1;
    }
    let mut i = 0;
    while i < APP.len() {
        table[n] = APP[i];
        n += 1;
        i += 1;
    }
    table
}

static ENTRIES: [EntryDescriptor; COUNT] = build();

/// The device's values, one slot per entry of [`ENTRIES`].
pub struct MinimalOd {
    values: [u32; COUNT],
}

impl MinimalOd {
    /// Power-on values for node `node_id`: RPDO1 = 6040h + 6042h, TPDO1 = 6041h + 6044h
    /// (event-driven), the other PDOs invalid, heartbeat 1000 ms.
    pub fn new(node_id: u8) -> Self {
        let id = u32::from(node_id);
        let mut od = MinimalOd { values: [0; COUNT] };
        let defaults: [(u16, u8, u32); 17] = [
            (0x1000, 0, 0x0001_0192),
            (0x1005, 0, 0x80),
            (0x1014, 0, 0x80 + id),
            (0x1017, 0, 1000),
            (0x1018, 0, 1),
            (0x1200, 0, 2),
            (0x1200, 1, 0x600 + id),
            (0x1200, 2, 0x580 + id),
            (0x1400, 1, 0x200 + id),
            (0x1600, 0, 2),
            (0x1600, 1, 0x6040_0010),
            (0x1600, 2, 0x6042_0010),
            (0x1800, 1, 0x180 + id),
            (0x1A00, 0, 2),
            (0x1A00, 1, 0x6041_0010),
            (0x1A00, 2, 0x6044_0010),
            (0x1003, 0, 0),
        ];
        for (index, sub, value) in defaults {
            if let Ok(pos) = position(index, sub) {
                od.values[pos] = value;
            }
        }
        for n in 0..4u16 {
            for (comm, invalid_from) in [(0x1400, 1), (0x1800, 1)] {
                if let Ok(pos) = position(comm + n, 0) {
                    od.values[pos] = 5;
                }
                if n >= invalid_from {
                    if let Ok(pos) = position(comm + n, 1) {
                        od.values[pos] = 0x8000_0000 | (u32::from(comm - 0x1200 + n * 0x100) + id);
                    }
                }
                if let Ok(pos) = position(comm + n, 2) {
                    od.values[pos] = 255;
                }
            }
        }
        od
    }
}

/// The size of an entry's value: every entry here has a fixed-size type of at most 4 bytes.
fn size(entry: &EntryDescriptor) -> usize {
    entry.data_type().fixed_size().unwrap_or(0)
}

fn position(index: u16, sub: u8) -> Result<usize, SdoAbort> {
    ENTRIES
        .binary_search_by(|e| (e.index(), e.sub()).cmp(&(index, sub)))
        .map_err(|_| SdoAbort::NoObject)
}

impl ObjectDictionary for MinimalOd {
    fn entry_count(&self) -> usize {
        ENTRIES.len()
    }

    fn entry(&self, position: usize) -> Option<EntryDescriptor> {
        ENTRIES.get(position).copied()
    }

    fn kind(&self, position: usize) -> Option<EntryKind> {
        Some(ENTRIES.get(position)?.kind())
    }

    /// The search generated dictionaries make, on the table here.
    fn locate(&self, index: u16, sub: u8) -> Result<usize, SdoAbort> {
        edsgen_runtime::support::position(&ENTRIES, index, sub)
    }

    /// The services of the objects above: no 1007h, 100Ch/100Dh or 1201h, and no writable
    /// string or domain.
    fn services(&self) -> Services {
        Services {
            sync_window: false,
            life_guarding: false,
            second_sdo: false,
            streamed_writes: false,
            ..Services::ALL
        }
    }

    fn value_len(&self, index: u16, sub: u8) -> Result<usize, SdoAbort> {
        Ok(size(&ENTRIES[self.locate(index, sub)?]))
    }

    fn read(&self, index: u16, sub: u8, offset: usize, buf: &mut [u8]) -> Result<usize, SdoAbort> {
        let pos = self.locate(index, sub)?;
        let bytes = self.values[pos].to_le_bytes();
        let value = &bytes[..size(&ENTRIES[pos])];
        let rest = value.get(offset..).unwrap_or(&[]);
        let n = rest.len().min(buf.len());
        buf[..n].copy_from_slice(&rest[..n]);
        Ok(n)
    }

    fn write(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<(), SdoAbort> {
        let pos = self.locate(index, sub)?;
        let size = size(&ENTRIES[pos]);
        if data.len() != size {
            return Err(if data.len() > size {
                SdoAbort::LengthTooHigh
            } else {
                SdoAbort::LengthTooLow
            });
        }
        let mut bytes = [0u8; 4];
        bytes[..size].copy_from_slice(data);
        self.values[pos] = u32::from_le_bytes(bytes);
        Ok(())
    }
}
