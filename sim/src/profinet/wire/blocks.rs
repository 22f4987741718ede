//! The PNIO blocks of the Connect are the runtime's views and reprs
//! ([`edsgen_runtime::profinet::wire::connect`]), the record access and control blocks too
//! ([`edsgen_runtime::profinet::wire::records`]); here the two conveniences the simulator's
//! machines use over vectors: an argument split into a `Vec` of blocks, a block appended.

pub use edsgen_runtime::profinet::wire::block::{Block, Reader};
pub use edsgen_runtime::profinet::wire::connect::*;
pub use edsgen_runtime::profinet::wire::records::*;

/// Splits an argument into its blocks ([`edsgen_runtime::profinet::wire::block::blocks`]);
/// `Err(offset)` where a header is short, a BlockLength below 2, or a block runs past the end.
pub fn split(args: &[u8]) -> Result<Vec<Block<'_>>, usize> {
    edsgen_runtime::profinet::wire::block::blocks(args).collect()
}

/// Appends a block of `block_type`, version 1.`low`, whose content `body` writes.
pub fn emit_block(out: &mut Vec<u8>, block_type: u16, low: u8, body: impl FnOnce(&mut Vec<u8>)) {
    let start = out.len();
    out.extend_from_slice(&block_type.to_be_bytes());
    out.extend_from_slice(&[0, 0, 1, low]);
    body(out);
    let len = u16::try_from(out.len() - start - 4).unwrap_or(u16::MAX);
    out[start + 2..start + 4].copy_from_slice(&len.to_be_bytes());
}

/// Appends the block `emit` writes (a repr's `emit`), with room for the longest a block can be
/// (its BlockLength is 16 bits); nothing when it does not fit even that.
pub fn append_block(
    out: &mut Vec<u8>,
    emit: impl FnOnce(&mut [u8]) -> Result<usize, super::BufferTooSmall>,
) {
    let start = out.len();
    out.resize(start + 4 + usize::from(u16::MAX), 0);
    let written = emit(&mut out[start..]).unwrap_or(0);
    out.truncate(start + written);
}
