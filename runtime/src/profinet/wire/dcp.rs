//! The DCP PDU (IEC 61158-6-10, Discovery and basic Configuration Protocol): FrameID, service
//! header (ServiceID, ServiceType, Xid, ResponseDelay, DCPDataLength) and the blocks (Option,
//! Suboption, DCPBlockLength, data padded to an even length). Requests carry blocks with a
//! BlockQualifier (Set) or filter values (Identify), Get requests bare option pairs; responses
//! carry a BlockInfo before the data. Blocks are read as an iterator over views of the caller's
//! bytes and written into the caller's buffer.

use super::{put, BufferTooSmall, Ethernet, Mac};

/// FrameID of a Hello request (multicast 01:0e:cf:00:00:01).
pub const FRAME_HELLO: u16 = 0xFEFC;
/// FrameID of Get and Set, requests and responses (unicast).
pub const FRAME_GET_SET: u16 = 0xFEFD;
/// FrameID of an Identify request (multicast 01:0e:cf:00:00:00, or unicast).
pub const FRAME_IDENTIFY_REQUEST: u16 = 0xFEFE;
/// FrameID of an Identify response (unicast).
pub const FRAME_IDENTIFY_RESPONSE: u16 = 0xFEFF;
/// The Identify multicast address.
pub const MULTICAST_IDENTIFY: [u8; 6] = [0x01, 0x0E, 0xCF, 0x00, 0x00, 0x00];
/// The Hello multicast address.
pub const MULTICAST_HELLO: [u8; 6] = [0x01, 0x0E, 0xCF, 0x00, 0x00, 0x01];

/// ServiceID Get.
pub const SERVICE_GET: u8 = 3;
/// ServiceID Set.
pub const SERVICE_SET: u8 = 4;
/// ServiceID Identify.
pub const SERVICE_IDENTIFY: u8 = 5;
/// ServiceID Hello.
pub const SERVICE_HELLO: u8 = 6;
/// ServiceType request.
pub const TYPE_REQUEST: u8 = 0;
/// ServiceType response, success.
pub const TYPE_RESPONSE: u8 = 1;
/// ServiceType response, request not supported.
pub const TYPE_NOT_SUPPORTED: u8 = 5;

/// Option IP, suboption MAC address.
pub const MAC_ADDRESS: (u8, u8) = (1, 1);
/// Option IP, suboption IP parameter (address, mask, gateway).
pub const IP_PARAMETER: (u8, u8) = (1, 2);
/// Device properties: type of station (vendor text).
pub const TYPE_OF_STATION: (u8, u8) = (2, 1);
/// Device properties: name of station.
pub const NAME_OF_STATION: (u8, u8) = (2, 2);
/// Device properties: VendorID and DeviceID.
pub const DEVICE_ID: (u8, u8) = (2, 3);
/// Device properties: device role.
pub const DEVICE_ROLE: (u8, u8) = (2, 4);
/// Device properties: the options the device has.
pub const DEVICE_OPTIONS: (u8, u8) = (2, 5);
/// Device properties: alias name (name of port.name of station).
pub const ALIAS_NAME: (u8, u8) = (2, 6);
/// Device properties: device instance.
pub const DEVICE_INSTANCE: (u8, u8) = (2, 7);
/// Control: start transaction.
pub const CONTROL_START: (u8, u8) = (5, 1);
/// Control: end transaction.
pub const CONTROL_END: (u8, u8) = (5, 2);
/// Control: signal (flash the LED).
pub const CONTROL_SIGNAL: (u8, u8) = (5, 3);
/// Control: response (to a Set).
pub const CONTROL_RESPONSE: (u8, u8) = (5, 4);
/// Control: factory reset.
pub const CONTROL_FACTORY_RESET: (u8, u8) = (5, 5);
/// Control: reset to factory.
pub const CONTROL_RESET_TO_FACTORY: (u8, u8) = (5, 6);
/// All selector (Identify all).
pub const ALL_SELECTOR: (u8, u8) = (0xFF, 0xFF);

/// BlockError: no error.
pub const ERROR_NONE: u8 = 0;
/// BlockError: option not supported.
pub const ERROR_OPTION: u8 = 1;
/// BlockError: suboption not supported or no data set available.
pub const ERROR_SUBOPTION: u8 = 2;
/// BlockError: suboption not set.
pub const ERROR_NOT_SET: u8 = 3;
/// BlockError: set not possible by local reasons.
pub const ERROR_LOCAL: u8 = 5;

/// A DCP PDU's header: FrameID and the service header (10 bytes after it).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DcpHeader {
    /// FrameID.
    pub frame_id: u16,
    /// ServiceID.
    pub service_id: u8,
    /// ServiceType.
    pub service_type: u8,
    /// Xid: the transaction the response answers.
    pub xid: u32,
    /// ResponseDelayFactor (Identify requests), else reserved.
    pub response_delay: u16,
    /// DCPDataLength: the bytes of blocks that follow.
    pub length: u16,
}

/// The header's size with the FrameID.
pub const HEADER_LEN: usize = 12;

/// A checked view of a DCP PDU: the header and as many block bytes as DCPDataLength says.
#[derive(Debug, Clone, Copy)]
pub struct DcpPacket<T: AsRef<[u8]>> {
    buffer: T,
}

impl<T: AsRef<[u8]>> DcpPacket<T> {
    /// The view, or `None` when the PDU is shorter than its header or than DCPDataLength says.
    pub fn new_checked(buffer: T) -> Option<Self> {
        let packet = DcpPacket { buffer };
        let h = packet.buffer.as_ref().get(..HEADER_LEN)?;
        let length = usize::from(u16::from_be_bytes([h[10], h[11]]));
        packet.buffer.as_ref().get(..HEADER_LEN + length)?;
        Some(packet)
    }

    /// The header.
    pub fn header(&self) -> DcpHeader {
        let h = &self.buffer.as_ref()[..HEADER_LEN];
        DcpHeader {
            frame_id: u16::from_be_bytes([h[0], h[1]]),
            service_id: h[2],
            service_type: h[3],
            xid: u32::from_be_bytes([h[4], h[5], h[6], h[7]]),
            response_delay: u16::from_be_bytes([h[8], h[9]]),
            length: u16::from_be_bytes([h[10], h[11]]),
        }
    }

    /// The blocks' bytes (DCPDataLength of them; padding after them is not included).
    pub fn blocks(&self) -> &[u8] {
        let length = usize::from(self.header().length);
        &self.buffer.as_ref()[HEADER_LEN..HEADER_LEN + length]
    }
}

impl DcpHeader {
    /// Reads the header and the blocks' bytes (`length` of them, or `None` when the PDU is
    /// shorter than it says).
    pub fn parse(pdu: &[u8]) -> Option<(DcpHeader, &[u8])> {
        let header = DcpPacket::new_checked(pdu)?.header();
        let blocks = pdu.get(HEADER_LEN..HEADER_LEN + usize::from(header.length))?;
        Some((header, blocks))
    }

    /// Writes the header at the start of `buf`; `length` is patched by [`finish`].
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize, BufferTooSmall> {
        let at = put(buf, 0, &self.frame_id.to_be_bytes())?;
        let at = put(buf, at, &[self.service_id, self.service_type])?;
        let at = put(buf, at, &self.xid.to_be_bytes())?;
        let at = put(buf, at, &self.response_delay.to_be_bytes())?;
        put(buf, at, &self.length.to_be_bytes())
    }
}

/// Sets DCPDataLength of the PDU that starts at `pdu_start` in `frame` to the bytes after its
/// header (to the end of `frame`).
pub fn finish(frame: &mut [u8], pdu_start: usize) {
    let len = frame.len().saturating_sub(pdu_start + HEADER_LEN);
    let len = u16::try_from(len).unwrap_or(u16::MAX).to_be_bytes();
    if let Some(field) = frame.get_mut(pdu_start + 10..pdu_start + 12) {
        field.copy_from_slice(&len);
    }
}

/// One block of a request: option, suboption and its data (without padding).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Block<'a> {
    /// Option and suboption.
    pub option: (u8, u8),
    /// The data (DCPBlockLength bytes).
    pub data: &'a [u8],
}

/// A block whose DCPBlockLength runs past the PDU's data.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TruncatedBlock;

/// The blocks of a request, in order; an error at a block whose length runs past the data.
pub fn blocks(mut data: &[u8]) -> impl Iterator<Item = Result<Block<'_>, TruncatedBlock>> {
    core::iter::from_fn(move || {
        if data.is_empty() {
            return None;
        }
        let Some(head) = data.get(..4) else {
            data = &[];
            return Some(Err(TruncatedBlock));
        };
        let option = (head[0], head[1]);
        let len = usize::from(u16::from_be_bytes([head[2], head[3]]));
        let Some(block) = data.get(4..4 + len) else {
            data = &[];
            return Some(Err(TruncatedBlock));
        };
        let padded = (4 + len + (len & 1)).min(data.len());
        data = &data[padded..];
        Some(Ok(Block {
            option,
            data: block,
        }))
    })
}

/// The option pairs of a Get request (two bytes each); a trailing odd byte is ignored.
pub fn get_options(data: &[u8]) -> impl Iterator<Item = (u8, u8)> + '_ {
    data.chunks_exact(2).map(|c| (c[0], c[1]))
}

/// Writes a block at the start of `buf`: option, suboption, DCPBlockLength (`info` and the
/// data), `info`, the data, padding to even; its length.
fn emit_any_block(
    buf: &mut [u8],
    option: (u8, u8),
    info: &[u8],
    data: &[u8],
) -> Result<usize, BufferTooSmall> {
    let len = u16::try_from(info.len() + data.len()).map_err(|_| BufferTooSmall)?;
    let at = put(buf, 0, &[option.0, option.1])?;
    let at = put(buf, at, &len.to_be_bytes())?;
    let at = put(buf, at, info)?;
    let at = put(buf, at, data)?;
    if data.len() % 2 == 1 {
        return put(buf, at, &[0]);
    }
    Ok(at)
}

/// Writes a response block at the start of `buf`: option, suboption, length (BlockInfo +
/// data), BlockInfo, data, padding to even; its length.
pub fn emit_block(
    buf: &mut [u8],
    option: (u8, u8),
    block_info: u16,
    data: &[u8],
) -> Result<usize, BufferTooSmall> {
    emit_any_block(buf, option, &block_info.to_be_bytes(), data)
}

/// Writes a request block (Hello carries these: no BlockInfo) at the start of `buf`: option,
/// suboption, length, data, padding to even; its length.
pub fn emit_plain_block(
    buf: &mut [u8],
    option: (u8, u8),
    data: &[u8],
) -> Result<usize, BufferTooSmall> {
    emit_any_block(buf, option, &[], data)
}

/// Writes a Control/Response block answering a Set of `option` with `error`; its length (8).
pub fn emit_set_response(
    buf: &mut [u8],
    option: (u8, u8),
    error: u8,
) -> Result<usize, BufferTooSmall> {
    let at = put(buf, 0, &[CONTROL_RESPONSE.0, CONTROL_RESPONSE.1, 0, 3])?;
    put(buf, at, &[option.0, option.1, error, 0])
}

/// A controller's request frame written into `buf`: `service` on `frame_id` from `src` to
/// `dst`, with `blocks` already encoded (filter or Set blocks with [`emit_plain_block`], Get
/// option pairs); its length (unpadded).
pub fn request(
    buf: &mut [u8],
    dst: Mac,
    src: Mac,
    frame_id: u16,
    service: u8,
    xid: u32,
    blocks: &[u8],
) -> Result<usize, BufferTooSmall> {
    let start = Ethernet::emit(dst, src, buf)?;
    let header = DcpHeader {
        frame_id,
        service_id: service,
        service_type: TYPE_REQUEST,
        xid,
        // Identify's ResponseDelayFactor 1: answer at once.
        response_delay: u16::from(frame_id == FRAME_IDENTIFY_REQUEST),
        length: 0,
    };
    let at = start + header.emit(buf.get_mut(start..).ok_or(BufferTooSmall)?)?;
    let end = put(buf, at, blocks)?;
    finish(&mut buf[..end], start);
    Ok(end)
}

/// The blocks of a response (each with its BlockInfo, or the Control/Response block with its
/// option and BlockError): (option, BlockInfo, data); a block that runs past the data ends them.
pub fn response_blocks(data: &[u8]) -> impl Iterator<Item = ((u8, u8), u16, &[u8])> {
    blocks(data).map_while(Result::ok).map(|b| {
        let info = b
            .data
            .get(..2)
            .map_or(0, |i| u16::from_be_bytes([i[0], i[1]]));
        (b.option, info, b.data.get(2..).unwrap_or(&[]))
    })
}

/// How a name of station breaks the PROFINET name rules (IEC 61158-6-10, NameOfStationValue):
/// up to 240 characters of labels separated by dots, each 1 to 63 lowercase letters, digits and
/// `-`, not starting or ending with `-`; the first label not of the form `port-xyz` or
/// `port-xyz-abcde` (digits), which name ports; and not of the form `n.n.n.n` (digits), which
/// reads as an IPv4 address. A device refuses such a name with BlockError 3 (p-net does, for the
/// forms it checks; it lets an empty label pass, and `port-xyz` only as the whole name).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NameProblem {
    /// Over 240 characters.
    TooLong,
    /// An empty label (a leading, trailing or doubled dot).
    EmptyLabel,
    /// A label over 63 characters.
    LabelTooLong,
    /// An uppercase letter: names of station are lowercase.
    Uppercase,
    /// A character other than a lowercase letter, a digit, `-` or `.`.
    Character,
    /// A label that starts or ends with `-`.
    Hyphen,
    /// The first label is `port-xyz` or `port-xyz-abcde`.
    PortName,
    /// The name is four labels of digits, like an IPv4 address.
    IpAddress,
}

impl NameProblem {
    /// The rule broken, in words.
    pub fn reason(self) -> &'static str {
        match self {
            NameProblem::TooLong => "longer than 240 characters",
            NameProblem::EmptyLabel => "an empty label (a leading, trailing or doubled `.`)",
            NameProblem::LabelTooLong => "a label longer than 63 characters",
            NameProblem::Uppercase => "uppercase letters (names of station are lowercase)",
            NameProblem::Character => {
                "a character other than lowercase letters, digits, `-` and `.`"
            }
            NameProblem::Hyphen => "a label that starts or ends with `-`",
            NameProblem::PortName => {
                "a first label of the form `port-xyz` or `port-xyz-abcde`, which names a port"
            }
            NameProblem::IpAddress => "the form `n.n.n.n` of an IP address",
        }
    }
}

impl core::fmt::Display for NameProblem {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.reason())
    }
}

/// `true` when `label` is `port-` and `digits` digits.
fn port_label(label: &str, digits: usize) -> bool {
    label.len() == 5 + digits
        && label.starts_with("port-")
        && label.bytes().skip(5).all(|b| b.is_ascii_digit())
}

/// The first rule a name of station breaks, `None` for a valid one. The empty name is valid
/// (a device without a name).
pub fn name_problem(name: &str) -> Option<NameProblem> {
    if name.is_empty() {
        return None;
    }
    if name.len() > 240 {
        return Some(NameProblem::TooLong);
    }
    for label in name.split('.') {
        if label.is_empty() {
            return Some(NameProblem::EmptyLabel);
        }
        if label.len() > 63 {
            return Some(NameProblem::LabelTooLong);
        }
        if label.bytes().any(|b| b.is_ascii_uppercase()) {
            return Some(NameProblem::Uppercase);
        }
        if !label
            .bytes()
            .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'-')
        {
            return Some(NameProblem::Character);
        }
        if label.starts_with('-') || label.ends_with('-') {
            return Some(NameProblem::Hyphen);
        }
    }
    let first = name.split('.').next().unwrap_or_default();
    let port_with_slot = first
        .get(..8)
        .zip(first.get(8..9))
        .is_some_and(|(port, dash)| port_label(port, 3) && dash == "-")
        && first.len() == 14
        && first.bytes().skip(9).all(|b| b.is_ascii_digit());
    if port_label(first, 3) || port_with_slot {
        return Some(NameProblem::PortName);
    }
    let labels = name.split('.');
    if labels.clone().count() == 4
        && labels
            .clone()
            .all(|l| l.bytes().all(|b| b.is_ascii_digit()))
    {
        return Some(NameProblem::IpAddress);
    }
    None
}

/// A name of station as PROFINET allows it ([`name_problem`] finds nothing): empty (no name),
/// or labels of lowercase letters, digits and `-` that are not a port's name or an address.
pub fn valid_name(name: &str) -> bool {
    name_problem(name).is_none()
}

#[cfg(test)]
mod tests;
