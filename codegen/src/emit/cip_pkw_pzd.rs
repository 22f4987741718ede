//! The conversions of an ODVA assembly's image to and from `edsgen_runtime::pkw_pzd`'s typed
//! images, when the overlay's `[pkw_pzd]` says the assembly carries one (part of the CIP module,
//! `cip`).

use proc_macro2::TokenStream;
use quote::quote;

use edsgen_model::model::Cip;

/// Conversions between an assembly's image and the PKW/PZD protocol's typed image, when the
/// overlay says the assembly carries one (`[pkw_pzd]`).
pub(super) fn conversions(cip: &Cip, number: u32, ty: &proc_macro2::Ident) -> TokenStream {
    let Some(images) = cip.pkw_pzd else {
        return TokenStream::new();
    };
    let (order, order_doc) = if images.little_endian {
        (quote!(LittleEndian), "little-endian")
    } else {
        (quote!(BigEndian), "big-endian")
    };
    let p = quote!(::edsgen_runtime::pkw_pzd);
    if number == images.output {
        let doc = format!(
            " The image as the PKW/PZD protocol's: PKW request, control word, PZD2-PZD12 (words \
             {order_doc}, as the overlay says)."
        );
        quote! {
            impl #ty {
                #[doc = #doc]
                pub fn pkw_pzd(&self) -> #p::OutputImage {
                    #p::OutputImage::parse(&self.to_bytes(), #p::ByteOrder::#order)
                }

                /// The image carrying a PKW/PZD output image.
                pub fn from_pkw_pzd(image: &#p::OutputImage) -> Self {
                    Self::from_bytes(&image.emit(#p::ByteOrder::#order))
                }
            }
        }
    } else if number == images.input {
        let doc = format!(
            " The image as the PKW/PZD protocol's: PKW response, status word, PZD2-PZD12 (words \
             {order_doc}, as the overlay says); an error for an undefined response code."
        );
        quote! {
            impl #ty {
                #[doc = #doc]
                pub fn pkw_pzd(&self) -> Result<#p::InputImage, #p::ResponseError> {
                    #p::InputImage::parse(&self.to_bytes(), #p::ByteOrder::#order)
                }

                /// The image carrying a PKW/PZD input image.
                pub fn from_pkw_pzd(image: &#p::InputImage) -> Self {
                    Self::from_bytes(&image.emit(#p::ByteOrder::#order))
                }
            }
        }
    } else {
        TokenStream::new()
    }
}
