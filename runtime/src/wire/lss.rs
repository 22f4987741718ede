//! LSS frame layouts (CiA 305): COB-ID 7E5h master to slave and 7E4h slave to master, always
//! eight bytes, the command specifier first. [`LssRequest`] is what a master sends,
//! [`LssResponse`] what a slave answers; both parse and emit exact bytes.

/// The COB-ID of LSS requests (master to slave).
pub const LSS_REQUEST_COB_ID: u16 = 0x7E5;
/// The COB-ID of LSS responses (slave to master).
pub const LSS_RESPONSE_COB_ID: u16 = 0x7E4;
/// The node-ID of a non-configured LSS slave.
pub const UNCONFIGURED_NODE_ID: u8 = 0xFF;
/// The BitChecked value of a fastscan request that resets every slave's LSS-ID sub-state.
pub const FASTSCAN_RESET: u8 = 0x80;

/// Command specifiers.
pub mod cs {
    /// Switch state global.
    pub const SWITCH_GLOBAL: u8 = 0x04;
    /// Switch state selective: vendor-ID (then product 41h, revision 42h, serial 43h).
    pub const SWITCH_SELECTIVE_VENDOR: u8 = 0x40;
    /// Switch state selective: serial number, the last of the four.
    pub const SWITCH_SELECTIVE_SERIAL: u8 = 0x43;
    /// Switch state selective: the slave's answer.
    pub const SWITCH_SELECTIVE_ANSWER: u8 = 0x44;
    /// Configure node-ID.
    pub const CONFIGURE_NODE_ID: u8 = 0x11;
    /// Configure bit timing parameters.
    pub const CONFIGURE_BIT_TIMING: u8 = 0x13;
    /// Activate bit timing parameters.
    pub const ACTIVATE_BIT_TIMING: u8 = 0x15;
    /// Store configuration.
    pub const STORE_CONFIGURATION: u8 = 0x17;
    /// Inquire identity vendor-ID (then product 5Bh, revision 5Ch, serial 5Dh).
    pub const INQUIRE_VENDOR: u8 = 0x5A;
    /// Inquire node-ID.
    pub const INQUIRE_NODE_ID: u8 = 0x5E;
    /// Identify remote slave: vendor-ID (then product 47h, revision low 48h and high 49h,
    /// serial low 4Ah and high 4Bh).
    pub const IDENTIFY_VENDOR: u8 = 0x46;
    /// Identify remote slave: serial number high, the last of the six.
    pub const IDENTIFY_SERIAL_HIGH: u8 = 0x4B;
    /// Identify non-configured remote slave.
    pub const IDENTIFY_NON_CONFIGURED: u8 = 0x4C;
    /// Identify slave: the answer to identify remote slave and fastscan.
    pub const IDENTIFY_SLAVE: u8 = 0x4F;
    /// Identify non-configured slave: the answer to 4Ch.
    pub const NON_CONFIGURED_SLAVE: u8 = 0x50;
    /// LSS Fastscan.
    pub const FASTSCAN: u8 = 0x51;
}

/// The LSS state a switch state global command enters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LssMode {
    /// LSS waiting state (0).
    Waiting,
    /// LSS configuration state (1).
    Configuration,
}

/// One of the four parts of the LSS address (the identity object 1018h sub-indices 1..4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LssPart {
    /// Vendor-ID (1018h:01).
    Vendor,
    /// Product code (1018h:02).
    Product,
    /// Revision number (1018h:03).
    Revision,
    /// Serial number (1018h:04).
    Serial,
}

impl LssPart {
    /// The four parts in LSS address order.
    pub const ALL: [LssPart; 4] = [
        LssPart::Vendor,
        LssPart::Product,
        LssPart::Revision,
        LssPart::Serial,
    ];

    /// The part's position, 0..=3 (also the fastscan LSSSub value).
    pub const fn index(self) -> u8 {
        self as u8
    }

    /// The part at `index` (0..=3).
    pub const fn from_index(index: u8) -> Option<Self> {
        match index {
            0 => Some(LssPart::Vendor),
            1 => Some(LssPart::Product),
            2 => Some(LssPart::Revision),
            3 => Some(LssPart::Serial),
            _ => None,
        }
    }
}

/// The LSS address: vendor-ID, product code, revision number, serial number.
pub type LssAddress = [u32; 4];

/// What an LSS master sends on 7E5h.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LssRequest {
    /// Switch state global (04h).
    SwitchGlobal(LssMode),
    /// One of the four switch state selective frames (40h..43h).
    SwitchSelective(LssPart, u32),
    /// Configure node-ID (11h).
    ConfigureNodeId(u8),
    /// Configure bit timing (13h): table selector, table index.
    ConfigureBitTiming {
        /// 0 the CiA 305 table, 1..=127 reserved, 128..=255 manufacturer tables.
        table: u8,
        /// The entry of the table.
        index: u8,
    },
    /// Activate bit timing (15h) with the switch delay in milliseconds.
    ActivateBitTiming(u16),
    /// Store configuration (17h).
    StoreConfiguration,
    /// Inquire one part of the identity (5Ah..5Dh).
    Inquire(LssPart),
    /// Inquire node-ID (5Eh).
    InquireNodeId,
    /// Identify remote slave (46h..4Bh): the vendor, the product, then the low and high
    /// bounds of revision and serial number.
    IdentifyRemote(IdentifyField, u32),
    /// Identify non-configured remote slave (4Ch).
    IdentifyNonConfigured,
    /// LSS Fastscan (51h).
    Fastscan(Fastscan),
}

/// The six fields of identify remote slave, in the order a master sends them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum IdentifyField {
    /// Vendor-ID (46h).
    Vendor,
    /// Product code (47h).
    Product,
    /// Revision number, low bound (48h).
    RevisionLow,
    /// Revision number, high bound (49h).
    RevisionHigh,
    /// Serial number, low bound (4Ah).
    SerialLow,
    /// Serial number, high bound (4Bh): the slaves in the range answer.
    SerialHigh,
}

impl IdentifyField {
    const ALL: [IdentifyField; 6] = [
        IdentifyField::Vendor,
        IdentifyField::Product,
        IdentifyField::RevisionLow,
        IdentifyField::RevisionHigh,
        IdentifyField::SerialLow,
        IdentifyField::SerialHigh,
    ];
}

/// A fastscan request's fields.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Fastscan {
    /// The bits of the LSS address part under test.
    pub id_number: u32,
    /// The lowest bit compared (0..=31), or [`FASTSCAN_RESET`].
    pub bit_checked: u8,
    /// The part under test (0..=3).
    pub lss_sub: u8,
    /// The part a slave tests next once this one matched in full.
    pub lss_next: u8,
}

fn u32_at(data: &[u8; 8]) -> u32 {
    u32::from_le_bytes([data[1], data[2], data[3], data[4]])
}

fn frame_with(cs: u8, rest: &[u8]) -> [u8; 8] {
    let mut data = [0; 8];
    data[0] = cs;
    data[1..1 + rest.len()].copy_from_slice(rest);
    data
}

impl LssRequest {
    /// Parses the data of a frame on 7E5h. `None` unless it has eight bytes, a known
    /// specifier and valid fields.
    pub fn parse(data: &[u8]) -> Option<Self> {
        let data: &[u8; 8] = data.try_into().ok()?;
        let value = u32_at(data);
        Some(match data[0] {
            cs::SWITCH_GLOBAL => LssRequest::SwitchGlobal(match data[1] {
                0 => LssMode::Waiting,
                1 => LssMode::Configuration,
                _ => return None,
            }),
            cs @ 0x40..=0x43 => LssRequest::SwitchSelective(LssPart::from_index(cs - 0x40)?, value),
            cs::CONFIGURE_NODE_ID => LssRequest::ConfigureNodeId(data[1]),
            cs::CONFIGURE_BIT_TIMING => LssRequest::ConfigureBitTiming {
                table: data[1],
                index: data[2],
            },
            cs::ACTIVATE_BIT_TIMING => {
                LssRequest::ActivateBitTiming(u16::from_le_bytes([data[1], data[2]]))
            }
            cs::STORE_CONFIGURATION => LssRequest::StoreConfiguration,
            cs @ 0x5A..=0x5D => LssRequest::Inquire(LssPart::from_index(cs - 0x5A)?),
            cs::INQUIRE_NODE_ID => LssRequest::InquireNodeId,
            cs @ 0x46..=0x4B => {
                LssRequest::IdentifyRemote(IdentifyField::ALL[usize::from(cs - 0x46)], value)
            }
            cs::IDENTIFY_NON_CONFIGURED => LssRequest::IdentifyNonConfigured,
            cs::FASTSCAN => LssRequest::Fastscan(Fastscan {
                id_number: value,
                bit_checked: data[5],
                lss_sub: data[6],
                lss_next: data[7],
            }),
            _ => return None,
        })
    }

    /// The eight data bytes (unused bytes 0).
    pub fn emit(&self) -> [u8; 8] {
        match *self {
            LssRequest::SwitchGlobal(mode) => {
                frame_with(cs::SWITCH_GLOBAL, &[(mode == LssMode::Configuration) as u8])
            }
            LssRequest::SwitchSelective(part, value) => {
                frame_with(0x40 + part.index(), &value.to_le_bytes())
            }
            LssRequest::ConfigureNodeId(id) => frame_with(cs::CONFIGURE_NODE_ID, &[id]),
            LssRequest::ConfigureBitTiming { table, index } => {
                frame_with(cs::CONFIGURE_BIT_TIMING, &[table, index])
            }
            LssRequest::ActivateBitTiming(delay) => {
                frame_with(cs::ACTIVATE_BIT_TIMING, &delay.to_le_bytes())
            }
            LssRequest::StoreConfiguration => frame_with(cs::STORE_CONFIGURATION, &[]),
            LssRequest::Inquire(part) => frame_with(cs::INQUIRE_VENDOR + part.index(), &[]),
            LssRequest::InquireNodeId => frame_with(cs::INQUIRE_NODE_ID, &[]),
            LssRequest::IdentifyRemote(field, value) => {
                frame_with(cs::IDENTIFY_VENDOR + field as u8, &value.to_le_bytes())
            }
            LssRequest::IdentifyNonConfigured => frame_with(cs::IDENTIFY_NON_CONFIGURED, &[]),
            LssRequest::Fastscan(f) => {
                let mut data = frame_with(cs::FASTSCAN, &f.id_number.to_le_bytes());
                data[5..8].copy_from_slice(&[f.bit_checked, f.lss_sub, f.lss_next]);
                data
            }
        }
    }
}

/// What an LSS slave answers on 7E4h.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LssResponse {
    /// Switch state selective done (44h).
    SwitchSelective,
    /// The result of configure node-ID (11h), configure bit timing (13h) or store (17h):
    /// the specifier, the error code (0 success) and the manufacturer's error code.
    Result {
        /// 11h, 13h or 17h.
        cs: u8,
        /// 0 success; see [`LssError`].
        error: u8,
        /// Meaningful when `error` is 255.
        specific: u8,
    },
    /// One part of the identity (5Ah..5Dh).
    Identity(LssPart, u32),
    /// The active node-ID (5Eh).
    NodeId(u8),
    /// Identify slave (4Fh): an answer to identify remote slave or fastscan.
    IdentifySlave,
    /// Identify non-configured slave (50h).
    NonConfiguredSlave,
}

/// The error codes of configure and store answers (CiA 305). Code 1 means "out of range" to
/// configure node-ID and bit timing, "not supported" to store configuration.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LssError {
    /// 1 to configure: node-ID out of range, or bit timing not supported.
    OutOfRange,
    /// 1 to store: store configuration not supported.
    StoreNotSupported,
    /// 2 to store: storage media access error.
    StorageAccess,
    /// 255: implementation specific, with the manufacturer's code.
    Specific(u8),
    /// A code CiA 305 reserves.
    Reserved(u8),
}

impl LssError {
    /// The error code and the implementation-specific byte.
    pub const fn codes(self) -> (u8, u8) {
        match self {
            LssError::OutOfRange | LssError::StoreNotSupported => (1, 0),
            LssError::StorageAccess => (2, 0),
            LssError::Specific(code) => (255, code),
            LssError::Reserved(code) => (code, 0),
        }
    }

    /// The error of an answer to service `cs` (11h, 13h or 17h) with these codes; `None` for
    /// 0 (success).
    pub const fn from_codes(cs: u8, error: u8, specific: u8) -> Option<Self> {
        let store = cs == cs::STORE_CONFIGURATION;
        Some(match error {
            0 => return None,
            1 if store => LssError::StoreNotSupported,
            1 => LssError::OutOfRange,
            2 if store => LssError::StorageAccess,
            255 => LssError::Specific(specific),
            code => LssError::Reserved(code),
        })
    }
}

impl LssResponse {
    /// Parses the data of a frame on 7E4h. `None` unless it has eight bytes and a known
    /// specifier.
    pub fn parse(data: &[u8]) -> Option<Self> {
        let data: &[u8; 8] = data.try_into().ok()?;
        Some(match data[0] {
            cs::SWITCH_SELECTIVE_ANSWER => LssResponse::SwitchSelective,
            cs @ (cs::CONFIGURE_NODE_ID | cs::CONFIGURE_BIT_TIMING | cs::STORE_CONFIGURATION) => {
                LssResponse::Result {
                    cs,
                    error: data[1],
                    specific: data[2],
                }
            }
            cs @ 0x5A..=0x5D => {
                LssResponse::Identity(LssPart::from_index(cs - 0x5A)?, u32_at(data))
            }
            cs::INQUIRE_NODE_ID => LssResponse::NodeId(data[1]),
            cs::IDENTIFY_SLAVE => LssResponse::IdentifySlave,
            cs::NON_CONFIGURED_SLAVE => LssResponse::NonConfiguredSlave,
            _ => return None,
        })
    }

    /// The eight data bytes (unused bytes 0).
    pub fn emit(&self) -> [u8; 8] {
        match *self {
            LssResponse::SwitchSelective => frame_with(cs::SWITCH_SELECTIVE_ANSWER, &[]),
            LssResponse::Result {
                cs,
                error,
                specific,
            } => frame_with(cs, &[error, specific]),
            LssResponse::Identity(part, value) => {
                frame_with(cs::INQUIRE_VENDOR + part.index(), &value.to_le_bytes())
            }
            LssResponse::NodeId(id) => frame_with(cs::INQUIRE_NODE_ID, &[id]),
            LssResponse::IdentifySlave => frame_with(cs::IDENTIFY_SLAVE, &[]),
            LssResponse::NonConfiguredSlave => frame_with(cs::NON_CONFIGURED_SLAVE, &[]),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn requests_have_the_cia305_bytes() {
        let cases: [(LssRequest, [u8; 8]); 9] = [
            (
                LssRequest::SwitchGlobal(LssMode::Configuration),
                [4, 1, 0, 0, 0, 0, 0, 0],
            ),
            (
                LssRequest::SwitchGlobal(LssMode::Waiting),
                [4, 0, 0, 0, 0, 0, 0, 0],
            ),
            (
                LssRequest::SwitchSelective(LssPart::Vendor, 0x0000_04D8),
                [0x40, 0xD8, 0x04, 0, 0, 0, 0, 0],
            ),
            (
                LssRequest::SwitchSelective(LssPart::Serial, 7),
                [0x43, 7, 0, 0, 0, 0, 0, 0],
            ),
            (LssRequest::ConfigureNodeId(5), [0x11, 5, 0, 0, 0, 0, 0, 0]),
            (
                LssRequest::ConfigureBitTiming { table: 0, index: 3 },
                [0x13, 0, 3, 0, 0, 0, 0, 0],
            ),
            (
                LssRequest::ActivateBitTiming(0x1F4),
                [0x15, 0xF4, 1, 0, 0, 0, 0, 0],
            ),
            (
                LssRequest::Inquire(LssPart::Revision),
                [0x5C, 0, 0, 0, 0, 0, 0, 0],
            ),
            (
                LssRequest::Fastscan(Fastscan {
                    id_number: 0x9252,
                    bit_checked: 12,
                    lss_sub: 1,
                    lss_next: 1,
                }),
                [0x51, 0x52, 0x92, 0, 0, 12, 1, 1],
            ),
        ];
        for (repr, bytes) in cases {
            assert_eq!(repr.emit(), bytes, "{repr:?}");
            assert_eq!(LssRequest::parse(&bytes), Some(repr));
        }
        assert_eq!(
            LssRequest::parse(&[0x4A, 1, 0, 0, 0, 0, 0, 0]),
            Some(LssRequest::IdentifyRemote(IdentifyField::SerialLow, 1))
        );
    }

    #[test]
    fn responses_have_the_cia305_bytes() {
        let cases: [(LssResponse, [u8; 8]); 5] = [
            (LssResponse::SwitchSelective, [0x44, 0, 0, 0, 0, 0, 0, 0]),
            (
                LssResponse::Result {
                    cs: 0x11,
                    error: 1,
                    specific: 0,
                },
                [0x11, 1, 0, 0, 0, 0, 0, 0],
            ),
            (
                LssResponse::Identity(LssPart::Product, 0x9252),
                [0x5B, 0x52, 0x92, 0, 0, 0, 0, 0],
            ),
            (LssResponse::NodeId(0xFF), [0x5E, 0xFF, 0, 0, 0, 0, 0, 0]),
            (LssResponse::IdentifySlave, [0x4F, 0, 0, 0, 0, 0, 0, 0]),
        ];
        for (repr, bytes) in cases {
            assert_eq!(repr.emit(), bytes, "{repr:?}");
            assert_eq!(LssResponse::parse(&bytes), Some(repr));
        }
    }

    #[test]
    fn short_frames_and_unknown_specifiers_are_rejected() {
        assert_eq!(LssRequest::parse(&[0x04, 1]), None);
        assert_eq!(LssRequest::parse(&[0x04, 2, 0, 0, 0, 0, 0, 0]), None);
        assert_eq!(LssRequest::parse(&[0x99, 0, 0, 0, 0, 0, 0, 0]), None);
        assert_eq!(LssResponse::parse(&[0x44, 0, 0, 0, 0, 0, 0]), None);
        assert_eq!(LssResponse::parse(&[0x04, 0, 0, 0, 0, 0, 0, 0]), None);
        assert_eq!(LssError::from_codes(0x11, 0, 0), None);
        assert_eq!(LssError::from_codes(0x11, 1, 0), Some(LssError::OutOfRange));
        assert_eq!(
            LssError::from_codes(0x17, 1, 0),
            Some(LssError::StoreNotSupported)
        );
        assert_eq!(
            LssError::from_codes(0x17, 2, 0),
            Some(LssError::StorageAccess)
        );
        assert_eq!(
            LssError::from_codes(0x13, 2, 0),
            Some(LssError::Reserved(2))
        );
        assert_eq!(
            LssError::from_codes(0x17, 255, 9),
            Some(LssError::Specific(9))
        );
    }
}
