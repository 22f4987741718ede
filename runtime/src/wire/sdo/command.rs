//! The command byte, field by field (CiA 301 §7.2.4.3): the specifier in bits 7..5, then the
//! message's own bits.

/// Client command specifiers (ccs).
pub mod ccs {
    /// Download SDO segment.
    pub const DOWNLOAD_SEGMENT: u8 = 0;
    /// Initiate SDO download.
    pub const INITIATE_DOWNLOAD: u8 = 1;
    /// Initiate SDO upload.
    pub const INITIATE_UPLOAD: u8 = 2;
    /// Upload SDO segment.
    pub const UPLOAD_SEGMENT: u8 = 3;
    /// Abort SDO transfer (the same in both directions).
    pub const ABORT: u8 = 4;
    /// SDO block upload (sub-command in bits 1..0).
    pub const BLOCK_UPLOAD: u8 = 5;
    /// SDO block download (sub-command in bit 0).
    pub const BLOCK_DOWNLOAD: u8 = 6;
}

/// Server command specifiers (scs).
pub mod scs {
    /// Upload SDO segment.
    pub const UPLOAD_SEGMENT: u8 = 0;
    /// Download SDO segment.
    pub const DOWNLOAD_SEGMENT: u8 = 1;
    /// Initiate SDO upload.
    pub const INITIATE_UPLOAD: u8 = 2;
    /// Initiate SDO download.
    pub const INITIATE_DOWNLOAD: u8 = 3;
    /// Abort SDO transfer (the same in both directions).
    pub const ABORT: u8 = 4;
    /// SDO block download (sub-command in bits 1..0).
    pub const BLOCK_DOWNLOAD: u8 = 5;
    /// SDO block upload (sub-command in bit 0).
    pub const BLOCK_UPLOAD: u8 = 6;
}

/// The command specifier (bits 7..5).
pub const fn specifier(command: u8) -> u8 {
    command >> 5
}

/// A command byte with `specifier` and the other bits zero.
pub const fn of(specifier: u8) -> u8 {
    specifier << 5
}

/// The toggle bit of a segment message (t, bit 4).
pub const fn toggle(command: u8) -> bool {
    command & 0x10 != 0
}

/// The toggle bit, in place.
pub const fn toggle_bit(toggle: bool) -> u8 {
    if toggle {
        0x10
    } else {
        0
    }
}

/// How many of a segment's 7 bytes carry no data (n, bits 3..1).
pub const fn segment_unused(command: u8) -> u8 {
    (command >> 1) & 0b111
}

/// Whether no segment follows (c, bit 0 of a segment message).
pub const fn last(command: u8) -> bool {
    command & 0x01 != 0
}

/// The bits 4..0 of a segment message: toggle, unused bytes, last.
pub const fn segment_bits(toggle: bool, unused: u8, last: bool) -> u8 {
    toggle_bit(toggle) | (unused & 0b111) << 1 | last as u8
}

/// Whether an initiate message is expedited (e, bit 1).
pub const fn expedited(command: u8) -> bool {
    command & 0b10 != 0
}

/// Whether an initiate message indicates the size (s, bit 0).
pub const fn size_indicated(command: u8) -> bool {
    command & SIZE_INDICATED != 0
}

/// The size-indicated bit (s) of a segmented initiate message, in place.
pub const SIZE_INDICATED: u8 = 0b01;

/// The size-indicated bit (s) of a block download request or block upload response, in
/// place.
pub const BLOCK_SIZE_INDICATED: u8 = 0b10;

/// How many of an expedited message's 4 data bytes are data, when the size is indicated
/// (4 - n, n in bits 3..2).
pub const fn expedited_len(command: u8) -> u8 {
    4 - ((command >> 2) & 0b11)
}

/// The bits 3..0 of an expedited initiate message with `len` (1..=4) bytes indicated.
pub const fn expedited_bits(len: u8) -> u8 {
    (4 - len) << 2 | 0b11
}

/// Whether a block initiate message announces CRC support (cc / sc, bit 2).
pub const fn crc(command: u8) -> bool {
    command & 0x04 != 0
}

/// The CRC-support bit, in place.
pub const fn crc_bit(crc: bool) -> u8 {
    if crc {
        0x04
    } else {
        0
    }
}

/// The sub-command of a block message (cs / ss, bits 1..0; only bit 0 in a block download
/// request and a block upload response, whose bit 1 is [`block_size_indicated`]).
pub const fn block_subcommand(command: u8) -> u8 {
    command & 0b11
}

/// Whether a block download request or block upload response indicates the size (s,
/// bit 1).
pub const fn block_size_indicated(command: u8) -> bool {
    command & BLOCK_SIZE_INDICATED != 0
}

/// How many bytes of a block transfer's last segment carry no data (n, bits 4..2 of the
/// end message).
pub const fn block_end_unused(command: u8) -> u8 {
    (command >> 2) & 0b111
}

/// The bits 4..2 of a block transfer's end message: `unused` bytes of its last segment.
pub const fn block_end_bits(unused: u8) -> u8 {
    (unused & 0b111) << 2
}
