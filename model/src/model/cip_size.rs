//! Assembly sizes: what an assembly's members add up to, in bits and bytes, as the file says.
//! The validator checks them against the written sizes; the emitter and the simulator size
//! connections and images with them.

use super::{Cip, CipAssembly, CipNumber, ConnectionData, FieldRef};

/// How deep assemblies may nest (an assembly naming itself ends here).
const MAX_DEPTH: u32 = 8;

impl Cip {
    /// An assembly's size in bytes as the file says it (written, or the members' sum).
    pub fn assembly_size(&self, assembly: &CipAssembly) -> Option<u64> {
        self.assembly_bits(assembly, 0).map(|bits| bits.div_ceil(8))
    }

    /// The size in bytes of one direction of a connection (O->T, T->O), as the device holds
    /// it: the size of the assembly its format names, when known; else its written size (a
    /// `ParamN` gives that parameter's default). The one sizing of the simulated adapter, whose
    /// assemblies are [`Cip::assembly_size`] long, and of a scanner that opens the connection
    /// (`edsgen enip io`), so that they agree; where the written size disagrees with the
    /// assembly, the validator says so (CIP030).
    pub fn connection_size(&self, data: &ConnectionData) -> Option<u64> {
        let assembly = match &data.format.value {
            FieldRef::Assem(n) => self.assemblies.get(n).and_then(|a| self.assembly_size(a)),
            _ => None,
        };
        assembly.or_else(|| match &data.size.value {
            FieldRef::Number(n) => Some(*n),
            FieldRef::Param(n) => match self.params.get(n)?.default.as_ref()?.value {
                CipNumber::Int(v) => u64::try_from(v).ok(),
                CipNumber::Real(_) => None,
            },
            _ => None,
        })
    }

    /// The sum of an assembly's members in bits, when the file gives every member's size.
    pub fn members_bits(&self, assembly: &CipAssembly) -> Option<u64> {
        self.members_bits_at(assembly, 0)
    }

    /// The size in bits of what a member names, when the file says.
    fn member_target_bits(&self, member: &FieldRef, depth: u32) -> Option<u64> {
        match member {
            FieldRef::Param(n) => self
                .params
                .get(n)?
                .data_size
                .as_ref()
                .map(|s| u64::from(s.value) * 8),
            FieldRef::Assem(n) if depth < MAX_DEPTH => {
                self.assembly_bits(self.assemblies.get(n)?, depth + 1)
            }
            _ => None,
        }
    }

    /// An assembly's size in bits: its written size, else the sum of its members.
    fn assembly_bits(&self, assembly: &CipAssembly, depth: u32) -> Option<u64> {
        if let Some(size) = &assembly.size {
            return Some(u64::from(size.value) * 8);
        }
        self.members_bits_at(assembly, depth)
    }

    fn members_bits_at(&self, assembly: &CipAssembly, depth: u32) -> Option<u64> {
        assembly
            .members
            .iter()
            .map(|m| {
                m.bits
                    .map(u64::from)
                    .or_else(|| self.member_target_bits(&m.member, depth))
            })
            .sum()
    }
}
