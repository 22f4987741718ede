//! The layouts against exact bytes: what the simulated adapter, the bench scanner and the
//! peers (python ethernetip, cpppo) exchange; and short or odd bytes are errors, never panics.

use super::connection_manager::{
    network_params, ForwardCloseRepr, ForwardOpenReply, ForwardOpenRepr, Triad, DEFAULT_TICKS,
};
use super::cpf::{item, CpfRepr, Item, Items, SendDataRepr, Sockaddr};
use super::encap::{EncapError, EncapPacket, EncapRepr, IdentityItem, RegisterSession};
use super::epath::{LogicalPath, Path};
use super::io::{ConnectedMessage, IoDatagram};
use super::message::{RequestRepr, ResponseRepr};
use super::{Emit, Error};

fn emit(repr: &impl Emit) -> ([u8; 128], usize) {
    let mut buf = [0; 128];
    let len = repr.emit(&mut buf).expect("fits");
    assert_eq!(len, repr.buffer_len());
    (buf, len)
}

macro_rules! assert_emits {
    ($repr:expr, $bytes:expr) => {{
        let (buf, len) = emit(&$repr);
        assert_eq!(&buf[..len], &$bytes[..]);
    }};
}

const TRIAD: Triad = Triad {
    serial: 7,
    vendor: 0xEDE5,
    originator_serial: 0x0102_0304,
};

const CONNECTION_PATH: [u8; 8] = [0x20, 0x04, 0x24, 0x01, 0x2C, 0x96, 0x2C, 0x64];

fn open(large: bool) -> ForwardOpenRepr<'static> {
    ForwardOpenRepr {
        large,
        ticks: DEFAULT_TICKS,
        o_t_id: 0,
        t_o_id: 0x2000_0001,
        triad: TRIAD,
        multiplier: 1,
        o_t_rpi: 20_000,
        o_t_params: network_params(large, 2, 2, false, 10),
        t_o_rpi: 20_000,
        t_o_params: network_params(large, 2, 2, false, 6),
        transport: 0x01,
        path: &CONNECTION_PATH,
    }
}

#[test]
fn register_session_round_trip() {
    let data = RegisterSession::REQUEST.to_bytes();
    let message = EncapRepr::request(0x65, 0, *b"edsgen  ", &data);
    let bytes = [
        0x65, 0, 4, 0, 0, 0, 0, 0, 0, 0, 0, 0, b'e', b'd', b's', b'g', b'e', b'n', b' ', b' ', 0,
        0, 0, 0, 1, 0, 0, 0,
    ];
    assert_emits!(message, bytes);
    let packet = EncapPacket::new_checked(&bytes[..]).expect("whole");
    assert_eq!(
        (packet.command(), packet.length(), packet.total_len()),
        (0x65, 4, 28)
    );
    assert_eq!(EncapRepr::parse(&packet), Ok(message));
    assert_eq!(
        RegisterSession::parse(&[1, 0, 0, 0]),
        Ok(RegisterSession::REQUEST)
    );
    assert_eq!(RegisterSession::parse(&[1, 0]), Err(Error::Truncated));
    assert_eq!(
        RegisterSession::parse(&[1, 0, 0, 0, 0]),
        Err(Error::Trailing)
    );
    // A TCP stream: a message and the start of the next.
    let mut stream = bytes.to_vec();
    stream.extend_from_slice(&bytes[..5]);
    assert_eq!(EncapRepr::parse_prefix(&stream), Ok((message, 28)));
    assert_eq!(
        EncapRepr::parse_prefix(&stream[28..]),
        Err(EncapError::Incomplete)
    );
    assert_eq!(
        EncapRepr::parse_prefix(&bytes[..26]),
        Err(EncapError::Truncated { needed: 28 })
    );
    // Unchecked views read zeros past the end.
    let short = EncapPacket::new_unchecked(&bytes[..3]);
    assert_eq!(
        (short.command(), short.session(), short.data()),
        (0x65, 0, &[][..])
    );
}

#[test]
fn reply_keeps_command_session_and_context() {
    let request = EncapRepr::request(0x6F, 3, *b"ctx12345", &[1, 2]);
    let reply = request.reply(0x64, &[]);
    assert_eq!(
        (reply.command, reply.session, reply.status, reply.context),
        (0x6F, 3, 0x64, *b"ctx12345")
    );
    let mut small = [0; 23];
    assert_eq!(reply.emit(&mut small), Err(Error::BufferTooSmall));
}

#[test]
fn identity_item_bytes() {
    let identity = IdentityItem {
        protocol_version: 1,
        port: 44818,
        address: [192, 168, 0, 1],
        vendor: 0,
        device_type: 12,
        product_code: 350,
        revision: (1, 10),
        status: 0,
        serial: 0x1234_5678,
        name: b"GD350",
        state: 3,
    };
    let bytes = [
        1, 0, 0, 2, 0xAF, 0x12, 192, 168, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 12, 0, 0x5E, 0x01, 1,
        10, 0, 0, 0x78, 0x56, 0x34, 0x12, 5, b'G', b'D', b'3', b'5', b'0', 3,
    ];
    assert_emits!(identity, bytes);
    assert_eq!(IdentityItem::parse(&bytes), Ok(identity));
    let without_state = IdentityItem::parse(&bytes[..38]).expect("parses");
    assert_eq!(without_state.state, 0xFF);
    assert_eq!(IdentityItem::parse(&bytes[..36]), Err(Error::Truncated));
}

#[test]
fn cpf_items_and_send_data() {
    let request = [0x0E, 3, 0x20, 0x01, 0x24, 0x01, 0x30, 0x07];
    let items = [
        Item::new(item::NULL_ADDRESS, &[]),
        Item::new(item::UNCONNECTED_DATA, &request),
    ];
    let bytes = [
        0, 0, 0, 0, 0, 0, 2, 0, 0, 0, 0, 0, 0xB2, 0, 8, 0, 0x0E, 3, 0x20, 0x01, 0x24, 0x01, 0x30,
        0x07,
    ];
    assert_emits!(
        SendDataRepr {
            timeout: 0,
            items: &items
        },
        bytes
    );
    let parsed = Items::parse_send_data(&bytes).expect("items");
    assert!(parsed.iter().eq(items.iter().copied()));
    assert_eq!(parsed.find(item::UNCONNECTED_DATA), Some(&request[..]));
    assert_eq!(parsed.find(item::CONNECTED_DATA), None);
    // A count or a length past the bytes.
    assert_eq!(Items::parse(&bytes[6..23]), Err(Error::Truncated));
    assert_eq!(Items::parse(&[3, 0, 0, 0, 0, 0]), Err(Error::Truncated));
    assert_eq!(Items::parse(&[1]), Err(Error::Truncated));
    assert_emits!(CpfRepr { items: &[] }, [0, 0]);
}

#[test]
fn sockaddr_bytes() {
    let port = Sockaddr {
        port: 0x1234,
        address: [127, 0, 0, 1],
    };
    assert_eq!(
        port.to_bytes(),
        [0, 2, 0x12, 0x34, 127, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0]
    );
    assert_eq!(Sockaddr::parse(&port.to_bytes()), Ok(port));
    assert_eq!(Sockaddr::parse(&[0, 2, 8]), Err(Error::Malformed));
}

#[test]
fn message_router_request_and_response() {
    let path = [0x20, 0x01, 0x24, 0x01, 0x30, 0x07];
    let get = RequestRepr {
        service: 0x0E,
        path: &path,
        data: &[],
    };
    assert_emits!(get, [0x0E, 3, 0x20, 0x01, 0x24, 0x01, 0x30, 0x07]);
    assert_eq!(
        RequestRepr::parse(&[0x0E, 3, 0x20, 0x01]),
        Err(Error::Truncated)
    );
    let odd = RequestRepr {
        service: 0x0E,
        path: &[0x20],
        data: &[],
    };
    assert_eq!(odd.emit(&mut [0; 8]), Err(Error::Malformed));
    // Connection failure, invalid O→T size, 10 bytes expected.
    let refused = ResponseRepr {
        service: 0x54,
        status: 0x01,
        extended: &[0x27, 0x01, 10, 0],
        data: &[],
    };
    let bytes = [0xD4, 0, 0x01, 2, 0x27, 0x01, 10, 0];
    assert_emits!(refused, bytes);
    let parsed = ResponseRepr::parse(&bytes).expect("parses");
    assert_eq!(parsed, refused);
    assert_eq!(
        (
            parsed.extended_status(0),
            parsed.extended_status(1),
            parsed.extended_status(2)
        ),
        (Some(0x0127), Some(10), None)
    );
    assert_emits!(ResponseRepr::success(0x0E, &[5, 0]), [0x8E, 0, 0, 0, 5, 0]);
    assert_eq!(ResponseRepr::parse(&[0x8E, 0, 0]), Err(Error::Truncated));
    assert_eq!(
        ResponseRepr::parse(&[0x8E, 0, 1, 2, 0]),
        Err(Error::Truncated)
    );
}

#[test]
fn epath_logical_segments() {
    let path = Path::parse(&CONNECTION_PATH).expect("parses");
    assert_eq!(
        (path.class, path.instance, path.attribute),
        (Some(4), Some(1), None)
    );
    assert_eq!(path.points(), &[150, 100]);
    // 16- and 32-bit formats, a port segment and an electronic key skipped.
    let wide = [
        0x01, 0x00, 0x34, 0x04, 0, 0, 12, 0, 0x5E, 0x01, 0x01, 0x0A, 0x21, 0, 0x34, 0x12, 0x26, 0,
        0x78, 0x56, 0x34, 0x12, 0x30, 0x03,
    ];
    let path = Path::parse(&wide).expect("parses");
    assert_eq!(
        (path.class, path.instance, path.attribute),
        (Some(0x1234), Some(0x1234_5678), Some(3))
    );
    assert_eq!(Path::parse(&[0x20]), Err(Error::Truncated));
    assert_eq!(Path::parse(&[0x21, 0, 1]), Err(Error::Truncated));
    assert_eq!(Path::parse(&[0x23, 0]), Err(Error::Malformed));
    assert_eq!(Path::parse(&[0xE0, 0]), Err(Error::Malformed));
    let five = [0x2C, 1, 0x2C, 2, 0x2C, 3, 0x2C, 4, 0x2C, 5];
    assert_eq!(Path::parse(&five), Err(Error::Malformed));
    assert_emits!(
        LogicalPath {
            class: 0x0F,
            instance: 300,
            attribute: Some(1)
        },
        [0x20, 0x0F, 0x25, 0, 0x2C, 0x01, 0x30, 0x01]
    );
    assert_emits!(
        LogicalPath::assembly_data(100),
        [0x20, 0x04, 0x24, 100, 0x30, 0x03]
    );
    assert_emits!(LogicalPath::CONNECTION_MANAGER, [0x20, 0x06, 0x24, 0x01]);
    assert_emits!(
        LogicalPath::assembly_data(0x1_0000),
        [0x20, 0x04, 0x26, 0, 0, 0, 1, 0, 0x30, 0x03]
    );
}

#[test]
fn forward_open_bytes_small_and_large() {
    let small = [
        0x54, 2, 0x20, 0x06, 0x24, 0x01, 0x0A, 0x0E, 0, 0, 0, 0, 0x01, 0, 0, 0x20, 7, 0, 0xE5,
        0xED, 0x04, 0x03, 0x02, 0x01, 1, 0, 0, 0, 0x20, 0x4E, 0, 0, 0x0A, 0x48, 0x20, 0x4E, 0, 0,
        0x06, 0x48, 0x01, 4, 0x20, 0x04, 0x24, 0x01, 0x2C, 0x96, 0x2C, 0x64,
    ];
    assert_emits!(open(false), small);
    let request = RequestRepr::parse(&small).expect("request");
    assert_eq!(ForwardOpenRepr::parse(request.data, false), Ok(open(false)));
    let (large, len) = emit(&open(true));
    assert_eq!(large[0], 0x5B);
    // 32-bit parameter words: O→T at 32..36, T→O at 40..44.
    assert_eq!(&large[32..36], &[0x0A, 0, 0, 0x48]);
    assert_eq!(&large[40..44], &[0x06, 0, 0, 0x48]);
    assert_eq!(len, small.len() + 4);
    let request = RequestRepr::parse(&large[..len]).expect("request");
    let parsed = ForwardOpenRepr::parse(request.data, true).expect("parses");
    assert_eq!(parsed, open(true));
    assert_eq!((parsed.o_t_size(), parsed.t_o_size()), (10, 6));
    assert_eq!(parsed.timeout_us(), 160_000);
    let data = &small[6..];
    assert_eq!(
        ForwardOpenRepr::parse(&data[..20], false),
        Err(Error::Truncated)
    );
    assert_eq!(
        ForwardOpenRepr::parse(&data[..data.len() - 1], false),
        Err(Error::Truncated)
    );
    let mut longer = data.to_vec();
    longer.push(0);
    assert_eq!(ForwardOpenRepr::parse(&longer, false), Err(Error::Trailing));
}

#[test]
fn forward_open_reply_and_forward_close() {
    let reply = ForwardOpenReply {
        o_t_id: 0x1000_0001,
        t_o_id: 0x2000_0001,
        triad: TRIAD,
        o_t_api: 20_000,
        t_o_api: 10_000,
    };
    let bytes = [
        1, 0, 0, 0x10, 1, 0, 0, 0x20, 7, 0, 0xE5, 0xED, 4, 3, 2, 1, 0x20, 0x4E, 0, 0, 0x10, 0x27,
        0, 0, 0, 0,
    ];
    assert_emits!(reply, bytes);
    assert_eq!(ForwardOpenReply::parse(&bytes), Ok(reply));
    assert_eq!(ForwardOpenReply::parse(&bytes[..23]), Err(Error::Truncated));
    assert_eq!(TRIAD.reply(), [7, 0, 0xE5, 0xED, 4, 3, 2, 1, 0, 0]);
    let close = ForwardCloseRepr {
        ticks: DEFAULT_TICKS,
        triad: TRIAD,
        path: &[0x20, 0x04],
    };
    let bytes = [
        0x4E, 2, 0x20, 0x06, 0x24, 0x01, 0x0A, 0x0E, 7, 0, 0xE5, 0xED, 4, 3, 2, 1, 1, 0, 0x20, 0x04,
    ];
    assert_emits!(close, bytes);
    assert_eq!(ForwardCloseRepr::parse(&bytes[6..]), Ok(close));
    // The triad is enough.
    let bare = ForwardCloseRepr::parse(&bytes[6..16]).expect("parses");
    assert_eq!((bare.triad, bare.path), (TRIAD, &[][..]));
    assert_eq!(
        ForwardCloseRepr::parse(&bytes[6..15]),
        Err(Error::Truncated)
    );
}

#[test]
fn class1_datagram() {
    let datagram = IoDatagram {
        connection: 0x1000_0001,
        sequence: 5,
        data: &[5, 0, 1, 0, 0, 0],
    };
    let bytes = [
        2, 0, 0x02, 0x80, 8, 0, 1, 0, 0, 0x10, 5, 0, 0, 0, 0xB1, 0, 6, 0, 5, 0, 1, 0, 0, 0,
    ];
    assert_emits!(datagram, bytes);
    assert_eq!(IoDatagram::parse(&bytes), Ok(datagram));
    assert_eq!(datagram.sequence_count(), Some(5));
    assert_eq!(IoDatagram::parse(&bytes[..10]), Err(Error::Truncated));
    // Only the address item.
    assert_eq!(
        IoDatagram::parse(&[1, 0, 0x02, 0x80, 8, 0, 1, 0, 0, 0x10, 5, 0, 0, 0]),
        Err(Error::Malformed)
    );
}

#[test]
fn class3_message() {
    let message = ConnectedMessage {
        connection: 0x1000_0002,
        sequence: 1,
        message: &[0x0E, 3, 0x20, 0x01, 0x24, 0x01, 0x30, 0x01],
    };
    let bytes = [
        0, 0, 0, 0, 0, 0, 2, 0, 0xA1, 0, 4, 0, 2, 0, 0, 0x10, 0xB1, 0, 10, 0, 1, 0, 0x0E, 3, 0x20,
        0x01, 0x24, 0x01, 0x30, 0x01,
    ];
    assert_emits!(message, bytes);
    assert_eq!(ConnectedMessage::parse(&bytes), Ok(message));
    assert_eq!(message.payload_len(), 10);
    // A two-byte address.
    let short = [
        0, 0, 0, 0, 0, 0, 2, 0, 0xA1, 0, 2, 0, 2, 0, 0xB1, 0, 2, 0, 1, 0,
    ];
    assert_eq!(ConnectedMessage::parse(&short), Err(Error::Malformed));
    assert_eq!(ConnectedMessage::parse(&bytes[..4]), Err(Error::Truncated));
}

#[test]
fn network_parameters() {
    assert_eq!(network_params(false, 2, 2, false, 10), 0x480A);
    assert_eq!(network_params(false, 2, 0, true, 0x1FF), 0x43FF);
    assert_eq!(network_params(true, 2, 2, false, 1000), 0x4800_03E8);
}

#[test]
fn garbage_never_panics() {
    let mut seed = 0x1234_5678u32;
    for len in 0..200 {
        let bytes: [u8; 64] = core::array::from_fn(|_| {
            seed = seed.wrapping_mul(1_103_515_245).wrapping_add(12_345);
            (seed >> 16) as u8
        });
        let bytes = &bytes[..len % 64];
        let _ = EncapRepr::parse_prefix(bytes);
        let _ = Items::parse(bytes).map(|i| i.iter().count());
        let _ = RequestRepr::parse(bytes);
        let _ = ResponseRepr::parse(bytes);
        let _ = Path::parse(bytes);
        let _ = ForwardOpenRepr::parse(bytes, len % 2 == 0);
        let _ = ForwardCloseRepr::parse(bytes);
        let _ = IoDatagram::parse(bytes);
        let _ = ConnectedMessage::parse(bytes);
        let _ = IdentityItem::parse(bytes);
    }
}
