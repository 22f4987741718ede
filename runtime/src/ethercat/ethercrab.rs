//! Generated EtherCAT bindings on [ethercrab](https://docs.rs/ethercrab) (feature `ethercrab`):
//! generated process-image structs are ethercrab-wire types (through `ethercrab_wire!`, which
//! generated code invokes), and [`SdoExt`] gives a SubDevice typed CoE access by the generated
//! addresses.
//!
//! ```ignore
//! let inputs = ec_tx508::ethercat::Inputs::unpack_from_slice(&subdevice.inputs_raw())?;
//! outputs.pack_to_slice(&mut subdevice.outputs_raw_mut())?;
//! subdevice.write_entry(ec_tx508::od::OPERATION_MODE, 9).await?;
//! ```

use core::future::Future;
use core::ops::Deref;

use ::ethercrab::error::Error;
use ::ethercrab::{EtherCrabWireReadSized, EtherCrabWireWrite, SubDevice, SubDeviceRef};

use super::Identity;
use crate::od::access::{Readable, Writable};
use crate::od::entry::Entry;
use crate::od::typed::PdoError;

/// The ethercrab-wire crate, by the path `ethercrab_wire!` expansions name.
#[doc(hidden)]
pub use ::ethercrab_wire as wire;

/// A [`PdoError`] from a read as ethercrab-wire says it.
#[doc(hidden)]
pub fn read_error(error: PdoError) -> wire::WireError {
    match error {
        PdoError::WrongLength { .. } => wire::WireError::ReadBufferTooShort,
        PdoError::OutOfRange { .. } => wire::WireError::InvalidValue,
    }
}

/// A [`PdoError`] from a write as ethercrab-wire says it.
#[doc(hidden)]
pub fn write_error(error: PdoError) -> wire::WireError {
    match error {
        PdoError::WrongLength { .. } => wire::WireError::WriteBufferTooShort,
        PdoError::OutOfRange { .. } => wire::WireError::InvalidValue,
    }
}

impl Identity {
    /// Whether a discovered SubDevice is this device (vendor and product code; see
    /// [`Identity::matches`]).
    pub fn matches_subdevice(&self, subdevice: &SubDevice) -> bool {
        let found = subdevice.identity();
        self.matches(found.vendor_id, found.product_id)
    }
}

/// Typed CoE SDO access by generated addresses: `read_entry(od::STATUS_WORD)` returns a `u16`,
/// `write_entry(od::TARGET_POSITION, value)` takes an `i32`; writing a read-only entry or
/// reading a write-only one does not compile, as with the CANopen masters. Implemented for every ethercrab
/// `SubDeviceRef`.
pub trait SdoExt {
    /// Reads the entry by an SDO upload.
    fn read_entry<T, D, A>(&self, entry: Entry<T, D, A>) -> impl Future<Output = Result<T, Error>>
    where
        T: EtherCrabWireReadSized,
        A: Readable;

    /// Writes the entry by an SDO download.
    fn write_entry<T, D, A>(
        &self,
        entry: Entry<T, D, A>,
        value: T,
    ) -> impl Future<Output = Result<(), Error>>
    where
        T: EtherCrabWireWrite,
        A: Writable;
}

impl<S> SdoExt for SubDeviceRef<'_, S>
where
    S: Deref<Target = SubDevice>,
{
    fn read_entry<T, D, A>(&self, entry: Entry<T, D, A>) -> impl Future<Output = Result<T, Error>>
    where
        T: EtherCrabWireReadSized,
        A: Readable,
    {
        self.sdo_read::<T>(entry.index, entry.sub)
    }

    fn write_entry<T, D, A>(
        &self,
        entry: Entry<T, D, A>,
        value: T,
    ) -> impl Future<Output = Result<(), Error>>
    where
        T: EtherCrabWireWrite,
        A: Writable,
    {
        self.sdo_write(entry.index, entry.sub, value)
    }
}
