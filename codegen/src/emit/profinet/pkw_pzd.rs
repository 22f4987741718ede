//! The conversions of a submodule's images to and from `edsgen_runtime::pkw_pzd`'s when the
//! overlay's `[pkw_pzd]` names the submodule: its 32-byte `Input` is the drive's PKW response,
//! status word and PZD2-PZD12, its `Output` the controller's PKW request, control word and
//! PZD2-PZD12, words big-endian as PROFINET carries them. The IOPS stays where the raw images
//! put it: `Input::from_pkw_pzd(&image).to_bytes_with_iops(IOXS_GOOD)` is the frame's part.

use proc_macro2::TokenStream;
use quote::quote;

/// The `impl Input` and `impl Output` blocks of the conversions.
pub(super) fn conversions() -> TokenStream {
    let rt = quote!(::edsgen_runtime::pkw_pzd);
    quote! {
        impl Input {
            /// The image as the drive's PKW/PZD input image (PKW response, status word,
            /// PZD2-PZD12; words big-endian); an error for an undefined response code in PKW1.
            pub fn pkw_pzd(&self) -> Result<#rt::InputImage, #rt::ResponseError> {
                #rt::InputImage::parse(&self.to_bytes(), #rt::ByteOrder::BigEndian)
            }

            /// The image carrying a PKW/PZD input image.
            pub fn from_pkw_pzd(image: &#rt::InputImage) -> Self {
                Self::from_bytes(&image.emit(#rt::ByteOrder::BigEndian))
            }
        }

        impl Output {
            /// The image as the controller's PKW/PZD output image (PKW request, control word,
            /// PZD2-PZD12; words big-endian).
            pub fn pkw_pzd(&self) -> #rt::OutputImage {
                #rt::OutputImage::parse(&self.to_bytes(), #rt::ByteOrder::BigEndian)
            }

            /// The image carrying a PKW/PZD output image.
            pub fn from_pkw_pzd(image: &#rt::OutputImage) -> Self {
                Self::from_bytes(&image.emit(#rt::ByteOrder::BigEndian))
            }
        }
    }
}
