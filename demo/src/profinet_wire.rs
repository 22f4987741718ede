//! `edsgen demo --profinet`: the PROFINET card's steps ([`super::profinet::workflow`]) over real
//! frames. As root, two private network namespaces joined by a veth pair: `edsgen simulate
//! --profinet END --card goodrive350-pn --ip 192.168.251.1/24` in one; in the other this same
//! binary again as the demo's controller (`edsgen demo-role profinet-controller IFACE ADDR`,
//! [`control`]: a process enters a namespace only by being started in it), with DCP and the
//! RT_CLASS_1 frames on a packet socket (EtherType 0x8892) and connection management on its own
//! UDP 34964, where the card's ApplicationReady comes; it prints its report as JSON for this
//! process to take into its trace, followed by the card's own log lines. In real time the
//! watchdog is longer than in process (a loaded machine may keep a process waiting for more
//! than 12 ms), and the card's end is seen within a slack. Namespaces, pair and programs go
//! when the section ends (or on Ctrl-C, [`crate::netns`]). Not root: said on standard error,
//! and run in this process. The DCP frame helpers both ways share ([`dcp_request`],
//! [`answer`]) are here too.

use std::net::Ipv4Addr;
use std::process::Stdio;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::sync::Arc;
use std::time::{Duration, Instant};

use edsgen_runtime::profinet::wire::dcp::{self, response_blocks, DcpHeader, TYPE_RESPONSE};
use edsgen_runtime::profinet::wire::rpc::{RpcHeader, REQUEST, RESPONSE, RPC_PORT};
use edsgen_runtime::profinet::wire::rt::RT_CLASS_1;
use edsgen_runtime::profinet::wire::{Ethernet, Mac, ETHERTYPE_PROFINET};
use edsgen_sim::profinet::ar::Peer;
use edsgen_sim::profinet::driver::{RawSocket, RpcSocket};

use super::profinet::{workflow, Silence, Timing, Transport};
use super::two_namespaces::{self, Outcome, Pair, Server};
use super::{Report, Trace};
use crate::netns::Network;

/// The card's address (namespace 0) and the controller's (namespace 1), on a /24.
pub(super) const CARD: Ipv4Addr = Ipv4Addr::new(192, 168, 251, 1);
pub(super) const CONTROLLER: Ipv4Addr = Ipv4Addr::new(192, 168, 251, 2);
/// How long the controller may take to finish its steps (the drive's ramps alone take 20 s).
pub(super) const STEPS: Duration = Duration::from_secs(120);
/// On the wire: 4 ms cycles, a watchdog of 100 of them; the card's last input frame seen up to
/// 40 ms before the watchdog's time (its loop takes the kernel's ticks of 4 ms or more) or up
/// to 200 ms after it (a loaded machine).
const TIMING: Timing = Timing {
    interval_ms: 4,
    factor: 100,
    early_ms: 40,
    late_ms: 200,
};
/// How long the controller waits for a DCP answer, and for an RPC response or request.
const DCP_WAIT: Duration = Duration::from_secs(1);
const RPC_WAIT: Duration = Duration::from_secs(5);
/// Intervals without an input frame after which the card is taken to have stopped sending.
const QUIET_INTERVALS: u32 = 25;

fn interval() -> Duration {
    Duration::from_millis(TIMING.interval_ms)
}

/// Runs the card's section between two namespaces where this process can, else in process.
pub(super) fn run(trace: &mut Trace) {
    let card = "the PROFINET card";
    if !two_namespaces::as_root("demo --profinet", card, trace, super::profinet::run) {
        return;
    }
    trace.heading(
        "Goodrive350 PROFINET card: DCP, an AR over RPC on UDP 34964, RT_CLASS_1 frames every \
         4 ms, between two network namespaces",
    );
    let workflow = "Goodrive350 PROFINET workflow";
    let addresses = [CARD, CONTROLLER];
    two_namespaces::between_two(trace, "pn", addresses, workflow, "device", on_wire);
}

/// The card and the controller in their namespaces, the controller's report taken into
/// `trace`; the card's log once it is stopped (with the problem, if any).
fn on_wire(trace: &mut Trace, net: &mut Network, pair: &Pair) -> Outcome {
    let [card_end, controller_end] = &pair.ends;
    let [card_ns, controller_ns] = &pair.namespaces;
    let mut command = net.command(0, &pair.exe).map_err(|p| (p, Vec::new()))?;
    command
        .args(["simulate", "--profinet", card_end])
        .args(["--card", "goodrive350-pn", "--ip", &format!("{CARD}/24")])
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    let shown = format!(
        "ip netns exec {card_ns} edsgen simulate --profinet {card_end} --card goodrive350-pn \
         --ip {CARD}/24"
    );
    let ready = ("RPC on UDP 34964", true);
    let card = Server::start(trace, net, &mut command, shown, "the card", ready)?;

    let result = net.command(1, &pair.exe).and_then(|mut command| {
        command
            .args(["demo-role", "profinet-controller", controller_end])
            .arg(CARD.to_string());
        let shown = format!(
            "ip netns exec {controller_ns} edsgen demo-role profinet-controller {controller_end} \
             {CARD} (the controller, at {CONTROLLER})"
        );
        two_namespaces::client(trace, net, &mut command, shown, "the controller", STEPS)
    });
    card.stop(net, Duration::from_secs(2), result)
}

/// `edsgen demo-role profinet-controller IFACE ADDR`, run inside the controller's namespace by
/// `--profinet`: the card's steps from `iface` against the card at `card` (UDP 34964), the
/// report to print as JSON.
pub fn control(iface: &str, card: Ipv4Addr) -> Report {
    let mut trace = Trace::new(Report::default());
    match Wire::open(iface, card) {
        Ok(mut wire) => {
            if let Err(problem) = workflow(&mut trace, &mut wire) {
                trace.step("Goodrive350 PROFINET workflow", Err(problem));
            }
        }
        Err(problem) => trace.step("open the controller's sockets", Err(problem)),
    }
    trace.finish()
}

/// The controller's sockets and what came on them.
struct Wire {
    /// DCP and RT_CLASS_1 frames (EtherType 0x8892) out.
    raw: RawSocket,
    /// The frames received on it, each with when it came, from a thread blocked in its reads:
    /// a socket's read timeout goes by the kernel's ticks (4 ms or more), a channel's wait does
    /// not, so that the cycles keep to their interval.
    frames: Receiver<(Vec<u8>, Instant)>,
    /// Tells that thread to end.
    done: Arc<AtomicBool>,
    mac: Mac,
    /// UDP 34964: the controller's requests out, the card's responses and requests in.
    rpc: RpcSocket,
    card: Peer,
    start: Instant,
    /// When the current send interval ends.
    next: Instant,
    /// When the last output frame went.
    sent: Option<Instant>,
    /// The card's last input frame, and when it came.
    last: Option<(Vec<u8>, Instant)>,
    /// DCP answers, and RPC responses and requests from the card, not yet taken.
    dcp: Vec<Vec<u8>>,
    responses: Vec<Vec<u8>>,
    requests: Vec<Vec<u8>>,
}

impl Wire {
    fn open(iface: &str, card: Ipv4Addr) -> Result<Wire, String> {
        let packet = |e: std::io::Error| format!("a packet socket on `{iface}`: {e}");
        let raw = RawSocket::open(iface, Duration::from_millis(1)).map_err(packet)?;
        let mut reader = raw.try_clone().map_err(packet)?;
        let rpc =
            RpcSocket::open(iface).map_err(|e| format!("UDP {RPC_PORT} on `{iface}`: {e}"))?;
        let (tx, frames) = mpsc::channel();
        let done = Arc::new(AtomicBool::new(false));
        let stop = Arc::clone(&done);
        std::thread::spawn(move || {
            let mut buf = vec![0u8; 1600];
            while !stop.load(Ordering::Relaxed) {
                match reader.recv(&mut buf) {
                    Ok(Some(n)) => {
                        let frame = buf.get(..n).unwrap_or_default().to_vec();
                        if tx.send((frame, Instant::now())).is_err() {
                            break;
                        }
                    }
                    Ok(None) => {}
                    Err(_) => break,
                }
            }
        });
        let now = Instant::now();
        Ok(Wire {
            mac: raw.mac(),
            raw,
            frames,
            done,
            rpc,
            card: (card.octets(), RPC_PORT),
            start: now,
            next: now,
            sent: None,
            last: None,
            dcp: Vec::new(),
            responses: Vec::new(),
            requests: Vec::new(),
        })
    }

    /// Takes what comes on both sockets until `until`, or until `enough` holds.
    fn pump(&mut self, until: Instant, enough: impl Fn(&Wire) -> bool) -> Result<(), String> {
        let mut buf = vec![0u8; 1600];
        loop {
            let now = Instant::now();
            if now >= until || enough(self) {
                return Ok(());
            }
            // The UDP socket is looked at every millisecond at least.
            let wait = (until - now).min(Duration::from_millis(1));
            match self.frames.recv_timeout(wait) {
                Ok((frame, at)) => self.take_frame(&frame, at),
                Err(RecvTimeoutError::Timeout) => {}
                Err(RecvTimeoutError::Disconnected) => {
                    return Err("the packet socket's reader ended".into())
                }
            }
            while let Some((n, from)) = self.rpc.recv(&mut buf).map_err(|e| format!("{e}"))? {
                let Some(pdu) = buf.get(..n).filter(|_| from.0 == self.card.0) else {
                    continue;
                };
                match RpcHeader::parse(pdu).map(|(h, _)| h.packet_type) {
                    Some(REQUEST) => self.requests.push(pdu.to_vec()),
                    Some(RESPONSE) => self.responses.push(pdu.to_vec()),
                    _ => {}
                }
            }
        }
    }

    /// A frame from the card: a DCP answer, or an input frame (the packet socket also sees the
    /// controller's own frames, which are not the card's).
    fn take_frame(&mut self, frame: &[u8], at: Instant) {
        let Some(eth) = Ethernet::parse(frame) else {
            return;
        };
        if eth.src == self.mac || eth.ethertype != ETHERTYPE_PROFINET {
            return;
        }
        let pdu = &frame[eth.payload..];
        let Some(frame_id) = pdu.get(..2).map(|id| u16::from_be_bytes([id[0], id[1]])) else {
            return;
        };
        if RT_CLASS_1.contains(&frame_id) {
            self.last = Some((frame.to_vec(), at));
        } else if DcpHeader::parse(pdu).is_some_and(|(h, _)| h.service_type == TYPE_RESPONSE) {
            self.dcp.push(frame.to_vec());
        }
    }

    fn send_rpc(&mut self, pdu: &[u8]) -> Result<(), String> {
        self.rpc
            .send(self.card, pdu)
            .map_err(|e| format!("UDP to the card's {RPC_PORT}: {e}"))
    }
}

impl Drop for Wire {
    fn drop(&mut self) {
        self.done.store(true, Ordering::Relaxed);
    }
}

/// A DCP frame's Xid.
fn xid(frame: &[u8]) -> Option<u32> {
    let eth = Ethernet::parse(frame)?;
    Some(DcpHeader::parse(frame.get(eth.payload..)?)?.0.xid)
}

impl Transport for Wire {
    fn controller_mac(&self) -> Mac {
        self.mac
    }

    fn timing(&self) -> Timing {
        TIMING
    }

    fn dcp(&mut self, request: &[u8]) -> Result<Option<Vec<u8>>, String> {
        self.dcp.clear();
        self.raw
            .send(request)
            .map_err(|e| format!("a DCP request: {e}"))?;
        let wanted = xid(request);
        let answered = |w: &Wire| w.dcp.iter().any(|f| xid(f) == wanted);
        self.pump(Instant::now() + DCP_WAIT, answered)?;
        Ok(self.dcp.iter().find(|f| xid(f) == wanted).cloned())
    }

    fn call(&mut self, pdu: &[u8]) -> Result<Vec<u8>, String> {
        self.responses.clear();
        self.send_rpc(pdu)?;
        self.pump(Instant::now() + RPC_WAIT, |w| !w.responses.is_empty())?;
        self.responses
            .pop()
            .ok_or_else(|| format!("the card did not answer in {RPC_WAIT:?}"))
    }

    fn card_request(&mut self) -> Result<Vec<u8>, String> {
        self.pump(Instant::now() + RPC_WAIT, |w| !w.requests.is_empty())?;
        if self.requests.is_empty() {
            return Err(format!("no ApplicationReady in {RPC_WAIT:?}"));
        }
        Ok(self.requests.remove(0))
    }

    fn answer(&mut self, pdu: &[u8]) -> Result<(), String> {
        self.send_rpc(pdu)
    }

    fn card_events(&mut self) -> Option<Vec<&'static str>> {
        None
    }

    fn now_ms(&self) -> u64 {
        self.start.elapsed().as_millis() as u64
    }

    fn cycle(&mut self, frame: &[u8]) -> Result<Option<Vec<u8>>, String> {
        self.raw
            .send(frame)
            .map_err(|e| format!("an output frame: {e}"))?;
        let now = Instant::now();
        self.sent = Some(now);
        // The next interval from the last one's end, or from now if that is long past.
        self.next = (self.next + interval()).max(now + interval() / 2);
        self.pump(self.next, |_| false)?;
        // The card's first input frame may take its own interval to come.
        if self.last.is_none() {
            self.pump(Instant::now() + 10 * interval(), |w| w.last.is_some())?;
        }
        Ok(self.last.as_ref().map(|(frame, _)| frame.clone()))
    }

    /// The frames already on their way are let pass (3 intervals); then none may come in
    /// [`QUIET_INTERVALS`].
    fn sending_stopped(&mut self) -> Result<bool, String> {
        self.pump(Instant::now() + 3 * interval(), |_| false)?;
        self.last = None;
        self.pump(Instant::now() + QUIET_INTERVALS * interval(), |_| false)?;
        Ok(self.last.take().is_none())
    }

    /// Listens until the card's input frames have stopped for [`QUIET_INTERVALS`] and the
    /// watchdog's time (and slack) has passed since the last output frame, or until three
    /// seconds after that: the card aborted the AR if its frames stopped.
    fn fall_silent(&mut self) -> Result<Silence, String> {
        let sent = self.sent.ok_or("no output frame was sent")?;
        let watchdog = Duration::from_millis(TIMING.watchdog_ms() + TIMING.late_ms);
        let quiet = QUIET_INTERVALS * interval();
        let stopped = |w: &Wire| {
            let last = w.last.as_ref().map_or(sent, |(_, at)| *at);
            Instant::now() >= sent + watchdog && last.elapsed() >= quiet
        };
        self.pump(sent + watchdog + Duration::from_secs(3), stopped)?;
        let last = self.last.take().map_or(sent, |(_, at)| at);
        let after = last.saturating_duration_since(sent).as_millis() as u64;
        Ok(Silence {
            aborted: last.elapsed() >= quiet,
            after_ms: after,
            seen: format!(
                "the card's input frames stopped {after} ms after the controller's last output \
                 frame (watchdog {} × {} ms)",
                TIMING.factor, TIMING.interval_ms
            ),
        })
    }
}

/// A DCP request frame (see [`dcp::request`]).
pub(super) fn dcp_request(
    dst: Mac,
    src: Mac,
    frame_id: u16,
    service: u8,
    xid: u32,
    blocks: &[u8],
) -> Vec<u8> {
    let mut frame = vec![0; 14 + dcp::HEADER_LEN + blocks.len()];
    let n = dcp::request(&mut frame, dst, src, frame_id, service, xid, blocks).unwrap_or(0);
    frame.truncate(n);
    frame
}

/// A DCP answer's block: option, BlockInfo, data.
pub(super) type Block = ((u8, u8), u16, Vec<u8>);

/// The card's MAC address and the DCP blocks of its answer to `frame`, or why there is none.
pub(super) fn answer(link: &mut dyn Transport, frame: &[u8]) -> Result<(Mac, Vec<Block>), String> {
    let reply = link.dcp(frame)?.ok_or("the device did not answer")?;
    let eth = Ethernet::parse(&reply).ok_or("a short answer")?;
    let (_, blocks) = DcpHeader::parse(&reply[eth.payload..]).ok_or("a malformed DCP answer")?;
    Ok((
        eth.src,
        response_blocks(blocks)
            .map(|(o, i, d)| (o, i, d.to_vec()))
            .collect(),
    ))
}

pub(super) fn find(blocks: &[Block], option: (u8, u8)) -> Result<Vec<u8>, String> {
    blocks
        .iter()
        .find(|b| b.0 == option)
        .map(|b| b.2.clone())
        .ok_or_else(|| format!("no block {option:?} in the answer"))
}
