//! The connectionless DCE/RPC PDU that carries PROFINET's connection management on UDP 34964
//! (IEC 61158-6-10 and DCE 1.1 RPC, chapter 12): the 80-byte header (version 4, packet type,
//! flags, the data representation "drep" that says the byte order of every integer after it,
//! the object, interface and activity UUIDs, sequence and operation numbers, fragment fields),
//! then the NDR header of PROFINET's one argument (ArgsMaximum or the PNIOStatus, ArgsLength,
//! MaximumCount, Offset, ActualCount), then the PNIO blocks ([`super::block`]), which are
//! big-endian whatever the drep says. Both byte orders are read; answers keep the request's.
//! Parsing never panics: a short or malformed PDU is `None`; emitting writes into the caller's
//! buffer and returns the length, or [`BufferTooSmall`].

use super::{put, BufferTooSmall};

/// The UDP port of PROFINET's RPC endpoint (the device's and the controller's).
pub const RPC_PORT: u16 = 34964;

/// Packet type: a request.
pub const REQUEST: u8 = 0;
/// Packet type: a ping (is the call still alive?).
pub const PING: u8 = 1;
/// Packet type: a response.
pub const RESPONSE: u8 = 2;
/// Packet type: a fault (the call failed in the server).
pub const FAULT: u8 = 3;
/// Packet type: working (the answer to a ping while the call runs).
pub const WORKING: u8 = 4;
/// Packet type: no call (the answer to a ping for an unknown call).
pub const NOCALL: u8 = 5;
/// Packet type: reject (the call was not accepted).
pub const REJECT: u8 = 6;

/// Flags1: last fragment.
pub const FLAG_LAST_FRAGMENT: u8 = 0x02;
/// Flags1: no fragment acknowledge requested.
pub const FLAG_NO_FACK: u8 = 0x08;
/// Flags1: idempotent call.
pub const FLAG_IDEMPOTENT: u8 = 0x20;

/// Opnum Connect.
pub const OP_CONNECT: u16 = 0;
/// Opnum Release.
pub const OP_RELEASE: u16 = 1;
/// Opnum Read.
pub const OP_READ: u16 = 2;
/// Opnum Write.
pub const OP_WRITE: u16 = 3;
/// Opnum Control.
pub const OP_CONTROL: u16 = 4;
/// Opnum ReadImplicit (a read without an AR).
pub const OP_READ_IMPLICIT: u16 = 5;

/// The reject status "unknown interface" (nca_unk_if).
pub const NCA_UNKNOWN_INTERFACE: u32 = 0x1C01_0003;
/// The reject status "operation out of range" (nca_op_rng_error).
pub const NCA_OP_RANGE_ERROR: u32 = 0x1C01_0002;

/// The size of the RPC header.
pub const HEADER_LEN: usize = 80;
/// The size of the NDR header.
pub const NDR_LEN: usize = 20;

/// A UUID in its canonical (big-endian, as printed) byte order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Uuid(pub [u8; 16]);

impl Uuid {
    /// The PNIO device interface, DEA00001-6C97-11D1-8271-00A02442DF7D.
    pub const PNIO_DEVICE: Uuid = Uuid([
        0xDE, 0xA0, 0x00, 0x01, 0x6C, 0x97, 0x11, 0xD1, 0x82, 0x71, 0x00, 0xA0, 0x24, 0x42, 0xDF,
        0x7D,
    ]);
    /// The PNIO controller interface, DEA00002-6C97-11D1-8271-00A02442DF7D.
    pub const PNIO_CONTROLLER: Uuid = Uuid([
        0xDE, 0xA0, 0x00, 0x02, 0x6C, 0x97, 0x11, 0xD1, 0x82, 0x71, 0x00, 0xA0, 0x24, 0x42, 0xDF,
        0x7D,
    ]);

    /// A device's object UUID: DEA00000-6C97-11D1-8271-{instance}{DeviceID}{VendorID}.
    pub fn pnio_object(instance: u16, device_id: u16, vendor_id: u16) -> Uuid {
        let mut b = [
            0xDE, 0xA0, 0x00, 0x00, 0x6C, 0x97, 0x11, 0xD1, 0x82, 0x71, 0, 0, 0, 0, 0, 0,
        ];
        b[10..12].copy_from_slice(&instance.to_be_bytes());
        b[12..14].copy_from_slice(&device_id.to_be_bytes());
        b[14..16].copy_from_slice(&vendor_id.to_be_bytes());
        Uuid(b)
    }

    /// Reads a UUID as DCE encodes it: the first three fields in `little` endian or not.
    pub fn read(bytes: &[u8; 16], little: bool) -> Uuid {
        let mut b = *bytes;
        if little {
            b[0..4].reverse();
            b[4..6].reverse();
            b[6..8].reverse();
        }
        Uuid(b)
    }

    /// The UUID's bytes in the byte order of `little`.
    pub fn to_bytes(&self, little: bool) -> [u8; 16] {
        let mut b = self.0;
        if little {
            b[0..4].reverse();
            b[4..6].reverse();
            b[6..8].reverse();
        }
        b
    }
}

/// A PNIOStatus: ErrorCode, ErrorDecode, ErrorCode1, ErrorCode2 (all zero: no error).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PnioStatus(pub [u8; 4]);

impl PnioStatus {
    /// No error.
    pub const OK: PnioStatus = PnioStatus([0; 4]);
    /// ErrorCode: a Connect refused.
    pub const CODE_CONNECT: u8 = 0xDB;
    /// ErrorCode: a Release refused.
    pub const CODE_RELEASE: u8 = 0xDC;
    /// ErrorCode: a Control refused.
    pub const CODE_CONTROL: u8 = 0xDD;
    /// ErrorCode: a Read refused.
    pub const CODE_READ: u8 = 0xDE;
    /// ErrorCode: a Write refused.
    pub const CODE_WRITE: u8 = 0xDF;
    /// ErrorDecode of record access errors.
    pub const DECODE_PNIORW: u8 = 0x80;
    /// ErrorDecode of all other errors.
    pub const DECODE_PNIO: u8 = 0x81;

    /// A status from its four bytes.
    pub const fn new(code: u8, decode: u8, code1: u8, code2: u8) -> PnioStatus {
        PnioStatus([code, decode, code1, code2])
    }

    /// `true` for no error.
    pub fn is_ok(&self) -> bool {
        self.0 == [0; 4]
    }
}

/// The RPC header's fields, integers as numbers (the drep says how they were on the wire).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RpcHeader {
    /// Packet type ([`REQUEST`], [`RESPONSE`], ...).
    pub packet_type: u8,
    /// Flags1.
    pub flags1: u8,
    /// Flags2.
    pub flags2: u8,
    /// `true` when the integers are little-endian (drep byte 0 bit 4).
    pub little_endian: bool,
    /// The drep's second and third bytes (character and floating-point representation).
    pub drep_rest: [u8; 2],
    /// Serial number, high byte.
    pub serial_high: u8,
    /// Object UUID.
    pub object: Uuid,
    /// Interface UUID.
    pub interface: Uuid,
    /// Activity UUID (one per caller's activity).
    pub activity: Uuid,
    /// Server boot time.
    pub server_boot_time: u32,
    /// Interface version.
    pub interface_version: u32,
    /// Sequence number (one per call of the activity).
    pub sequence: u32,
    /// Operation number.
    pub opnum: u16,
    /// Interface hint.
    pub interface_hint: u16,
    /// Activity hint.
    pub activity_hint: u16,
    /// Length of the body.
    pub body_len: u16,
    /// Fragment number.
    pub fragment: u16,
    /// Authentication protocol (0: none).
    pub auth_protocol: u8,
    /// Serial number, low byte.
    pub serial_low: u8,
}

/// Reads a u16/u32 at `at` in the given byte order.
fn u16_at(b: &[u8], at: usize, little: bool) -> Option<u16> {
    let v: [u8; 2] = b.get(at..at + 2)?.try_into().ok()?;
    Some(if little {
        u16::from_le_bytes(v)
    } else {
        u16::from_be_bytes(v)
    })
}

fn u32_at(b: &[u8], at: usize, little: bool) -> Option<u32> {
    let v: [u8; 4] = b.get(at..at + 4)?.try_into().ok()?;
    Some(if little {
        u32::from_le_bytes(v)
    } else {
        u32::from_be_bytes(v)
    })
}

/// Writes a u16 at `at` in the given byte order; the offset after it.
fn put16(buf: &mut [u8], at: usize, v: u16, little: bool) -> Result<usize, BufferTooSmall> {
    put(
        buf,
        at,
        &if little {
            v.to_le_bytes()
        } else {
            v.to_be_bytes()
        },
    )
}

/// Writes a u32 at `at` in the given byte order; the offset after it.
fn put32(buf: &mut [u8], at: usize, v: u32, little: bool) -> Result<usize, BufferTooSmall> {
    put(
        buf,
        at,
        &if little {
            v.to_le_bytes()
        } else {
            v.to_be_bytes()
        },
    )
}

impl RpcHeader {
    /// Reads a PDU: the header and its body (exactly `body_len` bytes after the header; extra
    /// bytes after it are ignored). `None` for another version, a short PDU, or a body shorter
    /// than its length.
    pub fn parse(pdu: &[u8]) -> Option<(RpcHeader, &[u8])> {
        if pdu.len() < HEADER_LEN || pdu[0] != 4 {
            return None;
        }
        let little = pdu[4] & 0xF0 == 0x10;
        let uuid = |at: usize| -> Option<Uuid> {
            Some(Uuid::read(pdu.get(at..at + 16)?.try_into().ok()?, little))
        };
        let header = RpcHeader {
            packet_type: pdu[1],
            flags1: pdu[2],
            flags2: pdu[3],
            little_endian: little,
            drep_rest: [pdu[5], pdu[6]],
            serial_high: pdu[7],
            object: uuid(8)?,
            interface: uuid(24)?,
            activity: uuid(40)?,
            server_boot_time: u32_at(pdu, 56, little)?,
            interface_version: u32_at(pdu, 60, little)?,
            sequence: u32_at(pdu, 64, little)?,
            opnum: u16_at(pdu, 68, little)?,
            interface_hint: u16_at(pdu, 70, little)?,
            activity_hint: u16_at(pdu, 72, little)?,
            body_len: u16_at(pdu, 74, little)?,
            fragment: u16_at(pdu, 76, little)?,
            auth_protocol: pdu[78],
            serial_low: pdu[79],
        };
        let body = pdu.get(HEADER_LEN..HEADER_LEN + usize::from(header.body_len))?;
        Some((header, body))
    }

    /// Writes the header for a body of `body_len` bytes (which overrides the field) at the
    /// start of `buf`; its length ([`HEADER_LEN`]).
    pub fn emit(&self, body_len: u16, buf: &mut [u8]) -> Result<usize, BufferTooSmall> {
        let little = self.little_endian;
        let drep = if little { 0x10 } else { 0x00 };
        let at = put(
            buf,
            0,
            &[4, self.packet_type, self.flags1, self.flags2, drep],
        )?;
        let at = put(buf, at, &self.drep_rest)?;
        let at = put(buf, at, &[self.serial_high])?;
        let at = put(buf, at, &self.object.to_bytes(little))?;
        let at = put(buf, at, &self.interface.to_bytes(little))?;
        let at = put(buf, at, &self.activity.to_bytes(little))?;
        let at = put32(buf, at, self.server_boot_time, little)?;
        let at = put32(buf, at, self.interface_version, little)?;
        let at = put32(buf, at, self.sequence, little)?;
        let at = put16(buf, at, self.opnum, little)?;
        let at = put16(buf, at, self.interface_hint, little)?;
        let at = put16(buf, at, self.activity_hint, little)?;
        let at = put16(buf, at, body_len, little)?;
        let at = put16(buf, at, self.fragment, little)?;
        put(buf, at, &[self.auth_protocol, self.serial_low])
    }

    /// The header of the answer to this request: `packet_type`, the same byte order, UUIDs,
    /// sequence and opnum; last fragment, no fragment acknowledge.
    pub fn answer(&self, packet_type: u8) -> RpcHeader {
        RpcHeader {
            packet_type,
            flags1: FLAG_LAST_FRAGMENT | FLAG_NO_FACK,
            flags2: 0,
            interface_hint: 0xFFFF,
            activity_hint: 0xFFFF,
            fragment: 0,
            auth_protocol: 0,
            ..*self
        }
    }

    /// A request header: big-endian, interface version 1, no hints.
    pub fn request(
        object: Uuid,
        interface: Uuid,
        activity: Uuid,
        sequence: u32,
        opnum: u16,
    ) -> Self {
        RpcHeader {
            packet_type: REQUEST,
            flags1: FLAG_LAST_FRAGMENT | FLAG_IDEMPOTENT,
            flags2: 0,
            little_endian: false,
            drep_rest: [0, 0],
            serial_high: 0,
            object,
            interface,
            activity,
            server_boot_time: 0,
            interface_version: 1,
            sequence,
            opnum,
            interface_hint: 0xFFFF,
            activity_hint: 0xFFFF,
            body_len: 0,
            fragment: 0,
            auth_protocol: 0,
            serial_low: 0,
        }
    }
}

/// The NDR header of PROFINET's argument: first ArgsMaximum (a request) or the PNIOStatus (a
/// response), then ArgsLength, MaximumCount, Offset, ActualCount; each a 32-bit integer in the
/// drep's byte order (the PNIOStatus with ErrorCode its most significant byte, as Wireshark
/// reads it: a little-endian answer carries its four bytes reversed).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Ndr {
    /// The first field's four bytes as on the wire.
    pub first: [u8; 4],
    /// ArgsLength: the bytes of blocks that follow.
    pub args_length: u32,
    /// MaximumCount.
    pub maximum_count: u32,
    /// Offset.
    pub offset: u32,
    /// ActualCount.
    pub actual_count: u32,
    /// `true` when the integers are little-endian.
    pub little_endian: bool,
}

impl Ndr {
    /// Reads the NDR header of a body and the ArgsLength bytes of blocks after it. `None` when
    /// the body is short or ArgsLength disagrees with ActualCount or the bytes there.
    pub fn parse(body: &[u8], little: bool) -> Option<(Ndr, &[u8])> {
        let ndr = Ndr {
            first: body.get(..4)?.try_into().ok()?,
            args_length: u32_at(body, 4, little)?,
            maximum_count: u32_at(body, 8, little)?,
            offset: u32_at(body, 12, little)?,
            actual_count: u32_at(body, 16, little)?,
            little_endian: little,
        };
        if ndr.args_length != ndr.actual_count || ndr.offset != 0 {
            return None;
        }
        let len = usize::try_from(ndr.args_length).ok()?;
        let args = body.get(NDR_LEN..NDR_LEN.checked_add(len)?)?;
        Some((ndr, args))
    }

    /// A request's NDR header for `args_length` bytes, accepting answers of `args_maximum`.
    pub fn request(args_maximum: u32, args_length: u32, little: bool) -> Ndr {
        Ndr {
            first: if little {
                args_maximum.to_le_bytes()
            } else {
                args_maximum.to_be_bytes()
            },
            args_length,
            maximum_count: args_maximum,
            offset: 0,
            actual_count: args_length,
            little_endian: little,
        }
    }

    /// A response's NDR header: `status`, `args_length` bytes, the request's MaximumCount.
    pub fn response(status: PnioStatus, args_length: u32, maximum_count: u32, little: bool) -> Ndr {
        let mut first = status.0;
        if little {
            first.reverse();
        }
        Ndr {
            first,
            args_length,
            maximum_count,
            offset: 0,
            actual_count: args_length,
            little_endian: little,
        }
    }

    /// A request's ArgsMaximum.
    pub fn args_maximum(&self) -> u32 {
        if self.little_endian {
            u32::from_le_bytes(self.first)
        } else {
            u32::from_be_bytes(self.first)
        }
    }

    /// A response's PNIOStatus.
    pub fn status(&self) -> PnioStatus {
        let mut status = self.first;
        if self.little_endian {
            status.reverse();
        }
        PnioStatus(status)
    }

    /// Writes the header at the start of `buf`; its length ([`NDR_LEN`]).
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize, BufferTooSmall> {
        let little = self.little_endian;
        let at = put(buf, 0, &self.first)?;
        let at = put32(buf, at, self.args_length, little)?;
        let at = put32(buf, at, self.maximum_count, little)?;
        let at = put32(buf, at, self.offset, little)?;
        put32(buf, at, self.actual_count, little)
    }
}

/// A whole PDU written into `buf`: `header`, then the NDR header and `args`; its length. The
/// body (NDR header and `args`) must fit RPC's 16-bit length.
pub fn emit_pdu(
    header: &RpcHeader,
    ndr: &Ndr,
    args: &[u8],
    buf: &mut [u8],
) -> Result<usize, BufferTooSmall> {
    let body_len = u16::try_from(NDR_LEN + args.len()).map_err(|_| BufferTooSmall)?;
    let at = header.emit(body_len, buf)?;
    let at = at + ndr.emit(buf.get_mut(at..).ok_or(BufferTooSmall)?)?;
    put(buf, at, args)
}

/// A reject or fault PDU answering `request` with the 4-byte `status` as its body, written
/// into `buf`; its length.
pub fn emit_reject(
    request: &RpcHeader,
    packet_type: u8,
    status: u32,
    buf: &mut [u8],
) -> Result<usize, BufferTooSmall> {
    let at = request.answer(packet_type).emit(4, buf)?;
    put32(buf, at, status, request.little_endian)
}

#[cfg(test)]
mod tests;
