//! The futures' plumbing of the async master: the slot where the driver thread leaves a
//! request's outcome and wakes its task ([`Reply`] on the driver's side, [`Pending`] on the
//! caller's), and the queue of events the driver noticed ([`Events`], [`EventSender`]).

use std::collections::VecDeque;
use std::future::Future;
use std::io;
use std::pin::Pin;
use std::sync::{Arc, Mutex, MutexGuard};
use std::task::{Context, Poll, Waker};

use super::super::blocking::{MasterError, MasterEvent};

/// Events kept until taken; the oldest are dropped past this.
const EVENT_QUEUE: usize = 1024;

/// What a request gives back: by default the value read and its size (or the size written).
pub(super) type Outcome<T = Done> = Result<T, MasterError>;

/// A request's success: the bytes read (an upload) and the value's size (a transfer).
#[derive(Default)]
pub(super) struct Done {
    pub(super) bytes: Vec<u8>,
    pub(super) size: u32,
}

/// Where the driver thread leaves a request's outcome for its future.
struct Slot<T> {
    outcome: Option<Outcome<T>>,
    waker: Option<Waker>,
    /// The driver is gone without an outcome.
    abandoned: bool,
}

pub(super) fn lock<S>(slot: &Mutex<S>) -> MutexGuard<'_, S> {
    slot.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// A new pending request's two ends: the driver thread's and the caller's.
pub(super) fn pending<T>() -> (Reply<T>, Pending<T>) {
    let slot = Arc::new(Mutex::new(Slot {
        outcome: None,
        waker: None,
        abandoned: false,
    }));
    (Reply(Arc::clone(&slot)), Pending(slot))
}

/// The driver thread's end of a pending request.
pub(super) struct Reply<T = Done>(Arc<Mutex<Slot<T>>>);

impl<T> Reply<T> {
    pub(super) fn send(self, outcome: Outcome<T>) {
        let mut slot = lock(&self.0);
        slot.outcome = Some(outcome);
        if let Some(waker) = slot.waker.take() {
            waker.wake();
        }
    }
}

impl<T> Drop for Reply<T> {
    fn drop(&mut self) {
        let mut slot = lock(&self.0);
        if slot.outcome.is_none() {
            slot.abandoned = true;
            if let Some(waker) = slot.waker.take() {
                waker.wake();
            }
        }
    }
}

/// A request's outcome, once the driver thread has it.
pub(super) struct Pending<T = Done>(Arc<Mutex<Slot<T>>>);

impl<T> Future for Pending<T> {
    type Output = Outcome<T>;
    fn poll(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<Outcome<T>> {
        let mut slot = lock(&self.0);
        if let Some(outcome) = slot.outcome.take() {
            return Poll::Ready(outcome);
        }
        if slot.abandoned {
            return Poll::Ready(Err(MasterError::Io(io::Error::new(
                io::ErrorKind::BrokenPipe,
                "the master's driver thread stopped",
            ))));
        }
        slot.waker = Some(cx.waker().clone());
        Poll::Pending
    }
}

/// The events the driver thread noticed, for
/// [`AsyncMaster::next_event`](super::AsyncMaster::next_event).
#[derive(Default)]
pub(super) struct Events {
    pub(super) queue: VecDeque<MasterEvent>,
    pub(super) waker: Option<Waker>,
    /// The driver thread has stopped: no event follows the queued ones.
    pub(super) stopped: bool,
}

/// The driver thread's end of the events.
pub(super) struct EventSender(pub(super) Arc<Mutex<Events>>);

impl EventSender {
    pub(super) fn send(&self, event: MasterEvent) {
        let mut events = lock(&self.0);
        if events.queue.len() == EVENT_QUEUE {
            events.queue.pop_front();
        }
        events.queue.push_back(event);
        if let Some(waker) = events.waker.take() {
            waker.wake();
        }
    }
}

impl Drop for EventSender {
    fn drop(&mut self) {
        let mut events = lock(&self.0);
        events.stopped = true;
        if let Some(waker) = events.waker.take() {
            waker.wake();
        }
    }
}
