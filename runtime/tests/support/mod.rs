//! A hand-written object dictionary for the protocol tests: entries of every access type and
//! several data types, with lengths and limits checked the way generated dictionaries check them.

use edsgen_runtime::{Access, DataType, EntryDescriptor, ObjectDictionary, SdoAbort};

/// The 300 bytes 0x2006 (DOMAIN) holds at start.
pub fn domain_pattern() -> Vec<u8> {
    (0..300u32).map(|i| (i * 7 + 1) as u8).collect()
}

/// Inclusive limits of an unsigned value.
type Limits = Option<(u64, u64)>;

struct Value {
    bytes: Vec<u8>,
    /// The most bytes the value holds.
    capacity: usize,
    /// Inclusive limits of an unsigned value, checked on write.
    limits: Limits,
}

/// The test dictionary.
pub struct TestOd {
    descriptors: Vec<EntryDescriptor>,
    values: Vec<Value>,
    /// The download open in the dictionary (position and the pieces so far), staged until
    /// committed, as a generated dictionary stages it.
    download: Option<(usize, Vec<u8>)>,
}

fn descriptor(
    index: u16,
    sub: u8,
    data_type: DataType,
    access: Access,
    capacity: usize,
) -> (EntryDescriptor, usize) {
    let pdo_mappable = matches!(access, Access::Rwr | Access::Rww);
    let descriptor = EntryDescriptor::new(index, sub, data_type, access, pdo_mappable);
    (descriptor, capacity)
}

impl TestOd {
    /// The dictionary with its initial values.
    pub fn new() -> Self {
        use Access::*;
        use DataType::*;
        let table: Vec<((EntryDescriptor, usize), Vec<u8>, Limits)> = vec![
            (
                descriptor(0x1000, 0, Unsigned32, Ro, 4),
                0x0002_0192u32.to_le_bytes().to_vec(),
                None,
            ),
            (
                descriptor(0x1008, 0, VisibleString, Const, 20),
                b"edsgen".to_vec(),
                None,
            ),
            (descriptor(0x1017, 0, Unsigned16, Rw, 2), vec![0, 0], None),
            (descriptor(0x1018, 0, Unsigned8, Const, 1), vec![1], None),
            (
                descriptor(0x1018, 1, Unsigned32, Ro, 4),
                0x0000_0123u32.to_le_bytes().to_vec(),
                None,
            ),
            (descriptor(0x1801, 3, Unsigned16, Rw, 2), vec![0, 0], None),
            (
                descriptor(0x2000, 0, Unsigned16, Rw, 2),
                100u16.to_le_bytes().to_vec(),
                Some((10, 1000)),
            ),
            (descriptor(0x2001, 0, Unsigned32, Wo, 4), vec![0; 4], None),
            (descriptor(0x2002, 0, Unsigned8, Ro, 1), vec![3], None),
            (
                descriptor(0x2002, 3, Unsigned16, Rw, 2),
                0x0102u16.to_le_bytes().to_vec(),
                None,
            ),
            (
                descriptor(0x2003, 0, Unsigned64, Rw, 8),
                0x1122_3344_5566_7788u64.to_le_bytes().to_vec(),
                None,
            ),
            (descriptor(0x2004, 0, Integer8, Rww, 1), vec![0xFE], None),
            (
                descriptor(0x2005, 0, VisibleString, Rw, 20),
                b"hello".to_vec(),
                None,
            ),
            (
                descriptor(0x2006, 0, Domain, Rw, 300),
                domain_pattern(),
                None,
            ),
            (
                descriptor(0x2007, 0, Unsigned32, Rwr, 4),
                0x1234_5678u32.to_le_bytes().to_vec(),
                None,
            ),
            (
                descriptor(0x2008, 0, Unsigned24, Rw, 3),
                vec![0x01, 0x02, 0x03],
                None,
            ),
            (
                descriptor(0x2009, 0, Real32, Rw, 4),
                1.5f32.to_le_bytes().to_vec(),
                None,
            ),
        ];
        let mut od = TestOd {
            descriptors: Vec::new(),
            values: Vec::new(),
            download: None,
        };
        for ((descriptor, capacity), bytes, limits) in table {
            od.descriptors.push(descriptor);
            od.values.push(Value {
                bytes,
                capacity,
                limits,
            });
        }
        assert!(od
            .descriptors
            .windows(2)
            .all(|pair| (pair[0].index(), pair[0].sub()) < (pair[1].index(), pair[1].sub())));
        od
    }

    fn position(&self, index: u16, sub: u8) -> Result<usize, SdoAbort> {
        self.find(index, sub)?;
        self.descriptors
            .iter()
            .position(|d| d.index() == index && d.sub() == sub)
            .ok_or(SdoAbort::NoObject)
    }

    /// The current value of (index, sub).
    pub fn value(&self, index: u16, sub: u8) -> &[u8] {
        &self.values[self.position(index, sub).unwrap()].bytes
    }

    /// Replaces the value of (index, sub) behind the protocol's back (the application's side).
    pub fn set_value(&mut self, index: u16, sub: u8, bytes: &[u8]) {
        let position = self.position(index, sub).unwrap();
        self.values[position].bytes = bytes.to_vec();
    }
}

impl Default for TestOd {
    fn default() -> Self {
        Self::new()
    }
}

impl ObjectDictionary for TestOd {
    fn entry_count(&self) -> usize {
        self.descriptors.len()
    }

    fn entry(&self, position: usize) -> Option<EntryDescriptor> {
        self.descriptors.get(position).copied()
    }

    fn capacity(&self, position: usize) -> Option<usize> {
        self.values.get(position).map(|value| value.capacity)
    }

    fn value_len(&self, index: u16, sub: u8) -> Result<usize, SdoAbort> {
        Ok(self.values[self.position(index, sub)?].bytes.len())
    }

    fn read(&self, index: u16, sub: u8, offset: usize, buf: &mut [u8]) -> Result<usize, SdoAbort> {
        let bytes = &self.values[self.position(index, sub)?].bytes;
        let rest = bytes.get(offset..).unwrap_or(&[]);
        let len = rest.len().min(buf.len());
        buf[..len].copy_from_slice(&rest[..len]);
        Ok(len)
    }

    fn begin_write(&mut self, position: usize) -> Result<(), SdoAbort> {
        if self.download.is_some() {
            return Err(SdoAbort::NoResource);
        }
        self.download = Some((position, Vec::new()));
        Ok(())
    }

    fn write_part(&mut self, position: usize, offset: usize, data: &[u8]) -> Result<(), SdoAbort> {
        let capacity = self
            .values
            .get(position)
            .ok_or(SdoAbort::NoObject)?
            .capacity;
        if offset + data.len() > capacity {
            return Err(SdoAbort::LengthTooHigh);
        }
        match &mut self.download {
            Some((open, bytes)) if *open == position => {
                bytes.truncate(offset);
                bytes.extend_from_slice(data);
                Ok(())
            }
            _ => Err(SdoAbort::General),
        }
    }

    fn commit_write(&mut self, position: usize, len: usize) -> Result<(), SdoAbort> {
        match self.download.take() {
            Some((open, mut bytes)) if open == position => {
                bytes.truncate(len);
                let value = self.values.get_mut(position).ok_or(SdoAbort::NoObject)?;
                value.bytes = bytes;
                Ok(())
            }
            _ => Err(SdoAbort::General),
        }
    }

    fn abort_write(&mut self, position: usize) {
        if self
            .download
            .as_ref()
            .is_some_and(|(open, _)| *open == position)
        {
            self.download = None;
        }
    }

    fn write(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<(), SdoAbort> {
        let position = self.position(index, sub)?;
        let descriptor = self.descriptors[position];
        match descriptor.data_type().fixed_size() {
            Some(size) if data.len() > size => return Err(SdoAbort::LengthTooHigh),
            Some(size) if data.len() < size => return Err(SdoAbort::LengthTooLow),
            None if data.len() > self.values[position].capacity => {
                return Err(SdoAbort::LengthTooHigh)
            }
            _ => {}
        }
        let value = &mut self.values[position];
        if let Some((low, high)) = value.limits {
            let mut le = [0u8; 8];
            le[..data.len()].copy_from_slice(data);
            let number = u64::from_le_bytes(le);
            if number > high {
                return Err(SdoAbort::ValueTooHigh);
            }
            if number < low {
                return Err(SdoAbort::ValueTooLow);
            }
        }
        value.bytes = data.to_vec();
        Ok(())
    }
}
