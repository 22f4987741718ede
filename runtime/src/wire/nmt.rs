//! NMT module-control frame layout (CiA 301 §7.2.8.3.1): COB-ID 000h, two bytes, the command
//! specifier then the addressed node-ID (0 addresses every node).

/// An NMT command specifier.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NmtCommand {
    /// Start remote node (01h): enter operational.
    Start,
    /// Stop remote node (02h): enter stopped.
    Stop,
    /// Enter pre-operational (80h).
    EnterPreOperational,
    /// Reset node (81h): application and communication parameters.
    ResetNode,
    /// Reset communication (82h): communication parameters only.
    ResetCommunication,
}

impl NmtCommand {
    /// The command specifier byte.
    pub const fn specifier(self) -> u8 {
        match self {
            NmtCommand::Start => 0x01,
            NmtCommand::Stop => 0x02,
            NmtCommand::EnterPreOperational => 0x80,
            NmtCommand::ResetNode => 0x81,
            NmtCommand::ResetCommunication => 0x82,
        }
    }

    /// The command for a specifier byte, or `None` for an unknown one.
    #[inline]
    pub const fn from_specifier(cs: u8) -> Option<Self> {
        Some(match cs {
            0x01 => NmtCommand::Start,
            0x02 => NmtCommand::Stop,
            0x80 => NmtCommand::EnterPreOperational,
            0x81 => NmtCommand::ResetNode,
            0x82 => NmtCommand::ResetCommunication,
            _ => return None,
        })
    }
}

/// The COB-ID of NMT module control.
pub const NMT_COB_ID: u16 = 0x000;

/// An NMT module-control message.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct NmtRepr {
    /// What to do.
    pub command: NmtCommand,
    /// The addressed node, or 0 for all nodes.
    pub node_id: u8,
}

impl NmtRepr {
    /// Parses the data bytes of a frame received on COB-ID 000h. `None` unless the frame has
    /// exactly two bytes and a known command specifier.
    #[inline]
    pub fn parse(data: &[u8]) -> Option<Self> {
        match *data {
            [cs, node_id] => Some(NmtRepr {
                command: NmtCommand::from_specifier(cs)?,
                node_id,
            }),
            _ => None,
        }
    }

    /// The two data bytes.
    pub const fn emit(&self) -> [u8; 2] {
        [self.command.specifier(), self.node_id]
    }

    /// Whether the command addresses the node `node_id` (directly or by broadcast).
    #[inline]
    pub const fn addresses(&self, node_id: u8) -> bool {
        self.node_id == 0 || self.node_id == node_id
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn goodrive350_pre_operational_to_node_3() {
        let repr = NmtRepr::parse(&[0x80, 0x03]).unwrap();
        assert_eq!(repr.command, NmtCommand::EnterPreOperational);
        assert_eq!(repr.node_id, 3);
        assert!(repr.addresses(3));
        assert!(!repr.addresses(4));
        assert_eq!(repr.emit(), [0x80, 0x03]);
    }

    #[test]
    fn goodrive350_start_all_nodes_is_broadcast() {
        let repr = NmtRepr::parse(&[0x01, 0x00]).unwrap();
        assert_eq!(repr.command, NmtCommand::Start);
        assert!(repr.addresses(3) && repr.addresses(127));
    }

    #[test]
    fn wrong_length_or_unknown_specifier_is_rejected() {
        assert_eq!(NmtRepr::parse(&[0x01]), None);
        assert_eq!(NmtRepr::parse(&[0x01, 0x03, 0x00]), None);
        assert_eq!(NmtRepr::parse(&[0x03, 0x03]), None);
    }
}
