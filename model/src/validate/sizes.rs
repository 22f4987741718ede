//! Sizes the generated code cannot hold (EDS707), from the value image's layout.

use crate::diag::Diagnostic;
use crate::model::layout::{capacity, image_size, is_bytes, stored_entries, MAX_IMAGE_SIZE};
use crate::model::Device;
use crate::rules;

/// The sizes the generated code cannot hold (EDS707): an entry longer than 65535 bytes, or a
/// device whose values need more than [`MAX_IMAGE_SIZE`] bytes in all (the value image's
/// offsets are 16-bit, 2 bytes of flash per entry rather than 4). The validator reports them
/// too, so a file `edsgen validate` passes is a file the generator takes.
pub fn size_errors(device: &Device) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    let mut total = 0usize;
    for object in device.objects.values() {
        let before = total;
        for sub in stored_entries(object) {
            let Some(basic) = sub.data_type.and_then(|t| device.basic_type(t)) else {
                continue;
            };
            let cap = capacity(basic, sub);
            if is_bytes(basic) && cap > usize::from(u16::MAX) {
                out.push(Diagnostic::new(
                    &rules::CAPACITY_TOO_LARGE,
                    Some(sub.span),
                    format!(
                        "{:04X}h sub {} `{}`: needs {cap} bytes; an entry holds at most 65535",
                        object.index, sub.sub_index, sub.name
                    ),
                ));
                continue;
            }
            total += image_size(basic, cap);
        }
        if before <= MAX_IMAGE_SIZE && total > MAX_IMAGE_SIZE {
            out.push(Diagnostic::new(
                &rules::CAPACITY_TOO_LARGE,
                Some(object.span),
                format!(
                    "{:04X}h `{}`: with this object the device's values need more than {MAX_IMAGE_SIZE} bytes in all",
                    object.index, object.name
                ),
            ).with_help("lower string and domain capacities (the overlay sets them)"));
        }
    }
    out
}
