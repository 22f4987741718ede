//! `pn io`'s sockets: the packet socket (DCP, the AR's RT_CLASS_1 and alarm frames; a thread
//! blocked in its reads, so that the cycles keep to their interval) and UDP 34964 (the RPC
//! calls to the device and its ApplicationReady); [`Link::pump`] takes what comes on both while
//! it sends the output frames and the alarm machine's frames when due.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::sync::Arc;
use std::time::{Duration, Instant};

use edsgen_runtime::profinet::wire::dcp::{self, response_blocks, DcpHeader};
use edsgen_runtime::profinet::wire::rpc::{PnioStatus, RpcHeader, REQUEST, RESPONSE, RPC_PORT};
use edsgen_runtime::profinet::wire::rt::RtFrame;
use edsgen_runtime::profinet::wire::{Ethernet, Mac, ETHERTYPE_PROFINET};
use edsgen_sim::profinet::ar::Peer;
use edsgen_sim::profinet::controller::response;
use edsgen_sim::profinet::controller_alarm::ControllerAlarmEvent;
use edsgen_sim::profinet::driver::{RawSocket, RpcSocket};

use super::io::{usage, Ar, Stop, DCP_WAIT, RPC_WAIT};

/// A DCP answer's sender and blocks: (option, data after the BlockInfo).
pub(super) type DcpAnswer = (Mac, Vec<((u8, u8), Vec<u8>)>);

/// The controller's sockets and what came on them.
pub(super) struct Link {
    pub(super) raw: RawSocket,
    pub(super) frames: Receiver<Vec<u8>>,
    pub(super) done: Arc<AtomicBool>,
    pub(super) mac: Mac,
    pub(super) rpc: RpcSocket,
    pub(super) dcp: Vec<Vec<u8>>,
    pub(super) responses: Vec<Vec<u8>>,
    pub(super) requests: Vec<(Peer, Vec<u8>)>,
}

impl Link {
    pub(super) fn open(iface: &str) -> Result<Link, Stop> {
        let packet = |e: std::io::Error| usage(format!("cannot open `{iface}` for PROFINET: {e}"));
        let raw = RawSocket::open(iface, Duration::from_millis(1)).map_err(packet)?;
        let mut reader = raw.try_clone().map_err(packet)?;
        let rpc = RpcSocket::open(iface)
            .map_err(|e| usage(format!("cannot bind UDP {RPC_PORT} on `{iface}`: {e}")))?;
        let (tx, frames) = mpsc::channel();
        let done = Arc::new(AtomicBool::new(false));
        let stop = Arc::clone(&done);
        std::thread::spawn(move || {
            let mut buf = vec![0u8; 1600];
            while !stop.load(Ordering::Relaxed) {
                match reader.recv(&mut buf) {
                    Ok(Some(n)) => {
                        if tx.send(buf.get(..n).unwrap_or_default().to_vec()).is_err() {
                            break;
                        }
                    }
                    Ok(None) => {}
                    Err(_) => break,
                }
            }
        });
        Ok(Link {
            mac: raw.mac(),
            raw,
            frames,
            done,
            rpc,
            dcp: Vec::new(),
            responses: Vec::new(),
            requests: Vec::new(),
        })
    }

    pub(super) fn send(&mut self, frame: &[u8]) -> Result<(), Stop> {
        self.raw
            .send(frame)
            .map_err(|e| usage(format!("cannot send a frame: {e}")))
    }

    /// Sends a DCP request and waits for the answer to `xid`.
    pub(super) fn dcp(&mut self, frame: &[u8], xid: u32) -> Result<Option<DcpAnswer>, Stop> {
        self.dcp.clear();
        self.send(frame)?;
        let until = Instant::now() + DCP_WAIT;
        let answer = |f: &Vec<u8>| -> Option<DcpAnswer> {
            let eth = Ethernet::parse(f)?;
            let (header, blocks) = DcpHeader::parse(f.get(eth.payload..)?)?;
            (header.xid == xid && header.service_type == dcp::TYPE_RESPONSE).then(|| {
                let blocks = response_blocks(blocks)
                    .map(|(o, _, d)| (o, d.to_vec()))
                    .collect();
                (eth.src, blocks)
            })
        };
        while Instant::now() < until {
            match self.frames.recv_timeout(Duration::from_millis(10)) {
                Ok(f) => {
                    if let Some(found) = answer(&f) {
                        return Ok(Some(found));
                    }
                }
                Err(RecvTimeoutError::Timeout) => {}
                Err(RecvTimeoutError::Disconnected) => {
                    return Err(usage("the packet socket's reader ended"))
                }
            }
        }
        Ok(None)
    }

    /// One RPC call to the device at `ip`, the AR's frames going on meanwhile: the answer's
    /// PNIOStatus and argument bytes.
    pub(super) fn call(
        &mut self,
        ip: [u8; 4],
        pdu: &[u8],
        ar: &mut Ar,
    ) -> Result<(PnioStatus, Vec<u8>), Stop> {
        self.responses.clear();
        self.rpc
            .send((ip, RPC_PORT), pdu)
            .map_err(|e| usage(format!("UDP to the device: {e}")))?;
        self.pump(ar, Instant::now() + RPC_WAIT, |l, _| {
            !l.responses.is_empty()
        })?;
        let answer = self
            .responses
            .pop()
            .ok_or_else(|| Stop::Device(format!("the device did not answer in {RPC_WAIT:?}")))?;
        response(&answer)
            .ok_or_else(|| Stop::Device("the device's answer is no RPC response".into()))
    }

    /// Takes what comes on both sockets until `until` or until `enough` holds, sending the
    /// output frames and the alarm machine's frames when due.
    pub(super) fn pump(
        &mut self,
        ar: &mut Ar,
        until: Instant,
        enough: impl Fn(&Link, &Ar) -> bool,
    ) -> Result<(), Stop> {
        let mut buf = vec![0u8; 4096];
        loop {
            if let Some(frame) = ar.due_frame(self.mac) {
                self.send(&frame)?;
            }
            let now = Instant::now();
            if now >= until || enough(self, ar) {
                return Ok(());
            }
            let wait = (until - now)
                .min(ar.next.saturating_duration_since(now))
                .min(Duration::from_millis(1));
            match self.frames.recv_timeout(wait) {
                Ok(frame) => self.take_frame(ar, &frame),
                Err(RecvTimeoutError::Timeout) => {}
                Err(RecvTimeoutError::Disconnected) => {
                    return Err(usage("the packet socket's reader ended"))
                }
            }
            let t = ar.clock.now();
            if ar.alarms.poll_timeout().is_some_and(|at| at <= t) {
                ar.alarms.handle_timeout(t);
            }
            self.alarm_output(ar)?;
            while let Some((n, from)) = self
                .rpc
                .recv(&mut buf)
                .map_err(|e| usage(format!("UDP: {e}")))?
            {
                let Some(pdu) = buf.get(..n).filter(|_| from.0 == ar.ip) else {
                    continue;
                };
                match RpcHeader::parse(pdu).map(|(h, _)| h.packet_type) {
                    Some(REQUEST) => self.requests.push((from, pdu.to_vec())),
                    Some(RESPONSE) => self.responses.push(pdu.to_vec()),
                    _ => {}
                }
            }
        }
    }

    /// The alarm machine's frames out, its events printed; an AlarmCR's end ends the session.
    fn alarm_output(&mut self, ar: &mut Ar) -> Result<(), Stop> {
        while let Some(frame) = ar.alarms.poll_frame() {
            self.send(&frame)?;
        }
        while let Some(event) = ar.alarms.poll_event() {
            match event {
                ControllerAlarmEvent::Alarm(alarm) => {
                    let s = alarm.source;
                    let kind = match s.alarm_type {
                        0x0001 => "Diagnosis".to_owned(),
                        0x000C => "Diagnosis disappears".to_owned(),
                        0x0002 => "Process".to_owned(),
                        0x0003 => "Pull".to_owned(),
                        0x0004 => "Plug".to_owned(),
                        other => format!("type {other:#06x}"),
                    };
                    println!(
                        "alarm: {kind} ({:#06x}) in slot {} subslot {}, sequence {}, {} priority: acknowledged",
                        s.alarm_type,
                        s.slot,
                        s.subslot,
                        s.specifier & 0x07FF,
                        if alarm.high { "high" } else { "low" }
                    );
                }
                ControllerAlarmEvent::Aborted(_) if ar.releasing => {}
                ControllerAlarmEvent::Aborted(status) => {
                    let why = status.map_or("an AlarmAck not acknowledged".to_owned(), |s| {
                        let s = s.0;
                        format!(
                            "PNIOStatus {:02x} {:02x} {:02x} {:02x}",
                            s[0], s[1], s[2], s[3]
                        )
                    });
                    return Err(Stop::Device(format!("the device ended the AR: {why}")));
                }
            }
        }
        Ok(())
    }

    /// A frame from the device: a DCP answer, an input frame of the AR or an alarm frame.
    fn take_frame(&mut self, ar: &mut Ar, frame: &[u8]) {
        let Some(eth) = Ethernet::parse(frame) else {
            return;
        };
        if eth.src != ar.device || eth.ethertype != ETHERTYPE_PROFINET {
            return;
        }
        if ar.alarms.handle_frame(ar.clock.now(), frame) {
            return;
        }
        let pdu = frame.get(eth.payload..).unwrap_or_default();
        let Some(rt) = RtFrame::parse(pdu, usize::from(ar.input.length)) else {
            return;
        };
        if rt.frame_id == ar.frame_ids.0 {
            ar.last = Some((rt.c_sdu.to_vec(), Instant::now()));
        }
    }
}

impl Drop for Link {
    fn drop(&mut self) {
        self.done.store(true, Ordering::Relaxed);
    }
}
