//! The RD11 inverter behind its option CANopen card, as the card's manual describes it: the
//! 0x3000 address group at 2030h (frequency command 0x3000, control command 0x3001, status
//! 0x3002, fault code 0x3003; Tables 3.9/3.10), C-group monitoring at 2021h (C00.nn is sub
//! nn + 1), parameter groups at 2000h + group with the power-down-save indices 20F0h/20A0h
//! (§3.1.3), and an emergency per fault code of Table 3.12 (§3.1.7).
//!
//! Choices where the manual is silent:
//! - The drive obeys control commands only with F01.01 = 3 (option card) and takes the frequency
//!   command only with F01.02 = 10 (Table 3.14), as a real drive does. Both start at 0 (keypad);
//!   F01.10, the maximum frequency, starts at 50.00 Hz. Other parameters start at 0.
//! - Acceleration and deceleration take 10.0 s from 0 to F01.10 (the manual names no ramp
//!   parameter).
//! - The drive is a 220 V one (C00.26 = 220, the manual's example): input 220.0 V, DC bus
//!   311.0 V, motor voltage V/f up to 220.0 V at 50 Hz; torque, power and module temperature move
//!   with the load in a simple way.
//! - The card samples the inverter every 100 ms (status bit 14, the heartbeat, alternates
//!   then); bit 7 (ready) is set unless a fault is
//!   active; bits 5, 6 and 15 (GPRS lock, warning, braking) stay 0.
//! - A fault's emergency carries the fault code as its error code (the manual: "the same as the
//!   manufacturer's assigned error code") and in bytes 3–4, with error register bits 0 and 7.
//! - Commands 3 and 4 (jog) run at 5.00 Hz; 8 (run ban) stops the drive and refuses to run
//!   until 9 (run allow).

use edsgen_host::vbus::BusDevice;
use edsgen_runtime::node::{error_register, InvalidNodeId};
use edsgen_runtime::{CanFrame, Duration, Event, Instant, Node};

use super::vfd::{Ratings, Run, Vfd};
use super::{earliest, read_u16, replace_u16, write_u16};
use crate::cards::rd11::Od;

/// The 0x3000 address group: 2030h, sub-index = low byte of the address + 1.
const GROUP_3000: u16 = 0x2030;
/// 0x3000: frequency command, 0.01 Hz.
const FREQUENCY_COMMAND: u8 = 1;
/// 0x3001: control command (Table 3.10).
const CONTROL_COMMAND: u8 = 2;
/// 0x3002: operation status (Table 3.10).
const STATUS: u8 = 3;
/// 0x3003: fault code (Table 3.12).
const FAULT_CODE: u8 = 4;
/// C-group monitoring: C00.nn is 2021h sub nn + 1.
const MONITORING: u16 = 0x2021;
/// Function-code group F01 (2000h + 1): F01.nn is sub nn + 1.
const GROUP_F01: u16 = 0x2001;
/// F01.01 run command source: 3 is the option card.
const RUN_SOURCE: u8 = 0x02;
/// F01.02 frequency source: 10 is the option card.
const FREQUENCY_SOURCE: u8 = 0x03;
/// F01.10 maximum output frequency, 0.01 Hz.
const MAX_FREQUENCY: u8 = 0x0B;

/// How often the card samples the inverter's values (and status bit 14 alternates): the
/// period of Table 3.9's "asynchronous timing transfer", so the TPDOs carry fresh values at
/// their event timer and change-of-state sends no more often.
const SAMPLE_PERIOD: Duration = Duration::from_millis(100);

/// The simulated RD11 inverter: its card's device node and the drive behind it. Runs on any bus
/// as a [`BusDevice`].
pub struct Rd11 {
    node: Node<Od>,
    vfd: Vfd,
    /// An active fault's code (Table 3.12) and whether its cause is still present.
    fault: Option<u16>,
    /// Run ban (command 8) in force.
    banned: bool,
    heartbeat_bit: bool,
    next_sample: Instant,
}

impl Rd11 {
    /// An inverter that has just powered up with its card at `node_id`.
    pub fn new(node_id: u8, now: Instant) -> Result<Self, InvalidNodeId> {
        let mut node = Node::new(Od::new(node_id), node_id, now)?;
        write_u16(node.od_mut(), GROUP_F01, MAX_FREQUENCY, 5000);
        write_u16(node.od_mut(), MONITORING, 27, 220); // C00.26 rated voltage
        let ratings = Ratings {
            max_frequency: 5000,
            rated_voltage: 2200,
            rated_frequency: 5000,
            bus_voltage: 3110,
            pole_pairs: 2,
        };
        let mut rd11 = Rd11 {
            node,
            vfd: Vfd::new(ratings, now),
            fault: None,
            banned: false,
            heartbeat_bit: false,
            next_sample: now + SAMPLE_PERIOD,
        };
        rd11.publish();
        Ok(rd11)
    }

    /// The card's device node.
    pub fn node(&self) -> &Node<Od> {
        &self.node
    }

    /// The card's device node, to change.
    pub fn node_mut(&mut self) -> &mut Node<Od> {
        &mut self.node
    }

    /// The drive's motion and electrical state.
    pub fn vfd(&self) -> &Vfd {
        &self.vfd
    }

    /// The inverter trips with a fault code of Table 3.12 (0x0005 is overcurrent in
    /// acceleration): the output is cut, 0x3003 holds the code, the card sends its emergency.
    pub fn inject_fault(&mut self, now: Instant, code: u16) {
        self.vfd.trip(now, code);
        self.fault = Some(code);
        let [lo, hi] = code.to_le_bytes();
        self.node.raise_error(
            code,
            error_register::GENERIC | error_register::MANUFACTURER,
            [lo, hi, 0, 0, 0],
        );
        self.publish();
    }

    /// The fault's cause has gone: a fault reset (command 7) now clears it.
    pub fn remove_fault_cause(&mut self) {
        self.vfd.cause_removed();
    }

    fn process_events(&mut self, now: Instant) {
        while let Some(event) = self.node.poll_event() {
            match event {
                Event::RpdoReceived { .. }
                | Event::Written {
                    index: GROUP_3000, ..
                } => self.apply_commands(now),
                Event::Written { index, sub } => self.save_at_power_down(now, index, sub),
                _ => {}
            }
        }
    }

    /// A write through 20F0h–20FFh (F00–F15) or 20A0h–20AFh (F16–F31) sets the parameter too.
    fn save_at_power_down(&mut self, now: Instant, index: u16, sub: u8) {
        let group = match index {
            0x20F0..=0x20FF => index - 0x20F0,
            0x20A0..=0x20AF => index - 0x20A0 + 16,
            _ => return,
        };
        // The power-down-save entries are write-only: the value written is in the node's
        // dictionary only as the last write, which the generated image keeps like any other.
        let value = read_u16(self.node.od(), index, sub);
        write_u16(self.node.od_mut(), 0x2000 + group, sub, value);
        if group == 1 {
            self.apply_commands(now);
        }
    }

    /// The frequency and control commands of the 0x3000 group.
    fn apply_commands(&mut self, now: Instant) {
        let od = self.node.od();
        let run_from_card = read_u16(od, GROUP_F01, RUN_SOURCE) == 3;
        let frequency_from_card = read_u16(od, GROUP_F01, FREQUENCY_SOURCE) == 10;
        let max_frequency = read_u16(od, GROUP_F01, MAX_FREQUENCY);
        let frequency = read_u16(od, GROUP_3000, FREQUENCY_COMMAND);
        let command = read_u16(od, GROUP_3000, CONTROL_COMMAND);
        if frequency_from_card && frequency <= max_frequency {
            self.vfd.set_reference(now, u32::from(frequency));
        }
        if run_from_card {
            match command {
                1 | 2 if !self.banned => {
                    let run = if command == 1 {
                        Run::Forward
                    } else {
                        Run::Reverse
                    };
                    self.vfd.command(now, run);
                }
                3 | 4 if !self.banned => {
                    self.vfd.set_reference(now, 500);
                    let run = if command == 3 {
                        Run::Forward
                    } else {
                        Run::Reverse
                    };
                    self.vfd.command(now, run);
                }
                5 => self.vfd.command(now, Run::Stop),
                6 => self.vfd.coast(),
                7 => self.reset_fault(),
                8 => {
                    self.banned = true;
                    self.vfd.command(now, Run::Stop);
                }
                9 => self.banned = false,
                _ => {}
            }
        }
        self.publish();
    }

    fn reset_fault(&mut self) {
        if self.vfd.reset_fault().is_some() {
            if let Some(code) = self.fault.take() {
                self.node.clear_error(code);
            }
        }
    }

    /// The operation status of Table 3.10.
    fn status(&self) -> u16 {
        let vfd = &self.vfd;
        let bits = [
            (0, vfd.running()),
            (1, vfd.accelerating()),
            (2, vfd.decelerating()),
            (3, vfd.output_frequency() < 0 || vfd.run() == Run::Reverse),
            (4, self.fault.is_some()),
            (7, self.fault.is_none()),
            (14, self.heartbeat_bit),
        ];
        bits.iter()
            .filter(|(_, set)| *set)
            .fold(0, |word, (bit, _)| word | 1 << bit)
    }

    /// Writes the status, fault code and C-group values into the dictionary.
    fn publish(&mut self) {
        let vfd = &self.vfd;
        let frequency = vfd.output_frequency().unsigned_abs();
        let current = vfd.output_current();
        let torque = if frequency == 0 {
            0
        } else {
            300 + if vfd.accelerating() { 500 } else { 0 }
        };
        // C00.nn = value (units of Table 3.9).
        let monitoring = [
            (0, vfd.reference()),
            (1, frequency),
            (2, current),
            (3, 2200),
            (4, vfd.output_voltage()),
            (5, vfd.speed_rpm().unsigned_abs()),
            (7, torque),
            (10, torque * frequency / 5000),
            (11, vfd.bus_voltage()),
            (12, 250 + current / 2),
        ];
        let status = self.status();
        let fault = self.fault.unwrap_or(0);
        let od = self.node.od_mut();
        for (number, value) in monitoring {
            replace_u16(od, MONITORING, number + 1, value as u16);
        }
        replace_u16(od, GROUP_3000, STATUS, status);
        replace_u16(od, GROUP_3000, FAULT_CODE, fault);
    }
}

impl BusDevice for Rd11 {
    fn handle_frame(&mut self, now: Instant, frame: &CanFrame) {
        self.node.handle_frame(now, frame);
        self.process_events(now);
    }

    fn poll_transmit(&mut self, now: Instant) -> Option<CanFrame> {
        self.node.poll_transmit(now)
    }

    fn poll_timeout(&self) -> Option<Instant> {
        earliest(self.node.poll_timeout(), Some(self.next_sample))
    }

    fn handle_timeout(&mut self, now: Instant) {
        self.node.handle_timeout(now);
        self.process_events(now);
        if self.next_sample <= now {
            self.heartbeat_bit = !self.heartbeat_bit;
            self.next_sample = now + SAMPLE_PERIOD;
            self.vfd.update(now);
            self.publish();
        }
    }
}
