//! The device's connection management (p-net's `pf_cmrpc`, `pf_cmdev`, `pf_cmrdr`, `pf_cmwrr`):
//! the RPC endpoint on UDP 34964 and the one application relation (AR) it serves. Sans-IO: a
//! datagram and its sender in, the answer out; the device's own requests (the ApplicationReady
//! CControl) and what happened ([`ArEvent`]) polled.
//!
//! An AR's life: Connect (checked in [`connect`] against the GSDML's [`config`]) → parameter
//! phase (Write of records, Read) → the controller's PrmEnd → the device's ApplicationReady
//! request to the controller's RPC port → its Done → data exchange ([`ArEvent::DataStart`]: the
//! cyclic frames are valid from now) → Release, or [`Cm::abort`] when the cyclic watchdog
//! expires, or when the controller sends no request for its CMInitiatorActivityTimeout before
//! data exchange. One AR at a time: a Connect while one is up is refused (CMRPC out of AR resources),
//! unless it repeats the same AR UUID. A device access AR (IOSAR) has no cyclic data.
//! Records (module `records`): 0xF000 RealIdentificationData, 0xAFF0 I&M0, and the GSDML's
//! parameter records of each submodule (written with their exact length, read back).
//! Alarms: the AlarmCR is accepted and answered (AlarmCRBlockRes, the device's
//! LocalAlarmReference 1); [`Cm::alarm_cr`] gives the AR's alarm machines
//! ([`super::alarm::AlarmCr`]), which the device runs.

pub mod config;
pub mod connect;
mod records;

use edsgen_runtime::{Duration, Instant};

use super::alarm::AlarmCr;
use super::cyclic::CrLayout;
use super::wire::blocks::*;
use super::wire::rpc::*;
use super::wire::{append, rpc_pdu, rpc_reject, Mac};
use config::DeviceConfig;
use connect::{refuse, Accepted, AR_TYPE_IOC_SINGLE};

/// A datagram's peer: IPv4 address and UDP port.
pub type Peer = ([u8; 4], u16);

/// Whether a datagram can be sent to `peer`: a port, and a unicast address.
pub fn answerable(peer: Peer) -> bool {
    let ip = core::net::Ipv4Addr::from(peer.0);
    peer.1 != 0 && !ip.is_unspecified() && !ip.is_broadcast() && !ip.is_multicast()
}

/// What the connection management tells the application.
#[derive(Debug, Clone, PartialEq)]
pub enum ArEvent {
    /// An AR was established (with its cyclic layout for an IO AR; `diff` when the expected
    /// configuration differed).
    Connected {
        /// ARType.
        ar_type: u16,
        /// The cyclic layout, for an IO AR.
        layout: Option<CrLayout>,
        /// The expected configuration differed (a ModuleDiffBlock was sent).
        diff: bool,
    },
    /// A parameter record was written.
    RecordWritten {
        /// Slot.
        slot: u16,
        /// Subslot.
        subslot: u16,
        /// Index.
        index: u16,
        /// The data.
        data: Vec<u8>,
    },
    /// The controller ended the parameter phase.
    PrmEnd,
    /// The controller confirmed ApplicationReady: cyclic data is valid from now.
    DataStart,
    /// The controller released the AR.
    Released,
    /// The AR was aborted (watchdog, or the controller never confirmed ApplicationReady).
    Aborted,
}

/// Where the AR is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Phase {
    /// Between Connect and PrmEnd.
    Parameter,
    /// ApplicationReady sent, its Done not yet come.
    AwaitingReady,
    /// Cyclic data exchange.
    Data,
}

#[derive(Debug, Clone)]
struct Ar {
    accepted: Accepted,
    controller: [u8; 4],
    phase: Phase,
    /// The ApplicationReady request, its activity, when it was last sent, how often.
    ready: Option<(Vec<u8>, Uuid, Instant, u8)>,
    /// The last request of the controller: before data exchange, the AR ends when none comes
    /// for CMInitiatorActivityTimeoutFactor × 100 ms.
    last_request: Instant,
}

impl Ar {
    /// CMInitiatorActivityTimeoutFactor × 100 ms.
    fn activity_timeout(&self) -> Duration {
        Duration::from_millis(u64::from(self.accepted.ar.timeout_factor.max(1)) * 100)
    }

    /// When the AR ends for want of the controller's requests (not in data exchange).
    fn activity_deadline(&self) -> Option<Instant> {
        (self.phase != Phase::Data).then(|| self.last_request + self.activity_timeout())
    }
}

/// The device's LocalAlarmReference (its AlarmSrcEndpoint), the same for every AR.
pub const LOCAL_ALARM_REFERENCE: u16 = 1;

/// How long the device waits for the Done of its ApplicationReady before sending it again,
/// and how often it sends it.
const READY_RETRY: Duration = Duration::from_millis(1000);
const READY_TRIES: u8 = 3;

/// The device's connection management.
#[derive(Debug, Clone)]
pub struct Cm {
    config: DeviceConfig,
    mac: Mac,
    object: Uuid,
    ar: Option<Ar>,
    records: Vec<((u16, u16, u16), Vec<u8>)>,
    outbox: Vec<(Peer, Vec<u8>)>,
    events: Vec<ArEvent>,
    /// The last answer, by activity and sequence: a repeated request gets it again.
    last: Option<(Uuid, u32, Vec<u8>)>,
    /// I&M0's fields: VendorID, OrderID.
    vendor_id: u16,
    order_id: String,
    sequence: u32,
}

impl Cm {
    /// The connection management of a device with `config`, on an interface with `mac`;
    /// `ids` are its (VendorID, DeviceID, instance) for its object UUID, `order_id` its I&M0
    /// OrderID.
    pub fn new(config: DeviceConfig, mac: Mac, ids: (u16, u16, u16), order_id: &str) -> Cm {
        let records = config
            .slots
            .iter()
            .flat_map(|s| {
                s.submodules.iter().flat_map(move |sub| {
                    sub.records
                        .iter()
                        .map(move |r| ((s.slot, sub.subslot, r.index), r.initial.clone()))
                })
            })
            .collect();
        Cm {
            object: Uuid::pnio_object(ids.2, ids.1, ids.0),
            config,
            mac,
            ar: None,
            records,
            outbox: Vec::new(),
            events: Vec::new(),
            last: None,
            vendor_id: ids.0,
            order_id: order_id.to_owned(),
            sequence: 0,
        }
    }

    /// `true` while cyclic data is valid (between ApplicationReady's Done and the AR's end).
    pub fn data_valid(&self) -> bool {
        self.ar.as_ref().is_some_and(|a| a.phase == Phase::Data)
    }

    /// The AR's CMInitiatorActivityTimeout (zero without an AR).
    pub fn activity_timeout(&self) -> Duration {
        self.ar
            .as_ref()
            .map_or(Duration::from_micros(0), Ar::activity_timeout)
    }

    /// The next event.
    pub fn poll_event(&mut self) -> Option<ArEvent> {
        (!self.events.is_empty()).then(|| self.events.remove(0))
    }

    /// The next datagram the device sends of its own (the ApplicationReady request).
    pub fn poll_datagram(&mut self) -> Option<(Peer, Vec<u8>)> {
        (!self.outbox.is_empty()).then(|| self.outbox.remove(0))
    }

    /// When [`Cm::handle_timeout`] has something to do.
    pub fn poll_timeout(&self) -> Option<Instant> {
        let ar = self.ar.as_ref()?;
        let ready = ar.ready.as_ref().map(|(_, _, at, _)| *at + READY_RETRY);
        [ready, ar.activity_deadline()].into_iter().flatten().min()
    }

    /// Time passed: ApplicationReady sent again, or the AR aborted after the last try or when
    /// the controller fell silent before data exchange.
    pub fn handle_timeout(&mut self, now: Instant) {
        let Some(ar) = self.ar.as_mut() else { return };
        if ar.activity_deadline().is_some_and(|d| d <= now) {
            self.abort();
            return;
        }
        let Some((pdu, _, at, tries)) = ar.ready.as_mut() else {
            return;
        };
        if now < *at + READY_RETRY {
            return;
        }
        if *tries >= READY_TRIES {
            self.abort();
            return;
        }
        *tries += 1;
        *at = now;
        let pdu = pdu.clone();
        self.outbox.push(((ar.controller, RPC_PORT), pdu));
    }

    /// Ends the AR (the cyclic watchdog expired).
    pub fn abort(&mut self) {
        if self.ar.take().is_some() {
            self.events.push(ArEvent::Aborted);
        }
    }

    /// A datagram from `from` at `now`: the answer to send back to it, if any. A sender that
    /// cannot be answered (port 0, or a source address no host has: 0.0.0.0, broadcast,
    /// multicast) is ignored: a socket refuses a datagram to it.
    pub fn handle_datagram(&mut self, now: Instant, from: Peer, pdu: &[u8]) -> Option<Vec<u8>> {
        if !answerable(from) {
            return None;
        }
        let (header, body) = RpcHeader::parse(pdu)?;
        match header.packet_type {
            REQUEST => {}
            RESPONSE => {
                self.handle_response(&header, body);
                return None;
            }
            PING => {
                // Calls complete at once: a ping of the last one gets its answer again, of
                // any other "no call".
                if let Some((activity, sequence, answer)) = &self.last {
                    if *activity == header.activity && *sequence == header.sequence {
                        return Some(answer.clone());
                    }
                }
                let mut out = vec![0; HEADER_LEN];
                let written = header.answer(NOCALL).emit(0, &mut out).unwrap_or(0);
                out.truncate(written);
                return Some(out);
            }
            _ => return None,
        }
        if header.interface != Uuid::PNIO_DEVICE {
            return Some(rpc_reject(&header, REJECT, NCA_UNKNOWN_INTERFACE));
        }
        if let Some((activity, sequence, answer)) = &self.last {
            if *activity == header.activity && *sequence == header.sequence {
                return Some(answer.clone());
            }
        }
        if let Some(ar) = self.ar.as_mut() {
            ar.last_request = now;
        }
        let little = header.little_endian;
        let (status, args, max) = match Ndr::parse(body, little) {
            // CMRPC: ArgsLength invalid.
            None => (
                PnioStatus::new(0xDB, 0x81, connect::CMRPC, 0),
                Vec::new(),
                0,
            ),
            Some((ndr, args)) => {
                let result = match header.opnum {
                    OP_CONNECT => self.connect(now, from, args),
                    OP_RELEASE => self.release(args, PnioStatus::CODE_RELEASE),
                    OP_READ => self.read(args, false),
                    OP_READ_IMPLICIT => self.read(args, true),
                    OP_WRITE => self.write(args),
                    OP_CONTROL => self.control(now, args),
                    _ => return Some(rpc_reject(&header, REJECT, NCA_OP_RANGE_ERROR)),
                };
                match result {
                    Ok(args) => (PnioStatus::OK, args, ndr.args_maximum()),
                    Err(status) => (status, Vec::new(), ndr.args_maximum()),
                }
            }
        };
        let ndr = Ndr::response(status, args.len() as u32, max, little);
        let answer = rpc_pdu(&header.answer(RESPONSE), &ndr, &args);
        self.last = Some((header.activity, header.sequence, answer.clone()));
        Some(answer)
    }

    fn connect(&mut self, now: Instant, from: Peer, args: &[u8]) -> Result<Vec<u8>, PnioStatus> {
        let accepted = connect::check(&self.config, self.mac, args)?;
        if let Some(ar) = &self.ar {
            if ar.accepted.ar.ar_uuid != accepted.ar.ar_uuid {
                return Err(refuse(connect::CMRPC, 0x04));
            }
        }
        let mut out = Vec::new();
        let ar_res = ArBlockRes {
            ar_type: accepted.ar.ar_type,
            ar_uuid: accepted.ar.ar_uuid,
            session_key: accepted.ar.session_key,
            responder_mac: self.mac,
            udp_rt_port: 0x8892,
        };
        append_block(&mut out, |b| ar_res.emit(b));
        for iocr in &accepted.iocrs {
            append_block(&mut out, |b| iocr.emit(b));
        }
        if let Some(alarm) = &accepted.alarm {
            let alarm_res = AlarmCrBlockRes {
                alarm_cr_type: alarm.alarm_cr_type,
                local_alarm_reference: LOCAL_ALARM_REFERENCE,
                max_alarm_data_length: alarm.max_alarm_data_length,
            };
            append_block(&mut out, |b| alarm_res.emit(b));
        }
        if !accepted.diff.is_empty() {
            let diff = ModuleDiffBlock {
                apis: accepted.diff.clone(),
            };
            append_block(&mut out, |b| diff.emit(b));
        }
        self.events.push(ArEvent::Connected {
            ar_type: accepted.ar.ar_type,
            layout: accepted.layout.clone(),
            diff: !accepted.diff.is_empty(),
        });
        self.ar = Some(Ar {
            accepted,
            controller: from.0,
            phase: Phase::Parameter,
            ready: None,
            last_request: now,
        });
        Ok(out)
    }

    /// The AR a request names, with its session key when it has one.
    fn ar_of(&self, ar_uuid: Uuid, session_key: Option<u16>) -> Option<&Ar> {
        self.ar.as_ref().filter(|a| {
            a.accepted.ar.ar_uuid == ar_uuid
                && session_key.is_none_or(|k| k == a.accepted.ar.session_key)
        })
    }

    fn control_block(args: &[u8], code: u8) -> Result<IodControl, PnioStatus> {
        let blocks = split(args).map_err(|_| PnioStatus::new(code, 0x81, 0x40, 0x01))?;
        let block = blocks
            .first()
            .filter(|_| blocks.len() == 1)
            .ok_or(PnioStatus::new(code, 0x81, 0x40, 0x03))?;
        IodControl::parse(block.block_type, block.body)
            .ok_or(PnioStatus::new(code, 0x81, 0x40, 0x01))
    }

    fn release(&mut self, args: &[u8], code: u8) -> Result<Vec<u8>, PnioStatus> {
        let req = Self::control_block(args, code)?;
        if req.block_type != RELEASE_REQ || req.command != CMD_RELEASE {
            return Err(PnioStatus::new(code, 0x81, 0x28, 0x04));
        }
        self.ar_of(req.ar_uuid, Some(req.session_key))
            .ok_or(PnioStatus::new(code, 0x81, 0x40, 0x05))?;
        self.ar = None;
        self.events.push(ArEvent::Released);
        let mut out = Vec::new();
        append(&mut out, |b| req.done().emit(b));
        Ok(out)
    }

    fn control(&mut self, now: Instant, args: &[u8]) -> Result<Vec<u8>, PnioStatus> {
        let code = PnioStatus::CODE_CONTROL;
        let req = Self::control_block(args, code)?;
        if req.block_type == RELEASE_REQ {
            return self.release(args, code);
        }
        if req.block_type != PRM_END_REQ || req.command != CMD_PRM_END {
            return Err(PnioStatus::new(code, 0x81, 0x3D, 0x00));
        }
        let ar = self
            .ar_of(req.ar_uuid, Some(req.session_key))
            .ok_or(PnioStatus::new(code, 0x81, 0x40, 0x05))?;
        if ar.phase != Phase::Parameter {
            // CMDEV state conflict.
            return Err(PnioStatus::new(code, 0x81, 0x3D, 0x00));
        }
        let mut out = Vec::new();
        append(&mut out, |b| req.done().emit(b));
        self.events.push(ArEvent::PrmEnd);
        self.application_ready(now);
        Ok(out)
    }

    /// Queues the ApplicationReady request (CControl) to the controller's RPC port.
    fn application_ready(&mut self, now: Instant) {
        self.sequence = self.sequence.wrapping_add(1);
        let Some(ar) = self.ar.as_mut() else { return };
        if ar.accepted.ar.ar_type != AR_TYPE_IOC_SINGLE {
            ar.phase = Phase::Data;
            return;
        }
        // The activity of the device's call: the AR UUID with the first byte turned.
        let mut activity = ar.accepted.ar.ar_uuid;
        activity.0[0] ^= 0xFF;
        let header = RpcHeader::request(
            ar.accepted.ar.initiator_object,
            Uuid::PNIO_CONTROLLER,
            activity,
            self.sequence,
            OP_CONTROL,
        );
        let mut args = Vec::new();
        let block = IodControl {
            block_type: APPLICATION_READY_REQ,
            ar_uuid: ar.accepted.ar.ar_uuid,
            session_key: ar.accepted.ar.session_key,
            command: CMD_APPLICATION_READY,
            properties: 0,
        };
        append(&mut args, |b| block.emit(b));
        let pdu = rpc_pdu(
            &header,
            &Ndr::request(4068, args.len() as u32, false),
            &args,
        );
        ar.phase = Phase::AwaitingReady;
        ar.ready = Some((pdu.clone(), activity, now, 1));
        self.outbox.push(((ar.controller, RPC_PORT), pdu));
    }

    fn handle_response(&mut self, header: &RpcHeader, body: &[u8]) {
        let Some(ar) = self.ar.as_mut() else { return };
        let Some((_, activity, _, _)) = &ar.ready else {
            return;
        };
        if header.activity != *activity || header.opnum != OP_CONTROL {
            return;
        }
        let Some((ndr, args)) = Ndr::parse(body, header.little_endian) else {
            return;
        };
        let done = split(args).ok().and_then(|b| {
            let b = b.first()?;
            IodControl::parse(b.block_type, b.body)
        });
        if !ndr.status().is_ok()
            || !done.is_some_and(|d| {
                d.block_type == APPLICATION_READY_REQ | RESPONSE_BIT
                    && d.command == CMD_DONE
                    && d.ar_uuid == ar.accepted.ar.ar_uuid
            })
        {
            return;
        }
        ar.ready = None;
        ar.phase = Phase::Data;
        self.events.push(ArEvent::DataStart);
    }

    /// The device's object UUID.
    pub fn object(&self) -> Uuid {
        self.object
    }

    /// The configuration the device checks Connects against.
    pub fn config(&self) -> &DeviceConfig {
        &self.config
    }

    /// The AR's AlarmCR machines, as its AlarmCRBlockReq asked, when the AR has one.
    pub fn alarm_cr(&self) -> Option<AlarmCr> {
        let ar = self.ar.as_ref()?;
        let req = ar.accepted.alarm.as_ref()?;
        Some(AlarmCr::new(
            req,
            LOCAL_ALARM_REFERENCE,
            self.mac,
            ar.accepted.ar.initiator_mac,
        ))
    }
}

#[cfg(test)]
mod tests;
