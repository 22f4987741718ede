//! One EtherCAT datagram (ETG.1000.4 §5.4): a 10-byte header (command, index, address, length
//! with the "circulating" and "more datagrams follow" flags, IRQ), its data and a 16-bit working
//! counter, all little-endian. [`Datagram`] is the view a SubDevice processes in place;
//! [`DatagramRepr`] the header's fields; [`Command`] the command codes.

use super::{le16, set_le16, WireError};

/// A datagram header's length.
pub const HEADER_LEN: usize = 10;
/// The working counter's length.
pub const WKC_LEN: usize = 2;
/// The longest datagram data the 11-bit length field can say.
pub const MAX_DATA_LEN: usize = 0x7FF;

const CIRCULATING: u16 = 0x4000;
const MORE: u16 = 0x8000;

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

/// The commands in the order of their codes.
const COMMANDS: [Command; 15] = {
    use Command::*;
    [
        Nop, Aprd, Apwr, Aprw, Fprd, Fpwr, Fprw, Brd, Bwr, Brw, Lrd, Lwr, Lrw, Armw, Frmw,
    ]
};

impl Command {
    /// The command its code names, if any.
    pub fn from_code(code: u8) -> Option<Command> {
        COMMANDS.get(usize::from(code)).copied()
    }

    /// The command's code on the wire.
    pub fn code(self) -> u8 {
        self as u8
    }
}

/// A view over one datagram: header, data and working counter. [`Datagram::new_checked`]
/// makes sure the length field's data and the working counter fit, so the accessors never fail.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Datagram<T: AsRef<[u8]>> {
    buffer: T,
}

impl<T: AsRef<[u8]>> Datagram<T> {
    /// A view over `buffer` without checks (accessors read zeros where bytes are missing).
    pub const fn new_unchecked(buffer: T) -> Self {
        Datagram { buffer }
    }

    /// A view over `buffer`, which must hold the header, the data its length says and the
    /// working counter (more bytes may follow: the next datagram).
    pub fn new_checked(buffer: T) -> Result<Self, WireError> {
        let datagram = Datagram { buffer };
        if datagram.buffer.as_ref().len() < HEADER_LEN
            || datagram.buffer.as_ref().len() < datagram.total_len()
        {
            return Err(WireError::Truncated);
        }
        Ok(datagram)
    }

    /// The bytes under the view.
    pub fn into_inner(self) -> T {
        self.buffer
    }

    fn bytes(&self) -> &[u8] {
        self.buffer.as_ref()
    }

    /// The command code (kept raw: an unknown code is a datagram no SubDevice answers).
    pub fn command(&self) -> u8 {
        self.bytes().first().copied().unwrap_or(0)
    }

    /// The index the master matches replies by.
    pub fn index(&self) -> u8 {
        self.bytes().get(1).copied().unwrap_or(0)
    }

    /// ADP: position or station address, or the low half of a logical address.
    pub fn adp(&self) -> u16 {
        le16(self.bytes(), 2)
    }

    /// ADO: register or memory address, or the high half of a logical address.
    pub fn ado(&self) -> u16 {
        le16(self.bytes(), 4)
    }

    /// The data length in bytes.
    pub fn data_len(&self) -> usize {
        usize::from(le16(self.bytes(), 6)) & MAX_DATA_LEN
    }

    /// Whether the frame has circulated (a ring was broken).
    pub fn circulating(&self) -> bool {
        le16(self.bytes(), 6) & CIRCULATING != 0
    }

    /// Whether another datagram follows.
    pub fn more(&self) -> bool {
        le16(self.bytes(), 6) & MORE != 0
    }

    /// The IRQ field.
    pub fn irq(&self) -> u16 {
        le16(self.bytes(), 8)
    }

    /// The header, data and working counter's length.
    pub fn total_len(&self) -> usize {
        HEADER_LEN + self.data_len() + WKC_LEN
    }

    /// The data.
    pub fn data(&self) -> &[u8] {
        self.bytes()
            .get(HEADER_LEN..HEADER_LEN + self.data_len())
            .unwrap_or_default()
    }

    /// The working counter.
    pub fn wkc(&self) -> u16 {
        le16(self.bytes(), HEADER_LEN + self.data_len())
    }
}

impl<T: AsRef<[u8]> + AsMut<[u8]>> Datagram<T> {
    /// Sets the ADP (auto-increment commands count it up on the way).
    pub fn set_adp(&mut self, adp: u16) {
        set_le16(self.buffer.as_mut(), 2, adp);
    }

    /// Sets the "another datagram follows" flag.
    pub fn set_more(&mut self, more: bool) {
        let word = le16(self.buffer.as_ref(), 6);
        let word = if more { word | MORE } else { word & !MORE };
        set_le16(self.buffer.as_mut(), 6, word);
    }

    /// Sets the working counter.
    pub fn set_wkc(&mut self, wkc: u16) {
        let at = HEADER_LEN + self.data_len();
        set_le16(self.buffer.as_mut(), at, wkc);
    }

    /// The data, to change in place.
    pub fn data_mut(&mut self) -> &mut [u8] {
        let len = self.data_len();
        self.buffer
            .as_mut()
            .get_mut(HEADER_LEN..HEADER_LEN + len)
            .unwrap_or_default()
    }

    /// The header and the data at once: what a SubDevice processes a datagram with.
    pub fn split_mut(&mut self) -> (DatagramRepr, &mut [u8]) {
        let repr = DatagramRepr::parse(&*self);
        (repr, self.data_mut())
    }
}

/// A datagram header's fields.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DatagramRepr {
    /// The command code (kept raw: an unknown code is a datagram no SubDevice answers).
    pub command: u8,
    /// The index the master matches replies by.
    pub index: u8,
    /// ADP: position or station address for physical commands, the low half of the logical
    /// address for logical ones.
    pub adp: u16,
    /// ADO: register or memory address for physical commands, the high half of the logical
    /// address for logical ones.
    pub ado: u16,
    /// The data length in bytes (at most [`MAX_DATA_LEN`]).
    pub len: u16,
    /// The frame has circulated (a ring was broken).
    pub circulating: bool,
    /// Another datagram follows.
    pub more: bool,
    /// The IRQ field.
    pub irq: u16,
}

impl DatagramRepr {
    /// The header of `datagram`.
    pub fn parse<T: AsRef<[u8]>>(datagram: &Datagram<T>) -> Self {
        DatagramRepr {
            command: datagram.command(),
            index: datagram.index(),
            adp: datagram.adp(),
            ado: datagram.ado(),
            len: datagram.data_len() as u16,
            circulating: datagram.circulating(),
            more: datagram.more(),
            irq: datagram.irq(),
        }
    }

    /// The 32-bit logical address of a logical command.
    pub fn logical_address(&self) -> u32 {
        u32::from(self.adp) | (u32::from(self.ado) << 16)
    }

    /// Writes the header into the first [`HEADER_LEN`] bytes of `buffer`.
    pub fn emit(&self, buffer: &mut [u8]) -> Result<(), WireError> {
        if usize::from(self.len) > MAX_DATA_LEN {
            return Err(WireError::Malformed);
        }
        let header = buffer.get_mut(..HEADER_LEN).ok_or(WireError::Truncated)?;
        let len_word = self.len
            | if self.circulating { CIRCULATING } else { 0 }
            | if self.more { MORE } else { 0 };
        header[0] = self.command;
        header[1] = self.index;
        set_le16(header, 2, self.adp);
        set_le16(header, 4, self.ado);
        set_le16(header, 6, len_word);
        set_le16(header, 8, self.irq);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FPWR: [u8; 14] = [5, 8, 0x01, 0x10, 0x20, 0x01, 0x02, 0x80, 0, 0, 2, 0, 3, 0];

    #[test]
    fn a_datagram_reads_its_fields() {
        let datagram = Datagram::new_checked(&FPWR[..]).unwrap();
        assert_eq!(Command::from_code(datagram.command()), Some(Command::Fpwr));
        assert_eq!(
            (datagram.index(), datagram.adp(), datagram.ado()),
            (8, 0x1001, 0x0120)
        );
        assert_eq!(
            (datagram.data_len(), datagram.more(), datagram.circulating()),
            (2, true, false)
        );
        assert_eq!((datagram.data(), datagram.wkc()), (&[2, 0][..], 3));
        assert_eq!(datagram.total_len(), 14);
    }

    #[test]
    fn the_repr_round_trips() {
        let repr = DatagramRepr::parse(&Datagram::new_checked(&FPWR[..]).unwrap());
        let mut out = [0u8; HEADER_LEN];
        repr.emit(&mut out).unwrap();
        assert_eq!(out, FPWR[..HEADER_LEN]);
        assert_eq!(repr.logical_address(), 0x0120_1001);
        assert_eq!(repr.emit(&mut [0u8; 9]), Err(WireError::Truncated));
        let too_long = DatagramRepr { len: 0x800, ..repr };
        assert_eq!(too_long.emit(&mut out), Err(WireError::Malformed));
    }

    #[test]
    fn a_datagram_is_changed_in_place() {
        let mut bytes = FPWR;
        let mut datagram = Datagram::new_checked(&mut bytes[..]).unwrap();
        datagram.set_adp(0x1002);
        datagram.set_wkc(0x0105);
        datagram.set_more(false);
        datagram.data_mut().copy_from_slice(&[7, 9]);
        assert_eq!(
            bytes,
            [5, 8, 0x02, 0x10, 0x20, 0x01, 0x02, 0, 0, 0, 7, 9, 5, 1]
        );
    }

    #[test]
    fn a_length_past_the_bytes_is_refused() {
        assert_eq!(
            Datagram::new_checked(&FPWR[..13]),
            Err(WireError::Truncated)
        );
        assert_eq!(Datagram::new_checked(&FPWR[..9]), Err(WireError::Truncated));
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
