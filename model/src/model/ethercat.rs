//! The EtherCAT side of an ESI device: SyncManagers, PDOs and their alternative assignments,
//! the CoE mailbox, DC op-modes, and the modules and slots of a modular device.

use std::collections::{BTreeMap, BTreeSet};

use super::{Object, Span, Spanned};

/// The EtherCAT side of a device read from an ESI file: what a CANopen description has no place
/// for. Identity goes in [`DeviceInfo`](super::DeviceInfo) (`vendor_number`, `product_number`, `revision_number`)
/// and the CoE dictionary in [`Device::objects`](super::Device::objects), as for CANopen.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct EtherCat {
    /// The device's type name (`Device/Type` text), which picks it in a file with several.
    pub type_name: String,
    /// `Profile/ProfileNo` values (402 for a drive, 5001 for a modular device).
    pub profiles: Vec<u32>,
    /// The SyncManagers, in order (SM0, SM1, ...).
    pub sync_managers: Vec<SyncManager>,
    /// `RxPdo` elements: outputs, written by the master.
    pub rx_pdos: Vec<EcPdo>,
    /// `TxPdo` elements: inputs, read by the master.
    pub tx_pdos: Vec<EcPdo>,
    /// The CoE mailbox, if the device has one.
    pub coe: Option<CoeMailbox>,
    /// Distributed-clock operation modes (`Dc/OpMode`).
    pub op_modes: Vec<DcOpMode>,
    /// `AlternativeSmMapping` elements (anywhere in the `Device`, usually
    /// `Info/VendorSpecific/TwinCAT`): other PDO assignments a master may pick.
    pub alternative_mappings: Vec<AlternativeSmMapping>,
    /// The file's `Modules/Module` elements: what can be plugged into the device's slots.
    pub modules: Vec<EcModule>,
    /// The device's `Slots/Slot` elements, in order.
    pub slots: Vec<EcSlot>,
    /// Other devices in the same file, by type name, product code and revision: the reader picks
    /// one (the first, unless told otherwise) and lists the rest here.
    pub other_devices: Vec<(String, u32, u32)>,
    /// Where the `Device` element is.
    pub span: Span,
    /// The module instances chosen (the overlay's `[modules]`); `None`: no module
    /// ([`EtherCat::configured`]).
    pub chosen: Option<super::modules::EcConfiguration>,
}

/// What a SyncManager carries.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SmKind {
    /// Mailbox, master to device (`MBoxOut`).
    MailboxOut,
    /// Mailbox, device to master (`MBoxIn`).
    MailboxIn,
    /// Process data outputs (`Outputs`): the assigned RxPDOs.
    Outputs,
    /// Process data inputs (`Inputs`): the assigned TxPDOs.
    Inputs,
    /// Anything else, as written (an empty or vendor-specific text).
    Other(String),
}

/// One `Sm` element.
#[derive(Debug, Clone, PartialEq)]
pub struct SyncManager {
    /// What it carries.
    pub kind: SmKind,
    /// `StartAddress` in the device's memory.
    pub start_address: u16,
    /// `DefaultSize` in bytes, if given.
    pub default_size: Option<u16>,
    /// `ControlByte`.
    pub control_byte: u8,
    /// `Enable`.
    pub enable: bool,
    /// Where the element is.
    pub span: Span,
}

/// One `RxPdo` or `TxPdo` element.
#[derive(Debug, Clone, PartialEq)]
pub struct EcPdo {
    /// The mapping object's index (1600h... for RxPDOs, 1A00h... for TxPDOs).
    pub index: u16,
    /// `Name`.
    pub name: String,
    /// The SyncManager it is assigned to by default (`Sm`); `None` when not assigned.
    pub sm: Option<u8>,
    /// `Fixed`: the mapping cannot be changed.
    pub fixed: bool,
    /// `Mandatory`: it must be assigned.
    pub mandatory: bool,
    /// `Exclude`: PDOs that cannot be assigned together with this one.
    pub exclude: Vec<Spanned<u16>>,
    /// The mapped entries, in process-image order.
    pub entries: Vec<EcPdoEntry>,
    /// Where the element is.
    pub span: Span,
}

/// One `Entry` of a PDO: a mapped object, or padding (index 0).
#[derive(Debug, Clone, PartialEq)]
pub struct EcPdoEntry {
    /// The mapped object's index; 0 for padding.
    pub index: u16,
    /// Its sub-index.
    pub sub: u8,
    /// `BitLen`.
    pub bit_len: u16,
    /// `Name`, if any.
    pub name: String,
    /// `DataType` as written (`UINT`, `DINT`, ...), if any.
    pub data_type: Option<String>,
    /// Where the element is.
    pub span: Span,
}

/// The `Mailbox/CoE` element.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CoeMailbox {
    /// `SdoInfo`: the SDO information service.
    pub sdo_info: bool,
    /// `PdoAssign`: PDO assignment (1C12h/1C13h) may be changed.
    pub pdo_assign: bool,
    /// `PdoConfig`: PDO mapping may be changed.
    pub pdo_config: bool,
    /// `CompleteAccess`: SDO complete access.
    pub complete_access: bool,
    /// `SegmentedSdo`.
    pub segmented_sdo: bool,
    /// `InitCmds`: SDO writes the master makes on a state transition.
    pub init_cmds: Vec<CoeInitCmd>,
}

/// One `InitCmd`.
#[derive(Debug, Clone, PartialEq)]
pub struct CoeInitCmd {
    /// Transitions (`PS`, `IP`, ...).
    pub transitions: Vec<String>,
    /// Index.
    pub index: u16,
    /// Sub-index.
    pub sub: u8,
    /// The data, as bytes.
    pub data: Vec<u8>,
    /// Whether it writes the whole object (`CompleteAccess`).
    pub complete_access: bool,
    /// Where the element is.
    pub span: Span,
}

/// One `Dc/OpMode`.
#[derive(Debug, Clone, PartialEq)]
pub struct DcOpMode {
    /// `Name` (`DC`, `FreeRun`, `SYNC0`, ...).
    pub name: String,
    /// `Desc`, if any.
    pub description: String,
    /// `AssignActivate`.
    pub assign_activate: u16,
    /// SYNC0 cycle time in ns (`CycleTimeSync0`; 0 when it follows the bus cycle).
    pub cycle_time_sync0: u32,
}

/// One `AlternativeSmMapping`: a named PDO assignment other than the `Sm` attributes' default.
#[derive(Debug, Clone, PartialEq)]
pub struct AlternativeSmMapping {
    /// `Name`.
    pub name: String,
    /// `Default="1"`: the assignment a configuration tool starts with.
    pub default: bool,
    /// Per `Sm No="n"`: the SyncManager number and the PDO indices assigned to it, in order.
    pub sms: Vec<(u8, Vec<Spanned<u16>>)>,
    /// Where the element is.
    pub span: Span,
}

/// One `Modules/Module`: a module a modular device takes in a slot.
#[derive(Debug, Clone, PartialEq)]
pub struct EcModule {
    /// `Type@ModuleIdent`, which slots name (0 when missing or not a number).
    pub ident: u32,
    /// The `Type` text.
    pub type_name: String,
    /// `Type@ModuleClass`, which slots may name instead of idents.
    pub class: Option<String>,
    /// `Name` (English, else the first).
    pub name: String,
    /// The module's `RxPdo` elements, with indices as written (before `SlotPdoIncrement`).
    pub rx_pdos: Vec<EcPdo>,
    /// The module's `TxPdo` elements, likewise.
    pub tx_pdos: Vec<EcPdo>,
    /// The module's `Profile/Dictionary` objects, with indices as written (before
    /// `SlotIndexIncrement`).
    pub objects: BTreeMap<u16, Object>,
    /// The indices written with `DependOnSlot`: they move with the instance's slot.
    pub slot_indices: SlotIndices,
    /// Where the element is.
    pub span: Span,
}

/// A module's indices whose `Index` element says `DependOnSlot="1"` (ETG.2000): per slot
/// instance, a PDO's index moves by the slot's `SlotPdoIncrement`, a mapped entry's and an
/// object's by its `SlotIndexIncrement`; the others keep their written index.
/// (`DependOnSlotGroup` is not read: no file of the corpus writes it.)
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct SlotIndices {
    /// `RxPdo`/`TxPdo` indices.
    pub pdos: BTreeSet<u16>,
    /// Mapped entries' indices.
    pub entries: BTreeSet<u16>,
    /// The module's dictionary's object indices.
    pub objects: BTreeSet<u16>,
}

/// One `Slots/Slot` of a device.
#[derive(Debug, Clone, PartialEq)]
pub struct EcSlot {
    /// `Name`.
    pub name: String,
    /// `MinInstances` (1 when absent).
    pub min_instances: u32,
    /// `MaxInstances` (1 when absent).
    pub max_instances: u32,
    /// `ModuleIdent` values: the modules allowed here.
    pub module_idents: Vec<u32>,
    /// `ModuleClass/Class` values: the module classes allowed here.
    pub module_classes: Vec<String>,
    /// The `ModuleIdent` marked `Default="1"`, if any.
    pub default_module: Option<u32>,
    /// `SlotIndexIncrement` (the slot's own, else the `Slots` element's; 0 when neither): how far
    /// a module's `DependOnSlot` object indices move per slot.
    pub index_increment: u16,
    /// `SlotPdoIncrement` (likewise): how far its PDO indices move per slot.
    pub pdo_increment: u16,
    /// Where the element is.
    pub span: Span,
}
