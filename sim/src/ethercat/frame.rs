//! The EtherCAT frame and datagram wire formats (ETG.1000.4): an Ethernet frame of EtherType
//! 0x88A4 whose 2-byte EtherCAT header (length in bits 0–10, type 1 in bits 12–15) is followed by
//! datagrams, each a 10-byte header (command, index, address, length with the "more datagrams
//! follow" flag in bit 15, IRQ), its data and a 16-bit working counter. All fields little-endian
//! except the Ethernet header's.
//!
//! [`parse`] finds the datagrams of a frame without copying them (their places in the frame), so
//! that a SubDevice processes each in place and sends the same bytes back; [`FrameBuilder`]
//! builds a frame, as a MainDevice (or a test) does.

use std::ops::Range;

/// The EtherType of EtherCAT frames.
pub const ETHERTYPE: u16 = 0x88A4;
/// The Ethernet header's length (destination, source, EtherType).
pub const ETHERNET_HEADER_LEN: usize = 14;
/// The EtherCAT header's length.
pub const ECAT_HEADER_LEN: usize = 2;
/// A datagram header's length.
pub const DATAGRAM_HEADER_LEN: usize = 10;
/// The EtherCAT header's type for datagrams (the only type a SubDevice processes).
pub const TYPE_DATAGRAMS: u8 = 1;
/// The longest datagram data the 11-bit length field can say.
pub const MAX_DATA_LEN: usize = 0x7FF;

/// A datagram's command (ETG.1000.4 table 13).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Command {
    /// No operation.
    Nop,
    /// Auto-increment physical read.
    Aprd,
    /// Auto-increment physical write.
    Apwr,
    /// Auto-increment physical read-write.
    Aprw,
    /// Configured address physical read.
    Fprd,
    /// Configured address physical write.
    Fpwr,
    /// Configured address physical read-write.
    Fprw,
    /// Broadcast read.
    Brd,
    /// Broadcast write.
    Bwr,
    /// Broadcast read-write.
    Brw,
    /// Logical read.
    Lrd,
    /// Logical write.
    Lwr,
    /// Logical read-write.
    Lrw,
    /// Auto-increment physical read, multiple write.
    Armw,
    /// Configured address physical read, multiple write.
    Frmw,
}

impl Command {
    /// The command its code names, if any.
    pub fn from_code(code: u8) -> Option<Command> {
        use Command::*;
        Some(match code {
            0 => Nop,
            1 => Aprd,
            2 => Apwr,
            3 => Aprw,
            4 => Fprd,
            5 => Fpwr,
            6 => Fprw,
            7 => Brd,
            8 => Bwr,
            9 => Brw,
            10 => Lrd,
            11 => Lwr,
            12 => Lrw,
            13 => Armw,
            14 => Frmw,
            _ => return None,
        })
    }

    /// The command's code on the wire.
    pub fn code(self) -> u8 {
        use Command::*;
        match self {
            Nop => 0,
            Aprd => 1,
            Apwr => 2,
            Aprw => 3,
            Fprd => 4,
            Fpwr => 5,
            Fprw => 6,
            Brd => 7,
            Bwr => 8,
            Brw => 9,
            Lrd => 10,
            Lwr => 11,
            Lrw => 12,
            Armw => 13,
            Frmw => 14,
        }
    }
}

/// One datagram's header, as read from a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Header {
    /// The command code (kept raw: an unknown code is a datagram no SubDevice answers).
    pub command: u8,
    /// The index the master matches replies by.
    pub index: u8,
    /// ADP (position or station address) for physical commands, the low half of the logical
    /// address for logical ones.
    pub adp: u16,
    /// ADO (register or memory address) for physical commands, the high half of the logical
    /// address for logical ones.
    pub ado: u16,
    /// The data length in bytes.
    pub len: u16,
    /// Bit 14 of the length word: the frame has circulated (a ring was broken).
    pub circulating: bool,
    /// Bit 15 of the length word: another datagram follows.
    pub more: bool,
    /// The IRQ field.
    pub irq: u16,
}

impl Header {
    /// The 32-bit logical address of a logical command.
    pub fn logical_address(&self) -> u32 {
        u32::from(self.adp) | (u32::from(self.ado) << 16)
    }

    /// The header's 10 bytes.
    pub fn emit(&self) -> [u8; DATAGRAM_HEADER_LEN] {
        let mut out = [0u8; DATAGRAM_HEADER_LEN];
        out[0] = self.command;
        out[1] = self.index;
        out[2..4].copy_from_slice(&self.adp.to_le_bytes());
        out[4..6].copy_from_slice(&self.ado.to_le_bytes());
        let len_word = (self.len & MAX_DATA_LEN as u16)
            | if self.circulating { 0x4000 } else { 0 }
            | if self.more { 0x8000 } else { 0 };
        out[6..8].copy_from_slice(&len_word.to_le_bytes());
        out[8..10].copy_from_slice(&self.irq.to_le_bytes());
        out
    }

    /// Reads a header from its 10 bytes.
    pub fn parse(bytes: &[u8; DATAGRAM_HEADER_LEN]) -> Header {
        let word = |at: usize| u16::from_le_bytes([bytes[at], bytes[at + 1]]);
        let len_word = word(6);
        Header {
            command: bytes[0],
            index: bytes[1],
            adp: word(2),
            ado: word(4),
            len: len_word & MAX_DATA_LEN as u16,
            circulating: len_word & 0x4000 != 0,
            more: len_word & 0x8000 != 0,
            irq: word(8),
        }
    }
}

/// Where one datagram lies in a frame.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Datagram {
    /// Its header.
    pub header: Header,
    /// Where its header starts (the ADP is rewritten in place by auto-increment commands).
    pub header_at: usize,
    /// Its data.
    pub data: Range<usize>,
    /// Its working counter (2 bytes).
    pub wkc_at: usize,
}

/// What a frame holds, as [`parse`] finds it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Parsed {
    /// Not an EtherCAT frame (another EtherType, a runt, another EtherCAT type): ignored.
    NotEtherCat,
    /// An EtherCAT frame: the datagrams that are whole, in order, and whether the list ended
    /// early at a malformed one (a length beyond the frame or the EtherCAT header's length, or
    /// a "more" flag with no room for another header). The malformed one and those after it
    /// are not answered.
    Datagrams {
        /// The whole datagrams.
        datagrams: Vec<Datagram>,
        /// Whether a malformed datagram cut the list short.
        truncated: bool,
    },
}

/// Finds the datagrams of an Ethernet frame.
pub fn parse(frame: &[u8]) -> Parsed {
    if frame.len() < ETHERNET_HEADER_LEN + ECAT_HEADER_LEN
        || u16::from_be_bytes([frame[12], frame[13]]) != ETHERTYPE
    {
        return Parsed::NotEtherCat;
    }
    let ecat = u16::from_le_bytes([frame[14], frame[15]]);
    if (ecat >> 12) as u8 != TYPE_DATAGRAMS {
        return Parsed::NotEtherCat;
    }
    let start = ETHERNET_HEADER_LEN + ECAT_HEADER_LEN;
    // The EtherCAT header's length bounds the datagrams (the rest is Ethernet padding).
    let end = frame
        .len()
        .min(start + usize::from(ecat & MAX_DATA_LEN as u16));
    let mut datagrams = Vec::new();
    let mut at = start;
    loop {
        let Some(header_bytes) = frame
            .get(at..at + DATAGRAM_HEADER_LEN)
            .filter(|_| at + DATAGRAM_HEADER_LEN <= end)
        else {
            return Parsed::Datagrams {
                datagrams,
                truncated: true,
            };
        };
        let mut bytes = [0u8; DATAGRAM_HEADER_LEN];
        bytes.copy_from_slice(header_bytes);
        let header = Header::parse(&bytes);
        let data_at = at + DATAGRAM_HEADER_LEN;
        let wkc_at = data_at + usize::from(header.len);
        if wkc_at + 2 > end {
            return Parsed::Datagrams {
                datagrams,
                truncated: true,
            };
        }
        datagrams.push(Datagram {
            header,
            header_at: at,
            data: data_at..wkc_at,
            wkc_at,
        });
        if !header.more {
            return Parsed::Datagrams {
                datagrams,
                truncated: false,
            };
        }
        at = wkc_at + 2;
    }
}

/// The working counter of the datagram at `datagram` in `frame`.
pub fn wkc(frame: &[u8], datagram: &Datagram) -> u16 {
    u16::from_le_bytes([frame[datagram.wkc_at], frame[datagram.wkc_at + 1]])
}

/// Builds an EtherCAT frame datagram by datagram, as a MainDevice sends it.
#[derive(Debug, Clone)]
pub struct FrameBuilder {
    bytes: Vec<u8>,
    last_header_at: Option<usize>,
}

impl FrameBuilder {
    /// An empty frame from `source` to the broadcast address.
    pub fn new(source: [u8; 6]) -> Self {
        let mut bytes = vec![0xFF; 6];
        bytes.extend_from_slice(&source);
        bytes.extend_from_slice(&ETHERTYPE.to_be_bytes());
        bytes.extend_from_slice(&[0, 0]);
        FrameBuilder {
            bytes,
            last_header_at: None,
        }
    }

    /// Appends a datagram with `data` and working counter `wkc` (0 as a master sends it).
    pub fn datagram(
        mut self,
        command: Command,
        index: u8,
        address: (u16, u16),
        data: &[u8],
        wkc: u16,
    ) -> Self {
        if let Some(at) = self.last_header_at {
            self.bytes[at + 7] |= 0x80;
        }
        let header = Header {
            command: command.code(),
            index,
            adp: address.0,
            ado: address.1,
            len: data.len().min(MAX_DATA_LEN) as u16,
            circulating: false,
            more: false,
            irq: 0,
        };
        self.last_header_at = Some(self.bytes.len());
        self.bytes.extend_from_slice(&header.emit());
        self.bytes
            .extend_from_slice(&data[..data.len().min(MAX_DATA_LEN)]);
        self.bytes.extend_from_slice(&wkc.to_le_bytes());
        self
    }

    /// The frame's bytes, the EtherCAT header's length set (padded to Ethernet's 60 bytes).
    pub fn build(mut self) -> Vec<u8> {
        let len = (self.bytes.len() - ETHERNET_HEADER_LEN - ECAT_HEADER_LEN) as u16;
        let ecat = (len & MAX_DATA_LEN as u16) | (u16::from(TYPE_DATAGRAMS) << 12);
        self.bytes[14..16].copy_from_slice(&ecat.to_le_bytes());
        if self.bytes.len() < 60 {
            self.bytes.resize(60, 0);
        }
        self.bytes
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MAC: [u8; 6] = [0x10; 6];

    #[test]
    fn a_frame_of_two_datagrams_round_trips() {
        let frame = FrameBuilder::new(MAC)
            .datagram(Command::Brd, 7, (0, 0x0130), &[0, 0], 0)
            .datagram(Command::Fpwr, 8, (0x1001, 0x0120), &[2, 0], 0)
            .build();
        assert_eq!(
            frame[12..30],
            [
                0x88, 0xA4, // EtherType
                0x1C, 0x10, // 28 bytes of datagrams, type 1
                7, 7, 0, 0, 0x30, 0x01, 0x02, 0x80, 0, 0, // BRD, more follows
                0, 0, 0, 0, // data, WKC
            ]
        );
        let Parsed::Datagrams {
            datagrams,
            truncated,
        } = parse(&frame)
        else {
            panic!("not EtherCAT");
        };
        assert!(!truncated);
        assert_eq!(datagrams.len(), 2);
        assert_eq!(datagrams[0].header.command, 7);
        assert!(datagrams[0].header.more);
        assert_eq!(datagrams[1].header.adp, 0x1001);
        assert_eq!(datagrams[1].header.ado, 0x0120);
        assert_eq!(datagrams[1].data, 40..42);
        assert_eq!(datagrams[1].wkc_at, 42);
        assert!(!datagrams[1].header.more);
        assert_eq!(frame.len(), 60);
    }

    #[test]
    fn other_ethertypes_and_runts_are_not_ethercat() {
        let mut frame = FrameBuilder::new(MAC)
            .datagram(Command::Nop, 0, (0, 0), &[], 0)
            .build();
        assert_eq!(parse(&frame[..15]), Parsed::NotEtherCat);
        frame[13] = 0x00;
        assert_eq!(parse(&frame), Parsed::NotEtherCat);
        frame[13] = 0xA4;
        frame[15] = 0x40; // type 4: network variables
        assert_eq!(parse(&frame), Parsed::NotEtherCat);
    }

    #[test]
    fn a_datagram_longer_than_the_frame_ends_the_list() {
        let mut frame = FrameBuilder::new(MAC)
            .datagram(Command::Brd, 1, (0, 0), &[0; 2], 0)
            .datagram(Command::Brd, 2, (0, 0), &[0; 2], 0)
            .build();
        // The second datagram claims 100 bytes.
        frame[30 + 6] = 100;
        let Parsed::Datagrams {
            datagrams,
            truncated,
        } = parse(&frame)
        else {
            panic!("not EtherCAT");
        };
        assert!(truncated);
        assert_eq!(datagrams.len(), 1);
        assert_eq!(datagrams[0].header.index, 1);
    }

    #[test]
    fn the_ethercat_length_bounds_the_datagrams_not_the_padding() {
        let mut frame = FrameBuilder::new(MAC)
            .datagram(Command::Brd, 1, (0, 0), &[0; 2], 0)
            .build();
        // "More follows" with only Ethernet padding after it: malformed.
        frame[16 + 7] |= 0x80;
        assert_eq!(
            parse(&frame),
            Parsed::Datagrams {
                datagrams: vec![Datagram {
                    header: Header {
                        command: 7,
                        index: 1,
                        adp: 0,
                        ado: 0,
                        len: 2,
                        circulating: false,
                        more: true,
                        irq: 0
                    },
                    header_at: 16,
                    data: 26..28,
                    wkc_at: 28
                }],
                truncated: true
            }
        );
    }

    #[test]
    fn every_command_code_round_trips() {
        for code in 0..=14 {
            assert_eq!(Command::from_code(code).map(Command::code), Some(code));
        }
        assert_eq!(Command::from_code(15), None);
        assert_eq!(Command::from_code(0xFF), None);
    }
}
