//! The queue of [`Event`]s the node reports until the application polls them.

use super::Event;

/// Events kept until the application polls them; older ones are kept, newer ones counted as lost.
pub const EVENT_QUEUE: usize = 16;

#[derive(Debug, Clone, Copy)]
pub(crate) struct EventQueue {
    events: [Event; EVENT_QUEUE],
    head: usize,
    len: usize,
    lost: u32,
}

impl EventQueue {
    pub const fn new() -> Self {
        EventQueue {
            events: [Event::LifeGuardingLost; EVENT_QUEUE],
            head: 0,
            len: 0,
            lost: 0,
        }
    }

    pub fn push(&mut self, event: Event) {
        if self.len == EVENT_QUEUE {
            self.lost = self.lost.saturating_add(1);
            return;
        }
        self.events[(self.head + self.len) % EVENT_QUEUE] = event;
        self.len += 1;
    }

    /// Events dropped because the queue was full.
    pub fn lost(&self) -> u32 {
        self.lost
    }

    pub fn pop(&mut self) -> Option<Event> {
        if self.len == 0 {
            return None;
        }
        let event = self.events[self.head];
        self.head = (self.head + 1) % EVENT_QUEUE;
        self.len -= 1;
        Some(event)
    }
}
