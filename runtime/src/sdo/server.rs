//! The SDO server (CiA 301 §7.2.4.3): one client, every transfer type, no allocation. Block
//! transfer needs the `sdo-block` feature; without it a block request (command specifier 5 or 6)
//! is aborted with 0504 0001, like any unknown command.
//!
//! Feed each request payload to [`SdoServer::handle`], send what [`SdoServer::poll_transmit`]
//! returns, and call [`SdoServer::handle_timeout`] once [`SdoServer::poll_timeout`] has passed.
//!
//! Protocol choices (all within CiA 301):
//! - Access rights are checked here against the entry's descriptor (write to `ro`/`const`:
//!   0601 0002; read of `wo`: 0601 0001); lengths and limits are checked by the object
//!   dictionary's `write`, whose abort code is passed on unchanged.
//! - Uploads of 1 to 4 bytes are answered expedited with the size indicated: the command byte is
//!   `0x43 | (4 - len) << 2`, so a 2-byte value gives `4B` and a 4-byte value `43`. (Some device
//!   manuals print `43` for every expedited upload; CiA 301 defines `n` as the number of bytes
//!   that do not contain data, which this server follows.) Longer or empty values are uploaded
//!   segmented (or by block transfer), streamed from the dictionary without a copy of the value.
//! - An expedited download without the size indicated is accepted when the entry's size is 1 to
//!   4 bytes: that many bytes are written. For a longer entry it is aborted with 0607 0010, as the
//!   server cannot know how many of the four bytes the client meant.
//! - Downloads apply all or nothing: the entry changes only when the transfer completes (the
//!   CRC checked for a block download), and a transfer that ends any other way (an abort from
//!   either side, a timeout, a new initiate, [`SdoServer::reset`]) leaves it as it was and
//!   reports no [`SdoEvent::Written`]. A fixed-size value (at most 8 bytes) is collected here
//!   and written once, when complete, so that its limits are checked on the whole value; a
//!   string, octet string or domain goes through the dictionary's streaming steps
//!   ([`ObjectDictionary::begin_write`], [`write_part`](ObjectDictionary::write_part) for each
//!   piece as it arrives, then [`commit_write`](ObjectDictionary::commit_write) or
//!   [`abort_write`](ObjectDictionary::abort_write)), which stage it (the generated
//!   dictionaries, in a buffer sized to their largest writable value) or send it where it goes
//!   (an application's domain in flash, discarded on abort). Segmented and block downloads of
//!   any length up to the entry's capacity. An announced size above the entry's capacity is
//!   aborted with 0607 0012, below a fixed-size entry's size with 0607 0013; data beyond the
//!   announced size, or a final length that differs from it, with 0607 0010.
//! - Block download: the server's block size is 127 (the most CiA 301 allows: segments are
//!   streamed, not buffered) unless [`SdoServer::with_block_size`] says less. A segment whose
//!   sequence number is 0 (`00`, and `80` with the last-segment bit, which during a sub-block is
//!   a segment too, not the client's abort) or above the block size is aborted with 0504 0003;
//!   an out-of-order one
//!   within range is ignored and the sub-block acknowledged up to the last segment received in
//!   order, so the client repeats the rest (CiA 301's retransmission). CRC is supported and
//!   checked when the client supports it too (mismatch: 0504 0004).
//! - Block upload: a client block size of 0 or above 127 is aborted with 0504 0002, an
//!   acknowledged sequence number above the segments sent with 0504 0003. When the client's
//!   protocol switch threshold is non-zero and at least the value's size, a normal upload answers.
//! - A new initiate request replaces any transfer in progress (the client has given up on it;
//!   the replaced download changes nothing), except during a block download sub-block, where
//!   every frame is a segment. A client abort ends the transfer without a response. A frame that is not 8 bytes long, has an unknown
//!   command specifier, or does not fit the transfer in progress is aborted with 0504 0001.
//! - Each request queues at most one response; one not yet taken by `poll_transmit` is replaced.
//!
//! This module holds the channel's state and dispatches each request; `segmented` serves the
//! expedited and segmented transfers and `block` the block transfers.

use crate::od::{ObjectDictionary, SdoAbort};
use crate::time::{Duration, Instant};
use crate::wire::sdo::command::{self, ccs, scs};
use crate::wire::sdo::{frame, Frame, Multiplexer, FRAME_LEN, SEGMENT_DATA_LEN};

#[cfg(feature = "sdo-block")]
mod block;
mod segmented;

#[cfg(feature = "sdo-block")]
use crate::wire::sdo::MAX_BLOCK_SIZE;
#[cfg(feature = "sdo-block")]
use block::{BlockDownload, BlockUpload};

/// What the server tells the application after a request.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SdoEvent {
    /// A client wrote (index, sub); the value is in the object dictionary.
    Written {
        /// OD index.
        index: u16,
        /// Sub-index.
        sub: u8,
    },
}

/// Where a download goes: the entry's position and the most bytes its value holds (exactly that
/// many for a fixed-size type; `usize::MAX` when the dictionary does not say).
#[derive(Debug, Clone, Copy)]
struct WriteTarget {
    position: usize,
    capacity: usize,
    fixed: bool,
}

/// A normal (segmented) transfer in either direction, between its initiate and its last
/// segment. Both directions keep the same few fields, so that one step serves a segment of
/// either: the toggle, the bytes so far and where they end.
#[derive(Debug, Clone, Copy)]
struct Segmented {
    /// A download (else an upload).
    download: bool,
    /// The toggle bit the next segment carries.
    toggle: bool,
    /// Whether `end` is a size the last segment must reach: an upload's, or a download's
    /// announced size (else the entry's capacity, which a download may stop short of).
    sized: bool,
    /// The entry: where a download goes (a fixed-size value collected in `held`, another
    /// streamed into the dictionary's staging), or where an upload is read from.
    target: WriteTarget,
    /// Where the transfer ends: an upload's value length, a download's announced size or
    /// else its entry's capacity.
    end: usize,
    /// Bytes transferred so far.
    offset: usize,
}

#[derive(Debug, Clone, Copy)]
enum Transfer {
    Idle,
    Segmented(Segmented),
    #[cfg(feature = "sdo-block")]
    BlockDownload(BlockDownload),
    #[cfg(feature = "sdo-block")]
    BlockUpload(BlockUpload),
}

/// An SDO server for one client. It holds no copy of a value but a fixed-size one of up to 8
/// bytes being downloaded: uploads stream from the dictionary, downloads into its staging.
#[derive(Debug, Clone)]
pub struct SdoServer {
    timeout: Duration,
    transfer: Transfer,
    mux: Multiplexer,
    deadline: Option<Instant>,
    /// A response is queued: `response`. A flag beside a plain array rather than an `Option`,
    /// which the device stores and takes with less code.
    pending: bool,
    response: [u8; FRAME_LEN],
    /// A fixed-size value being downloaded.
    held: [u8; 8],
    /// The block size offered for block downloads.
    #[cfg(feature = "sdo-block")]
    block_size: u8,
}

/// How handling one request ended: `Err` aborts the transfer. Whether it wrote the entry is
/// not returned through every step but read from the state it left ([`SdoServer::handle`]):
/// a `Result` of nothing but the abort code fits a register.
type Handled = Result<(), SdoAbort>;

impl SdoServer {
    /// A server with no transfer in progress, aborting a transfer after `timeout` without a
    /// request from the client, offering block downloads sub-blocks of 127 segments.
    pub const fn new(timeout: Duration) -> Self {
        SdoServer {
            timeout,
            transfer: Transfer::Idle,
            mux: Multiplexer::new(0, 0),
            deadline: None,
            pending: false,
            response: [0; FRAME_LEN],
            held: [0; 8],
            #[cfg(feature = "sdo-block")]
            block_size: MAX_BLOCK_SIZE,
        }
    }

    /// The same server offering block downloads sub-blocks of `segments` (clamped to 1..=127):
    /// fewer when the frames come through a receive queue that could overflow.
    #[cfg(feature = "sdo-block")]
    pub const fn with_block_size(mut self, segments: u8) -> Self {
        self.block_size = if segments == 0 {
            1
        } else if segments > MAX_BLOCK_SIZE {
            MAX_BLOCK_SIZE
        } else {
            segments
        };
        self
    }

    /// The block size offered for block downloads.
    #[cfg(feature = "sdo-block")]
    pub const fn block_size(&self) -> u8 {
        self.block_size
    }

    /// Handles one request payload (the data of a frame sent to this server's rx COB-ID). Any
    /// response is queued for [`SdoServer::poll_transmit`].
    pub fn handle<O: ObjectDictionary + ?Sized>(
        &mut self,
        now: Instant,
        request: &[u8],
        od: &mut O,
    ) -> Option<SdoEvent> {
        let outcome = match Frame::new_checked(request) {
            Ok(frame) => self.handle_frame(frame, od).map(|()| frame.specifier()),
            Err(_) => Err(SdoAbort::InvalidCommand),
        };
        match outcome {
            Ok(specifier) => {
                let idle = matches!(self.transfer, Transfer::Idle);
                self.deadline = (!idle).then(|| now + self.timeout);
                // A download request (expedited, a segment, a block download's end) that leaves
                // no transfer open has completed its download: the entry is written.
                let download = matches!(
                    specifier,
                    ccs::INITIATE_DOWNLOAD | ccs::DOWNLOAD_SEGMENT | ccs::BLOCK_DOWNLOAD
                );
                let event = (download && idle).then_some(SdoEvent::Written {
                    index: self.mux.index,
                    sub: self.mux.sub,
                });
                if idle {
                    // Until an initiate request names an entry, aborts name none.
                    self.mux = Multiplexer::new(0, 0);
                }
                event
            }
            Err(abort) => {
                self.release(od);
                self.abort(abort);
                None
            }
        }
    }

    /// The next response payload to send (8 bytes, always DLC 8), including block-upload
    /// sub-block segments.
    pub fn poll_transmit<O: ObjectDictionary + ?Sized>(
        &mut self,
        now: Instant,
        od: &O,
    ) -> Option<[u8; FRAME_LEN]> {
        if core::mem::take(&mut self.pending) {
            return Some(self.response);
        }
        #[cfg(feature = "sdo-block")]
        if let Transfer::BlockUpload(_) = self.transfer {
            return self.block_upload_segment(now, od);
        }
        // Without block upload, the server sends only answers to requests.
        let _ = (now, od);
        None
    }

    /// When the server next needs [`SdoServer::handle_timeout`] (an SDO transfer in progress),
    /// if ever.
    pub fn poll_timeout(&self) -> Option<Instant> {
        self.deadline
    }

    /// Aborts a transfer whose timeout has passed (queues abort 0504 0000); a download leaves
    /// the entry as it was.
    pub fn handle_timeout<O: ObjectDictionary + ?Sized>(&mut self, now: Instant, od: &mut O) {
        if let Some(deadline) = self.deadline {
            if now >= deadline {
                self.release(od);
                self.abort(SdoAbort::Timeout);
            }
        }
    }

    /// Drops any transfer in progress (a download leaves the entry as it was) and any queued
    /// response (NMT reset communication).
    pub fn reset<O: ObjectDictionary + ?Sized>(&mut self, od: &mut O) {
        self.release(od);
        self.deadline = None;
        self.pending = false;
        self.mux = Multiplexer::new(0, 0);
    }

    /// Whether a download of a string, octet string or domain is open in the dictionary (begun
    /// and neither committed nor aborted), and into which entry.
    fn streaming<O: ObjectDictionary + ?Sized>(&self, od: &O) -> Option<usize> {
        let target = match &self.transfer {
            Transfer::Segmented(segmented) => &segmented.target,
            #[cfg(feature = "sdo-block")]
            Transfer::BlockDownload(block) => &block.target,
            _ => return None,
        };
        Self::streams(target, od).then_some(target.position)
    }

    /// Whether a download into `target` streams into the dictionary (a string, octet string or
    /// domain) rather than being collected in `held` and written whole: never in a dictionary
    /// without such writable entries ([`Services::streamed_writes`](crate::od::Services), a
    /// constant in generated code), whose server then has no streaming code. Were such a
    /// dictionary to have one after all, its downloads of up to 8 bytes would be written whole
    /// and longer ones refused (0607 0012).
    #[inline(always)]
    fn streams<O: ObjectDictionary + ?Sized>(target: &WriteTarget, od: &O) -> bool {
        !target.fixed && od.services().streamed_writes
    }

    /// Forgets the transfer in progress: a download streaming into the dictionary ends without
    /// being applied (the entry keeps its value). The deadline is the caller's.
    #[inline(never)]
    fn release<O: ObjectDictionary + ?Sized>(&mut self, od: &mut O) {
        let streaming = self.streaming(od);
        self.transfer = Transfer::Idle;
        if let Some(position) = streaming {
            od.abort_write(position);
        }
    }

    fn end_transfer(&mut self) {
        self.transfer = Transfer::Idle;
        self.deadline = None;
    }

    /// Queues an abort of the current transfer (or of the last addressed entry) and ends it.
    fn abort(&mut self, abort: SdoAbort) {
        self.respond_mux(command::of(scs::ABORT), abort.code());
        self.end_transfer();
        // As after any transfer: until an initiate request names an entry, aborts name none.
        self.mux = Multiplexer::new(0, 0);
    }

    /// Queues a response: its command byte and the 7 bytes that follow. The server writes its
    /// few responses from the command byte's fields ([`command`]) rather than through
    /// [`ServerResponse`]'s encoder of every message, which costs some 500 B more flash on a
    /// device.
    ///
    /// [`ServerResponse`]: crate::wire::sdo::ServerResponse
    fn respond(&mut self, command: u8, data: [u8; SEGMENT_DATA_LEN]) {
        self.response = frame(command, data);
        self.pending = true;
    }

    /// Queues a response naming the addressed entry: the command byte, the multiplexer and
    /// `value` in bytes 4 to 7.
    fn respond_mux(&mut self, command: u8, value: u32) {
        // Through `respond`: one routine stores every response.
        let [index_lo, index_hi] = self.mux.index.to_le_bytes();
        let [v0, v1, v2, v3] = value.to_le_bytes();
        self.respond(command, [index_lo, index_hi, self.mux.sub, v0, v1, v2, v3]);
    }

    /// Handles an 8-byte request: a block-download sub-block segment, or a request.
    #[cfg(feature = "sdo-block")]
    fn handle_frame<O: ObjectDictionary + ?Sized>(
        &mut self,
        request: Frame<'_>,
        od: &mut O,
    ) -> Handled {
        // Tested by reference: a copy of the transfer would load all of it with every request.
        match &self.transfer {
            // Every frame of a sub-block is a segment: `80` too (sequence number 0 with the
            // last-segment bit), aborted with 0504 0003 as `00` is.
            Transfer::BlockDownload(block) if !block.complete => {
                let block = *block;
                self.block_download_segment(block, request.as_bytes(), od)
            }
            _ => self.handle_request(request, od),
        }
    }

    /// Handles an 8-byte request.
    #[cfg(not(feature = "sdo-block"))]
    fn handle_frame<O: ObjectDictionary + ?Sized>(
        &mut self,
        request: Frame<'_>,
        od: &mut O,
    ) -> Handled {
        self.handle_request(request, od)
    }

    /// Not inlined: inlined into the firmware's loop it costs 148 B of Cortex-M4 flash; out of
    /// line, the host's SDO upload still measures fewer instructions per frame than before.
    ///
    /// The request is read here through the frame view's accessors ([`Frame`]) rather than
    /// parsed into a [`ClientRequest`] first: the server needs few of the fields, and the
    /// general parser costs some 300 B more flash on a device.
    ///
    /// [`ClientRequest`]: crate::wire::sdo::ClientRequest
    #[inline(never)]
    fn handle_request<O: ObjectDictionary + ?Sized>(
        &mut self,
        request: Frame<'_>,
        od: &mut O,
    ) -> Handled {
        // On the command specifier first, and on the transfer in progress only where a segment
        // needs it: matching a copy of the transfer with every request loads all of it first.
        match request.specifier() {
            // The transfer ends (its deadline with it, in `handle`), without a response.
            ccs::ABORT => {
                self.release(od);
                Ok(())
            }
            ccs::INITIATE_DOWNLOAD | ccs::INITIATE_UPLOAD => {
                // Both initiates address an entry the same way; only the access they need
                // differs.
                let mux = request.mux();
                self.start(mux, od);
                let download = request.specifier() == ccs::INITIATE_DOWNLOAD;
                let (position, fixed) = Self::accessible_entry(mux, download, od)?;
                if download {
                    let target = Self::write_target(position, fixed, od);
                    self.initiate_download(target, request, od)
                } else {
                    let total = Self::upload_len(position, fixed, od)?;
                    self.start_upload(position, total, od)
                }
            }
            ccs::DOWNLOAD_SEGMENT | ccs::UPLOAD_SEGMENT => self.segment(request, od),
            #[cfg(feature = "sdo-block")]
            ccs::BLOCK_UPLOAD | ccs::BLOCK_DOWNLOAD => {
                self.handle_block_request(request, request.mux(), od)
            }
            _ => Err(SdoAbort::InvalidCommand),
        }
    }

    /// Forgets any transfer in progress (a download leaves its entry as it was) and addresses
    /// `mux`.
    #[inline]
    fn start<O: ObjectDictionary + ?Sized>(&mut self, mux: Multiplexer, od: &mut O) {
        // Nothing to forget when idle, the most frequent case (an expedited transfer).
        if !matches!(self.transfer, Transfer::Idle) {
            self.release(od);
        }
        self.mux = mux;
    }

    /// Opens a download into `target` in the dictionary if it streams (a string, octet string
    /// or domain): [`ObjectDictionary::begin_write`]. The caller records the transfer only
    /// once this succeeded, so that a refused download is never aborted in the dictionary.
    fn open<O: ObjectDictionary + ?Sized>(
        target: &WriteTarget,
        od: &mut O,
    ) -> Result<(), SdoAbort> {
        if Self::streams(target, od) {
            od.begin_write(target.position)
        } else {
            Ok(())
        }
    }

    /// The addressed entry's position and, for a fixed-size type, its size, if an SDO may
    /// write it (a `download`) or read it.
    #[inline(always)]
    fn accessible_entry<O: ObjectDictionary + ?Sized>(
        mux: Multiplexer,
        download: bool,
        od: &O,
    ) -> Result<(usize, Option<usize>), SdoAbort> {
        let position = od.locate(mux.index, mux.sub)?;
        let entry = od.kind(position).ok_or(SdoAbort::NoObject)?;
        let access = entry.access();
        if download {
            if !access.writable() {
                return Err(SdoAbort::ReadOnly);
            }
        } else if !access.readable() {
            return Err(SdoAbort::WriteOnly);
        }
        Ok((position, entry.data_type().fixed_size()))
    }

    /// Where a download into the entry at `position` goes: its fixed size, else the most bytes
    /// the dictionary says it holds.
    fn write_target<O: ObjectDictionary + ?Sized>(
        position: usize,
        fixed: Option<usize>,
        od: &O,
    ) -> WriteTarget {
        WriteTarget {
            position,
            capacity: fixed
                .or_else(|| od.capacity(position))
                .unwrap_or(usize::MAX),
            fixed: fixed.is_some(),
        }
    }

    /// The length of a readable entry's value: a fixed-size type's size from its descriptor
    /// (no second search), else the OD's current length. Inlined into the upload's initiate:
    /// out of line, an expedited upload pays its call and frame.
    #[inline(always)]
    fn upload_len<O: ObjectDictionary + ?Sized>(
        position: usize,
        fixed: Option<usize>,
        od: &O,
    ) -> Result<usize, SdoAbort> {
        match fixed {
            Some(size) => Ok(size),
            None => od.value_len_at(position),
        }
    }

    /// Checks a download's announced size against the entry.
    fn check_announced_size(target: &WriteTarget, size: Option<u32>) -> Result<(), SdoAbort> {
        let Some(size) = size else { return Ok(()) };
        let size = size as usize;
        if size > target.capacity {
            return Err(SdoAbort::LengthTooHigh);
        }
        if target.fixed && size < target.capacity {
            return Err(SdoAbort::LengthTooLow);
        }
        Ok(())
    }

    /// Checks that `len` bytes of download data fit the announced size and the entry (block
    /// downloads; a segmented one tests the announced size once, in `segment`).
    #[cfg(feature = "sdo-block")]
    fn check_received(len: usize, size: Option<u32>, capacity: usize) -> Result<(), SdoAbort> {
        if size.is_some_and(|size| len > size as usize) {
            return Err(SdoAbort::LengthMismatch);
        }
        if len > capacity {
            return Err(SdoAbort::LengthTooHigh);
        }
        Ok(())
    }

    /// Takes `data`, the download's bytes from `offset` on (checked by the caller against the
    /// entry's capacity): a fixed-size value's into `held`, a string's or domain's into the
    /// dictionary's open download.
    fn store<O: ObjectDictionary + ?Sized>(
        &mut self,
        target: &WriteTarget,
        offset: usize,
        data: &[u8],
        od: &mut O,
    ) -> Result<(), SdoAbort> {
        if !Self::streams(target, od) {
            self.held
                .get_mut(offset..offset + data.len())
                .ok_or(SdoAbort::LengthTooHigh)?
                .copy_from_slice(data);
            Ok(())
        } else if data.is_empty() {
            Ok(())
        } else {
            od.write_part(target.position, offset, data)
        }
    }

    /// Completes a download of `len` bytes: a fixed-size value is written whole (its limits
    /// checked), a string's or domain's download committed. The caller has ended the transfer
    /// first: a commit that fails leaves nothing open to abort.
    fn commit<O: ObjectDictionary + ?Sized>(
        &mut self,
        target: &WriteTarget,
        len: usize,
        od: &mut O,
    ) -> Result<(), SdoAbort> {
        if !Self::streams(target, od) {
            let data = self.held.get(..len).ok_or(SdoAbort::LengthTooHigh)?;
            od.write_at(target.position, data)
        } else {
            od.commit_write(target.position, len)
        }
    }
}
