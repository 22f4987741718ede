//! SII image reader: an EtherCAT device's EEPROM contents (ETG.2010, as `edsgen sii` writes them
//! or a master reads them from a device) into the model's EtherCAT part, so that `edsgen dump`
//! shows an image in the same form as an ESI file. What an image holds: the identity (words
//! 0x08–0x0D), the name and type from the Strings and General categories, the CoE details, the
//! SyncManagers (SyncM) and the PDOs (TxPDO/RxPDO). An image has no object dictionary: the
//! model's objects stay empty. The format is recorded as ESI (the model an ESI gives).
//!
//! Problems are `EDS818` diagnostics without a line (a binary has none): an image shorter than
//! its 64-word header, a configuration-area CRC that does not match, a category running past
//! the end, no end marker. What was read before a problem is kept.

use std::path::Path;

use super::Read;
use crate::diag::Diagnostic;
use crate::model::*;
use crate::rules;
use crate::sii::{category, crc8, pdo_flag};

/// Whether `path` names an SII image (extension `.bin` or `.sii`, any case).
pub fn is_sii_path(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("bin") || e.eq_ignore_ascii_case("sii"))
}

/// Reads an SII image.
pub fn read(path: &Path, bytes: &[u8]) -> Read {
    let mut device = super::eds::empty_device(path, Format::Esi, TextEncoding::Ascii);
    let mut diagnostics = Vec::new();
    let mut problem = |message: String| {
        diagnostics.push(Diagnostic::new(&rules::SII_IMAGE, None, message));
    };
    if bytes.len() < 0x80 {
        problem(format!(
            "an SII image of {} bytes: shorter than its 64-word header",
            bytes.len()
        ));
        return Read {
            device,
            diagnostics,
            text: String::new(),
        };
    }
    if crc8(&bytes[..14]) != bytes[14] {
        problem(format!(
            "the configuration area's CRC (word 7) is {:#04X}, but words 0-6 give {:#04X}",
            bytes[14],
            crc8(&bytes[..14])
        ));
    }
    let word = |w: usize| u16::from_le_bytes([bytes[2 * w], bytes[2 * w + 1]]);
    let dword = |w: usize| u32::from(word(w)) | u32::from(word(w + 1)) << 16;
    let here = Span::new(1, 1, 0);
    let info = &mut device.device_info;
    info.vendor_number = Some(Spanned::new(dword(0x08), here));
    info.product_number = Some(Spanned::new(dword(0x0A), here));
    info.revision_number = Some(Spanned::new(dword(0x0C), here));
    let mut ec = EtherCat {
        span: here,
        ..EtherCat::default()
    };

    let mut categories = Vec::new();
    let mut at = 0x80;
    loop {
        let Some(kind) = bytes.get(at..at + 2) else {
            problem(format!(
                "no end marker (0xFFFF): the image ends at byte {at}"
            ));
            break;
        };
        let kind = u16::from_le_bytes([kind[0], kind[1]]);
        if kind == category::END {
            break;
        }
        let Some(header) = bytes.get(at..at + 4) else {
            problem(format!(
                "category {kind} at byte {at}: its length is past the image's end"
            ));
            break;
        };
        let len = 2 * usize::from(u16::from_le_bytes([header[2], header[3]]));
        let Some(data) = bytes.get(at + 4..at + 4 + len) else {
            problem(format!(
                "category {kind} at byte {at} says {len} bytes, past the image's end"
            ));
            break;
        };
        categories.push((kind, data));
        at += 4 + len;
    }

    let strings = categories
        .iter()
        .find(|(kind, _)| *kind == category::STRINGS)
        .map(|(_, data)| strings(data))
        .unwrap_or_default();
    let string = |n: u8| {
        usize::from(n)
            .checked_sub(1)
            .and_then(|i| strings.get(i))
            .cloned()
            .unwrap_or_default()
    };
    let coe_mailbox = word(0x1C) & 0x0004 != 0;
    for (kind, data) in &categories {
        match *kind {
            category::GENERAL if data.len() >= 6 => {
                ec.type_name = string(data[2]);
                let name = string(data[3]);
                device.device_info.product_name = (!name.is_empty()).then_some(name);
                if coe_mailbox || data[5] & 1 != 0 {
                    ec.coe = Some(CoeMailbox {
                        sdo_info: data[5] & 0x02 != 0,
                        pdo_assign: data[5] & 0x04 != 0,
                        pdo_config: data[5] & 0x08 != 0,
                        complete_access: data[5] & 0x20 != 0,
                        ..CoeMailbox::default()
                    });
                }
            }
            category::SYNC_M => {
                for sm in data.chunks_exact(8) {
                    ec.sync_managers.push(SyncManager {
                        kind: match sm[7] {
                            1 => SmKind::MailboxOut,
                            2 => SmKind::MailboxIn,
                            3 => SmKind::Outputs,
                            4 => SmKind::Inputs,
                            other => SmKind::Other(format!("type {other}")),
                        },
                        start_address: u16::from_le_bytes([sm[0], sm[1]]),
                        default_size: Some(u16::from_le_bytes([sm[2], sm[3]])),
                        control_byte: sm[4],
                        enable: sm[6] & 1 != 0,
                        span: here,
                    });
                }
            }
            category::TX_PDO | category::RX_PDO => {
                let Some(pdo) = pdo(data, &string, here) else {
                    problem(format!(
                        "a PDO category of {} bytes: shorter than its header and entries",
                        data.len()
                    ));
                    continue;
                };
                if *kind == category::TX_PDO {
                    ec.tx_pdos.push(pdo);
                } else {
                    ec.rx_pdos.push(pdo);
                }
            }
            _ => {}
        }
    }
    device.bus = Bus::EtherCat(ec);
    Read {
        device,
        diagnostics,
        text: String::new(),
    }
}

/// A PDO category: its 8-byte header and 8-byte entries (`None` when cut short).
fn pdo(data: &[u8], string: &impl Fn(u8) -> String, here: Span) -> Option<EcPdo> {
    let header = data.get(..8)?;
    let count = usize::from(header[2]);
    let flags = u16::from_le_bytes([header[6], header[7]]);
    let entries = data.get(8..8 + 8 * count)?;
    Some(EcPdo {
        index: u16::from_le_bytes([header[0], header[1]]),
        name: string(header[5]),
        sm: (header[3] != 0xFF).then_some(header[3]),
        fixed: flags & pdo_flag::FIXED_CONTENT != 0,
        mandatory: flags & pdo_flag::MANDATORY != 0,
        exclude: Vec::new(),
        entries: entries
            .chunks_exact(8)
            .map(|e| EcPdoEntry {
                index: u16::from_le_bytes([e[0], e[1]]),
                sub: e[2],
                bit_len: u16::from(e[5]),
                name: string(e[3]),
                data_type: type_name(e[4]).map(str::to_owned),
                span: here,
            })
            .collect(),
        span: here,
    })
}

/// The ESI name of a CoE data type code, if it has one.
fn type_name(code: u8) -> Option<&'static str> {
    const NAMES: &[&str] = &[
        "BOOL", "SINT", "INT", "DINT", "USINT", "UINT", "UDINT", "REAL", "LREAL", "LINT", "ULINT",
        "BYTE", "WORD", "DWORD", "BIT1", "BIT2", "BIT3", "BIT4", "BIT5", "BIT6", "BIT7", "BIT8",
    ];
    NAMES
        .iter()
        .copied()
        .find(|name| crate::sii::data_type_code(name) == Some(code))
}

/// The Strings category's strings (a string cut short by the category's end is kept as far as
/// it goes; bytes that are not UTF-8 are replaced).
fn strings(data: &[u8]) -> Vec<String> {
    let Some((&count, mut rest)) = data.split_first() else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for _ in 0..count {
        let Some((&len, tail)) = rest.split_first() else {
            break;
        };
        let len = usize::from(len).min(tail.len());
        out.push(String::from_utf8_lossy(&tail[..len]).into_owned());
        rest = &tail[len..];
    }
    out
}
