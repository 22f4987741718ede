//! The EtherCAT application-layer (AL) state machine's states, status codes and the rule for
//! which requested transitions a SubDevice takes (ETG.1000.6 §6.4.1): Init ↔ Pre-Op ↔ Safe-Op ↔
//! Op step by step up, any step down; Bootstrap is not offered. What each upward step needs
//! (mailbox, process-data SyncManagers) is checked by the SubDevice, which knows its
//! configuration; this module says only whether the step itself is allowed.

/// An AL state, as the low 4 bits of AL control (0x0120) and AL status (0x0130) code it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
#[repr(u8)]
pub enum AlState {
    /// 1: Init.
    Init = 1,
    /// 2: Pre-Operational (mailbox).
    PreOp = 2,
    /// 4: Safe-Operational (mailbox, inputs).
    SafeOp = 4,
    /// 8: Operational (mailbox, inputs, outputs).
    Op = 8,
}

impl AlState {
    /// The state's code.
    pub fn code(self) -> u8 {
        self as u8
    }
}

/// AL status codes (register 0x0134) from ETG.1000.6 table 11 that this SubDevice gives.
pub mod code {
    /// No error.
    pub const NO_ERROR: u16 = 0x0000;
    /// Invalid requested state change.
    pub const INVALID_STATE_CHANGE: u16 = 0x0011;
    /// Unknown requested state.
    pub const UNKNOWN_STATE: u16 = 0x0012;
    /// Bootstrap not supported.
    pub const BOOTSTRAP_NOT_SUPPORTED: u16 = 0x0013;
    /// Invalid mailbox configuration (Pre-Op).
    pub const INVALID_MAILBOX_CONFIG: u16 = 0x0016;
    /// Sync manager watchdog.
    pub const SM_WATCHDOG: u16 = 0x001B;
    /// Invalid output configuration.
    pub const INVALID_OUTPUT_CONFIG: u16 = 0x001D;
    /// Invalid input configuration.
    pub const INVALID_INPUT_CONFIG: u16 = 0x001E;
    /// The SII (EEPROM) is not offered to the device, which has not read it yet.
    pub const EEPROM_NO_ACCESS: u16 = 0x0050;
    /// The SII (EEPROM) could not be read.
    pub const EEPROM_ERROR: u16 = 0x0051;
}

/// What a request written to AL control asks, before the configuration is checked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Request {
    /// Stay where it is (the requested state is the current one).
    Stay,
    /// Go to this state (a step up needs the SubDevice's checks first).
    Go(AlState),
    /// Refused with this AL status code.
    Refuse(u16),
}

/// The request `requested` (AL control's low 4 bits) in state `current`.
pub fn request(current: AlState, requested: u8) -> Request {
    let target = match requested {
        1 => AlState::Init,
        2 => AlState::PreOp,
        4 => AlState::SafeOp,
        8 => AlState::Op,
        3 => return Request::Refuse(code::BOOTSTRAP_NOT_SUPPORTED),
        _ => return Request::Refuse(code::UNKNOWN_STATE),
    };
    use AlState::*;
    match (current, target) {
        (a, b) if a == b => Request::Stay,
        // Down: always.
        (a, b) if b < a => Request::Go(b),
        // Up: one step at a time.
        (Init, PreOp) | (PreOp, SafeOp) | (SafeOp, Op) => Request::Go(target),
        _ => Request::Refuse(code::INVALID_STATE_CHANGE),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use AlState::*;

    #[test]
    fn up_one_step_at_a_time_and_down_at_will() {
        assert_eq!(request(Init, 2), Request::Go(PreOp));
        assert_eq!(request(PreOp, 4), Request::Go(SafeOp));
        assert_eq!(request(SafeOp, 8), Request::Go(Op));
        assert_eq!(request(Op, 1), Request::Go(Init));
        assert_eq!(request(Op, 2), Request::Go(PreOp));
        assert_eq!(request(SafeOp, 2), Request::Go(PreOp));
        assert_eq!(request(Op, 8), Request::Stay);
    }

    #[test]
    fn skipped_unknown_and_bootstrap_requests_are_refused_with_their_codes() {
        assert_eq!(request(Init, 4), Request::Refuse(0x0011));
        assert_eq!(request(Init, 8), Request::Refuse(0x0011));
        assert_eq!(request(PreOp, 8), Request::Refuse(0x0011));
        assert_eq!(request(Init, 3), Request::Refuse(0x0013));
        assert_eq!(request(Init, 5), Request::Refuse(0x0012));
        assert_eq!(request(PreOp, 0), Request::Refuse(0x0012));
    }
}
