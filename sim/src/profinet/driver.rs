//! The thin I/O driver: a raw `AF_PACKET` socket on one interface for EtherType 0x8892 (Linux,
//! needs `CAP_NET_RAW`), and [`serve_dcp`], the loop that feeds received frames to the DCP
//! machine and sends its answers. The protocol machines never see the socket.
//!
//! The one `unsafe` block is in `bind`: binding a packet socket to an interface takes a
//! `sockaddr_ll`, which `socket2` cannot build (its link-layer address has no public
//! constructor). Creating the socket, reading, writing and the timeout use `socket2`'s safe API.
#![allow(unsafe_code)]

use std::io::{self, Read, Write};
use std::os::fd::AsRawFd;
use std::time::{Duration, Instant};

use socket2::{Domain, Protocol, Socket, Type};

use super::dcp::{Dcp, DcpEvent};
use super::wire::{Mac, ETHERTYPE_PROFINET};

/// A packet socket bound to one interface, receiving PROFINET frames.
#[derive(Debug)]
pub struct RawSocket {
    socket: Socket,
    mac: Mac,
}

/// The interface's MAC address and index, from `/sys/class/net`.
pub fn interface(name: &str) -> io::Result<(Mac, i32)> {
    if name.is_empty() || name.contains('/') || name.starts_with('.') {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("`{name}` is not an interface name"),
        ));
    }
    let base = std::path::Path::new("/sys/class/net").join(name);
    let text = std::fs::read_to_string(base.join("address"))
        .map_err(|e| io::Error::new(e.kind(), format!("no interface `{name}`: {e}")))?;
    let bytes: Vec<u8> = text
        .trim()
        .split(':')
        .filter_map(|p| u8::from_str_radix(p, 16).ok())
        .collect();
    let mac: Mac = bytes.try_into().map_err(|_| {
        io::Error::new(
            io::ErrorKind::InvalidData,
            format!("`{name}` has no MAC address"),
        )
    })?;
    let index = std::fs::read_to_string(base.join("ifindex"))?
        .trim()
        .parse::<i32>()
        .map_err(|e| io::Error::new(io::ErrorKind::InvalidData, e))?;
    Ok((mac, index))
}

impl RawSocket {
    /// Opens a packet socket on `name` for PROFINET frames; reads wait at most `timeout`.
    pub fn open(name: &str, timeout: Duration) -> io::Result<RawSocket> {
        let (mac, index) = interface(name)?;
        let protocol = Protocol::from(i32::from(ETHERTYPE_PROFINET.to_be()));
        let socket = Socket::new(Domain::PACKET, Type::RAW, Some(protocol))?;
        bind(&socket, index)?;
        socket.set_read_timeout(Some(timeout))?;
        Ok(RawSocket { socket, mac })
    }

    /// The interface's MAC address.
    pub fn mac(&self) -> Mac {
        self.mac
    }

    /// Sends one frame, padded to Ethernet's 60-byte minimum.
    pub fn send(&mut self, frame: &[u8]) -> io::Result<()> {
        let mut frame = frame.to_vec();
        super::wire::pad(&mut frame);
        (&self.socket).write_all(&frame)
    }

    /// Reads one frame into `buf`; `Ok(None)` when the timeout passed first.
    pub fn recv(&mut self, buf: &mut [u8]) -> io::Result<Option<usize>> {
        match (&self.socket).read(buf) {
            Ok(n) => Ok(Some(n)),
            Err(e)
                if matches!(
                    e.kind(),
                    io::ErrorKind::WouldBlock
                        | io::ErrorKind::TimedOut
                        | io::ErrorKind::Interrupted
                ) =>
            {
                Ok(None)
            }
            Err(e) => Err(e),
        }
    }
}

/// Binds `socket` to interface `index` for PROFINET frames.
fn bind(socket: &Socket, index: i32) -> io::Result<()> {
    let address = libc::sockaddr_ll {
        sll_family: libc::AF_PACKET as u16,
        sll_protocol: ETHERTYPE_PROFINET.to_be(),
        sll_ifindex: index,
        sll_hatype: 0,
        sll_pkttype: 0,
        sll_halen: 0,
        sll_addr: [0; 8],
    };
    // SAFETY: `address` is a valid, initialised sockaddr_ll and the length given is its size;
    // the descriptor is the socket's own, open for the whole call.
    let rc = unsafe {
        libc::bind(
            socket.as_raw_fd(),
            (&address as *const libc::sockaddr_ll).cast(),
            std::mem::size_of::<libc::sockaddr_ll>() as libc::socklen_t,
        )
    };
    if rc == 0 {
        Ok(())
    } else {
        Err(io::Error::last_os_error())
    }
}

/// Serves DCP on `socket` until `until` passes (forever with `None`): a Hello at start, then
/// every frame to the machine and its answers back; each event is passed to `on_event`.
pub fn serve_dcp(
    socket: &mut RawSocket,
    dcp: &mut Dcp,
    until: Option<Instant>,
    mut on_event: impl FnMut(&DcpEvent),
) -> io::Result<()> {
    socket.send(&dcp.hello())?;
    let mut buf = vec![0u8; 1600];
    while until.is_none_or(|t| Instant::now() < t) {
        let Some(n) = socket.recv(&mut buf)? else {
            continue;
        };
        if let Some(answer) = buf.get(..n).and_then(|frame| dcp.handle(frame)) {
            socket.send(&answer)?;
        }
        while let Some(event) = dcp.poll_event() {
            on_event(&event);
        }
    }
    Ok(())
}
