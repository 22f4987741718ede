//! One EtherCAT SubDevice, sans-IO: Ethernet frames and the time in, the same frames out with
//! every datagram processed by the [`Esc`], and between datagrams what a device's firmware does
//! behind its ESC: the AL state machine (requested transitions checked against the mailbox and
//! process-data SyncManagers the [`Layout`] expects, refusals with their AL status codes, the
//! error acknowledgement), the mailbox queue with the repeat request, the process data handed to
//! and taken from the [`Application`] in Safe-Op and Op, and the outputs watchdog.

use std::collections::VecDeque;

use edsgen_runtime::Instant;

use super::al::{self, code, AlState, Request};
use edsgen_runtime::ethercat::esc::{reg, Esc, Event, SmRegisters};

use super::esc::EmulatedEsc;
use edsgen_runtime::ethercat::wire::frame::Frame;

/// Where the device expects its SyncManagers (from its SII or ESI): SyncManager numbers and
/// the mailboxes' places and sizes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Layout {
    /// The master-to-device mailbox (number, start, length), if the device has a mailbox.
    pub mailbox_out: Option<(usize, u16, u16)>,
    /// The device-to-master mailbox (number, start, length).
    pub mailbox_in: Option<(usize, u16, u16)>,
    /// The outputs SyncManager's number, if any.
    pub outputs: Option<usize>,
    /// The inputs SyncManager's number, if any.
    pub inputs: Option<usize>,
}

/// What runs behind the ESC: the device's mailbox protocols and process data.
pub trait Application {
    /// Answers one mailbox message (the whole master-to-device SyncManager) received in
    /// `state`; returns the messages to send back, in order (none for a message it ignores).
    fn mailbox(&mut self, state: AlState, request: &[u8]) -> Vec<Vec<u8>>;
    /// The outputs and inputs image sizes in bytes for the PDO assignment in force.
    fn image_sizes(&self) -> (usize, usize);
    /// The outputs the master wrote, in Op.
    fn outputs(&mut self, now: Instant, outputs: &[u8]);
    /// The inputs image to show now, in Safe-Op and Op (its length as `image_sizes` says).
    fn inputs(&mut self, now: Instant) -> Vec<u8>;
    /// The AL state changed.
    fn state_changed(&mut self, _now: Instant, _from: AlState, _to: AlState) {}
}

/// A SubDevice: its ESC (the emulated one unless said) and the application behind it.
#[derive(Debug)]
pub struct SubDevice<A, E = EmulatedEsc> {
    esc: E,
    app: A,
    layout: Layout,
    state: AlState,
    outbox: VecDeque<Vec<u8>>,
    last_answer: Option<Vec<u8>>,
    last_outputs: Option<Instant>,
}

impl<A: Application> SubDevice<A> {
    /// A SubDevice in Init with the SII image `sii` in an emulated ESC.
    pub fn new(sii: Vec<u8>, layout: Layout, app: A) -> Self {
        SubDevice::with_esc(EmulatedEsc::new(sii), layout, app)
    }

    /// Processes the Ethernet frame `frame` in place at `now`, as the emulated ESC does in
    /// hardware, and the device between datagrams. Returns whether it is to be sent back:
    /// `false` for a frame that is not EtherCAT (ignored, unchanged). Datagrams after a
    /// malformed one are left as they came (their working counters unchanged).
    pub fn process_frame(&mut self, now: Instant, frame: &mut [u8]) -> bool {
        let Ok(mut frame) = Frame::new_checked(frame) else {
            return false;
        };
        self.poll(now);
        self.refresh_inputs(now);
        let mut datagrams = frame.datagrams();
        while let Some(Ok(place)) = datagrams.next(frame.as_bytes()) {
            let Some(mut datagram) = frame.datagram_mut(place) else {
                break;
            };
            let (header, data) = datagram.split_mut();
            let (gain, adp) = self.esc.datagram(&header, data);
            datagram.set_adp(adp);
            datagram.set_wkc(datagram.wkc().wrapping_add(gain));
            self.handle_events(now);
        }
        // As an ESC does on the way back: the source address's locally-administered bit.
        let mut source = frame.source();
        source[0] |= 0x02;
        frame.set_source(source);
        true
    }
}

impl<A: Application, E: Esc> SubDevice<A, E> {
    /// A SubDevice in Init over `esc`.
    pub fn with_esc(esc: E, layout: Layout, app: A) -> Self {
        let mut device = SubDevice {
            esc,
            app,
            layout,
            state: AlState::Init,
            outbox: VecDeque::new(),
            last_answer: None,
            last_outputs: None,
        };
        device.set_process_sms();
        device
    }

    /// The AL state.
    pub fn state(&self) -> AlState {
        self.state
    }

    /// The ESC, to look at its registers.
    pub fn esc(&self) -> &E {
        &self.esc
    }

    /// The application.
    pub fn app(&self) -> &A {
        &self.app
    }

    /// The application, to change it.
    pub fn app_mut(&mut self) -> &mut A {
        &mut self.app
    }

    /// Lets time pass: the outputs watchdog.
    pub fn poll(&mut self, now: Instant) {
        if self.state != AlState::Op {
            return;
        }
        let Some(n) = self.layout.outputs else {
            return;
        };
        let sm = self.esc.sm(n);
        let time = u64::from(self.esc.read_u16(reg::WATCHDOG_TIME_PD));
        if !sm.enabled() || sm.control & 0x40 == 0 || time == 0 {
            return;
        }
        let divider = u64::from(self.esc.read_u16(reg::WATCHDOG_DIVIDER));
        // One watchdog tick is (divider + 2) × 40 ns.
        let limit_us = (divider + 2) * 40 * time / 1000;
        let since = self.last_outputs.unwrap_or(Instant(0));
        if now.saturating_since(since).as_micros() > limit_us {
            self.esc.write_u16(reg::WATCHDOG_STATUS_PD, 0);
            self.enter(now, AlState::SafeOp);
            self.refuse(code::SM_WATCHDOG);
        }
    }

    /// Writes the application's inputs into the inputs SyncManager, in Safe-Op and Op.
    fn refresh_inputs(&mut self, now: Instant) {
        if self.state < AlState::SafeOp {
            return;
        }
        if let Some(n) = self.layout.inputs {
            let sm = self.esc.sm(n);
            let inputs = self.app.inputs(now);
            let len = inputs.len().min(usize::from(sm.len));
            self.esc.write(sm.start, &inputs[..len]);
        }
    }

    fn handle_events(&mut self, now: Instant) {
        while let Some(event) = self.esc.poll_event() {
            match event {
                Event::AlControl => self.al_control(now),
                Event::MailboxWritten(n) if Some(n) == self.layout.mailbox_out.map(|m| m.0) => {
                    // Reading the whole buffer empties the mailbox.
                    let request = self.read_buffer(n);
                    if self.state >= AlState::PreOp {
                        let answers = self.app.mailbox(self.state, &request);
                        self.outbox.extend(answers);
                        self.deliver();
                    }
                }
                Event::MailboxRead(_) => self.deliver(),
                Event::RepeatRequest(n) if Some(n) == self.layout.mailbox_in.map(|m| m.0) => {
                    if let Some(answer) = self.last_answer.clone() {
                        self.put_in_mailbox(n, &answer);
                    }
                    // The acknowledge (PDI control bit 1) follows the request (activate bit 1).
                    let sm = self.esc.sm(n);
                    let acknowledged = (sm.pdi_control & !0x02) | (sm.activate & 0x02);
                    self.esc.write_u8(reg::sm_pdi_control(n), acknowledged);
                }
                Event::BufferWritten(n) if Some(n) == self.layout.outputs => {
                    self.last_outputs = Some(now);
                    self.esc.write_u16(reg::WATCHDOG_STATUS_PD, 1);
                    if self.state == AlState::Op {
                        let outputs = self.read_buffer(n);
                        self.app.outputs(now, &outputs);
                    }
                }
                _ => {}
            }
        }
    }

    /// SyncManager `n`'s whole buffer.
    fn read_buffer(&mut self, n: usize) -> Vec<u8> {
        let sm = self.esc.sm(n);
        let mut buffer = vec![0; usize::from(sm.len)];
        self.esc.read(sm.start, &mut buffer);
        buffer
    }

    /// Puts the next queued answer in the device-to-master mailbox if it is empty.
    fn deliver(&mut self) {
        let Some((n, _, _)) = self.layout.mailbox_in else {
            return;
        };
        let sm = self.esc.sm(n);
        if !sm.enabled() || sm.status & 0x08 != 0 {
            return;
        }
        if let Some(answer) = self.outbox.pop_front() {
            self.put_in_mailbox(n, &answer);
            self.last_answer = Some(answer);
        }
    }

    fn put_in_mailbox(&mut self, n: usize, message: &[u8]) {
        let sm = self.esc.sm(n);
        let mut buffer = message.to_vec();
        buffer.resize(usize::from(sm.len), 0);
        // Writing the whole buffer fills the mailbox.
        self.esc.write(sm.start, &buffer);
    }

    fn al_control(&mut self, now: Instant) {
        let control = self.esc.read_u16(reg::AL_CONTROL);
        let requested = (control & 0x0F) as u8;
        let acknowledge = control & 0x10 != 0;
        let in_error = self.esc.read_u16(reg::AL_STATUS) & 0x10 != 0;
        if in_error && !acknowledge && requested >= self.state.code() {
            return;
        }
        if acknowledge {
            self.esc
                .write_u16(reg::AL_STATUS, u16::from(self.state.code()));
            self.esc.write_u16(reg::AL_STATUS_CODE, code::NO_ERROR);
        }
        match al::request(self.state, requested) {
            Request::Stay => {}
            Request::Refuse(status) => self.refuse(status),
            Request::Go(target) if target > self.state => match self.check(target) {
                Ok(()) => self.enter(now, target),
                Err(status) => self.refuse(status),
            },
            Request::Go(target) => self.enter(now, target),
        }
    }

    /// Stays in the current state with the error indication and `status`.
    fn refuse(&mut self, status: u16) {
        self.esc
            .write_u16(reg::AL_STATUS, u16::from(self.state.code()) | 0x10);
        self.esc.write_u16(reg::AL_STATUS_CODE, status);
    }

    /// What a step up to `target` needs.
    fn check(&mut self, target: AlState) -> Result<(), u16> {
        let mut sm = |n: Option<usize>| n.map(|n| self.esc.sm(n));
        match target {
            AlState::PreOp => {
                let fits = |expected: Option<(usize, u16, u16)>,
                            sm: Option<SmRegisters>,
                            master_writes: bool| {
                    expected.is_none_or(|(_, start, len)| {
                        sm.is_some_and(|sm| {
                            sm.activate & 1 != 0
                                && sm.start == start
                                && sm.len == len
                                && sm.is_mailbox()
                                && sm.master_writes() == master_writes
                        })
                    })
                };
                let (out, inp) = (self.layout.mailbox_out, self.layout.mailbox_in);
                let (out_sm, in_sm) = (sm(out.map(|m| m.0)), sm(inp.map(|m| m.0)));
                if fits(out, out_sm, true) && fits(inp, in_sm, false) {
                    Ok(())
                } else {
                    Err(code::INVALID_MAILBOX_CONFIG)
                }
            }
            AlState::SafeOp => {
                let (outputs, inputs) = self.app.image_sizes();
                let fits = |sm: Option<SmRegisters>, size: usize, master_writes: bool| {
                    size == 0
                        || sm.is_some_and(|sm| {
                            sm.activate & 1 != 0
                                && usize::from(sm.len) == size
                                && !sm.is_mailbox()
                                && sm.master_writes() == master_writes
                        })
                };
                let (out_sm, in_sm) = (sm(self.layout.outputs), sm(self.layout.inputs));
                if !fits(out_sm, outputs, true) {
                    Err(code::INVALID_OUTPUT_CONFIG)
                } else if !fits(in_sm, inputs, false) {
                    Err(code::INVALID_INPUT_CONFIG)
                } else {
                    Ok(())
                }
            }
            AlState::Init | AlState::Op => Ok(()),
        }
    }

    fn enter(&mut self, now: Instant, target: AlState) {
        let from = self.state;
        self.state = target;
        self.esc.write_u16(reg::AL_STATUS, u16::from(target.code()));
        self.esc.write_u16(reg::AL_STATUS_CODE, code::NO_ERROR);
        if target == AlState::Init {
            self.outbox.clear();
            self.last_answer = None;
            // Deactivating a mailbox SyncManager resets it (empties it).
            for n in [self.layout.mailbox_out, self.layout.mailbox_in]
                .into_iter()
                .flatten()
            {
                let at = reg::sm_pdi_control(n.0);
                let pdi_control = self.esc.read_u8(at);
                self.esc.write_u8(at, pdi_control | 1);
                self.esc.write_u8(at, pdi_control);
            }
        }
        if target == AlState::Op {
            // The watchdog runs from entering Op.
            self.last_outputs = Some(now);
        }
        self.set_process_sms();
        if from != target {
            self.app.state_changed(now, from, target);
        }
    }

    /// The process-data SyncManagers work in Safe-Op and Op only.
    fn set_process_sms(&mut self) {
        let off = self.state < AlState::SafeOp;
        for n in [self.layout.outputs, self.layout.inputs]
            .into_iter()
            .flatten()
        {
            let at = reg::sm_pdi_control(n);
            let pdi_control = self.esc.read_u8(at);
            self.esc.write_u8(
                at,
                if off {
                    pdi_control | 1
                } else {
                    pdi_control & !1
                },
            );
        }
    }
}
