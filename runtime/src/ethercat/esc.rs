//! The EtherCAT SubDevice Controller (ESC) as the device's firmware reaches it through its
//! process data interface (PDI): registers and process memory read and written by address, as
//! SOES's `ESC_read`/`ESC_write` and KickCAT's `AbstractESC` do ([`Esc`]), the register map
//! ([`reg`]), a SyncManager's registers ([`SmRegisters`]) and what the master did that the
//! device answers ([`Event`]). An emulated ESC (the simulator's) and a chip on SPI both
//! implement [`Esc`]; the SubDevice's core needs nothing else.
//!
//! PDI semantics the core relies on, as ESCs have them (ETG.1000.4, the ET1100 and LAN9252
//! datasheets): reading the last byte of a full master-to-device mailbox empties it; writing
//! the last byte of a device-to-master mailbox fills it; setting bit 0 of a SyncManager's PDI
//! control (0x0807 + 8n) deactivates and resets it.

/// Register addresses.
pub mod reg {
    /// ESC type (u8).
    pub const TYPE: u16 = 0x0000;
    /// FMMUs supported (u8).
    pub const FMMU_COUNT: u16 = 0x0004;
    /// SyncManagers supported (u8).
    pub const SM_COUNT: u16 = 0x0005;
    /// RAM size in KiB (u8).
    pub const RAM_SIZE: u16 = 0x0006;
    /// Port descriptor (u8).
    pub const PORT_DESCRIPTOR: u16 = 0x0007;
    /// ESC features supported (u16).
    pub const FEATURES: u16 = 0x0008;
    /// Configured station address (u16).
    pub const STATION_ADDRESS: u16 = 0x0010;
    /// Configured station alias (u16).
    pub const STATION_ALIAS: u16 = 0x0012;
    /// DL control (u32); bit 24 enables the alias.
    pub const DL_CONTROL: u16 = 0x0100;
    /// DL status (u16).
    pub const DL_STATUS: u16 = 0x0110;
    /// AL control (u16).
    pub const AL_CONTROL: u16 = 0x0120;
    /// AL status (u16).
    pub const AL_STATUS: u16 = 0x0130;
    /// AL status code (u16).
    pub const AL_STATUS_CODE: u16 = 0x0134;
    /// PDI control (u8).
    pub const PDI_CONTROL: u16 = 0x0140;
    /// Watchdog divider (u16).
    pub const WATCHDOG_DIVIDER: u16 = 0x0400;
    /// Process-data watchdog time (u16).
    pub const WATCHDOG_TIME_PD: u16 = 0x0420;
    /// Process-data watchdog status (u16).
    pub const WATCHDOG_STATUS_PD: u16 = 0x0440;
    /// SII configuration (u8): bit 0 offers the SII to the PDI.
    pub const SII_CONFIG: u16 = 0x0500;
    /// SII PDI access state (u8).
    pub const SII_PDI_ACCESS: u16 = 0x0501;
    /// SII control/status (u16).
    pub const SII_CONTROL: u16 = 0x0502;
    /// SII word address (u32).
    pub const SII_ADDRESS: u16 = 0x0504;
    /// SII data (8 bytes).
    pub const SII_DATA: u16 = 0x0508;
    /// The lowest address a SyncManager governs: the digital I/O registers (0x0F00, where
    /// simple I/O devices put their outputs) and the process memory (0x1000); below them the
    /// registers are never buffered.
    pub const SYNC_MANAGED: u16 = 0x0F00;
    /// FMMU 0 (16 bytes each).
    pub const FMMU0: u16 = 0x0600;
    /// SyncManager 0 (8 bytes each).
    pub const SM0: u16 = 0x0800;
    /// AL event request (u32): bit 0 AL control written, bit 8 + n SyncManager n.
    pub const AL_EVENT: u16 = 0x0220;

    /// SyncManager `n`'s first register.
    pub const fn sm(n: usize) -> u16 {
        SM0 + 8 * n as u16
    }

    /// SyncManager `n`'s PDI control register (bit 0 deactivate, bit 1 repeat acknowledge).
    pub const fn sm_pdi_control(n: usize) -> u16 {
        sm(n) + 7
    }
}

/// What the ESC tells the device's application, in the order it happened.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Event {
    /// AL control was written.
    AlControl,
    /// The master filled the mailbox SyncManager `n` (master to device).
    MailboxWritten(usize),
    /// The master emptied the mailbox SyncManager `n` (device to master).
    MailboxRead(usize),
    /// The master toggled the repeat request of SyncManager `n`.
    RepeatRequest(usize),
    /// The master wrote the last byte of the buffered SyncManager `n` (outputs).
    BufferWritten(usize),
}

/// One SyncManager's registers, decoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SmRegisters {
    /// Physical start address.
    pub start: u16,
    /// Length in bytes.
    pub len: u16,
    /// Control byte (mode in bits 0–1, direction in bits 2–3, watchdog in bit 6).
    pub control: u8,
    /// Status byte (bit 3: mailbox full).
    pub status: u8,
    /// Activate byte (bit 0 enable, bit 1 repeat request).
    pub activate: u8,
    /// PDI control byte (bit 0 deactivated by the device, bit 1 repeat acknowledge).
    pub pdi_control: u8,
}

impl SmRegisters {
    /// The registers from their 8 bytes.
    pub fn from_bytes(b: [u8; 8]) -> Self {
        SmRegisters {
            start: u16::from_le_bytes([b[0], b[1]]),
            len: u16::from_le_bytes([b[2], b[3]]),
            control: b[4],
            status: b[5],
            activate: b[6],
            pdi_control: b[7],
        }
    }

    /// Enabled by the master and not deactivated by the device.
    pub fn enabled(&self) -> bool {
        self.activate & 1 != 0 && self.pdi_control & 1 == 0 && self.len > 0
    }
    /// Mailbox mode (control bits 0–1 = 10b).
    pub fn is_mailbox(&self) -> bool {
        self.control & 0x03 == 0x02
    }
    /// Written by the master (control bits 2–3 = 01b).
    pub fn master_writes(&self) -> bool {
        self.control & 0x0C == 0x04
    }
    /// The bytes it covers.
    pub fn range(&self) -> core::ops::Range<u32> {
        u32::from(self.start)..u32::from(self.start) + u32::from(self.len)
    }
}

/// An ESC as its PDI reaches it.
pub trait Esc {
    /// Reads `buf.len()` bytes of registers or process memory from `address`.
    fn read(&mut self, address: u16, buf: &mut [u8]);

    /// Writes `data` to registers or process memory at `address`.
    fn write(&mut self, address: u16, data: &[u8]);

    /// The next thing the master did that the device answers, in the order it happened (a
    /// chip's AL event request register, 0x0220, and the SyncManagers' status say it).
    fn poll_event(&mut self) -> Option<Event>;

    /// A register byte.
    fn read_u8(&mut self, address: u16) -> u8 {
        let mut b = [0u8];
        self.read(address, &mut b);
        b[0]
    }

    /// A little-endian u16 of registers.
    fn read_u16(&mut self, address: u16) -> u16 {
        let mut b = [0u8; 2];
        self.read(address, &mut b);
        u16::from_le_bytes(b)
    }

    /// Writes a register byte.
    fn write_u8(&mut self, address: u16, value: u8) {
        self.write(address, &[value]);
    }

    /// Writes a little-endian u16 of registers.
    fn write_u16(&mut self, address: u16, value: u16) {
        self.write(address, &value.to_le_bytes());
    }

    /// SyncManager `n`'s registers.
    fn sm(&mut self, n: usize) -> SmRegisters {
        let mut b = [0u8; 8];
        self.read(reg::sm(n), &mut b);
        SmRegisters::from_bytes(b)
    }
}
