//! EtherCAT wire formats as views (ETG.1000.4, ETG.1000.6), no_std and allocation-free: the
//! Ethernet frame with its EtherCAT header and the cursor over its datagrams ([`frame`]), one
//! datagram's header, data and working counter ([`datagram`]), the mailbox header ([`mailbox`])
//! and the CoE header ([`coe`]). Each is a smoltcp-style `Packet<T: AsRef<[u8]>>` view that
//! checks its length once, plus a `Repr` that parses and emits into the caller's buffer; nothing
//! here panics on any input. The SDO inside a CoE message is CiA 301's ([`crate::wire::sdo`]).

pub mod coe;
pub mod datagram;
pub mod frame;
pub mod mailbox;

/// Why bytes are not the message a view expects.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WireError {
    /// Too short for the header, or a length field that runs past the bytes.
    Truncated,
    /// A field holds a value the format does not allow here (another EtherType, another
    /// EtherCAT type, a length that does not fit its field).
    Malformed,
}

/// The little-endian u16 at `at` (callers have checked the length).
fn le16(bytes: &[u8], at: usize) -> u16 {
    match bytes.get(at..at + 2) {
        Some(&[a, b]) => u16::from_le_bytes([a, b]),
        _ => 0,
    }
}

/// Writes `value` little-endian at `at` (callers have checked the length).
fn set_le16(bytes: &mut [u8], at: usize, value: u16) {
    if let Some(field) = bytes.get_mut(at..at + 2) {
        field.copy_from_slice(&value.to_le_bytes());
    }
}
