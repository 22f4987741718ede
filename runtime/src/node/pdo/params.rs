//! What a PDO of either direction reads from the OD: its communication parameter (1400h–15FFh,
//! 1800h–19FFh) and its checked mapping (1600h–17FFh, 1A00h–1BFFh), in one routine for both.

use crate::node::{read_uint, read_uint_or};
use crate::od::{ObjectDictionary, SdoAbort};
use crate::wire::pdo::CobIdEntry;

use super::mapping::{check_mapping, Mapping};

/// A PDO's configuration as read. A receive PDO has no inhibit time, SYNC start value or RTR
/// bit (CiA 301 §7.5.2.35): those fields keep what the OD holds and go unused.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PdoParams {
    /// Whether the PDO exists and is valid (and its mapping passed the checks).
    pub enabled: bool,
    pub cob_id: u16,
    /// Bit 30 of the COB-ID is clear: a TPDO answers remote requests.
    pub rtr_allowed: bool,
    /// Sub 02h.
    pub transmission: u8,
    /// Sub 06h.
    pub sync_start: u8,
    /// Sub 03h (100 µs) and sub 05h (ms), UNSIGNED16 both (CiA 301 §7.5.2.35): 16 bits each
    /// rather than 64-bit `Duration`s.
    pub inhibit_100us: u16,
    pub event_timer_ms: u16,
    pub mapping: Mapping,
}

impl PdoParams {
    /// Nothing configured.
    pub const OFF: PdoParams = PdoParams {
        enabled: false,
        cob_id: 0,
        rtr_allowed: false,
        transmission: 0,
        sync_start: 0,
        inhibit_100us: 0,
        event_timer_ms: 0,
        mapping: Mapping::EMPTY,
    };

    /// Reads the communication parameter at `comm` (1400h + n or 1800h + n) and the mapping
    /// 200h above it into these parameters, which are [`PdoParams::OFF`]. Returns why the
    /// mapping was refused if the COB-ID is valid (the PDO is then not served).
    pub fn load<O: ObjectDictionary + ?Sized>(&mut self, od: &O, comm: u16) -> Option<SdoAbort> {
        let cob = CobIdEntry(read_uint(od, comm, 1)?);
        self.cob_id = cob.can_id();
        self.rtr_allowed = !cob.bit30();
        self.transmission = read_uint_or(od, comm, 2, 255) as u8;
        self.inhibit_100us = read_uint_or(od, comm, 3, 0) as u16;
        self.event_timer_ms = read_uint_or(od, comm, 5, 0) as u16;
        self.sync_start = read_uint_or(od, comm, 6, 0) as u8;
        let map = comm + 0x200;
        let checked = read_uint(od, map, 0)
            .ok_or(SdoAbort::NoObject)
            .and_then(|count| check_mapping(od, map, 0, count, &mut self.mapping));
        match checked {
            Ok(()) => {
                self.enabled = cob.valid() && !cob.extended();
                None
            }
            Err(reason) => cob.valid().then_some(reason),
        }
    }
}
