//! A small drive-like object dictionary written the way generated code is: a sorted `const`
//! descriptor table and typed fields, matched by (index, sub). Shared by the SDO loop example and
//! the SDO benchmark so both measure the same thing.

use edsgen_runtime::{Access, DataType, EntryDescriptor, ObjectDictionary, SdoAbort};

const fn entry(index: u16, sub: u8, data_type: DataType, access: Access) -> EntryDescriptor {
    EntryDescriptor::new(index, sub, data_type, access, false)
}

const ENTRIES: [EntryDescriptor; 10] = [
    entry(0x1000, 0, DataType::Unsigned32, Access::Ro),
    entry(0x1001, 0, DataType::Unsigned8, Access::Ro),
    entry(0x1017, 0, DataType::Unsigned16, Access::Rw),
    entry(0x1018, 0, DataType::Unsigned8, Access::Const),
    entry(0x1018, 1, DataType::Unsigned32, Access::Ro),
    entry(0x1018, 2, DataType::Unsigned32, Access::Ro),
    entry(0x6040, 0, DataType::Unsigned16, Access::Rww),
    entry(0x6041, 0, DataType::Unsigned16, Access::Rwr),
    entry(0x6060, 0, DataType::Integer8, Access::Rw),
    entry(0x607A, 0, DataType::Integer32, Access::Rw),
];

/// The dictionary's values.
pub struct DriveOd {
    /// 0x1000 device type.
    pub device_type: u32,
    /// 0x1001 error register.
    pub error_register: u8,
    /// 0x1017 producer heartbeat time.
    pub heartbeat_ms: u16,
    /// 0x1018:01 vendor id.
    pub vendor_id: u32,
    /// 0x1018:02 product code.
    pub product_code: u32,
    /// 0x6040 controlword.
    pub controlword: u16,
    /// 0x6041 statusword.
    pub statusword: u16,
    /// 0x6060 modes of operation.
    pub mode: i8,
    /// 0x607A target position.
    pub target_position: i32,
}

impl DriveOd {
    /// The dictionary with its default values.
    pub const fn new() -> Self {
        DriveOd {
            device_type: 0x0002_0192,
            error_register: 0,
            heartbeat_ms: 0,
            vendor_id: 0x0000_0123,
            product_code: 0x0000_0456,
            controlword: 0,
            statusword: 0x0250,
            mode: 0,
            target_position: 0,
        }
    }

    /// The value's bytes (at most 4 here) and length.
    fn bytes(&self, index: u16, sub: u8) -> Result<([u8; 4], usize), SdoAbort> {
        fn le<const L: usize>(bytes: [u8; L]) -> ([u8; 4], usize) {
            let mut out = [0u8; 4];
            out[..L].copy_from_slice(&bytes);
            (out, L)
        }
        Ok(match (index, sub) {
            (0x1000, 0) => le(self.device_type.to_le_bytes()),
            (0x1001, 0) => le(self.error_register.to_le_bytes()),
            (0x1017, 0) => le(self.heartbeat_ms.to_le_bytes()),
            (0x1018, 0) => le([2u8]),
            (0x1018, 1) => le(self.vendor_id.to_le_bytes()),
            (0x1018, 2) => le(self.product_code.to_le_bytes()),
            (0x6040, 0) => le(self.controlword.to_le_bytes()),
            (0x6041, 0) => le(self.statusword.to_le_bytes()),
            (0x6060, 0) => le(self.mode.to_le_bytes()),
            (0x607A, 0) => le(self.target_position.to_le_bytes()),
            _ => return Err(self.find(index, sub).err().unwrap_or(SdoAbort::NoObject)),
        })
    }
}

impl Default for DriveOd {
    fn default() -> Self {
        Self::new()
    }
}

fn exact<const L: usize>(data: &[u8]) -> Result<[u8; L], SdoAbort> {
    match data.len() {
        len if len > L => Err(SdoAbort::LengthTooHigh),
        len if len < L => Err(SdoAbort::LengthTooLow),
        _ => {
            let mut out = [0u8; L];
            out.copy_from_slice(data);
            Ok(out)
        }
    }
}

impl ObjectDictionary for DriveOd {
    fn entry_count(&self) -> usize {
        ENTRIES.len()
    }

    fn entry(&self, position: usize) -> Option<EntryDescriptor> {
        ENTRIES.get(position).copied()
    }

    fn value_len(&self, index: u16, sub: u8) -> Result<usize, SdoAbort> {
        Ok(self.bytes(index, sub)?.1)
    }

    fn read(&self, index: u16, sub: u8, offset: usize, buf: &mut [u8]) -> Result<usize, SdoAbort> {
        let (bytes, len) = self.bytes(index, sub)?;
        let rest = bytes[..len].get(offset..).unwrap_or(&[]);
        let count = rest.len().min(buf.len());
        buf[..count].copy_from_slice(&rest[..count]);
        Ok(count)
    }

    fn write(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<(), SdoAbort> {
        match (index, sub) {
            (0x1017, 0) => self.heartbeat_ms = u16::from_le_bytes(exact(data)?),
            (0x6040, 0) => self.controlword = u16::from_le_bytes(exact(data)?),
            (0x6041, 0) => self.statusword = u16::from_le_bytes(exact(data)?),
            (0x6060, 0) => self.mode = i8::from_le_bytes(exact(data)?),
            (0x607A, 0) => self.target_position = i32::from_le_bytes(exact(data)?),
            _ => return Err(self.find(index, sub).err().unwrap_or(SdoAbort::ReadOnly)),
        }
        Ok(())
    }
}
