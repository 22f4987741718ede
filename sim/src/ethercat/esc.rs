//! The EtherCAT SubDevice Controller (ESC) as a master sees it: the 64 KiB register and process
//! memory, and what one datagram does to it (ETG.1000.4 §5.4, ETG.1000.3): physical reads and
//! writes by position, station address (or alias) and broadcast, logical ones through the FMMUs,
//! the working-counter rules, read-only registers, the SII (EEPROM) interface at 0x0500 (for the
//! master, and for the device's PDI while the master offers it the SII), and the
//! SyncManagers' mailbox full/empty states and repeat toggle.
//!
//! What the device's application does (the AL state machine, the mailbox protocols, the process
//! data) is not here: the ESC reports [`Event`]s, and the SubDevice answers them between
//! datagrams, as an ESC's PDI would.
//!
//! Choices: 8 FMMUs, 8 SyncManagers, process memory 0x1000–0xFFFF, two MII ports (port 0 the
//! link, port 1 closed unless a next SubDevice follows it: [`EmulatedEsc::connect_port1`]), SII
//! reads of 8 bytes; the ESC type, revision and build read 0 (not a real chip's); distributed
//! clocks are declared unsupported (0x0008 bit 2 clear), and the DC registers are plain memory.
//! Reading a mailbox SyncManager that is empty, or writing one that is full, is refused as the
//! ESC refuses it (no working counter). SyncManagers govern the digital I/O registers and the
//! process memory only: one that starts below 0x0F00 governs nothing.

use std::collections::VecDeque;

use edsgen_runtime::ethercat::wire::datagram::{Command, DatagramRepr};

mod logical;

/// Number of FMMUs.
pub const FMMUS: usize = 8;
/// Number of SyncManagers.
pub const SYNC_MANAGERS: usize = 8;
/// The ESC's address space in bytes (registers and process memory).
const MEMORY: usize = 0x1_0000;

pub use edsgen_runtime::ethercat::esc::{reg, Event, SmRegisters};

/// The ESC's memory and SII.
#[derive(Debug, Clone)]
pub struct EmulatedEsc {
    /// The whole 64 KiB: a `u16` address indexes it without a bounds check.
    mem: Box<[u8; MEMORY]>,
    /// The FMMU registers decoded, as the last write to them left them.
    fmmus: [Option<logical::Fmmu>; FMMUS],
    sii: Vec<u8>,
    events: VecDeque<Event>,
}

/// Registers the master cannot change (a write still counts, but leaves them as they are).
fn read_only(address: u16) -> bool {
    matches!(address,
        0x0000..=0x000F | 0x0012..=0x0013 | 0x0110..=0x0111 | 0x0130..=0x0135
        | 0x0140..=0x0141 | 0x0440..=0x0441 | 0x0501 | 0x0900..=0x09FF)
        || ((0x0800..0x0800 + 8 * SYNC_MANAGERS as u16).contains(&address)
            && matches!(address % 8, 5 | 7))
}

impl EmulatedEsc {
    /// An ESC after power-up, loaded from the SII image `sii` (its configured station alias,
    /// word 4).
    pub fn new(sii: Vec<u8>) -> Self {
        let mut esc = EmulatedEsc {
            mem: Box::new([0; MEMORY]),
            fmmus: [None; FMMUS],
            sii,
            events: VecDeque::new(),
        };
        esc.mem[usize::from(reg::FMMU_COUNT)] = FMMUS as u8;
        esc.mem[usize::from(reg::SM_COUNT)] = SYNC_MANAGERS as u8;
        esc.mem[usize::from(reg::RAM_SIZE)] = 60;
        // Ports 0 and 1 MII, 2 and 3 not implemented.
        esc.mem[usize::from(reg::PORT_DESCRIPTOR)] = 0x0F;
        // PDI operational; port 0 link, loop open, communication; ports 1-3 loop closed.
        esc.set_u16(reg::DL_STATUS, 0x5611);
        esc.set_u16(reg::AL_STATUS, 1);
        esc.mem[usize::from(reg::PDI_CONTROL)] = 0x05; // SPI
        esc.set_u16(reg::WATCHDOG_DIVIDER, 0x09C2); // 100 µs
        esc.set_u16(reg::WATCHDOG_TIME_PD, 0x03E8); // 1000 × 100 µs
        esc.set_u16(reg::SII_CONTROL, 0x0040); // 8-byte reads
        let alias = esc.sii_word(4);
        esc.set_u16(reg::STATION_ALIAS, alias);
        esc
    }

    /// Connects port 1 to a next SubDevice (link, loop open, communication) or leaves it
    /// closed, as the last SubDevice of a segment has it (the DL status, 0x0110).
    pub fn connect_port1(&mut self, connected: bool) {
        const LINK: u16 = 1 << 5;
        const LOOP_CLOSED: u16 = 1 << 10;
        const COMMUNICATION: u16 = 1 << 11;
        let status = self.u16(reg::DL_STATUS) & !(LINK | LOOP_CLOSED | COMMUNICATION);
        let port1 = if connected {
            LINK | COMMUNICATION
        } else {
            LOOP_CLOSED
        };
        self.set_u16(reg::DL_STATUS, status | port1);
    }

    /// The SII image.
    pub fn sii(&self) -> &[u8] {
        &self.sii
    }

    /// The SII word at `address` (0xFFFF beyond the image).
    pub fn sii_word(&self, address: u32) -> u16 {
        let at = address as usize * 2;
        match self.sii.get(at..at + 2) {
            Some(b) => u16::from_le_bytes([b[0], b[1]]),
            None => 0xFFFF,
        }
    }

    /// A register (or memory) byte.
    pub fn u8(&self, address: u16) -> u8 {
        self.mem[usize::from(address)]
    }

    /// A little-endian u16 of registers.
    pub fn u16(&self, address: u16) -> u16 {
        let a = usize::from(address);
        u16::from_le_bytes([self.mem[a], self.mem[(a + 1) & 0xFFFF]])
    }

    /// Sets a register byte as the device (PDI) does.
    pub fn set_u8(&mut self, address: u16, value: u8) {
        self.mem[usize::from(address)] = value;
        self.fmmus_written(u32::from(address)..u32::from(address) + 1);
    }

    /// Sets a little-endian u16 of registers as the device (PDI) does.
    pub fn set_u16(&mut self, address: u16, value: u16) {
        let a = usize::from(address);
        let [lo, hi] = value.to_le_bytes();
        self.mem[a] = lo;
        self.mem[(a + 1) & 0xFFFF] = hi;
        self.fmmus_written(u32::from(address)..u32::from(address) + 2);
    }

    /// Memory as the device (PDI) sees it.
    pub fn memory(&self, start: u16, len: usize) -> &[u8] {
        let start = usize::from(start);
        &self.mem[start..(start + len).min(MEMORY)]
    }

    /// Writes memory as the device (PDI) does (no events).
    pub fn write_memory(&mut self, start: u16, data: &[u8]) {
        let start = usize::from(start);
        let end = (start + data.len()).min(MEMORY);
        self.mem[start..end].copy_from_slice(&data[..end - start]);
        self.fmmus_written(start as u32..end as u32);
    }

    /// SyncManager `n`'s registers.
    pub fn sm(&self, n: usize) -> SmRegisters {
        let base = usize::from(reg::sm(n));
        let mut bytes = [0; 8];
        bytes.copy_from_slice(&self.mem[base..base + 8]);
        SmRegisters::from_bytes(bytes)
    }

    /// Sets or clears SyncManager `n`'s mailbox-full flag (status bit 3), as the device does
    /// when it has written an answer or read a request.
    pub fn set_mailbox_full(&mut self, n: usize, full: bool) {
        let at = reg::SM0 + 8 * n as u16 + 5;
        let status = self.u8(at);
        self.set_u8(at, if full { status | 0x08 } else { status & !0x08 });
    }

    /// Deactivates (or reactivates) SyncManager `n` from the device side (PDI control bit 0).
    pub fn set_sm_deactivated(&mut self, n: usize, deactivated: bool) {
        let at = reg::SM0 + 8 * n as u16 + 7;
        let pdi = self.u8(at);
        self.set_u8(at, if deactivated { pdi | 1 } else { pdi & !1 });
    }

    /// The station address the datagram's ADP must name for a configured-address command.
    fn fixed_match(&self, adp: u16) -> bool {
        adp == self.u16(reg::STATION_ADDRESS)
            || (self.u8(reg::DL_CONTROL + 3) & 1 != 0 && adp == self.u16(reg::STATION_ALIAS))
    }

    /// Processes one datagram: `data` is its data in the frame, changed as the command says.
    /// Returns what the working counter gains and the ADP to write back (auto-increment
    /// commands count it up). A command code that is not EtherCAT's gains nothing.
    pub fn datagram(&mut self, header: &DatagramRepr, data: &mut [u8]) -> (u16, u16) {
        let Some(command) = Command::from_code(header.command) else {
            return (0, header.adp);
        };
        use Command::*;
        let address = header.ado;
        let positional = header.adp == 0;
        let next_adp = header.adp.wrapping_add(1);
        match command {
            Nop => (0, header.adp),
            Aprd | Apwr | Aprw if !positional => (0, next_adp),
            Aprd => (self.physical(address, data, true, false), next_adp),
            Apwr => (self.physical(address, data, false, true), next_adp),
            Aprw => (self.physical(address, data, true, true), next_adp),
            Fprd | Fpwr | Fprw if !self.fixed_match(header.adp) => (0, header.adp),
            Fprd => (self.physical(address, data, true, false), header.adp),
            Fpwr => (self.physical(address, data, false, true), header.adp),
            Fprw => (self.physical(address, data, true, true), header.adp),
            Brd => (self.broadcast_read(address, data), next_adp),
            Bwr => (self.physical(address, data, false, true), next_adp),
            Brw => {
                let incoming = data.to_vec();
                let read = self.broadcast_read(address, data);
                let wrote = self.physical(address, &mut incoming.clone(), false, true);
                (read + 2 * wrote, next_adp)
            }
            Lrd => (
                self.logical(header.logical_address(), data, true, false),
                header.adp,
            ),
            Lwr => (
                self.logical(header.logical_address(), data, false, true),
                header.adp,
            ),
            Lrw => (
                self.logical(header.logical_address(), data, true, true),
                header.adp,
            ),
            Armw if positional => (self.physical(address, data, true, false), next_adp),
            Armw => (self.physical(address, data, false, true), next_adp),
            Frmw if self.fixed_match(header.adp) => {
                (self.physical(address, data, true, false), header.adp)
            }
            Frmw => (self.physical(address, data, false, true), header.adp),
        }
    }

    /// A BRD: the memory ORed into the data, +1 (nothing if refused, as [`physical`] refuses).
    ///
    /// [`physical`]: Self::physical
    fn broadcast_read(&mut self, address: u16, data: &mut [u8]) -> u16 {
        let start = u32::from(address);
        let end = start + data.len() as u32;
        if end > 0x1_0000 || !self.mailbox_allows(start..end, true, false) {
            return 0;
        }
        for (d, m) in data.iter_mut().zip(&self.mem[start as usize..end as usize]) {
            *d |= m;
        }
        self.after_read(start..end);
        1
    }

    /// A physical access at `address`: a read puts memory into `data` (+1), a write puts
    /// `data` (as it came, before any read) into memory (+1; +2 when both). Nothing happens and
    /// nothing counts when the range runs past the memory or touches a mailbox in the wrong
    /// state.
    fn physical(&mut self, address: u16, data: &mut [u8], read: bool, write: bool) -> u16 {
        let start = u32::from(address);
        let end = start + data.len() as u32;
        if end > 0x1_0000 {
            return 0;
        }
        if !self.mailbox_allows(start..end, read, write) {
            return 0;
        }
        let incoming = if read && write {
            Some(data.to_vec())
        } else {
            None
        };
        let mut wkc = 0;
        if read {
            data.copy_from_slice(&self.mem[start as usize..end as usize]);
            self.after_read(start..end);
            wkc += 1;
        }
        if write {
            let source = incoming.as_deref().unwrap_or(data);
            self.write_bytes(start, source);
            self.after_write(start..end);
            wkc += if read { 2 } else { 1 };
        }
        wkc
    }

    /// Writes bytes from the master, skipping read-only registers.
    fn write_bytes(&mut self, start: u32, data: &[u8]) {
        for (offset, &byte) in data.iter().enumerate() {
            let address = start + offset as u32;
            if address >= 0x1000 || !read_only(address as u16) {
                self.mem[address as usize] = byte;
            }
        }
        self.fmmus_written(start..start + data.len() as u32);
    }

    /// Whether an access to `range` respects the mailboxes it touches: a master-written
    /// mailbox takes writes only while empty and is never read, the other is read only while
    /// full and never written.
    fn mailbox_allows(&self, range: std::ops::Range<u32>, read: bool, write: bool) -> bool {
        (0..SYNC_MANAGERS).all(|n| {
            let sm = self.sm(n);
            if !sm.enabled() || !sm.is_mailbox() || !governs(&sm) || !overlaps(&sm.range(), &range)
            {
                return true;
            }
            let full = sm.status & 0x08 != 0;
            if sm.master_writes() {
                // Never read; written only while empty.
                !read && (!write || !full)
            } else {
                // Never written; read only while full.
                !write && (!read || full)
            }
        })
    }

    /// What a read of `range` does: a device-to-master mailbox whose last byte is read is empty.
    fn after_read(&mut self, range: std::ops::Range<u32>) {
        for n in 0..SYNC_MANAGERS {
            let sm = self.sm(n);
            if sm.enabled() && governs(&sm) && sm.is_mailbox() && !sm.master_writes() {
                let last = sm.range().end - 1;
                if range.contains(&last) {
                    self.set_mailbox_full(n, false);
                    self.events.push_back(Event::MailboxRead(n));
                }
            }
        }
    }

    /// What a write of `range` does: AL control, the SII command, the SyncManagers' activation
    /// (disabling one empties its mailbox; a repeat toggle is reported) and the last byte of a
    /// master-written SyncManager.
    fn after_write(&mut self, range: std::ops::Range<u32>) {
        if overlaps(&range, &(0x0120..0x0122)) {
            self.events.push_back(Event::AlControl);
        }
        if overlaps(&range, &(0x0502..0x0504)) {
            self.sii_command(false);
        }
        if overlaps(&range, &(0x0500..0x0501)) {
            self.sii_access_follows_offer();
        }
        for n in 0..SYNC_MANAGERS {
            let base = u32::from(reg::SM0) + 8 * n as u32;
            let sm = self.sm(n);
            if overlaps(&range, &(base..base + 7)) {
                if sm.activate & 1 == 0 {
                    self.set_mailbox_full(n, false);
                }
                if sm.is_mailbox() && (sm.activate ^ sm.pdi_control) & 0x02 != 0 {
                    self.events.push_back(Event::RepeatRequest(n));
                }
            }
            if sm.enabled()
                && governs(&sm)
                && sm.master_writes()
                && range.contains(&(sm.range().end - 1))
            {
                if sm.is_mailbox() {
                    self.set_mailbox_full(n, true);
                    self.events.push_back(Event::MailboxWritten(n));
                } else {
                    self.events.push_back(Event::BufferWritten(n));
                }
            }
        }
    }

    /// Acknowledges a repeat request of SyncManager `n` (PDI control bit 1 follows activate
    /// bit 1).
    pub fn acknowledge_repeat(&mut self, n: usize) {
        let sm = self.sm(n);
        let at = reg::SM0 + 8 * n as u16 + 7;
        self.set_u8(at, (sm.pdi_control & !0x02) | (sm.activate & 0x02));
    }

    /// The PDI holds the SII only while the master offers it (0x0500 bit 0, without bit 1
    /// "force ECAT access").
    fn sii_access_follows_offer(&mut self) {
        if self.u8(reg::SII_CONFIG) & 0x03 != 0x01 {
            let access = self.u8(reg::SII_PDI_ACCESS);
            self.set_u8(reg::SII_PDI_ACCESS, access & !1);
        }
    }

    /// Runs the SII command written to 0x0502 (bits 8–10: 1 read, 2 write, 4 reload) by the
    /// master (`by_pdi` false) or the device, if it is the one holding the SII (0x0501 bit 0).
    fn sii_command(&mut self, by_pdi: bool) {
        let control = self.u16(reg::SII_CONTROL);
        let write_enable = control & 1;
        let mut status = 0x0040 | write_enable;
        if (self.u8(reg::SII_PDI_ACCESS) & 1 != 0) == by_pdi {
            let address = u32::from(self.u16(reg::SII_ADDRESS))
                | (u32::from(self.u16(reg::SII_ADDRESS + 2)) << 16);
            match (control >> 8) & 0x07 {
                0 | 4 => {}
                1 => {
                    for word in 0..4u32 {
                        let value = self.sii_word(address.wrapping_add(word));
                        self.set_u16(reg::SII_DATA + 2 * word as u16, value);
                    }
                }
                2 if write_enable == 0 => status |= 0x4000,
                2 => {
                    let value = self.u16(reg::SII_DATA);
                    let at = address as usize * 2;
                    if let Some(bytes) = self.sii.get_mut(at..at + 2) {
                        bytes.copy_from_slice(&value.to_le_bytes());
                    } else {
                        status |= 0x2000;
                    }
                }
                _ => status |= 0x2000,
            }
        }
        self.set_u16(reg::SII_CONTROL, status);
    }
}

/// Whether two ranges share a value.
fn overlaps(a: &std::ops::Range<u32>, b: &std::ops::Range<u32>) -> bool {
    a.start < b.end && b.start < a.end
}

/// The PDI: what the device's firmware reads and writes, with an ESC's side effects on the
/// mailboxes (see [`Esc`](edsgen_runtime::ethercat::esc::Esc)).
impl edsgen_runtime::ethercat::esc::Esc for EmulatedEsc {
    fn read(&mut self, address: u16, buf: &mut [u8]) {
        let start = usize::from(address);
        let end = (start + buf.len()).min(MEMORY);
        buf[..end - start].copy_from_slice(&self.mem[start..end]);
        // Only a SyncManager's buffer (process memory) empties a mailbox: a register read
        // changes nothing.
        if end <= usize::from(reg::SYNC_MANAGED) {
            return;
        }
        for n in 0..SYNC_MANAGERS {
            let sm = EmulatedEsc::sm(self, n);
            if sm.is_mailbox() && sm.master_writes() && covers_last_byte(&sm, start, end) {
                self.set_mailbox_full(n, false);
            }
        }
    }

    fn write(&mut self, address: u16, data: &[u8]) {
        self.write_memory(address, data);
        let start = usize::from(address);
        let end = (start + data.len()).min(MEMORY);
        let touches = |register: u16| (start..end).contains(&usize::from(register));
        if touches(reg::SII_PDI_ACCESS) {
            self.sii_access_follows_offer();
        }
        if touches(reg::SII_CONTROL) || touches(reg::SII_CONTROL + 1) {
            self.sii_command(true);
        }
        // The mailboxes change with their buffers (process memory) and the SyncManagers' PDI
        // control registers only.
        let sm_registers = usize::from(reg::SM0)..usize::from(reg::sm(SYNC_MANAGERS));
        if end <= sm_registers.start
            || (sm_registers.end <= start && end <= usize::from(reg::SYNC_MANAGED))
        {
            return;
        }
        for n in 0..SYNC_MANAGERS {
            let sm = EmulatedEsc::sm(self, n);
            if !sm.is_mailbox() {
                continue;
            }
            if !sm.master_writes() && covers_last_byte(&sm, start, end) {
                self.set_mailbox_full(n, true);
            }
            let pdi_control = usize::from(reg::sm_pdi_control(n));
            if (start..end).contains(&pdi_control) && sm.pdi_control & 1 != 0 {
                self.set_mailbox_full(n, false);
            }
        }
    }

    fn poll_event(&mut self) -> Option<Event> {
        self.events.pop_front()
    }

    // Registers (below 0x0F00) have no side effects when the PDI reads them: a load, as the
    // core reads them on every frame. Process memory goes through `read`.

    fn read_u8(&mut self, address: u16) -> u8 {
        if address >= reg::SYNC_MANAGED {
            let mut b = [0];
            self.read(address, &mut b);
            return b[0];
        }
        EmulatedEsc::u8(self, address)
    }

    fn read_u16(&mut self, address: u16) -> u16 {
        if address >= reg::SYNC_MANAGED - 1 {
            let mut b = [0; 2];
            self.read(address, &mut b);
            return u16::from_le_bytes(b);
        }
        EmulatedEsc::u16(self, address)
    }

    fn sm(&mut self, n: usize) -> SmRegisters {
        EmulatedEsc::sm(self, n)
    }
}

/// Whether the SyncManager governs memory: it has a length and starts at the digital I/O
/// registers or in the process memory ([`reg::SYNC_MANAGED`]; one configured over the other
/// registers would lock the master out of its own configuration).
fn governs(sm: &SmRegisters) -> bool {
    sm.len > 0 && sm.start >= reg::SYNC_MANAGED
}

/// Whether bytes `start..end` hold the last byte of the SyncManager's buffer.
fn covers_last_byte(sm: &SmRegisters, start: usize, end: usize) -> bool {
    let last = usize::from(sm.start) + usize::from(sm.len);
    governs(sm) && start < last && last <= end
}
