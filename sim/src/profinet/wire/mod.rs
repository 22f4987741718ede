//! PROFINET wire formats, apart from the protocol machines, are the runtime's views
//! ([`edsgen_runtime::profinet::wire`]): the Ethernet header, DCP ([`dcp`]), the RT frame
//! ([`rt`]), DCE/RPC ([`rpc`]), the AlarmCR's frames ([`alarm`]), the Connect's blocks and the
//! record access and control blocks ([`blocks`]). Here what the simulator adds over `Vec`s:
//! frames and blocks appended, whole PDUs as datagrams, and the alarm payload and diagnosis
//! data the alarm machines keep as owned structs. Parsing never panics.

pub mod alarm;
pub mod blocks;

use rpc::{Ndr, RpcHeader, HEADER_LEN, NDR_LEN};

pub use edsgen_runtime::profinet::wire::{
    dcp, rpc, rt, BufferTooSmall, Ethernet, EthernetFrame, Mac, ETHERTYPE_PROFINET, ETHERTYPE_VLAN,
};

/// The longest untagged Ethernet frame without FCS.
const MAX_FRAME_LEN: usize = 1514;

/// Appends to `out`, a frame being built, what `emit` writes into the room the frame has left
/// (a whole Ethernet frame at most, whatever came before); nothing when it does not fit. A
/// frame built by appending never outgrows the interface: a DCP Get asking for the name of
/// station 700 times gets the answers that fit one frame.
pub fn append(out: &mut Vec<u8>, emit: impl FnOnce(&mut [u8]) -> Result<usize, BufferTooSmall>) {
    let start = out.len();
    out.resize(MAX_FRAME_LEN.max(start), 0);
    let written = emit(&mut out[start..]).unwrap_or(0);
    out.truncate(start + written);
}

/// A whole RPC PDU ([`rpc::emit_pdu`]) as a datagram.
pub fn rpc_pdu(header: &RpcHeader, ndr: &Ndr, args: &[u8]) -> Vec<u8> {
    let mut out = vec![0; HEADER_LEN + NDR_LEN + args.len()];
    let written = rpc::emit_pdu(header, ndr, args, &mut out).unwrap_or(0);
    out.truncate(written);
    out
}

/// A reject or fault PDU ([`rpc::emit_reject`]) as a datagram.
pub fn rpc_reject(request: &RpcHeader, packet_type: u8, status: u32) -> Vec<u8> {
    let mut out = vec![0; HEADER_LEN + 4];
    let written = rpc::emit_reject(request, packet_type, status, &mut out).unwrap_or(0);
    out.truncate(written);
    out
}

/// Pads a frame to Ethernet's 60-byte minimum (without FCS), as a driver sends it.
pub fn pad(frame: &mut Vec<u8>) {
    frame.resize(edsgen_runtime::profinet::wire::padded_len(frame.len()), 0);
}
