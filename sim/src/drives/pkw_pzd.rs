//! The Goodrive350 behind its PROFIBUS-DP, PROFINET or EtherNet/IP card: one drive speaking the
//! PKW/PZD protocol of the manual's chapters 2, 4 and 5 ([`edsgen_runtime::pkw_pzd`]) on the
//! [`Vfd`] model the CANopen Goodrive350 uses. Sans-IO: the bus's protocol core hands each
//! cycle's output image in and carries the input image back ([`PkwPzdDrive::exchange`]), and
//! tells the drive when its own watchdog expires ([`PkwPzdDrive::communication_lost`]).
//!
//! The bus ([`Bus`]) selects what differs between the cards: the PZD function parameters
//! (P15.02–P15.23 for PROFIBUS-DP, P16.32–P16.53 for PROFINET and EtherNet/IP), the values of
//! P00.02 and P00.06 that give the bus the run command and the frequency (1 and 9 for PROFIBUS,
//! 3 and 13 for PROFINET and EtherNet/IP, Appendix C), the communication timeout parameter
//! (P15.25, P16.31, P16.54) and the fault (29 E-DP, 57 E-PN, 70 E-EIP, P07.27).
//!
//! Choices where the manual is silent:
//! - A command (CW bits 0–7) acts when it changes, as an edge: a held "run forward" does not
//!   restart the drive after a fault reset. Jogging runs at 5.00 Hz; "stop jogging" stops it
//!   and the PZD frequency applies again.
//! - PKW writes need CW bit 8 ("enabling writing, mainly through PKW1 to PKW4"); without it a
//!   write is refused with error 1 (invalid command). A write runs once per new request (PKW
//!   words or bit 8 changed); a read is answered afresh every cycle. Tasks 2, 3 and 5 ("not
//!   supported currently") are refused with error 1, as is any undefined task; a value beyond
//!   the parameter's range (or beyond 16 bits) with 3, a missing address with 2, a read-only
//!   parameter with 7, a stopped-only parameter while running with 8. Every parameter is one
//!   word, so reads answer with response 1.
//! - SW bits 13–14 give P00.01 (0 keypad, 1 terminal, 2 communication); bit 15 echoes CW bit 15
//!   (heartbeat); bit 8 (bus voltage established) is always set; bits 9–12 stay 0.
//! - The bus's own watchdog (DP's from Set_Prm) trips the fault whatever the timeout parameter
//!   says; the timeout parameter (in 0.1 s, 0 off) trips it when no exchange came for that long.
//!   The cause goes with the next exchange; a fault reset (command 7) then clears it.
//! - Transmitted PZD functions 1 and 10 give the output frequency, 2 the reference, 3 the bus
//!   voltage, 4 the output voltage, 5 the current, 8 the speed, 11 the fault code; the others 0.
//!   Received functions other than 1 (set frequency) are accepted and have no effect.

use edsgen_runtime::pkw_pzd::control::sw_bit;
use edsgen_runtime::pkw_pzd::{
    ByteOrder, Command, ControlWord, ErrorNumber, InputImage, OutputImage, PkwRequest, PkwResponse,
    RunState, RunStopMode, StatusWord, Task, WordLayout, IMAGE_BYTES, PZD_WORDS,
};
use edsgen_runtime::{Duration, Instant};

use super::vfd::{Modify, ParameterError, ParameterSpec, Parameters, Ratings, Run, Vfd};

/// The bus the card sits on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Bus {
    /// PROFIBUS-DP (chapter 2): P15.xx.
    ProfibusDp,
    /// PROFINET (chapter 4): P16.xx.
    Profinet,
    /// EtherNet/IP (chapter 5): P16.xx, and P16.56 chooses the CW/SW layout.
    EthernetIp,
}

impl Bus {
    /// The address of the received PZD2 function parameter (P15.02 or P16.32); PZD3–PZD12
    /// follow.
    pub const fn received_pzd2(self) -> u16 {
        match self {
            Bus::ProfibusDp => 0x0F02,
            Bus::Profinet | Bus::EthernetIp => 0x1020,
        }
    }

    /// The address of the transmitted PZD2 function parameter (P15.13 or P16.43).
    pub const fn transmitted_pzd2(self) -> u16 {
        match self {
            Bus::ProfibusDp => 0x0F0D,
            Bus::Profinet | Bus::EthernetIp => 0x102B,
        }
    }

    /// The communication timeout parameter (P15.25, P16.31, P16.54), in 0.1 s.
    pub const fn timeout_parameter(self) -> u16 {
        match self {
            Bus::ProfibusDp => 0x0F19,
            Bus::Profinet => 0x101F,
            Bus::EthernetIp => 0x1036,
        }
    }

    /// The fault type (P07.27) of a lost connection.
    pub const fn fault(self) -> u16 {
        match self {
            Bus::ProfibusDp => 29,
            Bus::Profinet => 57,
            Bus::EthernetIp => 70,
        }
    }

    /// The keypad's name of that fault.
    pub const fn fault_name(self) -> &'static str {
        match self {
            Bus::ProfibusDp => "E-DP",
            Bus::Profinet => "E-PN",
            Bus::EthernetIp => "E-EIP",
        }
    }

    /// P00.02's value that makes this bus the run command channel.
    pub const fn command_channel(self) -> u16 {
        match self {
            Bus::ProfibusDp => 1,
            Bus::Profinet | Bus::EthernetIp => 3,
        }
    }

    /// P00.06's value that makes this bus the frequency source.
    pub const fn frequency_source(self) -> u16 {
        match self {
            Bus::ProfibusDp => 9,
            Bus::Profinet | Bus::EthernetIp => 13,
        }
    }
}

/// Parameter addresses (group in the high byte, number in the low byte).
pub mod parameter {
    /// P00.01 channel of running commands: 2 communication.
    pub const RUN_COMMAND_CHANNEL: u16 = 0x0001;
    /// P00.02 communication channel of running commands.
    pub const COMMUNICATION_CHANNEL: u16 = 0x0002;
    /// P00.03 maximum output frequency, 0.01 Hz.
    pub const MAX_FREQUENCY: u16 = 0x0003;
    /// P00.06 frequency A command setting mode.
    pub const FREQUENCY_A_SOURCE: u16 = 0x0006;
    /// P00.10 keypad set frequency, 0.01 Hz (the §2.6 examples' address 10).
    pub const KEYPAD_FREQUENCY: u16 = 0x000A;
    /// P00.11 acceleration time 1, 0.1 s.
    pub const ACCELERATION_TIME: u16 = 0x000B;
    /// P00.12 deceleration time 1, 0.1 s.
    pub const DECELERATION_TIME: u16 = 0x000C;
    /// P07.27 type of present fault (read-only).
    pub const PRESENT_FAULT: u16 = 0x071B;
    /// P07.28 type of last fault (read-only).
    pub const LAST_FAULT: u16 = 0x071C;
    /// P15.01 module address (the PROFIBUS node address).
    pub const MODULE_ADDRESS: u16 = 0x0F01;
    /// P16.56 EtherNet/IP CW/SW layout: 0 by byte, 1 by bit.
    pub const EIP_WORD_LAYOUT: u16 = 0x1038;
}

/// Jogging frequency, 0.01 Hz.
const JOG_FREQUENCY: u32 = 500;

/// The parameters the simulation keeps, sorted by address: P00 as the CANopen Goodrive350 has
/// them plus P00.10 (default 50.00 Hz, which §2.6 example 1 reads), P07.27/P07.28, and
/// Appendix C's P15 and P16 communication parameters of the three cards with their ranges.
static PARAMETERS: [ParameterSpec; 61] = {
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
    const fn pzd(address: u16) -> ParameterSpec {
        ParameterSpec {
            address,
            default: 0,
            min: 0,
            max: 31,
            modify: Modify::Always,
        }
    }
    [
        p(0x0001, 0, 0, 2, Stopped),
        p(0x0002, 0, 0, 5, Stopped),
        p(0x0003, 5000, 1000, 63000, Stopped),
        p(0x0006, 0, 0, 15, Stopped),
        p(0x0007, 2, 0, 15, Stopped),
        p(0x000A, 5000, 0, 63000, Always),
        p(0x000B, 100, 0, 36000, Always),
        p(0x000C, 100, 0, 36000, Always),
        p(0x071B, 0, 0, 0xFFFF, ReadOnly),
        p(0x071C, 0, 0, 0xFFFF, ReadOnly),
        p(0x0F01, 2, 0, 127, Stopped),
        // P15.02–P15.12 received, P15.13–P15.23 transmitted PZD2–PZD12 (0–31).
        pzd(0x0F02),
        pzd(0x0F03),
        pzd(0x0F04),
        pzd(0x0F05),
        pzd(0x0F06),
        pzd(0x0F07),
        pzd(0x0F08),
        pzd(0x0F09),
        pzd(0x0F0A),
        pzd(0x0F0B),
        pzd(0x0F0C),
        pzd(0x0F0D),
        pzd(0x0F0E),
        pzd(0x0F0F),
        pzd(0x0F10),
        pzd(0x0F11),
        pzd(0x0F12),
        pzd(0x0F13),
        pzd(0x0F14),
        pzd(0x0F15),
        pzd(0x0F16),
        pzd(0x0F17),
        // P15.24 temporary variable; P15.25 DP communication timeout, 0.0–300.0 s.
        p(0x0F18, 0, 0, 0xFFFF, Always),
        p(0x0F19, 0, 0, 3000, Always),
        // P16.31 PROFINET communication timeout, 0.0–300.0 s.
        p(0x101F, 0, 0, 3000, Always),
        // P16.32–P16.42 received, P16.43–P16.53 transmitted PZD2–PZD12 (0–31).
        pzd(0x1020),
        pzd(0x1021),
        pzd(0x1022),
        pzd(0x1023),
        pzd(0x1024),
        pzd(0x1025),
        pzd(0x1026),
        pzd(0x1027),
        pzd(0x1028),
        pzd(0x1029),
        pzd(0x102A),
        pzd(0x102B),
        pzd(0x102C),
        pzd(0x102D),
        pzd(0x102E),
        pzd(0x102F),
        pzd(0x1030),
        pzd(0x1031),
        pzd(0x1032),
        pzd(0x1033),
        pzd(0x1034),
        pzd(0x1035),
        // P16.54 EtherNet/IP timeout: Appendix C says 0.5–60.0 s with default "0.0s"; 0 (off)
        // is kept as the default and allowed, up to 60.0 s.
        p(0x1036, 0, 0, 600, Always),
        // P16.55 EtherNet/IP rate, P16.56 CW/SW layout.
        p(0x1037, 0, 0, 4, Always),
        p(0x1038, 0, 0, 1, Stopped),
    ]
};

/// The simulated Goodrive350 behind a PKW/PZD card (see the module comment).
#[derive(Debug, Clone)]
pub struct PkwPzdDrive {
    bus: Bus,
    parameters: Parameters,
    vfd: Vfd,
    /// The last write request served, with CW bit 8 as it was.
    last_write: Option<(PkwRequest, bool)>,
    /// The answer to the present request.
    response: PkwResponse,
    /// CW bits 0–7 of the last exchange (commands act on change).
    last_command_byte: u8,
    last_control: ControlWord,
    jogging: bool,
    last_exchange: Option<Instant>,
    /// The bus fault's cause is present until the next exchange.
    bus_fault: bool,
    /// The fault last reported by [`PkwPzdDrive::poll_fault_change`].
    reported_fault: Option<u16>,
}

/// A change of the drive's faults, for the bus to report (PROFINET's Diagnosis alarms).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FaultChange {
    /// The drive tripped with this fault (P07.27's type).
    Appears(u16),
    /// This fault was reset.
    Disappears(u16),
}

impl PkwPzdDrive {
    /// The drive powered up at `now` on `bus`, parameters at their defaults (keypad control).
    pub fn new(bus: Bus, now: Instant) -> Self {
        let parameters = Parameters::new(&PARAMETERS);
        let ratings = Ratings {
            max_frequency: u32::from(parameters.get(parameter::MAX_FREQUENCY).unwrap_or(5000)),
            rated_voltage: 380,
            rated_frequency: 5000,
            bus_voltage: 5400,
            pole_pairs: 2,
        };
        PkwPzdDrive {
            bus,
            parameters,
            vfd: Vfd::new(ratings, now),
            last_write: None,
            response: PkwResponse::None,
            last_command_byte: 0,
            last_control: ControlWord(0),
            jogging: false,
            last_exchange: None,
            bus_fault: false,
            reported_fault: None,
        }
    }

    /// The drive on `bus` set up as the manual's examples expect: run commands (P00.01 = 2,
    /// P00.02) and frequency A (P00.06) from the bus, received PZD2 the set frequency and
    /// transmitted PZD2 the running frequency.
    pub fn bus_controlled(bus: Bus, now: Instant) -> Self {
        let mut drive = PkwPzdDrive::new(bus, now);
        let settings = [
            (parameter::RUN_COMMAND_CHANNEL, 2),
            (parameter::COMMUNICATION_CHANNEL, bus.command_channel()),
            (parameter::FREQUENCY_A_SOURCE, bus.frequency_source()),
            (bus.received_pzd2(), 1),
            (bus.transmitted_pzd2(), 1),
        ];
        for (address, value) in settings {
            // At rest and in range: the table above allows each.
            let _ = drive.parameters.set(address, value, false);
        }
        drive
    }

    /// The bus.
    pub fn bus(&self) -> Bus {
        self.bus
    }

    /// A parameter's value (`None` if the simulation has none there).
    pub fn parameter(&self, address: u16) -> Option<u16> {
        self.parameters.get(address)
    }

    /// Sets a parameter as the keypad would, with the same checks as a PKW write.
    pub fn set_parameter(&mut self, address: u16, value: u16) -> Result<(), ParameterError> {
        self.parameters.set(address, value, self.vfd.running())
    }

    /// The drive's motion and electrical state.
    pub fn vfd(&self) -> &Vfd {
        &self.vfd
    }

    /// The CW/SW layout: by bit only on EtherNet/IP with P16.56 = 1.
    pub fn layout(&self) -> WordLayout {
        match (self.bus, self.parameter(parameter::EIP_WORD_LAYOUT)) {
            (Bus::EthernetIp, Some(1)) => WordLayout::ByBit,
            _ => WordLayout::ByByte,
        }
    }

    /// One cycle: the master's image in at `now`, the drive's image out.
    pub fn exchange(&mut self, now: Instant, output: &OutputImage) -> InputImage {
        self.vfd.update(now);
        self.last_exchange = Some(now);
        if self.bus_fault {
            self.bus_fault = false;
            self.vfd.cause_removed();
        }
        self.apply_control(now, output.control, &output.pzd);
        self.response = self.serve(output.pkw, output.control);
        // A write may have changed the ramps.
        self.apply_ramps(now);
        self.inputs()
    }

    /// [`exchange`](Self::exchange) on the 32 bytes of each image in `order`.
    pub fn exchange_bytes(
        &mut self,
        now: Instant,
        output: &[u8; IMAGE_BYTES],
        order: ByteOrder,
    ) -> [u8; IMAGE_BYTES] {
        let output = OutputImage::parse(output, order);
        self.exchange(now, &output).emit(order)
    }

    /// The drive's image as it stands (the last PKW response, the SW and the actual values).
    pub fn inputs(&self) -> InputImage {
        let base = self.bus.transmitted_pzd2();
        let mut pzd = [0u16; PZD_WORDS];
        for (n, value) in pzd.iter_mut().enumerate() {
            let function = self.parameter(base + n as u16).unwrap_or(0);
            *value = super::goodrive350::returned_value(&self.vfd, function);
        }
        InputImage {
            pkw: self.response,
            status: self.status_word(),
            pzd,
        }
    }

    /// The bus's own watchdog expired at `now` (DP's, set by Set_Prm): the drive trips with
    /// the bus's fault (E-DP on PROFIBUS).
    pub fn communication_lost(&mut self, now: Instant) {
        self.trip(now, self.bus.fault());
        self.bus_fault = true;
        self.last_exchange = None;
    }

    /// A fault of type `fault` (P07.27's numbering) trips the drive at `now`.
    pub fn inject_fault(&mut self, now: Instant, fault: u16) {
        self.trip(now, fault);
    }

    /// The next change of the drive's fault since the last call, other than the bus's own
    /// (which ends the connection: there is no one left to tell). A fault present at the first
    /// call after [`PkwPzdDrive::forget_reported_fault`] appears then.
    pub fn poll_fault_change(&mut self) -> Option<FaultChange> {
        let bus_fault = self.bus.fault();
        let fault = self.vfd.fault().filter(|&f| f != bus_fault);
        if fault == self.reported_fault {
            return None;
        }
        if let Some(old) = self.reported_fault.take() {
            return Some(FaultChange::Disappears(old));
        }
        self.reported_fault = fault;
        fault.map(FaultChange::Appears)
    }

    /// A new connection starts: nothing has been reported to it.
    pub fn forget_reported_fault(&mut self) {
        self.reported_fault = None;
    }

    /// The injected fault's cause has gone: a fault reset now clears it.
    pub fn remove_fault_cause(&mut self) {
        self.vfd.cause_removed();
    }

    /// When the drive next wants [`handle_timeout`](Self::handle_timeout): while the output
    /// ramps, and when the timeout parameter would expire.
    pub fn poll_timeout(&self) -> Option<Instant> {
        let ramp = self.vfd.next_update();
        let watchdog = self.timeout_deadline();
        match (ramp, watchdog) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    /// Moves the ramps to `now` and trips the bus fault if the timeout parameter expired.
    pub fn handle_timeout(&mut self, now: Instant) {
        self.vfd.update(now);
        if self.timeout_deadline().is_some_and(|at| at <= now) {
            self.communication_lost(now);
        }
    }

    fn timeout_deadline(&self) -> Option<Instant> {
        let tenths = self.parameter(self.bus.timeout_parameter()).unwrap_or(0);
        let last = self.last_exchange?;
        (tenths > 0 && self.vfd.fault().is_none())
            .then(|| last + Duration::from_millis(u64::from(tenths) * 100))
    }

    fn trip(&mut self, now: Instant, fault: u16) {
        self.vfd.trip(now, fault);
        self.jogging = false;
        self.parameters.record(parameter::PRESENT_FAULT, fault);
    }

    fn p(&self, address: u16) -> u16 {
        self.parameters.get(address).unwrap_or(0)
    }

    fn apply_ramps(&mut self, now: Instant) {
        let accel = self.p(parameter::ACCELERATION_TIME);
        let decel = self.p(parameter::DECELERATION_TIME);
        self.vfd.set_ramp_times(now, accel, decel);
    }

    fn apply_control(&mut self, now: Instant, control: ControlWord, pzd: &[u16; PZD_WORDS]) {
        self.apply_ramps(now);
        self.last_control = control;
        let bus_runs = self.p(parameter::RUN_COMMAND_CHANNEL) == 2
            && self.p(parameter::COMMUNICATION_CHANNEL) == self.bus.command_channel();
        let bus_sets_frequency =
            self.p(parameter::FREQUENCY_A_SOURCE) == self.bus.frequency_source();
        let max_frequency = self.p(parameter::MAX_FREQUENCY);
        if bus_sets_frequency && !self.jogging {
            let base = self.bus.received_pzd2();
            for (n, setting) in pzd.iter().enumerate() {
                // Function 1, set frequency (0–Fmax): out of range is ignored.
                if self.p(base + n as u16) == 1 && *setting <= max_frequency {
                    self.vfd.set_reference(now, u32::from(*setting));
                }
            }
        }
        let byte = control.0 as u8;
        let changed = byte != self.last_command_byte;
        self.last_command_byte = byte;
        if !bus_runs || !changed {
            return;
        }
        match control.command(self.layout()) {
            Some(Command::RunForward) => self.vfd.command(now, Run::Forward),
            Some(Command::RunReverse) => self.vfd.command(now, Run::Reverse),
            Some(jog @ (Command::JogForward | Command::JogReverse))
                if self.vfd.fault().is_none() =>
            {
                self.jogging = true;
                self.vfd.set_reference(now, JOG_FREQUENCY);
                let run = if jog == Command::JogForward {
                    Run::Forward
                } else {
                    Run::Reverse
                };
                self.vfd.command(now, run);
            }
            Some(Command::DecelerateToStop) => self.vfd.command(now, Run::Stop),
            Some(Command::StopJogging) if self.jogging => {
                self.jogging = false;
                self.vfd.command(now, Run::Stop);
            }
            Some(Command::CoastToStop) => {
                self.jogging = false;
                self.vfd.coast();
            }
            Some(Command::FaultReset) => {
                if let Some(fault) = self.vfd.reset_fault() {
                    self.parameters.record(parameter::LAST_FAULT, fault);
                    self.parameters.record(parameter::PRESENT_FAULT, 0);
                }
            }
            _ => {}
        }
    }

    /// Table 2-10: the request's answer.
    fn serve(&mut self, request: PkwRequest, control: ControlWord) -> PkwResponse {
        let address = request.address;
        let refuse = |error| PkwResponse::Refused { address, error };
        match request.task {
            Task::None => {
                self.last_write = None;
                PkwResponse::None
            }
            Task::Read => match self.parameters.get(address) {
                Some(value) => PkwResponse::Word { address, value },
                None => refuse(ErrorNumber::InvalidAddress),
            },
            Task::WriteEeprom => {
                let key = (request, control.write_enabled());
                if self.last_write == Some(key) {
                    return self.response;
                }
                self.last_write = Some(key);
                if !control.write_enabled() {
                    return refuse(ErrorNumber::InvalidCommand);
                }
                let Ok(value) = u16::try_from(request.value) else {
                    return refuse(ErrorNumber::InvalidValue);
                };
                match self.parameters.set(address, value, self.vfd.running()) {
                    Ok(()) => PkwResponse::Word { address, value },
                    Err(ParameterError::NoSuchParameter) => refuse(ErrorNumber::InvalidAddress),
                    Err(ParameterError::ReadOnly) => refuse(ErrorNumber::ReadOnly),
                    Err(ParameterError::OutOfRange) => refuse(ErrorNumber::InvalidValue),
                    Err(ParameterError::WhileRunning) => refuse(ErrorNumber::WhileRunning),
                }
            }
            Task::WriteRam | Task::WriteRamDouble | Task::WriteEepromDouble | Task::Other(_) => {
                refuse(ErrorNumber::InvalidCommand)
            }
        }
    }

    /// Table 2-7 (or 5-9): the status word.
    fn status_word(&self) -> StatusWord {
        let vfd = &self.vfd;
        let state = if vfd.fault().is_some() {
            RunState::Fault
        } else if vfd.output_frequency() > 0 || vfd.run() == Run::Forward {
            RunState::Forward
        } else if vfd.output_frequency() < 0 || vfd.run() == Run::Reverse {
            RunState::Reverse
        } else {
            RunState::Stopped
        };
        let mode = match self.p(parameter::RUN_COMMAND_CHANNEL) {
            0 => RunStopMode::Keypad,
            1 => RunStopMode::Terminal,
            _ => RunStopMode::Communication,
        };
        StatusWord::new(state, self.layout())
            .with(sw_bit::READY, true)
            .with_run_stop_mode(mode)
            .with(sw_bit::HEARTBEAT, self.last_control.0 & 0x8000 != 0)
    }
}

#[cfg(test)]
mod tests;
