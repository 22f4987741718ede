//! The DP slave's state machine (EN 50170 / IEC 61158 DP-V0), sans-IO: telegram bytes and the
//! time in, the answer's bytes out (or none: a slave says nothing to a broadcast, to a telegram
//! for another station, to a bad one, or to a SAP it does not serve).
//!
//! Wait_Prm → (Set_Prm with this slave's Ident_Number and parameters) → Wait_Cfg → (Chk_Cfg
//! with its configuration bytes) → Data_Exchange. Slave_Diag answers the six standard bytes at
//! any time; Get_Cfg the configuration. A wrong Ident_Number or parameter length sets
//! Prm_Fault, a wrong configuration Cfg_Fault, both back in Wait_Prm. Global_Control's Sync
//! latches outputs until the next Sync, Freeze holds inputs until the next Freeze, Clear_Data
//! zeroes the outputs. The watchdog Set_Prm switches on leaves Data_Exchange when no telegram
//! came in time, and tells the application ([`DpApplication::watchdog_expired`]).
//!
//! FCB/FCV: a request whose frame count bit equals the last one from the same master (with FCV
//! set) is a repetition: the stored answer goes again and nothing is executed twice.

use edsgen_runtime::{Duration, Instant};

use super::fdl::{self, DataTelegram, Telegram};

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

/// What sits behind the slave: the cyclic data's owner.
pub trait DpApplication {
    /// One exchange at `now`: the outputs (master to slave) in, the inputs out.
    fn exchange(&mut self, now: Instant, outputs: &[u8]) -> Vec<u8>;
    /// The DP watchdog expired at `now`: the master is gone.
    fn watchdog_expired(&mut self, now: Instant);
}

/// What the slave is: from its GSD.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SlaveConfig {
    /// The station address.
    pub address: u8,
    /// Ident_Number.
    pub ident_number: u16,
    /// The configuration bytes Chk_Cfg must carry (and Get_Cfg answers).
    pub config: Vec<u8>,
    /// Bytes of User_Prm_Data Set_Prm must carry after its seven standard bytes.
    pub user_prm_len: usize,
    /// Output bytes of Data_Exchange (master to slave).
    pub output_len: usize,
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
    freeze_active: bool,
    /// Outputs in effect (latched by Sync in sync mode).
    outputs: Vec<u8>,
    /// Outputs received in sync mode, waiting for the next Sync.
    pending_outputs: Option<Vec<u8>>,
    frozen_inputs: Option<Vec<u8>>,
    /// The last request's (master, FCB) and answer, for repetitions.
    last: Option<(u8, bool, Option<Vec<u8>>)>,
}

impl<A: DpApplication> DpSlave<A> {
    /// A slave just powered up, in Wait_Prm.
    pub fn new(config: SlaveConfig, app: A, now: Instant) -> Self {
        let outputs = vec![0; config.output_len];
        DpSlave {
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
            freeze_active: false,
            outputs,
            pending_outputs: None,
            frozen_inputs: None,
            last: None,
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
            self.app.watchdog_expired(now);
        }
    }

    /// Handles one received telegram's bytes at `now`; the answer's bytes, if any.
    pub fn handle(&mut self, now: Instant, bytes: &[u8]) -> Option<Vec<u8>> {
        let Ok((Telegram::Data(t), used)) = fdl::parse(bytes) else {
            return None;
        };
        if used != bytes.len() || !t.is_request() {
            return None;
        }
        let broadcast = t.da == fdl::BROADCAST;
        if t.da != self.config.address && !broadcast {
            return None;
        }
        self.handle_timeout(now);
        if let (Some(fcb), Some((sa, last_fcb, answer))) = (t.fcb(), &self.last) {
            if *sa == t.sa && *last_fcb == fcb {
                return answer.clone();
            }
        }
        let answer = self.serve(now, &t, broadcast);
        if let Some(fcb) = t.fcb() {
            self.last = Some((t.sa, fcb, answer.clone()));
        }
        if (answer.is_some() || broadcast) && self.master.is_none_or(|m| m == t.sa) {
            self.last_seen = now;
        }
        answer
    }

    fn serve(&mut self, now: Instant, t: &DataTelegram, broadcast: bool) -> Option<Vec<u8>> {
        use fdl::request::*;
        let function = t.function();
        match (t.dsap, function) {
            (None, FDL_STATUS) if !broadcast => self.short(t, fdl::response::OK),
            (None, SRD_LOW | SRD_HIGH) if !broadcast => self.data_exchange(now, t),
            (Some(sap::GLOBAL_CONTROL), SDN_LOW | SDN_HIGH | SDA_LOW | SDA_HIGH) => {
                self.global_control(now, t);
                None
            }
            (Some(_), _) if broadcast => None,
            (Some(sap::SLAVE_DIAG), SRD_LOW | SRD_HIGH) => {
                let diag = self.diagnosis();
                self.reply(t, diag)
            }
            (Some(sap::SET_PRM), SRD_LOW | SRD_HIGH | SDA_LOW | SDA_HIGH) => {
                self.set_prm(t);
                Some(vec![fdl::SC])
            }
            (Some(sap::CHK_CFG), SRD_LOW | SRD_HIGH | SDA_LOW | SDA_HIGH) => {
                self.chk_cfg(t);
                Some(vec![fdl::SC])
            }
            (Some(sap::GET_CFG), SRD_LOW | SRD_HIGH) => {
                let config = self.config.config.clone();
                self.reply(t, config)
            }
            _ => None,
        }
    }

    /// The six standard diagnosis bytes.
    pub fn diagnosis(&self) -> Vec<u8> {
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
        if self.freeze_active {
            b2 |= diag2::FREEZE;
        }
        if self.sync_active {
            b2 |= diag2::SYNC;
        }
        let [hi, lo] = self.config.ident_number.to_be_bytes();
        vec![b1, b2, 0, self.master.unwrap_or(0xFF), hi, lo]
    }

    fn set_prm(&mut self, t: &DataTelegram) {
        let data = &t.data;
        let ident = data.get(4..6).map(|b| u16::from_be_bytes([b[0], b[1]]));
        let status = data.first().copied().unwrap_or(0);
        let freeze = status & 0x10 != 0;
        let sync = status & 0x20 != 0;
        let ok = data.len() == 7 + self.config.user_prm_len
            && ident == Some(self.config.ident_number)
            && (!freeze || self.config.freeze)
            && (!sync || self.config.sync);
        self.cfg_fault = false;
        if !ok {
            self.prm_fault = true;
            self.state = DpState::WaitPrm;
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
        self.freeze_active = false;
        self.pending_outputs = None;
        self.frozen_inputs = None;
        self.state = DpState::WaitCfg;
    }

    fn chk_cfg(&mut self, t: &DataTelegram) {
        if self.state == DpState::WaitPrm || self.master != Some(t.sa) {
            return;
        }
        if t.data == self.config.config {
            self.cfg_fault = false;
            self.state = DpState::DataExchange;
        } else {
            self.cfg_fault = true;
            self.watchdog = None;
            self.state = DpState::WaitPrm;
        }
    }

    fn data_exchange(&mut self, now: Instant, t: &DataTelegram) -> Option<Vec<u8>> {
        if self.state != DpState::DataExchange || self.master != Some(t.sa) {
            return self.short(t, fdl::response::SAP_NOT_ACTIVATED);
        }
        if t.data.len() != self.config.output_len {
            return None;
        }
        if self.sync_active {
            self.pending_outputs = Some(t.data.clone());
        } else {
            self.outputs.clone_from(&t.data);
        }
        let inputs = self.app.exchange(now, &self.outputs);
        let inputs = self.frozen_inputs.clone().unwrap_or(inputs);
        self.reply(t, inputs)
    }

    fn global_control(&mut self, now: Instant, t: &DataTelegram) {
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
            self.outputs.iter_mut().for_each(|b| *b = 0);
            self.pending_outputs = None;
            self.app.exchange(now, &self.outputs);
        }
        if control & 0x20 != 0 && self.config.sync {
            // Sync: outputs received since take effect now, later ones wait for the next Sync.
            if let Some(pending) = self.pending_outputs.take() {
                self.outputs = pending;
            }
            self.sync_active = true;
            self.app.exchange(now, &self.outputs);
        } else if control & 0x10 != 0 {
            self.sync_active = false;
            if let Some(pending) = self.pending_outputs.take() {
                self.outputs = pending;
            }
        }
        if control & 0x08 != 0 && self.config.freeze {
            self.freeze_active = true;
            self.frozen_inputs = Some(self.app.exchange(now, &self.outputs));
        } else if control & 0x04 != 0 {
            self.freeze_active = false;
            self.frozen_inputs = None;
        }
    }

    /// An SD1 answer with a response function.
    fn short(&self, t: &DataTelegram, function: u8) -> Option<Vec<u8>> {
        DataTelegram {
            da: t.sa,
            sa: self.config.address,
            dsap: None,
            ssap: None,
            fc: function,
            data: Vec::new(),
        }
        .emit()
    }

    /// A data answer (DL) with the request's SAPs swapped.
    fn reply(&self, t: &DataTelegram, data: Vec<u8>) -> Option<Vec<u8>> {
        DataTelegram {
            da: t.sa,
            sa: self.config.address,
            dsap: t.ssap,
            ssap: t.dsap,
            fc: fdl::response::DATA_LOW,
            data,
        }
        .emit()
    }
}

#[cfg(test)]
mod tests;
