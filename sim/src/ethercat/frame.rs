//! EtherCAT frames as a MainDevice (or a test) builds and reads them, with the runtime's wire
//! views ([`edsgen_runtime::ethercat::wire`]): [`FrameBuilder`] appends datagrams, [`parse`]
//! lists where each datagram of an answered frame lies.

use std::ops::Range;

use edsgen_runtime::ethercat::wire::datagram::{self, Datagram as View, DatagramRepr};
use edsgen_runtime::ethercat::wire::frame::{Frame, FrameRepr, DATAGRAMS_AT, MIN_FRAME_LEN};

pub use edsgen_runtime::ethercat::wire::datagram::{Command, MAX_DATA_LEN};

/// Where one datagram lies in a frame.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Datagram {
    /// Its header.
    pub header: DatagramRepr,
    /// Where its header starts.
    pub header_at: usize,
    /// Its data.
    pub data: Range<usize>,
    /// Its working counter (2 bytes).
    pub wkc_at: usize,
}

/// What a frame holds, as [`parse`] finds it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Parsed {
    /// Not an EtherCAT frame (another EtherType, a runt, another EtherCAT type).
    NotEtherCat,
    /// An EtherCAT frame: the datagrams that are whole, in order, and whether the list ended
    /// early at a malformed one.
    Datagrams {
        /// The whole datagrams.
        datagrams: Vec<Datagram>,
        /// Whether a malformed datagram cut the list short.
        truncated: bool,
    },
}

/// Finds the datagrams of an Ethernet frame.
pub fn parse(frame: &[u8]) -> Parsed {
    let Ok(view) = Frame::new_checked(frame) else {
        return Parsed::NotEtherCat;
    };
    let mut cursor = view.datagrams();
    let mut datagrams = Vec::new();
    while let Some(place) = cursor.next(frame) {
        let Ok(place) = place else {
            return Parsed::Datagrams {
                datagrams,
                truncated: true,
            };
        };
        let header = DatagramRepr::parse(&View::new_unchecked(&frame[place.clone()]));
        let data_at = place.start + datagram::HEADER_LEN;
        let wkc_at = place.end - datagram::WKC_LEN;
        datagrams.push(Datagram {
            header,
            header_at: place.start,
            data: data_at..wkc_at,
            wkc_at,
        });
    }
    Parsed::Datagrams {
        datagrams,
        truncated: false,
    }
}

/// The working counter of the datagram at `datagram` in `frame`.
pub fn wkc(frame: &[u8], datagram: &Datagram) -> u16 {
    View::new_unchecked(&frame[datagram.header_at..]).wkc()
}

/// Builds an EtherCAT frame datagram by datagram, as a MainDevice sends it.
#[derive(Debug, Clone)]
pub struct FrameBuilder {
    bytes: Vec<u8>,
    source: [u8; 6],
    last_header_at: Option<usize>,
}

impl FrameBuilder {
    /// An empty frame from `source` to the broadcast address.
    pub fn new(source: [u8; 6]) -> Self {
        FrameBuilder {
            bytes: vec![0; DATAGRAMS_AT],
            source,
            last_header_at: None,
        }
    }

    /// Appends a datagram with `data` (cut to [`MAX_DATA_LEN`]) and working counter `wkc` (0 as
    /// a master sends it).
    pub fn datagram(
        mut self,
        command: Command,
        index: u8,
        address: (u16, u16),
        data: &[u8],
        wkc: u16,
    ) -> Self {
        if let Some(at) = self.last_header_at {
            View::new_unchecked(&mut self.bytes[at..]).set_more(true);
        }
        let data = &data[..data.len().min(MAX_DATA_LEN)];
        let header = DatagramRepr {
            command: command.code(),
            index,
            adp: address.0,
            ado: address.1,
            len: data.len() as u16,
            circulating: false,
            more: false,
            irq: 0,
        };
        let at = self.bytes.len();
        self.last_header_at = Some(at);
        self.bytes.resize(
            at + datagram::HEADER_LEN + data.len() + datagram::WKC_LEN,
            0,
        );
        let _ = header.emit(&mut self.bytes[at..]);
        let mut view = View::new_unchecked(&mut self.bytes[at..]);
        view.data_mut().copy_from_slice(data);
        view.set_wkc(wkc);
        self
    }

    /// The frame's bytes, the EtherCAT header's length set (padded to Ethernet's 60 bytes).
    pub fn build(mut self) -> Vec<u8> {
        let repr = FrameRepr {
            destination: [0xFF; 6],
            source: self.source,
            datagrams_len: self.bytes.len() - DATAGRAMS_AT,
        };
        let _ = repr.emit(&mut self.bytes);
        self.bytes.resize(self.bytes.len().max(MIN_FRAME_LEN), 0);
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
            .datagram(Command::Fpwr, 8, (0x1001, 0x0120), &[2, 0], 3)
            .build();
        assert_eq!(
            frame[..30],
            [
                0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x10, 0x10, 0x10, 0x10, 0x10,
                0x10, // MACs
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
        assert_eq!(wkc(&frame, &datagrams[1]), 3);
        assert!(!datagrams[1].header.more);
        assert_eq!(frame.len(), 60);
    }

    #[test]
    fn a_datagram_longer_than_the_frame_ends_the_list() {
        let mut frame = FrameBuilder::new(MAC)
            .datagram(Command::Brd, 1, (0, 0), &[0; 2], 0)
            .datagram(Command::Brd, 2, (0, 0), &[0; 2], 0)
            .build();
        frame[30 + 6] = 100; // the second datagram claims 100 bytes
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
        frame[13] = 0;
        assert_eq!(parse(&frame), Parsed::NotEtherCat);
    }
}
