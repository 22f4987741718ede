//! The dialects of ODVA EDS authors the reader recognises and honours, each reported with the
//! reading it took: assembly member sizes written in bytes where the specification wants bits
//! (CIP022), read as bytes when that, and only that, makes the assembly add up to its size.

use crate::diag::Diagnostic;
use crate::model::{Cip, CipAssembly};
use crate::rules;

/// Reads as bytes the member sizes of every assembly that adds up only that way (each member's
/// bits multiplied by 8), with a CIP022 warning naming the reading.
pub fn member_sizes_in_bytes(cip: &mut Cip, diags: &mut Vec<Diagnostic>) {
    for assembly in cip.assemblies.values_mut() {
        let Some(reading) = bytes_reading(assembly) else {
            continue;
        };
        let as_bits = member_sum(assembly).unwrap_or(0);
        for member in &mut assembly.members {
            member.bits = member.bits.map(|b| b * 8);
        }
        let size = assembly.size.as_ref().map_or(0, |s| s.value);
        diags.push(
            Diagnostic::new(
                &rules::CIP_MEMBER_BYTES,
                assembly.size.as_ref().map(|s| s.span),
                format!(
                    "Assem{} `{}`: member sizes read as bytes: {reading} = {size} bytes, the \
                     assembly's size",
                    assembly.number, assembly.name
                ),
            )
            .with_label("size of the assembly")
            .with_help(format!(
                "member sizes are bits in the EDS specification: write each member's size times 8 \
                 (read as bits, the members add up to {} bits, not {} bytes)",
                as_bits, size
            )),
        );
    }
}

/// The sum of the members' written sizes, when every member has one.
fn member_sum(assembly: &CipAssembly) -> Option<u64> {
    assembly.members.iter().map(|m| m.bits.map(u64::from)).sum()
}

/// `4 members of 2 bytes`, `5 members of 4 bytes and 12 of 1 byte`: the members' sizes read as
/// bytes, when read as bits they miss the assembly's size and read as bytes they make it.
fn bytes_reading(assembly: &CipAssembly) -> Option<String> {
    let size = u64::from(assembly.size.as_ref()?.value);
    let sum = member_sum(assembly)?;
    if size == 0 || sum.div_ceil(8) == size || sum != size {
        return None;
    }
    // Runs of equal sizes, in order.
    let mut runs: Vec<(u32, usize)> = Vec::new();
    for bits in assembly.members.iter().filter_map(|m| m.bits) {
        match runs.last_mut() {
            Some((b, n)) if *b == bits => *n += 1,
            _ => runs.push((bits, 1)),
        }
    }
    let parts: Vec<String> = runs
        .iter()
        .enumerate()
        .map(|(i, (bytes, n))| {
            let unit = if *bytes == 1 { "byte" } else { "bytes" };
            match (i, n) {
                (0, 1) => format!("1 member of {bytes} {unit}"),
                (0, _) => format!("{n} members of {bytes} {unit}"),
                _ => format!("{n} of {bytes} {unit}"),
            }
        })
        .collect();
    Some(match parts.as_slice() {
        [one] => one.clone(),
        [rest @ .., last] => format!("{} and {last}", rest.join(", ")),
        [] => return None,
    })
}
