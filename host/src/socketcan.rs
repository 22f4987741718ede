//! Linux SocketCAN (feature `socketcan`, Linux only): a [`Transport`] on a kernel CAN interface
//! (`can0`, `vcan0`) through the `socketcan` crate. Thin by design: the kernel does the bus, this
//! converts frames. Error frames are skipped; the socket does not receive its own frames (the
//! kernel default), as the [`Transport`] contract asks.

use std::io;
use std::time::{Duration as StdDuration, Instant as StdInstant};

use socketcan::{CanFrame as KernelFrame, CanSocket, Socket};

use super::Transport;
use edsgen_runtime::frame::CanFrame;

/// A raw CAN socket bound to one interface.
#[derive(Debug)]
pub struct SocketCan {
    socket: CanSocket,
}

impl SocketCan {
    /// Opens the interface named `interface` (`can0`).
    pub fn open(interface: &str) -> io::Result<Self> {
        let socket = CanSocket::open(interface).map_err(|e| {
            io::Error::new(
                e.kind(),
                format!("cannot open CAN interface {interface}: {e}"),
            )
        })?;
        Ok(SocketCan { socket })
    }
}

impl Transport for SocketCan {
    fn send(&mut self, frame: &CanFrame) -> io::Result<()> {
        let frame: KernelFrame = frame.to_frame().ok_or_else(|| {
            io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("not a CAN frame: {frame:?}"),
            )
        })?;
        self.socket.write_frame_insist(&frame)
    }

    fn recv_timeout(&mut self, timeout: StdDuration) -> io::Result<Option<CanFrame>> {
        let deadline = StdInstant::now() + timeout;
        loop {
            let left = deadline.saturating_duration_since(StdInstant::now());
            match self.socket.read_frame_timeout(left) {
                Ok(KernelFrame::Error(_)) => {}
                Ok(frame) => {
                    if let Some(frame) = CanFrame::from_frame(&frame) {
                        return Ok(Some(frame));
                    }
                }
                Err(e)
                    if matches!(
                        e.kind(),
                        io::ErrorKind::TimedOut | io::ErrorKind::WouldBlock
                    ) =>
                {
                    return Ok(None)
                }
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => return Err(e),
            }
            if left.is_zero() {
                return Ok(None);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn opening_a_missing_interface_is_an_error_naming_it() {
        let error = SocketCan::open("edsgen-none0").unwrap_err();
        assert!(
            error
                .to_string()
                .starts_with("cannot open CAN interface edsgen-none0: "),
            "{error}"
        );
    }
}
