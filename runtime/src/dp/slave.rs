//! The DP slave's state machine (EN 50170 / IEC 61158 DP-V0), sans-IO, no_std and
//! allocation-free: a telegram's bytes and the time in ([`DpSlave::handle`]), the answer out
//! ([`DpSlave::poll_transmit`]); none for a broadcast, a telegram for another station, a bad
//! one, or a SAP it does not serve.
//!
//! Wait_Prm → (Set_Prm with this slave's Ident_Number and parameters) → Wait_Cfg → (Chk_Cfg
//! with its configuration bytes) → Data_Exchange. Slave_Diag answers the six standard bytes at
//! any time; Get_Cfg the configuration. A wrong Ident_Number or parameter length sets
//! Prm_Fault, a configuration the application refuses ([`DpApplication::check_config`]: by
//! default any but the slave's own) Cfg_Fault, both back in Wait_Prm. Global_Control's Sync
//! latches outputs until the next Sync, Freeze holds inputs until the next Freeze, Clear_Data
//! zeroes the outputs. The watchdog Set_Prm switches on leaves Data_Exchange when no telegram
//! came in time ([`DpSlave::poll_timeout`], [`DpSlave::handle_timeout`]), and tells the
//! application ([`DpApplication::watchdog_expired`]).
//!
//! FCB/FCV: a request whose frame count bit equals the last one from the same master (with FCV
//! set) is a repetition: the stored answer goes again and nothing is executed twice.
//!
//! Only a valid request is served ([`is_valid_request`]); anything else gets silence, as from
//! any FDL station. Unlike the Ethernet cores, `handle` takes no sender: on a PROFIBUS line the
//! source address is in the telegram. Cutting the line's bytes into telegrams is
//! [`super::line`]'s.

use super::fdl::{self, DataRepr, Repr, MAX_TELEGRAM_LEN};
use super::DpData;
use crate::{Duration, Instant};

/// DP's service access points (the slave's DSAPs; the master sends from 62).
pub mod sap {
    /// Global_Control.
    pub const GLOBAL_CONTROL: u8 = 58;
    /// Get_Cfg.
    pub const GET_CFG: u8 = 59;
    /// Slave_Diag.
    pub const SLAVE_DIAG: u8 = 60;
    /// Set_Prm.
    pub const SET_PRM: u8 = 61;
    /// Chk_Cfg.
    pub const CHK_CFG: u8 = 62;
}

/// Slave_Diag byte 1 bits.
pub mod diag1 {
    /// Not ready for data exchange.
    pub const STATION_NOT_READY: u8 = 0x02;
    /// The configuration of Chk_Cfg did not match.
    pub const CFG_FAULT: u8 = 0x04;
    /// The parameters of Set_Prm were wrong (Ident_Number, length).
    pub const PRM_FAULT: u8 = 0x40;
}

/// Slave_Diag byte 2 bits.
pub mod diag2 {
    /// The slave needs parameterising.
    pub const PRM_REQ: u8 = 0x01;
    /// Always set by a slave.
    pub const ALWAYS: u8 = 0x04;
    /// The watchdog is on.
    pub const WD_ON: u8 = 0x08;
    /// Freeze mode is active.
    pub const FREEZE: u8 = 0x10;
    /// Sync mode is active.
    pub const SYNC: u8 = 0x20;
}

/// Whether `t` is a request a DP-V0 slave at `address` may answer or execute (addressed to it
/// or broadcast): FC a request (bit 7 clear, bit 6 set) with a function a DP slave serves, FCV
/// only on a function with an acknowledgement (SDA, SRD); a master's source address (0–126,
/// not the slave's own); both SAPs or none, each 0–63 (no segment or address extension).
pub fn is_valid_request(t: &DataRepr<'_>, address: u8) -> bool {
    use fdl::request::*;
    let fcv = t.fc & 0x10 != 0;
    let function_ok = match t.function() {
        SDA_LOW | SDA_HIGH | SRD_LOW | SRD_HIGH => true,
        SDN_LOW | SDN_HIGH | FDL_STATUS => !fcv,
        _ => false,
    };
    let saps_ok = match (t.dsap, t.ssap) {
        (Some(d), Some(s)) => d <= 63 && s <= 63,
        (None, None) => true,
        _ => false,
    };
    t.fc & 0xC0 == 0x40
        && function_ok
        && saps_ok
        && t.sa < fdl::BROADCAST
        && t.sa != address
        && (t.da == address || t.da == fdl::BROADCAST)
}

/// What sits behind the slave: the cyclic data's owner.
pub trait DpApplication {
    /// One exchange at `now`: the outputs (master to slave) in, the inputs written into
    /// `inputs` (as long as [`SlaveConfig::input_len`]).
    fn exchange(&mut self, now: Instant, outputs: &[u8], inputs: &mut [u8]);
    /// The DP watchdog expired at `now`: the master is gone.
    fn watchdog_expired(&mut self, now: Instant);
    /// Chk_Cfg's configuration bytes `config`: the input and output lengths of Data_Exchange
    /// they mean if the slave accepts them, `None` for a Cfg_Fault. By default only the
    /// slave's own configuration ([`SlaveConfig::config`], `own`) is accepted; a modular
    /// slave accepts any allowed combination of its modules.
    fn check_config(&mut self, own: &SlaveConfig, config: &[u8]) -> Option<(usize, usize)> {
        (config == own.config.as_slice()).then_some((own.input_len, own.output_len))
    }
    /// Set_Prm's User_Prm_Data (`user_prm`, after the seven standard bytes): whether the slave
    /// takes it, else Prm_Fault. By default exactly [`SlaveConfig::user_prm_len`] bytes; a
    /// modular slave whose master picks the modules takes its own and any modules' after them.
    fn check_prm(&mut self, own: &SlaveConfig, user_prm: &[u8]) -> bool {
        user_prm.len() == own.user_prm_len
    }
}

/// What the slave is: from its GSD.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SlaveConfig {
    /// The station address.
    pub address: u8,
    /// Ident_Number.
    pub ident_number: u16,
    /// The configuration bytes Chk_Cfg must carry (and Get_Cfg answers).
    pub config: DpData,
    /// Bytes of User_Prm_Data Set_Prm must carry after its seven standard bytes: the slave's
    /// own, then its modules' (see [`DpApplication::check_prm`]).
    pub user_prm_len: usize,
    /// Output bytes of Data_Exchange (master to slave), at most [`DpData::CAPACITY`].
    pub output_len: usize,
    /// Input bytes of Data_Exchange (slave to master), at most [`DpData::CAPACITY`].
    pub input_len: usize,
    /// Freeze supported.
    pub freeze: bool,
    /// Sync supported.
    pub sync: bool,
}

/// The DP state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DpState {
    /// Waiting for Set_Prm.
    WaitPrm,
    /// Waiting for Chk_Cfg.
    WaitCfg,
    /// Exchanging data.
    DataExchange,
}

/// What happened in the slave, for the driver to report.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Event {
    /// The DP state changed.
    StateChanged {
        /// The state before.
        from: DpState,
        /// The state now.
        to: DpState,
    },
    /// The watchdog expired: the slave left Data_Exchange for Wait_Prm (no `StateChanged`
    /// comes for this change).
    WatchdogExpired,
}

/// The slave (see the module comment).
#[derive(Debug, Clone)]
pub struct DpSlave<A> {
    config: SlaveConfig,
    app: A,
    state: DpState,
    master: Option<u8>,
    prm_fault: bool,
    cfg_fault: bool,
    watchdog: Option<Duration>,
    last_seen: Instant,
    group: u8,
    sync_active: bool,
    /// Outputs in effect (latched by Sync in sync mode).
    outputs: DpData,
    /// Outputs received in sync mode, waiting for the next Sync.
    pending_outputs: Option<DpData>,
    /// The application's latest inputs.
    inputs: DpData,
    /// The inputs of the last Freeze, while freeze mode is active.
    frozen_inputs: Option<DpData>,
    /// The last answer and whether it waits to be sent.
    answer: [u8; MAX_TELEGRAM_LEN],
    answer_len: Option<usize>,
    transmit_pending: bool,
    /// The last request with FCV: its (master, FCB) and its answer's length in `repeat`.
    last: Option<(u8, bool, Option<usize>)>,
    repeat: [u8; MAX_TELEGRAM_LEN],
    /// Events not polled yet, oldest first (a telegram makes at most two).
    events: [Option<Event>; EVENT_CAPACITY],
    events_lost: u32,
}

/// How many events wait for [`DpSlave::poll_event`].
const EVENT_CAPACITY: usize = 4;

impl<A: DpApplication> DpSlave<A> {
    /// A slave just powered up, in Wait_Prm. Lengths above [`DpData::CAPACITY`] are cut to it.
    pub fn new(mut config: SlaveConfig, app: A, now: Instant) -> Self {
        config.output_len = config.output_len.min(DpData::CAPACITY);
        config.input_len = config.input_len.min(DpData::CAPACITY);
        DpSlave {
            outputs: DpData::zeroed(config.output_len),
            inputs: DpData::zeroed(config.input_len),
            config,
            app,
            state: DpState::WaitPrm,
            master: None,
            prm_fault: false,
            cfg_fault: false,
            watchdog: None,
            last_seen: now,
            group: 0,
            sync_active: false,
            pending_outputs: None,
            frozen_inputs: None,
            answer: [0; MAX_TELEGRAM_LEN],
            answer_len: None,
            transmit_pending: false,
            last: None,
            repeat: [0; MAX_TELEGRAM_LEN],
            events: [None; EVENT_CAPACITY],
            events_lost: 0,
        }
    }

    /// The DP state.
    pub fn state(&self) -> DpState {
        self.state
    }

    /// The application.
    pub fn app(&self) -> &A {
        &self.app
    }

    /// The application, to change.
    pub fn app_mut(&mut self) -> &mut A {
        &mut self.app
    }

    /// The configuration.
    pub fn config(&self) -> &SlaveConfig {
        &self.config
    }

    /// The next event, oldest first.
    pub fn poll_event(&mut self) -> Option<Event> {
        let first = self.events[0].take();
        self.events.rotate_left(1);
        first
    }

    /// Events dropped because the driver did not poll them in time.
    pub fn events_lost(&self) -> u32 {
        self.events_lost
    }

    /// When the watchdog expires, while it runs.
    pub fn poll_timeout(&self) -> Option<Instant> {
        let watchdog = self.watchdog?;
        (self.state == DpState::DataExchange).then(|| self.last_seen + watchdog)
    }

    /// Leaves Data_Exchange if the watchdog expired by `now`.
    pub fn handle_timeout(&mut self, now: Instant) {
        if self.poll_timeout().is_some_and(|at| at <= now) {
            self.state = DpState::WaitPrm;
            self.master = None;
            self.watchdog = None;
            self.push_event(Event::WatchdogExpired);
            self.app.watchdog_expired(now);
        }
    }

    /// The answer to the last telegram, written into `buf`; its length. `None` when there is
    /// nothing to send (or `buf` is shorter than the answer, which is then dropped).
    pub fn poll_transmit(&mut self, _now: Instant, buf: &mut [u8]) -> Option<usize> {
        if !core::mem::take(&mut self.transmit_pending) {
            return None;
        }
        let len = self.answer_len?;
        buf.get_mut(..len)?.copy_from_slice(&self.answer[..len]);
        Some(len)
    }

    /// Handles one received telegram's bytes at `now` (exactly one telegram); the answer, if
    /// any, waits in [`DpSlave::poll_transmit`].
    pub fn handle(&mut self, now: Instant, bytes: &[u8]) {
        self.transmit_pending = false;
        let Ok((Repr::Data(t), used)) = fdl::parse(bytes) else {
            return;
        };
        if used != bytes.len() || !is_valid_request(&t, self.config.address) {
            return;
        }
        let broadcast = t.da == fdl::BROADCAST;
        if t.da != self.config.address && !broadcast {
            return;
        }
        self.handle_timeout(now);
        if let (Some(fcb), Some((sa, last_fcb, repeated))) = (t.fcb(), self.last) {
            if sa == t.sa && last_fcb == fcb {
                if let Some(len) = repeated {
                    self.answer[..len].copy_from_slice(&self.repeat[..len]);
                }
                self.answer_len = repeated;
                self.transmit_pending = repeated.is_some();
                return;
            }
        }
        self.answer_len = None;
        self.serve(now, &t, broadcast);
        let answered = self.answer_len.is_some();
        self.transmit_pending = answered;
        if let Some(fcb) = t.fcb() {
            if let Some(len) = self.answer_len {
                self.repeat[..len].copy_from_slice(&self.answer[..len]);
            }
            self.last = Some((t.sa, fcb, self.answer_len));
        }
        if (answered || broadcast) && self.master.is_none_or(|m| m == t.sa) {
            self.last_seen = now;
        }
    }

    fn serve(&mut self, now: Instant, t: &DataRepr<'_>, broadcast: bool) {
        use fdl::request::*;
        match (t.dsap, t.function()) {
            (None, FDL_STATUS) if !broadcast => self.short(t, fdl::response::OK),
            (None, SRD_LOW | SRD_HIGH) if !broadcast => self.data_exchange(now, t),
            (Some(sap::GLOBAL_CONTROL), SDN_LOW | SDN_HIGH | SDA_LOW | SDA_HIGH) => {
                self.global_control(now, t)
            }
            (Some(_), _) if broadcast => {}
            (Some(sap::SLAVE_DIAG), SRD_LOW | SRD_HIGH) => {
                let diag = self.diagnosis();
                self.reply(t, &diag);
            }
            (Some(sap::SET_PRM), SRD_LOW | SRD_HIGH | SDA_LOW | SDA_HIGH) => {
                self.set_prm(t);
                self.short_ack();
            }
            (Some(sap::CHK_CFG), SRD_LOW | SRD_HIGH | SDA_LOW | SDA_HIGH) => {
                self.chk_cfg(t);
                self.short_ack();
            }
            (Some(sap::GET_CFG), SRD_LOW | SRD_HIGH) => {
                let config = self.config.config;
                self.reply(t, config.as_slice());
            }
            _ => {}
        }
    }

    /// The six standard diagnosis bytes.
    pub fn diagnosis(&self) -> [u8; 6] {
        let mut b1 = 0;
        if self.state != DpState::DataExchange {
            b1 |= diag1::STATION_NOT_READY;
        }
        if self.cfg_fault {
            b1 |= diag1::CFG_FAULT;
        }
        if self.prm_fault {
            b1 |= diag1::PRM_FAULT;
        }
        let mut b2 = diag2::ALWAYS;
        if self.state == DpState::WaitPrm {
            b2 |= diag2::PRM_REQ;
        }
        if self.watchdog.is_some() {
            b2 |= diag2::WD_ON;
        }
        if self.frozen_inputs.is_some() {
            b2 |= diag2::FREEZE;
        }
        if self.sync_active {
            b2 |= diag2::SYNC;
        }
        let [hi, lo] = self.config.ident_number.to_be_bytes();
        [b1, b2, 0, self.master.unwrap_or(0xFF), hi, lo]
    }

    fn set_state(&mut self, to: DpState) {
        if self.state != to {
            let from = core::mem::replace(&mut self.state, to);
            self.push_event(Event::StateChanged { from, to });
        }
    }

    /// Queues `event`; when the driver has not polled the queue empty, the oldest is lost.
    fn push_event(&mut self, event: Event) {
        if self.events[EVENT_CAPACITY - 1].is_some() {
            self.events_lost = self.events_lost.saturating_add(1);
            self.events.rotate_left(1);
            self.events[EVENT_CAPACITY - 1] = None;
        }
        if let Some(free) = self.events.iter_mut().find(|e| e.is_none()) {
            *free = Some(event);
        }
    }

    fn set_prm(&mut self, t: &DataRepr<'_>) {
        let data = t.data;
        let ident = data.get(4..6).map(|b| u16::from_be_bytes([b[0], b[1]]));
        let status = data.first().copied().unwrap_or(0);
        let freeze = status & 0x10 != 0;
        let sync = status & 0x20 != 0;
        let user_prm = data.get(7..).unwrap_or(&[]);
        let ok = data.len() >= 7
            && self.app.check_prm(&self.config, user_prm)
            && ident == Some(self.config.ident_number)
            && (!freeze || self.config.freeze)
            && (!sync || self.config.sync);
        self.cfg_fault = false;
        if !ok {
            self.prm_fault = true;
            self.set_state(DpState::WaitPrm);
            return;
        }
        self.prm_fault = false;
        self.master = Some(t.sa);
        self.watchdog = (status & 0x08 != 0).then(|| {
            let factor = u64::from(data[1]) * u64::from(data[2]);
            Duration::from_millis(10 * factor.max(1))
        });
        self.group = data[6];
        self.sync_active = false;
        self.pending_outputs = None;
        self.frozen_inputs = None;
        self.set_state(DpState::WaitCfg);
    }

    fn chk_cfg(&mut self, t: &DataRepr<'_>) {
        if self.state == DpState::WaitPrm || self.master != Some(t.sa) {
            return;
        }
        let accepted = self
            .app
            .check_config(&self.config, t.data)
            .zip(DpData::new(t.data))
            .filter(|((i, o), _)| *i <= DpData::CAPACITY && *o <= DpData::CAPACITY);
        if let Some(((input_len, output_len), config)) = accepted {
            // Get_Cfg answers the configuration in effect; the images take its lengths.
            self.config.config = config;
            if (input_len, output_len) != (self.config.input_len, self.config.output_len) {
                self.config.input_len = input_len;
                self.config.output_len = output_len;
                self.inputs = DpData::zeroed(input_len);
                self.outputs = DpData::zeroed(output_len);
                self.pending_outputs = None;
                self.frozen_inputs = None;
            }
            self.cfg_fault = false;
            self.set_state(DpState::DataExchange);
        } else {
            self.cfg_fault = true;
            self.watchdog = None;
            self.set_state(DpState::WaitPrm);
        }
    }

    fn data_exchange(&mut self, now: Instant, t: &DataRepr<'_>) {
        if self.state != DpState::DataExchange || self.master != Some(t.sa) {
            return self.short(t, fdl::response::SAP_NOT_ACTIVATED);
        }
        let Some(received) = DpData::new(t.data).filter(|d| d.len() == self.config.output_len)
        else {
            return;
        };
        if self.sync_active {
            self.pending_outputs = Some(received);
        } else {
            self.outputs = received;
        }
        self.exchange(now);
        let inputs = self.frozen_inputs.unwrap_or(self.inputs);
        self.reply(t, inputs.as_slice());
    }

    /// One exchange with the application: the outputs in effect in, `self.inputs` out.
    fn exchange(&mut self, now: Instant) {
        self.app
            .exchange(now, self.outputs.as_slice(), self.inputs.as_mut_slice());
    }

    fn global_control(&mut self, now: Instant, t: &DataRepr<'_>) {
        let (Some(&control), Some(&select)) = (t.data.first(), t.data.get(1)) else {
            return;
        };
        if self.state != DpState::DataExchange
            || self.master != Some(t.sa)
            || (select != 0 && select & self.group == 0)
        {
            return;
        }
        if control & 0x02 != 0 {
            // Clear_Data: outputs to zero.
            self.outputs.as_mut_slice().fill(0);
            self.pending_outputs = None;
            self.exchange(now);
        }
        if control & 0x20 != 0 && self.config.sync {
            // Sync: outputs received since take effect now, later ones wait for the next Sync.
            if let Some(pending) = self.pending_outputs.take() {
                self.outputs = pending;
            }
            self.sync_active = true;
            self.exchange(now);
        } else if control & 0x10 != 0 {
            self.sync_active = false;
            if let Some(pending) = self.pending_outputs.take() {
                self.outputs = pending;
            }
        }
        if control & 0x08 != 0 && self.config.freeze {
            self.exchange(now);
            self.frozen_inputs = Some(self.inputs);
        } else if control & 0x04 != 0 {
            self.frozen_inputs = None;
        }
    }

    /// The short acknowledgement.
    fn short_ack(&mut self) {
        self.answer[0] = fdl::SC;
        self.answer_len = Some(1);
    }

    /// An SD1 answer with a response function.
    fn short(&mut self, t: &DataRepr<'_>, function: u8) {
        self.emit_answer(DataRepr {
            da: t.sa,
            sa: self.config.address,
            dsap: None,
            ssap: None,
            fc: function,
            data: &[],
        });
    }

    /// A data answer (DL) with the request's SAPs swapped.
    fn reply(&mut self, t: &DataRepr<'_>, data: &[u8]) {
        self.emit_answer(DataRepr {
            da: t.sa,
            sa: self.config.address,
            dsap: t.ssap,
            ssap: t.dsap,
            fc: fdl::response::DATA_LOW,
            data,
        });
    }

    fn emit_answer(&mut self, answer: DataRepr<'_>) {
        self.answer_len = answer.emit(&mut self.answer).ok();
    }
}
