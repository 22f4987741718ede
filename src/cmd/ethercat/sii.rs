//! `edsgen sii FILE [--device NAME|#xCODE] -o eeprom.bin`: the SII (EEPROM) image of an ESI
//! device, as the EtherCAT simulator serves it and as a real ESC's EEPROM would hold it
//! (`edsgen_model::sii`; docs/ethercat-sii.md says what the image holds and what is our
//! choice).

use std::path::Path;
use std::process::ExitCode;

use edsgen_model::{render, sii};

use crate::cmd::fail;

/// Runs `edsgen sii`: 0 when written, 1 when the file could not be read, 2 for a file that is
/// not an ESI device or an image that cannot be written.
pub fn run(path: &Path, device: Option<&str>, output: &Path) -> ExitCode {
    let read = match crate::cmd::load(path, device) {
        Ok(read) => read,
        Err(err) => return fail(err),
    };
    if read.nothing_read {
        let name = path.display().to_string();
        eprint!(
            "{}",
            render::human(&name, &read.text, &read.diagnostics, false)
        );
        return ExitCode::from(1);
    }
    let image = match sii::build(&read.device) {
        Ok(image) => image,
        Err(message) => return fail(format!("{}: {message}", path.display())),
    };
    if let Err(err) = std::fs::write(output, &image) {
        return fail(format!("cannot write `{}`: {err}", output.display()));
    }
    eprintln!(
        "wrote {} bytes ({} words) of SII to {}",
        image.len(),
        image.len() / 2,
        output.display()
    );
    ExitCode::SUCCESS
}
