//! The EtherCAT frame (ETG.1000.4 §5.3): an Ethernet frame of EtherType 0x88A4 whose 2-byte
//! EtherCAT header (length in bits 0–10, type in bits 12–15) is followed by datagrams.
//! [`Frame`] views one, [`FrameRepr`] is its headers' fields, and [`Datagrams`] finds the
//! datagrams one after the other without copying them, so that a SubDevice processes each in
//! place and sends the same bytes back.

use core::ops::Range;

use super::datagram::{Datagram, MAX_DATA_LEN};
use super::{le16, set_le16, WireError};

/// The EtherType of EtherCAT frames.
pub const ETHERTYPE: u16 = 0x88A4;
/// The Ethernet header's length (destination, source, EtherType).
pub const ETHERNET_HEADER_LEN: usize = 14;
/// The EtherCAT header's length.
pub const ECAT_HEADER_LEN: usize = 2;
/// Where the first datagram starts.
pub const DATAGRAMS_AT: usize = ETHERNET_HEADER_LEN + ECAT_HEADER_LEN;
/// The EtherCAT header's type for datagrams (the only type a SubDevice processes).
pub const TYPE_DATAGRAMS: u8 = 1;
/// The shortest Ethernet frame without its FCS: shorter frames are padded to it.
pub const MIN_FRAME_LEN: usize = 60;

/// A view over an Ethernet frame carrying EtherCAT datagrams.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Frame<T: AsRef<[u8]>> {
    buffer: T,
}

impl<T: AsRef<[u8]>> Frame<T> {
    /// A view over `buffer` if it is an EtherCAT frame of datagrams: long enough for both
    /// headers ([`WireError::Truncated`]), EtherType 0x88A4 and type 1 ([`WireError::Malformed`]
    /// otherwise: a frame a SubDevice ignores).
    pub fn new_checked(buffer: T) -> Result<Self, WireError> {
        let frame = Frame { buffer };
        if frame.buffer.as_ref().len() < DATAGRAMS_AT {
            return Err(WireError::Truncated);
        }
        if frame.ethertype() != ETHERTYPE || frame.ecat_type() != TYPE_DATAGRAMS {
            return Err(WireError::Malformed);
        }
        Ok(frame)
    }

    /// The bytes under the view.
    pub fn into_inner(self) -> T {
        self.buffer
    }

    /// The frame's bytes.
    pub fn as_bytes(&self) -> &[u8] {
        self.buffer.as_ref()
    }

    /// The destination MAC address.
    pub fn destination(&self) -> [u8; 6] {
        mac(self.as_bytes(), 0)
    }

    /// The source MAC address.
    pub fn source(&self) -> [u8; 6] {
        mac(self.as_bytes(), 6)
    }

    /// The EtherType (big-endian, as Ethernet's).
    pub fn ethertype(&self) -> u16 {
        match self.as_bytes().get(12..14) {
            Some(&[a, b]) => u16::from_be_bytes([a, b]),
            _ => 0,
        }
    }

    /// The EtherCAT header's length: the bytes of datagrams (the rest is Ethernet padding).
    pub fn ecat_length(&self) -> usize {
        usize::from(le16(self.as_bytes(), ETHERNET_HEADER_LEN)) & MAX_DATA_LEN
    }

    /// The EtherCAT header's type.
    pub fn ecat_type(&self) -> u8 {
        (le16(self.as_bytes(), ETHERNET_HEADER_LEN) >> 12) as u8
    }

    /// A cursor over the datagrams.
    pub fn datagrams(&self) -> Datagrams {
        Datagrams {
            at: DATAGRAMS_AT,
            end: self.as_bytes().len().min(DATAGRAMS_AT + self.ecat_length()),
            finished: false,
        }
    }
}

impl<T: AsRef<[u8]> + AsMut<[u8]>> Frame<T> {
    /// Sets the source MAC address (an ESC sets its locally-administered bit on the way back).
    pub fn set_source(&mut self, source: [u8; 6]) {
        if let Some(field) = self.buffer.as_mut().get_mut(6..12) {
            field.copy_from_slice(&source);
        }
    }

    /// The datagram `place` (from [`Datagrams::next`]) holds, to change in place.
    pub fn datagram_mut(&mut self, place: Range<usize>) -> Option<Datagram<&mut [u8]>> {
        let bytes = self.buffer.as_mut().get_mut(place)?;
        Datagram::new_checked(bytes).ok()
    }
}

fn mac(bytes: &[u8], at: usize) -> [u8; 6] {
    let mut out = [0; 6];
    if let Some(field) = bytes.get(at..at + 6) {
        out.copy_from_slice(field);
    }
    out
}

/// Finds the datagrams of a frame one after the other: each one's place in the frame (header
/// to working counter). It ends after the datagram without the "more" flag, or with
/// [`WireError::Truncated`] at a malformed one (a length beyond the frame or the EtherCAT
/// header's length, or a "more" flag with no room for another header); the malformed one and
/// those after it are not to be answered. It borrows nothing, so the frame can be changed
/// between two steps.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Datagrams {
    at: usize,
    end: usize,
    finished: bool,
}

impl Datagrams {
    /// The place of the next datagram of `frame` (the frame this cursor was made from).
    pub fn next(&mut self, frame: &[u8]) -> Option<Result<Range<usize>, WireError>> {
        if self.finished {
            return None;
        }
        let bounded = frame.get(self.at..self.end).unwrap_or_default();
        let Ok(datagram) = Datagram::new_checked(bounded) else {
            self.finished = true;
            return Some(Err(WireError::Truncated));
        };
        let place = self.at..self.at + datagram.total_len();
        self.finished = !datagram.more();
        self.at = place.end;
        Some(Ok(place))
    }
}

/// An EtherCAT frame's headers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FrameRepr {
    /// The destination MAC address.
    pub destination: [u8; 6],
    /// The source MAC address.
    pub source: [u8; 6],
    /// The bytes of datagrams that follow the headers.
    pub datagrams_len: usize,
}

impl FrameRepr {
    /// The headers of `frame`.
    pub fn parse<T: AsRef<[u8]>>(frame: &Frame<T>) -> Self {
        FrameRepr {
            destination: frame.destination(),
            source: frame.source(),
            datagrams_len: frame.ecat_length(),
        }
    }

    /// Writes the Ethernet and EtherCAT headers into the first [`DATAGRAMS_AT`] bytes of
    /// `buffer`.
    pub fn emit(&self, buffer: &mut [u8]) -> Result<(), WireError> {
        if self.datagrams_len > MAX_DATA_LEN {
            return Err(WireError::Malformed);
        }
        let header = buffer.get_mut(..DATAGRAMS_AT).ok_or(WireError::Truncated)?;
        header[..6].copy_from_slice(&self.destination);
        header[6..12].copy_from_slice(&self.source);
        header[12..14].copy_from_slice(&ETHERTYPE.to_be_bytes());
        let word = self.datagrams_len as u16 | (u16::from(TYPE_DATAGRAMS) << 12);
        set_le16(header, ETHERNET_HEADER_LEN, word);
        Ok(())
    }

    /// The frame's length with its datagrams, padded to Ethernet's minimum.
    pub fn frame_len(&self) -> usize {
        (DATAGRAMS_AT + self.datagrams_len).max(MIN_FRAME_LEN)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A BRD of 0x0130 (more follows) and an FPWR of 0x0120 at station 0x1001, padded to 60.
    fn two_datagrams() -> [u8; 60] {
        let mut frame = [0u8; 60];
        let head: [u8; 44] = [
            0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x10, 0x10, 0x10, 0x10, 0x10, 0x10, // MACs
            0x88, 0xA4, 0x1C, 0x10, // EtherType, 28 bytes of datagrams, type 1
            7, 7, 0, 0, 0x30, 0x01, 0x02, 0x80, 0, 0, 0, 0, 0, 0, // BRD, more follows
            5, 8, 0x01, 0x10, 0x20, 0x01, 0x02, 0, 0, 0, 2, 0, 0, 0, // FPWR
        ];
        frame[..44].copy_from_slice(&head);
        frame
    }

    #[test]
    fn the_cursor_finds_both_datagrams() {
        let bytes = two_datagrams();
        let frame = Frame::new_checked(&bytes[..]).unwrap();
        let mut datagrams = frame.datagrams();
        assert_eq!(datagrams.next(&bytes), Some(Ok(16..30)));
        assert_eq!(datagrams.next(&bytes), Some(Ok(30..44)));
        assert_eq!(datagrams.next(&bytes), None);
        let repr = FrameRepr::parse(&frame);
        assert_eq!(repr.datagrams_len, 28);
        let mut out = [0u8; 16];
        repr.emit(&mut out).unwrap();
        assert_eq!(out, bytes[..16]);
        assert_eq!(repr.frame_len(), 60);
    }

    #[test]
    fn other_ethertypes_types_and_runts_are_refused() {
        let mut bytes = two_datagrams();
        assert_eq!(Frame::new_checked(&bytes[..15]), Err(WireError::Truncated));
        bytes[13] = 0x00;
        assert_eq!(Frame::new_checked(&bytes[..]), Err(WireError::Malformed));
        bytes[13] = 0xA4;
        bytes[15] = 0x40; // type 4: network variables
        assert_eq!(Frame::new_checked(&bytes[..]), Err(WireError::Malformed));
    }

    #[test]
    fn a_datagram_longer_than_the_frame_ends_the_list() {
        let mut bytes = two_datagrams();
        bytes[30 + 6] = 100; // the FPWR claims 100 bytes
        let mut datagrams = Frame::new_checked(&bytes[..]).unwrap().datagrams();
        assert_eq!(datagrams.next(&bytes), Some(Ok(16..30)));
        assert_eq!(datagrams.next(&bytes), Some(Err(WireError::Truncated)));
        assert_eq!(datagrams.next(&bytes), None);
    }

    #[test]
    fn the_ethercat_length_bounds_the_datagrams_not_the_padding() {
        let mut bytes = two_datagrams();
        bytes[14] = 14; // only the BRD, but it says "more"
        let mut datagrams = Frame::new_checked(&bytes[..]).unwrap().datagrams();
        assert_eq!(datagrams.next(&bytes), Some(Ok(16..30)));
        assert_eq!(datagrams.next(&bytes), Some(Err(WireError::Truncated)));
    }

    #[test]
    fn a_datagram_is_changed_through_the_frame() {
        let mut bytes = two_datagrams();
        let mut frame = Frame::new_checked(&mut bytes[..]).unwrap();
        let mut datagram = frame.datagram_mut(30..44).unwrap();
        datagram.set_wkc(1);
        frame.set_source([0x12; 6]);
        assert_eq!(frame.datagram_mut(30..43), None);
        assert_eq!(bytes[42..44], [1, 0]);
        assert_eq!(bytes[6..12], [0x12; 6]);
    }
}
