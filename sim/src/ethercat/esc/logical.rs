//! Logical addressing: what an LRD, LWR or LRW does through the ESC's FMMUs, each mapping a
//! span of the logical address space bit by bit onto physical memory, and whether a datagram
//! reads a span of memory at all (what the device need not prepare when no datagram does). The
//! FMMUs are decoded when their registers are written, so that a datagram that passes by
//! another SubDevice's images costs a few comparisons.

use std::ops::Range;

use edsgen_runtime::ethercat::wire::datagram::{Command, DatagramRepr};

use super::{governs, overlaps};
use super::{reg, EmulatedEsc, FMMUS, SYNC_MANAGERS};

/// An active FMMU, decoded from its 16 registers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Fmmu {
    /// Logical bits `from..to` (absolute).
    from: u64,
    to: u64,
    /// The physical bit of `from`.
    physical: u64,
    read: bool,
    write: bool,
}

impl Fmmu {
    /// FMMU `n` of the registers in `mem`, if it is active and maps at least one bit.
    fn decode(mem: &[u8], n: usize) -> Option<Fmmu> {
        let base = usize::from(reg::FMMU0) + 16 * n;
        let f = mem.get(base..base + 16)?;
        let (kind, active) = (f[11], f[12] & 1 != 0);
        let len = u16::from_le_bytes([f[4], f[5]]);
        if !active || len == 0 {
            return None;
        }
        let logical = u64::from(u32::from_le_bytes([f[0], f[1], f[2], f[3]]));
        let (start_bit, stop_bit) = (u64::from(f[6] & 7), u64::from(f[7] & 7));
        let physical = u64::from(u16::from_le_bytes([f[8], f[9]]));
        let from = logical * 8 + start_bit;
        let to = (logical + u64::from(len) - 1) * 8 + stop_bit + 1;
        (from < to).then_some(Fmmu {
            from,
            to,
            physical: physical * 8 + u64::from(f[10] & 7),
            read: kind & 1 != 0,
            write: kind & 2 != 0,
        })
    }
}

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

    /// The share as byte ranges of the datagram's data and of memory, when it is whole bytes on
    /// both sides (as a MainDevice lays out most images); `d0` is the datagram's first bit.
    fn bytes(&self, d0: u64) -> Option<(Range<usize>, Range<usize>)> {
        let whole = (self.from | self.to | self.physical) & 7 == 0;
        whole.then(|| {
            let (d, p) = (
                ((self.from - d0) / 8) as usize,
                (self.physical / 8) as usize,
            );
            let n = ((self.to - self.from) / 8) as usize;
            (d..d + n, p..p + n)
        })
    }
}

impl EmulatedEsc {
    /// Decodes the FMMUs again after a write over `range` reached their registers.
    pub(super) fn fmmus_written(&mut self, range: Range<u32>) {
        let registers = u32::from(reg::FMMU0)..u32::from(reg::FMMU0) + 16 * FMMUS as u32;
        if overlaps(&range, &registers) {
            for n in 0..FMMUS {
                self.fmmus[n] = Fmmu::decode(&self.mem[..], n);
            }
        }
    }

    /// Whether an active FMMU maps any of the `len` logical bytes at `address`: most logical
    /// datagrams carry other SubDevices' images and pass by on this test.
    fn maps(&self, address: u32, len: usize) -> bool {
        let d0 = u64::from(address) * 8;
        let d1 = d0 + len as u64 * 8;
        self.fmmus
            .iter()
            .flatten()
            .any(|f| f.from < d1 && d0 < f.to)
    }

    /// FMMU `n`'s share of the logical bits `d0..d1`, if it is active and overlaps them and
    /// the memory it maps is reachable.
    fn share(&self, n: usize, d0: u64, d1: u64) -> Option<Share> {
        let fmmu = self.fmmus[n]?;
        let (from, to) = (fmmu.from.max(d0), fmmu.to.min(d1));
        if from >= to {
            return None;
        }
        let (pfrom, pto) = (
            fmmu.physical + (from - fmmu.from),
            fmmu.physical + (to - fmmu.from),
        );
        if pto > 0x1_0000 * 8 || !self.process_memory_reachable(pfrom / 8, (pto - 1) / 8) {
            return None;
        }
        Some(Share {
            from,
            to,
            physical: pfrom,
            read: fmmu.read,
            write: fmmu.write,
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
    ///
    /// Writes take the data as it came: they go first, and the reads then put memory into the
    /// data. Only when a read maps memory that a write of the same datagram changes do the
    /// reads go first (they give the memory as it was), the writes then taking a copy of the
    /// data as it came.
    pub(super) fn logical(
        &mut self,
        address: u32,
        data: &mut [u8],
        read: bool,
        write: bool,
    ) -> u16 {
        if !self.maps(address, data.len()) {
            return 0;
        }
        let (shares, d0) = self.shares(address, data.len());
        let reads = read && shares.iter().flatten().any(|s| s.read);
        let writes = write && shares.iter().flatten().any(|s| s.write);
        if !reads && !writes {
            return 0;
        }
        let rewritten = |s: &Share| {
            shares
                .iter()
                .flatten()
                .any(|w| w.write && overlaps(&w.physical_bytes(), &s.physical_bytes()))
        };
        let read_first = reads && writes && shares.iter().flatten().any(|s| s.read && rewritten(s));
        if read_first {
            let incoming = data.to_vec();
            self.read_shares(&shares, d0, data);
            self.write_shares(&shares, d0, &incoming);
        } else {
            if writes {
                self.write_shares(&shares, d0, data);
            }
            if reads {
                self.read_shares(&shares, d0, data);
            }
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

    /// Puts the memory the read shares map into `data` (the datagram's, from logical bit `d0`).
    fn read_shares(&self, shares: &[Option<Share>; FMMUS], d0: u64, data: &mut [u8]) {
        for s in shares.iter().flatten().filter(|s| s.read) {
            if let Some((d, p)) = s.bytes(d0) {
                data[d].copy_from_slice(&self.mem[p]);
                continue;
            }
            for bit in s.from..s.to {
                let p = s.physical + (bit - s.from);
                let value = self.mem[(p / 8) as usize] >> (p % 8) & 1;
                let d = bit - d0;
                let byte = &mut data[(d / 8) as usize];
                *byte = (*byte & !(1 << (d % 8))) | (value << (d % 8));
            }
        }
    }

    /// Puts `source` (the datagram's data as it came, from logical bit `d0`) into the memory
    /// the write shares map, then reports what the writes did (a buffer's last byte written).
    fn write_shares(&mut self, shares: &[Option<Share>; FMMUS], d0: u64, source: &[u8]) {
        for s in shares.iter().flatten().filter(|s| s.write) {
            if let Some((d, p)) = s.bytes(d0) {
                self.mem[p].copy_from_slice(&source[d]);
                continue;
            }
            for bit in s.from..s.to {
                let p = s.physical + (bit - s.from);
                let d = bit - d0;
                let value = source[(d / 8) as usize] >> (d % 8) & 1;
                let byte = &mut self.mem[(p / 8) as usize];
                *byte = (*byte & !(1 << (p % 8))) | (value << (p % 8));
            }
        }
        for s in shares.iter().flatten().filter(|s| s.write) {
            self.fmmus_written(s.physical_bytes());
            self.after_write(s.physical_bytes());
        }
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
                let (address, len) = (header.logical_address(), usize::from(header.len));
                if !self.maps(address, len) {
                    return false;
                }
                let (shares, _) = self.shares(address, len);
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
