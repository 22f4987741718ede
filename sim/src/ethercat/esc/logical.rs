//! Logical addressing: what an LRD, LWR or LRW does through the ESC's FMMUs, each mapping a
//! span of the logical address space bit by bit onto physical memory.

use super::{governs, overlaps};
use super::{reg, EmulatedEsc, FMMUS, SYNC_MANAGERS};

impl EmulatedEsc {
    /// A logical access through the FMMUs: each active FMMU overlapping the datagram maps its
    /// bits to physical memory; +1 if a read FMMU took part, +2 (or +1 for LWR) if a write one
    /// did. Memory of a SyncManager the device has deactivated is not reached.
    pub(super) fn logical(
        &mut self,
        address: u32,
        data: &mut [u8],
        read: bool,
        write: bool,
    ) -> u16 {
        let incoming = data.to_vec();
        let d0 = u64::from(address) * 8;
        let d1 = d0 + data.len() as u64 * 8; // exclusive
        let (mut did_read, mut did_write) = (false, false);
        let mut written = Vec::new();
        for n in 0..FMMUS {
            let base = usize::from(reg::FMMU0) + 16 * n;
            let f = &self.mem[base..base + 16];
            let logical = u32::from_le_bytes([f[0], f[1], f[2], f[3]]);
            let len = u16::from_le_bytes([f[4], f[5]]);
            let (start_bit, stop_bit) = (f[6] & 7, f[7] & 7);
            let physical = u16::from_le_bytes([f[8], f[9]]);
            let physical_bit = f[10] & 7;
            let (kind, active) = (f[11], f[12] & 1 != 0);
            if !active || len == 0 {
                continue;
            }
            let l0 = u64::from(logical) * 8 + u64::from(start_bit);
            let l1 = (u64::from(logical) + u64::from(len) - 1) * 8 + u64::from(stop_bit) + 1;
            let (from, to) = (l0.max(d0), l1.min(d1));
            if from >= to {
                continue;
            }
            let p0 = u64::from(physical) * 8 + u64::from(physical_bit);
            let (pfrom, pto) = (p0 + (from - l0), p0 + (to - l0));
            if pto > 0x1_0000 * 8 || !self.process_memory_reachable(pfrom / 8, (pto - 1) / 8) {
                continue;
            }
            // Whole bytes on both sides, as a MainDevice lays out most images: copied as bytes.
            let bytes = (from % 8 == 0 && to % 8 == 0 && pfrom % 8 == 0).then(|| {
                let (d, p) = (((from - d0) / 8) as usize, (pfrom / 8) as usize);
                let n = ((to - from) / 8) as usize;
                (d..d + n, p..p + n)
            });
            if read && kind & 1 != 0 {
                if let Some((d, p)) = bytes.clone() {
                    data[d].copy_from_slice(&self.mem[p]);
                } else {
                    for bit in from..to {
                        let p = p0 + (bit - l0);
                        let value = self.mem[(p / 8) as usize] >> (p % 8) & 1;
                        let d = bit - d0;
                        let byte = &mut data[(d / 8) as usize];
                        *byte = (*byte & !(1 << (d % 8))) | (value << (d % 8));
                    }
                }
                did_read = true;
            }
            if write && kind & 2 != 0 {
                if let Some((d, p)) = bytes {
                    self.mem[p].copy_from_slice(&incoming[d]);
                } else {
                    for bit in from..to {
                        let p = p0 + (bit - l0);
                        let d = bit - d0;
                        let value = incoming[(d / 8) as usize] >> (d % 8) & 1;
                        let byte = &mut self.mem[(p / 8) as usize];
                        *byte = (*byte & !(1 << (p % 8))) | (value << (p % 8));
                    }
                }
                written.push((pfrom / 8) as u32..((pto - 1) / 8 + 1) as u32);
                did_write = true;
            }
        }
        for range in written {
            self.after_write(range);
        }
        let mut wkc = 0;
        if did_read {
            wkc += 1;
        }
        if did_write {
            wkc += if read { 2 } else { 1 };
        }
        wkc
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
