//! The boot-up check (CiA 302-2 in spirit): the identity a master expects of a node (1000h and
//! 1018h:1–4, as the generated bindings' constants give them) compared with what the node reads.

use crate::od::entry::Entry;

/// Device type (1000h).
pub const DEVICE_TYPE: Entry<u32> = Entry::new(0x1000, 0);
/// Vendor-ID (1018h:1).
pub const VENDOR_ID: Entry<u32> = Entry::new(0x1018, 1);
/// Product code (1018h:2).
pub const PRODUCT_CODE: Entry<u32> = Entry::new(0x1018, 2);
/// Revision number (1018h:3).
pub const REVISION_NUMBER: Entry<u32> = Entry::new(0x1018, 3);
/// Serial number (1018h:4).
pub const SERIAL_NUMBER: Entry<u32> = Entry::new(0x1018, 4);

/// The identity entries in the order a boot-up check reads them.
pub const IDENTITY_ENTRIES: [Entry<u32>; 5] = [
    DEVICE_TYPE,
    VENDOR_ID,
    PRODUCT_CODE,
    REVISION_NUMBER,
    SERIAL_NUMBER,
];

/// What a master expects of a node; `None` (like 0 in 1F84h–1F88h) is not checked.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ExpectedIdentity {
    /// 1000h.
    pub device_type: Option<u32>,
    /// 1018h:1.
    pub vendor_id: Option<u32>,
    /// 1018h:2.
    pub product_code: Option<u32>,
    /// 1018h:3.
    pub revision_number: Option<u32>,
    /// 1018h:4.
    pub serial_number: Option<u32>,
}

impl ExpectedIdentity {
    /// The expectation for each of [`IDENTITY_ENTRIES`], in order.
    pub const fn expected(&self) -> [Option<u32>; 5] {
        [
            self.device_type,
            self.vendor_id,
            self.product_code,
            self.revision_number,
            self.serial_number,
        ]
    }
}

/// One identity entry that is not what the master expects.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IdentityMismatch {
    /// The node.
    pub node_id: u8,
    /// The entry (1000h or 1018h:n).
    pub entry: Entry<u32>,
    /// The expected value.
    pub expected: u32,
    /// What the node holds; `None` if it could not be read (its abort code in `abort`).
    pub actual: Option<u32>,
    /// The abort code when the read failed.
    pub abort: Option<u32>,
}
