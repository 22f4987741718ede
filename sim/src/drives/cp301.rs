//! The CP301 card in an SA3/SE3/SF3 inverter, as its manual describes it: CiA 402 velocity mode
//! (§5.3, §8.2) run by the runtime's [`Drive`], the monitor array 2D02h (§6.3), and an emergency
//! per inverter alarm with the CANopen error code of §7's table, also in 603Fh.
//!
//! Choices where the manual is silent:
//! - The ramp times refer to 1500 rpm (parameter 01-09, P.20, at 50 Hz on a 4-pole motor; the
//!   card manual does not give its default), and the output voltage is V/f with 380 V there.
//! - Of 2D02h, only sub 6 (output voltage, Modbus 1005h) is named by the manual; subs 1–5 stay 0.
//! - The error register of an alarm follows its code's class (CiA 301): 2xxxh current,
//!   3xxxh voltage, 4xxxh temperature, 81xxh communication, FFxxh manufacturer-specific; the
//!   others set the generic bit only.
//! - On heartbeat loss (a consumer configured in 1016h) the card sends EMCY 8130h (the runtime's
//!   node does, until the heartbeat returns) and the drive acts as 6007h says.

use edsgen_host::vbus::BusDevice;
use edsgen_runtime::cia402::{Drive, DriveConfig, State};
use edsgen_runtime::node::{error_register, InvalidNodeId};
use edsgen_runtime::{CanFrame, Event, Instant, Node};

use super::{earliest, write_u16};
use crate::cards::cp301::Od;

/// The inverter alarms of §7 with their CANopen error codes.
pub static ALARMS: [(&str, u16); 48] = [
    ("OC1", 0x2213),
    ("OC2", 0x2214),
    ("OC3", 0x2213),
    ("OC0", 0x2310),
    ("OV1", 0x3210),
    ("OV2", 0x3210),
    ("OV3", 0x3210),
    ("OV0", 0x3210),
    ("ThT", 0x4300),
    ("ThN", 0x4000),
    ("FAN", 0xFF00),
    ("OhT", 0x7120),
    ("OPT", 0x7500),
    ("EEP", 0x5530),
    ("PID", 0x7300),
    ("CPU", 0x6000),
    ("OLS", 0x8311),
    ("SCP", 0x2320),
    ("NTC", 0x4310),
    ("NTC2", 0x4310),
    ("NTC3", 0x4310),
    ("NTC4", 0x4310),
    ("NTC5", 0x4310),
    ("NTC6", 0x4310),
    ("NTC7", 0x4310),
    ("NTC8", 0x4310),
    ("OL2", 0x8311),
    ("BE", 0x7110),
    ("IPF", 0x5100),
    ("CPR", 0x6010),
    ("AEr", 0x7110),
    ("PG1", 0x7301),
    ("PG2", 0x7301),
    ("PG3", 0x7301),
    ("PTC", 0x4000),
    ("BEB", 0xFF01),
    ("DV1", 0x7301),
    ("DV2", 0x7301),
    ("DV3", 0x7301),
    ("DV4", 0x7301),
    ("EbE", 0xFF02),
    ("GF", 0x2330),
    ("SAF", 0xFF03),
    ("LF", 0x2300),
    ("hDC", 0xFF04),
    ("ADE", 0x5210),
    ("rAE", 0x7110),
    ("CbE", 0x8130),
];

/// The error register bits of an emergency code, by its class.
fn register_of(code: u16) -> u8 {
    match code >> 12 {
        0x2 => error_register::CURRENT,
        0x3 => error_register::VOLTAGE,
        0x4 => error_register::TEMPERATURE,
        0x8 if code >> 8 == 0x81 => error_register::COMMUNICATION,
        0xF if code >> 8 == 0xFF => error_register::MANUFACTURER,
        _ => error_register::GENERIC,
    }
}

/// The speed the ramp times refer to, rpm.
const MAX_SPEED: u16 = 1500;
/// The output voltage at [`MAX_SPEED`], V.
const RATED_VOLTAGE: u32 = 380;

/// The simulated CP301 drive: its device node and the CiA 402 drive behind it. Runs on any bus
/// as a [`BusDevice`].
pub struct Cp301 {
    node: Node<Od>,
    drive: Drive,
    /// The active alarm's emergency code.
    alarm: Option<u16>,
}

/// Why an alarm was not raised.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UnknownAlarm(pub String);

impl Cp301 {
    /// A drive that has just powered up with its card at `node_id`.
    pub fn new(node_id: u8, now: Instant) -> Result<Self, InvalidNodeId> {
        let node = Node::new(Od::new(node_id), node_id, now)?;
        let mut cp301 = Cp301 {
            node,
            drive: Drive::new(DriveConfig::new(MAX_SPEED), now),
            alarm: None,
        };
        cp301.run_drive(now);
        Ok(cp301)
    }

    /// The card's device node.
    pub fn node(&self) -> &Node<Od> {
        &self.node
    }

    /// The card's device node, to change.
    pub fn node_mut(&mut self) -> &mut Node<Od> {
        &mut self.node
    }

    /// The CiA 402 drive.
    pub fn drive(&self) -> &Drive {
        &self.drive
    }

    /// The inverter raises an alarm of §7 (by its code, `"OC1"`): the drive's fault reaction
    /// runs, 603Fh and the emergency carry the alarm's CANopen error code.
    pub fn raise_alarm(&mut self, now: Instant, alarm: &str) -> Result<(), UnknownAlarm> {
        let code = ALARMS
            .iter()
            .find(|(name, _)| *name == alarm)
            .map(|(_, code)| *code)
            .ok_or_else(|| UnknownAlarm(alarm.to_string()))?;
        self.fault(now, code);
        Ok(())
    }

    fn fault(&mut self, now: Instant, code: u16) {
        if self.alarm.is_some() {
            return;
        }
        self.drive.raise_fault(now);
        self.node.raise_error(code, register_of(code), [0; 5]);
        self.alarm = Some(code);
        self.run_drive(now);
    }

    /// The master's heartbeat was lost (the node raised EMCY 8130h, cleared when the heartbeat
    /// returns): the drive acts as 6007h says. A fault (6007h = 1) has no cause left to
    /// remove, so a fault reset clears it.
    fn connection_lost(&mut self, now: Instant) {
        self.drive.connection_lost(now);
        self.drive.clear_fault();
        self.run_drive(now);
    }

    /// The alarm's cause has gone: a fault reset (6040h bit 7 rising) now clears it.
    pub fn remove_alarm_cause(&mut self) {
        self.drive.clear_fault();
    }

    /// Runs the drive on the dictionary, clears a reset alarm, and refreshes 603Fh and 2D02h.
    fn run_drive(&mut self, now: Instant) {
        let od = self.node.od_mut();
        // The dictionary is generated from the CP301's EDS, whose 6040h–6061h the drive reads
        // and writes with their types: a refusal here is a bug in the simulation.
        let ran = self.drive.run_on(od, now);
        debug_assert_eq!(ran, Ok(()));
        if let Some(code) = self.alarm {
            if !matches!(
                self.drive.state(),
                State::Fault | State::FaultReactionActive
            ) {
                self.alarm = None;
                self.node.clear_error(code);
            }
        }
        let error_code = self.alarm.unwrap_or(0);
        let speed = u32::from(self.drive.velocity_actual().unsigned_abs());
        let voltage = RATED_VOLTAGE * speed.min(u32::from(MAX_SPEED)) / u32::from(MAX_SPEED);
        let od = self.node.od_mut();
        write_u16(od, 0x603F, 0, error_code);
        write_u16(od, 0x2D02, 6, voltage as u16);
    }

    fn process_events(&mut self, now: Instant) {
        while let Some(event) = self.node.poll_event() {
            match event {
                Event::Written {
                    index: 0x6000..=0x67FF,
                    ..
                }
                | Event::RpdoReceived { .. }
                | Event::Reset(_) => self.run_drive(now),
                Event::HeartbeatLost { .. } => self.connection_lost(now),
                _ => {}
            }
        }
    }
}

impl BusDevice for Cp301 {
    fn handle_frame(&mut self, now: Instant, frame: &CanFrame) {
        self.node.handle_frame(now, frame);
        self.process_events(now);
    }

    fn poll_transmit(&mut self, now: Instant) -> Option<CanFrame> {
        self.node.poll_transmit(now)
    }

    fn poll_timeout(&self) -> Option<Instant> {
        earliest(self.node.poll_timeout(), self.drive.next_update())
    }

    fn handle_timeout(&mut self, now: Instant) {
        self.node.handle_timeout(now);
        self.process_events(now);
        if self.drive.next_update().is_some_and(|at| at <= now) {
            self.run_drive(now);
        }
    }
}
