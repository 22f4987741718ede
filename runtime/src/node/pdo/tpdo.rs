//! A transmit PDO: its configuration from 1800h–19FFh and when it sends (SYNC, event, RTR,
//! inhibit time and event timer).

use crate::frame::CanFrame;
use crate::od::{ObjectDictionary, SdoAbort};
use crate::time::{Duration, Instant};

use super::arm_timer;
use super::params::PdoParams;

/// A transmit PDO.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Tpdo {
    params: PdoParams,
    /// A frame is waiting to be sent; `data` holds it if it was sampled already (synchronous,
    /// `sampled`). A flag beside a plain array rather than an `Option`, which keeps the array
    /// word-aligned (it is copied into a frame as whole words).
    pending: bool,
    sampled: bool,
    data: [u8; 8],
    /// For synchronous PDOs: the latest sample (252) and the window deadline.
    sync_deadline: Option<Instant>,
    /// Type 0: an event occurred since the last SYNC.
    acyclic_request: bool,
    /// SYNCs left until the next cyclic transmission (1 to 240); 0 before the first SYNC and
    /// while waiting for the SYNC start value. A plain count rather than an `Option`.
    sync_countdown: u8,
    /// Type 252: `data` holds the sample of the last SYNC, sent on a remote request (a PDO of
    /// type 252 uses `data` for nothing else).
    rtr_sampled: bool,
    /// The payload last sent (change-of-state detection).
    last_data: [u8; 8],
    last_sent: Option<Instant>,
    /// A mapped object may have changed: compare before the next transmission decision.
    check_change: bool,
}

impl Tpdo {
    /// A PDO that does not exist (yet): nothing configured, nothing running. A constant, like
    /// [`Rpdo::OFF`](super::Rpdo::OFF).
    pub const OFF: Tpdo = Tpdo {
        params: PdoParams::OFF,
        pending: false,
        sampled: false,
        data: [0; 8],
        sync_deadline: None,
        acyclic_request: false,
        sync_countdown: 0,
        rtr_sampled: false,
        last_data: [0; 8],
        last_sent: None,
        check_change: false,
    };

    /// Reads the configuration of TPDO `n` (1800h + n, 1A00h + n) into this PDO, in place, and
    /// forgets its running state. Returns why the mapping was refused if the COB-ID is valid
    /// (the PDO is then not served).
    pub fn load<O: ObjectDictionary + ?Sized>(&mut self, od: &O, n: u16) -> Option<SdoAbort> {
        *self = Tpdo::OFF;
        self.params.load(od, 0x1800 + n)
    }

    #[inline]
    pub fn event_driven(&self) -> bool {
        self.params.transmission >= 254
    }

    /// Forgets everything a running PDO accumulated (leaving operational, reconfiguring).
    pub fn stop(&mut self) {
        self.pending = false;
        self.sampled = false;
        self.rtr_sampled = false;
        self.sync_deadline = None;
        self.acyclic_request = false;
        self.sync_countdown = 0;
        self.check_change = false;
    }

    /// The inhibit time.
    pub fn inhibit(&self) -> Duration {
        Duration::from_micros(u64::from(self.params.inhibit_100us) * 100)
    }

    /// Whether its mapping holds the object at `position` in the OD's table.
    #[inline]
    pub fn maps(&self, position: u16) -> bool {
        self.params.mapping.contains(position)
    }

    /// A mapped object may have changed: compare before the next transmission decision.
    #[inline]
    pub fn mark_changed(&mut self) {
        self.check_change = true;
    }

    /// Re-reads TPDO `n` after an SDO write to its parameters, keeping the timing history
    /// (last transmission, last data) of a running PDO across a change of its event timer or
    /// transmission type. In operational, an event-driven PDO restarts its event timer (its
    /// slot `event_timer` in the node's timer table; a new configuration stops it otherwise)
    /// and, if it has just become valid, is sent. Returns whether it is now waiting to be sent.
    pub fn reload<O: ObjectDictionary + ?Sized>(
        &mut self,
        od: &O,
        n: u16,
        now: Instant,
        operational: bool,
        event_timer: &mut Option<Instant>,
    ) -> bool {
        let was_enabled = self.params.enabled;
        // The running state goes as with a stop (`data` is read only when `sampled`); the
        // timing history stays.
        self.stop();
        self.params = PdoParams::OFF;
        let _ = self.params.load(od, 0x1800 + n);
        *event_timer = None;
        if operational && self.params.enabled && self.event_driven() {
            arm_timer(event_timer, now, self.params.event_timer_ms);
            if !was_enabled {
                self.pending = true;
            }
        }
        self.pending
    }

    /// Entering operational: an event-driven PDO is sent once. Returns whether it is waiting.
    pub fn start(&mut self) -> bool {
        if self.params.enabled && self.event_driven() {
            self.pending = true;
        }
        self.pending
    }

    /// An application event (`Node::trigger_tpdo`): an event-driven PDO is sent as soon as its
    /// inhibit time allows, an acyclic synchronous one at the next SYNC. `false` if the PDO is
    /// not valid or has another transmission type.
    pub fn trigger(&mut self) -> bool {
        if !self.params.enabled {
            return false;
        }
        match self.params.transmission {
            0 => self.acyclic_request = true,
            254 | 255 => self.pending = true,
            _ => return false,
        }
        true
    }

    /// A remote request on `id`: a PDO of type 252 sends its sample of the last SYNC, one of
    /// 253 (or event-driven) a fresh one. Returns whether it was for this PDO.
    pub fn remote_request(&mut self, id: u16) -> bool {
        if !(self.params.enabled && self.params.rtr_allowed && self.params.cob_id == id) {
            return false;
        }
        match self.params.transmission {
            252 => {
                if self.rtr_sampled {
                    self.sampled = true;
                    self.pending = true;
                }
            }
            _ => {
                self.sampled = false;
                self.pending = true;
            }
        }
        true
    }

    /// A SYNC with `counter` (`use_start`: 1019h is set, so the SYNC start value applies),
    /// whose synchronous window ends at `window_end`. Returns whether the PDO is now waiting
    /// to be sent.
    pub fn on_sync<O: ObjectDictionary + ?Sized>(
        &mut self,
        od: &O,
        counter: Option<u8>,
        use_start: bool,
        window_end: Option<Instant>,
    ) -> bool {
        if !self.params.enabled {
            return false;
        }
        let send = match self.params.transmission {
            0 => {
                if self.check_change {
                    let data = self.params.mapping.pack(od);
                    self.check_change = false;
                    if data != self.last_data {
                        self.acyclic_request = true;
                    }
                }
                core::mem::take(&mut self.acyclic_request)
            }
            every @ 1..=240 => {
                let start = if use_start { self.params.sync_start } else { 0 };
                // SYNCs left until the next transmission, counting this one.
                // SYNCs left until the next transmission, counting this one (0: not yet).
                let left = match self.sync_countdown {
                    0 if start != 0 => u8::from(counter == Some(start)),
                    0 => every,
                    left => left,
                };
                match left {
                    0 => false,
                    1 => {
                        self.sync_countdown = every;
                        true
                    }
                    left => {
                        self.sync_countdown = left - 1;
                        false
                    }
                }
            }
            252 => {
                self.data = self.params.mapping.pack(od);
                self.rtr_sampled = true;
                false
            }
            _ => false,
        };
        if send {
            self.data = self.params.mapping.pack(od);
            self.sampled = true;
            self.pending = true;
            self.sync_deadline = window_end;
        }
        send
    }

    /// The frame to send at `now`, if the PDO is waiting and may go: an event-driven PDO
    /// whose mapped values changed is sent (change of state), within its inhibit time; a
    /// synchronous one only within its SYNC's window (else that SYNC's PDO is dropped). A PDO
    /// sent restarts its event timer (its slot `event_timer` in the node's timer table).
    pub fn poll_transmit<O: ObjectDictionary + ?Sized>(
        &mut self,
        od: &O,
        now: Instant,
        event_timer: &mut Option<Instant>,
    ) -> Option<CanFrame> {
        if !self.params.enabled {
            return None;
        }
        if self.event_driven() && core::mem::take(&mut self.check_change) {
            let data = self.params.mapping.pack(od);
            if data != self.last_data {
                self.pending = true;
            }
        }
        if !self.pending {
            return None;
        }
        // Only a dictionary with 1007h sets a window (a constant for a generated one).
        let window = od.services().sync_window;
        if let Some(deadline) = self.sync_deadline.filter(|_| window) {
            if now > deadline {
                // Outside the synchronous window (1007h): this SYNC's PDO is dropped.
                self.pending = false;
                self.sampled = false;
                self.sync_deadline = None;
                return None;
            }
        }
        if self.event_driven() && !self.inhibit_passed(now) {
            return None;
        }
        let data = if core::mem::take(&mut self.sampled) {
            self.data
        } else {
            self.params.mapping.pack(od)
        };
        self.pending = false;
        // Never set without 1007h.
        if window {
            self.sync_deadline = None;
        }
        self.last_data = data;
        self.last_sent = Some(now);
        if self.event_driven() {
            arm_timer(event_timer, now, self.params.event_timer_ms);
        }
        Some(CanFrame::from_parts(
            self.params.cob_id,
            data,
            self.params.mapping.len,
        ))
    }

    /// Whether a frame is waiting (perhaps for its inhibit time).
    #[inline]
    pub fn pending(&self) -> bool {
        self.pending
    }

    /// When the inhibit time of an event-driven PDO's waiting frame ends (it may go out
    /// through [`Tpdo::poll_transmit`] then), if one is waiting.
    #[inline]
    pub fn inhibit_end(&self) -> Option<Instant> {
        if !(self.event_driven() && self.pending) {
            return None;
        }
        self.last_sent.map(|sent| sent + self.inhibit())
    }

    /// The event timer ran out: the PDO is waiting to be sent.
    pub fn expire_event(&mut self) {
        self.pending = true;
    }

    /// Whether the inhibit time since the last transmission has passed.
    #[inline]
    pub fn inhibit_passed(&self, now: Instant) -> bool {
        match self.last_sent {
            Some(sent) => now >= sent + self.inhibit(),
            None => true,
        }
    }
}
