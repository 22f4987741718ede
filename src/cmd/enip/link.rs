//! The bench scanner's explicit messaging: the runtime's originator session
//! (`edsgen_runtime::enip::originator`) carried over TCP, for `enip get|set` and `enip io`.
//! Messages are written into and read from vectors here; the bytes are the runtime's.

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::time::Duration;

use edsgen_runtime::enip::originator::{Failure, Session};
use edsgen_runtime::enip::wire::connection_manager::extended;
use edsgen_runtime::enip::wire::cpf::{item, Item, Sockaddr};
use edsgen_runtime::enip::wire::encap::{EncapPacket, HEADER_LEN};
use edsgen_runtime::enip::wire::message::general;
use edsgen_runtime::enip::wire::Emit;

/// The sender context of the bench scanner's messages.
pub(super) const CONTEXT: [u8; 8] = *b"edsgen  ";

/// Why an exchange failed: the link itself (I/O, bytes that are no reply), or the device's
/// encapsulation refused the command.
#[derive(Debug)]
pub(super) enum LinkError {
    /// Connecting, sending or receiving failed, or the reply is malformed.
    Io(String),
    /// The encapsulation status of a refusal.
    Refused(String),
}

impl LinkError {
    /// The message either way.
    pub(super) fn text(self) -> String {
        match self {
            LinkError::Io(m) | LinkError::Refused(m) => m,
        }
    }
}

impl From<Failure> for LinkError {
    fn from(failure: Failure) -> LinkError {
        match failure {
            Failure::Refused { command, status } => LinkError::Refused(format!(
                "{} refused: encapsulation status {status:#06x}",
                match command {
                    0x65 => "RegisterSession",
                    0x70 => "SendUnitData",
                    _ => "SendRRData",
                }
            )),
            Failure::Malformed(what) => LinkError::Io(what.to_owned()),
        }
    }
}

/// A Message Router response, owned.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct Response {
    /// The general status.
    pub(super) status: u8,
    /// The extended status words.
    pub(super) extended: Vec<u16>,
    /// The reply data.
    pub(super) data: Vec<u8>,
    /// Where the device wants O→T data (a Forward_Open reply's O→T sockaddr item).
    pub(super) o_t_sockaddr: Option<Sockaddr>,
}

impl Response {
    /// `None` on success, else what the refusal of `what` means (general status, and the
    /// Connection Manager's extended status and expected size where there are).
    pub(super) fn refusal(&self, what: &str) -> Option<String> {
        let status = self.status;
        if status == general::SUCCESS {
            return None;
        }
        Some(match self.extended.first() {
            Some(&code) => {
                let mut text = format!(
                    "{what} refused: {} (general status {status:#04x}, extended status \
                     {code:#06x})",
                    extended::text(code)
                );
                let size_refused = matches!(
                    code,
                    extended::INVALID_O_T_SIZE | extended::INVALID_T_O_SIZE
                );
                if let (true, Some(size)) = (size_refused, self.extended.get(1)) {
                    text.push_str(&format!("; the device expects {size} bytes"));
                }
                text
            }
            None => format!("{what} refused: general status {status:#04x}"),
        })
    }
}

/// A registered session with a device over TCP.
pub(super) struct Link {
    stream: TcpStream,
    session: Session,
}

impl Link {
    /// Connects to `target` and registers a session.
    pub(super) fn open(target: SocketAddr) -> Result<Link, LinkError> {
        let stream = TcpStream::connect_timeout(&target, Duration::from_secs(3))
            .map_err(|e| LinkError::Io(format!("cannot connect to {target}: {e}")))?;
        stream
            .set_read_timeout(Some(Duration::from_secs(3)))
            .map_err(|e| LinkError::Io(e.to_string()))?;
        let mut link = Link {
            stream,
            session: Session::new(CONTEXT),
        };
        let mut register = [0; 28];
        let len = link.session.register(&mut register).map_err(wire)?;
        let reply = link.exchange(&register[..len])?;
        link.session.registered(&reply)?;
        Ok(link)
    }

    /// The local end's address (where T→O data may be asked to come).
    pub(super) fn local(&self) -> Result<SocketAddr, LinkError> {
        self.stream
            .local_addr()
            .map_err(|e| LinkError::Io(e.to_string()))
    }

    /// One message and its reply.
    fn exchange(&mut self, message: &[u8]) -> Result<Vec<u8>, LinkError> {
        let io = |e: std::io::Error| LinkError::Io(format!("the device's TCP connection: {e}"));
        self.stream.write_all(message).map_err(io)?;
        let mut got = Vec::new();
        let mut buf = [0u8; 4096];
        loop {
            if let Ok(packet) = EncapPacket::new_checked(&got[..]) {
                let len = packet.total_len();
                got.truncate(len);
                return Ok(got);
            }
            let n = self.stream.read(&mut buf).map_err(io)?;
            if n == 0 {
                return Err(LinkError::Io("the device closed the connection".into()));
            }
            got.extend_from_slice(&buf[..n]);
        }
    }

    /// A Message Router request by SendRRData, with `extra` items after it; its response.
    pub(super) fn request(
        &mut self,
        request: &impl Emit,
        extra: &[Item<'_>],
    ) -> Result<Response, LinkError> {
        let extra_len: usize = extra.iter().map(|i| 4 + i.data.len()).sum();
        let mut message = vec![0; HEADER_LEN + 16 + request.buffer_len() + extra_len];
        let len = self
            .session
            .send_rr_data(request, extra, &mut message)
            .map_err(wire)?;
        let reply = self.exchange(&message[..len])?;
        let reply = self.session.rr_data_reply(&reply)?;
        let response = reply.response;
        Ok(Response {
            status: response.status,
            extended: response
                .extended
                .chunks_exact(2)
                .map(|w| u16::from_le_bytes([w[0], w[1]]))
                .collect(),
            data: response.data.to_vec(),
            o_t_sockaddr: reply
                .items
                .find(item::SOCKADDR_O_T)
                .and_then(|d| Sockaddr::parse(d).ok()),
        })
    }

    /// UnRegisterSession (no reply comes), the TCP connection closed.
    pub(super) fn close(mut self) {
        let mut message = [0; HEADER_LEN];
        if let Ok(len) = self.session.unregister(&mut message) {
            let _ = self.stream.write_all(&message[..len]);
        }
    }
}

/// A message that cannot be written: too long for its length fields.
fn wire(error: edsgen_runtime::enip::wire::Error) -> LinkError {
    LinkError::Io(format!("a request too long for EtherNet/IP ({error:?})"))
}
