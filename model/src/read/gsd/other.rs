//! The top-level keywords outside the reader's blocks and main keys: supported baud rates and
//! their MaxTsdr, constant and referenced user parameter data, unit diagnostic bits, and every
//! other keyword, kept as written (reported when the specification does not define it).

use super::values::{call_arg, number, quoted};
use super::Reader;
use crate::diag::Diagnostic;
use crate::model::{DpBaud, DpBaudRate, GsdKeyword, Span, UnitDiag};
use crate::rules;

/// Keywords of the specification the model does not interpret: kept without a report.
const KNOWN_OTHER: &[&str] = &[
    "slave_family",
    "fms_supp",
    "redundancy",
    "repeater_ctrl_sig",
    "24v_pins",
    "implementation_type",
    "modul_offset",
    "info_text",
    "check_cfg_mode",
    "publisher_supp",
    "wd_base_1ms_supp",
    "max_initiate_pdu_length",
    "diagnostic_alarm_supp",
    "process_alarm_supp",
    "pull_plug_alarm_supp",
    "status_alarm_supp",
    "update_alarm_supp",
    "manufacturer_specific_alarm_supp",
    "extra_alarm_sap_supp",
    "alarm_sequence_mode_count",
    "alarm_type_mode_supp",
    "diagnostic_alarm_required",
    "ident_maintenance_supp",
    "physical_interface",
    "transmission_delay_9.6",
    "prm_block_structure_supp",
    "prm_block_structure_req",
    "jitter_compensation",
    "isochron_mode_supp",
    "isochron_mode_required",
    "hardware_release",
    "dpv1_data_types",
    "ext_module_prm_data_len",
    "max_iso_slave_intervall",
    "ds_ctrl_supp",
    "prm_structure_supp",
    "unitdiagtype",
];

/// Prefixes of such keywords (C1_/C2_ DPV1 services, bitmaps, OrderNumber-like texts...).
/// The keywords the reader interprets (`mod.rs`), spelt as the GSD specification writes them:
/// what an unknown keyword may have meant.
const INTERPRETED: &[&str] = &[
    "GSD_Revision",
    "Vendor_Name",
    "Model_Name",
    "Revision",
    "Ident_Number",
    "Protocol_Ident",
    "Station_Type",
    "Hardware_Release",
    "Software_Release",
    "OrderNumber",
    "Freeze_Mode_supp",
    "Sync_Mode_supp",
    "Auto_Baud_supp",
    "Set_Slave_Add_supp",
    "Fail_Safe",
    "DPV1_Slave",
    "Min_Slave_Intervall",
    "Modular_Station",
    "Max_Module",
    "Max_Input_Len",
    "Max_Output_Len",
    "Max_Data_Len",
    "Max_Diag_Data_Len",
    "Max_User_Prm_Data_Len",
    "User_Prm_Data_Len",
    "User_Prm_Data",
    "Unit_Diag_Area",
    "PrmText",
    "ExtUserPrmData",
    "Module",
];

const KNOWN_OTHER_PREFIXES: &[&str] = &[
    "c1_", "c2_", "bitmap_", "x_", "dxb_", "isochron", "tbase_", "t_", "ti_", "to_", "ppo",
    "vendor_", "mod_", "prm_", "info_", "cs_", "sub_",
];

impl Reader {
    pub(super) fn other_keyword(&mut self, lower: &str, key: &str, value: &str, span: Span) {
        if let Some(rate) = lower
            .strip_suffix("_supp")
            .and_then(DpBaudRate::from_keyword)
        {
            if self.flag(value, span) {
                let tsdr = self.dp.orphan_tsdr.iter().position(|(r, _)| *r == rate);
                let _ = tsdr.map(|i| self.dp.orphan_tsdr.remove(i));
                self.dp.baud_rates.push(DpBaud {
                    rate,
                    max_tsdr: None,
                    span,
                });
                self.dp.baud_rates.sort_by_key(|b| b.rate);
            }
            return;
        }
        if let Some(rate) = lower
            .strip_prefix("maxtsdr_")
            .and_then(DpBaudRate::from_keyword)
        {
            let tsdr = self.u32(value, span);
            match self.dp.baud_rates.iter_mut().find(|b| b.rate == rate) {
                Some(baud) => baud.max_tsdr = tsdr,
                None => self.dp.orphan_tsdr.push((rate, span)),
            }
            return;
        }
        if let Some(c) = self.prm_const(lower, value, span) {
            self.dp.prm_consts.push(c);
            return;
        }
        if let Some(r) = self.prm_ref(lower, value, span) {
            self.dp.prm_refs.push(r);
            return;
        }
        let bit = call_arg(lower, "unit_diag_bit")
            .map(|a| (a, false))
            .or_else(|| call_arg(lower, "unit_diag_not_bit").map(|a| (a, true)));
        if let Some((arg, not)) = bit {
            match (
                number(arg).and_then(|n| u32::try_from(n).ok()),
                quoted(value),
            ) {
                (Some(bit), Some(text)) => self.dp.unit_diag.push(UnitDiag {
                    bits: (bit, bit),
                    value: None,
                    not,
                    text,
                    span,
                }),
                _ => self.bad(span, "`Unit_Diag_Bit(n) = \"text\"`", value),
            }
            return;
        }
        let known = KNOWN_OTHER.contains(&lower)
            || KNOWN_OTHER_PREFIXES.iter().any(|p| lower.starts_with(p));
        if !known {
            let candidates = INTERPRETED
                .iter()
                .map(|k| (k.to_ascii_lowercase(), (*k).to_owned()))
                .chain(
                    KNOWN_OTHER
                        .iter()
                        .map(|k| ((*k).to_owned(), (*k).to_owned())),
                );
            let message = format!("unknown keyword `{key}` (kept, not interpreted)");
            let typo = crate::did_you_mean::misspelt(lower, candidates);
            match typo {
                Some(meant) => self.diags.push(
                    Diagnostic::new(&rules::GSD_UNKNOWN, Some(span), message)
                        .with_help(format!("did you mean `{meant}`?")),
                ),
                None => self.diag(&rules::GSD_UNKNOWN, Some(span), message),
            }
        }
        self.dp.other.push(GsdKeyword {
            key: key.to_owned(),
            value: value.to_owned(),
            span,
        });
    }
}
