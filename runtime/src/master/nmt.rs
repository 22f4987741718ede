//! NMT master commands and the error-control side of a master: a heartbeat consumer and a
//! node-guarding master for up to `N` nodes, reporting boot-up, state changes, loss and
//! recovery as [`MonitorEvent`]s. Sans-IO: frames and instants in, RTRs and events out.

use crate::frame::CanFrame;
use crate::time::{Duration, Instant};
use crate::wire::heartbeat::{ErrorControlRepr, NmtState};
use crate::wire::nmt::{NmtCommand, NmtRepr, NMT_COB_ID};

/// The NMT frame commanding `node_id` (0: all nodes).
pub fn nmt_frame(command: NmtCommand, node_id: u8) -> CanFrame {
    let data = NmtRepr { command, node_id }.emit();
    CanFrame::from_parts(NMT_COB_ID, [data[0], data[1], 0, 0, 0, 0, 0, 0], 2)
}

/// How the master watches one node.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Watch {
    /// Heartbeat consumer: the node is lost when no heartbeat arrives within this time
    /// (the node's producer time plus margin, as in 1016h).
    Heartbeat(Duration),
    /// Node guarding: an RTR every `guard_time`; the node is lost after `life_factor` RTRs in a
    /// row without a correct answer (answers must alternate their toggle bit).
    Guarding {
        /// Time between two guarding RTRs (100Ch on the node).
        guard_time: Duration,
        /// How many unanswered RTRs make the node lost (100Dh on the node).
        life_factor: u8,
    },
}

/// What the monitor noticed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MonitorEvent {
    /// The node sent its boot-up message (it is now pre-operational).
    BootUp {
        /// The node.
        node_id: u8,
    },
    /// The node reported a state other than the last one seen.
    StateChanged {
        /// The node.
        node_id: u8,
        /// The state seen before, if any.
        from: Option<NmtState>,
        /// The state reported now.
        to: NmtState,
    },
    /// No heartbeat in time, or too many guarding RTRs unanswered.
    Lost {
        /// The node.
        node_id: u8,
    },
    /// A lost node answers again.
    Recovered {
        /// The node.
        node_id: u8,
        /// The state it reports.
        state: NmtState,
    },
}

#[derive(Debug, Clone, Copy)]
struct Watched {
    node_id: u8,
    watch: Watch,
    state: Option<NmtState>,
    lost: bool,
    /// Heartbeat: when the node is lost without another heartbeat. Guarding: the next RTR.
    deadline: Option<Instant>,
    /// Guarding: the toggle bit the next answer must carry.
    toggle: bool,
    /// Guarding: RTRs sent without a correct answer.
    unanswered: u8,
    /// Guarding: an RTR is due now.
    rtr_due: bool,
}

/// Why a node cannot be watched.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WatchError {
    /// All `N` places are taken.
    Full,
    /// The node-ID is not 1..=127, or a time is zero.
    Invalid,
}

/// Events kept until taken; the oldest are dropped past this.
const EVENT_QUEUE: usize = 32;

/// Heartbeat consumer and guarding master for up to `N` nodes.
#[derive(Debug, Clone)]
pub struct NodeMonitor<const N: usize> {
    nodes: [Option<Watched>; N],
    events: [Option<MonitorEvent>; EVENT_QUEUE],
    event_head: usize,
    event_len: usize,
}

impl<const N: usize> Default for NodeMonitor<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> NodeMonitor<N> {
    /// A monitor watching no node.
    pub const fn new() -> Self {
        NodeMonitor {
            nodes: [None; N],
            events: [None; EVENT_QUEUE],
            event_head: 0,
            event_len: 0,
        }
    }

    /// Watches `node_id` from `now` on (replacing how it was watched). A heartbeat consumer's
    /// first deadline runs from `now`; guarding sends its first RTR at `now` (through
    /// [`handle_timeout`](Self::handle_timeout)).
    pub fn watch(&mut self, now: Instant, node_id: u8, watch: Watch) -> Result<(), WatchError> {
        let valid = match watch {
            Watch::Heartbeat(time) => time.as_micros() > 0,
            Watch::Guarding {
                guard_time,
                life_factor,
            } => guard_time.as_micros() > 0 && life_factor > 0,
        };
        if !(1..=127).contains(&node_id) || !valid {
            return Err(WatchError::Invalid);
        }
        let slot = match self.position(node_id) {
            Some(i) => i,
            None => self
                .nodes
                .iter()
                .position(Option::is_none)
                .ok_or(WatchError::Full)?,
        };
        self.nodes[slot] = Some(Watched {
            node_id,
            watch,
            state: None,
            lost: false,
            deadline: match watch {
                Watch::Heartbeat(time) => Some(now + time),
                Watch::Guarding { .. } => Some(now),
            },
            toggle: false,
            unanswered: 0,
            rtr_due: false,
        });
        Ok(())
    }

    /// Stops watching `node_id`.
    pub fn unwatch(&mut self, node_id: u8) {
        if let Some(i) = self.position(node_id) {
            self.nodes[i] = None;
        }
    }

    /// The last state `node_id` reported, if it is watched and has reported one.
    pub fn state(&self, node_id: u8) -> Option<NmtState> {
        self.find(node_id)?.state
    }

    /// Whether `node_id` is watched and currently lost.
    pub fn is_lost(&self, node_id: u8) -> bool {
        self.find(node_id).is_some_and(|n| n.lost)
    }

    /// The next event, oldest first.
    pub fn poll_event(&mut self) -> Option<MonitorEvent> {
        if self.event_len == 0 {
            return None;
        }
        let event = self.events[self.event_head].take();
        self.event_head = (self.event_head + 1) % EVENT_QUEUE;
        self.event_len -= 1;
        event
    }

    /// Takes a frame from the bus: error-control messages (700h + node-ID) of watched nodes.
    pub fn handle_frame(&mut self, now: Instant, frame: &CanFrame) {
        let Some(id) = frame.std_id() else {
            return;
        };
        if frame.is_remote() || !(0x701..=0x77F).contains(&id) {
            return;
        }
        let node_id = (id - 0x700) as u8;
        let Some(message) = ErrorControlRepr::parse(frame.data()) else {
            return;
        };
        let Some(i) = self.position(node_id) else {
            return;
        };
        let Some(mut node) = self.nodes[i] else {
            return;
        };
        let mut events = [None; 3];
        if message == ErrorControlRepr::BOOT_UP {
            events[0] = Some(MonitorEvent::BootUp { node_id });
            node.toggle = false;
            node.unanswered = 0;
            let recovered = core::mem::take(&mut node.lost);
            node.state = Some(NmtState::PreOperational);
            if recovered {
                events[1] = Some(MonitorEvent::Recovered {
                    node_id,
                    state: NmtState::PreOperational,
                });
            }
            if let Watch::Heartbeat(time) = node.watch {
                node.deadline = Some(now + time);
            }
        } else {
            if let Watch::Guarding { .. } = node.watch {
                if node.unanswered == 0 || message.toggle != node.toggle {
                    // Unasked, or a repeated toggle: not an answer.
                    self.nodes[i] = Some(node);
                    return;
                }
                node.toggle = !node.toggle;
                node.unanswered = 0;
            } else if let Watch::Heartbeat(time) = node.watch {
                node.deadline = Some(now + time);
            }
            if core::mem::take(&mut node.lost) {
                events[0] = Some(MonitorEvent::Recovered {
                    node_id,
                    state: message.state,
                });
            }
            if node.state != Some(message.state) {
                events[1] = Some(MonitorEvent::StateChanged {
                    node_id,
                    from: node.state,
                    to: message.state,
                });
                node.state = Some(message.state);
            }
        }
        self.nodes[i] = Some(node);
        for event in events.into_iter().flatten() {
            self.push_event(event);
        }
    }

    /// The next guarding RTR due.
    pub fn poll_transmit(&mut self, _now: Instant) -> Option<CanFrame> {
        let node = self.nodes.iter_mut().flatten().find(|n| n.rtr_due)?;
        node.rtr_due = false;
        Some(CanFrame::remote(ErrorControlRepr::cob_id(node.node_id), 1))
    }

    /// The earliest deadline: a heartbeat overdue or the next guarding RTR.
    pub fn poll_timeout(&self) -> Option<Instant> {
        self.nodes.iter().flatten().filter_map(|n| n.deadline).min()
    }

    /// Declares nodes lost whose heartbeat is overdue, and schedules guarding RTRs.
    pub fn handle_timeout(&mut self, now: Instant) {
        let mut lost = [0u8; N];
        let mut lost_count = 0;
        for node in self.nodes.iter_mut().flatten() {
            if node.deadline.is_none_or(|at| at > now) {
                continue;
            }
            match node.watch {
                Watch::Heartbeat(_) => {
                    node.deadline = None;
                    if !node.lost {
                        node.lost = true;
                        lost[lost_count] = node.node_id;
                        lost_count += 1;
                    }
                }
                Watch::Guarding {
                    guard_time,
                    life_factor,
                } => {
                    if node.unanswered >= life_factor && !node.lost {
                        node.lost = true;
                        lost[lost_count] = node.node_id;
                        lost_count += 1;
                    }
                    node.unanswered = node.unanswered.saturating_add(1);
                    node.rtr_due = true;
                    node.deadline = Some(now + guard_time);
                }
            }
        }
        for &node_id in &lost[..lost_count] {
            self.push_event(MonitorEvent::Lost { node_id });
        }
    }

    fn position(&self, node_id: u8) -> Option<usize> {
        self.nodes
            .iter()
            .position(|n| n.is_some_and(|n| n.node_id == node_id))
    }

    fn find(&self, node_id: u8) -> Option<&Watched> {
        self.nodes.iter().flatten().find(|n| n.node_id == node_id)
    }

    fn push_event(&mut self, event: MonitorEvent) {
        if self.event_len == EVENT_QUEUE {
            // Full: the oldest goes.
            self.event_head = (self.event_head + 1) % EVENT_QUEUE;
            self.event_len -= 1;
        }
        self.events[(self.event_head + self.event_len) % EVENT_QUEUE] = Some(event);
        self.event_len += 1;
    }
}
