//! What only generated code calls: the value image's layout and default unpacking, bit packing
//! of PDO payloads, and the table search. Not part of the documented API a firmware or master
//! author uses; generated code names its plumbing by these paths only
//! (`::edsgen_runtime::support::…`), so the modules behind them move without breaking it.

pub use crate::od::image::{unpack_defaults, Layout, Limit};
pub use crate::od::stage::Stage;
pub use crate::od::typed::{
    fits_signed, fits_unsigned, get_bits, payload, position, put_bits, read_bytes, sign_extend,
};
