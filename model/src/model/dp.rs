//! The PROFIBUS-DP side of a device read from a GSD file (IEC 61784 / the PNO's GSD
//! specification): what a DP master needs to bring the slave to data exchange (identity, baud
//! rates with MaxTsdr, the master's flags, the modules' configuration bytes decoded, the
//! parameterisation with its defaults and ranges) and what a configuration tool shows (texts,
//! slots, unit diagnosis). Every part keeps its [`Span`].

use super::{Span, Spanned};

/// A DP baud rate: the GSD keyword's suffix (`9.6`, `1.5M`, ...).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum DpBaudRate {
    /// 9.6 kbit/s.
    B9k6,
    /// 19.2 kbit/s.
    B19k2,
    /// 31.25 kbit/s (PA couplers).
    B31k25,
    /// 45.45 kbit/s.
    B45k45,
    /// 93.75 kbit/s.
    B93k75,
    /// 187.5 kbit/s.
    B187k5,
    /// 500 kbit/s.
    B500k,
    /// 1.5 Mbit/s.
    B1M5,
    /// 3 Mbit/s.
    B3M,
    /// 6 Mbit/s.
    B6M,
    /// 12 Mbit/s.
    B12M,
}

impl DpBaudRate {
    /// Every rate, slowest first.
    pub const ALL: [DpBaudRate; 11] = [
        DpBaudRate::B9k6,
        DpBaudRate::B19k2,
        DpBaudRate::B31k25,
        DpBaudRate::B45k45,
        DpBaudRate::B93k75,
        DpBaudRate::B187k5,
        DpBaudRate::B500k,
        DpBaudRate::B1M5,
        DpBaudRate::B3M,
        DpBaudRate::B6M,
        DpBaudRate::B12M,
    ];

    /// The keyword suffix (`9.6` in `9.6_supp` and `MaxTsdr_9.6`).
    pub const fn keyword(self) -> &'static str {
        match self {
            DpBaudRate::B9k6 => "9.6",
            DpBaudRate::B19k2 => "19.2",
            DpBaudRate::B31k25 => "31.25",
            DpBaudRate::B45k45 => "45.45",
            DpBaudRate::B93k75 => "93.75",
            DpBaudRate::B187k5 => "187.5",
            DpBaudRate::B500k => "500",
            DpBaudRate::B1M5 => "1.5M",
            DpBaudRate::B3M => "3M",
            DpBaudRate::B6M => "6M",
            DpBaudRate::B12M => "12M",
        }
    }

    /// The rate in bit/s.
    pub const fn bits_per_second(self) -> u32 {
        match self {
            DpBaudRate::B9k6 => 9_600,
            DpBaudRate::B19k2 => 19_200,
            DpBaudRate::B31k25 => 31_250,
            DpBaudRate::B45k45 => 45_450,
            DpBaudRate::B93k75 => 93_750,
            DpBaudRate::B187k5 => 187_500,
            DpBaudRate::B500k => 500_000,
            DpBaudRate::B1M5 => 1_500_000,
            DpBaudRate::B3M => 3_000_000,
            DpBaudRate::B6M => 6_000_000,
            DpBaudRate::B12M => 12_000_000,
        }
    }

    /// The rate of a keyword suffix (case-insensitive).
    pub fn from_keyword(text: &str) -> Option<DpBaudRate> {
        DpBaudRate::ALL
            .into_iter()
            .find(|rate| rate.keyword().eq_ignore_ascii_case(text))
    }
}

/// A supported baud rate and its MaxTsdr (bit times the slave may take to answer).
#[derive(Debug, Clone, PartialEq)]
pub struct DpBaud {
    /// The rate.
    pub rate: DpBaudRate,
    /// `MaxTsdr_x`, if given.
    pub max_tsdr: Option<u32>,
    /// Where `x_supp` is.
    pub span: Span,
}

/// One identifier of a module's configuration (Chk_Cfg) bytes, decoded.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CfgIdentifier {
    /// The identifier's bytes as written (header, length bytes, manufacturer data).
    pub bytes: Vec<u8>,
    /// Input bytes (slave to master).
    pub input_bytes: u32,
    /// Output bytes (master to slave).
    pub output_bytes: u32,
    /// Words rather than bytes (bit 6).
    pub words: bool,
    /// Consistent over the whole length (bit 7).
    pub consistent: bool,
    /// The special format (bits 4–5 zero).
    pub special: bool,
    /// Manufacturer-specific bytes of the special format.
    pub manufacturer_data: Vec<u8>,
}

/// Why configuration bytes cannot be decoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CfgError {
    /// An identifier at this byte offset says more bytes follow than there are.
    Truncated(usize),
}

/// Decodes configuration bytes (EN 50170: general identifier format and special format).
pub fn decode_cfg(bytes: &[u8]) -> Result<Vec<CfgIdentifier>, CfgError> {
    let mut out = Vec::new();
    let mut at = 0;
    while at < bytes.len() {
        let header = bytes[at];
        let start = at;
        at += 1;
        let mut id = CfgIdentifier {
            bytes: Vec::new(),
            input_bytes: 0,
            output_bytes: 0,
            words: false,
            consistent: false,
            special: false,
            manufacturer_data: Vec::new(),
        };
        let length = |byte: u8, bits: u8| -> (u32, bool, bool) {
            let words = byte & 0x40 != 0;
            let n = u32::from(byte & bits) + 1;
            (if words { 2 * n } else { n }, words, byte & 0x80 != 0)
        };
        let direction = (header >> 4) & 0x03;
        if direction != 0 {
            let (n, words, consistent) = length(header, 0x0F);
            id.words = words;
            id.consistent = consistent;
            if direction & 0b01 != 0 {
                id.input_bytes = n;
            }
            if direction & 0b10 != 0 {
                id.output_bytes = n;
            }
        } else if header != 0 {
            id.special = true;
            let kind = header >> 6;
            let manufacturer = usize::from(header & 0x0F);
            // Output length byte first, then input (11: both).
            if kind & 0b10 != 0 {
                let byte = *bytes.get(at).ok_or(CfgError::Truncated(start))?;
                at += 1;
                let (n, words, consistent) = length(byte, 0x3F);
                id.output_bytes = n;
                id.words |= words;
                id.consistent |= consistent;
            }
            if kind & 0b01 != 0 {
                let byte = *bytes.get(at).ok_or(CfgError::Truncated(start))?;
                at += 1;
                let (n, words, consistent) = length(byte, 0x3F);
                id.input_bytes = n;
                id.words |= words;
                id.consistent |= consistent;
            }
            let end = at + manufacturer;
            let data = bytes.get(at..end).ok_or(CfgError::Truncated(start))?;
            id.manufacturer_data = data.to_vec();
            at = end;
        }
        id.bytes = bytes[start..at].to_vec();
        out.push(id);
    }
    Ok(out)
}

/// A module: its name and configuration bytes.
#[derive(Debug, Clone, PartialEq)]
pub struct DpModule {
    /// The name as written.
    pub name: String,
    /// The configuration bytes (Chk_Cfg).
    pub config: Vec<u8>,
    /// The module reference number (GSD revision 3: the number on the line after `Module`).
    pub reference: Option<u32>,
    /// `Ext_Module_Prm_Data_Len`.
    pub prm_data_len: Option<u32>,
    /// The module's `Ext_User_Prm_Data_Const(n)` blocks.
    pub prm_consts: Vec<PrmConst>,
    /// The module's `Ext_User_Prm_Data_Ref(n)` entries.
    pub prm_refs: Vec<PrmRef>,
    /// Where `Module` is.
    pub span: Span,
}

impl DpModule {
    /// The decoded identifiers (empty on an error, which the validator reports).
    pub fn identifiers(&self) -> Vec<CfgIdentifier> {
        decode_cfg(&self.config).unwrap_or_default()
    }

    /// The module's parameter bytes in Set_Prm (GSD defaults): `Ext_Module_Prm_Data_Len`
    /// bytes, overlaid by its `Ext_User_Prm_Data_Const` blocks and the defaults its
    /// `Ext_User_Prm_Data_Ref` entries place, offsets counted from the module's first byte
    /// (`dp` holds the definitions). Without `Ext_Module_Prm_Data_Len`, as long as its
    /// constants and references reach; none for a module without parameters.
    pub fn default_prm_data(&self, dp: &Dp) -> Vec<u8> {
        let len = self.prm_data_len.unwrap_or(0) as usize;
        let mut data = prm_defaults(
            vec![0; len],
            &self.prm_consts,
            &self.prm_refs,
            &dp.prm_definitions,
        );
        if self.prm_data_len.is_some() {
            data.truncate(len);
        }
        data
    }

    /// Input and output bytes of the module.
    pub fn io_lengths(&self) -> (u32, u32) {
        self.identifiers().iter().fold((0, 0), |(i, o), id| {
            (i + id.input_bytes, o + id.output_bytes)
        })
    }
}

/// `Ext_User_Prm_Data_Const(offset) = bytes`.
#[derive(Debug, Clone, PartialEq)]
pub struct PrmConst {
    /// Byte offset in User_Prm_Data.
    pub offset: u32,
    /// The bytes.
    pub bytes: Vec<u8>,
    /// Where it is.
    pub span: Span,
}

/// `Ext_User_Prm_Data_Ref(offset) = reference`.
#[derive(Debug, Clone, PartialEq)]
pub struct PrmRef {
    /// Byte offset in User_Prm_Data.
    pub offset: u32,
    /// The `ExtUserPrmData` it places there.
    pub reference: u32,
    /// Where it is.
    pub span: Span,
}

/// The data type of a parameter definition.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PrmType {
    /// `Bit(n)`: one bit of a byte.
    Bit(u8),
    /// `BitArea(first-last)`: bits of a byte.
    BitArea(u8, u8),
    /// `Unsigned8`, `Unsigned16`, `Unsigned32`: 1, 2 or 4 bytes.
    Unsigned(u8),
    /// `Signed8`, `Signed16`, `Signed32`.
    Signed(u8),
}

impl PrmType {
    /// Bytes the parameter takes in User_Prm_Data.
    pub const fn size(self) -> u32 {
        match self {
            PrmType::Bit(_) | PrmType::BitArea(..) => 1,
            PrmType::Unsigned(n) | PrmType::Signed(n) => n as u32,
        }
    }

    /// The lowest and highest value the type holds.
    pub fn bounds(self) -> (i64, i64) {
        match self {
            PrmType::Bit(_) => (0, 1),
            PrmType::BitArea(first, last) => (0, (1i64 << (last.saturating_sub(first) + 1)) - 1),
            PrmType::Unsigned(n) => (0, (1i64 << (8 * u32::from(n))) - 1),
            PrmType::Signed(n) => {
                let half = 1i64 << (8 * u32::from(n) - 1);
                (-half, half - 1)
            }
        }
    }
}

/// The values a parameter may take.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PrmValues {
    /// `min-max`.
    Range(i64, i64),
    /// `a,b,c`.
    List(Vec<i64>),
    /// Nothing written: the type's bounds.
    Any,
}

/// `ExtUserPrmData = reference "name"` ... `EndExtUserPrmData`.
#[derive(Debug, Clone, PartialEq)]
pub struct ExtUserPrmData {
    /// The reference number.
    pub reference: u32,
    /// The name.
    pub name: String,
    /// The type.
    pub data_type: PrmType,
    /// The default value.
    pub default: i64,
    /// The allowed values.
    pub values: PrmValues,
    /// `Prm_Text_Ref`.
    pub text_ref: Option<u32>,
    /// Where the block starts.
    pub span: Span,
    /// Where the type line is.
    pub type_span: Span,
}

/// `PrmText = reference` ... `EndPrmText`.
#[derive(Debug, Clone, PartialEq)]
pub struct PrmText {
    /// The reference number.
    pub reference: u32,
    /// `Text(value) = "text"` in order.
    pub texts: Vec<(i64, String)>,
    /// Where the block starts.
    pub span: Span,
}

/// `Slot(n) = "name" default allowed` in a `SlotDefinition` block.
#[derive(Debug, Clone, PartialEq)]
pub struct DpSlot {
    /// The slot number.
    pub number: u32,
    /// The name.
    pub name: String,
    /// The default module's reference.
    pub default_module: u32,
    /// The allowed modules' references (`a-b` or `a,b,c` expanded).
    pub allowed: Vec<u32>,
    /// Where it is.
    pub span: Span,
}

/// A unit diagnosis text: `Unit_Diag_Bit(n)`, `Unit_Diag_Not_Bit(n)` or a
/// `Unit_Diag_Area = a-b` block's `Value(v)`.
#[derive(Debug, Clone, PartialEq)]
pub struct UnitDiag {
    /// The bit (or the area's first and last bits).
    pub bits: (u32, u32),
    /// The value within an area (`None` for a bit).
    pub value: Option<i64>,
    /// Whether the text is for the bit being 0 (`Unit_Diag_Not_Bit`).
    pub not: bool,
    /// The text.
    pub text: String,
    /// Where it is.
    pub span: Span,
}

/// A keyword kept as written (unknown ones, for the report and round trips).
#[derive(Debug, Clone, PartialEq)]
pub struct GsdKeyword {
    /// The keyword as written.
    pub key: String,
    /// The value as written (continuations joined).
    pub value: String,
    /// Where it is.
    pub span: Span,
}

/// The DP side of a GSD file.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Dp {
    /// `GSD_Revision`.
    pub gsd_revision: Option<u32>,
    /// `Vendor_Name`.
    pub vendor_name: Option<String>,
    /// `Model_Name`.
    pub model_name: Option<String>,
    /// `Revision`.
    pub revision: Option<String>,
    /// `OrderNumber`.
    pub order_number: Option<String>,
    /// `Hardware_Release`.
    pub hardware_release: Option<String>,
    /// `Software_Release`.
    pub software_release: Option<String>,
    /// `Ident_Number`.
    pub ident_number: Option<Spanned<u16>>,
    /// `Protocol_Ident` (0 DP).
    pub protocol_ident: Option<u32>,
    /// `Station_Type` (0 DP slave).
    pub station_type: Option<u32>,
    /// Supported baud rates (`x_supp = 1`), slowest first.
    pub baud_rates: Vec<DpBaud>,
    /// `MaxTsdr_x` for a rate without `x_supp = 1` (kept for the validator).
    pub orphan_tsdr: Vec<(DpBaudRate, Span)>,
    /// `Auto_Baud_supp`.
    pub auto_baud: bool,
    /// `Freeze_Mode_supp`.
    pub freeze: bool,
    /// `Sync_Mode_supp`.
    pub sync: bool,
    /// `Fail_Safe`.
    pub fail_safe: bool,
    /// `Set_Slave_Add_supp`.
    pub set_slave_add: bool,
    /// `DPV1_Slave`.
    pub dpv1: bool,
    /// `Min_Slave_Intervall` in 100 µs.
    pub min_slave_interval: Option<u32>,
    /// `Max_Diag_Data_Len`.
    pub max_diag_data_len: Option<u32>,
    /// `Modular_Station`.
    pub modular_station: bool,
    /// `Max_Module`.
    pub max_module: Option<u32>,
    /// `Max_Input_Len`.
    pub max_input_len: Option<Spanned<u32>>,
    /// `Max_Output_Len`.
    pub max_output_len: Option<Spanned<u32>>,
    /// `Max_Data_Len`.
    pub max_data_len: Option<Spanned<u32>>,
    /// `User_Prm_Data_Len`.
    pub user_prm_data_len: Option<Spanned<u32>>,
    /// `User_Prm_Data`.
    pub user_prm_data: Vec<u8>,
    /// `Max_User_Prm_Data_Len`.
    pub max_user_prm_data_len: Option<Spanned<u32>>,
    /// The device's `Ext_User_Prm_Data_Const(n)` blocks.
    pub prm_consts: Vec<PrmConst>,
    /// The device's `Ext_User_Prm_Data_Ref(n)` entries.
    pub prm_refs: Vec<PrmRef>,
    /// `ExtUserPrmData` definitions.
    pub prm_definitions: Vec<ExtUserPrmData>,
    /// `PrmText` blocks.
    pub prm_texts: Vec<PrmText>,
    /// Modules in file order.
    pub modules: Vec<DpModule>,
    /// `SlotDefinition` slots.
    pub slots: Vec<DpSlot>,
    /// Unit diagnosis texts.
    pub unit_diag: Vec<UnitDiag>,
    /// Keywords the reader does not interpret, as written.
    pub other: Vec<GsdKeyword>,
    /// The module whose 32-byte images are INVT's PKW/PZD layout (4 PKW + 12 PZD words), as
    /// the overlay's `[pkw_pzd] module` says: its generated images convert to and from
    /// `edsgen_runtime::pkw_pzd`'s. A GSD cannot say it.
    pub pkw_pzd_module: Option<String>,
    /// The modules chosen for a modular station (the overlay's `[modules]`); `None`: the
    /// default configuration ([`Dp::configuration`]).
    pub chosen: Option<super::modules::DpConfiguration>,
}

impl Dp {
    /// The configuration the slave runs with: the chosen one, else its first module whose
    /// configuration bytes decode, in the first slot (a compact station's one module).
    pub fn configuration(&self) -> super::modules::DpConfiguration {
        use super::modules::{dp_first_slot, DpConfiguration, DpPlugged};
        if let Some(chosen) = &self.chosen {
            return chosen.clone();
        }
        let first = self
            .modules
            .iter()
            .position(|m| !m.config.is_empty() && decode_cfg(&m.config).is_ok());
        DpConfiguration {
            slots: first
                .map(|module| DpPlugged {
                    slot: dp_first_slot(self),
                    module,
                })
                .into_iter()
                .collect(),
        }
    }

    /// The parameterisation's default bytes (DP's User_Prm_Data after the seven standard
    /// Set_Prm bytes): `User_Prm_Data`, overlaid by the device's `Ext_User_Prm_Data_Const`
    /// blocks, then by the defaults of the definitions its `Ext_User_Prm_Data_Ref` entries place
    /// (the modules' own parameter blocks are not included).
    pub fn default_user_prm_data(&self) -> Vec<u8> {
        prm_defaults(
            self.user_prm_data.clone(),
            &self.prm_consts,
            &self.prm_refs,
            &self.prm_definitions,
        )
    }

    /// The slave's own parameter bytes in Set_Prm: [`Dp::default_user_prm_data`], padded with
    /// zeros to `User_Prm_Data_Len` when that is longer (the modules' follow them:
    /// [`crate::model::modules::DpConfiguration::user_prm_data`]).
    pub fn own_prm_data(&self) -> Vec<u8> {
        let mut data = self.default_user_prm_data();
        if let Some(len) = &self.user_prm_data_len {
            if (len.value as usize) > data.len() {
                data.resize(len.value as usize, 0);
            }
        }
        data
    }
}

/// Parameter bytes from `data`: overlaid by the `consts` in offset order, then by the defaults
/// of the definitions (`defs`) the `refs` place (a device's or a module's own block).
pub(crate) fn prm_defaults(
    mut data: Vec<u8>,
    consts: &[PrmConst],
    refs: &[PrmRef],
    defs: &[ExtUserPrmData],
) -> Vec<u8> {
    let mut consts: Vec<&PrmConst> = consts.iter().collect();
    consts.sort_by_key(|c| c.offset);
    fn put(data: &mut Vec<u8>, offset: usize, bytes: &[u8]) {
        if data.len() < offset + bytes.len() {
            data.resize(offset + bytes.len(), 0);
        }
        data[offset..offset + bytes.len()].copy_from_slice(bytes);
    }
    for c in consts {
        put(&mut data, c.offset as usize, &c.bytes);
    }
    for r in refs {
        let Some(def) = defs.iter().find(|d| d.reference == r.reference) else {
            continue;
        };
        let at = r.offset as usize;
        match def.data_type {
            PrmType::Bit(bit) => {
                let mut byte = [data.get(at).copied().unwrap_or(0)];
                byte[0] = byte[0] & !(1 << (bit & 7)) | (((def.default & 1) as u8) << (bit & 7));
                put(&mut data, at, &byte);
            }
            PrmType::BitArea(first, last) => {
                let width = last.saturating_sub(first) + 1;
                let mask = (((1u16 << width) - 1) << first) as u8;
                let value = ((def.default as u16) << first) as u8 & mask;
                let byte = [data.get(at).copied().unwrap_or(0) & !mask | value];
                put(&mut data, at, &byte);
            }
            PrmType::Unsigned(n) | PrmType::Signed(n) => {
                let bytes = (def.default as u32).to_be_bytes();
                put(&mut data, at, &bytes[4 - usize::from(n)..]);
            }
        }
    }
    data
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cfg_bytes_decode() {
        // F3: 4 words in and out, consistent (PKW). FB: 12 words in and out, consistent.
        let ids = decode_cfg(&[0xF3, 0xFB]).unwrap();
        assert_eq!((ids[0].input_bytes, ids[0].output_bytes), (8, 8));
        assert!(ids[0].consistent && ids[0].words && !ids[0].special);
        assert_eq!((ids[1].input_bytes, ids[1].output_bytes), (24, 24));
        // 10: 1 input byte; 20: 1 output byte; 00: empty slot.
        let ids = decode_cfg(&[0x10, 0x20, 0x00]).unwrap();
        assert_eq!(
            ids.iter()
                .map(|i| (i.input_bytes, i.output_bytes))
                .collect::<Vec<_>>(),
            [(1, 0), (0, 1), (0, 0)]
        );
        // Special: C2 = output and input length bytes, 2 manufacturer bytes.
        let ids = decode_cfg(&[0xC2, 0x41, 0x83, 0xAA, 0xBB]).unwrap();
        assert!(ids[0].special);
        assert_eq!((ids[0].output_bytes, ids[0].input_bytes), (4, 4));
        assert_eq!(ids[0].manufacturer_data, [0xAA, 0xBB]);
        assert_eq!(decode_cfg(&[0x40]), Err(CfgError::Truncated(0)));
        assert_eq!(decode_cfg(&[0x10, 0x83, 0x41]), Err(CfgError::Truncated(1)));
    }
}
