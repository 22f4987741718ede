//! The configuration blocks as owned reprs (feature `alloc`): what a controller builds and a
//! device keeps of an accepted Connect, read through the views and written into the caller's
//! buffer.

use alloc::vec::Vec;

use super::super::super::block::emit_block;
use super::super::super::BufferTooSmall;
use super::super::REAL_IDENTIFICATION_DATA;
use super::super::{Writer, EXPECTED_SUBMODULE_BLOCK_REQ, MODULE_DIFF_BLOCK};
use super::{DataDescription, ExpectedSubmoduleBlockReqPacket, IdentificationPacket};

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
        let view = ExpectedSubmoduleBlockReqPacket::new_checked(body)?;
        let slots = view
            .slots()
            .map(|s| ExpectedSlot {
                api: s.api,
                slot: s.slot,
                module_ident: s.module_ident,
                module_properties: s.module_properties,
                submodules: s
                    .submodules
                    .map(|sub| ExpectedSubmodule {
                        subslot: sub.subslot,
                        ident: sub.ident,
                        properties: sub.properties,
                        data: sub.data().to_vec(),
                    })
                    .collect(),
            })
            .collect();
        Some(ExpectedSubmoduleBlockReq { slots })
    }

    /// Writes the block at the start of `buf`; its length. Each submodule's DataDescriptions
    /// are written as they are listed.
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize, BufferTooSmall> {
        emit_block(buf, EXPECTED_SUBMODULE_BLOCK_REQ, 0, |b| {
            let mut w = Writer::new(b);
            w.count(self.slots.len())?;
            for s in &self.slots {
                w.u32(s.api)?;
                w.u16(s.slot)?;
                w.u32(s.module_ident)?;
                w.u16(s.module_properties)?;
                w.count(s.submodules.len())?;
                for sub in &s.submodules {
                    w.u16(sub.subslot)?;
                    w.u32(sub.ident)?;
                    w.u16(sub.properties)?;
                    for d in &sub.data {
                        w.u16(d.direction)?;
                        w.u16(d.length)?;
                        w.u8(d.iocs_len)?;
                        w.u8(d.iops_len)?;
                    }
                }
            }
            Ok(w.len())
        })
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

fn idents<T: AsRef<[u8]>>(view: IdentificationPacket<T>) -> Vec<ApiIdent> {
    view.apis()
        .map(|a| ApiIdent {
            api: a.api,
            modules: a
                .modules
                .map(|m| SlotIdent {
                    slot: m.slot,
                    module_ident: m.module_ident,
                    state: m.state,
                    submodules: m.submodules.collect(),
                })
                .collect(),
        })
        .collect()
}

fn emit_idents(
    buf: &mut [u8],
    (block_type, low): (u16, u8),
    apis: &[ApiIdent],
    with_state: bool,
) -> Result<usize, BufferTooSmall> {
    emit_block(buf, block_type, low, |b| {
        let mut w = Writer::new(b);
        w.count(apis.len())?;
        for api in apis {
            w.u32(api.api)?;
            w.count(api.modules.len())?;
            for m in &api.modules {
                w.u16(m.slot)?;
                w.u32(m.module_ident)?;
                if with_state {
                    w.u16(m.state)?;
                }
                w.count(m.submodules.len())?;
                for &(subslot, ident, state) in &m.submodules {
                    w.u16(subslot)?;
                    w.u32(ident)?;
                    if with_state {
                        w.u16(state)?;
                    }
                }
            }
        }
        Ok(w.len())
    })
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
            apis: idents(IdentificationPacket::module_diff(body)?),
        })
    }

    /// Writes the block at the start of `buf`; its length.
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize, BufferTooSmall> {
        emit_idents(buf, (MODULE_DIFF_BLOCK, 0), &self.apis, true)
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
            apis: idents(IdentificationPacket::real_identification(body)?),
        })
    }

    /// Writes the block at the start of `buf`; its length.
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize, BufferTooSmall> {
        emit_idents(buf, (REAL_IDENTIFICATION_DATA, 1), &self.apis, false)
    }
}
