//! The originator (scanner) side, sans-IO: a [`Session`] writes RegisterSession, SendRRData
//! (unconnected explicit messages), SendUnitData (class 3) and UnRegisterSession into the
//! caller's buffer and reads their replies from the caller's bytes; a [`Class1`] connection
//! numbers the O→T datagrams it produces and keeps the T→O data it has not seen. The caller
//! carries the bytes (TCP 44818, UDP 2222) and keeps the time (the RPI, the timeout).

use crate::enip::wire::cpf::{item, Item, Items};
use crate::enip::wire::encap::{command, EncapRepr, RegisterSession, HEADER_LEN};
use crate::enip::wire::io::{ConnectedMessage, IoDatagram};
use crate::enip::wire::message::ResponseRepr;
use crate::enip::wire::{length_u16, Emit, Error, Writer};

/// Why a reply is not the answer asked for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Failure {
    /// The encapsulation refused the command: its status (0x64 invalid session, ...).
    Refused {
        /// The command refused.
        command: u16,
        /// The encapsulation status.
        status: u32,
    },
    /// The reply is not a message of the command's shape; what is missing.
    Malformed(&'static str),
}

/// A SendRRData reply: the Message Router response and the reply's items (sockaddr items
/// after a Forward_Open).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct UnconnectedReply<'a> {
    /// The response.
    pub response: ResponseRepr<'a>,
    /// All the reply's items.
    pub items: Items<'a>,
}

/// An encapsulation session with a target.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Session {
    handle: u32,
    context: [u8; 8],
}

impl Session {
    /// A session not registered yet; `context` goes in every message's sender context.
    pub const fn new(context: [u8; 8]) -> Session {
        Session { handle: 0, context }
    }

    /// The session handle the target issued (0 before [`registered`](Self::registered)).
    pub const fn handle(&self) -> u32 {
        self.handle
    }

    fn message<'a>(&self, command: u16, data: &'a [u8]) -> EncapRepr<'a> {
        EncapRepr::request(command, self.handle, self.context, data)
    }

    /// ListIdentity (no session needed; over UDP, to one target or by broadcast). Its sender
    /// context's first two bytes (little-endian, the low 16 bits) say the maximum delay in ms
    /// a target may wait before it answers (CIP Vol 2 §2-4.2.3; 0 means up to 2000 ms, more
    /// than 2000 is read as 2000); the other six bytes are this session's context's.
    pub fn list_identity(&self, max_delay_ms: u16, buf: &mut [u8]) -> Result<usize, Error> {
        let mut context = self.context;
        context[..2].copy_from_slice(&max_delay_ms.to_le_bytes());
        EncapRepr::request(command::LIST_IDENTITY, 0, context, &[]).emit(buf)
    }

    /// RegisterSession.
    pub fn register(&self, buf: &mut [u8]) -> Result<usize, Error> {
        let data = RegisterSession::REQUEST.to_bytes();
        self.message(command::REGISTER_SESSION, &data).emit(buf)
    }

    /// RegisterSession's reply: the session handle, kept for the messages that follow.
    pub fn registered(&mut self, reply: &[u8]) -> Result<u32, Failure> {
        let reply = checked(command::REGISTER_SESSION, reply)?;
        self.handle = reply.session;
        Ok(reply.session)
    }

    /// UnRegisterSession (the target does not reply).
    pub fn unregister(&self, buf: &mut [u8]) -> Result<usize, Error> {
        self.message(command::UNREGISTER_SESSION, &[]).emit(buf)
    }

    /// SendRRData with `request` (a Message Router request: a
    /// [`RequestRepr`](crate::enip::wire::message::RequestRepr), a Forward_Open, ...) in an
    /// unconnected data item after a null address, then `extra` items.
    pub fn send_rr_data(
        &self,
        request: &impl Emit,
        extra: &[Item<'_>],
        buf: &mut [u8],
    ) -> Result<usize, Error> {
        // Header, interface handle and timeout, item count, the null address item, the
        // unconnected data item's header: the request is written in place after them.
        const REQUEST_AT: usize = HEADER_LEN + 6 + 2 + 4 + 4;
        let request_len = request.emit(buf.get_mut(REQUEST_AT..).ok_or(Error::BufferTooSmall)?)?;
        let mut end = REQUEST_AT + request_len;
        for extra in extra {
            let mut w = Writer::new(buf.get_mut(end..).ok_or(Error::BufferTooSmall)?);
            w.u16(extra.kind)?;
            w.u16(length_u16(extra.data.len())?)?;
            w.bytes(extra.data)?;
            end += w.done();
        }
        let data_len = end - HEADER_LEN;
        let mut w = Writer::new(buf);
        w.u16(command::SEND_RR_DATA)?;
        w.u16(length_u16(data_len)?)?;
        w.u32(self.handle)?;
        w.u32(0)?;
        w.bytes(&self.context)?;
        w.u32(0)?;
        w.u32(0)?; // interface handle: CIP
        w.u16(0)?; // timeout
        w.u16(length_u16(2 + extra.len())?)?;
        w.u16(item::NULL_ADDRESS)?;
        w.u16(0)?;
        w.u16(item::UNCONNECTED_DATA)?;
        w.u16(length_u16(request_len)?)?;
        Ok(end)
    }

    /// SendRRData's reply.
    pub fn rr_data_reply<'a>(&self, reply: &'a [u8]) -> Result<UnconnectedReply<'a>, Failure> {
        let reply = checked(command::SEND_RR_DATA, reply)?;
        let items = Items::parse_send_data(reply.data)
            .map_err(|_| Failure::Malformed("a malformed SendRRData reply"))?;
        let response = items
            .find(item::UNCONNECTED_DATA)
            .ok_or(Failure::Malformed("a SendRRData reply without a response"))?;
        let response = ResponseRepr::parse(response)
            .map_err(|_| Failure::Malformed("a response shorter than its header"))?;
        Ok(UnconnectedReply { response, items })
    }

    /// SendUnitData with a class-3 request.
    pub fn send_unit_data(
        &self,
        message: &ConnectedMessage<'_>,
        buf: &mut [u8],
    ) -> Result<usize, Error> {
        let data_len = message.buffer_len();
        let at = HEADER_LEN;
        message.emit(buf.get_mut(at..).ok_or(Error::BufferTooSmall)?)?;
        let mut w = Writer::new(buf);
        w.u16(command::SEND_UNIT_DATA)?;
        w.u16(length_u16(data_len)?)?;
        w.u32(self.handle)?;
        w.u32(0)?;
        w.bytes(&self.context)?;
        w.u32(0)?;
        Ok(at + data_len)
    }

    /// SendUnitData's reply: the class-3 response.
    pub fn unit_data_reply<'a>(&self, reply: &'a [u8]) -> Result<ConnectedMessage<'a>, Failure> {
        let reply = checked(command::SEND_UNIT_DATA, reply)?;
        ConnectedMessage::parse(reply.data)
            .map_err(|_| Failure::Malformed("a malformed SendUnitData reply"))
    }
}

/// A reply to `command` with status 0.
fn checked(command: u16, reply: &[u8]) -> Result<EncapRepr<'_>, Failure> {
    let (reply, _) =
        EncapRepr::parse_prefix(reply).map_err(|_| Failure::Malformed("an incomplete reply"))?;
    if reply.command != command {
        return Err(Failure::Malformed("a reply to another command"));
    }
    if reply.status != 0 {
        return Err(Failure::Refused {
            command,
            status: reply.status,
        });
    }
    Ok(reply)
}

/// A class-1 connection as its originator has it after Forward_Open: the O→T datagrams it
/// produces (sequence numbers, the 32-bit run/idle header when the connection has one) and
/// the T→O data it consumes (new sequence counts only).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Class1 {
    /// The O→T connection ID (the target's choice).
    pub o_t_id: u32,
    /// The T→O connection ID (the originator's).
    pub t_o_id: u32,
    /// O→T data starts with the run/idle header.
    pub o_t_header: bool,
    /// T→O data starts with the run/idle header.
    pub t_o_header: bool,
    sequence: u32,
    last_count: Option<u16>,
}

impl Class1 {
    /// The connection Forward_Open opened.
    pub const fn new(o_t_id: u32, t_o_id: u32, o_t_header: bool, t_o_header: bool) -> Class1 {
        Class1 {
            o_t_id,
            t_o_id,
            o_t_header,
            t_o_header,
            sequence: 0,
            last_count: None,
        }
    }

    /// The next O→T datagram with `image` (run or idle in its header when it has one).
    pub fn produce(&mut self, run: bool, image: &[u8], buf: &mut [u8]) -> Result<usize, Error> {
        self.sequence = self.sequence.wrapping_add(1);
        let header = if self.o_t_header { 4 } else { 0 };
        let data_len = 2 + header + image.len();
        // The datagram's items before the connected data: count, sequenced address (4 + 8),
        // connected data item header (4).
        const DATA_AT: usize = 2 + 12 + 4;
        let datagram = IoDatagram {
            connection: self.o_t_id,
            sequence: self.sequence,
            data: &[],
        };
        datagram.emit(buf)?;
        let out = buf
            .get_mut(..DATA_AT + data_len)
            .ok_or(Error::BufferTooSmall)?;
        out[DATA_AT - 2..DATA_AT].copy_from_slice(&length_u16(data_len)?.to_le_bytes());
        let mut w = Writer::new(&mut out[DATA_AT..]);
        w.u16(self.sequence as u16)?;
        if self.o_t_header {
            w.u32(u32::from(run))?;
        }
        w.bytes(image)?;
        Ok(DATA_AT + data_len)
    }

    /// The image of a T→O datagram of this connection with a sequence count not seen last
    /// time (after the count and the header); `None` for another connection, a repeat or bytes
    /// that are no datagram.
    pub fn consume<'a>(&mut self, datagram: &'a [u8]) -> Option<&'a [u8]> {
        let datagram = IoDatagram::parse(datagram).ok()?;
        let count = datagram.sequence_count()?;
        if datagram.connection != self.t_o_id || self.last_count == Some(count) {
            return None;
        }
        self.last_count = Some(count);
        let skip = if self.t_o_header { 6 } else { 2 };
        Some(datagram.data.get(skip..).unwrap_or(&[]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::enip::wire::message::RequestRepr;

    #[test]
    fn list_identity_carries_the_max_delay() {
        let session = Session::new(*b"edsgen  ");
        let mut buf = [0; 24];
        let n = session.list_identity(1000, &mut buf).expect("fits");
        assert_eq!(
            &buf[..n],
            &[
                0x63, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0xE8, 0x03, b's', b'g', b'e', b'n', b' ',
                b' ', 0, 0, 0, 0
            ]
        );
        assert_eq!(
            session.list_identity(0, &mut [0; 23]),
            Err(Error::BufferTooSmall)
        );
    }

    #[test]
    fn session_messages_and_replies() {
        let mut session = Session::new(*b"edsgen  ");
        let mut buf = [0; 96];
        let n = session.register(&mut buf).expect("fits");
        assert_eq!(&buf[..4], &[0x65, 0, 4, 0]);
        assert_eq!(&buf[24..n], &[1, 0, 0, 0]);
        let mut reply = [0; 28];
        reply.copy_from_slice(&buf[..n]);
        reply[4] = 9;
        assert_eq!(session.registered(&reply), Ok(9));
        let get = RequestRepr {
            service: 0x0E,
            path: &[0x20, 0x01, 0x24, 0x01, 0x30, 0x07],
            data: &[],
        };
        let n = session.send_rr_data(&get, &[], &mut buf).expect("fits");
        assert_eq!(
            &buf[..n],
            &[
                0x6F, 0, 24, 0, 9, 0, 0, 0, 0, 0, 0, 0, b'e', b'd', b's', b'g', b'e', b'n', b' ',
                b' ', 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 0, 0, 0, 0, 0, 0xB2, 0, 8, 0, 0x0E, 3, 0x20,
                0x01, 0x24, 0x01, 0x30, 0x07
            ]
        );
        let sockaddr = [0, 2, 0x08, 0xAE, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0];
        let with = session
            .send_rr_data(&get, &[Item::new(item::SOCKADDR_T_O, &sockaddr)], &mut buf)
            .expect("fits");
        assert_eq!((with, &buf[2..4], buf[30]), (n + 20, &[44, 0][..], 3));
        assert_eq!(&buf[n..n + 4], &[0x01, 0x80, 16, 0]);
        // The target's reply: the response after the items' headers.
        let mut reply = [0u8; 44];
        reply[..24].copy_from_slice(&buf[..24]);
        reply[2] = 20;
        reply[30..44].copy_from_slice(&[2, 0, 0, 0, 0, 0, 0xB2, 0, 4, 0, 0x8E, 0, 0, 0]);
        let got = session.rr_data_reply(&reply[..40]);
        assert_eq!(got, Err(Failure::Malformed("an incomplete reply")));
        let got = session.rr_data_reply(&reply).expect("a reply");
        assert_eq!(got.response, ResponseRepr::success(0x0E, &[]));
        assert_eq!(got.items.iter().count(), 2);
        reply[8] = 0x64;
        assert_eq!(
            session.rr_data_reply(&reply),
            Err(Failure::Refused {
                command: 0x6F,
                status: 0x64
            })
        );
        assert_eq!(
            session.send_rr_data(&get, &[], &mut [0; 40]),
            Err(Error::BufferTooSmall)
        );
    }

    #[test]
    fn class1_produces_and_consumes() {
        let mut connection = Class1::new(0x1000_0001, 0x2000_0001, true, false);
        let mut buf = [0; 64];
        let n = connection.produce(true, &[9, 8], &mut buf).expect("fits");
        assert_eq!(
            &buf[..n],
            &[
                2, 0, 0x02, 0x80, 8, 0, 1, 0, 0, 0x10, 1, 0, 0, 0, 0xB1, 0, 8, 0, 1, 0, 1, 0, 0, 0,
                9, 8
            ]
        );
        let n = connection.produce(false, &[], &mut buf).expect("fits");
        assert_eq!(&buf[10..n], &[2, 0, 0, 0, 0xB1, 0, 6, 0, 2, 0, 0, 0, 0, 0]);
        let t_o = [
            2, 0, 0x02, 0x80, 8, 0, 1, 0, 0, 0x20, 7, 0, 0, 0, 0xB1, 0, 4, 0, 7, 0, 5, 6,
        ];
        assert_eq!(connection.consume(&t_o), Some(&[5, 6][..]));
        assert_eq!(connection.consume(&t_o), None);
        let mut other = t_o;
        other[9] = 0x30;
        other[18] = 8;
        assert_eq!(connection.consume(&other), None);
        assert_eq!(connection.consume(&t_o[..12]), None);
        assert_eq!(
            connection.produce(true, &[0; 50], &mut buf),
            Err(Error::BufferTooSmall)
        );
    }
}
