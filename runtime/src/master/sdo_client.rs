//! The SDO client: one channel to one server (CiA 301 §7.2.4), sans-IO like the device's server.
//!
//! It owns the transfer's protocol state and a byte window of `BUF` bytes through which the value
//! streams: the caller feeds a download with [`SdoClient::write_data`] and drains an upload with
//! [`SdoClient::read_data`] while the transfer runs, so a domain of any length passes through it.
//! Frame layouts come from [`crate::wire::sdo`]; no byte is indexed here.
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
    BlockSegment, ClientRequest, InitiatePayload, Multiplexer, SegmentData, ServerResponse,
    FRAME_LEN, MAX_BLOCK_SIZE, SEGMENT_DATA_LEN,
};

#[cfg(feature = "sdo-block")]
use crate::sdo::crc::Crc16;

use super::fifo::ByteFifo;

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
}

/// Why a transfer could not start.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StartError {
    /// A transfer is in progress on this channel.
    Busy,
    /// The value does not fit the entry's width or the window.
    Value,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(not(feature = "sdo-block"), allow(dead_code))]
enum State {
    Idle,
    /// Initiate upload sent (normal or block), waiting for the answer.
    UploadInitiate,
    /// Segmented upload: the next request carries `toggle`; `waiting` once it is sent.
    UploadSegment {
        toggle: bool,
        waiting: bool,
    },
    /// Block upload: receiving a sub-block of `blksize`, next in-order sequence number
    /// `expected`; `last` once the last segment arrived; `ack_due` when the sub-block is over.
    BlockUploadSub {
        expected: u8,
        blksize: u8,
        last: bool,
        ack_due: bool,
    },
    /// Block upload: the last sub-block is acknowledged, waiting for the end request.
    BlockUploadEnd,
    /// Initiate download: `sent` once on the bus; `expedited` if the value travels in it.
    DownloadInitiate {
        sent: bool,
        expedited: bool,
    },
    /// Segmented download: the next segment carries `toggle`; `waiting` for its answer.
    DownloadSegment {
        toggle: bool,
        waiting: bool,
    },
    /// Block download initiate sent, waiting for the answer.
    BlockDownloadInitiate,
    /// Sending a sub-block: `sent` of `blksize` segments, `last` once the value's last segment
    /// went; `waiting` for the acknowledgement.
    BlockDownloadSub {
        blksize: u8,
        sent: u8,
        last: bool,
        waiting: bool,
    },
    /// Block download end sent, waiting for the answer.
    BlockDownloadEnd,
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

    fn begin(
        &mut self,
        now: Instant,
        mux: Multiplexer,
        size: Option<u32>,
    ) -> Result<(), StartError> {
        if self.is_busy() {
            return Err(StartError::Busy);
        }
        self.mux = mux;
        self.size = size;
        self.ended = false;
        self.count = 0;
        #[cfg(feature = "sdo-block")]
        {
            self.crc = Crc16::new();
            self.crc_on = false;
        }
        self.fifo.clear();
        self.result = None;
        self.deadline = Some(now + self.timeout);
        Ok(())
    }

    fn is_download(&self) -> bool {
        matches!(
            self.state,
            State::DownloadInitiate { .. }
                | State::DownloadSegment { .. }
                | State::BlockDownloadInitiate
                | State::BlockDownloadSub { .. }
                | State::BlockDownloadEnd
        )
    }

    /// Segments per sub-block the window can take now, keeping room for a held last segment.
    fn upload_block_size(&self) -> u8 {
        let segments = self.fifo.free().saturating_sub(SEGMENT_DATA_LEN) / SEGMENT_DATA_LEN;
        segments.min(usize::from(MAX_BLOCK_SIZE)) as u8
    }

    /// Bytes of the value still to go after those acknowledged; `None` while a value of
    /// unannounced size has not ended.
    fn remaining(&self) -> Option<usize> {
        match self.size {
            Some(size) => Some((size - self.count) as usize),
            // The window holds every byte not yet acknowledged.
            None => self.ended.then_some(self.fifo.len()),
        }
    }

    /// A frame the state owes the server once the caller's data or room allows it.
    fn next_frame(&mut self) -> Option<[u8; FRAME_LEN]> {
        match self.state {
            State::UploadSegment {
                toggle,
                waiting: false,
            } if self.fifo.free() >= SEGMENT_DATA_LEN => {
                self.state = State::UploadSegment {
                    toggle,
                    waiting: true,
                };
                Some(ClientRequest::UploadSegment { toggle }.emit())
            }
            State::BlockUploadSub {
                expected,
                blksize,
                last,
                ack_due: true,
            } => {
                let ackseq = expected - 1;
                if last {
                    // The last segment came in order: the whole value is here.
                    self.state = State::BlockUploadEnd;
                    return Some(ClientRequest::BlockUploadAck { ackseq, blksize }.emit());
                }
                let next = self.upload_block_size();
                if next == 0 {
                    return None; // the caller drains the window first
                }
                self.state = State::BlockUploadSub {
                    expected: 1,
                    blksize: next,
                    last: false,
                    ack_due: false,
                };
                Some(
                    ClientRequest::BlockUploadAck {
                        ackseq,
                        blksize: next,
                    }
                    .emit(),
                )
            }
            State::DownloadInitiate {
                sent: false,
                expedited: true,
            } if Some(self.fifo.len()) == self.remaining() => {
                let mut data = [0u8; 4];
                let len = self.fifo.peek(0, &mut data) as u8;
                self.state = State::DownloadInitiate {
                    sent: true,
                    expedited: true,
                };
                let payload = InitiatePayload::Expedited { data, len };
                Some(
                    ClientRequest::InitiateDownload {
                        mux: self.mux,
                        payload,
                    }
                    .emit(),
                )
            }
            State::DownloadSegment {
                toggle,
                waiting: false,
            } => {
                let (bytes, len, last) = self.segment_at(0)?;
                let data = SegmentData::new(&bytes[..len])?;
                self.state = State::DownloadSegment {
                    toggle,
                    waiting: true,
                };
                Some(ClientRequest::DownloadSegment { toggle, data, last }.emit())
            }
            State::BlockDownloadSub {
                blksize,
                sent,
                last: false,
                waiting: false,
            } => {
                let (bytes, _, last) = self.segment_at(usize::from(sent) * SEGMENT_DATA_LEN)?;
                let sent = sent + 1;
                self.state = State::BlockDownloadSub {
                    blksize,
                    sent,
                    last,
                    waiting: last || sent == blksize,
                };
                Some(
                    BlockSegment {
                        seqno: sent,
                        last,
                        data: bytes,
                    }
                    .emit(),
                )
            }
            _ => None,
        }
    }

    /// The download segment `offset` bytes past the acknowledged ones, if the caller has
    /// supplied its bytes: its 7 bytes (zero past the data), how many are data, and whether it
    /// is the value's last.
    /// A value of unannounced size that has not ended gives a segment once a byte after it is
    /// here: only then is it known not to be the last.
    fn segment_at(&self, offset: usize) -> Option<([u8; SEGMENT_DATA_LEN], usize, bool)> {
        let (len, last) = match self.remaining() {
            Some(remaining) => {
                let remaining = remaining.checked_sub(offset)?;
                (
                    remaining.min(SEGMENT_DATA_LEN),
                    remaining <= SEGMENT_DATA_LEN,
                )
            }
            None if self.fifo.len() > offset + SEGMENT_DATA_LEN => (SEGMENT_DATA_LEN, false),
            None => return None,
        };
        if self.fifo.len() < offset + len {
            return None;
        }
        let mut bytes = [0u8; SEGMENT_DATA_LEN];
        self.fifo.peek(offset, &mut bytes[..len]);
        Some((bytes, len, last))
    }

    fn handle_response(&mut self, response: ServerResponse) {
        match (self.state, response) {
            (State::UploadInitiate, ServerResponse::InitiateUpload { mux, payload }) => {
                if mux != self.mux {
                    return self.protocol_error(SdoAbort::General);
                }
                match payload {
                    InitiatePayload::Expedited { data, len } => {
                        self.fifo.push(&data[..usize::from(len)]);
                        self.complete(u32::from(len));
                    }
                    InitiatePayload::ExpeditedUnsized { data } => {
                        self.fifo.push(&data);
                        self.complete(4);
                    }
                    InitiatePayload::Sized(size) => self.start_upload_segments(Some(size)),
                    InitiatePayload::Unsized => self.start_upload_segments(None),
                }
            }
            (
                State::UploadSegment {
                    toggle,
                    waiting: true,
                },
                ServerResponse::UploadSegment {
                    toggle: echoed,
                    data,
                    last,
                },
            ) => {
                if echoed != toggle {
                    return self.protocol_error(SdoAbort::ToggleBit);
                }
                self.fifo.push(data.as_slice());
                self.count += data.as_slice().len() as u32;
                if self.size.is_some_and(|size| self.count > size) {
                    return self.protocol_error(SdoAbort::LengthTooHigh);
                }
                if last {
                    if self.size.is_some_and(|size| self.count != size) {
                        return self.protocol_error(SdoAbort::LengthTooLow);
                    }
                    self.complete(self.count);
                } else {
                    self.state = State::UploadSegment {
                        toggle: !toggle,
                        waiting: false,
                    };
                }
            }
            #[cfg(feature = "sdo-block")]
            (State::UploadInitiate, ServerResponse::BlockUploadInitiate { mux, crc, size }) => {
                if mux != self.mux {
                    return self.protocol_error(SdoAbort::General);
                }
                self.crc_on = crc;
                self.size = size;
                self.state = State::BlockUploadSub {
                    expected: 1,
                    blksize: self.upload_block_size().max(1),
                    last: false,
                    ack_due: false,
                };
                self.tx = Some(ClientRequest::BlockUploadStart.emit());
            }
            #[cfg(feature = "sdo-block")]
            (State::BlockUploadEnd, ServerResponse::BlockUploadEnd { unused, crc }) => {
                let len = SEGMENT_DATA_LEN.saturating_sub(usize::from(unused));
                let held = self.held;
                self.accept_upload_bytes(&held[..len]);
                if self.size.is_some_and(|size| self.count != size) {
                    return self.protocol_error(SdoAbort::LengthMismatch);
                }
                if self.crc_on && crc != self.crc.value() {
                    return self.protocol_error(SdoAbort::CrcError);
                }
                self.tx = Some(ClientRequest::BlockUploadEnd.emit());
                self.complete(self.count);
            }
            (
                State::DownloadInitiate {
                    sent: true,
                    expedited,
                },
                ServerResponse::InitiateDownload { mux },
            ) => {
                if mux != self.mux {
                    return self.protocol_error(SdoAbort::General);
                }
                if expedited {
                    let size = self.remaining().unwrap_or(0) as u32;
                    self.fifo.clear();
                    self.count = size;
                    self.complete(size);
                } else {
                    self.state = State::DownloadSegment {
                        toggle: false,
                        waiting: false,
                    };
                }
            }
            (
                State::DownloadSegment {
                    toggle,
                    waiting: true,
                },
                ServerResponse::DownloadSegment { toggle: echoed },
            ) => {
                if echoed != toggle {
                    return self.protocol_error(SdoAbort::ToggleBit);
                }
                // Every segment but the last is full.
                let len = self
                    .remaining()
                    .map_or(SEGMENT_DATA_LEN, |r| r.min(SEGMENT_DATA_LEN));
                self.fifo.discard(len);
                self.count += len as u32;
                if self.remaining() == Some(0) {
                    self.complete(self.count);
                } else {
                    self.state = State::DownloadSegment {
                        toggle: !toggle,
                        waiting: false,
                    };
                }
            }
            #[cfg(feature = "sdo-block")]
            (
                State::BlockDownloadInitiate,
                ServerResponse::BlockDownloadInitiate { mux, crc, blksize },
            ) => {
                if mux != self.mux {
                    return self.protocol_error(SdoAbort::General);
                }
                self.crc_on = crc;
                self.start_sub_block(blksize);
            }
            #[cfg(feature = "sdo-block")]
            (
                State::BlockDownloadSub {
                    sent,
                    last,
                    waiting: true,
                    ..
                },
                ServerResponse::BlockDownloadAck { ackseq, blksize },
            ) => {
                if ackseq > sent {
                    return self.protocol_error(SdoAbort::InvalidSequence);
                }
                // Only the value's last segment may be short, and only once the value ended.
                let sent_bytes = usize::from(ackseq) * SEGMENT_DATA_LEN;
                let acked = self.remaining().map_or(sent_bytes, |r| sent_bytes.min(r));
                let mut chunk = [0u8; SEGMENT_DATA_LEN];
                let mut done = 0;
                while done < acked {
                    let n = self
                        .fifo
                        .peek(0, &mut chunk[..(acked - done).min(SEGMENT_DATA_LEN)]);
                    self.crc.update(&chunk[..n]);
                    self.fifo.discard(n);
                    done += n;
                }
                self.count += acked as u32;
                if last && ackseq == sent {
                    // The whole value is acknowledged: its size, announced or not, is the count.
                    let size = self.count as usize;
                    let tail = size % SEGMENT_DATA_LEN;
                    let unused = if size == 0 {
                        SEGMENT_DATA_LEN
                    } else if tail == 0 {
                        0
                    } else {
                        SEGMENT_DATA_LEN - tail
                    };
                    self.state = State::BlockDownloadEnd;
                    let crc = if self.crc_on { self.crc.value() } else { 0 };
                    self.tx = Some(
                        ClientRequest::BlockDownloadEnd {
                            unused: unused as u8,
                            crc,
                        }
                        .emit(),
                    );
                } else {
                    self.start_sub_block(blksize);
                }
            }
            (State::BlockDownloadEnd, ServerResponse::BlockDownloadEnd) => {
                self.complete(self.count);
            }
            _ => self.protocol_error(SdoAbort::InvalidCommand),
        }
    }

    fn start_upload_segments(&mut self, size: Option<u32>) {
        self.size = size;
        self.state = State::UploadSegment {
            toggle: false,
            waiting: false,
        };
    }

    #[cfg(feature = "sdo-block")]
    fn start_sub_block(&mut self, blksize: u8) {
        if blksize == 0 || blksize > MAX_BLOCK_SIZE {
            return self.protocol_error(SdoAbort::InvalidBlockSize);
        }
        // A sub-block is kept in the window until acknowledged: no more than it holds (and, for
        // a value of unannounced size, the byte that shows its last segment is not the last).
        let room = if self.size.is_none() { BUF - 1 } else { BUF };
        let fits = (room / SEGMENT_DATA_LEN).min(usize::from(MAX_BLOCK_SIZE)) as u8;
        self.state = State::BlockDownloadSub {
            blksize: blksize.min(fits),
            sent: 0,
            last: false,
            waiting: false,
        };
    }

    #[cfg(feature = "sdo-block")]
    fn block_upload_segment(&mut self, segment: BlockSegment) {
        let State::BlockUploadSub {
            expected,
            blksize,
            last,
            ack_due: false,
        } = self.state
        else {
            return; // past the sub-block's end: the server will repeat it after the ack
        };
        let in_order = segment.seqno == expected && !last;
        let mut last = last;
        if in_order {
            if segment.last {
                self.held = segment.data;
                last = true;
            } else {
                self.accept_upload_bytes(&segment.data);
            }
        }
        let expected = if in_order { expected + 1 } else { expected };
        let ack_due = segment.last || segment.seqno >= blksize;
        self.state = State::BlockUploadSub {
            expected,
            blksize,
            last,
            ack_due,
        };
    }

    #[cfg(not(feature = "sdo-block"))]
    fn block_upload_segment(&mut self, _segment: BlockSegment) {}

    #[cfg(feature = "sdo-block")]
    fn accept_upload_bytes(&mut self, bytes: &[u8]) {
        self.fifo.push(bytes);
        self.crc.update(bytes);
        self.count += bytes.len() as u32;
    }

    fn complete(&mut self, size: u32) {
        let upload = !self.is_download();
        self.finish(Ok(Completed {
            mux: self.mux,
            size,
            upload,
        }));
    }

    fn finish(&mut self, result: Result<Completed, SdoError>) {
        if result.is_err() {
            self.fifo.clear();
        }
        self.state = State::Idle;
        self.deadline = None;
        self.result = Some(result);
    }

    fn finish_abort(&mut self, error: SdoError) {
        self.tx = Some(
            ClientRequest::Abort {
                mux: self.mux,
                code: error.code(),
            }
            .emit(),
        );
        self.finish(Err(error));
    }

    fn protocol_error(&mut self, abort: SdoAbort) {
        self.finish_abort(SdoError::Client(abort.code()));
    }
}
