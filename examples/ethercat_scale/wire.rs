//! The MainDevice's frames on the wire from the thread that runs the cycle: ethercrab's futures
//! are polled here, the frames they queue written to a packet socket at once, and the answers
//! fed back, with no executor and no second thread.
//!
//! Why: with `tx_rx_task` on tokio, an answer wakes async-io's reactor thread (its `epoll` on
//! the socket), which wakes the tokio thread (an eventfd write to tokio's own `epoll`), which
//! reads it and polls the group's future: two threads woken per frame, three or four frames a
//! cycle at 64 SubDevices. Here an answer wakes the one thread that waits for it in `poll(2)`; sending
//! costs no wake-up either way (the frame is written by the thread that queued it). The socket
//! also shows our own frames going out, so each frame is read twice, the first time at once.
//! ethercrab's timeouts are async-io timers: each frame's timer still notes itself with
//! async-io's thread, though nothing here waits on that thread (see `Inline::settle`).

use std::future::Future;
use std::pin::pin;
use std::task::{Context, Poll, Waker};
use std::time::{Duration, Instant};

use edsgen_sim::packet_socket::PacketSocket;
use ethercrab::{PduRx, PduTx};

/// EtherCAT's EtherType.
const ETHERTYPE: u16 = 0x88A4;
/// How long one wait for an answer lasts before the futures are polled again (their timeouts).
const WAIT: Duration = Duration::from_millis(1);

/// A packet socket and ethercrab's two ends of its PDU storage.
pub struct Wire<'sto> {
    socket: PacketSocket,
    tx: PduTx<'sto>,
    rx: PduRx<'sto>,
    buf: Vec<u8>,
    /// When the oldest frame still unanswered was sent.
    sent_at: Option<Instant>,
    /// Frames answered, and the time spent waiting for answers (the wire, the simulator and
    /// the wake-ups), since [`Wire::take_counts`].
    answered: u64,
    waited: Duration,
}

impl<'sto> Wire<'sto> {
    /// Opens `iface` for EtherCAT frames.
    pub fn open(iface: &str, tx: PduTx<'sto>, rx: PduRx<'sto>) -> Result<Self, String> {
        let socket =
            PacketSocket::open(iface, ETHERTYPE, WAIT).map_err(|e| format!("{iface}: {e}"))?;
        Ok(Wire {
            socket,
            tx,
            rx,
            buf: vec![0; 2048],
            sent_at: None,
            answered: 0,
            waited: Duration::ZERO,
        })
    }

    /// The frames answered and the time waited for them since the last call.
    pub fn take_counts(&mut self) -> (u64, Duration) {
        let counts = (self.answered, self.waited);
        self.answered = 0;
        self.waited = Duration::ZERO;
        counts
    }

    /// Runs `future` (anything of ethercrab's that sends frames) to its end on this thread.
    pub fn run<F: Future>(&mut self, future: F) -> Result<F::Output, String> {
        let mut future = pin!(future);
        // Nothing needs waking: the future is polled again after every frame and every `WAIT`.
        let mut cx = Context::from_waker(Waker::noop());
        loop {
            if let Poll::Ready(output) = future.as_mut().poll(&mut cx) {
                return Ok(output);
            }
            while let Some(frame) = self.tx.next_sendable_frame() {
                let socket = &mut self.socket;
                frame
                    .send_blocking(|data| {
                        socket
                            .send(data)
                            .map(|()| data.len())
                            .map_err(|_| ethercrab::error::Error::SendFrame)
                    })
                    .map_err(|e| format!("send: {e:?}"))?;
                self.sent_at.get_or_insert_with(Instant::now);
            }
            if let Some(n) = self.socket.recv(&mut self.buf).map_err(|e| e.to_string())? {
                // Our own frames going out come back here too, and ethercrab ignores them; an
                // answer that comes after its frame timed out is refused, and that frame's
                // future has already failed with the timeout: neither stops the wire.
                if let Ok(ethercrab::ReceiveAction::Processed) =
                    self.rx.receive_frame(&self.buf[..n])
                {
                    if let Some(sent) = self.sent_at.take() {
                        self.waited += sent.elapsed();
                        self.answered += 1;
                    }
                }
            }
        }
    }
}
