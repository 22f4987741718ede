//! CIP values in assembly images, one rule for the simulated adapter and the bench scanner: a
//! member's width (written, else its parameter's data size, else its nested assembly's size),
//! members laid out as CIP packs them (from bit 0 of byte 0, each least significant bit first),
//! and bits read and written at any bit offset.

use super::{AssemblyMember, Cip, CipAssembly, FieldRef};

/// The width in bits of an assembly member: written, else its parameter's data size, else its
/// nested assembly's size, else 0.
pub fn member_bits(cip: &Cip, member: &AssemblyMember) -> u32 {
    member
        .bits
        .or_else(|| match &member.member {
            FieldRef::Param(n) => cip.params.get(n)?.data_size.as_ref()?.value.checked_mul(8),
            FieldRef::Assem(n) => cip
                .assemblies
                .get(n)
                .and_then(|a| cip.assembly_size(a))
                .and_then(|s| u32::try_from(s * 8).ok()),
            _ => None,
        })
        .unwrap_or(0)
}

/// Where an assembly member lies in the assembly's image.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MemberPlace<'a> {
    /// The member.
    pub member: &'a AssemblyMember,
    /// Its first bit.
    pub bit: u64,
    /// Its width in bits.
    pub bits: u32,
}

/// Every member of `assembly` (padding included) in order, at its place.
pub fn layout<'a>(cip: &Cip, assembly: &'a CipAssembly) -> Vec<MemberPlace<'a>> {
    let mut bit = 0u64;
    assembly
        .members
        .iter()
        .map(|member| {
            let bits = member_bits(cip, member);
            let place = MemberPlace { member, bit, bits };
            bit += u64::from(bits);
            place
        })
        .collect()
}

/// Bits `at..at + len` (at most 64) of `buf`, least significant first; bits past its end are 0.
pub fn get_bits(buf: &[u8], at: u64, len: u32) -> u64 {
    let mut value = 0u64;
    for i in 0..u64::from(len.min(64)) {
        if bit(buf, at + i) {
            value |= 1 << i;
        }
    }
    value
}

/// Writes the low `len` bits (at most 64) of `value` at bit `at` of `buf` (bits past its end
/// are dropped).
pub fn put_bits(buf: &mut [u8], at: u64, len: u32, value: u64) {
    for i in 0..u64::from(len.min(64)) {
        set_bit(buf, at + i, (value >> i) & 1 != 0);
    }
}

/// Bits `at..at + len` of `buf` as little-endian bytes, at least `size` of them (bits past the
/// end of `buf` are 0).
pub fn read_bits(buf: &[u8], at: u64, len: u64, size: usize) -> Vec<u8> {
    let bytes = usize::try_from(len.div_ceil(8)).unwrap_or(0);
    let mut out = vec![0u8; size.max(bytes)];
    for i in 0..len {
        set_bit(&mut out, i, bit(buf, at + i));
    }
    out
}

/// Writes `len` bits of the little-endian `value` at bit `at` of `buf` (bits past the end of
/// `value` are 0, past the end of `buf` dropped).
pub fn write_bits(buf: &mut [u8], at: u64, len: u64, value: &[u8]) {
    for i in 0..len {
        set_bit(buf, at + i, bit(value, i));
    }
}

fn bit(buf: &[u8], at: u64) -> bool {
    usize::try_from(at / 8)
        .ok()
        .and_then(|byte| buf.get(byte))
        .is_some_and(|byte| (byte >> (at % 8)) & 1 != 0)
}

fn set_bit(buf: &mut [u8], at: u64, on: bool) {
    let Some(byte) = usize::try_from(at / 8).ok().and_then(|b| buf.get_mut(b)) else {
        return;
    };
    if on {
        *byte |= 1 << (at % 8);
    } else {
        *byte &= !(1 << (at % 8));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bits_at_any_offset() {
        let mut image = [0u8; 4];
        put_bits(&mut image, 3, 10, 0x3FF);
        assert_eq!(image, [0xF8, 0x1F, 0, 0]);
        assert_eq!(get_bits(&image, 3, 10), 0x3FF);
        assert_eq!(get_bits(&image, 30, 8), 0);
        write_bits(&mut image, 12, 12, &[0x21, 0x03]);
        assert_eq!(image, [0xF8, 0x1F, 0x32, 0]);
        assert_eq!(read_bits(&image, 12, 12, 4), [0x21, 0x03, 0, 0]);
        assert_eq!(read_bits(&image, 0, 70, 1).len(), 9);
        // Past the end: dropped, never a panic.
        put_bits(&mut image, 30, 8, 0xFF);
        assert_eq!(image[3], 0xC0);
    }
}
