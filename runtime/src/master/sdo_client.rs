//! The SDO client: one channel to one server (CiA 301 §7.2.4), sans-IO like the device's server.
//!
//! It owns the transfer's protocol state and a byte window of `BUF` bytes through which the value
//! streams: the caller feeds a download with [`SdoClient::write_data`] and drains an upload with
//! [`SdoClient::read_data`] while the transfer runs, so a domain of any length passes through it.
//! Frame layouts come from [`crate::wire::sdo`]; no byte is indexed here. This module holds the
//! public API; `state` the protocol state and its transitions.
//!
//! ```
//! use edsgen_runtime::master::SdoClient;
//! use edsgen_runtime::{CanFrame, Entry, Instant};
//!
//! const CONTROLWORD: Entry<u16> = Entry::new(0x6040, 0);
//! let now = Instant::from_millis(0);
//! let mut client: SdoClient = SdoClient::new(3);
//! client.write(now, CONTROLWORD, &0x000F).unwrap();
//! let request = client.poll_transmit(now).unwrap();
//! assert_eq!(request, CanFrame::new(0x603, &[0x2B, 0x40, 0x60, 0, 0x0F, 0, 0, 0]).unwrap());
//! client.handle_frame(now, &CanFrame::new(0x583, &[0x60, 0x40, 0x60, 0, 0, 0, 0, 0]).unwrap());
//! assert!(client.poll_result().unwrap().is_ok());
//! ```
//!
//! A value of the wrong type for the entry does not compile:
//!
//! ```compile_fail
//! # use edsgen_runtime::master::SdoClient;
//! # use edsgen_runtime::{Entry, Instant};
//! const CONTROLWORD: Entry<u16> = Entry::new(0x6040, 0);
//! let mut client: SdoClient = SdoClient::new(3);
//! client.write(Instant::from_millis(0), CONTROLWORD, &-1i16).unwrap();
//! ```

use crate::frame::CanFrame;
use crate::od::access::{Readable, Writable};
use crate::od::entry::{Entry, OdValue};
use crate::od::SdoAbort;
use crate::time::{Duration, Instant};
use crate::wire::sdo::{
    BlockSegment, ClientRequest, InitiatePayload, Multiplexer, ServerResponse, FRAME_LEN,
    MAX_BLOCK_SIZE, SEGMENT_DATA_LEN,
};

#[cfg(feature = "sdo-block")]
use crate::sdo::crc::Crc16;

use super::fifo::ByteFifo;

mod state;

use state::State;

/// The default time a client waits for each answer: generous, since a busy drive may take a
/// while to store a value (python `canopen` waits 0.3 s and its users ask for more).
pub const DEFAULT_TIMEOUT: Duration = Duration::from_millis(1000);

/// The default window: room for a full block-transfer sub-block (127 segments) and its last
/// segment.
pub const DEFAULT_BUFFER: usize = (MAX_BLOCK_SIZE as usize + 1) * SEGMENT_DATA_LEN;

/// The COB-ID a client sends requests to server `node_id` on (600h + node-ID).
pub const fn request_cob_id(node_id: u8) -> u16 {
    0x600 + node_id as u16
}

/// The COB-ID server `node_id` answers on (580h + node-ID).
pub const fn response_cob_id(node_id: u8) -> u16 {
    0x580 + node_id as u16
}

/// How a value travels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Mode {
    /// Expedited when the value fits in 4 bytes (downloads; for uploads the server chooses),
    /// segmented otherwise.
    #[default]
    Normal,
    /// Block transfer with CRC (falls back to [`Mode::Normal`] without the `sdo-block` feature).
    /// An upload of at most the protocol switch threshold's bytes may be answered normally.
    Block,
}

/// How a transfer ended badly.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SdoError {
    /// The server aborted the transfer with this code.
    Server(u32),
    /// No answer within the timeout; the client sent abort 0504 0000.
    Timeout,
    /// The server's answer broke the protocol (or the caller aborted); the client sent an
    /// abort with this code.
    Client(u32),
}

impl SdoError {
    /// The abort code sent on the bus, by either side.
    pub const fn code(self) -> u32 {
        match self {
            SdoError::Server(code) | SdoError::Client(code) => code,
            SdoError::Timeout => SdoAbort::Timeout.code(),
        }
    }
}

/// A transfer that completed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Completed {
    /// The entry.
    pub mux: Multiplexer,
    /// The value's length in bytes.
    pub size: u32,
    /// Whether it was an upload (a read).
    pub upload: bool,
    /// How the value travelled: a block upload the server answered normally (a value at most
    /// the protocol switch threshold long) says so here.
    pub transfer: Transfer,
}

/// How a completed transfer went on the wire.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Transfer {
    /// In the initiate request or response.
    Expedited,
    /// In segments.
    Segmented,
    /// In blocks.
    Block,
}

/// Why a transfer could not start.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StartError {
    /// A transfer is in progress on this channel.
    Busy,
    /// The value does not fit the entry's width or the window.
    Value,
}

/// An SDO client channel to one server.
///
/// Start a transfer with [`upload`](Self::upload), [`download`](Self::download) or the typed
/// [`read`](Self::read) / [`write`](Self::write); then feed it frames from the server with
/// [`handle_frame`](Self::handle_frame), send what [`poll_transmit`](Self::poll_transmit)
/// gives, call [`handle_timeout`](Self::handle_timeout) at [`poll_timeout`](Self::poll_timeout),
/// and take the outcome from [`poll_result`](Self::poll_result).
#[derive(Debug, Clone)]
pub struct SdoClient<const BUF: usize = DEFAULT_BUFFER> {
    server: u8,
    timeout: Duration,
    pst: u8,
    state: State,
    mux: Multiplexer,
    /// The value's size: announced by the caller (download) or the server (upload).
    size: Option<u32>,
    /// A download of unannounced size: the caller has said that no more bytes follow.
    ended: bool,
    /// Bytes of the value moved so far: received (upload) or acknowledged (download).
    count: u32,
    #[cfg(feature = "sdo-block")]
    crc: Crc16,
    #[cfg(feature = "sdo-block")]
    crc_on: bool,
    /// The last segment of a block upload, held until the end request says how much is data.
    #[cfg(feature = "sdo-block")]
    held: [u8; SEGMENT_DATA_LEN],
    fifo: ByteFifo<BUF>,
    tx: Option<[u8; FRAME_LEN]>,
    deadline: Option<Instant>,
    result: Option<Result<Completed, SdoError>>,
}

impl<const BUF: usize> SdoClient<BUF> {
    const WINDOW_OK: () = assert!(BUF >= 2 * SEGMENT_DATA_LEN, "the window holds two segments");

    /// A client of server `node_id` (1..=127) with the default timeout.
    pub const fn new(node_id: u8) -> Self {
        #[allow(clippy::let_unit_value)]
        let () = Self::WINDOW_OK;
        SdoClient {
            server: node_id,
            timeout: DEFAULT_TIMEOUT,
            pst: 0,
            state: State::Idle,
            mux: Multiplexer::new(0, 0),
            size: None,
            ended: false,
            count: 0,
            #[cfg(feature = "sdo-block")]
            crc: Crc16::new(),
            #[cfg(feature = "sdo-block")]
            crc_on: false,
            #[cfg(feature = "sdo-block")]
            held: [0; SEGMENT_DATA_LEN],
            fifo: ByteFifo::new(),
            tx: None,
            deadline: None,
            result: None,
        }
    }

    /// The server's node-ID.
    pub const fn node_id(&self) -> u8 {
        self.server
    }

    /// How long the client waits for each answer before it aborts with 0504 0000.
    pub fn set_timeout(&mut self, timeout: Duration) {
        self.timeout = timeout;
    }

    /// The timeout per answer.
    pub const fn timeout(&self) -> Duration {
        self.timeout
    }

    /// The protocol switch threshold a block upload offers: a server may send a value of at
    /// most this many bytes by a normal upload instead (0, the default: never).
    pub fn set_protocol_switch_threshold(&mut self, bytes: u8) {
        self.pst = bytes;
    }

    /// The entry of the transfer in progress or the last one.
    pub const fn mux(&self) -> Multiplexer {
        self.mux
    }

    /// Whether a transfer is in progress.
    pub fn is_busy(&self) -> bool {
        self.state != State::Idle
    }

    /// Starts reading (index, sub).
    pub fn upload(&mut self, now: Instant, mux: Multiplexer, mode: Mode) -> Result<(), StartError> {
        self.begin(now, mux, None)?;
        self.state = State::UploadInitiate;
        self.tx = Some(match mode {
            #[cfg(feature = "sdo-block")]
            Mode::Block => ClientRequest::BlockUploadInitiate {
                mux,
                crc: true,
                blksize: self.upload_block_size().max(1),
                pst: self.pst,
            }
            .emit(),
            _ => ClientRequest::InitiateUpload { mux }.emit(),
        });
        Ok(())
    }

    /// Starts writing a value of `size` bytes to (index, sub). Feed its bytes with
    /// [`write_data`](Self::write_data), before or while it travels.
    pub fn download(
        &mut self,
        now: Instant,
        mux: Multiplexer,
        size: u32,
        mode: Mode,
    ) -> Result<(), StartError> {
        self.begin(now, mux, Some(size))?;
        match mode {
            #[cfg(feature = "sdo-block")]
            Mode::Block => {
                self.state = State::BlockDownloadInitiate;
                self.tx = Some(
                    ClientRequest::BlockDownloadInitiate {
                        mux,
                        crc: true,
                        size: Some(size),
                    }
                    .emit(),
                );
            }
            _ if (1..=4).contains(&size) => {
                // The value rides in the initiate request: it goes once its bytes are here.
                self.state = State::DownloadInitiate {
                    sent: false,
                    expedited: true,
                };
            }
            _ => {
                self.state = State::DownloadInitiate {
                    sent: true,
                    expedited: false,
                };
                self.tx = Some(
                    ClientRequest::InitiateDownload {
                        mux,
                        payload: InitiatePayload::Sized(size),
                    }
                    .emit(),
                );
            }
        }
        Ok(())
    }

    /// Starts writing a value whose length is not known yet (a stream) to (index, sub): feed
    /// its bytes with [`write_data`](Self::write_data) and say where it ends with
    /// [`end_data`](Self::end_data). The size is not indicated: a segmented download's initiate
    /// request has `s` clear (never expedited), a block download's too, and the block end
    /// request's `n` tells the server how much of the last segment is data (CiA 301
    /// §7.2.4.3.3, §7.2.4.3.9). A segment goes once the bytes after it (or the end) are known,
    /// so that the last one is marked as such.
    pub fn download_unsized(
        &mut self,
        now: Instant,
        mux: Multiplexer,
        mode: Mode,
    ) -> Result<(), StartError> {
        self.begin(now, mux, None)?;
        let request = match mode {
            #[cfg(feature = "sdo-block")]
            Mode::Block => {
                self.state = State::BlockDownloadInitiate;
                ClientRequest::BlockDownloadInitiate {
                    mux,
                    crc: true,
                    size: None,
                }
            }
            _ => {
                self.state = State::DownloadInitiate {
                    sent: true,
                    expedited: false,
                };
                ClientRequest::InitiateDownload {
                    mux,
                    payload: InitiatePayload::Unsized,
                }
            }
        };
        self.tx = Some(request.emit());
        Ok(())
    }

    /// Ends the value of a [`download_unsized`](Self::download_unsized): the bytes written so
    /// far are all of it. Without effect on other transfers.
    pub fn end_data(&mut self) {
        if self.is_download() && self.size.is_none() {
            self.ended = true;
        }
    }

    /// Starts a typed read of `entry` (an address of any device's generated module); take the
    /// value with [`take_value`](Self::take_value) once [`poll_result`](Self::poll_result)
    /// reports it complete.
    pub fn read<T: OdValue, D, A: Readable>(
        &mut self,
        now: Instant,
        entry: Entry<T, D, A>,
    ) -> Result<(), StartError> {
        self.upload(now, Multiplexer::new(entry.index, entry.sub), Mode::Normal)
    }

    /// Starts a typed write of `value` to `entry` (expedited when it fits in 4 bytes).
    pub fn write<T: OdValue, D, A: Writable>(
        &mut self,
        now: Instant,
        entry: Entry<T, D, A>,
        value: &T,
    ) -> Result<(), StartError> {
        if self.is_busy() {
            return Err(StartError::Busy);
        }
        self.fifo.clear();
        let size = self
            .fifo
            .fill_with(|buf| entry.encode(value, buf))
            .ok_or(StartError::Value)?;
        let mux = Multiplexer::new(entry.index, entry.sub);
        self.download(now, mux, size as u32, Mode::Normal)?;
        // `begin` emptied the window; the encoded bytes are still in place.
        self.fifo.fill_with(|_| Some(size));
        Ok(())
    }

    /// The value of a completed read of `entry`, from the window (emptied by this call); `None`
    /// if its bytes do not decode as `T` (a length not matching the type).
    pub fn take_value<T: OdValue, D, A>(&mut self, entry: &Entry<T, D, A>) -> Option<T> {
        let value = entry.decode(self.fifo.contiguous());
        self.fifo.clear();
        value
    }

    /// Adds bytes of the value being downloaded; returns how many the window took.
    pub fn write_data(&mut self, data: &[u8]) -> usize {
        if !self.is_download() || self.ended {
            return 0;
        }
        // A value of unannounced size may take up to the most a transfer counts.
        let size = self.size.unwrap_or(u32::MAX);
        let wanted = ((size - self.count) as usize).saturating_sub(self.fifo.len());
        self.fifo.push(&data[..data.len().min(wanted)])
    }

    /// Takes received bytes of the value being (or just) uploaded; returns how many.
    pub fn read_data(&mut self, out: &mut [u8]) -> usize {
        if self.is_download() {
            return 0;
        }
        self.fifo.pop(out)
    }

    /// Received bytes waiting in the window.
    pub fn available(&self) -> usize {
        if self.is_download() {
            return 0;
        }
        self.fifo.len()
    }

    /// Aborts the transfer in progress with `code` (the caller's reason).
    pub fn abort(&mut self, code: u32) {
        if self.is_busy() {
            self.finish_abort(SdoError::Client(code));
        }
    }

    /// Forgets the transfer in progress without telling the server, as for a node-ID that never
    /// answered (a scan); no result is reported.
    pub fn cancel(&mut self) {
        self.state = State::Idle;
        self.deadline = None;
        self.tx = None;
        self.result = None;
        self.fifo.clear();
    }

    /// The outcome of the last transfer, once.
    pub fn poll_result(&mut self) -> Option<Result<Completed, SdoError>> {
        self.result.take()
    }

    /// When the client next needs [`handle_timeout`](Self::handle_timeout).
    pub fn poll_timeout(&self) -> Option<Instant> {
        if self.is_busy() {
            self.deadline
        } else {
            None
        }
    }

    /// Aborts the transfer if its answer is overdue at `now`.
    pub fn handle_timeout(&mut self, now: Instant) {
        if self.is_busy() && self.deadline.is_some_and(|at| at <= now) {
            self.finish_abort(SdoError::Timeout);
        }
    }

    /// The next frame to send to the server.
    pub fn poll_transmit(&mut self, now: Instant) -> Option<CanFrame> {
        let data = self.tx.take().or_else(|| self.next_frame())?;
        if self.is_busy() {
            self.deadline = Some(now + self.timeout);
        }
        CanFrame::new(request_cob_id(self.server), &data)
    }

    /// Takes a frame from the bus; frames not from this client's server are ignored.
    pub fn handle_frame(&mut self, now: Instant, frame: &CanFrame) {
        if frame.is_remote()
            || frame.std_id() != Some(response_cob_id(self.server))
            || !self.is_busy()
        {
            return;
        }
        self.deadline = Some(now + self.timeout);
        let data = frame.data();
        if let State::BlockUploadSub { .. } = self.state {
            // A sub-block segment has no command specifier; an abort is the one message
            // whose first byte reads as the invalid sequence number 0.
            match BlockSegment::parse(data) {
                Ok(segment) if segment.seqno != 0 => self.block_upload_segment(segment),
                _ => match ServerResponse::parse(data) {
                    Ok(ServerResponse::Abort { code, .. }) => {
                        self.finish(Err(SdoError::Server(code)))
                    }
                    _ => self.protocol_error(SdoAbort::InvalidSequence),
                },
            }
            return;
        }
        match ServerResponse::parse(data) {
            Ok(ServerResponse::Abort { code, .. }) => self.finish(Err(SdoError::Server(code))),
            Ok(response) => self.handle_response(response),
            Err(_) => self.protocol_error(SdoAbort::InvalidCommand),
        }
    }
}
