//! The CoE SDO server of a simulated SubDevice (ETG.1000.6 §5.6.2, CiA 301's SDO in a mailbox):
//! expedited, normal and segmented uploads and downloads, complete access (a whole object:
//! sub-index 0 in one byte and one padding byte, then each sub-index's value in order), and
//! aborts with CiA 301 codes, served from a [`RuntimeDictionary`]. Which writes the device's
//! state allows is the caller's to say (a `guard`); access rights are the dictionary's.
//!
//! The longest answer is the device-to-master mailbox's size: a longer upload continues in
//! segments the master asks for.

use edsgen_runtime::{ObjectDictionary, SdoAbort};

use crate::canopen::RuntimeDictionary;

/// A transfer in progress.
#[derive(Debug, Clone, PartialEq)]
enum Transfer {
    Upload {
        data: Vec<u8>,
        offset: usize,
        toggle: bool,
    },
    Download {
        index: u16,
        sub: u8,
        complete: bool,
        size: usize,
        data: Vec<u8>,
        toggle: bool,
    },
}

/// The SDO server (its transfer in progress).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SdoServer {
    transfer: Option<Transfer>,
}

/// What may be written now: `Err` with the abort for an entry the device's state (or
/// configuration) protects.
pub type Guard<'a> = &'a dyn Fn(u16, u8, &[u8]) -> Result<(), SdoAbort>;

impl SdoServer {
    /// Answers the SDO request `body` (after the CoE header); `mailbox` is the device-to-master
    /// mailbox's size. `None` for a request that gets no answer (an abort from the master, an
    /// empty request).
    pub fn request(
        &mut self,
        od: &mut RuntimeDictionary,
        guard: Guard<'_>,
        mailbox: usize,
        body: &[u8],
    ) -> Option<Vec<u8>> {
        let command = *body.first()?;
        let index = body
            .get(1..3)
            .map_or(0, |b| u16::from_le_bytes([b[0], b[1]]));
        let sub = body.get(3).copied().unwrap_or(0);
        let result = match command >> 5 {
            0 => self.download_segment(od, guard, body),
            1 if body.len() >= 8 => self.download(od, guard, body, index, sub),
            2 if body.len() >= 4 => self.upload(od, mailbox, command & 0x10 != 0, index, sub),
            3 => self.upload_segment(mailbox, command),
            4 => {
                self.transfer = None;
                return None;
            }
            _ => Err(SdoAbort::InvalidCommand),
        };
        Some(result.unwrap_or_else(|abort| {
            self.transfer = None;
            let mut out = vec![0x80];
            out.extend_from_slice(&index.to_le_bytes());
            out.push(sub);
            out.extend_from_slice(&abort.code().to_le_bytes());
            out
        }))
    }

    fn download(
        &mut self,
        od: &mut RuntimeDictionary,
        guard: Guard<'_>,
        body: &[u8],
        index: u16,
        sub: u8,
    ) -> Result<Vec<u8>, SdoAbort> {
        let command = body[0];
        let complete = command & 0x10 != 0;
        let answer = [0x60, body[1], body[2], sub, 0, 0, 0, 0].to_vec();
        if command & 0x02 != 0 {
            // Expedited: the size in bits 2-3 when bit 0 says it is given.
            let len = if command & 0x01 != 0 {
                4 - usize::from((command >> 2) & 0x03)
            } else {
                od.value_len(index, sub).unwrap_or(4).min(4)
            };
            write(od, guard, index, sub, complete, &body[4..4 + len])?;
            self.transfer = None;
            return Ok(answer);
        }
        let size = u32::from_le_bytes([body[4], body[5], body[6], body[7]]) as usize;
        let data = &body[8..];
        if data.len() >= size {
            write(od, guard, index, sub, complete, &data[..size])?;
            self.transfer = None;
        } else {
            if size > crate::canopen::dictionary::DOMAIN_CAPACITY + 0x100 {
                return Err(SdoAbort::LengthTooHigh);
            }
            self.transfer = Some(Transfer::Download {
                index,
                sub,
                complete,
                size,
                data: data.to_vec(),
                toggle: false,
            });
        }
        Ok(answer)
    }

    fn download_segment(
        &mut self,
        od: &mut RuntimeDictionary,
        guard: Guard<'_>,
        body: &[u8],
    ) -> Result<Vec<u8>, SdoAbort> {
        let Some(Transfer::Download {
            index,
            sub,
            complete,
            size,
            mut data,
            toggle,
        }) = self.transfer.take()
        else {
            return Err(SdoAbort::InvalidCommand);
        };
        let command = body[0];
        if (command & 0x10 != 0) != toggle {
            return Err(SdoAbort::ToggleBit);
        }
        let segment = &body[1..];
        let len = if segment.len() <= 7 {
            (7 - usize::from((command >> 1) & 0x07)).min(segment.len())
        } else {
            segment.len()
        };
        data.extend_from_slice(&segment[..len]);
        let answer = vec![0x20 | (command & 0x10), 0, 0, 0, 0, 0, 0, 0];
        if command & 0x01 != 0 {
            if data.len() != size {
                return Err(SdoAbort::LengthMismatch);
            }
            write(od, guard, index, sub, complete, &data)?;
        } else {
            if data.len() > size {
                return Err(SdoAbort::LengthMismatch);
            }
            self.transfer = Some(Transfer::Download {
                index,
                sub,
                complete,
                size,
                data,
                toggle: !toggle,
            });
        }
        Ok(answer)
    }

    fn upload(
        &mut self,
        od: &RuntimeDictionary,
        mailbox: usize,
        complete: bool,
        index: u16,
        sub: u8,
    ) -> Result<Vec<u8>, SdoAbort> {
        self.transfer = None;
        let data = if complete {
            read_object(od, index, sub)?
        } else {
            read(od, index, sub)?
        };
        let [i0, i1] = index.to_le_bytes();
        let ca = if complete { 0x10 } else { 0 };
        if data.len() <= 4 && !data.is_empty() {
            let mut out = vec![0x43 | ca | (((4 - data.len()) as u8) << 2), i0, i1, sub];
            out.extend_from_slice(&data);
            out.resize(8, 0);
            return Ok(out);
        }
        let room = mailbox.saturating_sub(16).max(1);
        let mut out = vec![0x41 | ca, i0, i1, sub];
        out.extend_from_slice(&(data.len() as u32).to_le_bytes());
        let first = data.len().min(room);
        out.extend_from_slice(&data[..first]);
        if first < data.len() {
            self.transfer = Some(Transfer::Upload {
                data,
                offset: first,
                toggle: false,
            });
        }
        Ok(out)
    }

    fn upload_segment(&mut self, mailbox: usize, command: u8) -> Result<Vec<u8>, SdoAbort> {
        let Some(Transfer::Upload {
            data,
            offset,
            toggle,
        }) = self.transfer.take()
        else {
            return Err(SdoAbort::InvalidCommand);
        };
        if (command & 0x10 != 0) != toggle {
            return Err(SdoAbort::ToggleBit);
        }
        let room = mailbox.saturating_sub(9).max(7);
        let end = data.len().min(offset + room);
        let chunk = &data[offset..end];
        let last = end == data.len();
        let unused = 7usize.saturating_sub(chunk.len()) as u8;
        let mut out = vec![(command & 0x10) | (unused << 1) | u8::from(last)];
        out.extend_from_slice(chunk);
        if chunk.len() < 7 {
            out.resize(8, 0);
        }
        if !last {
            self.transfer = Some(Transfer::Upload {
                data,
                offset: end,
                toggle: !toggle,
            });
        }
        Ok(out)
    }
}

/// One entry's value, if readable.
fn read(od: &RuntimeDictionary, index: u16, sub: u8) -> Result<Vec<u8>, SdoAbort> {
    if !od.find(index, sub)?.access.readable() {
        return Err(SdoAbort::WriteOnly);
    }
    let mut data = vec![0; od.value_len(index, sub)?];
    let n = od.read(index, sub, 0, &mut data)?;
    data.truncate(n);
    Ok(data)
}

/// A whole object by complete access from `sub` (0 or 1): sub-index 0 and a padding byte, then
/// sub-indices 1 to the value of sub-index 0.
fn read_object(od: &RuntimeDictionary, index: u16, sub: u8) -> Result<Vec<u8>, SdoAbort> {
    if sub > 1 {
        return Err(SdoAbort::UnsupportedAccess);
    }
    let count = read(od, index, 0)?;
    let Some(&n) = count
        .first()
        .filter(|_| count.len() == 1 && has_subs(od, index))
    else {
        // A VAR: its value.
        return if sub == 0 {
            Ok(count)
        } else {
            Err(SdoAbort::NoSubIndex)
        };
    };
    let mut data = Vec::new();
    if sub == 0 {
        data.extend_from_slice(&[n, 0]);
    }
    for s in 1..=n {
        if od.find(index, s).is_ok() {
            data.extend(read(od, index, s)?);
        }
    }
    Ok(data)
}

fn has_subs(od: &RuntimeDictionary, index: u16) -> bool {
    od.entries().iter().any(|e| e.index == index && e.sub > 0)
}

/// Writes one entry, or a whole object by complete access (sub-index 0 set to 0 first, then
/// each sub-index, then sub-index 0 to its new value).
fn write(
    od: &mut RuntimeDictionary,
    guard: Guard<'_>,
    index: u16,
    sub: u8,
    complete: bool,
    data: &[u8],
) -> Result<(), SdoAbort> {
    if !complete {
        guard(index, sub, data)?;
        if !od.find(index, sub)?.access.writable() {
            return Err(SdoAbort::ReadOnly);
        }
        return od.write(index, sub, data);
    }
    if sub > 1 {
        return Err(SdoAbort::UnsupportedAccess);
    }
    let (n, mut rest) = if sub == 0 {
        let (&n, rest) = data.split_first().ok_or(SdoAbort::LengthTooLow)?;
        (n, rest.get(1..).unwrap_or_default())
    } else {
        (read(od, index, 0)?.first().copied().unwrap_or(0), data)
    };
    if sub == 0 {
        write(od, guard, index, 0, false, &[0])?;
    }
    for s in 1..=n {
        let position = od.locate(index, s)?;
        let len = od.capacity(position).unwrap_or(0).min(rest.len());
        write(od, guard, index, s, false, &rest[..len])?;
        rest = &rest[len..];
    }
    if sub == 0 {
        write(od, guard, index, 0, false, &[n])?;
    }
    Ok(())
}
