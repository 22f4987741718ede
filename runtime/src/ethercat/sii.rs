//! The SII (the ESC's EEPROM) as a device's firmware reads it through its ESC's EEPROM
//! interface (registers 0x0500–0x050F, ETG.1000.4 §6.4), and what the SubDevice core takes
//! from it ([`Sii`]): the identity (words 8–0x0D) and the SyncManager layout (category 41,
//! SyncM: one 8-byte entry per SyncManager, its type in the last byte).
//!
//! The PDI reads the SII only while the master offers it (0x0500 bit 0 set, bit 1 "force
//! ECAT" clear), as SOEM and ethercrab do before they request Pre-Op: it takes the SII (0x0501
//! bit 0), writes the word address (0x0504) and the read command (0x0502 bit 8), waits while
//! busy (bit 15), reads 4 or 8 bytes (bit 6) from 0x0508 and gives the SII back.

use super::esc::{reg, Esc};
use super::subdevice::Layout;
use super::Identity;

/// Why the SII could not be read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SiiError {
    /// The master has not offered the SII to the PDI (AL status code 0x0050).
    NoAccess,
    /// The ESC reported an error, stayed busy, or the image's categories run on without end
    /// (AL status code 0x0051).
    Failed,
}

/// What the SubDevice core reads from the SII.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Sii {
    /// Vendor ID, product code and revision (words 8, 0x0A, 0x0C).
    pub identity: Identity,
    /// The SyncManagers by the types the SyncM category gives them.
    pub layout: Layout,
}

/// Control/status bits of 0x0502.
const READ_COMMAND: u16 = 0x0100;
const EIGHT_BYTE_READS: u16 = 0x0040;
const ACKNOWLEDGE_ERROR: u16 = 0x2000;
const BUSY: u16 = 0x8000;
/// How many times the status is read before a busy ESC counts as failed.
const BUSY_POLLS: usize = 10_000;
/// Where the categories start, how many are walked at most.
const CATEGORIES: u32 = 0x40;
const MAX_CATEGORIES: usize = 256;
const SYNC_M: u16 = 41;
const END: u16 = 0xFFFF;

/// Reads the identity and the SyncManager layout from the SII, taking it from the master and
/// giving it back.
pub fn read<E: Esc + ?Sized>(esc: &mut E) -> Result<Sii, SiiError> {
    if esc.read_u8(reg::SII_CONFIG) & 0x03 != 0x01 {
        return Err(SiiError::NoAccess);
    }
    esc.write_u8(reg::SII_PDI_ACCESS, 1);
    if esc.read_u8(reg::SII_PDI_ACCESS) & 1 == 0 {
        return Err(SiiError::NoAccess);
    }
    let sii = read_held(esc);
    esc.write_u8(reg::SII_PDI_ACCESS, 0);
    sii
}

/// [`read`] while the PDI holds the SII.
fn read_held<E: Esc + ?Sized>(esc: &mut E) -> Result<Sii, SiiError> {
    // Vendor ID, product code and revision: words 8 to 0x0D, read at once.
    let mut words = [0u8; 12];
    read_words(esc, 0x08, &mut words)?;
    let u32_at =
        |i: usize| u32::from_le_bytes([words[i], words[i + 1], words[i + 2], words[i + 3]]);
    let identity = Identity {
        vendor_id: u32_at(0),
        product_code: u32_at(4),
        revision: u32_at(8),
    };
    let mut layout = Layout::default();
    let mut at = CATEGORIES;
    for _ in 0..MAX_CATEGORIES {
        let mut header = [0u8; 4];
        read_words(esc, at, &mut header)?;
        let kind = u16::from_le_bytes([header[0], header[1]]);
        let len = u16::from_le_bytes([header[2], header[3]]);
        if kind == END {
            return Ok(Sii {
                identity,
                layout: layout.paired(),
            });
        }
        if kind == SYNC_M {
            for n in 0..usize::from(len) / 4 {
                let mut entry = [0u8; 8];
                read_words(esc, at + 2 + 4 * n as u32, &mut entry)?;
                layout.add(n, entry);
            }
        }
        at = at.wrapping_add(2 + u32::from(len));
    }
    Err(SiiError::Failed)
}

/// Reads `buf.len()` bytes (an even number) from SII word `address` on.
fn read_words<E: Esc + ?Sized>(esc: &mut E, address: u32, buf: &mut [u8]) -> Result<(), SiiError> {
    let mut done = 0;
    while done < buf.len() {
        let word = address.wrapping_add((done / 2) as u32);
        esc.write(reg::SII_ADDRESS, &word.to_le_bytes());
        esc.write_u16(reg::SII_CONTROL, READ_COMMAND);
        let status = (0..BUSY_POLLS)
            .map(|_| esc.read_u16(reg::SII_CONTROL))
            .find(|status| status & BUSY == 0)
            .ok_or(SiiError::Failed)?;
        if status & ACKNOWLEDGE_ERROR != 0 {
            return Err(SiiError::Failed);
        }
        let chunk = if status & EIGHT_BYTE_READS != 0 { 8 } else { 4 };
        let take = chunk.min(buf.len() - done);
        esc.read(reg::SII_DATA, &mut buf[done..done + take]);
        done += take;
    }
    Ok(())
}

impl Layout {
    /// Takes SyncManager `n`'s SyncM entry (start, length, control, status, enable, type):
    /// type 1 mailbox out, 2 mailbox in, 3 outputs, 4 inputs. The mailboxes count only as a
    /// pair.
    fn add(&mut self, n: usize, entry: [u8; 8]) {
        let start = u16::from_le_bytes([entry[0], entry[1]]);
        let len = u16::from_le_bytes([entry[2], entry[3]]);
        match entry[7] {
            1 => self.mailbox_out = Some((n, start, len)),
            2 => self.mailbox_in = Some((n, start, len)),
            3 => self.outputs = Some(n),
            4 => self.inputs = Some(n),
            _ => {}
        }
    }

    /// The mailboxes only as a pair: a device with one of them has none.
    fn paired(mut self) -> Self {
        if self.mailbox_out.is_none() || self.mailbox_in.is_none() {
            self.mailbox_out = None;
            self.mailbox_in = None;
        }
        self
    }
}
