//! The EtherCAT commands: [`ecat`] (feature `ethercrab`) is the master at the bench, [`sii`]
//! writes a device's EEPROM image, [`simulate`] serves a SubDevice (`edsgen simulate --ethercat`).

#[cfg(feature = "ethercrab")]
pub mod ecat;
pub mod sii;
pub mod simulate;
