//! The blocks that describe a configuration: ExpectedSubmoduleBlockReq (what the controller
//! expects in each slot), the ModuleDiffBlock (where the device differs) and the
//! RealIdentificationData record (what the device has), all of one shape: APIs, slots with a
//! module ident, subslots with a submodule ident. Checked views whose lists are iterators, and
//! owned reprs behind `alloc`.

use super::super::block::Reader;

/// DataDescription: input.
pub const DATA_INPUT: u16 = 1;
/// DataDescription: output.
pub const DATA_OUTPUT: u16 = 2;

/// One DataDescription of an expected submodule.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DataDescription {
    /// [`DATA_INPUT`] or [`DATA_OUTPUT`].
    pub direction: u16,
    /// SubmoduleDataLength.
    pub length: u16,
    /// LengthIOCS.
    pub iocs_len: u8,
    /// LengthIOPS.
    pub iops_len: u8,
}

/// One expected submodule as a view.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ExpectedSubmoduleView {
    /// SubslotNumber.
    pub subslot: u16,
    /// SubmoduleIdentNumber.
    pub ident: u32,
    /// SubmoduleProperties (Type in bits 0-1: 0 no IO, 1 input, 2 output, 3 both).
    pub properties: u16,
    descriptions: [DataDescription; 2],
}

impl ExpectedSubmoduleView {
    /// Its DataDescriptions: two for a submodule with input and output, else one.
    pub fn data(&self) -> &[DataDescription] {
        let count = if self.properties & 3 == 3 { 2 } else { 1 };
        &self.descriptions[..count]
    }

    fn read(r: &mut Reader<'_>) -> Option<ExpectedSubmoduleView> {
        let mut sub = ExpectedSubmoduleView {
            subslot: r.u16()?,
            ident: r.u32()?,
            properties: r.u16()?,
            descriptions: [DataDescription::default(); 2],
        };
        let count = sub.data().len();
        for d in &mut sub.descriptions[..count] {
            *d = DataDescription {
                direction: r.u16()?,
                length: r.u16()?,
                iocs_len: r.u8()?,
                iops_len: r.u8()?,
            };
        }
        Some(sub)
    }
}

/// The submodules of one expected slot.
#[derive(Debug, Clone)]
pub struct ExpectedSubmodules<'a> {
    r: Reader<'a>,
    left: u16,
}

impl Iterator for ExpectedSubmodules<'_> {
    type Item = ExpectedSubmoduleView;
    fn next(&mut self) -> Option<ExpectedSubmoduleView> {
        self.left = self.left.checked_sub(1)?;
        ExpectedSubmoduleView::read(&mut self.r)
    }
}

/// One slot of an ExpectedSubmoduleBlockReq as a view.
#[derive(Debug, Clone)]
pub struct ExpectedSlotView<'a> {
    /// API.
    pub api: u32,
    /// SlotNumber.
    pub slot: u16,
    /// ModuleIdentNumber.
    pub module_ident: u32,
    /// ModuleProperties.
    pub module_properties: u16,
    /// The submodules.
    pub submodules: ExpectedSubmodules<'a>,
}

/// The slots of an ExpectedSubmoduleBlockReq.
#[derive(Debug, Clone)]
pub struct ExpectedSlots<'a> {
    r: Reader<'a>,
    left: u16,
}

impl<'a> Iterator for ExpectedSlots<'a> {
    type Item = ExpectedSlotView<'a>;
    fn next(&mut self) -> Option<ExpectedSlotView<'a>> {
        self.left = self.left.checked_sub(1)?;
        let r = &mut self.r;
        let (api, slot, module_ident, module_properties) = (r.u32()?, r.u16()?, r.u32()?, r.u16()?);
        let submodules = ExpectedSubmodules {
            left: r.u16()?,
            r: r.clone(),
        };
        // Past the submodules: read them once more on the slots' own reader.
        for _ in 0..submodules.left {
            ExpectedSubmoduleView::read(r)?;
        }
        Some(ExpectedSlotView {
            api,
            slot,
            module_ident,
            module_properties,
            submodules,
        })
    }
}

/// A checked view of an ExpectedSubmoduleBlockReq's body: every slot and submodule fits.
#[derive(Debug, Clone, Copy)]
pub struct ExpectedSubmoduleBlockReqPacket<T: AsRef<[u8]>> {
    body: T,
}

impl<T: AsRef<[u8]>> ExpectedSubmoduleBlockReqPacket<T> {
    /// The view, or `None` when a slot or submodule runs past the body's end.
    pub fn new_checked(body: T) -> Option<Self> {
        body.as_ref().get(..2)?;
        let view = ExpectedSubmoduleBlockReqPacket { body };
        let mut slots = view.slots();
        let n = slots.left;
        for _ in 0..n {
            slots.next()?;
        }
        Some(view)
    }

    /// The slots (the standard's API entries), in order.
    pub fn slots(&self) -> ExpectedSlots<'_> {
        let mut r = Reader::new(self.body.as_ref());
        let left = r.u16().unwrap_or(0);
        ExpectedSlots { r, left }
    }
}

/// A module of a configuration as a view: its slot, ident, state and submodules.
#[derive(Debug, Clone)]
pub struct SlotIdentView<'a> {
    /// SlotNumber.
    pub slot: u16,
    /// ModuleIdentNumber.
    pub module_ident: u32,
    /// ModuleState (ModuleDiffBlock only; 0 in RealIdentificationData).
    pub state: u16,
    /// (SubslotNumber, SubmoduleIdentNumber, SubmoduleState (ModuleDiffBlock only)).
    pub submodules: SubmoduleIdents<'a>,
}

/// The submodules of a [`SlotIdentView`].
#[derive(Debug, Clone)]
pub struct SubmoduleIdents<'a> {
    r: Reader<'a>,
    with_state: bool,
}

impl Iterator for SubmoduleIdents<'_> {
    type Item = (u16, u32, u16);
    fn next(&mut self) -> Option<(u16, u32, u16)> {
        let (subslot, ident) = (self.r.u16()?, self.r.u32()?);
        let state = if self.with_state { self.r.u16()? } else { 0 };
        Some((subslot, ident, state))
    }
}

/// The modules of one API.
#[derive(Debug, Clone)]
pub struct SlotIdents<'a> {
    r: Reader<'a>,
    left: u16,
    with_state: bool,
}

impl<'a> Iterator for SlotIdents<'a> {
    type Item = SlotIdentView<'a>;
    fn next(&mut self) -> Option<SlotIdentView<'a>> {
        self.left = self.left.checked_sub(1)?;
        let r = &mut self.r;
        let (slot, module_ident) = (r.u16()?, r.u32()?);
        let state = if self.with_state { r.u16()? } else { 0 };
        let size = if self.with_state { 8 } else { 6 };
        let count = usize::from(r.u16()?);
        let submodules = SubmoduleIdents {
            r: Reader::new(r.take(count * size)?),
            with_state: self.with_state,
        };
        Some(SlotIdentView {
            slot,
            module_ident,
            state,
            submodules,
        })
    }
}

/// The configuration of one API as a view.
#[derive(Debug, Clone)]
pub struct ApiIdentView<'a> {
    /// API.
    pub api: u32,
    /// Its modules.
    pub modules: SlotIdents<'a>,
}

/// The APIs of an [`IdentificationPacket`].
#[derive(Debug, Clone)]
pub struct ApiIdents<'a> {
    r: Reader<'a>,
    left: u16,
    with_state: bool,
}

impl<'a> Iterator for ApiIdents<'a> {
    type Item = ApiIdentView<'a>;
    fn next(&mut self) -> Option<ApiIdentView<'a>> {
        self.left = self.left.checked_sub(1)?;
        let api = self.r.u32()?;
        let modules = SlotIdents {
            left: self.r.u16()?,
            r: self.r.clone(),
            with_state: self.with_state,
        };
        let mut walk = modules.clone();
        for _ in 0..modules.left {
            walk.next()?;
        }
        self.r = walk.r;
        Some(ApiIdentView { api, modules })
    }
}

/// A checked view of a ModuleDiffBlock's or a RealIdentificationData's body (version 1.1):
/// every API, module and submodule fits.
#[derive(Debug, Clone, Copy)]
pub struct IdentificationPacket<T: AsRef<[u8]>> {
    body: T,
    with_state: bool,
}

impl<T: AsRef<[u8]>> IdentificationPacket<T> {
    /// A ModuleDiffBlock's body (with ModuleState and SubmoduleState), or `None` when short.
    pub fn module_diff(body: T) -> Option<Self> {
        IdentificationPacket {
            body,
            with_state: true,
        }
        .checked()
    }

    /// A RealIdentificationData's body (no states), or `None` when short.
    pub fn real_identification(body: T) -> Option<Self> {
        IdentificationPacket {
            body,
            with_state: false,
        }
        .checked()
    }

    fn checked(self) -> Option<Self> {
        self.body.as_ref().get(..2)?;
        let mut apis = self.apis();
        // Each API walks its modules, and each module slices its submodules.
        for _ in 0..apis.left {
            apis.next()?;
        }
        Some(self)
    }

    /// The APIs, in order.
    pub fn apis(&self) -> ApiIdents<'_> {
        let mut r = Reader::new(self.body.as_ref());
        let left = r.u16().unwrap_or(0);
        ApiIdents {
            r,
            left,
            with_state: self.with_state,
        }
    }
}

#[cfg(feature = "alloc")]
mod owned;
#[cfg(feature = "alloc")]
pub use owned::*;
