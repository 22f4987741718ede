//! Logical addressing: what an LRD, LWR or LRW does through the ESC's FMMUs, each mapping a
//! span of the logical address space bit by bit onto physical memory, and whether a datagram
//! reads a span of memory at all (what the device need not prepare when no datagram does).

use std::ops::Range;

use edsgen_runtime::ethercat::wire::datagram::{Command, DatagramRepr};

use super::{governs, overlaps};
use super::{reg, EmulatedEsc, FMMUS, SYNC_MANAGERS};

/// One active FMMU's share of a logical datagram: the bits it maps, in the datagram's logical
/// space and in physical memory.
#[derive(Debug, Clone, Copy)]
struct Share {
    /// Logical bits `from..to` (absolute).
    from: u64,
    to: u64,
    /// The physical bit of `from`.
    physical: u64,
    read: bool,
    write: bool,
}

impl Share {
    /// Physical bytes the share touches.
    fn physical_bytes(&self) -> Range<u32> {
        let last = self.physical + (self.to - self.from) - 1;
        (self.physical / 8) as u32..(last / 8 + 1) as u32
    }
}

impl EmulatedEsc {
    /// FMMU `n`'s share of the logical bits `d0..d1`, if it is active and overlaps them and
    /// the memory it maps is reachable.
    fn share(&self, n: usize, d0: u64, d1: u64) -> Option<Share> {
        let base = usize::from(reg::FMMU0) + 16 * n;
        let f = &self.mem[base..base + 16];
        let (kind, active) = (f[11], f[12] & 1 != 0);
        let len = u16::from_le_bytes([f[4], f[5]]);
        if !active || len == 0 {
            return None;
        }
        let logical = u32::from_le_bytes([f[0], f[1], f[2], f[3]]);
        let (start_bit, stop_bit) = (f[6] & 7, f[7] & 7);
        let physical = u16::from_le_bytes([f[8], f[9]]);
        let physical_bit = f[10] & 7;
        let l0 = u64::from(logical) * 8 + u64::from(start_bit);
        let l1 = (u64::from(logical) + u64::from(len) - 1) * 8 + u64::from(stop_bit) + 1;
        let (from, to) = (l0.max(d0), l1.min(d1));
        if from >= to {
            return None;
        }
        let p0 = u64::from(physical) * 8 + u64::from(physical_bit);
        let (pfrom, pto) = (p0 + (from - l0), p0 + (to - l0));
        if pto > 0x1_0000 * 8 || !self.process_memory_reachable(pfrom / 8, (pto - 1) / 8) {
            return None;
        }
        Some(Share {
            from,
            to,
            physical: pfrom,
            read: kind & 1 != 0,
            write: kind & 2 != 0,
        })
    }

    /// The FMMUs' shares of a logical datagram of `len` bytes at `address`, in FMMU order.
    fn shares(&self, address: u32, len: usize) -> ([Option<Share>; FMMUS], u64) {
        let d0 = u64::from(address) * 8;
        let d1 = d0 + len as u64 * 8; // exclusive
        let mut shares = [None; FMMUS];
        for (n, share) in shares.iter_mut().enumerate() {
            *share = self.share(n, d0, d1);
        }
        (shares, d0)
    }

    /// A logical access through the FMMUs: each active FMMU overlapping the datagram maps its
    /// bits to physical memory; +1 if a read FMMU took part, +2 (or +1 for LWR) if a write one
    /// did. Memory of a SyncManager the device has deactivated is not reached. A datagram no
    /// FMMU overlaps is left as it came, at no cost.
    pub(super) fn logical(
        &mut self,
        address: u32,
        data: &mut [u8],
        read: bool,
        write: bool,
    ) -> u16 {
        let (shares, d0) = self.shares(address, data.len());
        let reads = read && shares.iter().flatten().any(|s| s.read);
        let writes = write && shares.iter().flatten().any(|s| s.write);
        if !reads && !writes {
            return 0;
        }
        // A write puts the data as it came, before any read of the same datagram changed it.
        let incoming = (reads && writes).then(|| data.to_vec());
        let mut written: [Option<Range<u32>>; FMMUS] = Default::default();
        for (n, share) in shares.iter().enumerate() {
            let Some(s) = share else { continue };
            // Whole bytes on both sides, as a MainDevice lays out most images: copied as bytes.
            let bytes = (s.from % 8 == 0 && s.to % 8 == 0 && s.physical % 8 == 0).then(|| {
                let (d, p) = (((s.from - d0) / 8) as usize, (s.physical / 8) as usize);
                let n = ((s.to - s.from) / 8) as usize;
                (d..d + n, p..p + n)
            });
            if reads && s.read {
                if let Some((d, p)) = bytes.clone() {
                    data[d].copy_from_slice(&self.mem[p]);
                } else {
                    for bit in s.from..s.to {
                        let p = s.physical + (bit - s.from);
                        let value = self.mem[(p / 8) as usize] >> (p % 8) & 1;
                        let d = bit - d0;
                        let byte = &mut data[(d / 8) as usize];
                        *byte = (*byte & !(1 << (d % 8))) | (value << (d % 8));
                    }
                }
            }
            if writes && s.write {
                let source = incoming.as_deref().unwrap_or(data);
                if let Some((d, p)) = bytes {
                    self.mem[p].copy_from_slice(&source[d]);
                } else {
                    for bit in s.from..s.to {
                        let p = s.physical + (bit - s.from);
                        let d = bit - d0;
                        let value = source[(d / 8) as usize] >> (d % 8) & 1;
                        let byte = &mut self.mem[(p / 8) as usize];
                        *byte = (*byte & !(1 << (p % 8))) | (value << (p % 8));
                    }
                }
                written[n] = Some(s.physical_bytes());
            }
        }
        for range in written.into_iter().flatten() {
            self.after_write(range);
        }
        let mut wkc = 0;
        if reads {
            wkc += 1;
        }
        if writes {
            wkc += if read { 2 } else { 1 };
        }
        wkc
    }

    /// Whether the datagram `header`, reaching this ESC as it is, reads any byte of physical
    /// memory `memory`: a physical read that addresses this ESC (by position, station address
    /// or broadcast) over those bytes, or a logical read through a read FMMU that maps onto
    /// them. A device prepares what is in `memory` (its inputs) only for a frame that reads it.
    pub fn reads(&self, header: &DatagramRepr, memory: &Range<u32>) -> bool {
        let Some(command) = Command::from_code(header.command) else {
            return false;
        };
        use Command::*;
        let physical = || {
            let start = u32::from(header.ado);
            overlaps(&(start..start + u32::from(header.len)), memory)
        };
        match command {
            Aprd | Aprw | Armw => header.adp == 0 && physical(),
            Fprd | Fprw | Frmw => self.fixed_match(header.adp) && physical(),
            Brd | Brw => physical(),
            Lrd | Lrw => {
                let (shares, _) = self.shares(header.logical_address(), usize::from(header.len));
                shares
                    .iter()
                    .flatten()
                    .any(|s| s.read && overlaps(&s.physical_bytes(), memory))
            }
            Nop | Apwr | Fpwr | Bwr | Lwr => false,
        }
    }

    /// Whether process memory `first..=last` (bytes) is outside every SyncManager, or inside an
    /// enabled buffered one.
    fn process_memory_reachable(&self, first: u64, last: u64) -> bool {
        let range = first as u32..last as u32 + 1;
        (0..SYNC_MANAGERS).all(|n| {
            let sm = self.sm(n);
            !governs(&sm) || !overlaps(&sm.range(), &range) || (sm.enabled() && !sm.is_mailbox())
        })
    }
}
