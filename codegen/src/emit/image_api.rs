//! The one process-image API every bus's generated images share (CANopen PDOs, EtherCAT PDOs
//! and SyncManager images, DP module images, PROFINET submodule images, CIP assembly images):
//! `SIZE` in bytes, `from_bytes(&[u8; SIZE])`, `to_bytes() -> [u8; SIZE]`, and the fallible
//! `from_slice(&[u8])` for bytes whose length only the wire knows. docs/generated-code.md says why.

use proc_macro2::{Literal, TokenStream};
use quote::quote;

/// `SIZE` (with `doc`, which says what the bytes are) and `from_slice`, for an image of `size`
/// bytes whose `from_bytes(&[u8; size])` the caller emits.
pub(super) fn size_and_from_slice(size: usize, doc: &str) -> TokenStream {
    let size = Literal::usize_unsuffixed(size);
    let doc = format!(" {doc}");
    quote! {
        #[doc = #doc]
        pub const SIZE: usize = #size;

        /// The image of exactly [`Self::SIZE`] bytes; `WrongLength` for any other length.
        pub fn from_slice(bytes: &[u8]) -> ::core::result::Result<Self, ::edsgen_runtime::PdoError> {
            ::edsgen_runtime::support::payload::<#size>(bytes).map(|bytes| Self::from_bytes(&bytes))
        }
    }
}
