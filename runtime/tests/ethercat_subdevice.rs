//! The EtherCAT SubDevice core over an ESC that is only memory, an SII behind the EEPROM
//! interface and an event queue, as a chip's PDI presents it: the layout and identity read from
//! the SII only once the master offers it (0050h before), AL state requests checked against the
//! mailbox SyncManagers (refused with AL status code 0016h, then taken), a mailbox request
//! answered into the device-to-master mailbox (which the write fills), and the repeat request
//! answered with the same answer.

use std::collections::VecDeque;

use edsgen_runtime::ethercat::al::AlState;
use edsgen_runtime::ethercat::esc::{reg, Esc, Event};
use edsgen_runtime::ethercat::subdevice::{Application, Layout, SubDevice};
use edsgen_runtime::ethercat::Identity;
use edsgen_runtime::Instant;

/// Registers and memory up to 0x1100, the SII, and what the "master" did.
struct MemoryEsc {
    mem: Vec<u8>,
    sii: Vec<u8>,
    events: VecDeque<Event>,
}

/// An SII: identity 0x0000_04D8 / 0x0000_9252 / 3, then the SyncM category (41, 16 words):
/// SM0 mailbox out at 0x1000 and SM1 mailbox in at 0x1080, 64 bytes each; then the end.
fn sii() -> Vec<u8> {
    let mut sii = vec![0u8; 0x80];
    sii[0x10..0x1C].copy_from_slice(&[0xD8, 4, 0, 0, 0x52, 0x92, 0, 0, 3, 0, 0, 0]);
    sii.extend_from_slice(&[41, 0, 8, 0]);
    sii.extend_from_slice(&[0x00, 0x10, 64, 0, 0x26, 0, 1, 1]);
    sii.extend_from_slice(&[0x80, 0x10, 64, 0, 0x22, 0, 1, 2]);
    sii.extend_from_slice(&[0xFF, 0xFF]);
    sii
}

impl Esc for MemoryEsc {
    fn read(&mut self, address: u16, buf: &mut [u8]) {
        let at = usize::from(address);
        buf.copy_from_slice(&self.mem[at..at + buf.len()]);
    }
    fn write(&mut self, address: u16, data: &[u8]) {
        let at = usize::from(address);
        self.mem[at..at + data.len()].copy_from_slice(data);
        // The PDI takes the SII only when offered; a read command fills 0x0508 with 8 bytes.
        if at == usize::from(reg::SII_PDI_ACCESS) && self.mem[0x0500] & 1 == 0 {
            self.mem[0x0501] = 0;
        }
        if at == usize::from(reg::SII_CONTROL) && self.mem[0x0501] & 1 != 0 {
            let word = u32::from_le_bytes([
                self.mem[0x0504],
                self.mem[0x0505],
                self.mem[0x0506],
                self.mem[0x0507],
            ]) as usize;
            for i in 0..8 {
                self.mem[0x0508 + i] = self.sii.get(2 * word + i).copied().unwrap_or(0xFF);
            }
            self.mem[0x0502] = 0x40;
            self.mem[0x0503] = 0;
        }
        // Writing the last byte of SM1's buffer (0x1080, 64 bytes) fills the mailbox.
        if at + data.len() == 0x10C0 {
            self.mem[usize::from(reg::sm(1)) + 5] |= 0x08;
        }
    }
    fn poll_event(&mut self) -> Option<Event> {
        self.events.pop_front()
    }
}

impl MemoryEsc {
    /// The master writes `data` at `address` and the ESC reports `event`.
    fn master_writes(&mut self, address: u16, data: &[u8], event: Event) {
        let at = usize::from(address);
        self.mem[at..at + data.len()].copy_from_slice(data);
        self.events.push_back(event);
    }
}

/// Answers a mailbox message with its first 4 bytes reversed.
struct Echo;

impl Application for Echo {
    fn mailbox(&mut self, _: AlState, request: &[u8], answer: &mut [u8]) -> usize {
        for (a, r) in answer.iter_mut().zip(request[..4].iter().rev()) {
            *a = *r;
        }
        4
    }
    fn image_sizes(&self) -> (usize, usize) {
        (0, 0)
    }
    fn outputs(&mut self, _: Instant, _: &[u8]) {}
    fn inputs(&mut self, _: Instant, _: &mut [u8]) {}
}

fn device() -> SubDevice<MemoryEsc, Echo, 64> {
    let esc = MemoryEsc {
        mem: vec![0; 0x1100],
        sii: sii(),
        events: VecDeque::new(),
    };
    SubDevice::new(esc, Echo)
}

fn al_status(device: &mut SubDevice<MemoryEsc, Echo, 64>) -> (u16, u16) {
    let esc = device.esc_mut();
    (
        esc.read_u16(reg::AL_STATUS),
        esc.read_u16(reg::AL_STATUS_CODE),
    )
}

/// SyncManager registers: start, length, control, status 0, activate, PDI control 0.
fn sm(start: u16, len: u16, control: u8) -> [u8; 8] {
    let [s0, s1] = start.to_le_bytes();
    let [l0, l1] = len.to_le_bytes();
    [s0, s1, l0, l1, control, 0, 1, 0]
}

#[test]
fn preop_needs_the_mailboxes_and_a_request_is_answered_and_repeated() {
    let mut d = device();
    let now = Instant::from_micros(0);
    d.esc_mut()
        .master_writes(reg::AL_CONTROL, &[2, 0], Event::AlControl);
    d.poll(now);
    assert_eq!(al_status(&mut d), (0x11, 0x0050), "the SII not offered");
    assert_eq!(d.identity(), None);

    // The master offers the SII (0x0500 bit 0): the core reads it, and gives it back.
    d.esc_mut().mem[0x0500] = 1;
    d.esc_mut()
        .master_writes(reg::AL_CONTROL, &[0x12, 0], Event::AlControl);
    d.poll(now);
    assert_eq!(al_status(&mut d), (0x11, 0x0016), "no mailbox SyncManagers");
    assert_eq!(d.state(), AlState::Init);
    assert_eq!(
        d.identity(),
        Some(Identity {
            vendor_id: 0x04D8,
            product_code: 0x9252,
            revision: 3
        })
    );
    assert_eq!(
        *d.layout(),
        Layout {
            mailbox_out: Some((0, 0x1000, 64)),
            mailbox_in: Some((1, 0x1080, 64)),
            outputs: None,
            inputs: None,
        }
    );
    assert_eq!(d.esc_mut().read_u8(reg::SII_PDI_ACCESS), 0, "given back");
    // Taken back by the master: the SII read before stands.
    d.esc_mut().mem[0x0500] = 0;

    d.esc_mut()
        .master_writes(reg::sm(0), &sm(0x1000, 64, 0x26), Event::AlControl);
    d.esc_mut()
        .master_writes(reg::sm(1), &sm(0x1080, 64, 0x22), Event::AlControl);
    d.esc_mut()
        .master_writes(reg::AL_CONTROL, &[0x12, 0], Event::AlControl);
    d.poll(now);
    assert_eq!(al_status(&mut d), (0x02, 0));
    assert_eq!(d.state(), AlState::PreOp);

    d.esc_mut()
        .master_writes(0x1000, &[1, 2, 3, 4], Event::MailboxWritten(0));
    d.poll(now);
    let mut answer = [0u8; 6];
    d.esc_mut().read(0x1080, &mut answer);
    assert_eq!(answer, [4, 3, 2, 1, 0, 0]);
    assert_eq!(
        d.esc_mut().sm(1).status & 0x08,
        0x08,
        "the answer fills SM1"
    );

    // The master lost it: the repeat request (activate bit 1) gets the same answer and the
    // acknowledge (PDI control bit 1).
    let esc = d.esc_mut();
    esc.mem[0x1080..0x1084].fill(0);
    esc.mem[usize::from(reg::sm(1)) + 5] &= !0x08;
    esc.master_writes(reg::sm(1) + 6, &[0x03], Event::RepeatRequest(1));
    d.poll(now);
    let mut again = [0u8; 4];
    d.esc_mut().read(0x1080, &mut again);
    assert_eq!(again, [4, 3, 2, 1]);
    assert_eq!(d.esc_mut().read_u8(reg::sm_pdi_control(1)) & 0x02, 0x02);
}
