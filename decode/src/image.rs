//! EtherCAT process images decoded by name: the bytes of a SyncManager's image split into the
//! entries of the PDOs its ESI file assigns to it by default, one after another, each named as
//! the file names it and typed by its object in the dictionary, as the bus decoder prints a
//! CANopen PDO (`Control word = 15, Target speed = 300, Operation mode = 9`).

use edsgen_model::model::{Device, EcPdo, SmKind};
use edsgen_runtime::od::typed::get_bits;
use edsgen_runtime::ObjectDictionary;

use super::text;
use edsgen_sim::canopen::RuntimeDictionary;

/// A device's process images, decoded by its ESI file's default PDO assignment.
pub struct ImageDecoder {
    device: Device,
    dictionary: RuntimeDictionary,
}

impl ImageDecoder {
    /// A decoder for `device` (read from an ESI file; a device without EtherCAT data has no
    /// PDOs, and its images decode as hex bytes).
    pub fn new(device: &Device) -> Self {
        ImageDecoder {
            device: device.clone(),
            dictionary: RuntimeDictionary::new(device, 0),
        }
    }

    /// The outputs image (master to device: the RxPDOs of the outputs SyncManager) as text.
    pub fn outputs(&self, data: &[u8]) -> String {
        self.image(SmKind::Outputs, data)
    }

    /// The inputs image (device to master: the TxPDOs of the inputs SyncManager) as text.
    pub fn inputs(&self, data: &[u8]) -> String {
        self.image(SmKind::Inputs, data)
    }

    /// `data` split into the entries of the PDOs assigned to the first SyncManager of `kind`:
    /// `Name = value` for each, hex bytes where the image is shorter than the PDOs need (bytes
    /// beyond them are not shown).
    fn image(&self, kind: SmKind, data: &[u8]) -> String {
        let Some(ethercat) = self.device.ethercat() else {
            return text::hex_bytes(data);
        };
        let Some(sm) = ethercat.sync_managers.iter().position(|s| s.kind == kind) else {
            return text::hex_bytes(data);
        };
        let pdos = match kind {
            SmKind::Outputs => &ethercat.rx_pdos,
            _ => &ethercat.tx_pdos,
        };
        let assigned = pdos
            .iter()
            .filter(|pdo| pdo.sm.is_some_and(|n| usize::from(n) == sm));
        let needed: usize = assigned.clone().map(bits_of).sum();
        if needed > 8 * data.len() {
            return format!(
                "{} (the PDOs need {needed} bits, the image has {})",
                text::hex_bytes(data),
                8 * data.len()
            );
        }
        let mut fields = Vec::new();
        let mut offset = 0usize;
        for entry in assigned.flat_map(|pdo| &pdo.entries) {
            let bits = usize::from(entry.bit_len);
            // Index 0 is padding (a gap in the image).
            if entry.index != 0 {
                let data_type = self
                    .dictionary
                    .find(entry.index, entry.sub)
                    .ok()
                    .map(|e| e.data_type());
                let value = if bits.is_multiple_of(8) && offset.is_multiple_of(8) {
                    text::value(data_type, &data[offset / 8..(offset + bits) / 8])
                } else {
                    get_bits(data, offset, bits as u32).to_string()
                };
                fields.push(format!("{} = {value}", entry.name));
            }
            offset += bits;
        }
        if fields.is_empty() {
            return text::hex_bytes(data);
        }
        fields.join(", ")
    }
}

/// The bits a PDO's entries take.
fn bits_of(pdo: &EcPdo) -> usize {
    pdo.entries.iter().map(|e| usize::from(e.bit_len)).sum()
}
