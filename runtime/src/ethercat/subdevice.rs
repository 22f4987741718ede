//! The EtherCAT SubDevice's core, no_std and allocation-free, over an [`Esc`]: what a device's
//! firmware does behind its ESC. The AL state machine (requested transitions checked against
//! the mailbox and process-data SyncManagers the [`Layout`] expects, refusals with their AL
//! status codes, the error acknowledgement), the mailbox (one answer waiting at a time, the
//! last one kept for the repeat request), the process data handed to and taken from the
//! [`Application`] in Safe-Op and Op, and the outputs watchdog. Buffers are `N` bytes: the
//! longest mailbox and process image the device takes.
//!
//! The layout comes from the SII, read through the ESC's EEPROM interface ([`sii`]) when the
//! master asks for a step up from Init (SOEM and ethercrab offer the SII to the device first);
//! without an SII read at least once, the step is refused with 0x0050 (0x0051 if it fails).
//!
//! Drive it with [`SubDevice::poll`] (or its three steps, in the order an emulated ESC needs
//! them: [`handle_timeout`](SubDevice::handle_timeout) and
//! [`update_inputs`](SubDevice::update_inputs) before a frame's datagrams,
//! [`handle_events`](SubDevice::handle_events) after each).

use super::al::{self, code, AlState, Request};
use super::esc::{reg, Esc, Event, SmRegisters};
use super::sii::{self, SiiError};
use super::Identity;
use crate::time::Instant;

/// Where the device expects its SyncManagers (from its SII): SyncManager numbers and the
/// mailboxes' places and sizes.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
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
    /// `state` into `answer` (as long as the device-to-master mailbox); returns the answer's
    /// length, 0 for a message it ignores.
    fn mailbox(&mut self, state: AlState, request: &[u8], answer: &mut [u8]) -> usize;
    /// The outputs and inputs image sizes in bytes for the PDO assignment in force.
    fn image_sizes(&self) -> (usize, usize);
    /// The outputs the master wrote, in Op.
    fn outputs(&mut self, now: Instant, outputs: &[u8]);
    /// Fills `inputs` (the inputs image) with what to show now, in Safe-Op and Op.
    fn inputs(&mut self, now: Instant, inputs: &mut [u8]);
    /// The AL state changed.
    fn state_changed(&mut self, _now: Instant, _from: AlState, _to: AlState) {}
}

/// A SubDevice: its ESC, the application behind it and `N`-byte buffers.
#[derive(Debug)]
pub struct SubDevice<E, A, const N: usize> {
    esc: E,
    app: A,
    layout: Layout,
    /// The identity in the SII, once it has been read.
    identity: Option<Identity>,
    state: AlState,
    /// A request or process image on its way.
    scratch: [u8; N],
    /// The answer waiting for the mailbox, `queued` bytes of it (0: none).
    next: [u8; N],
    queued: usize,
    /// The last answer put in the mailbox, `last_len` bytes of it (0: none yet).
    last: [u8; N],
    last_len: usize,
    last_outputs: Option<Instant>,
}

impl<E: Esc, A: Application, const N: usize> SubDevice<E, A, N> {
    /// A SubDevice in Init over `esc`; it reads its layout from the SII (see the module comment).
    pub fn new(esc: E, app: A) -> Self {
        // No process-data SyncManager is known before the SII is read: none to deactivate.
        SubDevice {
            esc,
            app,
            layout: Layout::default(),
            identity: None,
            state: AlState::Init,
            scratch: [0; N],
            next: [0; N],
            queued: 0,
            last: [0; N],
            last_len: 0,
            last_outputs: None,
        }
    }

    /// The AL state.
    pub fn state(&self) -> AlState {
        self.state
    }

    /// The identity the SII gives, once it has been read.
    pub fn identity(&self) -> Option<Identity> {
        self.identity
    }

    /// The SyncManager layout the SII gives (empty until it has been read).
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// The ESC.
    pub fn esc(&self) -> &E {
        &self.esc
    }

    /// The ESC, to change it (an emulated ESC processes frames).
    pub fn esc_mut(&mut self) -> &mut E {
        &mut self.esc
    }

    /// The application.
    pub fn app(&self) -> &A {
        &self.app
    }

    /// The application, to change it.
    pub fn app_mut(&mut self) -> &mut A {
        &mut self.app
    }

    /// One turn of the device's main loop at `now`: the watchdog, the inputs, then what the
    /// master did.
    pub fn poll(&mut self, now: Instant) {
        self.handle_timeout(now);
        self.update_inputs(now);
        self.handle_events(now);
    }

    /// Lets time pass: the outputs watchdog.
    pub fn handle_timeout(&mut self, now: Instant) {
        if self.state != AlState::Op {
            return;
        }
        let Some(n) = self.layout.outputs else {
            return;
        };
        let sm = self.esc.sm(n);
        let time = u32::from(self.esc.read_u16(reg::WATCHDOG_TIME_PD));
        if !sm.enabled() || sm.control & 0x40 == 0 || time == 0 {
            return;
        }
        let divider = u32::from(self.esc.read_u16(reg::WATCHDOG_DIVIDER));
        // One watchdog tick is (divider + 2) × 40 ns, and 40 ns is 1/25 µs. In 32 bits: at most
        // 65,537 × 65,535 = 2³² − 1, and a microcontroller divides that without the ~1 KB of
        // library code a 64-bit division pulls in.
        let limit_us = u64::from((divider + 2) * time / 25);
        let since = self.last_outputs.unwrap_or(Instant(0));
        if now.saturating_since(since).as_micros() > limit_us {
            self.esc.write_u16(reg::WATCHDOG_STATUS_PD, 0);
            self.enter(now, AlState::SafeOp);
            self.refuse(code::SM_WATCHDOG);
        }
    }

    /// Writes the application's inputs into the inputs SyncManager, in Safe-Op and Op.
    pub fn update_inputs(&mut self, now: Instant) {
        if self.state < AlState::SafeOp {
            return;
        }
        if let Some(n) = self.layout.inputs {
            let sm = self.esc.sm(n);
            let len = self.app.image_sizes().1.min(usize::from(sm.len)).min(N);
            self.app.inputs(now, &mut self.scratch[..len]);
            self.esc.write(sm.start, &self.scratch[..len]);
        }
    }

    /// Answers what the ESC reports the master did: AL control written, a mailbox filled or
    /// emptied, a repeat request, outputs written.
    pub fn handle_events(&mut self, now: Instant) {
        while let Some(event) = self.esc.poll_event() {
            match event {
                Event::AlControl => self.al_control(now),
                Event::MailboxWritten(n) if Some(n) == self.layout.mailbox_out.map(|m| m.0) => {
                    // Reading the whole buffer empties the mailbox.
                    let len = self.read_buffer(n);
                    if self.state >= AlState::PreOp && self.queued == 0 {
                        let request = &self.scratch[..len];
                        let room = self.layout.mailbox_in.map_or(0, |m| usize::from(m.2));
                        let answer = &mut self.next[..room.min(N)];
                        let answer = self.app.mailbox(self.state, request, answer);
                        self.queued = answer.min(N);
                        self.deliver();
                    }
                }
                Event::MailboxRead(_) => self.deliver(),
                Event::RepeatRequest(n) if Some(n) == self.layout.mailbox_in.map(|m| m.0) => {
                    if self.last_len > 0 {
                        self.put_last_in_mailbox(n);
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
                        let len = self.read_buffer(n);
                        self.app.outputs(now, &self.scratch[..len]);
                    }
                }
                _ => {}
            }
        }
    }

    /// Reads SyncManager `n`'s whole buffer into the scratch buffer (its last byte too, which
    /// empties a mailbox, when it is longer than the scratch); returns the bytes kept.
    fn read_buffer(&mut self, n: usize) -> usize {
        let sm = self.esc.sm(n);
        let len = usize::from(sm.len);
        let kept = len.min(N);
        self.esc.read(sm.start, &mut self.scratch[..kept]);
        if len > kept {
            let mut last = [0u8];
            self.esc.read(sm.start.wrapping_add(sm.len - 1), &mut last);
        }
        kept
    }

    /// Puts the queued answer in the device-to-master mailbox if it is empty; it is then the
    /// last answer, which a repeat request sends again.
    fn deliver(&mut self) {
        let Some((n, _, _)) = self.layout.mailbox_in else {
            return;
        };
        let sm = self.esc.sm(n);
        if !sm.enabled() || sm.status & 0x08 != 0 {
            return;
        }
        if self.queued > 0 {
            core::mem::swap(&mut self.last, &mut self.next);
            self.last_len = core::mem::take(&mut self.queued);
            self.put_last_in_mailbox(n);
        }
    }

    /// Writes the last answer, padded with zeros to the whole buffer (which fills the mailbox).
    fn put_last_in_mailbox(&mut self, n: usize) {
        let sm = self.esc.sm(n);
        self.last[self.last_len..].fill(0);
        let whole = usize::from(sm.len).min(N);
        self.esc.write(sm.start, &self.last[..whole]);
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
            self.show_status(code::NO_ERROR);
        }
        match al::request(self.state, requested) {
            Request::Stay => {}
            Request::Refuse(status) => self.refuse(status),
            Request::Go(target) if target > self.state => {
                match self.read_sii().and_then(|()| self.check(target)) {
                    Ok(()) => self.enter(now, target),
                    Err(status) => self.refuse(status),
                }
            }
            Request::Go(target) => self.enter(now, target),
        }
    }

    /// Reads the SII on a step up from Init when the master offers it; an SII read before
    /// stands when it does not.
    fn read_sii(&mut self) -> Result<(), u16> {
        if self.state != AlState::Init {
            return Ok(());
        }
        match sii::read(&mut self.esc) {
            Ok(sii) => {
                self.layout = sii.layout;
                self.identity = Some(sii.identity);
                self.set_process_sms();
                Ok(())
            }
            Err(SiiError::NoAccess) if self.identity.is_some() => Ok(()),
            Err(SiiError::NoAccess) => Err(code::EEPROM_NO_ACCESS),
            Err(SiiError::Failed) => Err(code::EEPROM_ERROR),
        }
    }

    /// Stays in the current state with the error indication and `status`.
    fn refuse(&mut self, status: u16) {
        self.show_status(status);
    }

    /// Shows the state in AL status and `status` in AL status code, with the error indication
    /// unless it is [`code::NO_ERROR`].
    fn show_status(&mut self, status: u16) {
        let error = if status == code::NO_ERROR { 0 } else { 0x10 };
        self.esc
            .write_u16(reg::AL_STATUS, u16::from(self.state.code()) | error);
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
                                && usize::from(len) <= N
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
                                && sm.start >= reg::SYNC_MANAGED
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
        self.show_status(code::NO_ERROR);
        if target == AlState::Init {
            self.queued = 0;
            self.last_len = 0;
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
