//! PROFINET wire formats, apart from the protocol machines: the Ethernet header (with or without
//! a VLAN tag) that carries every PROFINET frame on EtherType 0x8892 ([`EthernetFrame`],
//! [`Ethernet`]), the DCP PDU ([`dcp`]), the cyclic RT frame ([`rt`]) and the DCE/RPC PDU of
//! connection management ([`rpc`]) and the framing of the PNIO blocks it carries ([`block`]): the
//! Connect's ([`connect`]), record access and control ([`records`]); the AlarmCR's frames
//! ([`alarm`]). Parsing never panics:
//! a frame too short or of another EtherType is `None`; emitting writes into the caller's buffer
//! and returns the length, or [`BufferTooSmall`].

pub mod alarm;
pub mod block;
pub mod connect;
pub mod dcp;
pub mod records;
pub mod rpc;
pub mod rt;

/// PROFINET's EtherType.
pub const ETHERTYPE_PROFINET: u16 = 0x8892;
/// The VLAN tag's EtherType.
pub const ETHERTYPE_VLAN: u16 = 0x8100;
/// Ethernet's shortest frame without FCS: shorter frames are padded to it.
pub const MIN_FRAME_LEN: usize = 60;
/// The untagged header's length.
pub const HEADER_LEN: usize = 14;

/// A MAC address.
pub type Mac = [u8; 6];

/// The caller's buffer is too small for what is emitted.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BufferTooSmall;

/// A checked view of an Ethernet frame: at least its header (18 bytes with a VLAN tag).
#[derive(Debug, Clone, Copy)]
pub struct EthernetFrame<T: AsRef<[u8]>> {
    buffer: T,
}

impl<T: AsRef<[u8]>> EthernetFrame<T> {
    /// The view, or `None` when `buffer` is shorter than the header it starts.
    pub fn new_checked(buffer: T) -> Option<Self> {
        let bytes = buffer.as_ref();
        let tagged = bytes.get(12..14)? == ETHERTYPE_VLAN.to_be_bytes();
        bytes.get(..if tagged { 18 } else { HEADER_LEN })?;
        Some(EthernetFrame { buffer })
    }

    fn word(&self, at: usize) -> u16 {
        let b = self.buffer.as_ref();
        u16::from_be_bytes([b[at], b[at + 1]])
    }

    fn mac(&self, at: usize) -> Mac {
        let mut mac = [0; 6];
        mac.copy_from_slice(&self.buffer.as_ref()[at..at + 6]);
        mac
    }

    /// Destination address.
    pub fn dst(&self) -> Mac {
        self.mac(0)
    }

    /// Source address.
    pub fn src(&self) -> Mac {
        self.mac(6)
    }

    /// The VLAN tag's TCI, when the frame has one.
    pub fn vlan(&self) -> Option<u16> {
        (self.word(12) == ETHERTYPE_VLAN).then(|| self.word(14))
    }

    /// The EtherType after any VLAN tag.
    pub fn ethertype(&self) -> u16 {
        self.word(self.header_len() - 2)
    }

    /// The header's length: 14, or 18 with a VLAN tag.
    pub fn header_len(&self) -> usize {
        if self.word(12) == ETHERTYPE_VLAN {
            18
        } else {
            HEADER_LEN
        }
    }

    /// The bytes after the header.
    pub fn payload(&self) -> &[u8] {
        &self.buffer.as_ref()[self.header_len()..]
    }
}

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
        EthernetFrame::new_checked(frame).map(|f| Ethernet::from_frame(&f))
    }

    /// The header of a checked frame.
    pub fn from_frame<T: AsRef<[u8]>>(frame: &EthernetFrame<T>) -> Ethernet {
        Ethernet {
            dst: frame.dst(),
            src: frame.src(),
            vlan: frame.vlan(),
            ethertype: frame.ethertype(),
            payload: frame.header_len(),
        }
    }

    /// Writes a PROFINET frame's header, untagged, at the start of `buf`; its length (14).
    pub fn emit(dst: Mac, src: Mac, buf: &mut [u8]) -> Result<usize, BufferTooSmall> {
        let out = buf.get_mut(..HEADER_LEN).ok_or(BufferTooSmall)?;
        out[..6].copy_from_slice(&dst);
        out[6..12].copy_from_slice(&src);
        out[12..].copy_from_slice(&ETHERTYPE_PROFINET.to_be_bytes());
        Ok(HEADER_LEN)
    }
}

/// The length a frame of `len` bytes goes out with: at least Ethernet's 60 (without FCS); the
/// bytes up to it must be zero.
pub fn padded_len(len: usize) -> usize {
    len.max(MIN_FRAME_LEN)
}

/// Writes `bytes` at `at` in `buf`; the offset after them.
pub(crate) fn put(buf: &mut [u8], at: usize, bytes: &[u8]) -> Result<usize, BufferTooSmall> {
    let end = at.checked_add(bytes.len()).ok_or(BufferTooSmall)?;
    buf.get_mut(at..end)
        .ok_or(BufferTooSmall)?
        .copy_from_slice(bytes);
    Ok(end)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tagged_and_untagged_headers() {
        let mut f = [0u8; 20];
        f[..16].copy_from_slice(&[
            1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 0x88, 0x92, 0xFE, 0xFE,
        ]);
        let e = Ethernet::parse(&f[..16]).expect("a header");
        assert_eq!((e.vlan, e.ethertype, e.payload), (None, 0x8892, 14));
        assert_eq!(e.dst, [1, 2, 3, 4, 5, 6]);
        assert_eq!(e.src, [7, 8, 9, 10, 11, 12]);
        f.copy_within(12..16, 16);
        f[12..16].copy_from_slice(&[0x81, 0x00, 0xA0, 0x00]);
        let e = Ethernet::parse(&f).expect("a header");
        assert_eq!((e.vlan, e.ethertype, e.payload), (Some(0xA000), 0x8892, 18));
        assert_eq!(
            EthernetFrame::new_checked(&f[..]).unwrap().payload(),
            [0xFE, 0xFE]
        );
        assert_eq!(Ethernet::parse(&f[..13]), None);
        assert_eq!(Ethernet::parse(&f[..16]), None);
    }

    #[test]
    fn header_emitted_untagged() {
        let mut buf = [0u8; 14];
        assert_eq!(Ethernet::emit([1; 6], [2; 6], &mut buf), Ok(14));
        assert_eq!(buf, [1, 1, 1, 1, 1, 1, 2, 2, 2, 2, 2, 2, 0x88, 0x92]);
        assert_eq!(
            Ethernet::emit([1; 6], [2; 6], &mut buf[..13]),
            Err(BufferTooSmall)
        );
        assert_eq!((padded_len(20), padded_len(61)), (60, 61));
    }
}
