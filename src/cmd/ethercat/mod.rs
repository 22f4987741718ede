//! The EtherCAT commands: [`ecat`] (feature `ethercrab`) is the master at the bench, [`sii`]
//! writes a device's EEPROM image, [`simulate`] serves a SubDevice (`edsgen simulate --ethercat`).

#[cfg(feature = "ethercrab")]
pub mod ecat;
pub mod sii;
pub mod simulate;

/// What `edsgen ecat` says in a build without the `ethercrab` feature.
#[cfg(not(feature = "ethercrab"))]
pub const NOT_BUILT: &str = "error: `edsgen ecat` is not in this build: it needs the `ethercrab` \
     feature (cargo install edsgen --features ethercrab, or cargo build --release --features \
     ethercrab)";
