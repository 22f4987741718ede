//! CoE's SDO (ETG.1000.6 §5.6.2) on the runtime's SDO server: a mailbox framing adapter that
//! feeds each CoE SDO request through [`SdoServer`] (CiA 301's state machine, 8 bytes at a
//! time) and frames the answers as CoE defines them, as long as the mailbox allows; whole
//! mailbox messages in and out with [`CoeSdoServer::mailbox`].
//!
//! What CoE adds to CiA 301, and where it is served:
//! - A normal download or upload carries data after the initiate's 8 bytes, and a segment can
//!   be longer than 7 bytes: the adapter splits the data into 7-byte segments for the server
//!   (holding at most 7 bytes between two mailbox messages) and packs the server's upload
//!   segments into one answer. The first answer of a normal upload holds up to the mailbox's
//!   size less 16 bytes, each segment up to its size less 9.
//! - Complete access (bit 4 of an initiate): a whole object, sub-index 0 and a padding byte
//!   then sub-indices 1 to the value of sub-index 0 (or from sub-index 1 without them). The
//!   server addresses one entry, so complete access reads and writes the dictionary here, with
//!   the server's access rules (0601 0001, 0601 0002). A complete-access download must fit one
//!   mailbox message (otherwise 0601 0000): the adapter holds no copy of an object.
//! - Which writes the device's state allows is the caller's `guard`, asked before a download
//!   reaches the server with the bytes the initiate carries; access rights are the dictionary's.
//! - Every abort names the request's index and sub-index (bytes 1..4 of the request), as
//!   CiA 301 §7.2.4.3.17 says, also for a command that is none; an abort of a segment names
//!   its transfer's (a segment's bytes 1..4 are data), 0 without a transfer.

mod complete_access;

use complete_access::{object_len, read_object, write_object};

use super::wire::coe::{self, Coe, CoeRepr};
use super::wire::mailbox::{self, Mailbox, MailboxRepr, TYPE_COE};
use crate::od::{ObjectDictionary, SdoAbort};
use crate::sdo::SdoServer;
use crate::time::{Duration, Instant};
use crate::wire::sdo::{FRAME_LEN, SEGMENT_DATA_LEN};

/// What may be written now: `Err` with the abort for an entry the device's state protects.
pub trait Guard {
    /// Whether `data` may be written to (`index`, `sub`) now.
    fn check(&self, index: u16, sub: u8, data: &[u8]) -> Result<(), SdoAbort>;
}

impl<F: Fn(u16, u8, &[u8]) -> Result<(), SdoAbort>> Guard for F {
    fn check(&self, index: u16, sub: u8, data: &[u8]) -> Result<(), SdoAbort> {
        self(index, sub, data)
    }
}

/// The transfer in progress.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Transfer {
    Idle,
    /// A normal download, through the server's segments.
    Download,
    /// A normal upload, from the server's segments.
    Upload,
    /// A complete-access upload of the object the transfer's index names.
    ObjectUpload,
}

/// The CoE SDO server: the runtime's [`SdoServer`] and the CoE transfer around it.
#[derive(Debug, Clone)]
pub struct CoeSdoServer {
    server: SdoServer,
    transfer: Transfer,
    /// The toggle bit the master's next segment carries.
    toggle: bool,
    /// The toggle bit of the next segment exchanged with the server.
    server_toggle: bool,
    /// Up to one segment's bytes held between the server and the mailbox, `carried` of them: a
    /// download's at the start (the segment being filled), an upload's at the end (what is
    /// left of the server's last segment).
    carry: [u8; SEGMENT_DATA_LEN],
    carried: usize,
    /// The bytes an upload has still to send.
    remaining: usize,
    /// How far a complete-access upload has read its object.
    offset: usize,
    /// The index and sub-index of the transfer in progress (its initiate's bytes 1..4), which
    /// an abort of one of its segments names.
    mux: [u8; 3],
}

impl Default for CoeSdoServer {
    fn default() -> Self {
        Self::new()
    }
}

/// The command specifiers of CoE SDO requests (bits 5–7 of the command byte).
mod ccs {
    pub const DOWNLOAD_SEGMENT: u8 = 0;
    pub const DOWNLOAD: u8 = 1;
    pub const UPLOAD: u8 = 2;
    pub const UPLOAD_SEGMENT: u8 = 3;
    pub const ABORT: u8 = 4;
}

/// The time the server is given: CoE transfers have no timeout, so it never matters.
const NO_TIME: Instant = Instant(0);
const TOGGLE: u8 = 0x10;
const COMPLETE_ACCESS: u8 = 0x10;
/// The mailbox and CoE headers before an SDO answer.
const HEADERS: usize = mailbox::HEADER_LEN + coe::HEADER_LEN;

impl CoeSdoServer {
    /// A server with no transfer in progress. CoE transfers have no timeout of their own: the
    /// master repeats or aborts.
    pub const fn new() -> Self {
        CoeSdoServer {
            server: SdoServer::new(Duration::from_micros(u64::MAX / 2)),
            transfer: Transfer::Idle,
            toggle: false,
            server_toggle: false,
            carry: [0; SEGMENT_DATA_LEN],
            carried: 0,
            remaining: 0,
            offset: 0,
            mux: [0; 3],
        }
    }

    /// Answers a whole mailbox message `message` (what the master wrote to the master-to-device
    /// mailbox) into `answer` (at most the device-to-master mailbox's size), headers and all:
    /// a CoE SDO request by [`request`](Self::request), another protocol with the mailbox error
    /// "unsupported protocol". Returns the answer's length, 0 for a message that gets none
    /// (malformed, a CoE service other than an SDO request, an abort from the master).
    pub fn mailbox<O: ObjectDictionary + ?Sized>(
        &mut self,
        od: &mut O,
        guard: &dyn Guard,
        message: &[u8],
        answer: &mut [u8],
    ) -> usize {
        let Ok(message) = Mailbox::new_checked(message) else {
            return 0;
        };
        let counter = message.counter();
        if message.kind() != TYPE_COE {
            return mailbox::emit_error(answer, counter, mailbox::ERROR_UNSUPPORTED_PROTOCOL)
                .unwrap_or(0);
        }
        let Some(coe) = Coe::new_checked(message.data())
            .ok()
            .filter(|coe| coe.service() == coe::SERVICE_SDO_REQUEST)
        else {
            return 0;
        };
        let Some(sdo) = answer.get_mut(HEADERS..) else {
            return 0;
        };
        let Some(len) = self.request(od, guard, coe.payload(), sdo) else {
            return 0;
        };
        let length = (coe::HEADER_LEN + len) as u16;
        let headers = MailboxRepr::new(TYPE_COE, counter, length)
            .emit(answer)
            .and_then(|()| {
                CoeRepr::service(coe::SERVICE_SDO_RESPONSE).emit(&mut answer[mailbox::HEADER_LEN..])
            });
        if headers.is_err() {
            return 0;
        }
        HEADERS + len
    }

    /// Answers the SDO request `request` (the mailbox's data after the CoE header) into
    /// `answer` (the room after the answer's CoE header: the device-to-master mailbox's size
    /// less 8 bytes, at least 8); returns the answer's length, or `None` for a request that gets
    /// no answer (an abort from the master, an empty request).
    pub fn request<O: ObjectDictionary + ?Sized>(
        &mut self,
        od: &mut O,
        guard: &dyn Guard,
        request: &[u8],
        answer: &mut [u8],
    ) -> Option<usize> {
        let command = *request.first()?;
        if answer.len() < FRAME_LEN {
            return None;
        }
        let mut mux = [0u8; 3];
        for (m, r) in mux.iter_mut().zip(request.iter().skip(1)) {
            *m = *r;
        }
        let index = u16::from_le_bytes([mux[0], mux[1]]);
        let sub = mux[2];
        if matches!(command >> 5, ccs::DOWNLOAD_SEGMENT | ccs::UPLOAD_SEGMENT) {
            // A segment's bytes 1..4 are data: its abort names the transfer's entry (none
            // without a transfer).
            mux = match self.transfer {
                Transfer::Idle => [0; 3],
                _ => self.mux,
            };
        } else {
            self.mux = mux;
        }
        let result = match command >> 5 {
            ccs::DOWNLOAD_SEGMENT => self.download_segment(od, request, answer),
            ccs::DOWNLOAD if request.len() >= FRAME_LEN => {
                self.download(od, guard, request, index, sub, answer)
            }
            ccs::UPLOAD if request.len() >= 4 => self.upload(od, command, index, sub, answer),
            ccs::UPLOAD_SEGMENT => self.upload_segment(od, command, answer),
            ccs::ABORT => {
                self.end(od);
                return None;
            }
            _ => Err(SdoAbort::InvalidCommand.code()),
        };
        Some(result.unwrap_or_else(|code| {
            self.end(od);
            answer[..FRAME_LEN].fill(0);
            answer[0] = 0x80;
            answer[1..4].copy_from_slice(&mux);
            answer[4..8].copy_from_slice(&code.to_le_bytes());
            FRAME_LEN
        }))
    }

    /// Ends any transfer (a download leaves the entry as it was).
    fn end<O: ObjectDictionary + ?Sized>(&mut self, od: &mut O) {
        self.transfer = Transfer::Idle;
        self.toggle = false;
        self.server_toggle = false;
        self.carried = 0;
        self.offset = 0;
        self.server.reset(od);
    }

    /// One request to the server and its answer (an abort's code as the error).
    fn exchange<O: ObjectDictionary + ?Sized>(
        &mut self,
        od: &mut O,
        request: [u8; FRAME_LEN],
    ) -> Result<[u8; FRAME_LEN], u32> {
        self.server.handle(NO_TIME, &request, od);
        let response = self
            .server
            .poll_transmit(NO_TIME, od)
            .ok_or(SdoAbort::General.code())?;
        if response[0] >> 5 == ccs::ABORT {
            return Err(u32::from_le_bytes([
                response[4],
                response[5],
                response[6],
                response[7],
            ]));
        }
        Ok(response)
    }

    #[allow(clippy::too_many_arguments)]
    fn download<O: ObjectDictionary + ?Sized>(
        &mut self,
        od: &mut O,
        guard: &dyn Guard,
        request: &[u8],
        index: u16,
        sub: u8,
        answer: &mut [u8],
    ) -> Result<usize, u32> {
        self.end(od);
        let command = request[0];
        let expedited = command & 0x02 != 0;
        let data = if expedited {
            let len = if command & 0x01 != 0 {
                4 - usize::from((command >> 2) & 0x03)
            } else {
                od.value_len(index, sub).unwrap_or(4).min(4)
            };
            &request[4..4 + len]
        } else {
            let data = &request[8..];
            &data[..data.len().min(size_of(request))]
        };
        if command & COMPLETE_ACCESS != 0 {
            if !expedited && data.len() < size_of(request) {
                return Err(SdoAbort::UnsupportedAccess.code());
            }
            write_object(od, guard, index, sub, data).map_err(SdoAbort::code)?;
        } else {
            guard.check(index, sub, data).map_err(SdoAbort::code)?;
            let mut initiate = [0u8; FRAME_LEN];
            initiate.copy_from_slice(&request[..FRAME_LEN]);
            if expedited {
                self.exchange(od, initiate)?;
            } else {
                initiate[0] = 0x21;
                self.exchange(od, initiate)?;
                self.transfer = Transfer::Download;
                let last = data.len() >= size_of(request);
                self.feed(od, data, last)?;
            }
        }
        answer[..FRAME_LEN].copy_from_slice(&[0x60, request[1], request[2], sub, 0, 0, 0, 0]);
        Ok(FRAME_LEN)
    }

    fn download_segment<O: ObjectDictionary + ?Sized>(
        &mut self,
        od: &mut O,
        request: &[u8],
        answer: &mut [u8],
    ) -> Result<usize, u32> {
        if self.transfer != Transfer::Download {
            return Err(SdoAbort::InvalidCommand.code());
        }
        let command = request[0];
        if (command & TOGGLE != 0) != self.toggle {
            return Err(SdoAbort::ToggleBit.code());
        }
        let segment = &request[1..];
        let len = if segment.len() <= SEGMENT_DATA_LEN {
            (SEGMENT_DATA_LEN - usize::from((command >> 1) & 0x07)).min(segment.len())
        } else {
            segment.len()
        };
        self.feed(od, &segment[..len], command & 0x01 != 0)?;
        self.toggle = !self.toggle;
        answer[..FRAME_LEN].copy_from_slice(&[0x20 | (command & TOGGLE), 0, 0, 0, 0, 0, 0, 0]);
        Ok(FRAME_LEN)
    }

    /// Hands `data` to the server in 7-byte segments, holding the last 1 to 7 bytes until the
    /// transfer's `last` part says they end it.
    fn feed<O: ObjectDictionary + ?Sized>(
        &mut self,
        od: &mut O,
        mut data: &[u8],
        last: bool,
    ) -> Result<(), u32> {
        if self.transfer != Transfer::Download {
            return Err(SdoAbort::InvalidCommand.code());
        }
        loop {
            let carried = self.carried;
            let take = (SEGMENT_DATA_LEN - carried).min(data.len());
            self.carry[carried..carried + take].copy_from_slice(&data[..take]);
            self.carried += take;
            data = &data[take..];
            if data.is_empty() && !last {
                return Ok(());
            }
            let ends = data.is_empty();
            let unused = (SEGMENT_DATA_LEN - self.carried) as u8;
            let mut segment = [0u8; FRAME_LEN];
            segment[0] = self.server_bit() | (unused << 1) | u8::from(ends);
            segment[1..1 + self.carried].copy_from_slice(&self.carry[..self.carried]);
            self.exchange(od, segment)?;
            self.server_toggle = !self.server_toggle;
            self.carried = 0;
            if ends {
                self.transfer = Transfer::Idle;
                return Ok(());
            }
        }
    }

    /// The toggle bit of the next segment exchanged with the server.
    fn server_bit(&self) -> u8 {
        if self.server_toggle {
            TOGGLE
        } else {
            0
        }
    }

    fn upload<O: ObjectDictionary + ?Sized>(
        &mut self,
        od: &mut O,
        command: u8,
        index: u16,
        sub: u8,
        answer: &mut [u8],
    ) -> Result<usize, u32> {
        self.end(od);
        let [i0, i1] = index.to_le_bytes();
        let (total, transfer, ca) = if command & COMPLETE_ACCESS != 0 {
            let total = object_len(od, index, sub).map_err(SdoAbort::code)?;
            (total, Transfer::ObjectUpload, COMPLETE_ACCESS)
        } else {
            let response = self.exchange(od, [0x40, i0, i1, sub, 0, 0, 0, 0])?;
            if response[0] & 0x02 != 0 {
                // Expedited: the server's answer is CoE's.
                answer[..FRAME_LEN].copy_from_slice(&response);
                return Ok(FRAME_LEN);
            }
            let size = u32::from_le_bytes([response[4], response[5], response[6], response[7]]);
            (size as usize, Transfer::Upload, 0)
        };
        self.transfer = transfer;
        self.remaining = total;
        answer[1..4].copy_from_slice(&[i0, i1, sub]);
        if (1..=4).contains(&total) {
            // Expedited: the value in bytes 4..8.
            answer[0] = 0x43 | ca | (((4 - total) as u8) << 2);
            answer[4..FRAME_LEN].fill(0);
            self.pull(od, &mut answer[4..4 + total])?;
            self.end(od);
            return Ok(FRAME_LEN);
        }
        answer[0] = 0x41 | ca;
        answer[4..8].copy_from_slice(&(total as u32).to_le_bytes());
        let room = answer.len() - FRAME_LEN;
        let first = total.min(room);
        self.pull(od, &mut answer[FRAME_LEN..FRAME_LEN + first])?;
        if first == total {
            self.end(od);
        }
        Ok(FRAME_LEN + first)
    }

    fn upload_segment<O: ObjectDictionary + ?Sized>(
        &mut self,
        od: &mut O,
        command: u8,
        answer: &mut [u8],
    ) -> Result<usize, u32> {
        if !matches!(self.transfer, Transfer::Upload | Transfer::ObjectUpload) {
            return Err(SdoAbort::InvalidCommand.code());
        }
        if (command & TOGGLE != 0) != self.toggle {
            return Err(SdoAbort::ToggleBit.code());
        }
        let remaining = self.remaining;
        let chunk = remaining.min(answer.len() - 1);
        self.pull(od, &mut answer[1..1 + chunk])?;
        let last = chunk == remaining;
        let unused = SEGMENT_DATA_LEN.saturating_sub(chunk) as u8;
        answer[0] = (command & TOGGLE) | (unused << 1) | u8::from(last);
        let len = (1 + chunk).max(FRAME_LEN);
        answer[1 + chunk..len].fill(0);
        self.toggle = !self.toggle;
        if last {
            self.end(od);
        }
        Ok(len)
    }

    /// Fills `out` with the upload's next bytes.
    fn pull<O: ObjectDictionary + ?Sized>(
        &mut self,
        od: &mut O,
        out: &mut [u8],
    ) -> Result<(), u32> {
        match self.transfer {
            Transfer::ObjectUpload => {
                let [i0, i1, sub] = self.mux;
                let index = u16::from_le_bytes([i0, i1]);
                read_object(od, index, sub, self.offset, out).map_err(SdoAbort::code)?;
                self.offset += out.len();
            }
            Transfer::Upload => {
                let mut filled = 0;
                while filled < out.len() {
                    if self.carried == 0 {
                        let request = [0x60 | self.server_bit(), 0, 0, 0, 0, 0, 0, 0];
                        let segment = self.exchange(od, request)?;
                        self.server_toggle = !self.server_toggle;
                        // The segment's data, moved to the end of the carry.
                        let len = SEGMENT_DATA_LEN - usize::from((segment[0] >> 1) & 0x07);
                        self.carry[SEGMENT_DATA_LEN - len..].copy_from_slice(&segment[1..1 + len]);
                        self.carried = len;
                        if self.carried == 0 {
                            return Err(SdoAbort::General.code());
                        }
                    }
                    // The carried bytes are the segment's last `carried`.
                    let at = SEGMENT_DATA_LEN - self.carried;
                    let take = self.carried.min(out.len() - filled);
                    out[filled..filled + take].copy_from_slice(&self.carry[at..at + take]);
                    self.carried -= take;
                    filled += take;
                }
            }
            Transfer::Idle | Transfer::Download => {
                return Err(SdoAbort::InvalidCommand.code());
            }
        }
        self.remaining -= out.len();
        Ok(())
    }
}

/// The size a normal download announces.
fn size_of(request: &[u8]) -> usize {
    let mut size = [0u8; 4];
    if let Some(bytes) = request.get(4..8) {
        size.copy_from_slice(bytes);
    }
    u32::from_le_bytes(size) as usize
}
