//! PDOs from the master's side: the SDO writes that configure a remote node's PDO in the
//! CiA 301 order (disable, clear the mapping, map, count, enable), from a generated PDO struct's
//! mapping ([`MappedPdo`], [`PdoConfig::of`]) or any other, and
//! [`pdo_dispatch!`](crate::pdo_dispatch), an enum of generated PDO structs decoded from a
//! received frame by its COB-ID.

use crate::wire::sdo::Multiplexer;

/// Whether a PDO is received or transmitted by the remote node.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PdoKind {
    /// An RPDO of the node (the master sends it): 1400h/1600h + n - 1.
    Receive,
    /// A TPDO of the node (the master receives it): 1800h/1A00h + n - 1.
    Transmit,
}

/// A PDO's communication and mapping parameters, as a master writes them to a node.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PdoConfig<'a> {
    /// RPDO or TPDO of the node.
    pub kind: PdoKind,
    /// The PDO number, 1..=512.
    pub number: u16,
    /// The COB-ID (bits 0–10, or 0–28 with bit 29; the valid bit 31 is managed here).
    pub cob_id: u32,
    /// Transmission type (sub 2): 0 acyclic synchronous, 1–240 every n-th SYNC, 254/255 event.
    pub transmission_type: u8,
    /// Event timer in ms (sub 5, TPDOs only; `None` leaves it).
    pub event_timer: Option<u16>,
    /// The mapped objects: index << 16 | sub << 8 | length in bits, in payload order.
    pub mapping: &'a [u32],
}

/// A generated PDO struct (`cp301::pdo::Tpdo1`): which PDO of its device it is and the mapping
/// its payload follows, so that a master configures a node to send or receive exactly that
/// payload ([`PdoConfig::of`]).
pub trait MappedPdo {
    /// RPDO or TPDO of the device.
    const KIND: PdoKind;
    /// The PDO number, 1..=512 (RPDO1 is 1, at 1400h/1600h).
    const NUMBER: u16;
    /// The mapped objects, index << 16 | sub << 8 | length in bits, in payload order (the
    /// description's default mapping; dummy entries included).
    const MAPPING: &'static [u32];
}

/// One SDO write of a configuration: the entry, the value and its width in bytes.
pub type ConfigWrite = (Multiplexer, u32, u8);

/// The bit that marks a PDO COB-ID invalid (the PDO disabled).
pub const COB_ID_INVALID: u32 = 0x8000_0000;

impl PdoConfig<'static> {
    /// The configuration of the PDO that the generated struct `P` is (its kind, number and
    /// mapping), on `cob_id`, with `transmission_type` and, for a TPDO, `event_timer` (in ms).
    ///
    /// ```
    /// use edsgen_runtime::master::pdo::{MappedPdo, PdoConfig, PdoKind};
    ///
    /// // A stand-in for a generated PDO struct (`cp301::pdo::Tpdo1`).
    /// pub struct Tpdo1;
    /// impl MappedPdo for Tpdo1 {
    ///     const KIND: PdoKind = PdoKind::Transmit;
    ///     const NUMBER: u16 = 1;
    ///     const MAPPING: &'static [u32] = &[0x6041_0010, 0x6044_0010];
    /// }
    ///
    /// let config = PdoConfig::of::<Tpdo1>(0x183, 254, Some(100));
    /// assert_eq!((config.communication_index(), config.mapping_index()), (0x1800, 0x1A00));
    /// assert_eq!(config.mapping, [0x6041_0010, 0x6044_0010]);
    /// ```
    pub const fn of<P: MappedPdo>(
        cob_id: u32,
        transmission_type: u8,
        event_timer: Option<u16>,
    ) -> Self {
        PdoConfig {
            kind: P::KIND,
            number: P::NUMBER,
            cob_id,
            transmission_type,
            event_timer,
            mapping: P::MAPPING,
        }
    }
}

impl PdoConfig<'_> {
    /// The communication parameter index (1400h/1800h + number - 1).
    pub const fn communication_index(&self) -> u16 {
        self.base() + self.number.saturating_sub(1)
    }

    /// The mapping parameter index (1600h/1A00h + number - 1).
    pub const fn mapping_index(&self) -> u16 {
        self.communication_index() + 0x200
    }

    const fn base(&self) -> u16 {
        match self.kind {
            PdoKind::Receive => 0x1400,
            PdoKind::Transmit => 0x1800,
        }
    }

    /// The writes in CiA 301's safe order: COB-ID invalid, transmission type, event timer,
    /// mapping count 0, each mapped object, the count, then the COB-ID valid.
    pub fn writes(&self) -> impl Iterator<Item = ConfigWrite> + '_ {
        let comm = self.communication_index();
        let map = self.mapping_index();
        let cob_id = self.cob_id & !COB_ID_INVALID;
        let event_timer = match (self.kind, self.event_timer) {
            (PdoKind::Transmit, Some(ms)) => Some((Multiplexer::new(comm, 5), u32::from(ms), 2)),
            _ => None,
        };
        let head = [
            Some((Multiplexer::new(comm, 1), cob_id | COB_ID_INVALID, 4)),
            Some((
                Multiplexer::new(comm, 2),
                u32::from(self.transmission_type),
                1,
            )),
            event_timer,
            Some((Multiplexer::new(map, 0), 0, 1)),
        ];
        let objects = self
            .mapping
            .iter()
            .enumerate()
            .map(move |(i, &object)| (Multiplexer::new(map, i as u8 + 1), object, 4));
        let tail = [
            (Multiplexer::new(map, 0), self.mapping.len() as u32, 1),
            (Multiplexer::new(comm, 1), cob_id, 4),
        ];
        head.into_iter().flatten().chain(objects).chain(tail)
    }
}

/// Declares an enum of generated PDO structs and a decoder that picks the variant by the
/// received frame's CAN identifier (each struct's `cob_id(node_id)`: a `u16` for an 11-bit
/// identifier, a `u32` for a 29-bit one), for one node.
///
/// ```
/// use edsgen_runtime::CanFrame;
///
/// // Stand-ins for generated PDO structs (`cp301::pdo::Tpdo1`, ...).
/// #[derive(Debug, PartialEq)]
/// pub struct Tpdo1 { pub statusword: u16 }
/// impl Tpdo1 {
///     pub const fn cob_id(node_id: u8) -> u16 { 0x180 + node_id as u16 }
///     pub fn from_slice(p: &[u8]) -> Result<Self, edsgen_runtime::PdoError> {
///         let p = edsgen_runtime::od::typed::payload::<2>(p)?;
///         Ok(Tpdo1 { statusword: u16::from_le_bytes(p) })
///     }
/// }
///
/// edsgen_runtime::pdo_dispatch! {
///     /// The TPDOs of one drive.
///     pub enum DrivePdo { Tpdo1(Tpdo1) }
/// }
///
/// let frame = CanFrame::new(0x183, &[0x37, 0x02]).unwrap();
/// assert_eq!(DrivePdo::decode(3, &frame), Some(Ok(DrivePdo::Tpdo1(Tpdo1 { statusword: 0x237 }))));
/// assert_eq!(DrivePdo::decode(4, &frame), None);
/// ```
#[macro_export]
macro_rules! pdo_dispatch {
    ($(#[$meta:meta])* $vis:vis enum $name:ident { $($variant:ident($ty:ty)),+ $(,)? }) => {
        $(#[$meta])*
        #[derive(Debug, PartialEq)]
        $vis enum $name {
            $(
                #[allow(missing_docs)]
                $variant($ty),
            )+
        }

        impl $name {
            /// The PDO in `frame` if its COB-ID is one of node `node_id`'s: `None` for other
            /// frames, an error for a payload of the wrong length.
            #[allow(dead_code)]
            $vis fn decode(
                node_id: u8,
                frame: &$crate::CanFrame,
            ) -> ::core::option::Option<::core::result::Result<Self, $crate::PdoError>> {
                let id = match frame.id() {
                    $crate::CanId::Standard(id) => u32::from(id),
                    $crate::CanId::Extended(id) => id,
                };
                if frame.is_remote() {
                    return None;
                }
                $(
                    if u32::from(<$ty>::cob_id(node_id)) == id {
                        return Some(<$ty>::from_slice(frame.data()).map($name::$variant));
                    }
                )+
                None
            }
        }
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tpdo_is_configured_in_the_safe_order() {
        let config = PdoConfig {
            kind: PdoKind::Transmit,
            number: 2,
            cob_id: 0x285,
            transmission_type: 254,
            event_timer: Some(100),
            mapping: &[0x6041_0010, 0x6044_0010],
        };
        let mut writes = [(Multiplexer::new(0, 0), 0, 0); 8];
        let mut n = 0;
        for write in config.writes() {
            writes[n] = write;
            n += 1;
        }
        assert_eq!(
            writes[..n],
            [
                (Multiplexer::new(0x1801, 1), 0x8000_0285, 4),
                (Multiplexer::new(0x1801, 2), 254, 1),
                (Multiplexer::new(0x1801, 5), 100, 2),
                (Multiplexer::new(0x1A01, 0), 0, 1),
                (Multiplexer::new(0x1A01, 1), 0x6041_0010, 4),
                (Multiplexer::new(0x1A01, 2), 0x6044_0010, 4),
                (Multiplexer::new(0x1A01, 0), 2, 1),
                (Multiplexer::new(0x1801, 1), 0x285, 4),
            ]
        );
    }
}
