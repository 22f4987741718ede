//! The SII (Slave Information Interface, the ESC's EEPROM) image of an EtherCAT device, built
//! from its model as ETG.2010 lays it out, in 16-bit little-endian words:
//!
//! - words 0x00–0x07, the ESC configuration area, word 7's low byte the CRC-8 of bytes 0–13
//!   (polynomial 0x07, initial value 0xFF, not reflected: [`crc8`]);
//! - 0x08–0x0F vendor ID, product code, revision, serial number (u32 each);
//! - 0x14–0x17 the bootstrap mailbox (none), 0x18–0x1B the standard mailbox's receive (SM0,
//!   master to device) and send (SM1) offsets and sizes, 0x1C the mailbox protocols (bit 2 CoE);
//! - 0x3E the EEPROM size in kbit minus one, 0x3F the version (1);
//! - from word 0x40 the categories, each a type and a length in words before its data: Strings
//!   (10), General (30), FMMU (40), SyncM (41), one TxPDO (50) / RxPDO (51) per PDO, and 0xFFFF.
//!
//! Choices where the model says nothing (an ESI's `<Eeprom>` is not read): the configuration
//! area is ours: PDI control 0x0005 (SPI), no PDI configuration, no SYNC impulse, alias 0. A
//! mailbox SyncManager without `DefaultSize` is 128 bytes; a process-data one without it is as
//! long as the PDOs assigned to it by default. FMMUs: one for outputs, one for inputs, one for
//! the mailbox state, those the device has. A PDO assigned to no SyncManager says SM 0xFF. The
//! serial number is 0; the General category names no group and no image, and declares two MII
//! ports.

use crate::model::{Device, EcPdo, SmKind};

/// Category types.
pub mod category {
    /// Strings.
    pub const STRINGS: u16 = 10;
    /// General.
    pub const GENERAL: u16 = 30;
    /// FMMU usage.
    pub const FMMU: u16 = 40;
    /// SyncManagers.
    pub const SYNC_M: u16 = 41;
    /// TxPDO (inputs).
    pub const TX_PDO: u16 = 50;
    /// RxPDO (outputs).
    pub const RX_PDO: u16 = 51;
    /// End of the list.
    pub const END: u16 = 0xFFFF;
}

/// PDO flags (ETG.2010 table 14).
pub mod pdo_flag {
    /// `Mandatory`.
    pub const MANDATORY: u16 = 0x0001;
    /// Assigned by default (`Sm`).
    pub const DEFAULT: u16 = 0x0002;
    /// `Fixed`.
    pub const FIXED_CONTENT: u16 = 0x0010;
}

/// The mailbox size used when a mailbox SyncManager has no `DefaultSize`.
pub const DEFAULT_MAILBOX_SIZE: u16 = 128;

/// The ETG.2010 CRC-8 of the configuration area: polynomial x⁸+x²+x+1 (0x07), initial value
/// 0xFF, most significant bit first, no final XOR.
pub fn crc8(bytes: &[u8]) -> u8 {
    let mut crc = 0xFFu8;
    for &byte in bytes {
        crc ^= byte;
        for _ in 0..8 {
            crc = if crc & 0x80 != 0 {
                (crc << 1) ^ 0x07
            } else {
                crc << 1
            };
        }
    }
    crc
}

/// The SII image of `device`, or why there is none (a model without its EtherCAT part).
pub fn build(device: &Device) -> Result<Vec<u8>, String> {
    let ec = device
        .ethercat()
        .ok_or("not an EtherCAT device: an SII image is built from an ESI file")?;
    let number = |n: Option<&crate::model::Spanned<u32>>| n.map_or(0, |n| n.value);
    let mailbox = |kind: SmKind| {
        ec.sync_managers
            .iter()
            .find(|sm| sm.kind == kind)
            .map(|sm| {
                (
                    sm.start_address,
                    sm.default_size.unwrap_or(DEFAULT_MAILBOX_SIZE),
                )
            })
    };
    let (out_mbx, in_mbx) = (mailbox(SmKind::MailboxOut), mailbox(SmKind::MailboxIn));

    let mut image = vec![0u8; 0x80];
    image[0] = 0x05;
    image[14] = crc8(&image[..14]);
    put_u32(
        &mut image,
        0x08,
        number(device.device_info.vendor_number.as_ref()),
    );
    put_u32(
        &mut image,
        0x0A,
        number(device.device_info.product_number.as_ref()),
    );
    put_u32(
        &mut image,
        0x0C,
        number(device.device_info.revision_number.as_ref()),
    );
    if let (Some(out), Some(inp)) = (out_mbx, in_mbx) {
        put_u16(&mut image, 0x18, out.0);
        put_u16(&mut image, 0x19, out.1);
        put_u16(&mut image, 0x1A, inp.0);
        put_u16(&mut image, 0x1B, inp.1);
        put_u16(&mut image, 0x1C, if ec.coe.is_some() { 0x0004 } else { 0 });
    }
    put_u16(&mut image, 0x3F, 1);

    let mut strings = Strings::default();
    let order = strings.index(&ec.type_name);
    let name = strings.index(device.device_info.product_name.as_deref().unwrap_or(""));
    let mut pdo_categories = Vec::new();
    for (kind, pdos) in [
        (category::TX_PDO, &ec.tx_pdos),
        (category::RX_PDO, &ec.rx_pdos),
    ] {
        for pdo in pdos {
            pdo_categories.push((kind, pdo_category(device, pdo, &mut strings)));
        }
    }

    let mut general = vec![0u8; 32];
    general[2] = order;
    general[3] = name;
    if let Some(coe) = &ec.coe {
        general[5] = 0x01
            | u8::from(coe.sdo_info) << 1
            | u8::from(coe.pdo_assign) << 2
            | u8::from(coe.pdo_config) << 3
            | u8::from(coe.complete_access) << 5;
    }
    // Ports 0 and 1 MII.
    general[14] = 0x11;

    let has = |kind: SmKind| ec.sync_managers.iter().any(|sm| sm.kind == kind);
    let mut fmmu = Vec::new();
    if has(SmKind::Outputs) {
        fmmu.push(1);
    }
    if has(SmKind::Inputs) {
        fmmu.push(2);
    }
    if out_mbx.is_some() && in_mbx.is_some() {
        fmmu.push(3);
    }

    let mut sync_m = Vec::new();
    for (n, sm) in ec.sync_managers.iter().enumerate() {
        let (kind, len) = match &sm.kind {
            SmKind::MailboxOut => (1, sm.default_size.unwrap_or(DEFAULT_MAILBOX_SIZE)),
            SmKind::MailboxIn => (2, sm.default_size.unwrap_or(DEFAULT_MAILBOX_SIZE)),
            SmKind::Outputs => (3, sm.default_size.unwrap_or(assigned_bytes(&ec.rx_pdos, n))),
            SmKind::Inputs => (4, sm.default_size.unwrap_or(assigned_bytes(&ec.tx_pdos, n))),
            SmKind::Other(_) => (0, sm.default_size.unwrap_or(0)),
        };
        sync_m.extend_from_slice(&sm.start_address.to_le_bytes());
        sync_m.extend_from_slice(&len.to_le_bytes());
        sync_m.extend_from_slice(&[sm.control_byte, 0, u8::from(sm.enable), kind]);
    }

    push_category(&mut image, category::STRINGS, &strings.emit());
    push_category(&mut image, category::GENERAL, &general);
    if !fmmu.is_empty() {
        push_category(&mut image, category::FMMU, &fmmu);
    }
    if !sync_m.is_empty() {
        push_category(&mut image, category::SYNC_M, &sync_m);
    }
    for (kind, data) in &pdo_categories {
        push_category(&mut image, *kind, data);
    }
    image.extend_from_slice(&category::END.to_le_bytes());
    // The size word: kbit minus one, at least 1 kbit.
    let kbit = (image.len() * 8).div_ceil(1024).max(1);
    put_u16(
        &mut image,
        0x3E,
        u16::try_from(kbit - 1).unwrap_or(u16::MAX),
    );
    Ok(image)
}

/// The bytes of the PDOs assigned to SyncManager `n` by default.
fn assigned_bytes(pdos: &[EcPdo], n: usize) -> u16 {
    let bits: u32 = pdos
        .iter()
        .filter(|p| p.sm.map(usize::from) == Some(n))
        .flat_map(|p| &p.entries)
        .map(|e| u32::from(e.bit_len))
        .sum();
    u16::try_from(bits.div_ceil(8)).unwrap_or(u16::MAX)
}

/// A TxPDO or RxPDO category's data: the 8-byte header, then 8 bytes per entry.
fn pdo_category(device: &Device, pdo: &EcPdo, strings: &mut Strings) -> Vec<u8> {
    let mut flags = 0;
    if pdo.mandatory {
        flags |= pdo_flag::MANDATORY;
    }
    if pdo.sm.is_some() {
        flags |= pdo_flag::DEFAULT;
    }
    if pdo.fixed {
        flags |= pdo_flag::FIXED_CONTENT;
    }
    let mut data = pdo.index.to_le_bytes().to_vec();
    data.push(u8::try_from(pdo.entries.len()).unwrap_or(u8::MAX));
    data.push(pdo.sm.unwrap_or(0xFF));
    data.push(0);
    data.push(strings.index(&pdo.name));
    data.extend_from_slice(&flags.to_le_bytes());
    for entry in pdo.entries.iter().take(usize::from(u8::MAX)) {
        let data_type = entry
            .data_type
            .as_deref()
            .and_then(data_type_code)
            .or_else(|| {
                let sub = device.objects.get(&entry.index)?.subs.get(&entry.sub)?;
                u8::try_from(sub.data_type?).ok()
            })
            .unwrap_or(0);
        data.extend_from_slice(&entry.index.to_le_bytes());
        data.push(entry.sub);
        data.push(strings.index(&entry.name));
        data.push(if entry.index == 0 { 0 } else { data_type });
        data.push(u8::try_from(entry.bit_len).unwrap_or(u8::MAX));
        data.extend_from_slice(&0u16.to_le_bytes());
    }
    data
}

/// The CoE data type code (ETG.1020) of an ESI `DataType` name, for the SII's PDO entries.
pub fn data_type_code(name: &str) -> Option<u8> {
    Some(match name.trim() {
        "BOOL" | "BIT" => 0x01,
        "SINT" => 0x02,
        "INT" => 0x03,
        "DINT" => 0x04,
        "USINT" => 0x05,
        "UINT" => 0x06,
        "UDINT" => 0x07,
        "REAL" => 0x08,
        "LREAL" => 0x11,
        "LINT" => 0x15,
        "ULINT" => 0x1B,
        "BYTE" => 0x1E,
        "WORD" => 0x1F,
        "DWORD" => 0x20,
        bits => {
            let n: u8 = bits.strip_prefix("BIT")?.parse().ok()?;
            return (1..=8).contains(&n).then(|| 0x2F + n);
        }
    })
}

/// The Strings category's strings, numbered from 1 in order of first use.
#[derive(Debug, Default)]
struct Strings {
    strings: Vec<Vec<u8>>,
}

impl Strings {
    /// The number of `text` (0 for an empty text, or when 255 strings are taken), added if new.
    /// A text is cut to 255 bytes at a character boundary.
    fn index(&mut self, text: &str) -> u8 {
        let mut end = text.len().min(255);
        while !text.is_char_boundary(end) {
            end -= 1;
        }
        let bytes = text.as_bytes()[..end].to_vec();
        if bytes.is_empty() {
            return 0;
        }
        if let Some(at) = self.strings.iter().position(|s| *s == bytes) {
            return u8::try_from(at + 1).unwrap_or(0);
        }
        if self.strings.len() == 255 {
            return 0;
        }
        self.strings.push(bytes);
        u8::try_from(self.strings.len()).unwrap_or(0)
    }

    /// The category's data: the count, then each string after its length.
    fn emit(&self) -> Vec<u8> {
        let mut data = vec![self.strings.len() as u8];
        for s in &self.strings {
            data.push(s.len() as u8);
            data.extend_from_slice(s);
        }
        data
    }
}

/// Appends a category (padded to whole words).
fn push_category(image: &mut Vec<u8>, kind: u16, data: &[u8]) {
    let words = data.len().div_ceil(2);
    image.extend_from_slice(&kind.to_le_bytes());
    image.extend_from_slice(&u16::try_from(words).unwrap_or(u16::MAX).to_le_bytes());
    image.extend_from_slice(data);
    if data.len() % 2 == 1 {
        image.push(0);
    }
}

fn put_u16(image: &mut [u8], word: usize, value: u16) {
    image[word * 2..word * 2 + 2].copy_from_slice(&value.to_le_bytes());
}

fn put_u32(image: &mut [u8], word: usize, value: u32) {
    image[word * 2..word * 2 + 4].copy_from_slice(&value.to_le_bytes());
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc8_is_etg2010s() {
        // The CRC-8 with these parameters has the check value 0xFB for "123456789" (computed apart, in Python).
        assert_eq!(crc8(b"123456789"), 0xFB);
        assert_eq!(crc8(&[]), 0xFF);
    }
}
