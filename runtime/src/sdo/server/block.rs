//! Block transfers (`sdo-block`) in both directions: their state, the requests that start and
//! end them, the sub-block segments and the CRC.

use crate::od::{ObjectDictionary, SdoAbort};
use crate::sdo::crc::Crc16;
use crate::time::Instant;
use crate::wire::sdo::command::{ccs, scs};
use crate::wire::sdo::{
    command, BlockSegment, Frame, Multiplexer, FRAME_LEN, MAX_BLOCK_SIZE, SEGMENT_DATA_LEN,
};

use super::{Handled, SdoServer, Transfer, WriteTarget};

/// A block download: a fixed-size value collected in the server's `held`, another streamed
/// into the dictionary's staging. The last segment received in order is held back
/// until the next one shows it was not the last, or the end request says how many of its bytes
/// are padding: only then is it written and added to the CRC.
#[derive(Debug, Clone, Copy)]
pub(super) struct BlockDownload {
    /// Whether the client computes the CRC (else the end request's is not checked).
    check_crc: bool,
    crc: Crc16,
    /// The segment held back.
    held: [u8; SEGMENT_DATA_LEN],
    size: Option<u32>,
    pub(super) target: WriteTarget,
    /// Segment bytes received in order, padding of the last segment included (the held
    /// segment's 7 bytes are the last 7 of them).
    received: usize,
    /// The sequence number of the last segment received in order in this sub-block.
    ackseq: u8,
    /// Whether the last segment (c = 1) was received: only the end request may follow.
    pub(super) complete: bool,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum BlockUploadPhase {
    /// Initiate answered; waiting for the start request.
    WaitStart,
    /// Sending the segments of a sub-block.
    Sending,
    /// Sub-block sent; waiting for the client's acknowledgement.
    WaitAck,
    /// End request sent; waiting for the client's end response.
    WaitEnd,
}

/// A block upload streamed from the dictionary.
#[derive(Debug, Clone, Copy)]
pub(super) struct BlockUpload {
    crc: bool,
    position: usize,
    total: usize,
    blksize: u8,
    /// Segments of the whole value acknowledged by the client.
    acked_segments: usize,
    /// Segments sent in the current sub-block.
    sent: u8,
    phase: BlockUploadPhase,
}

impl BlockUpload {
    /// Segments of the whole value (an empty value still takes one, carrying no data).
    fn segments(&self) -> usize {
        self.total.div_ceil(SEGMENT_DATA_LEN).max(1)
    }
}

impl SdoServer {
    /// The next segment of a block upload's sub-block, if one is due.
    pub(super) fn block_upload_segment<O: ObjectDictionary + ?Sized>(
        &mut self,
        now: Instant,
        od: &O,
    ) -> Option<[u8; FRAME_LEN]> {
        let Transfer::BlockUpload(upload) = &mut self.transfer else {
            return None;
        };
        if upload.phase != BlockUploadPhase::Sending {
            return None;
        }
        let segment_index = upload.acked_segments + usize::from(upload.sent);
        let offset = segment_index * SEGMENT_DATA_LEN;
        let chunk = upload.total.saturating_sub(offset).min(SEGMENT_DATA_LEN);
        let mut data = [0u8; SEGMENT_DATA_LEN];
        match od.read_at(upload.position, offset, &mut data[..chunk]) {
            Ok(read) if read == chunk => {}
            Ok(_) => {
                self.abort(SdoAbort::General);
                return core::mem::take(&mut self.pending).then_some(self.response);
            }
            Err(abort) => {
                self.abort(abort);
                return core::mem::take(&mut self.pending).then_some(self.response);
            }
        }
        upload.sent += 1;
        let last = segment_index + 1 == upload.segments();
        if last || upload.sent == upload.blksize {
            upload.phase = BlockUploadPhase::WaitAck;
        }
        let frame = BlockSegment {
            seqno: upload.sent,
            last,
            data,
        }
        .emit();
        self.deadline = Some(now + self.timeout);
        Some(frame)
    }

    /// Handles a block upload (ccs = 5) or block download (ccs = 6) request, decoded like the
    /// others by [`handle_request`](Self::handle_request).
    pub(super) fn handle_block_request<O: ObjectDictionary + ?Sized>(
        &mut self,
        request: Frame<'_>,
        mux: Multiplexer,
        od: &mut O,
    ) -> Handled {
        // Client CRC support (cc), in both initiate requests.
        let crc = request.crc_supported();
        // The sub-command (cs): bits 1 and 0 of a block upload, bit 0 of a block download.
        let subcommand = request.block_subcommand();
        match (request.specifier(), subcommand, self.transfer) {
            // Initiate block upload (cs = 0): blksize, pst.
            (ccs::BLOCK_UPLOAD, 0, _) => {
                self.start(mux, od);
                let (blksize, pst) = (
                    request.initiate_block_size(),
                    request.protocol_switch_threshold(),
                );
                self.initiate_block_upload(mux, crc, blksize, pst, od)
            }
            // End block upload response (cs = 1).
            (ccs::BLOCK_UPLOAD, 1, Transfer::BlockUpload(upload))
                if upload.phase == BlockUploadPhase::WaitEnd =>
            {
                self.end_transfer();
                Ok(())
            }
            // Block upload response (cs = 2): ackseq, blksize.
            (ccs::BLOCK_UPLOAD, 2, Transfer::BlockUpload(upload))
                if upload.phase == BlockUploadPhase::WaitAck =>
            {
                self.block_upload_ack(upload, request.ackseq(), request.ack_block_size(), od)
            }
            // Start block upload (cs = 3).
            (ccs::BLOCK_UPLOAD, 3, Transfer::BlockUpload(mut upload))
                if upload.phase == BlockUploadPhase::WaitStart =>
            {
                upload.phase = BlockUploadPhase::Sending;
                self.transfer = Transfer::BlockUpload(upload);
                Ok(())
            }
            // Initiate block download (cs = 0), with the size if indicated (s).
            (ccs::BLOCK_DOWNLOAD, 0 | 2, _) => {
                self.start(mux, od);
                let size = request.block_size_indicated().then(|| request.value());
                self.initiate_block_download(mux, crc, size, od)
            }
            // End block download request (cs = 1): n unused bytes, CRC.
            (ccs::BLOCK_DOWNLOAD, 1 | 3, Transfer::BlockDownload(block)) => {
                let (unused, crc) = (request.block_end_unused(), request.block_crc());
                self.end_block_download(block, unused, crc, od)
            }
            _ => Err(SdoAbort::InvalidCommand),
        }
    }

    fn initiate_block_download<O: ObjectDictionary + ?Sized>(
        &mut self,
        mux: Multiplexer,
        crc: bool,
        size: Option<u32>,
        od: &mut O,
    ) -> Handled {
        let (position, fixed) = Self::accessible_entry(mux, true, od)?;
        let target = Self::write_target(position, fixed, od);
        Self::check_announced_size(&target, size)?;
        Self::open(&target, od)?;
        self.transfer = Transfer::BlockDownload(BlockDownload {
            check_crc: crc,
            crc: Crc16::new(),
            held: [0; SEGMENT_DATA_LEN],
            size,
            target,
            received: 0,
            ackseq: 0,
            complete: false,
        });
        // Initiate block download response (ss = 0), CRC supported (sc).
        let response = command::of(scs::BLOCK_DOWNLOAD) | command::crc_bit(true);
        self.respond_mux(response, u32::from(self.block_size));
        Ok(())
    }

    /// Writes the held segment's first `len` bytes (the whole segment unless it is the last)
    /// into the entry and adds them to the CRC.
    fn flush_held<O: ObjectDictionary + ?Sized>(
        &mut self,
        block: &mut BlockDownload,
        len: usize,
        od: &mut O,
    ) -> Result<(), SdoAbort> {
        let offset = block.received - SEGMENT_DATA_LEN;
        let data = &block.held[..len];
        Self::check_received(offset + len, block.size, block.target.capacity)?;
        self.store(&block.target, offset, data, od)?;
        block.crc.update(data);
        Ok(())
    }

    pub(super) fn block_download_segment<O: ObjectDictionary + ?Sized>(
        &mut self,
        mut block: BlockDownload,
        request: &[u8],
        od: &mut O,
    ) -> Handled {
        let segment = BlockSegment::parse(request).map_err(|_| SdoAbort::InvalidCommand)?;
        let block_size = self.block_size;
        if segment.seqno == 0 || segment.seqno > block_size {
            return Err(SdoAbort::InvalidSequence);
        }
        let in_order = segment.seqno == block.ackseq + 1 && !block.complete;
        if in_order {
            if block.received > 0 {
                // The held segment was not the last: all of it is data.
                self.flush_held(&mut block, SEGMENT_DATA_LEN, od)?;
            }
            if !segment.last {
                // Only the last segment may carry padding, so the others must fit whole.
                Self::check_received(
                    block.received + SEGMENT_DATA_LEN,
                    block.size,
                    block.target.capacity,
                )?;
            }
            block.held = segment.data;
            block.received += SEGMENT_DATA_LEN;
            block.ackseq = segment.seqno;
            block.complete = segment.last;
        }
        if segment.seqno == block_size || segment.last || block.complete {
            // Block download response (ss = 2).
            let response = command::of(scs::BLOCK_DOWNLOAD) | 2;
            self.respond(response, [block.ackseq, block_size, 0, 0, 0, 0, 0]);
            block.ackseq = 0;
        }
        self.transfer = Transfer::BlockDownload(block);
        Ok(())
    }

    fn end_block_download<O: ObjectDictionary + ?Sized>(
        &mut self,
        mut block: BlockDownload,
        unused: u8,
        crc: u16,
        od: &mut O,
    ) -> Handled {
        if !block.complete || block.received == 0 {
            return Err(SdoAbort::InvalidCommand);
        }
        let last = SEGMENT_DATA_LEN
            .checked_sub(usize::from(unused))
            .ok_or(SdoAbort::LengthMismatch)?;
        let len = block.received - SEGMENT_DATA_LEN + last;
        // Any difference from the announced size (within the capacity) first.
        if block.size.is_some_and(|size| len != size as usize) {
            return Err(SdoAbort::LengthMismatch);
        }
        if len > block.target.capacity {
            return Err(SdoAbort::LengthTooHigh);
        }
        self.flush_held(&mut block, last, od)?;
        if block.check_crc && block.crc.value() != crc {
            return Err(SdoAbort::CrcError);
        }
        self.transfer = Transfer::Idle;
        self.commit(&block.target, len, od)?;
        // End block download response (ss = 1).
        self.respond(command::of(scs::BLOCK_DOWNLOAD) | 1, [0; SEGMENT_DATA_LEN]);
        Ok(())
    }

    fn initiate_block_upload<O: ObjectDictionary + ?Sized>(
        &mut self,
        mux: Multiplexer,
        crc: bool,
        blksize: u8,
        pst: u8,
        od: &O,
    ) -> Handled {
        let (position, fixed) = Self::accessible_entry(mux, false, od)?;
        let total = Self::upload_len(position, fixed, od)?;
        if blksize == 0 || blksize > MAX_BLOCK_SIZE {
            return Err(SdoAbort::InvalidBlockSize);
        }
        if pst != 0 && total <= usize::from(pst) {
            return self.start_upload(position, total, od);
        }
        let size = u32::try_from(total).map_err(|_| SdoAbort::LengthTooHigh)?;
        self.transfer = Transfer::BlockUpload(BlockUpload {
            crc,
            position,
            total,
            blksize,
            acked_segments: 0,
            sent: 0,
            phase: BlockUploadPhase::WaitStart,
        });
        // Initiate block upload response (ss = 0), CRC supported (sc), the size indicated (s).
        let response =
            command::of(scs::BLOCK_UPLOAD) | command::crc_bit(true) | command::BLOCK_SIZE_INDICATED;
        self.respond_mux(response, size);
        Ok(())
    }

    fn block_upload_ack<O: ObjectDictionary + ?Sized>(
        &mut self,
        mut upload: BlockUpload,
        ackseq: u8,
        blksize: u8,
        od: &O,
    ) -> Handled {
        if ackseq > upload.sent {
            return Err(SdoAbort::InvalidSequence);
        }
        if blksize == 0 || blksize > MAX_BLOCK_SIZE {
            return Err(SdoAbort::InvalidBlockSize);
        }
        upload.acked_segments += usize::from(ackseq);
        upload.sent = 0;
        upload.blksize = blksize;
        if upload.acked_segments >= upload.segments() {
            let crc = if upload.crc {
                Self::value_crc(upload.position, upload.total, od)?
            } else {
                0
            };
            let unused = (upload.segments() * SEGMENT_DATA_LEN - upload.total) as u8;
            upload.phase = BlockUploadPhase::WaitEnd;
            // End block upload request (ss = 1) with n unused bytes.
            let [crc_lo, crc_hi] = crc.to_le_bytes();
            let response = command::of(scs::BLOCK_UPLOAD) | command::block_end_bits(unused) | 1;
            self.respond(response, [crc_lo, crc_hi, 0, 0, 0, 0, 0]);
        } else {
            upload.phase = BlockUploadPhase::Sending;
        }
        self.transfer = Transfer::BlockUpload(upload);
        Ok(())
    }

    /// The CRC of the first `total` bytes of the addressed value, read from the dictionary.
    fn value_crc<O: ObjectDictionary + ?Sized>(
        position: usize,
        total: usize,
        od: &O,
    ) -> Result<u16, SdoAbort> {
        let mut crc = Crc16::new();
        let mut chunk = [0u8; 32];
        let mut offset = 0;
        while offset < total {
            let want = (total - offset).min(chunk.len());
            let read = od.read_at(position, offset, &mut chunk[..want])?;
            if read != want {
                return Err(SdoAbort::General);
            }
            crc.update(&chunk[..want]);
            offset += want;
        }
        Ok(crc.value())
    }
}
