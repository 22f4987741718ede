//! DP slaves from GSD files: a [`SlaveConfig`] from any GSD's model (its configuration: the
//! modules chosen, else its first module, as a compact station has one), the bundled
//! Goodrive350 card (`eds/goodrive350-dp.gsd`) with its PKW/PZD drive behind it, and
//! [`Loopback`], the application of a slave simulated from any other GSD (its inputs echo its
//! outputs; unless its modules are chosen, it accepts in Chk_Cfg any combination of them its
//! GSD allows, as a drive whose PPO the master picks does).

use std::path::Path;
use std::sync::Arc;

use edsgen_model::model::modules::{choose_dp, match_dp_cfg, ModuleChoice};
use edsgen_model::model::Dp;
use edsgen_runtime::pkw_pzd::ByteOrder;
use edsgen_runtime::Instant;

use crate::drives::pkw_pzd::{Bus, PkwPzdDrive};
use edsgen_runtime::dp::{DpApplication, DpData, DpSlave, SlaveConfig};

/// Where the card's GSD is in the repository.
pub const GSD_PATH: &str = "eds/goodrive350-dp.gsd";
/// The card's GSD bytes.
pub const GSD: &[u8] = include_bytes!("../../../eds/goodrive350-dp.gsd");
/// The card's default station address (Table 2-4: P15.01 defaults to 2).
pub const DEFAULT_ADDRESS: u8 = 2;

/// Why a GSD's model cannot be simulated.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CardError {
    /// The file was not read as GSD.
    NotGsd,
    /// No Ident_Number.
    NoIdentNumber,
    /// No module whose configuration bytes decode.
    NoModule,
    /// An address above 125.
    BadAddress(u8),
    /// Configuration bytes or an I/O length above DP's 244 bytes.
    TooLong,
    /// Modules chosen that the GSD does not allow, each problem a sentence.
    Modules(Vec<String>),
}

impl std::fmt::Display for CardError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CardError::NotGsd => write!(f, "not a GSD file"),
            CardError::NoIdentNumber => write!(f, "the GSD file has no Ident_Number"),
            CardError::NoModule => write!(f, "the GSD file has no module that decodes"),
            CardError::BadAddress(a) => write!(f, "station address {a} is not 0 to 125"),
            CardError::TooLong => write!(f, "the module has more than 244 bytes of data"),
            CardError::Modules(problems) => {
                write!(f, "the modules chosen do not fit: {}", problems.join("; "))
            }
        }
    }
}

impl std::error::Error for CardError {}

/// The slave a GSD describes at `address`: its Ident_Number, its configuration's bytes and
/// lengths ([`Dp::configuration`]: the modules chosen, else its first module), its
/// User_Prm_Data length.
pub fn slave_config(dp: &Dp, address: u8) -> Result<SlaveConfig, CardError> {
    if address > 125 {
        return Err(CardError::BadAddress(address));
    }
    let ident_number = dp
        .ident_number
        .as_ref()
        .ok_or(CardError::NoIdentNumber)?
        .value;
    let configuration = dp.configuration();
    if configuration.slots.is_empty() {
        return Err(CardError::NoModule);
    }
    let (input_len, output_len) = configuration.io_lengths(dp);
    // The slave's own parameter bytes, then its modules' (Ext_Module_Prm_Data_Len).
    let user_prm_len = configuration.user_prm_data(dp).len();
    let too_long = |len: u32| (len as usize > DpData::CAPACITY).then_some(CardError::TooLong);
    if let Some(e) = too_long(input_len).or(too_long(output_len)) {
        return Err(e);
    }
    Ok(SlaveConfig {
        address,
        ident_number,
        config: DpData::new(&configuration.config_bytes(dp)).ok_or(CardError::TooLong)?,
        user_prm_len,
        output_len: output_len as usize,
        input_len: input_len as usize,
        freeze: dp.freeze,
        sync: dp.sync,
    })
}

/// The model of a GSD file's bytes.
pub fn read_gsd(path: &Path, bytes: &[u8]) -> Result<Dp, CardError> {
    edsgen_model::read::read_bytes(path, bytes)
        .device
        .dp()
        .cloned()
        .ok_or(CardError::NotGsd)
}

/// The Goodrive350's DP card: its drive on the 32-byte big-endian images.
#[derive(Debug, Clone)]
pub struct Goodrive350Dp {
    /// The drive.
    pub drive: PkwPzdDrive,
}

impl DpApplication for Goodrive350Dp {
    fn exchange(&mut self, now: Instant, outputs: &[u8], inputs: &mut [u8]) {
        let mut image = [0u8; 32];
        let n = outputs.len().min(32);
        image[..n].copy_from_slice(&outputs[..n]);
        let answer = self.drive.exchange_bytes(now, &image, ByteOrder::BigEndian);
        let n = inputs.len().min(answer.len());
        inputs[..n].copy_from_slice(&answer[..n]);
    }

    fn watchdog_expired(&mut self, now: Instant) {
        self.drive.communication_lost(now);
    }
}

/// The card powered up at `now` at `address`, its drive set up for bus control
/// ([`PkwPzdDrive::bus_controlled`]); its identity and configuration are the code generated
/// from its GSD ([`crate::cards::goodrive350_dp`]).
pub fn goodrive350(address: u8, now: Instant) -> Result<DpSlave<Goodrive350Dp>, CardError> {
    use crate::cards::goodrive350_dp::{self as generated, modules::n_4_pkw_12_pzd as module};
    if address > 125 {
        return Err(CardError::BadAddress(address));
    }
    let config = SlaveConfig {
        address,
        ident_number: generated::IDENT_NUMBER,
        config: DpData::new(&module::CONFIG).ok_or(CardError::TooLong)?,
        user_prm_len: generated::USER_PRM_DATA.len(),
        output_len: module::Outputs::SIZE,
        input_len: module::Inputs::SIZE,
        freeze: generated::FREEZE,
        sync: generated::SYNC,
    };
    let app = Goodrive350Dp {
        drive: PkwPzdDrive::bus_controlled(Bus::ProfibusDp, now),
    };
    Ok(DpSlave::new(config, app, now))
}

/// A slave's application that echoes its outputs as its inputs (cut or zero-padded to the
/// input length): a GSD file says nothing of what the device does.
#[derive(Debug, Clone)]
pub struct Loopback {
    /// Whether the watchdog expired since the last exchange.
    pub watchdog_expired: bool,
    /// The GSD whose modules Chk_Cfg may combine as it allows (a slave whose modules the
    /// master picks); `None`: only the slave's own configuration is accepted (modules
    /// plugged, as in an I/O station).
    pub modular: Option<Arc<Dp>>,
    /// With `modular`: the bytes of module parameters the last Set_Prm carried after the
    /// slave's own, which the modules Chk_Cfg then names must take.
    pub module_prm_len: usize,
}

impl DpApplication for Loopback {
    fn exchange(&mut self, _now: Instant, outputs: &[u8], inputs: &mut [u8]) {
        self.watchdog_expired = false;
        inputs.fill(0);
        let n = outputs.len().min(inputs.len());
        inputs[..n].copy_from_slice(&outputs[..n]);
    }

    fn watchdog_expired(&mut self, _now: Instant) {
        self.watchdog_expired = true;
    }

    fn check_config(&mut self, own: &SlaveConfig, config: &[u8]) -> Option<(usize, usize)> {
        let Some(dp) = &self.modular else {
            return (config == own.config.as_slice()).then_some((own.input_len, own.output_len));
        };
        let configuration = match_dp_cfg(dp, config)?;
        if configuration.module_prm_data(dp).len() != self.module_prm_len {
            return None;
        }
        let (input_len, output_len) = configuration.io_lengths(dp);
        Some((input_len as usize, output_len as usize))
    }

    /// Plugged: exactly its own and its modules' parameters. Modular (the master picks the
    /// modules): its own, then any modules' (Chk_Cfg's modules must then take them).
    fn check_prm(&mut self, own: &SlaveConfig, user_prm: &[u8]) -> bool {
        let Some(dp) = &self.modular else {
            return user_prm.len() == own.user_prm_len;
        };
        let Some(modules) = user_prm.len().checked_sub(dp.own_prm_data().len()) else {
            return false;
        };
        self.module_prm_len = modules;
        true
    }
}

/// The application of a simulated slave: the card's drive or a GSD file's echo (so that one
/// line can carry both).
#[derive(Debug, Clone)]
pub enum Simulated {
    /// The Goodrive350 card.
    Card(Goodrive350Dp),
    /// A slave from a GSD file.
    Loopback(Loopback),
}

impl DpApplication for Simulated {
    fn exchange(&mut self, now: Instant, outputs: &[u8], inputs: &mut [u8]) {
        match self {
            Simulated::Card(card) => card.exchange(now, outputs, inputs),
            Simulated::Loopback(echo) => echo.exchange(now, outputs, inputs),
        }
    }

    fn watchdog_expired(&mut self, now: Instant) {
        match self {
            Simulated::Card(card) => card.watchdog_expired(now),
            Simulated::Loopback(echo) => echo.watchdog_expired(now),
        }
    }

    fn check_config(&mut self, own: &SlaveConfig, config: &[u8]) -> Option<(usize, usize)> {
        match self {
            Simulated::Card(card) => card.check_config(own, config),
            Simulated::Loopback(echo) => echo.check_config(own, config),
        }
    }

    fn check_prm(&mut self, own: &SlaveConfig, user_prm: &[u8]) -> bool {
        match self {
            Simulated::Card(card) => card.check_prm(own, user_prm),
            Simulated::Loopback(echo) => echo.check_prm(own, user_prm),
        }
    }
}

/// A slave simulated from any GSD's model at `address`, echoing its outputs. With `modules`
/// chosen (`--module`, the overlay's `[modules]`), it is plugged with them and accepts only
/// them; without, it starts with [`Dp::configuration`] and accepts any combination of its
/// modules the GSD allows.
pub fn loopback(
    dp: &Dp,
    modules: &[ModuleChoice],
    address: u8,
    now: Instant,
) -> Result<DpSlave<Loopback>, CardError> {
    let mut dp = dp.clone();
    if !modules.is_empty() {
        dp.chosen = Some(choose_dp(&dp, modules).map_err(CardError::Modules)?);
    }
    let config = slave_config(&dp, address)?;
    let app = Loopback {
        watchdog_expired: false,
        modular: dp.chosen.is_none().then(|| Arc::new(dp)),
        module_prm_len: 0,
    };
    Ok(DpSlave::new(config, app, now))
}

#[cfg(test)]
mod modular_tests;
#[cfg(test)]
mod tests;
