//! A raw Linux `AF_PACKET` socket on one network interface for one EtherType: the thin I/O
//! under the EtherCAT and PROFINET simulators (their protocol cores never see it).
//!
//! The one piece of `unsafe` in this crate is here, in `bind`, `accept_unicast` and
//! `ignore_outgoing`: binding a packet socket to an interface takes a `sockaddr_ll`, which
//! neither `socket2` nor `nix` can build without `unsafe` (their link-layer address types have
//! no public constructor), and neither offers `PACKET_ADD_MEMBERSHIP` or
//! `PACKET_IGNORE_OUTGOING`. Everything else (creating the
//! socket, reading, writing) goes through `socket2`'s safe API, the wait for a frame through
//! `rustix`'s `poll`, and the interface's index and MAC address come from `/sys/class/net/IFACE`.
#![allow(unsafe_code)]

use std::io::{self, Read, Write};
use std::os::fd::AsRawFd;
use std::path::PathBuf;
use std::time::Duration;

use socket2::{Domain, Protocol, Socket, Type};

/// A packet socket bound to one interface, receiving the frames of one EtherType.
#[derive(Debug)]
pub struct PacketSocket {
    socket: Socket,
    /// How long a read waits for a frame.
    timeout: Duration,
}

impl PacketSocket {
    /// Opens `iface` for `ethertype` (root, or CAP_NET_RAW, is needed); reads wait at most
    /// `timeout`.
    pub fn open(iface: &str, ethertype: u16, timeout: Duration) -> io::Result<Self> {
        let index = interface_index(iface)?;
        let protocol = Protocol::from(i32::from(ethertype.to_be()));
        let socket = Socket::new(Domain::PACKET, Type::RAW, Some(protocol))?;
        bind(&socket, ethertype, index)?;
        Ok(PacketSocket { socket, timeout })
    }

    /// Reads one frame into `buf`; `Ok(None)` when the timeout passed first (or a signal came).
    /// The wait is `poll(2)`'s, which keeps its time to about the microsecond: a socket's own
    /// read timeout (`SO_RCVTIMEO`) counts in scheduler ticks, and on a 250 Hz kernel a 1 ms
    /// wait took 8 ms, so a device's deadlines (a PROFINET device's next input frame) slipped
    /// whenever the wire was quiet.
    pub fn recv(&mut self, buf: &mut [u8]) -> io::Result<Option<usize>> {
        use rustix::event::{poll, PollFd, PollFlags, Timespec};
        let mut fds = [PollFd::new(&self.socket, PollFlags::IN)];
        let timeout = Timespec {
            tv_sec: i64::try_from(self.timeout.as_secs()).unwrap_or(i64::MAX),
            tv_nsec: i64::from(self.timeout.subsec_nanos()),
        };
        match poll(&mut fds, Some(&timeout)) {
            Ok(0) | Err(rustix::io::Errno::INTR) => return Ok(None),
            Ok(_) => {}
            Err(e) => return Err(e.into()),
        }
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

    /// Sends one frame as it is.
    pub fn send(&mut self, frame: &[u8]) -> io::Result<()> {
        (&self.socket).write_all(frame)
    }

    /// Has the interface (`index`) accept frames to `mac` as well as to its own address
    /// (`PACKET_MR_UNICAST`: the address joins the interface's unicast filter while the socket
    /// is open), for devices simulated with MAC addresses of their own.
    pub fn accept_unicast(&self, index: i32, mac: [u8; 6]) -> io::Result<()> {
        let mut address = [0u8; 8];
        address[..6].copy_from_slice(&mac);
        let request = libc::packet_mreq {
            mr_ifindex: index,
            mr_type: libc::PACKET_MR_UNICAST as u16,
            mr_alen: 6,
            mr_address: address,
        };
        // SAFETY: `request` is a fully initialised `packet_mreq` that lives across the call, the
        // length passed is its size, and the descriptor is the open socket `self` owns.
        let result = unsafe {
            libc::setsockopt(
                self.socket.as_raw_fd(),
                libc::SOL_PACKET,
                libc::PACKET_ADD_MEMBERSHIP,
                (&raw const request).cast::<libc::c_void>(),
                std::mem::size_of::<libc::packet_mreq>() as libc::socklen_t,
            )
        };
        if result == 0 {
            Ok(())
        } else {
            Err(io::Error::last_os_error())
        }
    }

    /// Stops the socket from seeing the frames it sends itself (`PACKET_IGNORE_OUTGOING`,
    /// Linux 4.20 and later): a packet socket otherwise reads each of its own frames back, one
    /// wake-up and one read for nothing per frame sent.
    pub fn ignore_outgoing(&self) -> io::Result<()> {
        let on: libc::c_int = 1;
        // SAFETY: `on` is an initialised `c_int` that lives across the call, the length passed
        // is its size, and the descriptor is the open socket `self` owns.
        let result = unsafe {
            libc::setsockopt(
                self.socket.as_raw_fd(),
                libc::SOL_PACKET,
                libc::PACKET_IGNORE_OUTGOING,
                (&raw const on).cast::<libc::c_void>(),
                std::mem::size_of::<libc::c_int>() as libc::socklen_t,
            )
        };
        if result == 0 {
            Ok(())
        } else {
            Err(io::Error::last_os_error())
        }
    }

    /// A second handle on the same socket (same binding and read timeout), so that one thread
    /// may read while another sends.
    pub fn try_clone(&self) -> io::Result<Self> {
        Ok(PacketSocket {
            socket: self.socket.try_clone()?,
            timeout: self.timeout,
        })
    }
}

/// The folder of interface `iface` in sysfs, refusing names that would lead elsewhere.
fn sysfs(iface: &str) -> io::Result<PathBuf> {
    if iface.is_empty() || iface.contains('/') || iface.starts_with('.') {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("`{iface}` is not an interface name"),
        ));
    }
    Ok(PathBuf::from("/sys/class/net").join(iface))
}

/// The index of interface `iface`.
pub fn interface_index(iface: &str) -> io::Result<i32> {
    let text = std::fs::read_to_string(sysfs(iface)?.join("ifindex"))
        .map_err(|e| io::Error::new(e.kind(), format!("no interface `{iface}`: {e}")))?;
    text.trim().parse().map_err(|_| {
        io::Error::new(
            io::ErrorKind::InvalidData,
            format!("interface `{iface}`: ifindex `{}`", text.trim()),
        )
    })
}

/// The MAC address of interface `iface`.
pub fn interface_mac(iface: &str) -> io::Result<[u8; 6]> {
    let text = std::fs::read_to_string(sysfs(iface)?.join("address"))
        .map_err(|e| io::Error::new(e.kind(), format!("no interface `{iface}`: {e}")))?;
    let bytes: Vec<u8> = text
        .trim()
        .split(':')
        .filter_map(|p| u8::from_str_radix(p, 16).ok())
        .collect();
    bytes.try_into().map_err(|_| {
        io::Error::new(
            io::ErrorKind::InvalidData,
            format!("`{iface}` has no MAC address"),
        )
    })
}

/// Binds `socket` to interface `index` for `ethertype`.
fn bind(socket: &Socket, ethertype: u16, index: i32) -> io::Result<()> {
    let address = libc::sockaddr_ll {
        sll_family: libc::AF_PACKET as u16,
        sll_protocol: ethertype.to_be(),
        sll_ifindex: index,
        sll_hatype: 0,
        sll_pkttype: 0,
        sll_halen: 0,
        sll_addr: [0; 8],
    };
    // SAFETY: `address` is a fully initialised `sockaddr_ll` that lives across the call, the
    // length passed is its size, and the descriptor is the open socket `socket` owns.
    let result = unsafe {
        libc::bind(
            socket.as_raw_fd(),
            (&raw const address).cast::<libc::sockaddr>(),
            std::mem::size_of::<libc::sockaddr_ll>() as libc::socklen_t,
        )
    };
    if result == 0 {
        Ok(())
    } else {
        Err(io::Error::last_os_error())
    }
}
