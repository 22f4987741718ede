//! An in-memory CAN bus across threads: every [`MemoryEndpoint`] is a [`Transport`], and a frame
//! one endpoint sends reaches every other endpoint in the order sent. For testing drivers and
//! masters without sockets; unlike [`crate::vbus`] it runs in real time.

use std::io;
use std::sync::mpsc::{self, Receiver, RecvTimeoutError, Sender, TryRecvError};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration as StdDuration;

use super::Transport;
use edsgen_runtime::frame::CanFrame;

/// The bus. Cloning it gives another handle on the same bus.
#[derive(Debug, Clone, Default)]
pub struct MemoryBus {
    members: Arc<Mutex<Members>>,
}

#[derive(Debug, Default)]
struct Members {
    next_id: u64,
    queues: Vec<(u64, Sender<CanFrame>)>,
}

fn lock(members: &Mutex<Members>) -> MutexGuard<'_, Members> {
    members
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

impl MemoryBus {
    /// An empty bus.
    pub fn new() -> Self {
        MemoryBus::default()
    }

    /// A new endpoint on the bus: it gets every frame sent after this call by the others.
    pub fn endpoint(&self) -> MemoryEndpoint {
        let (queue, frames) = mpsc::channel();
        let mut members = lock(&self.members);
        members.next_id += 1;
        let id = members.next_id;
        members.queues.push((id, queue));
        MemoryEndpoint {
            id,
            members: Arc::clone(&self.members),
            frames,
        }
    }
}

/// One node's connection to a [`MemoryBus`]; leaves the bus when dropped.
#[derive(Debug)]
pub struct MemoryEndpoint {
    id: u64,
    members: Arc<Mutex<Members>>,
    frames: Receiver<CanFrame>,
}

impl Transport for MemoryEndpoint {
    fn send(&mut self, frame: &CanFrame) -> io::Result<()> {
        for (id, queue) in &lock(&self.members).queues {
            if *id != self.id {
                // An endpoint being dropped no longer listens: nothing to deliver to.
                let _ = queue.send(*frame);
            }
        }
        Ok(())
    }

    fn recv_timeout(&mut self, timeout: StdDuration) -> io::Result<Option<CanFrame>> {
        if timeout.is_zero() {
            return match self.frames.try_recv() {
                Ok(frame) => Ok(Some(frame)),
                Err(TryRecvError::Empty | TryRecvError::Disconnected) => Ok(None),
            };
        }
        match self.frames.recv_timeout(timeout) {
            Ok(frame) => Ok(Some(frame)),
            Err(RecvTimeoutError::Timeout | RecvTimeoutError::Disconnected) => Ok(None),
        }
    }
}

impl Drop for MemoryEndpoint {
    fn drop(&mut self) {
        lock(&self.members).queues.retain(|(id, _)| *id != self.id);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const WAIT: StdDuration = StdDuration::from_secs(5);

    fn frame(id: u16, data: &[u8]) -> CanFrame {
        CanFrame::new(id, data).unwrap()
    }

    #[test]
    fn frames_reach_every_other_endpoint_in_order_and_not_the_sender() {
        let bus = MemoryBus::new();
        let mut a = bus.endpoint();
        let mut b = bus.endpoint();
        let mut c = bus.endpoint();
        a.send(&frame(0x181, &[1])).unwrap();
        a.send(&frame(0x182, &[2])).unwrap();
        b.send(&frame(0x183, &[])).unwrap();
        assert_eq!(c.recv_timeout(WAIT).unwrap(), Some(frame(0x181, &[1])));
        assert_eq!(c.recv_timeout(WAIT).unwrap(), Some(frame(0x182, &[2])));
        assert_eq!(c.recv_timeout(WAIT).unwrap(), Some(frame(0x183, &[])));
        assert_eq!(b.recv_timeout(WAIT).unwrap(), Some(frame(0x181, &[1])));
        assert_eq!(b.recv_timeout(WAIT).unwrap(), Some(frame(0x182, &[2])));
        assert_eq!(a.recv_timeout(WAIT).unwrap(), Some(frame(0x183, &[])));
        assert_eq!(a.recv_timeout(StdDuration::ZERO).unwrap(), None);
        assert_eq!(b.recv_timeout(StdDuration::ZERO).unwrap(), None);
    }

    #[test]
    fn endpoints_work_across_threads_and_a_dropped_one_leaves_the_bus() {
        let bus = MemoryBus::new();
        let mut a = bus.endpoint();
        let gone = bus.endpoint();
        drop(gone);
        let other = bus.clone();
        let echo = std::thread::spawn(move || {
            let mut b = other.endpoint();
            b.send(&frame(0x700, &[0])).unwrap();
            let got = b.recv_timeout(WAIT).unwrap().unwrap();
            b.send(&frame(0x580, got.data())).unwrap();
        });
        assert_eq!(a.recv_timeout(WAIT).unwrap(), Some(frame(0x700, &[0])));
        a.send(&frame(0x600, &[0x40, 0x00, 0x10])).unwrap();
        assert_eq!(
            a.recv_timeout(WAIT).unwrap(),
            Some(frame(0x580, &[0x40, 0x00, 0x10]))
        );
        echo.join().unwrap();
        assert_eq!(lock(&bus.members).queues.len(), 1);
    }

    #[test]
    fn nothing_arrives_within_the_timeout_on_a_quiet_bus() {
        let bus = MemoryBus::new();
        let mut a = bus.endpoint();
        let start = std::time::Instant::now();
        assert_eq!(a.recv_timeout(StdDuration::from_millis(20)).unwrap(), None);
        assert!(start.elapsed() >= StdDuration::from_millis(20));
    }
}
