//! The blocks that describe a configuration: ExpectedSubmoduleBlockReq (what the controller
//! expects in each slot), the ModuleDiffBlock (where the device differs) and the
//! RealIdentificationData record (what the device has), all of one shape: APIs, slots with a
//! module ident, subslots with a submodule ident.

use alloc::vec::Vec;

use super::REAL_IDENTIFICATION_DATA;
use super::{emit_block, put16, put32, Reader, EXPECTED_SUBMODULE_BLOCK_REQ, MODULE_DIFF_BLOCK};

/// DataDescription: input.
pub const DATA_INPUT: u16 = 1;
/// DataDescription: output.
pub const DATA_OUTPUT: u16 = 2;

/// One DataDescription of an expected submodule.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
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

/// One expected submodule.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExpectedSubmodule {
    /// SubslotNumber.
    pub subslot: u16,
    /// SubmoduleIdentNumber.
    pub ident: u32,
    /// SubmoduleProperties (Type in bits 0-1: 0 no IO, 1 input, 2 output, 3 both).
    pub properties: u16,
    /// Its DataDescriptions (one, or two for input and output).
    pub data: Vec<DataDescription>,
}

/// One slot of an ExpectedSubmoduleBlockReq (the standard calls it an API entry).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExpectedSlot {
    /// API.
    pub api: u32,
    /// SlotNumber.
    pub slot: u16,
    /// ModuleIdentNumber.
    pub module_ident: u32,
    /// ModuleProperties.
    pub module_properties: u16,
    /// The submodules.
    pub submodules: Vec<ExpectedSubmodule>,
}

/// ExpectedSubmoduleBlockReq.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExpectedSubmoduleBlockReq {
    /// The slots.
    pub slots: Vec<ExpectedSlot>,
}

impl ExpectedSubmoduleBlockReq {
    /// Reads the block's content: the DataDescriptions follow from each submodule's type.
    pub fn parse(body: &[u8]) -> Option<ExpectedSubmoduleBlockReq> {
        let mut r = Reader::new(body);
        let n = r.u16()?;
        let mut slots = Vec::new();
        for _ in 0..n {
            let mut slot = ExpectedSlot {
                api: r.u32()?,
                slot: r.u16()?,
                module_ident: r.u32()?,
                module_properties: r.u16()?,
                submodules: Vec::new(),
            };
            let subs = r.u16()?;
            for _ in 0..subs {
                let subslot = r.u16()?;
                let ident = r.u32()?;
                let properties = r.u16()?;
                let count = if properties & 3 == 3 { 2 } else { 1 };
                let data = (0..count)
                    .map(|_| {
                        Some(DataDescription {
                            direction: r.u16()?,
                            length: r.u16()?,
                            iocs_len: r.u8()?,
                            iops_len: r.u8()?,
                        })
                    })
                    .collect::<Option<Vec<_>>>()?;
                slot.submodules.push(ExpectedSubmodule {
                    subslot,
                    ident,
                    properties,
                    data,
                });
            }
            slots.push(slot);
        }
        Some(ExpectedSubmoduleBlockReq { slots })
    }

    /// Appends the block.
    pub fn emit(&self, out: &mut Vec<u8>) {
        emit_block(out, EXPECTED_SUBMODULE_BLOCK_REQ, 0, |o| {
            put16(o, self.slots.len() as u16);
            for s in &self.slots {
                put32(o, s.api);
                put16(o, s.slot);
                put32(o, s.module_ident);
                put16(o, s.module_properties);
                put16(o, s.submodules.len() as u16);
                for sub in &s.submodules {
                    put16(o, sub.subslot);
                    put32(o, sub.ident);
                    put16(o, sub.properties);
                    for d in &sub.data {
                        put16(o, d.direction);
                        put16(o, d.length);
                        o.push(d.iocs_len);
                        o.push(d.iops_len);
                    }
                }
            }
        });
    }
}

/// A module of a configuration: its slot, ident and subslots (subslot, ident, and for a
/// ModuleDiffBlock the SubmoduleState).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SlotIdent {
    /// SlotNumber.
    pub slot: u16,
    /// ModuleIdentNumber.
    pub module_ident: u32,
    /// ModuleState (ModuleDiffBlock only).
    pub state: u16,
    /// (SubslotNumber, SubmoduleIdentNumber, SubmoduleState (ModuleDiffBlock only)).
    pub submodules: Vec<(u16, u32, u16)>,
}

/// The configuration of one API.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ApiIdent {
    /// API.
    pub api: u32,
    /// Its modules.
    pub modules: Vec<SlotIdent>,
}

fn parse_idents(body: &[u8], with_state: bool) -> Option<Vec<ApiIdent>> {
    let mut r = Reader::new(body);
    let n = r.u16()?;
    let mut apis = Vec::new();
    for _ in 0..n {
        let api = r.u32()?;
        let m = r.u16()?;
        let mut modules = Vec::new();
        for _ in 0..m {
            let slot = r.u16()?;
            let module_ident = r.u32()?;
            let state = if with_state { r.u16()? } else { 0 };
            let s = r.u16()?;
            let submodules = (0..s)
                .map(|_| {
                    let subslot = r.u16()?;
                    let ident = r.u32()?;
                    let state = if with_state { r.u16()? } else { 0 };
                    Some((subslot, ident, state))
                })
                .collect::<Option<Vec<_>>>()?;
            modules.push(SlotIdent {
                slot,
                module_ident,
                state,
                submodules,
            });
        }
        apis.push(ApiIdent { api, modules });
    }
    Some(apis)
}

fn put_idents(o: &mut Vec<u8>, apis: &[ApiIdent], with_state: bool) {
    put16(o, apis.len() as u16);
    for api in apis {
        put32(o, api.api);
        put16(o, api.modules.len() as u16);
        for m in &api.modules {
            put16(o, m.slot);
            put32(o, m.module_ident);
            if with_state {
                put16(o, m.state);
            }
            put16(o, m.submodules.len() as u16);
            for &(subslot, ident, state) in &m.submodules {
                put16(o, subslot);
                put32(o, ident);
                if with_state {
                    put16(o, state);
                }
            }
        }
    }
}

/// ModuleDiffBlock: the modules and submodules where the device differs from the expected
/// configuration, with their real idents and states.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ModuleDiffBlock {
    /// The APIs with differences.
    pub apis: Vec<ApiIdent>,
}

impl ModuleDiffBlock {
    /// Reads the block's content.
    pub fn parse(body: &[u8]) -> Option<ModuleDiffBlock> {
        Some(ModuleDiffBlock {
            apis: parse_idents(body, true)?,
        })
    }

    /// Appends the block.
    pub fn emit(&self, out: &mut Vec<u8>) {
        emit_block(out, MODULE_DIFF_BLOCK, 0, |o| {
            put_idents(o, &self.apis, true)
        });
    }
}

/// RealIdentificationData (version 1.1, with APIs): the device's real configuration.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RealIdentificationData {
    /// The APIs.
    pub apis: Vec<ApiIdent>,
}

impl RealIdentificationData {
    /// Reads the block's content (version 1.1).
    pub fn parse(body: &[u8]) -> Option<RealIdentificationData> {
        Some(RealIdentificationData {
            apis: parse_idents(body, false)?,
        })
    }

    /// Appends the block.
    pub fn emit(&self, out: &mut Vec<u8>) {
        emit_block(out, REAL_IDENTIFICATION_DATA, 1, |o| {
            put_idents(o, &self.apis, false)
        });
    }
}
