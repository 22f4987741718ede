//! An [`Esc`] for a Microchip LAN9252 on SPI, as its datasheet describes the host interface:
//! 32-bit system registers written with the SPI command 02h and read with 0Bh (one dummy byte);
//! the EtherCAT core's registers (below 1000h) reached indirectly through the CSR data and
//! command registers (300h, 304h: busy in bit 31, read in bit 30, size in bits 16-18), the
//! process RAM through the PRAM read and write FIFOs (000h and 020h, address and length at
//! 308h/310h, command at 30Ch/314h: busy in bit 31, abort in bit 30, available in bit 0, the
//! words the FIFO holds in bits 8-12). What the master did is read from the AL event request
//! register (220h) and the SyncManagers' registers.
//!
//! It builds and is not tested against a chip: the SPI is the [`Spi`] trait, which a HAL's SPI
//! device implements in a few lines.

use edsgen_runtime::ethercat::esc::{reg, Esc, Event, SmRegisters};

/// One SPI transaction with the chip selected: `write`'s bytes out, then `read.len()` bytes in.
pub trait Spi {
    /// Runs one transaction.
    fn transfer(&mut self, write: &[u8], read: &mut [u8]);
}

const CMD_SERIAL_WRITE: u8 = 0x02;
const CMD_FAST_READ: u8 = 0x0B;
const CMD_FAST_READ_DUMMY: u8 = 0x01;

const PRAM_READ_FIFO: u16 = 0x000;
const PRAM_WRITE_FIFO: u16 = 0x020;
const PRAM_READ_ADDRESS_LENGTH: u16 = 0x308;
const PRAM_READ_COMMAND: u16 = 0x30C;
const PRAM_WRITE_ADDRESS_LENGTH: u16 = 0x310;
const PRAM_WRITE_COMMAND: u16 = 0x314;
const PRAM_BUSY: u32 = 1 << 31;
const PRAM_ABORT: u32 = 1 << 30;
const PRAM_AVAILABLE: u32 = 1;

const CSR_DATA: u16 = 0x300;
const CSR_COMMAND: u16 = 0x304;
const CSR_BUSY: u32 = 1 << 31;
const CSR_READ: u32 = (1 << 31) | (1 << 30);
const CSR_WRITE: u32 = 1 << 31;

/// Where the process RAM starts.
const PRAM_START: u16 = 0x1000;

/// A LAN9252 on `S`.
pub struct Lan9252<S> {
    spi: S,
    /// AL event request bits read and not yet reported.
    pending: u32,
}

impl<S: Spi> Lan9252<S> {
    /// The chip on `spi`.
    pub const fn new(spi: S) -> Self {
        Lan9252 { spi, pending: 0 }
    }

    fn write_32(&mut self, address: u16, value: u32) {
        let [a1, a0] = address.to_be_bytes();
        let [v0, v1, v2, v3] = value.to_le_bytes();
        self.spi
            .transfer(&[CMD_SERIAL_WRITE, a1, a0, v0, v1, v2, v3], &mut []);
    }

    fn read_32(&mut self, address: u16) -> u32 {
        let [a1, a0] = address.to_be_bytes();
        let mut value = [0u8; 4];
        self.spi
            .transfer(&[CMD_FAST_READ, a1, a0, CMD_FAST_READ_DUMMY], &mut value);
        u32::from_le_bytes(value)
    }

    /// Waits while `command`'s register says `busy`.
    fn wait_while(&mut self, command: u16, busy: u32) -> u32 {
        loop {
            let value = self.read_32(command);
            if value & busy == 0 {
                return value;
            }
        }
    }

    /// Reads into `buf` (`Some`) or writes `data` from `address` on: the core's registers
    /// through the CSR registers, 1, 2 or 4 bytes at a time as the address's alignment allows;
    /// the process RAM through the FIFO: whole words, the first one's bytes starting at the
    /// address's place in its word.
    fn access(&mut self, address: u16, mut buf: Option<&mut [u8]>, data: &[u8]) {
        let len = buf.as_deref().map_or(data.len(), <[u8]>::len);
        let reading = buf.is_some();
        let pram = address >= PRAM_START;
        if pram {
            let (command, address_length) = if reading {
                (PRAM_READ_COMMAND, PRAM_READ_ADDRESS_LENGTH)
            } else {
                (PRAM_WRITE_COMMAND, PRAM_WRITE_ADDRESS_LENGTH)
            };
            self.write_32(command, PRAM_ABORT);
            self.wait_while(command, PRAM_BUSY);
            self.write_32(address_length, ((len as u32) << 16) | u32::from(address));
            self.write_32(command, PRAM_BUSY);
            while self.read_32(command) & PRAM_AVAILABLE == 0 {}
        }
        let mut at = address;
        let mut done = 0;
        while done < len {
            let remaining = len - done;
            let (lane, size) = if pram {
                let lane = if done == 0 {
                    usize::from(address) % 4
                } else {
                    0
                };
                (lane, (4 - lane).min(remaining))
            } else {
                let size = if remaining >= 4 && at.is_multiple_of(4) {
                    4
                } else if remaining >= 2 && at.is_multiple_of(2) {
                    2
                } else {
                    1
                };
                (0, size)
            };
            let size_field = ((size as u32) << 16) | u32::from(at);
            if let Some(buf) = buf.as_deref_mut() {
                let word = if pram {
                    self.read_32(PRAM_READ_FIFO)
                } else {
                    self.write_32(CSR_COMMAND, CSR_READ | size_field);
                    self.wait_while(CSR_COMMAND, CSR_BUSY);
                    self.read_32(CSR_DATA)
                };
                buf[done..done + size].copy_from_slice(&word.to_le_bytes()[lane..lane + size]);
            } else {
                let mut word = [0u8; 4];
                word[lane..lane + size].copy_from_slice(&data[done..done + size]);
                let word = u32::from_le_bytes(word);
                if pram {
                    self.write_32(PRAM_WRITE_FIFO, word);
                } else {
                    self.write_32(CSR_DATA, word);
                    self.write_32(CSR_COMMAND, CSR_WRITE | size_field);
                    self.wait_while(CSR_COMMAND, CSR_BUSY);
                }
            }
            done += size;
            at = at.wrapping_add(size as u16);
        }
    }

    /// What the event of SyncManager `n` says, from its registers (reading its status clears
    /// the event).
    fn sm_event(sm: &SmRegisters, n: usize) -> Option<Event> {
        let full = sm.status & 0x08 != 0;
        match (sm.is_mailbox(), sm.master_writes()) {
            (true, true) if full => Some(Event::MailboxWritten(n)),
            (true, false) if !full => Some(Event::MailboxRead(n)),
            (false, true) => Some(Event::BufferWritten(n)),
            _ => None,
        }
    }
}

impl<S: Spi> Esc for Lan9252<S> {
    fn read(&mut self, address: u16, buf: &mut [u8]) {
        self.access(address, Some(buf), &[]);
    }

    fn write(&mut self, address: u16, data: &[u8]) {
        self.access(address, None, data);
    }

    fn poll_event(&mut self) -> Option<Event> {
        if self.pending == 0 {
            let mut request = [0u8; 4];
            self.read(reg::AL_EVENT, &mut request);
            // AL control and the events of SyncManagers 0 to 7.
            self.pending = u32::from_le_bytes(request) & 0x0000_FF01;
        }
        // The lowest bit first: AL control (bit 0), then SyncManagers 0 to 7 (bits 8 to 15).
        while self.pending != 0 {
            let bit = self.pending.trailing_zeros();
            self.pending &= self.pending - 1;
            if bit == 0 {
                return Some(Event::AlControl);
            }
            let n = (bit - 8) as usize;
            let sm = self.sm(n);
            // A repeat request: the activate register's toggle differs from the acknowledge.
            if sm.is_mailbox() && (sm.activate ^ sm.pdi_control) & 0x02 != 0 {
                return Some(Event::RepeatRequest(n));
            }
            if let Some(event) = Self::sm_event(&sm, n) {
                return Some(event);
            }
        }
        None
    }
}
