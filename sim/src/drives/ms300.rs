//! The Delta MS300 with its built-in CANopen, as chapter 15 of its manual describes it: three
//! control modes chosen by Pr. 09-40 and Pr. 09-30 (§15-3-1): DS402 velocity mode (6040h/6042h,
//! run by the runtime's [`Drive`]), Delta's old definition (2020h control, 2021h status) and its
//! new one (2060h control, 2061h status); and the fault codes of §15-5 as emergencies with their
//! CANopen code and error-register bit.
//!
//! Choices where the manual is silent or disagrees with itself:
//! - Commands are obeyed only with Pr. 00-21 = 3 and frequencies taken only with Pr. 00-20 = 6, in
//!   every mode, as the set-up steps of §15-3-2-1, §15-3-3-1 and §15-3-4-1 require.
//! - Pr. 09-40 = 1 selects DS402, its factory setting (§15-3-1; step 4 of §15-3-2-1 says 0).
//! - 2020h:01 bits 1–0: §15-3-3-2 runs with 0002h and stops with 0001h, where the table of §15-4
//!   calls 10b "disable"; the procedure is followed.
//! - 2060h:01 (new definition): the drive runs with Power (bit 7) and Ack (bit 0) set, in
//!   reverse with Dir (bit 1); Halt (bit 3) stops on the ramp, QStop (bit 6) cuts the output,
//!   RST (bit 15) resets a fault. §15-3-4-2's "008H for servo on" is taken as 0080h (bit 7).
//! - Delta frequencies are in 0.1 Hz (§15-3-3-2, §15-3-4-2); 2021h reports frequencies in
//!   0.01 Hz, current in 0.1 A and voltages in 0.1 V (Delta's register units). The motor is a
//!   4-pole 60 Hz one: 1800 rpm at 60.00 Hz, the speed the ramps refer to; 220 V at 60 Hz.
//! - §15-5's fault table as far as the manual text gives it (ocA to ovn): the emergency code and
//!   register bit of each row; 2021h:01's low byte and 603Fh hold the fault. A fault trips the
//!   drive of the mode in force; 2021h and 2061h report the Delta-mode drive, 6041h–6044h the
//!   DS402 one.

use edsgen_host::vbus::BusDevice;
use edsgen_runtime::cia402::{Drive, DriveConfig, State};
use edsgen_runtime::node::InvalidNodeId;
use edsgen_runtime::{CanFrame, Event, Instant, Node};

use super::vfd::{Ratings, Run, Vfd};
use super::{earliest, read_u16, replace_u16};
use crate::cards::ms300::Od;

/// The fault codes of §15-5: display, fault code, error-register bit, CANopen emergency code.
pub static FAULTS: [(&str, u8, u8, u16); 8] = [
    ("ocA", 1, 1, 0x2213),
    ("ocd", 2, 1, 0x2213),
    ("ocn", 3, 1, 0x2214),
    ("GFF", 4, 1, 0x2240),
    ("ocS", 6, 1, 0x2214),
    ("ovA", 7, 2, 0x3210),
    ("ovd", 8, 2, 0x3210),
    ("ovn", 9, 2, 0x3210),
];

/// Parameter group 00 (2000h) and 09 (2009h): sub-index = parameter number + 1.
const GROUP_00: u16 = 0x2000;
const GROUP_09: u16 = 0x2009;
/// Pr. 00-20 frequency source (6 = CANopen), Pr. 00-21 operation source (3 = CANopen).
const FREQUENCY_SOURCE: u8 = 21;
const OPERATION_SOURCE: u8 = 22;
/// Pr. 09-30 Delta definition (0 old, 1 new), Pr. 09-40 control mode (1 DS402, 0 Delta).
const DELTA_DEFINITION: u8 = 31;
const CONTROL_MODE: u8 = 41;
/// Delta's old definition: 2020h control (01 word, 02 frequency, 03 other trigger), 2021h status.
const OLD_CONTROL: u16 = 0x2020;
const OLD_STATUS: u16 = 0x2021;
/// Delta's new definition: 2060h control (01 word, 03 frequency), 2061h status (01 word,
/// 03 output frequency).
const NEW_CONTROL: u16 = 0x2060;
const NEW_STATUS: u16 = 0x2061;

/// The speed the ramp times refer to, rpm (60 Hz, 4 poles).
const MAX_SPEED: u16 = 1800;

/// Which definition of the control objects is in force (§15-3-1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ControlMode {
    /// Pr. 09-40 = 1: CiA 402 (6040h, 6042h).
    Ds402,
    /// Pr. 09-40 = 0, Pr. 09-30 = 0: Delta's old definition (2020h, 2021h).
    DeltaOld,
    /// Pr. 09-40 = 0, Pr. 09-30 = 1: Delta's new definition (2060h, 2061h).
    DeltaNew,
}

/// The simulated MS300: its device node, the CiA 402 drive and the Delta-mode drive behind it.
/// Runs on any bus as a [`BusDevice`].
pub struct Ms300 {
    node: Node<Od>,
    drive: Drive,
    vfd: Vfd,
    /// The active fault: its code and emergency code.
    fault: Option<(u8, u16)>,
}

/// Why a fault was not raised.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UnknownFault(pub String);

impl Ms300 {
    /// A drive that has just powered up at `node_id`.
    pub fn new(node_id: u8, now: Instant) -> Result<Self, InvalidNodeId> {
        let ratings = Ratings {
            max_frequency: 6000,
            rated_voltage: 2200,
            rated_frequency: 6000,
            bus_voltage: 3110,
            pole_pairs: 2,
        };
        let mut ms300 = Ms300 {
            node: Node::new(Od::new(node_id), node_id, now)?,
            drive: Drive::new(DriveConfig::new(MAX_SPEED), now),
            vfd: Vfd::new(ratings, now),
            fault: None,
        };
        ms300.update(now);
        Ok(ms300)
    }

    /// The card's device node.
    pub fn node(&self) -> &Node<Od> {
        &self.node
    }

    /// The control mode Pr. 09-40 and Pr. 09-30 select.
    pub fn control_mode(&self) -> ControlMode {
        let od = self.node.od();
        match (
            read_u16(od, GROUP_09, CONTROL_MODE),
            read_u16(od, GROUP_09, DELTA_DEFINITION),
        ) {
            (1, _) => ControlMode::Ds402,
            (_, 0) => ControlMode::DeltaOld,
            _ => ControlMode::DeltaNew,
        }
    }

    /// The Delta-mode drive (output frequency in 0.01 Hz).
    pub fn vfd(&self) -> &Vfd {
        &self.vfd
    }

    /// The CiA 402 drive.
    pub fn drive(&self) -> &Drive {
        &self.drive
    }

    /// A fault of §15-5 by its display code (`"ocA"`): the drive trips and the emergency goes
    /// out with the fault's CANopen code and error-register bit.
    pub fn raise_fault(&mut self, now: Instant, display: &str) -> Result<(), UnknownFault> {
        let &(_, code, bit, emcy) = FAULTS
            .iter()
            .find(|(name, ..)| *name == display)
            .ok_or_else(|| UnknownFault(display.to_string()))?;
        if self.control_mode() == ControlMode::Ds402 {
            self.drive.raise_fault(now);
        } else {
            self.vfd.trip(now, u16::from(code));
        }
        self.node.raise_error(emcy, 1 << bit, [code, 0, 0, 0, 0]);
        self.fault = Some((code, emcy));
        self.update(now);
        Ok(())
    }

    /// The fault's cause has gone: a reset (6040h bit 7 rising, 2020h:03 bit 1 or 2060h:01
    /// bit 15, as the control mode says) now clears it.
    pub fn remove_fault_cause(&mut self) {
        self.drive.clear_fault();
        self.vfd.cause_removed();
    }

    /// A Delta-mode fault reset: clears the fault if its cause has gone.
    fn reset_fault(&mut self) {
        if self.vfd.reset_fault().is_some() {
            self.fault_cleared();
        }
    }

    /// The drive that had the fault has left it: the error-reset emergency.
    fn fault_cleared(&mut self) {
        if let Some((_, emcy)) = self.fault.take() {
            self.node.clear_error(emcy);
        }
    }

    /// A Delta-mode command, after a write to 2020h or 2060h.
    fn delta_command(&mut self, now: Instant) {
        let od = self.node.od();
        let commands = read_u16(od, GROUP_00, OPERATION_SOURCE) == 3;
        let frequencies = read_u16(od, GROUP_00, FREQUENCY_SOURCE) == 6;
        match self.control_mode() {
            ControlMode::Ds402 => {}
            ControlMode::DeltaOld => {
                let word = read_u16(od, OLD_CONTROL, 1);
                let frequency = read_u16(od, OLD_CONTROL, 2);
                let trigger = read_u16(od, OLD_CONTROL, 3);
                if frequencies {
                    self.vfd.set_reference(now, u32::from(frequency) * 10);
                }
                if commands {
                    let reverse = match (word >> 4) & 0b11 {
                        0b01 => Some(false),
                        0b10 => Some(true),
                        0b11 => Some(self.vfd.output_frequency() >= 0),
                        _ => None,
                    };
                    let direction = |reverse| if reverse { Run::Reverse } else { Run::Forward };
                    match word & 0b11 {
                        0b01 => self.vfd.command(now, Run::Stop),
                        0b10 | 0b11 => {
                            let reverse = reverse.unwrap_or(self.vfd.run() == Run::Reverse);
                            self.vfd.command(now, direction(reverse));
                        }
                        _ => {}
                    }
                    if trigger & 0b10 != 0 {
                        self.reset_fault();
                    }
                }
            }
            ControlMode::DeltaNew => {
                let word = read_u16(od, NEW_CONTROL, 1);
                let frequency = read_u16(od, NEW_CONTROL, 3);
                if frequencies {
                    self.vfd.set_reference(now, u32::from(frequency) * 10);
                }
                if commands {
                    let bit = |n: u16| word & (1 << n) != 0;
                    if bit(15) {
                        self.reset_fault();
                    }
                    if bit(6) || !bit(7) {
                        self.vfd.coast();
                    } else if bit(3) || !bit(0) {
                        self.vfd.command(now, Run::Stop);
                    } else if bit(1) {
                        self.vfd.command(now, Run::Reverse);
                    } else {
                        self.vfd.command(now, Run::Forward);
                    }
                }
            }
        }
        self.update(now);
    }

    /// Advances both drives and writes the status objects of every mode.
    fn update(&mut self, now: Instant) {
        let ds402 = self.control_mode() == ControlMode::Ds402;
        let od = self.node.od();
        let commands = read_u16(od, GROUP_00, OPERATION_SOURCE) == 3;
        if ds402 && commands {
            let ran = self.drive.run_on(self.node.od_mut(), now);
            debug_assert_eq!(ran, Ok(()));
            let faulted = matches!(
                self.drive.state(),
                State::Fault | State::FaultReactionActive
            );
            if self.fault.is_some() && !faulted {
                self.fault_cleared();
            }
        }
        self.vfd.update(now);
        let vfd = &self.vfd;
        let output = vfd.output_frequency();
        let od = self.node.od();
        let by_comm = |index, sub, value| u16::from(read_u16(od, index, sub) == value);
        let operation = match (vfd.run(), output) {
            (Run::Stop, 0) => 0b00,
            (Run::Stop, _) => 0b01,
            _ => 0b11,
        };
        let direction = match (vfd.run(), output.signum()) {
            (Run::Reverse, -1 | 0) => 0b11,
            (Run::Reverse, 1) => 0b10,
            (Run::Forward, -1) => 0b01,
            _ => 0b00,
        };
        let old_status = operation
            | direction << 3
            | by_comm(GROUP_00, FREQUENCY_SOURCE, 6) << 8
            | by_comm(GROUP_00, OPERATION_SOURCE, 3) << 10;
        let setpoint_reached = output.unsigned_abs() == vfd.reference() && vfd.run() != Run::Stop;
        let new_status = u16::from(setpoint_reached)
            | u16::from(output < 0 || vfd.run() == Run::Reverse) << 1
            | u16::from(self.fault.is_some()) << 3
            | u16::from(read_u16(od, NEW_CONTROL, 1) & 0x40 != 0) << 6
            | u16::from(read_u16(od, NEW_CONTROL, 1) & 0x80 != 0) << 7;
        let fault_code = self.fault.map_or(0, |(code, _)| u16::from(code));
        let emcy_code = self.fault.map_or(0, |(_, emcy)| emcy);
        let values = [
            (OLD_STATUS, 1, fault_code),
            (OLD_STATUS, 2, old_status),
            (OLD_STATUS, 3, vfd.reference() as u16),
            (OLD_STATUS, 4, output.unsigned_abs() as u16),
            (OLD_STATUS, 5, vfd.output_current() as u16),
            (OLD_STATUS, 6, vfd.bus_voltage() as u16),
            (OLD_STATUS, 7, vfd.output_voltage() as u16),
            (NEW_STATUS, 1, new_status),
            (NEW_STATUS, 3, (output.unsigned_abs() / 10) as u16),
            (0x603F, 0, emcy_code),
        ];
        let od = self.node.od_mut();
        for (index, sub, value) in values {
            replace_u16(od, index, sub, value);
        }
    }

    fn process_events(&mut self, now: Instant) {
        while let Some(event) = self.node.poll_event() {
            if matches!(
                event,
                Event::Written { .. } | Event::RpdoReceived { .. } | Event::Reset(_)
            ) {
                self.delta_command(now);
            }
        }
    }
}

impl BusDevice for Ms300 {
    fn handle_frame(&mut self, now: Instant, frame: &CanFrame) {
        self.node.handle_frame(now, frame);
        self.process_events(now);
    }

    fn poll_transmit(&mut self, now: Instant) -> Option<CanFrame> {
        self.node.poll_transmit(now)
    }

    fn poll_timeout(&self) -> Option<Instant> {
        let drives = earliest(self.drive.next_update(), self.vfd.next_update());
        earliest(self.node.poll_timeout(), drives)
    }

    fn handle_timeout(&mut self, now: Instant) {
        self.node.handle_timeout(now);
        self.process_events(now);
        let due = |at: Option<Instant>| at.is_some_and(|at| at <= now);
        if due(self.drive.next_update()) || due(self.vfd.next_update()) {
            self.update(now);
        }
    }
}
