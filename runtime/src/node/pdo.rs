//! PDO state: the mapping a PDO packs or unpacks, the receive and transmit PDOs' configuration as
//! read from 1400h–1BFFh, and the checks a mapping entry must pass (CiA 301 §7.4.7).
//!
//! Mappings are byte-granular: each mapped object takes its whole size in whole bytes (a mapping
//! length that is not a multiple of 8 is refused with 0604 0041). At most [`MAX_MAPPED`] objects
//! per PDO.

mod mapping;
mod params;
mod rpdo;
mod tpdo;

pub use mapping::MAX_MAPPED;
pub(crate) use mapping::{check_mapping, Mapping};
pub(crate) use rpdo::Rpdo;
pub(crate) use tpdo::Tpdo;

use crate::time::{Duration, Instant};

/// Arms a PDO's timer `slot` (a TPDO's event timer, an RPDO's deadline) to run out `ms`
/// milliseconds after `now`, or disarms it if `ms` is 0 (the timer is off). One out-of-line
/// copy for both directions.
#[inline(never)]
fn arm_timer(slot: &mut Option<Instant>, now: Instant, ms: u16) {
    *slot = (ms != 0).then(|| now + Duration::from_millis(u64::from(ms)));
}
