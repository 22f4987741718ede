//! The DCP PDU (IEC 61158-6-10, Discovery and basic Configuration Protocol): FrameID, service
//! header (ServiceID, ServiceType, Xid, ResponseDelay, DCPDataLength) and the blocks (Option,
//! Suboption, DCPBlockLength, data padded to an even length). Requests carry blocks with a
//! BlockQualifier (Set) or filter values (Identify), Get requests bare option pairs; responses
//! carry a BlockInfo before the data.

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

impl DcpHeader {
    /// Reads the header and the blocks' bytes (`length` of them, or `None` when the PDU is
    /// shorter than it says).
    pub fn parse(pdu: &[u8]) -> Option<(DcpHeader, &[u8])> {
        let h = pdu.get(..HEADER_LEN)?;
        let header = DcpHeader {
            frame_id: u16::from_be_bytes([h[0], h[1]]),
            service_id: h[2],
            service_type: h[3],
            xid: u32::from_be_bytes([h[4], h[5], h[6], h[7]]),
            response_delay: u16::from_be_bytes([h[8], h[9]]),
            length: u16::from_be_bytes([h[10], h[11]]),
        };
        let blocks = pdu.get(HEADER_LEN..HEADER_LEN + usize::from(header.length))?;
        Some((header, blocks))
    }

    /// Appends the header; `length` is patched by [`finish`].
    pub fn emit(&self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.frame_id.to_be_bytes());
        out.push(self.service_id);
        out.push(self.service_type);
        out.extend_from_slice(&self.xid.to_be_bytes());
        out.extend_from_slice(&self.response_delay.to_be_bytes());
        out.extend_from_slice(&self.length.to_be_bytes());
    }
}

/// Sets DCPDataLength of the PDU that starts at `pdu_start` in `out` to the bytes after its
/// header.
pub fn finish(out: &mut [u8], pdu_start: usize) {
    let len = out.len().saturating_sub(pdu_start + HEADER_LEN);
    let len = u16::try_from(len).unwrap_or(u16::MAX).to_be_bytes();
    if let Some(field) = out.get_mut(pdu_start + 10..pdu_start + 12) {
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

/// The blocks of a request, in order; `Err(())` at a block whose length runs past the data.
pub fn blocks(mut data: &[u8]) -> impl Iterator<Item = Result<Block<'_>, ()>> {
    std::iter::from_fn(move || {
        if data.is_empty() {
            return None;
        }
        let Some(head) = data.get(..4) else {
            data = &[];
            return Some(Err(()));
        };
        let option = (head[0], head[1]);
        let len = usize::from(u16::from_be_bytes([head[2], head[3]]));
        let Some(block) = data.get(4..4 + len) else {
            data = &[];
            return Some(Err(()));
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

/// Appends a response block: option, suboption, length (BlockInfo + data), BlockInfo, data,
/// padding to even.
pub fn emit_block(out: &mut Vec<u8>, option: (u8, u8), block_info: u16, data: &[u8]) {
    out.push(option.0);
    out.push(option.1);
    let len = u16::try_from(data.len() + 2).unwrap_or(u16::MAX);
    out.extend_from_slice(&len.to_be_bytes());
    out.extend_from_slice(&block_info.to_be_bytes());
    out.extend_from_slice(data);
    if data.len() % 2 == 1 {
        out.push(0);
    }
}

/// Appends a request block (Hello carries these: no BlockInfo): option, suboption, length, data,
/// padding to even.
pub fn emit_plain_block(out: &mut Vec<u8>, option: (u8, u8), data: &[u8]) {
    out.push(option.0);
    out.push(option.1);
    let len = u16::try_from(data.len()).unwrap_or(u16::MAX);
    out.extend_from_slice(&len.to_be_bytes());
    out.extend_from_slice(data);
    if data.len() % 2 == 1 {
        out.push(0);
    }
}

/// Appends a Control/Response block answering a Set of `option` with `error`.
pub fn emit_set_response(out: &mut Vec<u8>, option: (u8, u8), error: u8) {
    out.extend_from_slice(&[CONTROL_RESPONSE.0, CONTROL_RESPONSE.1, 0, 3]);
    out.extend_from_slice(&[option.0, option.1, error, 0]);
}

/// A controller's request frame: `service` on `frame_id` from `src` to `dst`, with `blocks`
/// already encoded (filter or Set blocks with [`emit_plain_block`], Get option pairs).
pub fn request(
    dst: [u8; 6],
    src: [u8; 6],
    frame_id: u16,
    service: u8,
    xid: u32,
    blocks: &[u8],
) -> Vec<u8> {
    let mut out = Vec::new();
    super::Ethernet::emit(dst, src, &mut out);
    let start = out.len();
    DcpHeader {
        frame_id,
        service_id: service,
        service_type: TYPE_REQUEST,
        xid,
        // Identify's ResponseDelayFactor 1: answer at once.
        response_delay: u16::from(frame_id == FRAME_IDENTIFY_REQUEST),
        length: 0,
    }
    .emit(&mut out);
    out.extend_from_slice(blocks);
    finish(&mut out, start);
    out
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_are_padded_to_even_and_bounded() {
        let data = [2, 2, 0, 3, 0, 0, b'a', 0, 0xFF, 0xFF, 0, 0];
        let read: Vec<_> = blocks(&data).collect();
        assert_eq!(
            read,
            vec![
                Ok(Block {
                    option: (2, 2),
                    data: &[0, 0, b'a'][..]
                }),
                Ok(Block {
                    option: (0xFF, 0xFF),
                    data: &[][..]
                }),
            ]
        );
        assert_eq!(blocks(&[2, 2, 0, 9, 1]).collect::<Vec<_>>(), vec![Err(())]);
        assert_eq!(blocks(&[2, 2]).collect::<Vec<_>>(), vec![Err(())]);
    }

    #[test]
    fn header_round_trip_and_short_pdus() {
        let h = DcpHeader {
            frame_id: FRAME_IDENTIFY_REQUEST,
            service_id: SERVICE_IDENTIFY,
            service_type: TYPE_REQUEST,
            xid: 0x0102_0304,
            response_delay: 0x80,
            length: 4,
        };
        let mut out = Vec::new();
        h.emit(&mut out);
        out.extend_from_slice(&[0xFF, 0xFF, 0, 0]);
        assert_eq!(
            out,
            [0xFE, 0xFE, 5, 0, 1, 2, 3, 4, 0, 0x80, 0, 4, 0xFF, 0xFF, 0, 0]
        );
        assert_eq!(DcpHeader::parse(&out), Some((h, &out[12..])));
        assert_eq!(DcpHeader::parse(&out[..15]), None);
    }
}
