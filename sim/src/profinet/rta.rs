//! The acyclic transport both ends of an AlarmCR keep for each priority is the runtime's
//! ([`edsgen_runtime::profinet::rta`]); here it keeps its frames in `Vec`s. The device's
//! machine ([`super::alarm`]) and the controller's ([`super::controller_alarm`]) share it.

pub use edsgen_runtime::profinet::rta::{Due, Receipt};

/// A DATA PDU sent and not acknowledged yet, its frame a `Vec`.
pub type Pending = edsgen_runtime::profinet::rta::Pending<Vec<u8>>;

/// One priority's transport state, its pending frame a `Vec`.
pub type Transport = edsgen_runtime::profinet::rta::Transport<Vec<u8>>;
