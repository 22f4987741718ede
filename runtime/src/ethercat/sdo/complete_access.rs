//! Complete access (ETG.1000.6 §5.6.2.1): a whole object read or written at once, sub-index 0
//! and a padding byte then sub-indices 1 to the value of sub-index 0 (or from sub-index 1
//! without them), with the SDO server's access rules and the caller's guard.

use super::Guard;
use crate::od::{EntryKind, ObjectDictionary, SdoAbort};

/// Whether `index` is an object with sub-indices (a record or an array).
fn has_subs<O: ObjectDictionary + ?Sized>(od: &O, index: u16) -> bool {
    // Entries are sorted and unique: the entry after sub-index 0 has a higher sub-index if it
    // has the index, and an index without sub-index 0 has only others.
    match od.locate(index, 0) {
        Ok(position) => od.entry(position + 1).is_some_and(|e| e.index() == index),
        Err(abort) => abort == SdoAbort::NoSubIndex,
    }
}

/// The kind of the entry at (index, sub).
#[inline]
fn kind<O: ObjectDictionary + ?Sized>(od: &O, index: u16, sub: u8) -> Result<EntryKind, SdoAbort> {
    od.kind(od.locate(index, sub)?).ok_or(SdoAbort::NoObject)
}

/// The length of a readable entry's value.
fn readable_len<O: ObjectDictionary + ?Sized>(
    od: &O,
    index: u16,
    sub: u8,
) -> Result<usize, SdoAbort> {
    if !kind(od, index, sub)?.access().readable() {
        return Err(SdoAbort::WriteOnly);
    }
    od.value_len(index, sub)
}

/// The number of sub-indices a complete access covers, or `None` for a VAR (its value alone).
fn object_count<O: ObjectDictionary + ?Sized>(
    od: &O,
    index: u16,
    sub: u8,
) -> Result<Option<u8>, SdoAbort> {
    if sub > 1 {
        return Err(SdoAbort::UnsupportedAccess);
    }
    let count_len = readable_len(od, index, 0)?;
    if count_len != 1 || !has_subs(od, index) {
        return if sub == 0 {
            Ok(None)
        } else {
            Err(SdoAbort::NoSubIndex)
        };
    }
    let mut n = [0u8];
    od.read(index, 0, 0, &mut n)?;
    Ok(Some(n[0]))
}

/// The length of a whole object by complete access from `sub` (0 or 1).
pub(super) fn object_len<O: ObjectDictionary + ?Sized>(
    od: &O,
    index: u16,
    sub: u8,
) -> Result<usize, SdoAbort> {
    let Some(n) = object_count(od, index, sub)? else {
        return readable_len(od, index, 0);
    };
    let mut total = if sub == 0 { 2 } else { 0 };
    for s in 1..=n {
        if od.locate(index, s).is_ok() {
            total += readable_len(od, index, s)?;
        }
    }
    Ok(total)
}

/// Reads a piece of an object's image from an offset into a buffer; returns the bytes read.
type PieceReader<'a> = dyn FnMut(usize, &mut [u8]) -> Result<usize, SdoAbort> + 'a;

/// Reads `out.len()` bytes of a whole object by complete access, `offset` bytes in.
pub(super) fn read_object<O: ObjectDictionary + ?Sized>(
    od: &O,
    index: u16,
    sub: u8,
    mut offset: usize,
    out: &mut [u8],
) -> Result<(), SdoAbort> {
    let mut filled = 0;
    let mut piece = |len: usize, read: &mut PieceReader<'_>| {
        if offset >= len {
            offset -= len;
            return Ok(());
        }
        let want = (len - offset).min(out.len() - filled);
        let got = read(offset, &mut out[filled..filled + want])?;
        filled += got;
        offset = 0;
        Ok::<(), SdoAbort>(())
    };
    let Some(n) = object_count(od, index, sub)? else {
        let len = readable_len(od, index, 0)?;
        return piece(len, &mut |at, buf| od.read(index, 0, at, buf));
    };
    if sub == 0 {
        piece(2, &mut |at, buf| {
            let header = [n, 0];
            let len = buf.len().min(2 - at);
            buf[..len].copy_from_slice(&header[at..at + len]);
            Ok(len)
        })?;
    }
    for s in 1..=n {
        if od.locate(index, s).is_ok() {
            let len = readable_len(od, index, s)?;
            piece(len, &mut |at, buf| od.read(index, s, at, buf))?;
        }
    }
    Ok(())
}

/// Writes one entry after the guard and the access rights.
fn write_entry<O: ObjectDictionary + ?Sized>(
    od: &mut O,
    guard: &dyn Guard,
    index: u16,
    sub: u8,
    data: &[u8],
) -> Result<(), SdoAbort> {
    guard.check(index, sub, data)?;
    if !kind(od, index, sub)?.access().writable() {
        return Err(SdoAbort::ReadOnly);
    }
    od.write(index, sub, data)
}

/// Writes a whole object by complete access from `sub` (0 or 1): sub-index 0 set to 0 first,
/// then each sub-index, then sub-index 0 to its new value.
pub(super) fn write_object<O: ObjectDictionary + ?Sized>(
    od: &mut O,
    guard: &dyn Guard,
    index: u16,
    sub: u8,
    data: &[u8],
) -> Result<(), SdoAbort> {
    if sub > 1 {
        return Err(SdoAbort::UnsupportedAccess);
    }
    let (n, mut rest) = if sub == 0 {
        let (&n, rest) = data.split_first().ok_or(SdoAbort::LengthTooLow)?;
        (n, rest.get(1..).unwrap_or_default())
    } else {
        let mut n = [0u8];
        readable_len(od, index, 0)?;
        od.read(index, 0, 0, &mut n)?;
        (n[0], data)
    };
    if sub == 0 {
        write_entry(od, guard, index, 0, &[0])?;
    }
    for s in 1..=n {
        let position = od.locate(index, s)?;
        let len = od.capacity(position).unwrap_or(0).min(rest.len());
        write_entry(od, guard, index, s, &rest[..len])?;
        rest = &rest[len..];
    }
    if sub == 0 {
        write_entry(od, guard, index, 0, &[n])?;
    }
    Ok(())
}
