//! `edsgen devices`: the devices of an ESI file, one line each, to pick one with `--device`.

use std::path::Path;
use std::process::ExitCode;

use edsgen_model::model::{Device, EcPdo, Format};
use edsgen_model::read::{self, esi};
use edsgen_model::render;

use super::{fail, print_stdout};

/// Runs `edsgen devices FILE`: one tab-separated line per device (type name, product code,
/// revision, profiles, bits the default assignment maps to outputs and inputs, name). Exit 1 for
/// a file without devices (or not readable as XML) and, as `edsgen validate` says, for a file that
/// is empty or not text (EDS022, EDS029); 2 for another file that is not ESI.
pub fn run(path: &Path) -> ExitCode {
    let bytes = match std::fs::read(path) {
        Ok(bytes) => bytes,
        Err(err) => return fail(format!("{}: {err}", path.display())),
    };
    if read::detect_format(path, &bytes) != Format::Esi {
        // One answer for one file: what `validate` and `dump` report for it, when nothing of it
        // can be read at all.
        let read = read::read_bytes(path, &bytes);
        if read.nothing_read() {
            return rendered(path, &read);
        }
        return fail(format!(
            "{}: not an ESI file; a CANopen description has one device",
            path.display()
        ));
    }
    let all = esi::read_all(path, &bytes);
    if all.is_empty() {
        return rendered(path, &read::read_bytes(path, &bytes));
    }
    let lines: String = all.iter().map(|(device, _)| line(device) + "\n").collect();
    print_stdout(&lines);
    ExitCode::SUCCESS
}

/// Prints why nothing of `path` could be read, as `edsgen validate` does; exit 1.
fn rendered(path: &Path, read: &read::Read) -> ExitCode {
    let name = path.display().to_string();
    eprint!(
        "{}",
        render::human(&name, &read.text, &read.diagnostics, false)
    );
    ExitCode::from(1)
}

/// `TD-1 #x00009252 #x00000001 profile 402 out 56 bits in 16 bits Test drive`, tab-separated.
fn line(device: &Device) -> String {
    let info = &device.device_info;
    let hex = |n: Option<u32>| n.map_or("-".to_owned(), |n| format!("#x{n:08X}"));
    let Some(ec) = device.ethercat() else {
        return String::new();
    };
    let assigned = |pdos: &[EcPdo]| -> u64 {
        pdos.iter()
            .filter(|p| p.sm.is_some())
            .flat_map(|p| &p.entries)
            .map(|e| u64::from(e.bit_len))
            .sum()
    };
    let profiles = if ec.profiles.is_empty() {
        "-".to_owned()
    } else {
        let numbers: Vec<String> = ec.profiles.iter().map(u32::to_string).collect();
        numbers.join(",")
    };
    [
        ec.type_name.clone(),
        hex(info.product_number.as_ref().map(|n| n.value)),
        hex(info.revision_number.as_ref().map(|n| n.value)),
        format!("profile {profiles}"),
        format!("out {} bits", assigned(&ec.rx_pdos)),
        format!("in {} bits", assigned(&ec.tx_pdos)),
        info.product_name.clone().unwrap_or_else(|| "-".to_owned()),
    ]
    .join("\t")
}
