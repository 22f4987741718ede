//! The CAN frame the stack works with, and its conversion to and from `embedded-can` frames.
//!
//! Classic CAN only (8 data bytes). CANopen uses 11-bit identifiers; 29-bit ones are carried so
//! that a frame from a mixed bus is not lost, and the stack ignores them.

/// A CAN identifier.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum CanId {
    /// An 11-bit identifier (0..=0x7FF).
    Standard(u16),
    /// A 29-bit identifier.
    Extended(u32),
}

/// A classic CAN frame: identifier, 0..=8 data bytes, and the remote-request flag.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct CanFrame {
    /// The identifier, with [`EXTENDED`] set for a 29-bit one: one word rather than a [`CanId`]
    /// keeps the frame at 16 bytes, which a 32-bit target moves without a `memcpy` call.
    id: u32,
    len: u8,
    data: [u8; 8],
    rtr: bool,
}

/// The flag of [`CanFrame`]'s identifier word that marks a 29-bit identifier.
const EXTENDED: u32 = 1 << 31;

impl core::fmt::Debug for CanFrame {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("CanFrame")
            .field("id", &self.id())
            .field("len", &self.len)
            .field("data", &self.data)
            .field("rtr", &self.rtr)
            .finish()
    }
}

impl CanFrame {
    /// A data frame with an 11-bit identifier. `None` if `id > 0x7FF` or `data` is longer than 8.
    pub fn new(id: u16, data: &[u8]) -> Option<Self> {
        if id > 0x7FF || data.len() > 8 {
            return None;
        }
        let mut bytes = [0u8; 8];
        bytes[..data.len()].copy_from_slice(data);
        Some(CanFrame {
            id: id as u32,
            len: data.len() as u8,
            data: bytes,
            rtr: false,
        })
    }

    /// A data frame from a full 8-byte payload and a length (used by the protocol cores, which
    /// build payloads in place). `len` is clamped to 8 and `id` masked to 11 bits.
    #[inline]
    pub const fn from_parts(id: u16, data: [u8; 8], len: u8) -> Self {
        CanFrame {
            id: (id & 0x7FF) as u32,
            len: if len > 8 { 8 } else { len },
            data,
            rtr: false,
        }
    }

    /// A remote-transmission request with an 11-bit identifier and a requested length.
    pub const fn remote(id: u16, len: u8) -> Self {
        CanFrame {
            id: (id & 0x7FF) as u32,
            len: if len > 8 { 8 } else { len },
            data: [0; 8],
            rtr: true,
        }
    }

    /// A data frame with a 29-bit identifier (carried, not used by CANopen).
    pub fn new_extended(id: u32, data: &[u8]) -> Option<Self> {
        if id > 0x1FFF_FFFF || data.len() > 8 {
            return None;
        }
        let mut bytes = [0u8; 8];
        bytes[..data.len()].copy_from_slice(data);
        Some(CanFrame {
            id: id | EXTENDED,
            len: data.len() as u8,
            data: bytes,
            rtr: false,
        })
    }

    /// The identifier.
    #[inline]
    pub const fn id(&self) -> CanId {
        if self.id & EXTENDED != 0 {
            CanId::Extended(self.id & !EXTENDED)
        } else {
            CanId::Standard(self.id as u16)
        }
    }

    /// The 11-bit identifier, or `None` for an extended frame.
    #[inline]
    pub const fn std_id(&self) -> Option<u16> {
        if self.id & EXTENDED != 0 {
            None
        } else {
            Some(self.id as u16)
        }
    }

    /// The data bytes (empty for a remote request).
    #[inline]
    pub fn data(&self) -> &[u8] {
        if self.rtr {
            &[]
        } else {
            &self.data[..self.len as usize]
        }
    }

    /// The data length code.
    #[inline]
    pub const fn dlc(&self) -> u8 {
        self.len
    }

    /// Whether this is a remote-transmission request.
    #[inline]
    pub const fn is_remote(&self) -> bool {
        self.rtr
    }
}

impl embedded_can::Frame for CanFrame {
    fn new(id: impl Into<embedded_can::Id>, data: &[u8]) -> Option<Self> {
        match id.into() {
            embedded_can::Id::Standard(id) => CanFrame::new(id.as_raw(), data),
            embedded_can::Id::Extended(id) => CanFrame::new_extended(id.as_raw(), data),
        }
    }

    fn new_remote(id: impl Into<embedded_can::Id>, dlc: usize) -> Option<Self> {
        if dlc > 8 {
            return None;
        }
        match id.into() {
            embedded_can::Id::Standard(id) => Some(CanFrame::remote(id.as_raw(), dlc as u8)),
            embedded_can::Id::Extended(id) => Some(CanFrame {
                id: id.as_raw() | EXTENDED,
                len: dlc as u8,
                data: [0; 8],
                rtr: true,
            }),
        }
    }

    fn is_extended(&self) -> bool {
        self.id & EXTENDED != 0
    }

    fn is_remote_frame(&self) -> bool {
        self.rtr
    }

    fn id(&self) -> embedded_can::Id {
        match self.id() {
            // Both constructors mask the identifier, so these conversions cannot fail; fall back
            // to the zero identifier rather than panic.
            CanId::Standard(id) => embedded_can::StandardId::new(id)
                .map(embedded_can::Id::Standard)
                .unwrap_or(embedded_can::Id::Standard(embedded_can::StandardId::ZERO)),
            CanId::Extended(id) => embedded_can::ExtendedId::new(id)
                .map(embedded_can::Id::Extended)
                .unwrap_or(embedded_can::Id::Extended(embedded_can::ExtendedId::ZERO)),
        }
    }

    fn dlc(&self) -> usize {
        self.len as usize
    }

    fn data(&self) -> &[u8] {
        CanFrame::data(self)
    }
}

impl CanFrame {
    /// Converts any `embedded-can` frame into this frame type.
    pub fn from_frame<F: embedded_can::Frame>(frame: &F) -> Option<Self> {
        if frame.is_remote_frame() {
            <CanFrame as embedded_can::Frame>::new_remote(frame.id(), frame.dlc())
        } else {
            <CanFrame as embedded_can::Frame>::new(frame.id(), frame.data())
        }
    }

    /// Converts this frame into any `embedded-can` frame type.
    pub fn to_frame<F: embedded_can::Frame>(&self) -> Option<F> {
        let id = <CanFrame as embedded_can::Frame>::id(self);
        if self.rtr {
            F::new_remote(id, self.len as usize)
        } else {
            F::new(id, self.data())
        }
    }
}
