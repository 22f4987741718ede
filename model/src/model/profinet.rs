//! The PROFINET side of a device read from a GSDML file: identity, device access points with
//! their slots, limits and system submodules, the modules and submodules that plug into them with
//! their typed IO data and parameter records, value lists and channel diagnostics.

use super::{Span, Spanned};

/// What a GSDML file says (`ProfileBody`). Identity also goes to
/// [`DeviceInfo`](super::DeviceInfo) (`vendor_number`, `product_number`) so that tools reading
/// only identity see it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Profinet {
    /// `DeviceIdentity/@VendorID`.
    pub vendor_id: Option<Spanned<u16>>,
    /// `DeviceIdentity/@DeviceID`.
    pub device_id: Option<Spanned<u16>>,
    /// `DeviceIdentity/VendorName/@Value`.
    pub vendor_name: Option<String>,
    /// `DeviceIdentity/InfoText`, resolved.
    pub info_text: Option<String>,
    /// `DeviceFunction/Family`: main family and product family.
    pub family: Option<(String, String)>,
    /// The `DeviceAccessPointItem`s, in file order; the first is the default.
    pub access_points: Vec<AccessPoint>,
    /// The `ModuleList/ModuleItem`s, in file order.
    pub modules: Vec<PnModule>,
    /// `ValueList/ValueItem`s (the allowed values and their texts a record field may name).
    pub value_lists: Vec<ValueList>,
    /// `ChannelDiagList/ChannelDiagItem`s (and `UnitDiagTypeList` items, as error type 0x9000..).
    pub channel_diagnostics: Vec<ChannelDiag>,
    /// Text references (`TextId`) that no `ExternalTextList` text has, where they are.
    pub missing_texts: Vec<Spanned<String>>,
    /// Where the `DeviceIdentity` element is (else the root element).
    pub span: Span,
    /// The access point and modules chosen (the overlay's `[modules]`); `None`: the default
    /// ([`Profinet::configuration`]).
    pub chosen: Option<super::modules::PnConfiguration>,
}

impl Profinet {
    /// The configuration the device runs with: the chosen one, else the first access point with
    /// the modules it fixes or uses by default.
    pub fn configuration(&self) -> super::modules::PnConfiguration {
        match &self.chosen {
            Some(chosen) => chosen.clone(),
            None => super::modules::choose_pn(self, None, &[]).unwrap_or_default(),
        }
    }
}

/// One `DeviceAccessPointItem`: the head module in slot 0 and what may be plugged beside it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct AccessPoint {
    /// `ID`.
    pub id: String,
    /// `ModuleInfo/Name`, resolved.
    pub name: Option<String>,
    /// `ModuleIdentNumber`.
    pub module_ident: Option<Spanned<u32>>,
    /// `PhysicalSlots`: every slot number the device has.
    pub physical_slots: Vec<u16>,
    /// `FixedInSlots` of the access point itself (usually 0).
    pub fixed_in_slots: Vec<u16>,
    /// `MinDeviceInterval` in units of 31.25 µs.
    pub min_device_interval: Option<u32>,
    /// `DNS_CompatibleName`: the default name of station.
    pub dns_compatible_name: Option<String>,
    /// `PNIO_Version`.
    pub pnio_version: Option<String>,
    /// `IOConfigData/@MaxInputLength` in bytes.
    pub max_input_length: Option<Spanned<u32>>,
    /// `IOConfigData/@MaxOutputLength` in bytes.
    pub max_output_length: Option<Spanned<u32>>,
    /// `UseableModules/ModuleItemRef`s.
    pub useable_modules: Vec<ModuleRef>,
    /// The access point's own `VirtualSubmoduleList` items (subslot 1 and on).
    pub submodules: Vec<Submodule>,
    /// `SubslotList/SubslotItem`s: labels of its subslots.
    pub subslot_labels: Vec<SubslotLabel>,
    /// The `InterfaceSubmoduleItem`, if any.
    pub interface: Option<SystemSubmodule>,
    /// The `PortSubmoduleItem`s.
    pub ports: Vec<SystemSubmodule>,
    /// Where the element is.
    pub span: Span,
}

/// One `ModuleItemRef`: a module an access point accepts, and where.
#[derive(Debug, Clone, PartialEq)]
pub struct ModuleRef {
    /// `ModuleItemTarget`: the `ID` of a `ModuleItem`.
    pub target: Spanned<String>,
    /// `AllowedInSlots` (else `FixedInSlots`, else `UsedInSlots`): the slots it may go in.
    pub allowed_in_slots: Vec<u16>,
    /// `FixedInSlots`: where it always is.
    pub fixed_in_slots: Vec<u16>,
    /// `UsedInSlots`: where it is by default.
    pub used_in_slots: Vec<u16>,
    /// Where the element is.
    pub span: Span,
}

/// One `ModuleItem`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PnModule {
    /// `ID`.
    pub id: String,
    /// `ModuleIdentNumber`.
    pub module_ident: Option<Spanned<u32>>,
    /// `ModuleInfo/Name`, resolved.
    pub name: Option<String>,
    /// `ModuleInfo/InfoText`, resolved.
    pub info_text: Option<String>,
    /// Its `VirtualSubmoduleItem`s.
    pub submodules: Vec<Submodule>,
    /// `SubslotList/SubslotItem`s: labels of its subslots.
    pub subslot_labels: Vec<SubslotLabel>,
    /// Where the element is.
    pub span: Span,
}

/// One `SubslotItem`: the label an engineering tool shows for a subslot of a module or access
/// point.
#[derive(Debug, Clone, PartialEq)]
pub struct SubslotLabel {
    /// `SubslotNumber`.
    pub subslot: Spanned<u16>,
    /// The text `TextId` names.
    pub text: Option<String>,
}

/// One `VirtualSubmoduleItem`: IO data and parameter records.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Submodule {
    /// `ID`.
    pub id: String,
    /// `SubmoduleIdentNumber`.
    pub submodule_ident: Option<Spanned<u32>>,
    /// `FixedInSubslots` (else 1 for the first, 2 for the second, ...).
    pub subslot: u16,
    /// `ModuleInfo/Name`, resolved.
    pub name: Option<String>,
    /// `IOData/Input/DataItem`s: data the device sends.
    pub inputs: Vec<DataItem>,
    /// `IOData/Output/DataItem`s: data the controller sends.
    pub outputs: Vec<DataItem>,
    /// `RecordDataList/ParameterRecordDataItem`s.
    pub records: Vec<ParameterRecord>,
    /// Whether its images are the Goodrive350's 16-word PKW/PZD images, as the overlay's
    /// `[pkw_pzd]` says (a GSDML file cannot): its generated images then convert to and from
    /// `edsgen_runtime::pkw_pzd`'s.
    pub pkw_pzd: bool,
    /// Where the element is.
    pub span: Span,
}

/// The data types of GSDML (PROFINET's `DataType` attribute values).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PnDataType {
    /// `Bit` (a record field of one bit, at `BitOffset`).
    Bit,
    /// `BitArea` (a record field of `BitLength` bits).
    BitArea,
    /// `Boolean` (one byte).
    Boolean,
    /// `Integer8`.
    Integer8,
    /// `Integer16`.
    Integer16,
    /// `Integer32`.
    Integer32,
    /// `Integer64`.
    Integer64,
    /// `Unsigned8`.
    Unsigned8,
    /// `Unsigned16`.
    Unsigned16,
    /// `Unsigned32`.
    Unsigned32,
    /// `Unsigned64`.
    Unsigned64,
    /// `Float32`.
    Float32,
    /// `Float64`.
    Float64,
    /// `OctetString` (`Length` bytes).
    OctetString,
    /// `VisibleString` (`Length` bytes).
    VisibleString,
    /// `UnicodeString8` (`Length` bytes).
    UnicodeString8,
    /// A fixed-size type GSDML defines that is carried as bytes (`Date`, `TimeOfDay ...`,
    /// `F_MessageTrailer4Byte`, `Unsigned8+Unsigned8`, `Float32+Status8`, ...): its byte size.
    Fixed(u32),
}

impl PnDataType {
    /// The type a `DataType` attribute names, if GSDML defines it.
    pub fn from_name(name: &str) -> Option<Self> {
        use PnDataType::*;
        Some(match name {
            "Bit" => Bit,
            "BitArea" => BitArea,
            "Boolean" => Boolean,
            "Integer8" => Integer8,
            "Integer16" => Integer16,
            "Integer32" => Integer32,
            "Integer64" => Integer64,
            "Unsigned8" => Unsigned8,
            "Unsigned16" => Unsigned16,
            "Unsigned32" => Unsigned32,
            "Unsigned64" => Unsigned64,
            "Float32" => Float32,
            "Float64" => Float64,
            "OctetString" | "OctetString_S" => OctetString,
            "VisibleString" | "61131_STRING" => VisibleString,
            "UnicodeString8" | "61131_WSTRING" => UnicodeString8,
            "Date" | "TimeOfDay with date indication" | "TimeDifference with date indication" => {
                Fixed(7)
            }
            "TimeOfDay without date indication" | "TimeDifference without date indication" => {
                Fixed(6)
            }
            "NetworkTime" | "NetworkTimeDifference" | "TimeStamp" | "TimeStampDifference" => {
                Fixed(8)
            }
            "TimeStampDifferenceShort" => Fixed(4),
            "F_MessageTrailer4Byte" => Fixed(4),
            "F_MessageTrailer5Byte" => Fixed(5),
            "Unsigned8+Unsigned8" | "OctetString2+Unsigned8" => {
                Fixed(if name.starts_with('O') { 3 } else { 2 })
            }
            "Unsigned16_S" | "Integer16_S" => Fixed(3),
            "Unsigned8_S" => Fixed(2),
            "Float32+Unsigned8" | "Float32+Status8" => Fixed(5),
            "Float32_S" => Fixed(5),
            "N2" | "N4" | "V2" | "L2" | "R2" | "T2" | "D2" | "E2" | "C4" | "X2" | "X4" | "T4"
            | "Unipolar2.16" => Fixed(match name {
                "N4" | "C4" | "X4" | "T4" => 4,
                _ => 2,
            }),
            _ => return None,
        })
    }

    /// The size in bytes; `None` for `Bit`/`BitArea` and the strings (their `Length` says).
    pub fn size(self) -> Option<u32> {
        use PnDataType::*;
        match self {
            Bit | BitArea | OctetString | VisibleString | UnicodeString8 => None,
            Boolean | Integer8 | Unsigned8 => Some(1),
            Integer16 | Unsigned16 => Some(2),
            Integer32 | Unsigned32 | Float32 => Some(4),
            Integer64 | Unsigned64 | Float64 => Some(8),
            Fixed(n) => Some(n),
        }
    }
}

/// One `DataItem` of an `Input` or `Output`.
#[derive(Debug, Clone, PartialEq)]
pub struct DataItem {
    /// `DataType` as written.
    pub data_type: Spanned<String>,
    /// The type, when GSDML defines it.
    pub kind: Option<PnDataType>,
    /// `Length` (strings).
    pub length: Option<u32>,
    /// The text `TextId` names.
    pub name: Option<String>,
    /// `UseAsBits`.
    pub use_as_bits: bool,
    /// `BitDataItem`s: named bits of the item.
    pub bits: Vec<BitDataItem>,
    /// Where the element is.
    pub span: Span,
}

impl DataItem {
    /// The item's size in bytes, when known.
    pub fn size(&self) -> Option<u32> {
        match self.kind? {
            PnDataType::OctetString | PnDataType::VisibleString | PnDataType::UnicodeString8 => {
                self.length
            }
            kind => kind.size(),
        }
    }
}

/// One `BitDataItem`.
#[derive(Debug, Clone, PartialEq)]
pub struct BitDataItem {
    /// `BitOffset`.
    pub bit_offset: u32,
    /// The text `TextId` names.
    pub name: Option<String>,
    /// Where the element is.
    pub span: Span,
}

/// One `ParameterRecordDataItem`: a record the controller writes at connection.
#[derive(Debug, Clone, PartialEq)]
pub struct ParameterRecord {
    /// `Index`.
    pub index: Spanned<u16>,
    /// `Length` in bytes.
    pub length: Spanned<u32>,
    /// `TransferSequence`, if given.
    pub transfer_sequence: Option<u32>,
    /// `Name`, resolved.
    pub name: Option<String>,
    /// `Const` elements: fixed bytes at a byte offset.
    pub consts: Vec<(u32, Vec<u8>)>,
    /// `Ref` elements: typed fields.
    pub fields: Vec<RecordField>,
    /// Where the element is.
    pub span: Span,
}

/// One `Ref` of a parameter record.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordField {
    /// `DataType` as written.
    pub data_type: Spanned<String>,
    /// The type, when GSDML defines it.
    pub kind: Option<PnDataType>,
    /// `ByteOffset`.
    pub byte_offset: u32,
    /// `BitOffset` (`Bit`, `BitArea`).
    pub bit_offset: Option<u32>,
    /// `BitLength` (`BitArea`).
    pub bit_length: Option<u32>,
    /// `Length` (strings).
    pub length: Option<u32>,
    /// `DefaultValue`, as written.
    pub default: Option<Spanned<String>>,
    /// `AllowedValues` as ranges (`1..4 7` is `[(1, 4), (7, 7)]`).
    pub allowed_values: Vec<(i128, i128)>,
    /// `ValueItemTarget`: the `ID` of a `ValueItem`.
    pub value_item: Option<Spanned<String>>,
    /// `Changeable` (default true).
    pub changeable: bool,
    /// `Visible` (default true).
    pub visible: bool,
    /// The text `TextId` names.
    pub name: Option<String>,
    /// Where the element is.
    pub span: Span,
}

impl RecordField {
    /// The bits the field takes in its record: (first bit, number of bits), counting bit 0 as the
    /// least significant bit of byte 0 ... (`ByteOffset * 8 + BitOffset`); `None` when its size
    /// is unknown.
    pub fn bit_range(&self) -> Option<(u64, u64)> {
        let base = u64::from(self.byte_offset) * 8;
        match self.kind? {
            PnDataType::Bit => Some((base + u64::from(self.bit_offset.unwrap_or(0)), 1)),
            PnDataType::BitArea => Some((
                base + u64::from(self.bit_offset.unwrap_or(0)),
                u64::from(self.bit_length.unwrap_or(1)),
            )),
            PnDataType::OctetString | PnDataType::VisibleString | PnDataType::UnicodeString8 => {
                Some((base, u64::from(self.length?) * 8))
            }
            kind => Some((base, u64::from(kind.size()?) * 8)),
        }
    }
}

/// One `ValueItem`: named values.
#[derive(Debug, Clone, PartialEq)]
pub struct ValueList {
    /// `ID`.
    pub id: String,
    /// `Assignments/Assign`: (value, resolved text).
    pub assignments: Vec<(i128, Option<String>)>,
    /// Where the element is.
    pub span: Span,
}

/// One `ChannelDiagItem` (or `UnitDiagTypeItem`).
#[derive(Debug, Clone, PartialEq)]
pub struct ChannelDiag {
    /// `ErrorType` (or `UserStructureIdentifier` for a unit diagnosis type).
    pub error_type: u32,
    /// `Name`, resolved.
    pub name: Option<String>,
    /// `Help`, resolved.
    pub help: Option<String>,
    /// `ExtChannelDiagList/ExtChannelDiagItem`s: the error's finer causes.
    pub ext: Vec<ExtChannelDiag>,
    /// Where the `ErrorType` attribute is (else the element).
    pub error_type_span: Span,
    /// Where the element is.
    pub span: Span,
}

/// One `ExtChannelDiagItem`: a finer cause of a channel error (the alarm's ExtChannelErrorType).
#[derive(Debug, Clone, PartialEq)]
pub struct ExtChannelDiag {
    /// `ErrorType`: the ExtChannelErrorType (16 bits).
    pub error_type: Spanned<u16>,
    /// `Name`, resolved.
    pub name: Option<String>,
    /// `Help`, resolved.
    pub help: Option<String>,
    /// `ExtChannelAddValue/DataItem`s: what the alarm's ExtChannelAddValue (32 bits) carries.
    pub add_values: Vec<ExtAddValue>,
    /// Where the element is.
    pub span: Span,
}

/// One `ExtChannelAddValue/DataItem`: a field of the alarm's 32-bit additional value.
#[derive(Debug, Clone, PartialEq)]
pub struct ExtAddValue {
    /// `Id`.
    pub id: Option<u32>,
    /// `DataType` as written.
    pub data_type: Spanned<String>,
    /// The type, when GSDML defines it.
    pub kind: Option<PnDataType>,
    /// `Length` (strings).
    pub length: Option<u32>,
    /// Where the element is.
    pub span: Span,
}

/// One `InterfaceSubmoduleItem` or `PortSubmoduleItem`.
#[derive(Debug, Clone, PartialEq)]
pub struct SystemSubmodule {
    /// `ID`.
    pub id: String,
    /// `SubmoduleIdentNumber`.
    pub submodule_ident: Option<Spanned<u32>>,
    /// `SubslotNumber` (0x8000 the interface, 0x8001.. the ports).
    pub subslot: u16,
    /// The text `TextId` names.
    pub name: Option<String>,
    /// `SupportedRT_Classes` (interface).
    pub rt_classes: Option<String>,
    /// `ApplicationRelations/TimingProperties/@SendClock` (interface).
    pub send_clock: Vec<u32>,
    /// `ApplicationRelations/TimingProperties/@ReductionRatio` (interface).
    pub reduction_ratio: Vec<u32>,
    /// Where the element is.
    pub span: Span,
}
