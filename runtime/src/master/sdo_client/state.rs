//! The channel's protocol state and its transitions (expedited, segmented and block, both
//! directions): the frame each state owes the server once the window allows, and what each
//! server response does.

use crate::od::SdoAbort;
#[cfg(feature = "sdo-block")]
use crate::sdo::crc::Crc16;
use crate::time::Instant;
use crate::wire::sdo::{
    BlockSegment, ClientRequest, InitiatePayload, Multiplexer, SegmentData, ServerResponse,
    FRAME_LEN, MAX_BLOCK_SIZE, SEGMENT_DATA_LEN,
};

use super::{Completed, SdoClient, SdoError, StartError, Transfer};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(not(feature = "sdo-block"), allow(dead_code))]
pub(super) enum State {
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

impl<const BUF: usize> SdoClient<BUF> {
    pub(super) fn begin(
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

    pub(super) fn is_download(&self) -> bool {
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
    pub(super) fn upload_block_size(&self) -> u8 {
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
    pub(super) fn next_frame(&mut self) -> Option<[u8; FRAME_LEN]> {
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

    pub(super) fn handle_response(&mut self, response: ServerResponse) {
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
    pub(super) fn block_upload_segment(&mut self, segment: BlockSegment) {
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
    pub(super) fn block_upload_segment(&mut self, _segment: BlockSegment) {}

    #[cfg(feature = "sdo-block")]
    fn accept_upload_bytes(&mut self, bytes: &[u8]) {
        self.fifo.push(bytes);
        self.crc.update(bytes);
        self.count += bytes.len() as u32;
    }

    fn complete(&mut self, size: u32) {
        let upload = !self.is_download();
        // The state the transfer ends in says how it went.
        let transfer = match self.state {
            State::UploadInitiate
            | State::DownloadInitiate {
                expedited: true, ..
            } => Transfer::Expedited,
            State::UploadSegment { .. }
            | State::DownloadInitiate { .. }
            | State::DownloadSegment { .. } => Transfer::Segmented,
            _ => Transfer::Block,
        };
        self.finish(Ok(Completed {
            mux: self.mux,
            size,
            upload,
            transfer,
        }));
    }

    pub(super) fn finish(&mut self, result: Result<Completed, SdoError>) {
        if result.is_err() {
            self.fifo.clear();
        }
        self.state = State::Idle;
        self.deadline = None;
        self.result = Some(result);
    }

    pub(super) fn finish_abort(&mut self, error: SdoError) {
        self.tx = Some(
            ClientRequest::Abort {
                mux: self.mux,
                code: error.code(),
            }
            .emit(),
        );
        self.finish(Err(error));
    }

    pub(super) fn protocol_error(&mut self, abort: SdoAbort) {
        self.finish_abort(SdoError::Client(abort.code()));
    }
}
