//! TEMPORARY stand-in for `crate::sdo::server::SdoServer` (written on branch runtime-sdo) with
//! the pinned API: expedited upload and download only. Removed once that branch is merged.

use crate::od::{ObjectDictionary, SdoAbort};
use crate::time::{Duration, Instant};

/// What a completed transfer did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SdoEvent {
    /// A download completed.
    Written { index: u16, sub: u8 },
}

/// Expedited-only SDO server.
pub struct SdoServer<const N: usize> {
    response: Option<[u8; 8]>,
}

fn abort(index: u16, sub: u8, code: SdoAbort) -> [u8; 8] {
    let i = index.to_le_bytes();
    let c = code.code().to_le_bytes();
    [0x80, i[0], i[1], sub, c[0], c[1], c[2], c[3]]
}

impl<const N: usize> SdoServer<N> {
    pub const fn new(_timeout: Duration) -> Self {
        SdoServer { response: None }
    }

    pub fn handle<O: ObjectDictionary + ?Sized>(
        &mut self,
        _now: Instant,
        request: &[u8],
        od: &mut O,
    ) -> Option<SdoEvent> {
        let req: &[u8; 8] = request.try_into().ok()?;
        let index = u16::from_le_bytes([req[1], req[2]]);
        let sub = req[3];
        let ccs = req[0] >> 5;
        match ccs {
            2 => {
                let result = od.find(index, sub).and_then(|d| {
                    if !d.access.readable() {
                        return Err(SdoAbort::WriteOnly);
                    }
                    let mut data = [0u8; 4];
                    let len = od.value_len(index, sub)?;
                    if len > 4 {
                        return Err(SdoAbort::General);
                    }
                    od.read(index, sub, 0, &mut data[..len])?;
                    Ok((data, len))
                });
                self.response = Some(match result {
                    Ok((d, len)) => {
                        let i = index.to_le_bytes();
                        let cmd = 0x43 | (((4 - len) as u8) << 2);
                        [cmd, i[0], i[1], sub, d[0], d[1], d[2], d[3]]
                    }
                    Err(code) => abort(index, sub, code),
                });
                None
            }
            1 if req[0] & 0x03 == 0x03 => {
                let len = 4 - ((req[0] >> 2) & 3) as usize;
                let result = match od.find(index, sub) {
                    Ok(d) if !d.access.writable() => Err(SdoAbort::ReadOnly),
                    Ok(_) => od.write(index, sub, &req[4..4 + len]),
                    Err(e) => Err(e),
                };
                match result {
                    Ok(()) => {
                        let i = index.to_le_bytes();
                        self.response = Some([0x60, i[0], i[1], sub, 0, 0, 0, 0]);
                        Some(SdoEvent::Written { index, sub })
                    }
                    Err(code) => {
                        self.response = Some(abort(index, sub, code));
                        None
                    }
                }
            }
            _ => {
                self.response = Some(abort(index, sub, SdoAbort::InvalidCommand));
                None
            }
        }
    }

    pub fn poll_transmit<O: ObjectDictionary + ?Sized>(
        &mut self,
        _now: Instant,
        _od: &O,
    ) -> Option<[u8; 8]> {
        self.response.take()
    }

    pub fn poll_timeout(&self) -> Option<Instant> {
        None
    }

    pub fn handle_timeout(&mut self, _now: Instant) {}

    pub fn reset(&mut self) {
        self.response = None;
    }
}
