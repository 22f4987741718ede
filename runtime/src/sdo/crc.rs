//! CRC-16-CCITT as SDO block transfer uses it (CiA 301 §7.2.4.3.16): polynomial 0x1021
//! (x^16 + x^12 + x^5 + 1), initial value 0, no reflection, no final XOR (the "XMODEM" variant).
//!
//! A 16-entry table (one per nibble, 32 bytes of flash instead of 512 for a byte table) computed
//! at compile time; [`Crc16`] accumulates over chunks so that a value streamed in pieces gets the
//! same CRC as the whole.

const POLYNOMIAL: u16 = 0x1021;

/// The CRC register's change for each value of its top four bits shifted out.
const TABLE: [u16; 16] = build_table();

const fn build_table() -> [u16; 16] {
    let mut table = [0u16; 16];
    let mut nibble = 0;
    while nibble < 16 {
        let mut crc = (nibble as u16) << 12;
        let mut bit = 0;
        while bit < 4 {
            crc = if crc & 0x8000 != 0 {
                (crc << 1) ^ POLYNOMIAL
            } else {
                crc << 1
            };
            bit += 1;
        }
        table[nibble] = crc;
        nibble += 1;
    }
    table
}

/// A running CRC-16-CCITT (initial value 0).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Crc16(u16);

impl Crc16 {
    /// A CRC over no bytes yet.
    pub const fn new() -> Self {
        Crc16(0)
    }

    /// Adds `bytes` to the CRC.
    pub fn update(&mut self, bytes: &[u8]) {
        for &byte in bytes {
            let mut crc = self.0;
            for nibble in [byte >> 4, byte & 0x0F] {
                let top = usize::from((crc >> 12) as u8 ^ nibble) & 0x0F;
                crc = (crc << 4) ^ TABLE[top];
            }
            self.0 = crc;
        }
    }

    /// The CRC of everything added so far.
    pub const fn value(self) -> u16 {
        self.0
    }
}

/// The CRC-16-CCITT of `bytes`.
pub fn crc16(bytes: &[u8]) -> u16 {
    let mut crc = Crc16::new();
    crc.update(bytes);
    crc.value()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn check_value_of_the_standard_test_string() {
        // The catalogue check value of CRC-16/XMODEM.
        assert_eq!(crc16(b"123456789"), 0x31C3);
    }

    #[test]
    fn empty_input_is_zero() {
        assert_eq!(crc16(&[]), 0);
    }

    #[test]
    fn chunked_update_equals_whole() {
        let data: [u8; 300] = core::array::from_fn(|i| (i * 7 + 3) as u8);
        let mut crc = Crc16::new();
        for chunk in data.chunks(7) {
            crc.update(chunk);
        }
        assert_eq!(crc.value(), crc16(&data));
    }

    #[test]
    fn table_matches_bitwise_computation() {
        fn bitwise(bytes: &[u8]) -> u16 {
            let mut crc = 0u16;
            for &b in bytes {
                crc ^= u16::from(b) << 8;
                for _ in 0..8 {
                    crc = if crc & 0x8000 != 0 {
                        (crc << 1) ^ 0x1021
                    } else {
                        crc << 1
                    };
                }
            }
            crc
        }
        let data: [u8; 64] = core::array::from_fn(|i| (i * 31 + 11) as u8);
        assert_eq!(crc16(&data), bitwise(&data));
        for byte in 0..=255u8 {
            assert_eq!(
                crc16(&[byte, 0x5A]),
                bitwise(&[byte, 0x5A]),
                "byte {byte:#04x}"
            );
        }
    }
}
