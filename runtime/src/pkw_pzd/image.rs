//! The 16-word images (Figure 2-4): PKW1–PKW4, then the CW (output) or SW (input), then
//! PZD2–PZD12, each word in the bus's byte order: big-endian on PROFIBUS-DP and PROFINET (their
//! convention, and the byte order of the manual's §2.6 examples), little-endian if a CIP card
//! chooses CIP's convention.

use super::control::{ControlWord, StatusWord};
use super::pkw::{PkwRequest, PkwResponse, ResponseError};

/// Words in an image.
pub const IMAGE_WORDS: usize = 16;
/// Bytes in an image.
pub const IMAGE_BYTES: usize = 2 * IMAGE_WORDS;
/// Process words after the CW or SW: PZD2 to PZD12.
pub const PZD_WORDS: usize = 11;

/// How a 16-bit word is laid out in two bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ByteOrder {
    /// High byte first (PROFIBUS-DP, PROFINET).
    BigEndian,
    /// Low byte first (CIP's convention).
    LittleEndian,
}

impl ByteOrder {
    /// The word of two bytes.
    pub const fn word(self, bytes: [u8; 2]) -> u16 {
        match self {
            ByteOrder::BigEndian => u16::from_be_bytes(bytes),
            ByteOrder::LittleEndian => u16::from_le_bytes(bytes),
        }
    }

    /// The two bytes of a word.
    pub const fn bytes(self, word: u16) -> [u8; 2] {
        match self {
            ByteOrder::BigEndian => word.to_be_bytes(),
            ByteOrder::LittleEndian => word.to_le_bytes(),
        }
    }

    /// The 16 words of an image's 32 bytes.
    pub fn words(self, bytes: &[u8; IMAGE_BYTES]) -> [u16; IMAGE_WORDS] {
        let mut words = [0; IMAGE_WORDS];
        for (word, pair) in words.iter_mut().zip(bytes.chunks_exact(2)) {
            *word = self.word([pair[0], pair[1]]);
        }
        words
    }

    /// The 32 bytes of an image's 16 words.
    pub fn image_bytes(self, words: &[u16; IMAGE_WORDS]) -> [u8; IMAGE_BYTES] {
        let mut bytes = [0; IMAGE_BYTES];
        for (pair, word) in bytes.chunks_exact_mut(2).zip(words) {
            pair.copy_from_slice(&self.bytes(*word));
        }
        bytes
    }
}

/// The master's image (drive's input): a PKW request, the CW and PZD2–PZD12 settings.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct OutputImage {
    /// PKW1–PKW4.
    pub pkw: PkwRequest,
    /// The control word.
    pub control: ControlWord,
    /// PZD2–PZD12: settings whose meanings the drive's parameters choose.
    pub pzd: [u16; PZD_WORDS],
}

impl Default for OutputImage {
    fn default() -> Self {
        OutputImage::from_words([0; IMAGE_WORDS])
    }
}

impl OutputImage {
    /// The image of 16 words.
    pub fn from_words(words: [u16; IMAGE_WORDS]) -> Self {
        let mut pzd = [0; PZD_WORDS];
        pzd.copy_from_slice(&words[5..]);
        OutputImage {
            pkw: PkwRequest::from_words([words[0], words[1], words[2], words[3]]),
            control: ControlWord(words[4]),
            pzd,
        }
    }

    /// The 16 words.
    pub fn to_words(&self) -> [u16; IMAGE_WORDS] {
        let mut words = [0; IMAGE_WORDS];
        words[..4].copy_from_slice(&self.pkw.to_words());
        words[4] = self.control.0;
        words[5..].copy_from_slice(&self.pzd);
        words
    }

    /// The image of 32 bytes in `order`. Total: every 32 bytes are some image.
    pub fn parse(bytes: &[u8; IMAGE_BYTES], order: ByteOrder) -> Self {
        OutputImage::from_words(order.words(bytes))
    }

    /// The 32 bytes in `order`.
    pub fn emit(&self, order: ByteOrder) -> [u8; IMAGE_BYTES] {
        order.image_bytes(&self.to_words())
    }
}

/// The drive's image (master's input): a PKW response, the SW and PZD2–PZD12 actual values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct InputImage {
    /// PKW1–PKW4.
    pub pkw: PkwResponse,
    /// The status word.
    pub status: StatusWord,
    /// PZD2–PZD12: actual values whose meanings the drive's parameters choose.
    pub pzd: [u16; PZD_WORDS],
}

impl InputImage {
    /// The image of 16 words; an error if PKW1 holds an undefined response code.
    pub fn from_words(words: [u16; IMAGE_WORDS]) -> Result<Self, ResponseError> {
        let mut pzd = [0; PZD_WORDS];
        pzd.copy_from_slice(&words[5..]);
        Ok(InputImage {
            pkw: PkwResponse::from_words([words[0], words[1], words[2], words[3]])?,
            status: StatusWord(words[4]),
            pzd,
        })
    }

    /// The 16 words.
    pub fn to_words(&self) -> [u16; IMAGE_WORDS] {
        let mut words = [0; IMAGE_WORDS];
        words[..4].copy_from_slice(&self.pkw.to_words());
        words[4] = self.status.0;
        words[5..].copy_from_slice(&self.pzd);
        words
    }

    /// The image of 32 bytes in `order`.
    pub fn parse(bytes: &[u8; IMAGE_BYTES], order: ByteOrder) -> Result<Self, ResponseError> {
        InputImage::from_words(order.words(bytes))
    }

    /// The 32 bytes in `order`.
    pub fn emit(&self, order: ByteOrder) -> [u8; IMAGE_BYTES] {
        order.image_bytes(&self.to_words())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pkw_pzd::{Command, WordLayout};

    /// §2.6 PKW example 1, request: the manual prints "00 01 | 00 10 | 00 00 | 00 00" in
    /// decimal (task 1, address 10 = P00.10); on the wire, big-endian: 00 01 00 0A 00 00 00 00.
    #[test]
    fn example_1_request_on_the_wire() {
        let image = OutputImage {
            pkw: PkwRequest::read(10),
            control: ControlWord(0),
            pzd: [0; PZD_WORDS],
        };
        let bytes = image.emit(ByteOrder::BigEndian);
        assert_eq!(bytes[..8], [0x00, 0x01, 0x00, 0x0A, 0x00, 0x00, 0x00, 0x00]);
        assert_eq!(OutputImage::parse(&bytes, ByteOrder::BigEndian), image);
    }

    /// §2.6 PKW example 1, response: "00 01 | 00 10 | 00 00 | 50 00" (response 1, address 10,
    /// value 5000 = 50.00 Hz) is 00 01 00 0A 00 00 13 88 on the wire.
    #[test]
    fn example_1_response_on_the_wire() {
        let image = InputImage {
            pkw: PkwResponse::Word {
                address: 10,
                value: 5000,
            },
            status: StatusWord(0x0103),
            pzd: [0; PZD_WORDS],
        };
        let bytes = image.emit(ByteOrder::BigEndian);
        assert_eq!(
            bytes[..10],
            [0x00, 0x01, 0x00, 0x0A, 0x00, 0x00, 0x13, 0x88, 0x01, 0x03]
        );
        assert_eq!(InputImage::parse(&bytes, ByteOrder::BigEndian), Ok(image));
    }

    #[test]
    fn byte_order_is_a_parameter() {
        let mut words = [0u16; IMAGE_WORDS];
        words[0] = 4;
        words[1] = 10;
        words[3] = 5000;
        words[4] = ControlWord::new(Command::RunForward, WordLayout::ByByte).0 | 0x0100;
        words[15] = 0xBEEF;
        let image = OutputImage::from_words(words);
        let little = image.emit(ByteOrder::LittleEndian);
        assert_eq!(
            little[..10],
            [0x04, 0x00, 0x0A, 0x00, 0x00, 0x00, 0x88, 0x13, 0x01, 0x01]
        );
        assert_eq!(little[30..], [0xEF, 0xBE]);
        let big = image.emit(ByteOrder::BigEndian);
        assert_eq!(big[30..], [0xBE, 0xEF]);
        assert_eq!(OutputImage::parse(&little, ByteOrder::LittleEndian), image);
        assert_eq!(image.to_words(), words);
        assert_eq!(image.pzd[10], 0xBEEF);
    }

    #[test]
    fn undefined_response_code_is_an_error() {
        let mut bytes = [0u8; IMAGE_BYTES];
        bytes[1] = 9;
        assert_eq!(
            InputImage::parse(&bytes, ByteOrder::BigEndian),
            Err(ResponseError::UnknownResponse(9))
        );
    }
}
