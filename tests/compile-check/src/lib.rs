//! Generated device modules, compiled as a `no_std` library to prove they build without
//! warnings (missing docs included; dead code with the feature `private`) and without `std` or
//! `alloc`.
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

#[cfg(not(feature = "private"))]
include!(env!("EDSGEN_GENERATED"));

/// The generated modules where nothing outside can reach them (feature `private`).
#[cfg(feature = "private")]
mod firmware {
    include!(env!("EDSGEN_GENERATED"));
}

/// Reads one entry through the object-dictionary trait, so the trait implementations are
/// instantiated for the target.
pub fn read_entry<D: edsgen_runtime::ObjectDictionary>(
    od: &D,
    index: u16,
    sub: u8,
    buf: &mut [u8],
) -> Result<usize, edsgen_runtime::SdoAbort> {
    od.read(index, sub, 0, buf)
}
