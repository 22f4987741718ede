//! `edsgen demo --enip`: the EtherNet/IP card's steps ([`super::enip::workflow`]) over real TCP
//! 44818 and UDP 2222. As root, two private network namespaces joined by a veth pair: `edsgen
//! simulate --enip 192.168.250.1 --card goodrive350-enip` in one; in the other this same
//! binary again as the demo's scanner (`edsgen demo-role enip-scanner ADDR`, [`scan`]: a process
//! enters a namespace only by being started in it), which prints its report as JSON for this
//! process to take into its trace, with the adapter's own log lines. Namespaces, pair and
//! programs go when the section ends (or on Ctrl-C, [`crate::netns`]). Not root: said on
//! standard error, and run in this process.

use std::io::{Read, Write};
use std::net::{Ipv4Addr, SocketAddr, TcpStream, UdpSocket};
use std::process::Stdio;
use std::time::{Duration, Instant};

use edsgen_runtime::enip::wire::io::IoDatagram;
use edsgen_sim::enip::driver::IO_PORT;

use super::enip::{workflow, Scanner, Stopped, RPI_US};
use super::two_namespaces::{self, Outcome, Pair, Server};
use super::{Report, Trace};
use crate::netns::Network;

/// The adapter's address (namespace 0) and the scanner's (namespace 1), on a /24.
pub(super) const ADAPTER: Ipv4Addr = Ipv4Addr::new(192, 168, 250, 1);
pub(super) const SCANNER: Ipv4Addr = Ipv4Addr::new(192, 168, 250, 2);
/// How long the scanner may take to finish its steps.
pub(super) const STEPS: Duration = Duration::from_secs(60);
/// How long a TCP exchange with the adapter may take.
const TCP_TIMEOUT: Duration = Duration::from_secs(5);

fn rpi() -> Duration {
    Duration::from_micros(RPI_US)
}

/// Runs the card's section between two namespaces where this process can, else in process.
pub(super) fn run(trace: &mut Trace) {
    let card = "the EtherNet/IP card";
    if !two_namespaces::as_root("demo --enip", card, trace, super::enip::run) {
        return;
    }
    trace.heading(
        "Goodrive350 EtherNet/IP card: a class-1 scanner from the generated images, over TCP \
         44818 and UDP 2222 between two network namespaces",
    );
    let workflow = "Goodrive350 EtherNet/IP workflow";
    let addresses = [ADAPTER, SCANNER];
    two_namespaces::between_two(trace, "enip", addresses, workflow, "adapter", on_wire);
}

/// The adapter and the scanner in their namespaces, the scanner's report taken into `trace`;
/// the adapter's log once it is stopped (with the problem, if any).
fn on_wire(trace: &mut Trace, net: &mut Network, pair: &Pair) -> Outcome {
    let [adapter_ns, scanner_ns] = &pair.namespaces;
    let mut command = net.command(0, &pair.exe).map_err(|p| (p, Vec::new()))?;
    command
        .args(["simulate", "--enip", &ADAPTER.to_string()])
        .args(["--card", "goodrive350-enip"])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    let shown = format!(
        "ip netns exec {adapter_ns} edsgen simulate --enip {ADAPTER} --card goodrive350-enip"
    );
    let ready = ("serving ", false);
    let adapter = Server::start(trace, net, &mut command, shown, "the adapter", ready)?;

    let result = net.command(1, &pair.exe).and_then(|mut command| {
        command.args(["demo-role", "enip-scanner", &ADAPTER.to_string()]);
        let shown = format!(
            "ip netns exec {scanner_ns} edsgen demo-role enip-scanner {ADAPTER} (the scanner, at \
             {SCANNER})"
        );
        two_namespaces::client(trace, net, &mut command, shown, "the scanner", STEPS)
    });
    adapter.stop(net, Duration::from_secs(2), result)
}

/// `edsgen demo-role enip-scanner ADDR`, run inside the scanner's namespace by `--enip`: the card's
/// steps against the adapter at `addr` (TCP 44818, UDP 2222), the report to print as JSON.
pub fn scan(addr: Ipv4Addr) -> Report {
    let mut trace = Trace::new(Report::default());
    match Wire::connect(addr) {
        Ok(mut wire) => {
            if let Err(problem) = workflow(&mut trace, &mut wire) {
                trace.step("Goodrive350 EtherNet/IP workflow", Err(problem));
            }
        }
        Err(problem) => trace.step("connect to the adapter", Err(problem)),
    }
    trace.finish()
}

/// The scanner's sockets: TCP 44818 to the adapter, UDP 2222 both ways.
struct Wire {
    tcp: TcpStream,
    udp: UdpSocket,
    adapter: SocketAddr,
    /// The last T→O image, and when it came.
    last: Option<(Vec<u8>, Instant)>,
    /// When the last O→T datagram went.
    sent: Option<Instant>,
    /// When the current RPI ends.
    next: Instant,
}

impl Wire {
    fn connect(addr: Ipv4Addr) -> Result<Wire, String> {
        let tcp = TcpStream::connect_timeout(&SocketAddr::from((addr, 44818)), TCP_TIMEOUT)
            .map_err(|e| format!("TCP {addr}:44818: {e}"))?;
        tcp.set_read_timeout(Some(TCP_TIMEOUT))
            .and_then(|()| tcp.set_write_timeout(Some(TCP_TIMEOUT)))
            .and_then(|()| tcp.set_nodelay(true))
            .map_err(|e| format!("TCP {addr}:44818: {e}"))?;
        let udp = UdpSocket::bind((Ipv4Addr::UNSPECIFIED, IO_PORT))
            .map_err(|e| format!("UDP {IO_PORT}: {e}"))?;
        Ok(Wire {
            tcp,
            udp,
            adapter: SocketAddr::from((addr, IO_PORT)),
            last: None,
            sent: None,
            next: Instant::now(),
        })
    }

    /// Takes T→O datagrams until `until`, keeping the last image.
    fn receive_until(&mut self, until: Instant) -> Result<(), String> {
        let mut buf = [0u8; 1500];
        loop {
            let left = until.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return Ok(());
            }
            if !edsgen_host::wait::readable(&self.udp, left)
                .map_err(|e| format!("UDP {IO_PORT}: {e}"))?
            {
                continue;
            }
            let Ok((n, from)) = self.udp.recv_from(&mut buf) else {
                continue;
            };
            if from.ip() != self.adapter.ip() {
                continue;
            }
            // Sequenced address, then connected data: its 16-bit sequence count, the image.
            let image = IoDatagram::parse(&buf[..n])
                .ok()
                .and_then(|datagram| datagram.data.get(2..))
                .map(<[u8]>::to_vec);
            if let Some(image) = image {
                self.last = Some((image, Instant::now()));
            }
        }
    }

    /// The end of the next RPI (from now, if the last ended long ago).
    fn next_rpi(&mut self) -> Instant {
        let now = Instant::now();
        self.next = (self.next + rpi()).max(now + rpi() / 2);
        self.next
    }
}

impl Scanner for Wire {
    fn request(&mut self, message: &[u8]) -> Result<Vec<u8>, String> {
        let tcp = |e: std::io::Error| format!("TCP 44818: {e}");
        self.tcp.write_all(message).map_err(tcp)?;
        let mut reply = vec![0u8; 24];
        self.tcp.read_exact(&mut reply).map_err(tcp)?;
        let length = usize::from(u16::from_le_bytes([reply[2], reply[3]]));
        reply.resize(24 + length, 0);
        self.tcp.read_exact(&mut reply[24..]).map_err(tcp)?;
        Ok(reply)
    }

    fn rpi(&mut self, datagram: &[u8]) -> Result<Vec<u8>, String> {
        self.udp
            .send_to(datagram, self.adapter)
            .map_err(|e| format!("UDP {}: {e}", self.adapter))?;
        self.sent = Some(Instant::now());
        let until = self.next_rpi();
        self.receive_until(until)?;
        // The first T→O datagram may take the adapter's own RPI to come.
        if self.last.is_none() {
            let until = self.next_rpi();
            self.receive_until(until)?;
        }
        self.last
            .as_ref()
            .map(|(image, _)| image.clone())
            .ok_or_else(|| "no T→O datagram from the adapter".to_owned())
    }

    /// Closed: no T→O datagram in the last two RPIs, the last one at least two RPIs after the
    /// last O→T (the adapter waits 4 × RPI, and produces every RPI).
    fn stop_producing(&mut self, rpis: u32) -> Result<Stopped, String> {
        for _ in 0..rpis {
            let until = self.next_rpi();
            self.receive_until(until)?;
        }
        let last = self.last.as_ref().map(|(_, at)| *at);
        let quiet = last.map_or(Duration::MAX, |at| at.elapsed());
        let after = match (last, self.sent) {
            (Some(last), Some(sent)) => last.saturating_duration_since(sent),
            _ => Duration::ZERO,
        };
        let after = after.as_millis();
        Ok(Stopped {
            closed: quiet >= 2 * rpi() && after >= 2 * rpi().as_millis(),
            image: None,
            log: None,
            seen: format!(
                "the adapter's T→O datagrams stopped {after} ms after the scanner's last O→T"
            ),
        })
    }
}
