//! The runtime's EtherNet/IP layouts (`edsgen_runtime::enip::wire`) written into vectors, as
//! the adapter answers: its replies are sized by the EDS's assemblies and parameters, known
//! only at run time. A response longer than an encapsulation message carries is refused with
//! "reply data too large" (0x11) instead, so the items around it always fit their lengths.

use edsgen_runtime::enip::wire::cpf::{CpfRepr, Item, SendDataRepr};
use edsgen_runtime::enip::wire::message::{general, ResponseRepr};
use edsgen_runtime::enip::wire::Emit;

/// The longest response: what 65535 bytes of SendUnitData's data hold after the interface
/// handle, timeout, items and sequence count.
const MAX_RESPONSE: usize = u16::MAX as usize - 22;

/// A Message Router response's bytes, the extended status as words.
pub(super) fn response(service: u8, status: u8, extended: &[u16], data: &[u8]) -> Vec<u8> {
    let extended: Vec<u8> = extended.iter().flat_map(|w| w.to_le_bytes()).collect();
    let repr = ResponseRepr {
        service,
        status,
        extended: &extended,
        data,
    };
    match repr.to_vec() {
        Ok(bytes) if bytes.len() <= MAX_RESPONSE => bytes,
        _ => status_only(service, general::REPLY_DATA_TOO_LARGE),
    }
}

/// A Message Router response with a status and nothing else.
pub(super) fn status_only(service: u8, status: u8) -> Vec<u8> {
    let mut out = [0; 4];
    let _ = ResponseRepr::status(service, status).emit(&mut out);
    out.to_vec()
}

/// CPF items' bytes (a ListIdentity or ListServices reply's data); every item the adapter
/// writes fits its length field (see [`response`]).
pub(super) fn items(items: &[Item<'_>]) -> Vec<u8> {
    CpfRepr { items }.to_vec().unwrap_or_default()
}

/// SendRRData or SendUnitData's data: interface handle, timeout 0, the items.
pub(super) fn send_data(items: &[Item<'_>]) -> Vec<u8> {
    SendDataRepr { timeout: 0, items }
        .to_vec()
        .unwrap_or_default()
}
