//! The EC-TX508 EtherCAT card in a Goodrive350 as a simulated device: the runtime's CiA 402
//! [`Drive`] in cyclic synchronous velocity behind the card's generated process images. Each
//! cycle the outputs image (SM2, RxPDO 1600h: controlword, 6060h, 60FFh...) goes in as bytes,
//! the drive runs one cycle, and its statusword, 6061h and 606Ch come out as the inputs image
//! (SM3, TxPDO 1A00h). Sans-IO: the caller carries the images and the time, as an EtherCAT
//! master's cyclic exchange (or a test) does.
//!
//! Choices where the ESI file is silent: a drive of 3000 rpm whose ramps (604Fh, 6050h 1 s)
//! move 3 rpm per ms, and whose fault reaction (605Eh 2, 6051h 100 ms) stops at 30 rpm per ms;
//! velocity mode (2) in effect at power-up, csv (9) offered. 60FFh beyond the drive's INTEGER16
//! velocity is clamped; the image's other outputs (607Ah, 6071h, 6072h, 6081h, 60B8h) are not
//! used, and the inputs it has no value for (6064h, 6077h, 60F4h, 60B9h, 60BAh) stay 0.

use edsgen_runtime::cia402::{Drive, DriveConfig};
use edsgen_runtime::{Instant, PdoError};

use crate::cards::ec_tx508::ethercat::{Inputs, Outputs, TxPdo1A00};

/// Where the card's ESI file is in the repository.
pub const ESI_PATH: &str = "eds/ec-tx508.xml";
/// The ESI file's bytes.
pub const ESI: &[u8] = include_bytes!("../../../eds/ec-tx508.xml");

/// The simulated EC-TX508 (see the module comment).
#[derive(Debug, Clone)]
pub struct EcTx508 {
    drive: Drive,
}

impl EcTx508 {
    /// The drive powered up at `now`: switch on disabled, velocity mode shown.
    pub fn new(now: Instant) -> Self {
        let mut config = DriveConfig::new(3000);
        config.ramp_time_ms = 1_000;
        config.slow_down_time_ms = 1_000;
        config.quick_stop_time_ms = 100;
        config.cyclic_velocity = true;
        EcTx508 {
            drive: Drive::new(config, now),
        }
    }

    /// The inputs image the device shows now (before any cycle: the power-up state).
    pub fn inputs(&self) -> [u8; Inputs::SIZE] {
        let drive = &self.drive;
        Inputs {
            tx_pdo_1a00: TxPdo1A00 {
                status_word: drive.statusword(),
                actual_speed: i32::from(drive.velocity_actual()),
                operation_mode_display: drive.mode(),
                ..TxPdo1A00::default()
            },
        }
        .to_bytes()
    }

    /// One cycle at `now`: the outputs image in (decoded by the 1600h mapping; an image of the
    /// wrong length is refused and the drive left as it was), the drive run, the inputs image
    /// out.
    pub fn cycle(&mut self, now: Instant, outputs: &[u8]) -> Result<[u8; Inputs::SIZE], PdoError> {
        let rx = Outputs::from_slice(outputs)?.rx_pdo_1600;
        self.drive.set_mode(now, rx.operation_mode);
        let target = rx.target_speed.clamp(i16::MIN.into(), i16::MAX.into()) as i16;
        if target != self.drive.target() {
            self.drive.set_target(now, target);
        }
        self.drive.set_controlword(now, rx.control_word);
        self.drive.update(now);
        Ok(self.inputs())
    }

    /// The drive, to look at its state.
    pub fn drive(&self) -> &Drive {
        &self.drive
    }

    /// The drive, to raise and clear faults as the application would.
    pub fn drive_mut(&mut self) -> &mut Drive {
        &mut self.drive
    }
}
