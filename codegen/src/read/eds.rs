//! EDS and DCF reader (CiA 306). Placeholder until the reader lands.

use std::path::Path;

use super::Read;
use crate::model::*;

/// Reads an EDS or DCF file.
pub fn read(path: &Path, bytes: &[u8]) -> Read {
    let (text, encoding) = super::text::decode(bytes);
    Read {
        device: empty_device(path, Format::Eds, encoding),
        diagnostics: Vec::new(),
        text,
    }
}

/// A device with nothing in it, for a reader to fill.
pub fn empty_device(path: &Path, format: Format, encoding: TextEncoding) -> Device {
    Device {
        source: Source {
            path: path.to_path_buf(),
            format,
            encoding,
        },
        file_info: FileInfo::default(),
        device_info: DeviceInfo::default(),
        dummy_usage: Default::default(),
        comments: Vec::new(),
        objects: Default::default(),
        object_lists: Vec::new(),
        commissioning: None,
        other_sections: Vec::new(),
    }
}
