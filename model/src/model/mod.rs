//! The resolved device model: one intermediate representation for every format (CANopen EDS,
//! DCF, XDD, XDC; EtherCAT ESI and SII; ODVA EDS; PROFINET GSDML; PROFIBUS-DP GSD), with the
//! fieldbus part as one [`Bus`].
//!
//! Readers (`read::*`) build it, the validator judges it, the emitter turns it into Rust. Every
//! object, sub-object and value keeps the [`Span`] it was read from, so a diagnostic can point at
//! the exact line of the vendor file. Nothing here evaluates `$NODEID`: node-relative values stay
//! symbolic ([`Value::NodeRelative`]) until a DCF or the generated `new(node_id)` fixes the
//! node-ID.
//!
//! This module holds the device and its file-level parts (file and device info, object lists,
//! commissioning, kept sections); spans and sources, the CiA 301 kinds, objects with their
//! entries and values, the value image's [`layout`], and each bus's part have a submodule each,
//! re-exported here.

use std::collections::BTreeMap;

mod cip;
mod cip_path;
mod cip_size;
pub mod cip_value;
mod dp;
mod ethercat;
pub mod layout;
pub mod modules;
mod object;
mod profinet;
mod source;
mod subs;
mod types;

pub use cip::{
    data_type_info, data_type_range, real_time_format_name, AssemblyMember, Cip, CipAssembly,
    CipConnection, CipEntry, CipEnum, CipFile, CipIdentity, CipNumber, CipParam, CipPort,
    CipSection, ConnectionData, ConnectionParams, Field, FieldRef, PkwPzdImages, TriggerTransport,
};
pub use cip_path::{decode_path, path_bytes, PathSegment};
pub use dp::{
    decode_cfg, CfgError, CfgIdentifier, Dp, DpBaud, DpBaudRate, DpModule, DpSlot, ExtUserPrmData,
    GsdKeyword, PrmConst, PrmRef, PrmText, PrmType, PrmValues, UnitDiag,
};
pub use ethercat::{
    AlternativeSmMapping, CoeInitCmd, CoeMailbox, DcOpMode, EcModule, EcPdo, EcPdoEntry, EcSlot,
    EtherCat, SlotIndices, SmKind, SyncManager,
};
pub use object::{KeySpans, Object, SubObject, Value, ValueSource};
pub use profinet::{
    AccessPoint, BitDataItem, ChannelDiag, DataItem, ExtAddValue, ExtChannelDiag, ModuleRef,
    ParameterRecord, PnDataType, PnModule, Profinet, RecordField, Submodule, SubslotLabel,
    SystemSubmodule, ValueList,
};
pub use source::{Format, Source, Span, Spanned, TextEncoding};
pub use subs::Subs;
pub use types::{AccessType, BasicType, ObjectType};

/// `[FileInfo]` (EDS/DCF) or the XML ProfileBody attributes.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FileInfo {
    /// FileName.
    pub file_name: Option<String>,
    /// FileVersion.
    pub file_version: Option<String>,
    /// FileRevision.
    pub file_revision: Option<String>,
    /// EDSVersion (missing means 3.0).
    pub eds_version: Option<Spanned<String>>,
    /// Description.
    pub description: Option<String>,
    /// CreationTime.
    pub creation_time: Option<String>,
    /// CreationDate.
    pub creation_date: Option<String>,
    /// CreatedBy.
    pub created_by: Option<String>,
    /// ModificationTime.
    pub modification_time: Option<String>,
    /// ModificationDate.
    pub modification_date: Option<String>,
    /// ModifiedBy.
    pub modified_by: Option<String>,
    /// DCF LastEDS.
    pub last_eds: Option<String>,
    /// Where the section is (its header), if present.
    pub span: Option<Span>,
    /// Where each key's value is written, by canonical key name (`FileVersion`, ...), when the
    /// reader knows it; diagnostics about one key point there.
    pub key_spans: BTreeMap<String, Span>,
}

/// `[DeviceInfo]` (EDS/DCF) or DeviceIdentity and the general features (XML).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DeviceInfo {
    /// VendorName.
    pub vendor_name: Option<String>,
    /// VendorNumber (1018h sub 1).
    pub vendor_number: Option<Spanned<u32>>,
    /// ProductName.
    pub product_name: Option<String>,
    /// ProductNumber (1018h sub 2).
    pub product_number: Option<Spanned<u32>>,
    /// RevisionNumber (1018h sub 3).
    pub revision_number: Option<Spanned<u32>>,
    /// OrderCode.
    pub order_code: Option<String>,
    /// Supported bit rates in kbit/s, with the value written (`BaudRate_250=1` gives `(250, true)`).
    pub baud_rates: Vec<(u32, bool)>,
    /// SimpleBootUpMaster.
    pub simple_boot_up_master: bool,
    /// SimpleBootUpSlave.
    pub simple_boot_up_slave: bool,
    /// Granularity (0: mapping not modifiable, 1..64).
    pub granularity: Option<Spanned<u32>>,
    /// DynamicChannelsSupported.
    pub dynamic_channels_supported: u32,
    /// GroupMessaging.
    pub group_messaging: bool,
    /// NrOfRXPDO.
    pub nr_of_rx_pdo: Option<Spanned<u32>>,
    /// NrOfTXPDO.
    pub nr_of_tx_pdo: Option<Spanned<u32>>,
    /// LSS_Supported.
    pub lss_supported: bool,
    /// CompactPDO bitmask.
    pub compact_pdo: Option<Spanned<u32>>,
    /// Where the section is (its header), if present.
    pub span: Option<Span>,
}

/// `[DeviceComissioning]` (DCF) or `deviceCommissioning` (XDC).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Commissioning {
    /// NodeID.
    pub node_id: Option<Spanned<u32>>,
    /// NodeName.
    pub node_name: Option<String>,
    /// Baudrate in kbit/s.
    pub baudrate: Option<Spanned<u32>>,
    /// NetNumber.
    pub net_number: Option<u32>,
    /// NetworkName.
    pub network_name: Option<String>,
    /// CANopenManager.
    pub canopen_manager: bool,
    /// LSS_SerialNumber (1018h sub 4).
    pub lss_serial_number: Option<u32>,
    /// Where the section is.
    pub span: Span,
}

/// A section or key the reader kept without interpreting it, for round trips and for the module
/// and dynamic-channel sections that later stages may use.
#[derive(Debug, Clone, PartialEq)]
pub struct RawSection {
    /// The section name as written (without brackets).
    pub name: String,
    /// The keys in file order, as written.
    pub entries: Vec<RawEntry>,
    /// The section header's span.
    pub span: Span,
}

/// One `key=value` line kept verbatim.
#[derive(Debug, Clone, PartialEq)]
pub struct RawEntry {
    /// The key as written.
    pub key: String,
    /// The value, trimmed.
    pub value: String,
    /// Where the line is.
    pub span: Span,
}

/// A complete device description.
#[derive(Debug, Clone, PartialEq)]
pub struct Device {
    /// The file it was read from.
    pub source: Source,
    /// File information.
    pub file_info: FileInfo,
    /// Device information.
    pub device_info: DeviceInfo,
    /// `[DummyUsage]`: data type index → whether it may be used as a dummy mapping entry.
    pub dummy_usage: BTreeMap<u16, bool>,
    /// Where dummy usage is declared (the `[DummyUsage]` header or the XML element), if it is.
    pub dummy_usage_span: Option<Span>,
    /// `[Comments]` lines, in order.
    pub comments: Vec<String>,
    /// `[Comments]` `Lines` as written (the declared number of comment lines), for the validator.
    pub comment_lines: Option<Spanned<u32>>,
    /// The objects, by index. DEFTYPE/DEFSTRUCT objects (0x0001-0x0FFF) are here too.
    pub objects: BTreeMap<u16, Object>,
    /// The object lists (`[MandatoryObjects]`, `[OptionalObjects]`, `[ManufacturerObjects]`) as
    /// written, for the validator; `objects` is the union of the lists and the sections.
    pub object_lists: Vec<ObjectList>,
    /// DCF commissioning data.
    pub commissioning: Option<Commissioning>,
    /// Sections the model does not interpret further: modules (`[SupportedModules]`, `[Mx...]`,
    /// `[ConnectedModules]`), `[DynamicChannels]`, `[Tools]`, and unknown sections, in file order.
    pub other_sections: Vec<RawSection>,
    /// Generated names the overlay sets (see [`crate::overlay`]); empty without one.
    pub naming: Naming,
    /// The fieldbus the description is for, with what its format says beyond the object
    /// dictionary.
    pub bus: Bus,
}

/// The fieldbus a description is for, and what its format says beyond the CANopen object
/// dictionary. Every stage matches on it once, so a new bus is a compile error at each place
/// that must handle it.
#[derive(Debug, Clone, PartialEq)]
// One per description: the size of the larger variants costs nothing.
#[allow(clippy::large_enum_variant)]
pub enum Bus {
    /// CANopen (EDS, DCF, XDD, XDC): everything is in the object dictionary.
    CanOpen,
    /// EtherCAT (ESI, SII): the CoE dictionary is in `objects`, the rest here.
    EtherCat(EtherCat),
    /// EtherNet/IP or DeviceNet (ODVA EDS): a CIP device.
    Cip(Cip),
    /// PROFINET (GSDML): access points, modules, submodules, records.
    Profinet(Profinet),
    /// PROFIBUS-DP (GSD).
    Dp(Dp),
}

/// What an overlay says about generated names: the description cannot say how the device numbers
/// an array's elements, and its names may not suit Rust.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Naming {
    /// An object's name in generated code, in place of its ParameterName: a VAR's constant, an
    /// ARRAY's or RECORD's module in `od` (and the start of its numbered elements' constants).
    pub objects: BTreeMap<u16, String>,
    /// An entry's constant name (in its object's module for an ARRAY or RECORD), in place of the
    /// one made from its names.
    pub entries: BTreeMap<(u16, u8), String>,
    /// For an array, the number the device gives sub-index 1 (0 when sub-index = number + 1):
    /// its elements' constants end in that numbering, not in the sub-index.
    pub first_number: BTreeMap<u16, u32>,
}

/// Which object list.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ObjectListKind {
    /// `[MandatoryObjects]`.
    Mandatory,
    /// `[OptionalObjects]`.
    Optional,
    /// `[ManufacturerObjects]`.
    Manufacturer,
}

/// One object list section.
#[derive(Debug, Clone, PartialEq)]
pub struct ObjectList {
    /// Which list.
    pub kind: ObjectListKind,
    /// SupportedObjects as written.
    pub supported_objects: Option<Spanned<u32>>,
    /// The numbered entries: (key number, listed index).
    pub entries: Vec<(u32, Spanned<u16>)>,
    /// The section header's span.
    pub span: Span,
}

impl Device {
    /// What an ESI file says beyond the CoE dictionary; `None` for other buses.
    pub fn ethercat(&self) -> Option<&EtherCat> {
        match &self.bus {
            Bus::EtherCat(ec) => Some(ec),
            _ => None,
        }
    }

    /// What an ODVA EDS says about a CIP device; `None` for other buses.
    pub fn cip(&self) -> Option<&Cip> {
        match &self.bus {
            Bus::Cip(cip) => Some(cip),
            _ => None,
        }
    }

    /// What a GSDML file says; `None` for other buses.
    pub fn profinet(&self) -> Option<&Profinet> {
        match &self.bus {
            Bus::Profinet(pn) => Some(pn),
            _ => None,
        }
    }

    /// What a GSD file says (PROFIBUS-DP); `None` for other buses.
    pub fn dp(&self) -> Option<&Dp> {
        match &self.bus {
            Bus::Dp(dp) => Some(dp),
            _ => None,
        }
    }

    /// [`Device::ethercat`], to change.
    pub fn ethercat_mut(&mut self) -> Option<&mut EtherCat> {
        match &mut self.bus {
            Bus::EtherCat(ec) => Some(ec),
            _ => None,
        }
    }

    /// [`Device::cip`], to change.
    pub fn cip_mut(&mut self) -> Option<&mut Cip> {
        match &mut self.bus {
            Bus::Cip(cip) => Some(cip),
            _ => None,
        }
    }

    /// [`Device::profinet`], to change.
    pub fn profinet_mut(&mut self) -> Option<&mut Profinet> {
        match &mut self.bus {
            Bus::Profinet(pn) => Some(pn),
            _ => None,
        }
    }

    /// [`Device::dp`], to change.
    pub fn dp_mut(&mut self) -> Option<&mut Dp> {
        match &mut self.bus {
            Bus::Dp(dp) => Some(dp),
            _ => None,
        }
    }

    /// The entry at (index, sub), if the model has it.
    pub fn entry(&self, index: u16, sub: u8) -> Option<&SubObject> {
        self.objects.get(&index)?.subs.get(&sub)
    }

    /// The basic type of an entry's data type, following DEFTYPE objects (an index above 0x001B):
    /// the basic type that sub-object 1, or sub-index 0, names as its value (as CANfestival files
    /// do), else the DEFTYPE's own DataType (as CiA 306 writes `[0060]` with `DataType=0x0007`).
    /// `None` for a chain that ends nowhere (a DEFTYPE naming itself) or at anything else.
    pub fn basic_type(&self, data_type: u16) -> Option<BasicType> {
        let mut data_type = data_type;
        // A chain longer than this loops: CiA 306 files have none longer than one.
        for _ in 0..8 {
            if let Some(t) = BasicType::from_index(data_type) {
                return Some(t);
            }
            let def = self.objects.get(&data_type)?;
            if def.object_type != ObjectType::DefType {
                return None;
            }
            let sub = def.subs.get(&1).or_else(|| def.subs.get(&0))?;
            let named = match sub.default.as_ref().and_then(|d| d.value.as_ref()) {
                Some(Value::Integer(v)) => u16::try_from(*v).ok().and_then(BasicType::from_index),
                _ => None,
            };
            if named.is_some() {
                return named;
            }
            data_type = sub.data_type?;
        }
        None
    }
}
