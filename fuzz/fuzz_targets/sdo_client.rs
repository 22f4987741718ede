//! Fuzz the master's SDO client (`master::SdoClient`): transfers of every type (expedited,
//! segmented and block; upload and download; sized and unsized downloads) started from the
//! input, with the caller feeding and draining the window and time passing in between. The
//! answers come from the runtime's SDO server (serving the master tests' `DomainOd`: a domain at
//! 2100h, a word at 2101h) through a channel that delivers, drops, repeats or corrupts each of
//! them as the input says, mixed with arbitrary frames; so the fuzzer reaches the late steps of
//! long transfers (a sub-block's acknowledgement, the block end, the last segment) and breaks
//! them there.
//!
//! Properties: nothing panics; a busy client always has a deadline, and it reports a result
//! exactly when it stops being busy; a completed transfer reports its own entry and direction,
//! an upload's size is the number of bytes the caller can read, a download's the size announced
//! (or, unsized, the bytes the caller gave); every frame it sends is an 8-byte request on
//! 600h + node-ID; and at the end of the input, once the caller has given what it owes, the
//! transfer ends (a result or an abort) at the latest at its deadline.
#![no_main]

use edsgen_host::vbus::BusDevice;
use edsgen_runtime::master::sdo_client::DEFAULT_BUFFER;
use edsgen_runtime::master::{Completed, Mode, SdoClient, SdoError, StartError};
use edsgen_runtime::wire::sdo::Multiplexer;
use edsgen_runtime::{CanFrame, Duration, Instant};
use libfuzzer_sys::fuzz_target;
use std::collections::VecDeque;

#[path = "../../runtime/tests/master_support/mod.rs"]
mod master_support;

use master_support::{pattern, DomainServer};

/// The server's node-ID.
const NODE_ID: u8 = 5;

/// The small window: 3 segments, so that a full window is reached often. Odd-length inputs run
/// with it, even-length ones with the default window (a sub-block of 127 segments).
const SMALL: usize = 21;

/// What the caller asked for and has seen of the transfer in progress.
#[derive(Default)]
struct Transfer {
    mux: Multiplexer,
    upload: bool,
    /// The announced size of a download (`None`: unsized, or an upload).
    size: Option<u32>,
    /// Bytes the caller gave (download) or took (upload).
    moved: u64,
}

struct Harness<'a, const BUF: usize> {
    client: SdoClient<BUF>,
    server: DomainServer,
    /// The server's answers not delivered yet.
    answers: VecDeque<CanFrame>,
    now: Instant,
    transfer: Transfer,
    bytes: std::slice::Iter<'a, u8>,
}

impl<const BUF: usize> Harness<'_, BUF> {
    fn byte(&mut self) -> u8 {
        self.bytes.next().copied().unwrap_or(0)
    }

    /// Starts the transfer the next bytes describe.
    fn start(&mut self) {
        let kind = self.byte();
        // The domain (most often), the word, or an entry the server does not have.
        let mux = match kind >> 4 {
            0..=9 => Multiplexer::new(0x2100, 0),
            10..=13 => Multiplexer::new(0x2101, 0),
            n => Multiplexer::new(0x2100 + u16::from(n), self.byte() % 4),
        };
        // Mostly small sizes, so that a download completes within an input; sometimes any.
        let size = match self.byte() {
            b @ 0..=0xEF => u32::from(b % 64),
            _ => u32::from_le_bytes([self.byte(), self.byte(), self.byte(), self.byte()]),
        };
        let busy = self.client.is_busy();
        let mode = if kind & 8 == 0 {
            Mode::Normal
        } else {
            Mode::Block
        };
        let pst = self.byte();
        self.client.set_protocol_switch_threshold(pst);
        let (started, upload, announced) = match kind % 4 {
            0 => (self.client.upload(self.now, mux, mode), true, None),
            1 | 2 => (
                self.client.download(self.now, mux, size, mode),
                false,
                Some(size),
            ),
            _ => (
                self.client.download_unsized(self.now, mux, mode),
                false,
                None,
            ),
        };
        match started {
            Ok(()) => {
                assert!(!busy, "a transfer started on a busy client");
                assert!(self.client.is_busy(), "a started transfer is not busy");
                if upload {
                    // The server answers with a domain of the size (the request reaches it
                    // only at the next drain).
                    self.server.od.domain = pattern(size.min(4096) as usize);
                }
                self.transfer = Transfer {
                    mux,
                    upload,
                    size: announced,
                    moved: 0,
                };
            }
            Err(StartError::Busy) => assert!(busy, "Busy from an idle client"),
            Err(StartError::Value) => panic!("Value from a start without a value"),
        }
    }

    /// A frame from the bus: a flags byte (bits 4..7 the length, bit 0 a remote request, bit 1
    /// the transfer's entry in bytes 1..=3, bit 2 another node's COB-ID), then its data.
    fn frame(&mut self) {
        let flags = self.byte();
        let len = usize::from(flags >> 4).min(8);
        let mut data = [0u8; 8];
        for byte in &mut data[..len] {
            *byte = self.byte();
        }
        if flags & 2 != 0 && len >= 4 {
            data[1..3].copy_from_slice(&self.transfer.mux.index.to_le_bytes());
            data[3] = self.transfer.mux.sub;
        }
        let id = if flags & 4 == 0 {
            0x580 + u16::from(NODE_ID)
        } else {
            0x580 + u16::from(NODE_ID ^ 1)
        };
        let frame = if flags & 1 == 1 {
            CanFrame::remote(id, len as u8)
        } else {
            CanFrame::from_parts(id, data, len as u8)
        };
        self.client.handle_frame(self.now, &frame);
    }

    /// The caller gives `n` bytes of the value (a download) or takes up to `n` (an upload).
    fn caller(&mut self, n: usize) {
        if self.transfer.upload {
            let mut out = vec![0u8; n];
            self.transfer.moved += self.client.read_data(&mut out) as u64;
        } else {
            let data: Vec<u8> = (0..n).map(|_| self.byte()).collect();
            self.transfer.moved += self.client.write_data(&data) as u64;
        }
    }

    /// Sends what the client has to send to the server, and queues the server's answers.
    fn drain(&mut self) {
        let mut sent = 0;
        while let Some(frame) = self.client.poll_transmit(self.now) {
            assert_eq!(frame.std_id(), Some(0x600 + u16::from(NODE_ID)));
            assert_eq!(frame.dlc(), 8, "{frame:?}");
            sent += 1;
            assert!(sent <= 200, "poll_transmit never runs dry");
            self.server.handle_frame(self.now, &frame);
            while let Some(answer) = self.server.poll_transmit(self.now) {
                self.answers.push_back(answer);
            }
        }
    }

    /// Delivers the server's next answer as the next byte says: most often as it is; below
    /// 20h with one byte changed (byte `b % 8` XORed with the next input byte, made odd so that
    /// it changes); 20h to 27h not at all (lost); 28h to 2Fh twice.
    fn deliver(&mut self) {
        let Some(answer) = self.answers.pop_front() else {
            return;
        };
        let how = self.byte();
        match how {
            0x00..=0x1F => {
                let mut data = [0u8; 8];
                data[..answer.data().len()].copy_from_slice(answer.data());
                data[usize::from(how % 8)] ^= self.byte() | 1;
                let id = answer.std_id().unwrap_or(0);
                let changed = CanFrame::from_parts(id, data, answer.dlc());
                self.client.handle_frame(self.now, &changed);
            }
            0x20..=0x27 => {}
            0x28..=0x2F => {
                self.client.handle_frame(self.now, &answer);
                self.client.handle_frame(self.now, &answer);
            }
            _ => self.client.handle_frame(self.now, &answer),
        }
    }

    /// Checks the properties after one step; `was_busy` is whether the client was busy before.
    fn check(&mut self, was_busy: bool) {
        let busy = self.client.is_busy();
        if busy {
            assert!(
                self.client.poll_timeout().is_some(),
                "busy without a deadline"
            );
        }
        let result = self.client.poll_result();
        if was_busy && !busy {
            assert!(result.is_some(), "the transfer ended without a result");
        }
        let Some(result) = result else {
            return;
        };
        assert!(!busy, "a result while busy: {result:?}");
        assert!(was_busy, "a result without a transfer: {result:?}");
        if let Ok(completed) = result {
            self.completed(completed);
        }
    }

    fn completed(&mut self, completed: Completed) {
        let transfer = &mut self.transfer;
        assert_eq!(completed.mux, transfer.mux);
        assert_eq!(completed.upload, transfer.upload);
        if transfer.upload {
            let mut rest = vec![0u8; completed.size as usize + 64];
            transfer.moved += self.client.read_data(&mut rest) as u64;
            assert_eq!(
                transfer.moved,
                u64::from(completed.size),
                "the caller read other than the size of {completed:?}"
            );
        } else {
            let expected = transfer.size.map_or(transfer.moved, u64::from);
            assert_eq!(u64::from(completed.size), expected, "{completed:?}");
        }
    }

    /// The end of the input: the caller gives what it owes, then time runs to the deadline.
    fn finish(&mut self) {
        if !self.client.is_busy() {
            return;
        }
        if self.transfer.size.is_some() {
            // A sized download: the rest of the value, as far as the window takes it.
            loop {
                let n = self.client.write_data(&[0xA5; 7]);
                if n == 0 {
                    break;
                }
                self.transfer.moved += n as u64;
            }
        }
        if !self.transfer.upload {
            self.client.end_data();
        }
        self.drain();
        self.check(true);
        if !self.client.is_busy() {
            return;
        }
        let deadline = self.client.poll_timeout().expect("busy without a deadline");
        self.now = deadline;
        self.client.handle_timeout(deadline);
        assert!(!self.client.is_busy(), "busy after its deadline");
        assert_eq!(self.client.poll_result(), Some(Err(SdoError::Timeout)));
        self.drain();
    }
}

fuzz_target!(|input: &[u8]| {
    if input.len() % 2 == 1 {
        run::<SMALL>(input);
    } else {
        run::<DEFAULT_BUFFER>(input);
    }
});

/// Runs the transfers `input` describes on a client with a window of `BUF` bytes.
fn run<const BUF: usize>(input: &[u8]) {
    let mut client = SdoClient::<BUF>::new(NODE_ID);
    client.set_timeout(Duration::from_millis(100));
    let mut h = Harness {
        client,
        server: DomainServer::new(NODE_ID),
        answers: VecDeque::new(),
        now: Instant::from_millis(0),
        transfer: Transfer::default(),
        bytes: input.iter(),
    };
    h.start();
    h.drain();
    while let Some(&op) = h.bytes.next() {
        let was_busy = h.client.is_busy();
        match op % 12 {
            0..=3 => h.deliver(),
            4 => h.frame(),
            5 | 11 => h.drain(),
            6 => {
                let step = u64::from(h.byte()) * 1000;
                h.now = h.now + Duration::from_micros(step);
                if h.client.poll_timeout().is_some_and(|at| at <= h.now) {
                    h.client.handle_timeout(h.now);
                }
                if h.server.poll_timeout().is_some_and(|at| at <= h.now) {
                    h.server.handle_timeout(h.now);
                }
            }
            7 => {
                let n = usize::from(h.byte() % 32);
                h.caller(n);
            }
            8 => h.client.end_data(),
            9 => h.start(),
            _ => {
                if h.byte() == 0xAB {
                    h.client.abort(0x0800_0000);
                } else {
                    h.drain();
                }
            }
        }
        h.check(was_busy);
    }
    h.finish();
}
