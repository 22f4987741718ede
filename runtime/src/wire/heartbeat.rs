//! Error-control frame layout (CiA 301 §7.2.8.3.2): COB-ID 700h + node-ID, one byte. The same
//! layout carries the boot-up message (state 00h), the heartbeat (toggle bit 0) and the answer to
//! a node-guarding remote request (bit 7 the toggle bit, bits 0–6 the NMT state).

/// The function code of error control: the COB-ID is this plus the node-ID.
pub const ERROR_CONTROL_BASE: u16 = 0x700;

/// NMT states as the error-control byte encodes them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NmtState {
    /// Initialising (00h): sent only as the boot-up message.
    Initialising,
    /// Stopped (04h).
    Stopped,
    /// Operational (05h).
    Operational,
    /// Pre-operational (7Fh).
    PreOperational,
}

impl NmtState {
    /// The 7-bit state code.
    #[inline]
    pub const fn code(self) -> u8 {
        match self {
            NmtState::Initialising => 0x00,
            NmtState::Stopped => 0x04,
            NmtState::Operational => 0x05,
            NmtState::PreOperational => 0x7F,
        }
    }

    /// The state for a 7-bit code, or `None` for an unknown one.
    pub const fn from_code(code: u8) -> Option<Self> {
        Some(match code {
            0x00 => NmtState::Initialising,
            0x04 => NmtState::Stopped,
            0x05 => NmtState::Operational,
            0x7F => NmtState::PreOperational,
            _ => return None,
        })
    }
}

/// An error-control message: boot-up, heartbeat or node-guarding answer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ErrorControlRepr {
    /// The sender's NMT state.
    pub state: NmtState,
    /// The toggle bit (node guarding only; always `false` in heartbeats and boot-up).
    pub toggle: bool,
}

impl ErrorControlRepr {
    /// The boot-up message.
    pub const BOOT_UP: ErrorControlRepr = ErrorControlRepr {
        state: NmtState::Initialising,
        toggle: false,
    };

    /// Parses the data bytes. `None` unless there is exactly one byte with a known state.
    pub fn parse(data: &[u8]) -> Option<Self> {
        match *data {
            [byte] => Some(ErrorControlRepr {
                state: NmtState::from_code(byte & 0x7F)?,
                toggle: byte & 0x80 != 0,
            }),
            _ => None,
        }
    }

    /// The data byte.
    #[inline]
    pub const fn emit(&self) -> u8 {
        self.state.code() | if self.toggle { 0x80 } else { 0 }
    }

    /// The COB-ID for the node `node_id`.
    #[inline]
    pub const fn cob_id(node_id: u8) -> u16 {
        ERROR_CONTROL_BASE + node_id as u16
    }

    /// The node-ID (1..=127) whose error-control COB-ID `id` is, if it is one.
    #[inline]
    pub const fn node_of(id: u16) -> Option<u8> {
        match id.wrapping_sub(ERROR_CONTROL_BASE) {
            node @ 1..=127 => Some(node as u8),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_node_of_an_error_control_cob_id_is_1_to_127() {
        assert_eq!(ErrorControlRepr::node_of(0x703), Some(3));
        assert_eq!(ErrorControlRepr::node_of(0x77F), Some(127));
        assert_eq!(ErrorControlRepr::node_of(0x700), None);
        assert_eq!(ErrorControlRepr::node_of(0x780), None);
        assert_eq!(ErrorControlRepr::node_of(0x083), None);
    }

    #[test]
    fn goodrive350_guarding_answers() {
        let first = ErrorControlRepr {
            state: NmtState::Operational,
            toggle: true,
        };
        assert_eq!(first.emit(), 0x85);
        let second = ErrorControlRepr {
            toggle: false,
            ..first
        };
        assert_eq!(second.emit(), 0x05);
        assert_eq!(ErrorControlRepr::parse(&[0x85]), Some(first));
        assert_eq!(ErrorControlRepr::cob_id(3), 0x703);
    }

    #[test]
    fn boot_up_is_zero_and_pre_operational_is_7f() {
        assert_eq!(ErrorControlRepr::BOOT_UP.emit(), 0x00);
        let pre_op = ErrorControlRepr {
            state: NmtState::PreOperational,
            toggle: false,
        };
        assert_eq!(pre_op.emit(), 0x7F);
    }

    #[test]
    fn unknown_state_or_length_is_rejected() {
        assert_eq!(ErrorControlRepr::parse(&[0x06]), None);
        assert_eq!(ErrorControlRepr::parse(&[]), None);
        assert_eq!(ErrorControlRepr::parse(&[0x05, 0x00]), None);
    }
}
