//! The EtherCAT SubDevice core over an ESC that is only memory and an event queue, as a chip's
//! PDI presents it: AL state requests checked against the mailbox SyncManagers (refused with AL
//! status code 0016h, then taken), a mailbox request answered into the device-to-master mailbox
//! (which the write fills), and the repeat request answered with the same answer.

use std::collections::VecDeque;

use edsgen_runtime::ethercat::al::AlState;
use edsgen_runtime::ethercat::esc::{reg, Esc, Event};
use edsgen_runtime::ethercat::subdevice::{Application, Layout, SubDevice};
use edsgen_runtime::Instant;

/// Registers and memory up to 0x1100, and what the "master" did.
struct MemoryEsc {
    mem: Vec<u8>,
    events: VecDeque<Event>,
}

impl Esc for MemoryEsc {
    fn read(&mut self, address: u16, buf: &mut [u8]) {
        let at = usize::from(address);
        buf.copy_from_slice(&self.mem[at..at + buf.len()]);
    }
    fn write(&mut self, address: u16, data: &[u8]) {
        let at = usize::from(address);
        self.mem[at..at + data.len()].copy_from_slice(data);
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
        events: VecDeque::new(),
    };
    let layout = Layout {
        mailbox_out: Some((0, 0x1000, 64)),
        mailbox_in: Some((1, 0x1080, 64)),
        outputs: None,
        inputs: None,
    };
    SubDevice::new(esc, layout, Echo)
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
    assert_eq!(al_status(&mut d), (0x11, 0x0016), "no mailbox SyncManagers");
    assert_eq!(d.state(), AlState::Init);

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
