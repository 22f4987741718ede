//! PROFINET wire formats, apart from the protocol machines: the Ethernet header (with or without
//! a VLAN tag) that carries every PROFINET frame on EtherType 0x8892, the DCP PDU ([`dcp`]) and
//! the cyclic RT frame ([`rt`]), the DCE/RPC PDU of connection management ([`rpc`]) and the PNIO
//! blocks it carries ([`blocks`]), the alarm frames of the AlarmCR ([`alarm`]).
//! Parsing never panics: a frame too short or of another EtherType is `None`.

pub mod alarm;
pub mod blocks;
pub mod dcp;
pub mod rpc;
pub mod rt;

/// PROFINET's EtherType.
pub const ETHERTYPE_PROFINET: u16 = 0x8892;
/// The VLAN tag's EtherType.
pub const ETHERTYPE_VLAN: u16 = 0x8100;

/// A MAC address.
pub type Mac = [u8; 6];

/// An Ethernet frame's header and where its payload starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Ethernet {
    /// Destination address.
    pub dst: Mac,
    /// Source address.
    pub src: Mac,
    /// The VLAN tag's TCI, when the frame has one.
    pub vlan: Option<u16>,
    /// The EtherType after any VLAN tag.
    pub ethertype: u16,
    /// The payload's offset in the frame.
    pub payload: usize,
}

impl Ethernet {
    /// Reads the header; `None` for a frame shorter than its header.
    pub fn parse(frame: &[u8]) -> Option<Ethernet> {
        let mac = |at: usize| -> Option<Mac> { frame.get(at..at + 6)?.try_into().ok() };
        let word = |at: usize| -> Option<u16> {
            Some(u16::from_be_bytes(frame.get(at..at + 2)?.try_into().ok()?))
        };
        let (dst, src) = (mac(0)?, mac(6)?);
        let first = word(12)?;
        let (vlan, ethertype, payload) = if first == ETHERTYPE_VLAN {
            (Some(word(14)?), word(16)?, 18)
        } else {
            (None, first, 14)
        };
        Some(Ethernet {
            dst,
            src,
            vlan,
            ethertype,
            payload,
        })
    }

    /// A PROFINET frame's header bytes, untagged (14 bytes).
    pub fn emit(dst: Mac, src: Mac, out: &mut Vec<u8>) {
        out.extend_from_slice(&dst);
        out.extend_from_slice(&src);
        out.extend_from_slice(&ETHERTYPE_PROFINET.to_be_bytes());
    }
}

/// Pads a frame to Ethernet's 60-byte minimum (without FCS), as a driver sends it.
pub fn pad(frame: &mut Vec<u8>) {
    if frame.len() < 60 {
        frame.resize(60, 0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tagged_and_untagged_headers() {
        let mut f = vec![
            1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 0x88, 0x92, 0xFE, 0xFE,
        ];
        let e = Ethernet::parse(&f).expect("a header");
        assert_eq!((e.vlan, e.ethertype, e.payload), (None, 0x8892, 14));
        f.splice(12..12, [0x81, 0x00, 0xA0, 0x00]);
        let e = Ethernet::parse(&f).expect("a header");
        assert_eq!((e.vlan, e.ethertype, e.payload), (Some(0xA000), 0x8892, 18));
        assert_eq!(Ethernet::parse(&f[..13]), None);
        assert_eq!(Ethernet::parse(&f[..16]), None);
    }
}
