//! Several simulated IO devices on one network interface, as one process serves them: one
//! packet socket whose frames go to the device their destination MAC names (multicast and
//! broadcast to every device), one UDP endpoint per device bound to its own IP (and bound again
//! when DCP sets another), and each device's frames and datagrams sent when due.
//! [`device_mac`] gives each device its MAC address.

use std::io;
use std::ops::ControlFlow;
use std::time::Instant;

use edsgen_host::driver::MonotonicClock;

use super::application::IoApplication;
use super::dcp::Station;
use super::device::{Device, DeviceEvent, Link, Transmit};
use super::driver::{RawSocket, RpcSocket};
use super::wire::Mac;
use crate::drives::pkw_pzd::PkwPzdDrive;

/// The MAC address of the device at `position` (from 0) on an interface whose MAC is
/// `iface_mac`: the first device has the interface's own (so that one device is what it always
/// was, and the host's ARP answers for it); each next one the interface's made locally
/// administered and unicast, with `position` added to its last three bytes (the NIC's part).
pub fn device_mac(iface_mac: Mac, position: usize) -> Mac {
    if position == 0 {
        return iface_mac;
    }
    let [a, b, c, d, e, f] = iface_mac;
    let low = u32::from_be_bytes([0, d, e, f]).wrapping_add(position as u32) & 0x00FF_FFFF;
    let [_, d, e, f] = low.to_be_bytes();
    [(a | 0x02) & !0x01, b, c, d, e, f]
}

/// One device's RPC endpoint: the address it is bound to (zero: none) and its socket.
#[derive(Debug)]
struct Endpoint {
    address: [u8; 4],
    socket: Option<RpcSocket>,
}

/// Devices on one interface, served together.
#[derive(Debug)]
pub struct Segment<A = PkwPzdDrive> {
    iface: String,
    raw: RawSocket,
    devices: Vec<Device<A>>,
    endpoints: Vec<Endpoint>,
}

impl<A: IoApplication> Segment<A> {
    /// `devices` on `iface` through `raw` (opened with a short read timeout: it paces the
    /// loop): the interface accepts frames to each device's MAC, and each device with an IP
    /// gets its RPC endpoint. An endpoint that cannot be bound is an error.
    pub fn new(iface: &str, raw: RawSocket, devices: Vec<Device<A>>) -> io::Result<Self> {
        for device in &devices {
            let mac = device.station().mac;
            if mac != raw.mac() {
                raw.accept_unicast(mac)?;
            }
        }
        let mut segment = Segment {
            iface: iface.to_owned(),
            raw,
            endpoints: devices
                .iter()
                .map(|_| Endpoint {
                    address: [0; 4],
                    socket: None,
                })
                .collect(),
            devices,
        };
        for i in 0..segment.devices.len() {
            segment.bind(i)?;
        }
        Ok(segment)
    }

    /// The devices, in the order given.
    pub fn devices(&self) -> &[Device<A>] {
        &self.devices
    }

    /// Binds device `i`'s endpoint to its IP if that changed (none for 0.0.0.0).
    fn bind(&mut self, i: usize) -> io::Result<()> {
        let ip = self.devices[i].station().ip[0];
        let endpoint = &mut self.endpoints[i];
        if endpoint.address == ip {
            return Ok(());
        }
        endpoint.address = ip;
        endpoint.socket = None;
        if ip != [0; 4] {
            endpoint.socket = Some(RpcSocket::open_at(&self.iface, ip)?);
        }
        Ok(())
    }

    /// Serves every device until `until` passes (forever with `None`): a DCP Hello from each,
    /// then frames on the packet socket, datagrams on each endpoint, each device's own frames
    /// and datagrams when due. `tick` is given the devices and the time once a round, before
    /// their timers (to act on them from outside, such as a drive fault switched by standard
    /// input); serving ends when it breaks. Each event is passed to `on_event` with the station
    /// of its device as it is after the event.
    pub fn serve(
        &mut self,
        until: Option<Instant>,
        mut tick: impl FnMut(&mut [Device<A>], edsgen_runtime::Instant) -> ControlFlow<()>,
        mut on_event: impl FnMut(usize, &Station, &DeviceEvent),
    ) -> io::Result<()> {
        let clock = MonotonicClock::new();
        for i in 0..self.devices.len() {
            let hello = self.devices[i].dcp().hello();
            if let Err(e) = self.raw.send(&hello) {
                eprintln!("dropped the DCP Hello the socket refused: {e}");
            }
        }
        let mut buf = vec![0u8; 1600];
        let mut dgram = vec![0u8; 4096];
        // The endpoints are read when the wire is idle, else once a millisecond: reading each
        // device's after every frame would cost N system calls a frame.
        let mut rpc_due = Instant::now();
        while until.is_none_or(|t| Instant::now() < t) {
            let received = self.raw.recv(&mut buf)?;
            if let Some(n) = received {
                let frame = &buf[..n.min(buf.len())];
                let dst: Option<Mac> = frame.get(..6).and_then(|d| d.try_into().ok());
                for device in &mut self.devices {
                    let to_all = dst.is_some_and(|d| d[0] & 0x01 != 0);
                    if to_all || dst == Some(device.station().mac) {
                        device.handle(clock.now(), Link::Ethernet, frame);
                    }
                }
            }
            let rpc = received.is_none() || Instant::now() >= rpc_due;
            if rpc {
                rpc_due = Instant::now() + std::time::Duration::from_millis(1);
            }
            for i in (0..self.devices.len()).filter(|_| rpc) {
                while let Some((n, from)) = match &self.endpoints[i].socket {
                    Some(socket) => socket.recv(&mut dgram)?,
                    None => None,
                } {
                    let pdu = &dgram[..n.min(dgram.len())];
                    self.devices[i].handle(clock.now(), Link::Rpc(from), pdu);
                    self.send(i, clock.now());
                }
            }
            let now = clock.now();
            if tick(&mut self.devices, now).is_break() {
                break;
            }
            for i in 0..self.devices.len() {
                let device = &mut self.devices[i];
                if device.poll_timeout().is_some_and(|t| t <= now) {
                    device.handle_timeout(now);
                }
                self.send(i, now);
                while let Some(event) = self.devices[i].poll_event() {
                    on_event(i, self.devices[i].station(), &event);
                }
                if let Err(e) = self.bind(i) {
                    let ip = std::net::Ipv4Addr::from(self.endpoints[i].address);
                    eprintln!(
                        "cannot bind UDP 34964 at {ip} on `{}`: {e}: RPC does not reach `{}`",
                        self.iface,
                        self.devices[i].station().name_of_station
                    );
                }
            }
        }
        Ok(())
    }

    /// Sends what device `i` has to send at `now`: frames on the packet socket, datagrams on
    /// its endpoint. What a socket refuses is said on standard error and dropped: one bad
    /// request never stops the device.
    fn send(&mut self, i: usize, now: edsgen_runtime::Instant) {
        while let Some(transmit) = self.devices[i].poll_transmit(now) {
            let (sent, what) = match &transmit {
                Transmit::Frame(frame) => (
                    self.raw.send(frame),
                    format!("a frame of {} bytes", frame.len()),
                ),
                Transmit::Datagram(to, pdu) => (
                    match &self.endpoints[i].socket {
                        Some(socket) => socket.send(*to, pdu),
                        None => Err(io::Error::new(
                            io::ErrorKind::NotConnected,
                            "the device has no IP",
                        )),
                    },
                    format!(
                        "a datagram of {} bytes to {}:{}",
                        pdu.len(),
                        std::net::Ipv4Addr::from(to.0),
                        to.1
                    ),
                ),
            };
            if let Err(e) = sent {
                eprintln!("dropped {what} the socket refused: {e}");
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::device_mac;

    #[test]
    fn the_first_device_has_the_interface_s_mac_the_next_ones_local_ones_of_their_own() {
        let iface = [0x00, 0x1b, 0x21, 0x12, 0x34, 0xff];
        assert_eq!(device_mac(iface, 0), iface);
        assert_eq!(device_mac(iface, 1), [0x02, 0x1b, 0x21, 0x12, 0x35, 0x00]);
        assert_eq!(device_mac(iface, 2), [0x02, 0x1b, 0x21, 0x12, 0x35, 0x01]);
        // A veth's random MAC is locally administered already; the last three bytes wrap.
        let veth = [0x3e, 0x01, 0x02, 0xff, 0xff, 0xff];
        assert_eq!(device_mac(veth, 1), [0x3e, 0x01, 0x02, 0x00, 0x00, 0x00]);
    }
}
