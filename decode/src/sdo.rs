//! SDO transfers followed frame by frame from both sides, so that an expedited, segmented or
//! block transfer becomes one [`Transfer`] with its whole value (block segments committed as
//! the receiver acknowledges them, a sub-block repeated after a partial acknowledgement counted
//! once). The frame layouts are the runtime's `wire::sdo`. Frames shorter than 8 bytes, which
//! devices send although CiA 301 asks for 8, are read padded with zeros, their values cut to the
//! bytes sent.

use edsgen_runtime::wire::sdo::{
    BlockSegment, ClientRequest, InitiatePayload, Multiplexer, ServerResponse, SEGMENT_DATA_LEN,
};

/// How a transfer moved its value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// In the initiate message.
    Expedited,
    /// In segments.
    Segmented,
    /// In block-transfer sub-blocks.
    Block,
}

/// A finished transfer: a write (download) or a read (upload) of one entry.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Transfer {
    /// Download (client to server) or upload.
    pub write: bool,
    /// The entry.
    pub mux: Multiplexer,
    /// The value (for an aborted transfer, what had moved when it was aborted).
    pub data: Vec<u8>,
    /// How it moved.
    pub kind: Kind,
    /// The abort code and whether the server (rather than the client) sent it.
    pub abort: Option<(u32, bool)>,
    /// The CRC a block transfer's end message gave (None when not a block transfer, or 0 there:
    /// CRC not in use).
    pub crc: Option<u16>,
}

/// What one SDO frame meant.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Outcome {
    /// A step of a transfer that is not finished yet.
    Pending,
    /// The frame finished a transfer.
    Done(Transfer),
    /// The frame (a new request) started a transfer while this one was unfinished: the server
    /// drops the old one.
    Abandoned(Transfer),
    /// The frame fits no transfer seen (the log started in the middle of one, or a protocol
    /// error); `why` says so.
    Unattributed(&'static str),
}

/// Where a block transfer's sub-blocks are.
#[derive(Debug, Clone, Default)]
struct Blocks {
    /// Segments of the current sub-block, not yet acknowledged.
    pending: Vec<(u8, [u8; SEGMENT_DATA_LEN], bool)>,
    /// Whether the segments are flowing (after the initiate exchange and until the last one
    /// is acknowledged).
    flowing: bool,
    /// Whether the last segment has been acknowledged: the end message comes next.
    ended: bool,
}

#[derive(Debug, Clone)]
struct Active {
    write: bool,
    mux: Multiplexer,
    data: Vec<u8>,
    kind: Kind,
    /// A segmented download's last segment was sent; the server's answer ends it.
    last_sent: bool,
    blocks: Blocks,
    crc: Option<u16>,
}

/// One SDO channel (a client and a server COB-ID pair) between frames.
#[derive(Debug, Clone, Default)]
pub struct Channel {
    active: Option<Active>,
}

impl Channel {
    /// A frame the client sent (COB-ID 600h + node-ID).
    pub fn client(&mut self, sent: &[u8]) -> Outcome {
        let data = match padded(sent, true) {
            Ok(data) => data,
            Err(why) => return Outcome::Unattributed(why),
        };
        let data = &data[..];
        if let Some(active) = self.active.as_mut() {
            if active.write && active.kind == Kind::Block && active.blocks.flowing {
                return segment(&mut active.blocks, data);
            }
        }
        let Ok(request) = ClientRequest::parse(data) else {
            return Outcome::Unattributed("not an SDO request");
        };
        match request {
            ClientRequest::InitiateDownload { mux, payload } => {
                let (data, kind) = match expedited(payload, sent.len()) {
                    Some(data) => (data, Kind::Expedited),
                    None => (Vec::new(), Kind::Segmented),
                };
                self.start(true, mux, data, kind)
            }
            ClientRequest::InitiateUpload { mux } => {
                self.start(false, mux, Vec::new(), Kind::Expedited)
            }
            ClientRequest::BlockDownloadInitiate { mux, .. } => {
                self.start(true, mux, Vec::new(), Kind::Block)
            }
            ClientRequest::BlockUploadInitiate { mux, .. } => {
                self.start(false, mux, Vec::new(), Kind::Block)
            }
            ClientRequest::Abort { mux, code } => self.abort(mux, code, false),
            ClientRequest::DownloadSegment { data, last, .. } => match self.active.as_mut() {
                Some(a) if a.write && a.kind == Kind::Segmented => {
                    a.data
                        .extend_from_slice(segment_data(data.as_slice(), sent.len()));
                    a.last_sent = last;
                    Outcome::Pending
                }
                _ => Outcome::Unattributed("a download segment outside a download"),
            },
            ClientRequest::UploadSegment { .. } => match &self.active {
                Some(a) if !a.write && a.kind == Kind::Segmented => Outcome::Pending,
                _ => Outcome::Unattributed("an upload segment request outside an upload"),
            },
            ClientRequest::BlockUploadStart => match self.active.as_mut() {
                Some(a) if !a.write && a.kind == Kind::Block => {
                    a.blocks.flowing = true;
                    Outcome::Pending
                }
                _ => Outcome::Unattributed("a block upload start outside a block upload"),
            },
            ClientRequest::BlockUploadAck { ackseq, .. } => match self.active.as_mut() {
                Some(a) if !a.write && a.kind == Kind::Block => {
                    acknowledge(a, ackseq);
                    Outcome::Pending
                }
                _ => Outcome::Unattributed("a block acknowledgement outside a block upload"),
            },
            ClientRequest::BlockUploadEnd => match self.active.take() {
                Some(a) if !a.write && a.kind == Kind::Block && a.blocks.ended => {
                    Outcome::Done(a.finish(None))
                }
                other => {
                    self.active = other;
                    Outcome::Unattributed("a block upload end outside a block upload")
                }
            },
            ClientRequest::BlockDownloadEnd { unused, crc } => match self.active.as_mut() {
                Some(a) if a.write && a.kind == Kind::Block && a.blocks.ended => {
                    let len = a.data.len().saturating_sub(usize::from(unused));
                    a.data.truncate(len);
                    a.crc = Some(crc);
                    Outcome::Pending
                }
                _ => Outcome::Unattributed("a block download end outside a block download"),
            },
        }
    }

    /// A frame the server sent (COB-ID 580h + node-ID).
    pub fn server(&mut self, sent: &[u8]) -> Outcome {
        let data = match padded(sent, false) {
            Ok(data) => data,
            Err(why) => return Outcome::Unattributed(why),
        };
        let data = &data[..];
        if let Some(active) = self.active.as_mut() {
            if !active.write && active.kind == Kind::Block && active.blocks.flowing {
                return segment(&mut active.blocks, data);
            }
        }
        let Ok(response) = ServerResponse::parse(data) else {
            return Outcome::Unattributed("not an SDO response");
        };
        let active = self.active.take();
        let (outcome, active) = match (response, active) {
            (ServerResponse::Abort { mux, code }, active) => {
                self.active = active;
                return self.abort(mux, code, true);
            }
            (ServerResponse::InitiateDownload { .. }, Some(a))
                if a.write && a.kind == Kind::Expedited =>
            {
                (Outcome::Done(a.finish(None)), None)
            }
            (ServerResponse::InitiateDownload { .. }, Some(a))
                if a.write && a.kind == Kind::Segmented =>
            {
                (Outcome::Pending, Some(a))
            }
            (ServerResponse::DownloadSegment { .. }, Some(a))
                if a.write && a.kind == Kind::Segmented =>
            {
                if a.last_sent {
                    (Outcome::Done(a.finish(None)), None)
                } else {
                    (Outcome::Pending, Some(a))
                }
            }
            // An upload answered expedited or segmented (also a block upload the server
            // answered the classic way, as its protocol switch threshold allows); or an
            // answer whose request the log does not hold.
            (ServerResponse::InitiateUpload { mux, payload }, active)
                if active
                    .as_ref()
                    .is_none_or(|a| !a.write && a.kind != Kind::Segmented) =>
            {
                let mut a = Active::new(false, mux, Vec::new(), Kind::Expedited);
                match expedited(payload, sent.len()) {
                    Some(data) => {
                        a.data = data;
                        (Outcome::Done(a.finish(None)), None)
                    }
                    None => {
                        a.kind = Kind::Segmented;
                        (Outcome::Pending, Some(a))
                    }
                }
            }
            (ServerResponse::UploadSegment { data, last, .. }, Some(mut a))
                if !a.write && a.kind == Kind::Segmented =>
            {
                a.data
                    .extend_from_slice(segment_data(data.as_slice(), sent.len()));
                if last {
                    (Outcome::Done(a.finish(None)), None)
                } else {
                    (Outcome::Pending, Some(a))
                }
            }
            (ServerResponse::BlockDownloadInitiate { .. }, Some(mut a))
                if a.write && a.kind == Kind::Block =>
            {
                a.blocks.flowing = true;
                (Outcome::Pending, Some(a))
            }
            (ServerResponse::BlockDownloadAck { ackseq, .. }, Some(mut a))
                if a.write && a.kind == Kind::Block =>
            {
                acknowledge(&mut a, ackseq);
                (Outcome::Pending, Some(a))
            }
            (ServerResponse::BlockDownloadEnd, Some(a))
                if a.write && a.kind == Kind::Block && a.blocks.ended =>
            {
                (Outcome::Done(a.finish(None)), None)
            }
            (ServerResponse::BlockUploadInitiate { .. }, Some(a))
                if !a.write && a.kind == Kind::Block =>
            {
                (Outcome::Pending, Some(a))
            }
            (ServerResponse::BlockUploadEnd { unused, crc }, Some(mut a))
                if !a.write && a.kind == Kind::Block && a.blocks.ended =>
            {
                let len = a.data.len().saturating_sub(usize::from(unused));
                a.data.truncate(len);
                a.crc = Some(crc);
                (Outcome::Pending, Some(a))
            }
            (_, active) => (
                Outcome::Unattributed("an SDO response that fits no transfer seen"),
                active,
            ),
        };
        self.active = active;
        outcome
    }

    /// A transfer left unfinished (at the end of the log), if any.
    pub fn unfinished(&mut self) -> Option<Transfer> {
        self.active.take().map(|a| a.finish(None))
    }

    fn start(&mut self, write: bool, mux: Multiplexer, data: Vec<u8>, kind: Kind) -> Outcome {
        // A new request ends whatever was going on (the server forgets it).
        match self.active.replace(Active::new(write, mux, data, kind)) {
            Some(old) => Outcome::Abandoned(old.finish(None)),
            None => Outcome::Pending,
        }
    }

    fn abort(&mut self, mux: Multiplexer, code: u32, by_server: bool) -> Outcome {
        let active = self.active.take();
        let transfer = match active {
            Some(a) => a.finish(Some((code, by_server))),
            None => {
                Active::new(false, mux, Vec::new(), Kind::Expedited).finish(Some((code, by_server)))
            }
        };
        Outcome::Done(transfer)
    }
}

impl Active {
    fn new(write: bool, mux: Multiplexer, data: Vec<u8>, kind: Kind) -> Self {
        Active {
            write,
            mux,
            data,
            kind,
            last_sent: false,
            blocks: Blocks::default(),
            crc: None,
        }
    }

    fn finish(self, abort: Option<(u32, bool)>) -> Transfer {
        Transfer {
            write: self.write,
            mux: self.mux,
            data: self.data,
            kind: self.kind,
            abort,
            crc: self.crc,
        }
    }
}

/// The 8 bytes of an SDO frame from the `sent` ones, padded with zeros when fewer; an error when
/// nothing or more than 8 were sent, or an initiate or abort lacks its 4-byte header (the
/// command and the entry). `client`: a frame of the client (request), else of the server.
fn padded(sent: &[u8], client: bool) -> Result<[u8; 8], &'static str> {
    let Some(&command) = sent.first() else {
        return Err("an empty SDO frame");
    };
    if sent.len() > 8 {
        return Err("an SDO frame of more than 8 bytes");
    }
    // The specifiers whose messages name the entry (CiA 301 7.2.4.3): initiates and aborts,
    // the block transfers' initiates (their low bits 0).
    let names_entry = match (client, command >> 5) {
        (true, 1 | 2 | 4) | (false, 2..=4) => true,
        (true, 5) | (false, 5 | 6) => command & 0x03 == 0,
        (true, 6) => command & 0x01 == 0,
        _ => false,
    };
    if names_entry && sent.len() < 4 {
        return Err("an SDO initiate or abort shorter than its 4-byte header");
    }
    let mut frame = [0u8; 8];
    frame[..sent.len()].copy_from_slice(sent);
    Ok(frame)
}

/// The value of an expedited initiate of `sent` bytes (at most what was sent after the 4-byte
/// header); `None` for a segmented or block one.
fn expedited(payload: InitiatePayload, sent: usize) -> Option<Vec<u8>> {
    let sent = sent.saturating_sub(4);
    match payload {
        InitiatePayload::Expedited { data, len } => {
            Some(data[..usize::from(len).min(sent)].to_vec())
        }
        InitiatePayload::ExpeditedUnsized { data } => Some(data[..sent.min(data.len())].to_vec()),
        InitiatePayload::Sized(_) | InitiatePayload::Unsized => None,
    }
}

/// A segment's data, at most what a frame of `sent` bytes carried after its command byte.
fn segment_data(data: &[u8], sent: usize) -> &[u8] {
    &data[..data.len().min(sent.saturating_sub(1))]
}

/// A block-transfer segment, kept until the receiver acknowledges it.
fn segment(blocks: &mut Blocks, data: &[u8]) -> Outcome {
    match BlockSegment::parse(data) {
        Ok(s) => {
            blocks.pending.push((s.seqno, s.data, s.last));
            Outcome::Pending
        }
        Err(_) => Outcome::Unattributed("a block segment that is not 8 bytes"),
    }
}

/// Commits the segments numbered up to `ackseq`; the others will be sent again.
fn acknowledge(active: &mut Active, ackseq: u8) {
    let blocks = &mut active.blocks;
    for (seqno, data, last) in blocks.pending.drain(..) {
        if seqno <= ackseq {
            active.data.extend_from_slice(&data);
            if last {
                blocks.ended = true;
                blocks.flowing = false;
            }
        }
    }
}
