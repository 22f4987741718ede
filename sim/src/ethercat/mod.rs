//! EtherCAT SubDevices simulated from their descriptions, sans-IO (ETG.1000), on the runtime's wire
//! views, SubDevice core and CoE SDO server (`edsgen_runtime::ethercat`): frames as a MainDevice
//! builds and reads them ([`frame`]), the emulated ESC's registers and memory and what each
//! datagram does to them ([`esc`]), the SubDevice that answers frames with the runtime's core
//! behind that ESC ([`subdevice`]), SubDevices in line ([`segment`]), the application of any ESI
//! device ([`device`]) and its process images ([`image`]), a modular one with its modules plugged
//! ([`modules`]), and the EC-TX508's drive behind it ([`ec_tx508`]); on a wire, [`raw_socket`] and
//! [`serve`].

pub mod device;
pub mod ec_tx508;
pub mod esc;
pub mod frame;
pub mod image;
pub mod modules;
pub mod raw_socket;
pub mod segment;
pub mod serve;
pub mod subdevice;

#[cfg(test)]
mod segment_tests;
#[cfg(test)]
mod tests;

pub use device::{Behaviour, EsiDevice};
pub use edsgen_runtime::ethercat::al::{self, AlState};
pub use segment::Segment;
pub use subdevice::{Application, Layout, SubDevice};
