//! One simulated IO device, its protocol machines together: DCP ([`Dcp`]), connection
//! management ([`Cm`]) and, while an IO AR is up, the cyclic exchange on the AR's layout, with
//! the Goodrive350's PKW/PZD drive behind it when the device is the card (else a loopback: its
//! inputs are its outputs, [`Cyclic::looped_back`]).
//! Cyclic frames are produced only while the AR's data is valid (after ApplicationReady's Done)
//! and the watchdog aborts the AR. The AR's AlarmCR ([`AlarmCr`]) carries the card's
//! diagnosis: a fault of the drive is a Diagnosis alarm, its reset a Diagnosis disappears
//! alarm; an alarm the controller does not acknowledge ends the AR. Records 256 and 257 of the card are the drive's P16.32-P16.42
//! and P16.43-P16.53: a write sets them, a read shows them. Sans-IO, in the runtime's shape:
//! [`Device::handle`] takes Ethernet frames and UDP datagrams, [`Device::poll_transmit`] gives
//! frames and datagrams, with `poll_timeout`/`handle_timeout` and `poll_event`; the driver
//! ([`super::driver`]) moves them.

use std::collections::VecDeque;

use edsgen_runtime::pkw_pzd::IMAGE_BYTES;
use edsgen_runtime::{Duration, Instant};

use super::alarm::{AlarmCr, AlarmEvent};
use super::application::IoApplication;
pub use super::application::{RECORD_RECEIVED_PZD, RECORD_TRANSMITTED_PZD};
use super::ar::config::DeviceConfig;
use super::ar::{ArEvent, Cm, Peer};
use super::cyclic::{CrLayout, Cyclic};
use super::dcp::{Dcp, DcpEvent, Station};
use super::drive::{fault_alarm, CardCycle, DRIVE_SLOT};
use crate::drives::pkw_pzd::PkwPzdDrive;

/// Where received bytes came from, or where bytes to send go.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Link {
    /// The Ethernet port: DCP, cyclic RT and alarm frames.
    Ethernet,
    /// A peer on PROFINET's RPC endpoint (UDP 34964).
    Rpc(Peer),
}

/// Bytes the device sends.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Transmit {
    /// An Ethernet frame.
    Frame(Vec<u8>),
    /// A UDP datagram to a peer.
    Datagram(Peer, Vec<u8>),
}

impl Transmit {
    /// The frame, if it is one.
    pub fn frame(self) -> Option<Vec<u8>> {
        match self {
            Transmit::Frame(frame) => Some(frame),
            Transmit::Datagram(..) => None,
        }
    }

    /// The datagram and its destination, if it is one.
    pub fn datagram(self) -> Option<(Peer, Vec<u8>)> {
        match self {
            Transmit::Datagram(to, pdu) => Some((to, pdu)),
            Transmit::Frame(_) => None,
        }
    }
}

/// What happened in the device.
#[derive(Debug, Clone, PartialEq)]
pub enum DeviceEvent {
    /// A DCP Set.
    Dcp(DcpEvent),
    /// An AR's step.
    Ar(ArEvent),
    /// The AlarmCR's: an alarm acknowledged, or the AlarmCR (and its AR) over.
    Alarm(AlarmEvent),
}

#[derive(Debug, Clone)]
enum Exchange<A> {
    /// No IO AR.
    Idle(Option<A>),
    /// The card's drive behind the AR's layout.
    Card(CardCycle<A>),
    /// A device without a drive: a loopback ([`Cyclic::looped_back`]).
    Plain(Cyclic, Instant),
}

/// The device, with the application `A` behind its module (the Goodrive350 card's drive by
/// default).
#[derive(Debug, Clone)]
pub struct Device<A = PkwPzdDrive> {
    dcp: Dcp,
    cm: Cm,
    exchange: Exchange<A>,
    /// The AR's AlarmCR (after an abort it stays until the next Connect, to send its ERR).
    alarm: Option<AlarmCr>,
    events: Vec<DeviceEvent>,
    /// Answers to received frames and datagrams, oldest first.
    answers: VecDeque<Transmit>,
    /// Identify answers held for their response delay: when each is due, oldest first.
    delayed: VecDeque<(Instant, Vec<u8>)>,
}

impl<A: IoApplication> Device<A> {
    /// A device with `station` (DCP) and `config` (its GSDML's), and the application behind its
    /// module (`drive`: the Goodrive350 card's), if it has one.
    pub fn new(station: Station, config: DeviceConfig, drive: Option<A>) -> Self {
        let ids = (
            station.vendor_id,
            station.device_id,
            u16::from_be_bytes([station.instance.0, station.instance.1]),
        );
        let mut cm = Cm::new(config, station.mac, ids, &station.type_of_station);
        for (index, bytes) in drive.iter().flat_map(IoApplication::records) {
            cm.set_record((DRIVE_SLOT.0, DRIVE_SLOT.1, index), &bytes);
        }
        Device {
            dcp: Dcp::new(station),
            cm,
            exchange: Exchange::Idle(drive),
            alarm: None,
            events: Vec::new(),
            answers: VecDeque::new(),
            delayed: VecDeque::new(),
        }
    }

    /// The DCP machine (its station and Hello).
    pub fn dcp(&mut self) -> &mut Dcp {
        &mut self.dcp
    }

    /// What the device says about itself now (its name of station and IP change by DCP).
    pub fn station(&self) -> &Station {
        self.dcp.station()
    }

    /// The application (the drive), if the device has one.
    pub fn drive(&self) -> Option<&A> {
        match &self.exchange {
            Exchange::Idle(d) => d.as_ref(),
            Exchange::Card(c) => Some(c.drive()),
            Exchange::Plain(..) => None,
        }
    }

    /// The next event.
    pub fn poll_event(&mut self) -> Option<DeviceEvent> {
        (!self.events.is_empty()).then(|| self.events.remove(0))
    }

    /// Bytes received at `now` on `from`: an Ethernet frame (DCP, cyclic, alarm) or an RPC
    /// datagram. Answers wait in [`Device::poll_transmit`].
    pub fn handle(&mut self, now: Instant, from: Link, bytes: &[u8]) {
        let answer = match from {
            Link::Ethernet => self.handle_frame(now, bytes).map(Transmit::Frame),
            Link::Rpc(peer) => self
                .handle_datagram(now, peer, bytes)
                .map(|pdu| Transmit::Datagram(peer, pdu)),
        };
        self.answers.extend(answer);
    }

    /// The next bytes to send at `now`: answers first, then the device's own datagrams
    /// (ApplicationReady), then alarm and cyclic frames as they fall due.
    pub fn poll_transmit(&mut self, now: Instant) -> Option<Transmit> {
        if let Some(answer) = self.answers.pop_front() {
            return Some(answer);
        }
        if self.delayed.front().is_some_and(|(due, _)| *due <= now) {
            return self
                .delayed
                .pop_front()
                .map(|(_, frame)| Transmit::Frame(frame));
        }
        if let Some((to, pdu)) = self.poll_datagram() {
            return Some(Transmit::Datagram(to, pdu));
        }
        self.poll_frame(now).map(Transmit::Frame)
    }

    /// A received Ethernet frame: DCP's answer, if any (cyclic frames are consumed).
    pub(crate) fn handle_frame(&mut self, now: Instant, frame: &[u8]) -> Option<Vec<u8>> {
        let answer = self.dcp.handle(frame);
        while let Some(e) = self.dcp.poll_event() {
            self.events.push(DeviceEvent::Dcp(e));
        }
        if let Some(answer) = answer {
            let delay = self.dcp.response_delay(frame);
            if delay.as_micros() == 0 {
                return Some(answer);
            }
            // Kept in the order they fall due; a flood of Identify requests holds a few
            // answers at most (a real device answers one at a time).
            if self.delayed.len() >= MAX_HELD_IDENTIFY {
                return None;
            }
            self.delayed.push_back((now + delay, answer));
            self.delayed.make_contiguous().sort_by_key(|(due, _)| *due);
            return None;
        }
        if let Some(alarm) = self.alarm.as_mut() {
            if alarm.handle_frame(now, frame) {
                self.alarm_events(now);
                return None;
            }
        }
        if self.cm.data_valid() {
            match &mut self.exchange {
                Exchange::Card(c) => c.handle(now, frame),
                Exchange::Plain(c, _) => {
                    c.handle(now, frame);
                }
                Exchange::Idle(_) => {}
            }
            self.diagnosis(now);
        }
        None
    }

    /// The application (the drive), to change, if the device has one.
    pub fn drive_mut(&mut self) -> Option<&mut A> {
        match &mut self.exchange {
            Exchange::Idle(d) => d.as_mut(),
            Exchange::Card(c) => Some(c.drive_mut()),
            Exchange::Plain(..) => None,
        }
    }

    /// The drive's diagnosis changes as alarms, while the AR exchanges data.
    fn diagnosis(&mut self, now: Instant) {
        let (Exchange::Card(card), Some(alarm)) = (&mut self.exchange, self.alarm.as_mut()) else {
            return;
        };
        if !self.cm.data_valid() {
            return;
        }
        let config = self.cm.config();
        let idents = config
            .slot(DRIVE_SLOT.0)
            .zip(config.submodule(DRIVE_SLOT.0, DRIVE_SLOT.1))
            .map_or((0, 0), |(slot, sub)| (slot.module_ident, sub.ident));
        while let Some(change) = card.poll_diagnosis() {
            alarm.send(now, fault_alarm(change, idents));
        }
    }

    /// The AlarmCR's events; its end ends the AR.
    fn alarm_events(&mut self, now: Instant) {
        let Some(alarm) = self.alarm.as_mut() else {
            return;
        };
        let mut aborted = false;
        while let Some(event) = alarm.poll_event() {
            aborted |= matches!(event, AlarmEvent::Aborted(_));
            self.events.push(DeviceEvent::Alarm(event));
        }
        if aborted {
            self.cm.abort();
            self.ar_events(now);
        }
    }

    /// A received datagram on UDP 34964: the answer to its sender, if any.
    pub(crate) fn handle_datagram(
        &mut self,
        now: Instant,
        from: Peer,
        pdu: &[u8],
    ) -> Option<Vec<u8>> {
        let answer = self.cm.handle_datagram(now, from, pdu);
        self.ar_events(now);
        answer
    }

    /// A datagram the device sends of its own.
    pub(crate) fn poll_datagram(&mut self) -> Option<(Peer, Vec<u8>)> {
        self.cm.poll_datagram()
    }

    /// The cyclic frame due at `now`, if any.
    pub(crate) fn poll_frame(&mut self, now: Instant) -> Option<Vec<u8>> {
        if let Some(frame) = self.alarm.as_mut().and_then(AlarmCr::poll_frame) {
            return Some(frame);
        }
        if !self.cm.data_valid() {
            return None;
        }
        match &mut self.exchange {
            Exchange::Card(c) => c.poll_transmit(now),
            Exchange::Plain(c, next) => {
                if now < *next {
                    return None;
                }
                *next = now + c.layout().interval;
                let looped = c.looped_back();
                let inputs: Vec<&[u8]> = looped.iter().map(Vec::as_slice).collect();
                Some(c.produce(now, &inputs))
            }
            Exchange::Idle(_) => None,
        }
    }

    /// The next time something is due.
    pub fn poll_timeout(&self) -> Option<Instant> {
        let cyclic = match &self.exchange {
            Exchange::Card(c) if self.cm.data_valid() => Some(c.poll_timeout()),
            Exchange::Plain(c, next) if self.cm.data_valid() => {
                Some(c.poll_timeout().map_or(*next, |w| w.min(*next)))
            }
            _ => None,
        };
        let alarm = self.alarm.as_ref().and_then(AlarmCr::poll_timeout);
        let identify = self.delayed.front().map(|(due, _)| *due);
        [cyclic, self.cm.poll_timeout(), alarm, identify]
            .into_iter()
            .flatten()
            .min()
    }

    /// Time passed to `now`: the watchdog (which aborts the AR), the drive's ramps, the
    /// ApplicationReady's retries, the alarms' retransmissions.
    pub fn handle_timeout(&mut self, now: Instant) {
        self.cm.handle_timeout(now);
        if let Some(alarm) = self.alarm.as_mut() {
            alarm.handle_timeout(now);
            self.alarm_events(now);
        }
        let expired = match &mut self.exchange {
            Exchange::Card(c) if self.cm.data_valid() => c.handle_timeout(now),
            Exchange::Plain(c, _) if self.cm.data_valid() => c.handle_timeout(now),
            _ => false,
        };
        if expired {
            self.cm.abort();
        }
        self.ar_events(now);
        self.diagnosis(now);
    }

    fn ar_events(&mut self, now: Instant) {
        while let Some(event) = self.cm.poll_event() {
            match &event {
                ArEvent::Connected {
                    layout: Some(layout),
                    ..
                } => {
                    self.alarm = self.cm.alarm_cr();
                    self.start(now, layout.clone());
                }
                ArEvent::Released | ArEvent::Aborted => {
                    // A closed AlarmCR may still have its ERR to send; an open one is over.
                    self.alarm = self.alarm.take().filter(AlarmCr::closed);
                    self.stop();
                }
                ArEvent::DataStart => {
                    // The first output frame may take the AR's activity timeout to come.
                    let first = self.cm.activity_timeout();
                    match &mut self.exchange {
                        Exchange::Card(c) => c.arm(now, first),
                        Exchange::Plain(c, _) => c.arm(now, first),
                        Exchange::Idle(_) => {}
                    }
                }
                ArEvent::RecordWritten { index, data, .. } => self.write_parameters(*index, data),
                _ => {}
            }
            self.events.push(DeviceEvent::Ar(event));
        }
    }

    fn start(&mut self, now: Instant, layout: CrLayout) {
        self.stop();
        let drive_fits = layout
            .inputs
            .iter()
            .chain(&layout.outputs)
            .any(|o| (o.slot, o.subslot) == DRIVE_SLOT && o.len == IMAGE_BYTES);
        let idle = std::mem::replace(&mut self.exchange, Exchange::Idle(None));
        self.exchange = match idle {
            Exchange::Idle(Some(drive)) if drive_fits => {
                Exchange::Card(CardCycle::new(layout, drive, now))
            }
            Exchange::Idle(drive) if drive.is_some() => {
                // The expected configuration has no drive module: keep the drive for the
                // next AR.
                self.exchange = Exchange::Idle(drive);
                return;
            }
            _ => Exchange::Plain(Cyclic::new(layout), now),
        };
    }

    fn stop(&mut self) {
        let old = std::mem::replace(&mut self.exchange, Exchange::Idle(None));
        self.exchange = match old {
            Exchange::Card(c) => Exchange::Idle(Some(c.into_drive())),
            Exchange::Plain(..) => Exchange::Idle(None),
            idle => idle,
        };
    }

    /// A write of a record of the module goes to the application.
    fn write_parameters(&mut self, index: u16, data: &[u8]) {
        if let Some(drive) = self.drive_mut() {
            drive.write_record(index, data);
        }
    }
}

impl Device<PkwPzdDrive> {
    /// A test's hook: the drive trips with `fault` (P07.27's type) at `now`, as an
    /// overcurrent would; in data exchange the controller gets a Diagnosis alarm.
    pub fn inject_fault(&mut self, now: Instant, fault: u16) {
        if let Some(drive) = self.drive_mut() {
            drive.inject_fault(now, fault);
        }
        self.diagnosis(now);
    }

    /// A test's hook: the injected fault's cause is gone; the controller's fault reset (CW
    /// command 7) now clears it, and the controller gets a Diagnosis disappears alarm.
    pub fn remove_fault_cause(&mut self) {
        if let Some(drive) = self.drive_mut() {
            drive.remove_fault_cause();
        }
    }
}

/// How many Identify answers a device holds for their response delay at once.
const MAX_HELD_IDENTIFY: usize = 8;

/// How often a driver looks at the sockets when nothing is due.
pub const IDLE_POLL: Duration = Duration::from_millis(1);

#[cfg(test)]
mod tests;

#[cfg(test)]
mod hostile;
