//! EtherCAT rules on which PDO is which and where it goes by default: an `RxPdo` or `TxPdo` whose
//! index is the other direction's mapping object (EDS819), and the dictionary's default PDO
//! assignment (1C12h, 1C13h: 1C10h + SyncManager) against the PDOs' `Sm` attributes (EDS820).

use crate::diag::{short_list, Diagnostic};
use crate::model::{Device, EcPdo, EtherCat, Value};
use crate::rules;

/// EDS819: RxPDO mapping objects are 1600h–17FFh, TxPDO ones 1A00h–1BFFh (ETG.1000.6).
pub(super) fn swapped(ec: &EtherCat, out: &mut Vec<Diagnostic>) {
    let kinds = [
        (
            "RxPdo",
            &ec.rx_pdos,
            0x1A00..=0x1BFF,
            "a TxPDO",
            "1600h-17FFh",
        ),
        (
            "TxPdo",
            &ec.tx_pdos,
            0x1600..=0x17FF,
            "an RxPDO",
            "1A00h-1BFFh",
        ),
    ];
    for (kind, pdos, wrong, other, right) in kinds {
        for pdo in pdos.iter().filter(|p| wrong.contains(&p.index)) {
            out.push(
                Diagnostic::new(
                    &rules::ESI_PDO_SWAPPED,
                    Some(pdo.span),
                    format!(
                        "{kind} `{}` has Index {:04X}h, {other} mapping object",
                        pdo.name, pdo.index
                    ),
                )
                .with_label(format!("{kind} {:04X}h", pdo.index))
                .with_help(format!(
                    "a {kind} is mapped at {right}: swap the RxPdo and TxPdo indices (or the \
                     elements), or a master configures the wrong direction and cannot reach Op"
                )),
            );
        }
    }
}

/// EDS820: for each SyncManager whose assignment object (1C10h + its number) assigns PDOs by
/// default in the dictionary, the PDOs it lists against the PDOs whose `Sm` names it.
pub(super) fn assignment_defaults(device: &Device, ec: &EtherCat, out: &mut Vec<Diagnostic>) {
    for number in 0..ec.sync_managers.len() {
        let Ok(sm) = u8::try_from(number) else { break };
        let index = 0x1C10 + u16::from(sm);
        // None assigned at power-up (sub 0 is 0) is the master's to fill from `Sm`.
        let Some(listed) = dictionary_assignment(device, index).filter(|l| !l.is_empty()) else {
            continue;
        };
        let by_sm: Vec<u16> = ec
            .rx_pdos
            .iter()
            .chain(&ec.tx_pdos)
            .filter(|p| p.sm == Some(sm))
            .map(|p: &EcPdo| p.index)
            .collect();
        let mut sorted = (listed.clone(), by_sm.clone());
        sorted.0.sort_unstable();
        sorted.1.sort_unstable();
        if sorted.0 == sorted.1 {
            continue;
        }
        // `none` only where no PDO names the SyncManager (listed is never empty here).
        let span = device.objects.get(&index).map(|o| o.span);
        let show = |list: &[u16]| {
            if list.is_empty() {
                "none".to_owned()
            } else {
                let names: Vec<String> = list.iter().map(|i| format!("{i:04X}h")).collect();
                short_list(&names)
            }
        };
        out.push(
            Diagnostic::new(
                &rules::ESI_ASSIGN_DEFAULT,
                span,
                format!(
                    "{index:04X}h assigns {} to SM{sm} by default, but the PDOs whose `Sm` is \
                     {sm} are {}",
                    show(&listed),
                    show(&by_sm)
                ),
            )
            .with_label(format!("{index:04X}h's defaults"))
            .with_help(
                "a master configures the PDOs of `Sm`; the device starts with its dictionary's \
                 assignment: make the two say the same",
            ),
        );
    }
}

/// The PDO indices an assignment object lists by default (subs 1..=its sub 0's default), when
/// the dictionary gives them.
fn dictionary_assignment(device: &Device, index: u16) -> Option<Vec<u16>> {
    let object = device.objects.get(&index)?;
    let integer = |sub: u8| match object.subs.get(&sub)?.default.as_ref()?.value {
        Some(Value::Integer(v)) => Some(v),
        _ => None,
    };
    let count = integer(0)?;
    let listed: Vec<u16> = (1..=u8::try_from(count).ok()?)
        .filter_map(integer)
        .filter_map(|v| u16::try_from(v).ok())
        .filter(|&v| v != 0)
        .collect();
    Some(listed)
}
