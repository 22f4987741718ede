//! The INVT Goodrive350 with its EC-TX105 CANopen card, as the card's manual (chapter 3)
//! describes it: PDO1 reads and writes drive parameters (§3.5.2), PDO2–PDO4 carry the control
//! word and settings in and the status word and returned values out (§3.5.3–§3.5.6), a fault
//! sends an EMCY with the 5-byte VFD error code (§3.4.8), and SDO reaches the same objects
//! (2000h/2001h monitoring, 2100h/2101h control).
//!
//! Choices where the manual is silent or disagrees with itself:
//! - The drive obeys the control word only with P00.01 = 2 (communication) and P00.02 = 1
//!   (CANopen), and takes a setting of function 1 as its frequency reference only with
//!   P00.06 = 9, as §3.5.3's example requires; otherwise they are ignored, as on a real drive.
//! - Status word bits 13–14 (run/stop mode) stay 0: the manual's own example frame
//!   (`283: 01 01 88 13 7C 01 00 00`, §3.5.4) shows 0101h for a drive under communication
//!   control, where Table 3-18 would give 4101h. The simulation follows the frame.
//! - Setting functions other than 1 (set frequency) and returned-value functions other than
//!   0–5, 8, 10 and 11 are accepted and stored, and act as 0 (no function).
//! - Jogging (commands 3 and 4) runs at 5.00 Hz; command 8 stops it.
//! - PDO1 requests are served as [`pdo1`] describes.
//! - Fault types map to emergency codes as §3.4.8's example does for OUT1–OUT3 (3000h, voltage);
//!   31 (E-CAN) and 58 (ESCAN) to 8100h (communication); every other type to FF00h (device
//!   specific) with the generic bit.

use edsgen_host::vbus::BusDevice;
use edsgen_runtime::node::{error_register, InvalidNodeId};
use edsgen_runtime::{CanFrame, Event, Instant, Node};

use super::vfd::{Modify, ParameterSpec, Parameters, Ratings, Run, Vfd};
use super::{earliest, pdo1, read_u16, replace_u16};
use crate::cards::goodrive350::Od;

/// The card's control and monitoring objects (Appendix A, Tables 3-19/3-20).
mod objects {
    /// 2000h: response code (00), error code (01), response data (02), returned values (03–0D).
    pub const MONITORING: u16 = 0x2000;
    /// 2001h: the status word.
    pub const STATUS_WORD: u16 = 0x2001;
    /// 2100h: request code (00), parameter address (01), requested data (02), settings (03–0D).
    pub const CONTROL: u16 = 0x2100;
    /// 2101h: the control word.
    pub const CONTROL_WORD: u16 = 0x2101;
    /// The sub-index of setting 1 in 2100h and of returned value 1 in 2000h.
    pub const FIRST_PZD: u8 = 3;
    /// Settings and returned values: 11 of each.
    pub const PZD_COUNT: u8 = 11;
}

/// Parameter addresses (group in the high byte, number in the low byte: P15.13 is 0F0Dh).
pub mod parameter {
    /// P00.01 channel of running commands: 0 keypad, 1 terminal, 2 communication.
    pub const RUN_COMMAND_CHANNEL: u16 = 0x0001;
    /// P00.02 communication channel of running commands: 1 PROFIBUS/CANopen/DeviceNet.
    pub const COMMUNICATION_CHANNEL: u16 = 0x0002;
    /// P00.03 maximum output frequency, 0.01 Hz.
    pub const MAX_FREQUENCY: u16 = 0x0003;
    /// P00.06 frequency A command setting mode: 9 PROFIBUS/CANopen/DeviceNet.
    pub const FREQUENCY_A_SOURCE: u16 = 0x0006;
    /// P00.11 acceleration time 1, 0.1 s.
    pub const ACCELERATION_TIME: u16 = 0x000B;
    /// P00.12 deceleration time 1, 0.1 s.
    pub const DECELERATION_TIME: u16 = 0x000C;
    /// P07.27 type of present fault.
    pub const PRESENT_FAULT: u16 = 0x071B;
    /// P07.28 type of last fault.
    pub const LAST_FAULT: u16 = 0x071C;
    /// P15.01 module address.
    pub const MODULE_ADDRESS: u16 = 0x0F01;
    /// P15.02 received PZD2 (setting 1) function; P15.03–P15.12 follow for settings 2–11.
    pub const RECEIVED_PZD2: u16 = 0x0F02;
    /// P15.13 transmitted PZD2 (returned value 1) function; P15.14–P15.23 follow.
    pub const TRANSMITTED_PZD2: u16 = 0x0F0D;
}

/// The parameters the simulation keeps: Appendix C's communication parameters and the PZD
/// functions of §2/§3 with their ranges; P00.03/P00.11/P00.12 with the drive's usual defaults
/// (50.00 Hz, 10.0 s), which the card manual does not list.
static PARAMETERS: [ParameterSpec; 31] = {
    const fn p(address: u16, default: u16, min: u16, max: u16, modify: Modify) -> ParameterSpec {
        ParameterSpec {
            address,
            default,
            min,
            max,
            modify,
        }
    }
    use Modify::*;
    [
        p(0x0001, 0, 0, 2, Stopped),
        p(0x0002, 0, 0, 5, Stopped),
        p(0x0003, 5000, 1000, 63000, Stopped),
        p(0x0006, 0, 0, 15, Stopped),
        p(0x0007, 2, 0, 15, Stopped),
        p(0x000B, 100, 0, 36000, Always),
        p(0x000C, 100, 0, 36000, Always),
        p(0x071B, 0, 0, 0xFFFF, ReadOnly),
        p(0x071C, 0, 0, 0xFFFF, ReadOnly),
        p(0x0F01, 2, 0, 127, Stopped),
        // P15.02–P15.12: received PZD2–PZD12 functions (0–18).
        p(0x0F02, 0, 0, 18, Always),
        p(0x0F03, 0, 0, 18, Always),
        p(0x0F04, 0, 0, 18, Always),
        p(0x0F05, 0, 0, 18, Always),
        p(0x0F06, 0, 0, 18, Always),
        p(0x0F07, 0, 0, 18, Always),
        p(0x0F08, 0, 0, 18, Always),
        p(0x0F09, 0, 0, 18, Always),
        p(0x0F0A, 0, 0, 18, Always),
        p(0x0F0B, 0, 0, 18, Always),
        p(0x0F0C, 0, 0, 18, Always),
        // P15.13–P15.23: transmitted PZD2–PZD12 functions (0–26).
        p(0x0F0D, 0, 0, 26, Always),
        p(0x0F0E, 0, 0, 26, Always),
        p(0x0F0F, 0, 0, 26, Always),
        p(0x0F10, 0, 0, 26, Always),
        p(0x0F11, 0, 0, 26, Always),
        p(0x0F12, 0, 0, 26, Always),
        p(0x0F13, 0, 0, 26, Always),
        p(0x0F14, 0, 0, 26, Always),
        p(0x0F15, 0, 0, 26, Always),
        p(0x0F16, 0, 0, 26, Always),
    ]
};

/// The simulated drive and its card: a device node serving the generated Goodrive350
/// dictionary, and the drive behind it. Runs on any bus as a [`BusDevice`].
pub struct Goodrive350 {
    node: Node<Od>,
    parameters: Parameters,
    vfd: Vfd,
    /// The emergency code of the active fault, to clear on reset.
    fault_emcy: Option<u16>,
}

impl Goodrive350 {
    /// A drive that has just powered up with its card at `node_id`.
    pub fn new(node_id: u8, now: Instant) -> Result<Self, InvalidNodeId> {
        let node = Node::new(Od::new(node_id), node_id, now)?;
        let parameters = Parameters::new(&PARAMETERS);
        let ratings = Ratings {
            max_frequency: u32::from(parameters.get(parameter::MAX_FREQUENCY).unwrap_or(5000)),
            rated_voltage: 380,
            rated_frequency: 5000,
            bus_voltage: 5400,
            pole_pairs: 2,
        };
        let mut drive = Goodrive350 {
            node,
            parameters,
            vfd: Vfd::new(ratings, now),
            fault_emcy: None,
        };
        drive.publish();
        Ok(drive)
    }

    /// The card's device node.
    pub fn node(&self) -> &Node<Od> {
        &self.node
    }

    /// The card's device node, to change.
    pub fn node_mut(&mut self) -> &mut Node<Od> {
        &mut self.node
    }

    /// A parameter's value (`None` if the simulation has no parameter there).
    pub fn parameter(&self, address: u16) -> Option<u16> {
        self.parameters.get(address)
    }

    /// The drive's motion and electrical state.
    pub fn vfd(&self) -> &Vfd {
        &self.vfd
    }

    /// A fault of type `fault` (P07.27's numbering: 1 is OUT1) trips the drive: the output is
    /// cut, P07.27 records it, and the card sends its emergency.
    pub fn inject_fault(&mut self, now: Instant, fault: u8) {
        self.vfd.trip(now, u16::from(fault));
        self.parameters
            .record(parameter::PRESENT_FAULT, u16::from(fault));
        let (code, register) = match fault {
            1..=3 => (0x3000, error_register::VOLTAGE),
            31 | 58 => (0x8100, error_register::COMMUNICATION),
            _ => (0xFF00, error_register::GENERIC),
        };
        self.node.raise_error(code, register, [fault, 0, 0, 0, 0]);
        self.fault_emcy = Some(code);
        self.publish();
    }

    /// The fault's cause has gone: a fault reset (control word command 7) now clears it.
    pub fn remove_fault_cause(&mut self) {
        self.vfd.cause_removed();
    }

    /// Handles the node's events: PDO1 requests, control word and settings.
    fn process_events(&mut self, now: Instant) {
        while let Some(event) = self.node.poll_event() {
            match event {
                Event::RpdoReceived { pdo: 0 } => self.parameter_request(now),
                Event::RpdoReceived { pdo: 1..=3 } => self.apply_control(now),
                Event::Written {
                    index: objects::CONTROL | objects::CONTROL_WORD,
                    sub,
                } if sub >= objects::FIRST_PZD || sub == 0 => self.apply_control(now),
                _ => {}
            }
        }
    }

    /// §3.5.2: a PDO1 request answered on PDO1 Tx.
    fn parameter_request(&mut self, now: Instant) {
        let drive = pdo1::DriveState {
            running: self.vfd.running(),
            faulted: self.vfd.fault().is_some(),
        };
        if pdo1::serve(self.node.od_mut(), &mut self.parameters, drive) {
            self.node.trigger_tpdo(0);
        }
        // A write may have changed the ramps or the PZD functions.
        self.apply_control(now);
    }

    /// §3.5.3: the control word (2101h:00) and settings (2100h:03–0D).
    fn apply_control(&mut self, now: Instant) {
        let od = self.node.od();
        let control_word = read_u16(od, objects::CONTROL_WORD, 0);
        let settings: Vec<u16> = (0..objects::PZD_COUNT)
            .map(|n| read_u16(od, objects::CONTROL, objects::FIRST_PZD + n))
            .collect();
        let p = |address| self.parameters.get(address).unwrap_or(0);
        let bus_controls_run =
            p(parameter::RUN_COMMAND_CHANNEL) == 2 && p(parameter::COMMUNICATION_CHANNEL) == 1;
        let bus_sets_frequency = p(parameter::FREQUENCY_A_SOURCE) == 9;
        let max_frequency = p(parameter::MAX_FREQUENCY);
        let (accel, decel) = (
            p(parameter::ACCELERATION_TIME),
            p(parameter::DECELERATION_TIME),
        );
        self.vfd.set_ramp_times(now, accel, decel);
        for (n, setting) in settings.iter().enumerate() {
            let function = p(parameter::RECEIVED_PZD2 + n as u16);
            // Function 1, set frequency (0–Fmax): out of range is ignored, the others still apply.
            if function == 1 && bus_sets_frequency && *setting <= max_frequency {
                self.vfd.set_reference(now, u32::from(*setting));
            }
        }
        if bus_controls_run {
            match control_word & 0x00FF {
                1 => self.vfd.command(now, Run::Forward),
                2 => self.vfd.command(now, Run::Reverse),
                3 | 4 => {
                    self.vfd.set_reference(now, 500);
                    let run = if control_word & 0xFF == 3 {
                        Run::Forward
                    } else {
                        Run::Reverse
                    };
                    self.vfd.command(now, run);
                }
                5 | 8 => self.vfd.command(now, Run::Stop),
                6 => self.vfd.coast(),
                7 => self.reset_fault(),
                _ => {}
            }
        }
        self.publish();
    }

    fn reset_fault(&mut self) {
        if let Some(fault) = self.vfd.reset_fault() {
            self.parameters.record(parameter::LAST_FAULT, fault);
            self.parameters.record(parameter::PRESENT_FAULT, 0);
            if let Some(code) = self.fault_emcy.take() {
                self.node.clear_error(code);
            }
        }
    }

    /// The status word (Table 3-18), without the run/stop mode bits (see the module comment).
    fn status_word(&self) -> u16 {
        let state = if self.vfd.fault().is_some() {
            4
        } else if self.vfd.output_frequency() > 0 || self.vfd.run() == Run::Forward {
            1
        } else if self.vfd.output_frequency() < 0 || self.vfd.run() == Run::Reverse {
            2
        } else {
            3
        };
        state | 1 << 8 // bit 8: bus voltage established
    }

    /// Writes the status word and returned values into the dictionary, and triggers each of
    /// PDO2–PDO4 Tx (transmission type 254) whose content changed.
    fn publish(&mut self) {
        let status = self.status_word();
        let values: Vec<u16> = (0..u16::from(objects::PZD_COUNT))
            .map(|n| {
                let function = self
                    .parameters
                    .get(parameter::TRANSMITTED_PZD2 + n)
                    .unwrap_or(0);
                returned_value(&self.vfd, function)
            })
            .collect();
        let od = self.node.od_mut();
        let mut changed = [false; 3];
        changed[0] |= replace_u16(od, objects::STATUS_WORD, 0, status);
        for (n, value) in values.iter().enumerate() {
            let pdo = (n + 1) / 4; // returned values 1–3 on PDO2, 4–7 on PDO3, 8–11 on PDO4
            changed[pdo] |= replace_u16(
                od,
                objects::MONITORING,
                objects::FIRST_PZD + n as u8,
                *value,
            );
        }
        for (n, changed) in changed.iter().enumerate() {
            if *changed {
                self.node.trigger_tpdo(n + 1);
            }
        }
    }
}

impl BusDevice for Goodrive350 {
    fn handle_frame(&mut self, now: Instant, frame: &CanFrame) {
        self.node.handle_frame(now, frame);
        self.process_events(now);
    }

    fn poll_transmit(&mut self, now: Instant) -> Option<CanFrame> {
        self.node.poll_transmit(now)
    }

    fn poll_timeout(&self) -> Option<Instant> {
        earliest(self.node.poll_timeout(), self.vfd.next_update())
    }

    fn handle_timeout(&mut self, now: Instant) {
        self.node.handle_timeout(now);
        self.process_events(now);
        if self.vfd.next_update().is_some_and(|at| at <= now) {
            self.vfd.update(now);
            self.publish();
        }
    }
}
/// A returned value by its function: what a transmitted PZD carries (P15.13–P15.23 and
/// P16.43–P16.53, Table 2-8 of the PROFIBUS/PROFINET manual; the CANopen card's §2
/// "transmitted PZD"). One table for every Goodrive350 card.
pub(crate) fn returned_value(vfd: &Vfd, function: u16) -> u16 {
    let value = match function {
        1 | 10 => vfd.output_frequency().unsigned_abs(),
        2 => vfd.reference(),
        3 => vfd.bus_voltage(),
        4 => vfd.output_voltage(),
        5 => vfd.output_current(),
        8 => vfd.speed_rpm().unsigned_abs(),
        11 => u32::from(vfd.fault().unwrap_or(0)),
        _ => 0,
    };
    value as u16
}
