//! EtherNet/IP wire formats, little-endian as CIP is: the 24-byte encapsulation header, the
//! common packet format (CPF) items, Message Router requests and responses, and request paths.
//! Parsing never panics: a short or inconsistent buffer is an error the adapter answers with
//! the status the protocol defines.

/// Encapsulation commands.
pub mod command {
    /// NOP (no reply).
    pub const NOP: u16 = 0x0000;
    /// ListServices.
    pub const LIST_SERVICES: u16 = 0x0004;
    /// ListIdentity (TCP and UDP).
    pub const LIST_IDENTITY: u16 = 0x0063;
    /// ListInterfaces.
    pub const LIST_INTERFACES: u16 = 0x0064;
    /// RegisterSession.
    pub const REGISTER_SESSION: u16 = 0x0065;
    /// UnRegisterSession (no reply).
    pub const UNREGISTER_SESSION: u16 = 0x0066;
    /// SendRRData: unconnected explicit messages.
    pub const SEND_RR_DATA: u16 = 0x006F;
    /// SendUnitData: connected (class 3) explicit messages.
    pub const SEND_UNIT_DATA: u16 = 0x0070;
}

/// Encapsulation status codes.
pub mod encap_status {
    /// Success.
    pub const SUCCESS: u32 = 0x0000;
    /// The command is not one the receiver knows.
    pub const INVALID_COMMAND: u32 = 0x0001;
    /// Malformed data in the command.
    pub const INCORRECT_DATA: u32 = 0x0003;
    /// The session handle is not one the receiver issued.
    pub const INVALID_SESSION: u32 = 0x0064;
    /// The length does not match the data.
    pub const INVALID_LENGTH: u32 = 0x0065;
    /// The protocol version is not supported.
    pub const UNSUPPORTED_PROTOCOL: u32 = 0x0069;
}

/// CPF item types.
pub mod item {
    /// Null address (unconnected messages).
    pub const NULL_ADDRESS: u16 = 0x0000;
    /// Identity (ListIdentity reply).
    pub const IDENTITY: u16 = 0x000C;
    /// Connected address: a connection ID.
    pub const CONNECTED_ADDRESS: u16 = 0x00A1;
    /// Connected data (with a sequence count).
    pub const CONNECTED_DATA: u16 = 0x00B1;
    /// Unconnected data: a Message Router request or response.
    pub const UNCONNECTED_DATA: u16 = 0x00B2;
    /// ListServices reply item.
    pub const SERVICES: u16 = 0x0100;
    /// Sockaddr info, O→T.
    pub const SOCKADDR_O_T: u16 = 0x8000;
    /// Sockaddr info, T→O.
    pub const SOCKADDR_T_O: u16 = 0x8001;
    /// Sequenced address: connection ID and sequence number (class 0/1).
    pub const SEQUENCED_ADDRESS: u16 = 0x8002;
}

/// CIP general status codes.
pub mod general {
    /// Success.
    pub const SUCCESS: u8 = 0x00;
    /// Connection failure (extended status says which).
    pub const CONNECTION_FAILURE: u8 = 0x01;
    /// Path segment error.
    pub const PATH_SEGMENT_ERROR: u8 = 0x04;
    /// Path destination unknown.
    pub const PATH_DESTINATION_UNKNOWN: u8 = 0x05;
    /// Service not supported.
    pub const SERVICE_NOT_SUPPORTED: u8 = 0x08;
    /// Attribute not settable.
    pub const ATTRIBUTE_NOT_SETTABLE: u8 = 0x0E;
    /// Device state conflict.
    pub const DEVICE_STATE_CONFLICT: u8 = 0x10;
    /// Reply data too large (for the connection).
    pub const REPLY_DATA_TOO_LARGE: u8 = 0x11;
    /// Not enough data.
    pub const NOT_ENOUGH_DATA: u8 = 0x13;
    /// Attribute not supported.
    pub const ATTRIBUTE_NOT_SUPPORTED: u8 = 0x14;
    /// Too much data.
    pub const TOO_MUCH_DATA: u8 = 0x15;
    /// Object does not exist.
    pub const OBJECT_DOES_NOT_EXIST: u8 = 0x16;
}

/// An encapsulation header (24 bytes) and its data.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Encapsulation {
    /// The command.
    pub command: u16,
    /// The session handle.
    pub session: u32,
    /// The status.
    pub status: u32,
    /// The sender context, echoed in replies.
    pub context: [u8; 8],
    /// The options word.
    pub options: u32,
    /// The command's data.
    pub data: Vec<u8>,
}

/// Why bytes are no encapsulation message.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EncapError {
    /// Fewer than 24 bytes: wait for more.
    Incomplete,
    /// The header's length goes past the bytes given: wait for more (`needed` in all).
    Truncated {
        /// The whole message's size.
        needed: usize,
    },
}

/// Little-endian reads from a slice, `None` past its end.
pub fn u16_at(b: &[u8], at: usize) -> Option<u16> {
    Some(u16::from_le_bytes([*b.get(at)?, *b.get(at + 1)?]))
}

/// Little-endian `u32` at `at`.
pub fn u32_at(b: &[u8], at: usize) -> Option<u32> {
    Some(u32::from_le_bytes([
        *b.get(at)?,
        *b.get(at + 1)?,
        *b.get(at + 2)?,
        *b.get(at + 3)?,
    ]))
}

impl Encapsulation {
    /// The message at the start of `bytes`, and its size.
    pub fn parse(bytes: &[u8]) -> Result<(Encapsulation, usize), EncapError> {
        if bytes.len() < 24 {
            return Err(EncapError::Incomplete);
        }
        let length = usize::from(u16_at(bytes, 2).unwrap_or(0));
        let needed = 24 + length;
        if bytes.len() < needed {
            return Err(EncapError::Truncated { needed });
        }
        let mut context = [0; 8];
        context.copy_from_slice(&bytes[12..20]);
        Ok((
            Encapsulation {
                command: u16_at(bytes, 0).unwrap_or(0),
                session: u32_at(bytes, 4).unwrap_or(0),
                status: u32_at(bytes, 8).unwrap_or(0),
                context,
                options: u32_at(bytes, 20).unwrap_or(0),
                data: bytes[24..needed].to_vec(),
            },
            needed,
        ))
    }

    /// The message's bytes (the data is cut at 65535 bytes, the most a header can say).
    pub fn emit(&self) -> Vec<u8> {
        let data = &self.data[..self.data.len().min(usize::from(u16::MAX))];
        let mut out = Vec::with_capacity(24 + data.len());
        out.extend_from_slice(&self.command.to_le_bytes());
        out.extend_from_slice(&(data.len() as u16).to_le_bytes());
        out.extend_from_slice(&self.session.to_le_bytes());
        out.extend_from_slice(&self.status.to_le_bytes());
        out.extend_from_slice(&self.context);
        out.extend_from_slice(&self.options.to_le_bytes());
        out.extend_from_slice(data);
        out
    }

    /// A reply to this message: same command, session and context.
    pub fn reply(&self, status: u32, data: Vec<u8>) -> Encapsulation {
        Encapsulation {
            command: self.command,
            session: self.session,
            status,
            context: self.context,
            options: 0,
            data,
        }
    }
}

/// CPF items: (type, data) pairs after an item count; `None` if the count or a length runs past
/// the bytes.
pub fn parse_items(bytes: &[u8]) -> Option<Vec<(u16, &[u8])>> {
    let count = u16_at(bytes, 0)?;
    let mut at = 2;
    let mut items = Vec::new();
    for _ in 0..count {
        let kind = u16_at(bytes, at)?;
        let len = usize::from(u16_at(bytes, at + 2)?);
        let data = bytes.get(at + 4..at + 4 + len)?;
        items.push((kind, data));
        at += 4 + len;
    }
    Some(items)
}

/// CPF items as bytes.
pub fn emit_items(items: &[(u16, &[u8])]) -> Vec<u8> {
    let mut out = Vec::new();
    out.extend_from_slice(&(items.len() as u16).to_le_bytes());
    for (kind, data) in items {
        out.extend_from_slice(&kind.to_le_bytes());
        out.extend_from_slice(&(data.len() as u16).to_le_bytes());
        out.extend_from_slice(data);
    }
    out
}

/// A Message Router request.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Request<'a> {
    /// The service code.
    pub service: u8,
    /// The request path's bytes.
    pub path: &'a [u8],
    /// The service data.
    pub data: &'a [u8],
}

impl<'a> Request<'a> {
    /// The request in `bytes`; `None` when the path runs past them.
    pub fn parse(bytes: &'a [u8]) -> Option<Request<'a>> {
        let service = *bytes.first()?;
        let words = usize::from(*bytes.get(1)?);
        let path = bytes.get(2..2 + 2 * words)?;
        Some(Request {
            service,
            path,
            data: &bytes[2 + 2 * words..],
        })
    }
}

/// A Message Router response's bytes.
pub fn response(service: u8, status: u8, extended: &[u16], data: &[u8]) -> Vec<u8> {
    let mut out = vec![service | 0x80, 0, status, extended.len() as u8];
    for word in extended {
        out.extend_from_slice(&word.to_le_bytes());
    }
    out.extend_from_slice(data);
    out
}

/// A request path's logical class, instance, attribute and connection points.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Path {
    /// Class.
    pub class: Option<u32>,
    /// Instance.
    pub instance: Option<u32>,
    /// Attribute.
    pub attribute: Option<u32>,
    /// Connection points, in order.
    pub points: Vec<u32>,
}

/// Decodes a padded EPATH of logical segments (8/16/32-bit), skipping port, key and data
/// segments; `None` for anything else or a truncated segment.
pub fn parse_path(bytes: &[u8]) -> Option<Path> {
    let mut path = Path::default();
    let mut at = 0;
    while at < bytes.len() {
        let seg = bytes[at];
        match seg >> 5 {
            0 => {
                let len = if seg & 0x10 != 0 {
                    let n = usize::from(*bytes.get(at + 1)?);
                    2 + n + n % 2
                } else {
                    2
                };
                bytes.get(at + len - 1)?;
                at += len;
            }
            1 if seg == 0x34 => {
                bytes.get(at + 9)?;
                at += 10;
            }
            1 => {
                let (value, len) = match seg & 3 {
                    0 => (u32::from(*bytes.get(at + 1)?), 2),
                    1 => (u32::from(u16_at(bytes, at + 2)?), 4),
                    2 => (u32_at(bytes, at + 2)?, 6),
                    _ => return None,
                };
                match (seg >> 2) & 7 {
                    0 => path.class = Some(value),
                    1 => path.instance = Some(value),
                    3 => path.points.push(value),
                    4 => path.attribute = Some(value),
                    _ => return None,
                }
                at += len;
            }
            4 if seg == 0x80 => {
                let words = usize::from(*bytes.get(at + 1)?);
                bytes.get(at + 1 + 2 * words)?;
                at += 2 + 2 * words;
            }
            _ => return None,
        }
    }
    Some(path)
}

/// A sockaddr info item's data (CPF items 0x8000/0x8001): family 2 (AF_INET), port and IPv4
/// address big-endian, eight zero bytes. A scanner puts one T→O in its Forward_Open to ask for
/// T→O data on another port than 2222.
pub fn sockaddr(port: u16, address: [u8; 4]) -> [u8; 16] {
    let mut out = [0; 16];
    out[..2].copy_from_slice(&2u16.to_be_bytes());
    out[2..4].copy_from_slice(&port.to_be_bytes());
    out[4..8].copy_from_slice(&address);
    out
}

/// The port and address of a sockaddr info item's data; `None` when it is not 16 bytes of
/// family 2.
pub fn parse_sockaddr(data: &[u8]) -> Option<(u16, [u8; 4])> {
    if data.len() != 16 || data[..2] != [0, 2] {
        return None;
    }
    Some((
        u16::from_be_bytes([data[2], data[3]]),
        [data[4], data[5], data[6], data[7]],
    ))
}

/// A Forward_Open (or Large_Forward_Open) request as a scanner sends it to the Connection
/// Manager (class 6, instance 1).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ForwardOpen {
    /// Large_Forward_Open (32-bit network connection parameters) instead of Forward_Open.
    pub large: bool,
    /// The T→O connection ID the scanner chooses (the adapter chooses the O→T one).
    pub t_o_id: u32,
    /// Connection serial number.
    pub serial: u16,
    /// Originator vendor ID.
    pub vendor: u16,
    /// Originator serial number.
    pub originator_serial: u32,
    /// Timeout multiplier code (0 is ×4, 1 ×8, ... 7 ×512).
    pub multiplier: u8,
    /// O→T RPI in µs.
    pub o_t_rpi: u32,
    /// O→T network connection parameters (size in bits 0-8, or 0-15 when large).
    pub o_t_params: u32,
    /// T→O RPI in µs.
    pub t_o_rpi: u32,
    /// T→O network connection parameters.
    pub t_o_params: u32,
    /// Transport class and trigger byte (0x01: class 1, cyclic).
    pub transport: u8,
    /// The connection path (configuration instance, O→T and T→O connection points), padded.
    pub path: Vec<u8>,
}

impl ForwardOpen {
    /// The Message Router request's bytes (service, path `20 06 24 01`, data); the path is cut
    /// at 255 words.
    pub fn request(&self) -> Vec<u8> {
        let service = if self.large { 0x5B } else { 0x54 };
        let mut r = vec![service, 2, 0x20, 0x06, 0x24, 0x01];
        r.extend_from_slice(&[0x0A, 0x0E]); // priority/time tick, timeout ticks: 14 × 1 ms
        r.extend_from_slice(&0u32.to_le_bytes());
        r.extend_from_slice(&self.t_o_id.to_le_bytes());
        r.extend_from_slice(&self.serial.to_le_bytes());
        r.extend_from_slice(&self.vendor.to_le_bytes());
        r.extend_from_slice(&self.originator_serial.to_le_bytes());
        r.extend_from_slice(&[self.multiplier, 0, 0, 0]);
        for (rpi, params) in [
            (self.o_t_rpi, self.o_t_params),
            (self.t_o_rpi, self.t_o_params),
        ] {
            r.extend_from_slice(&rpi.to_le_bytes());
            if self.large {
                r.extend_from_slice(&params.to_le_bytes());
            } else {
                r.extend_from_slice(&(params as u16).to_le_bytes());
            }
        }
        r.push(self.transport);
        let path = &self.path[..self.path.len().min(510)];
        r.push((path.len() / 2) as u8);
        r.extend_from_slice(path);
        r
    }
}

/// A successful Forward_Open reply's data: the O→T and T→O connection IDs and the actual O→T
/// and T→O packet intervals (µs); `None` when the data is short.
pub fn parse_forward_open_reply(data: &[u8]) -> Option<(u32, u32, u32, u32)> {
    Some((
        u32_at(data, 0)?,
        u32_at(data, 4)?,
        u32_at(data, 16)?,
        u32_at(data, 20)?,
    ))
}

/// A Forward_Close request naming a connection by its triad (serial, vendor, originator
/// serial), with its connection path.
pub fn forward_close_request(
    serial: u16,
    vendor: u16,
    originator_serial: u32,
    path: &[u8],
) -> Vec<u8> {
    let mut r = vec![0x4E, 2, 0x20, 0x06, 0x24, 0x01, 0x0A, 0x0E];
    r.extend_from_slice(&serial.to_le_bytes());
    r.extend_from_slice(&vendor.to_le_bytes());
    r.extend_from_slice(&originator_serial.to_le_bytes());
    let path = &path[..path.len().min(510)];
    r.extend_from_slice(&[(path.len() / 2) as u8, 0]);
    r.extend_from_slice(path);
    r
}

/// A class-0/1 datagram: the sequenced address item (connection ID, encapsulation sequence
/// number) and the connected data item (for class 1 its 16-bit sequence count first).
pub fn io_datagram(connection: u32, sequence: u32, data: &[u8]) -> Vec<u8> {
    let mut address = connection.to_le_bytes().to_vec();
    address.extend_from_slice(&sequence.to_le_bytes());
    emit_items(&[
        (item::SEQUENCED_ADDRESS, &address),
        (item::CONNECTED_DATA, data),
    ])
}

/// A class-0/1 datagram's connection ID, encapsulation sequence number and connected data;
/// `None` without both items.
pub fn parse_io_datagram(bytes: &[u8]) -> Option<(u32, u32, &[u8])> {
    let items = parse_items(bytes)?;
    let (_, address) = items.iter().find(|(k, _)| *k == item::SEQUENCED_ADDRESS)?;
    let (_, data) = items.iter().find(|(k, _)| *k == item::CONNECTED_DATA)?;
    Some((u32_at(address, 0)?, u32_at(address, 4)?, data))
}

/// A Forward_Open's network connection parameters: the connection type (1 multicast, 2
/// point-to-point), the priority (0 low, 1 high, 2 scheduled, 3 urgent), fixed or variable size
/// and the size in bytes; 16 bits (size in bits 0-8) or, for Large_Forward_Open, 32 (size in
/// bits 0-15).
pub fn network_params(large: bool, kind: u8, priority: u8, variable: bool, size: u16) -> u32 {
    let (kind, priority) = (u32::from(kind & 3), u32::from(priority & 3));
    if large {
        kind << 29 | priority << 26 | u32::from(variable) << 25 | u32::from(size)
    } else {
        kind << 13 | priority << 10 | u32::from(variable) << 9 | u32::from(size & 0x01FF)
    }
}
