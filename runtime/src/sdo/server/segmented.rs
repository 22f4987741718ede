//! Expedited and segmented (normal) transfers in both directions: the initiate requests and the
//! segments that follow them.

use crate::od::{ObjectDictionary, SdoAbort};
use crate::wire::sdo::command::scs;
use crate::wire::sdo::{command, Frame, Multiplexer, SEGMENT_DATA_LEN};

use super::{Download, Handled, SdoServer, Transfer, Upload, WriteTarget};

impl SdoServer {
    pub(super) fn initiate_download<O: ObjectDictionary + ?Sized>(
        &mut self,
        mux: Multiplexer,
        request: Frame<'_>,
        od: &mut O,
    ) -> Handled {
        let target = Self::writable_entry(mux, od)?;
        let data = request.data();
        let len = match (request.expedited(), request.size_indicated()) {
            (true, true) => usize::from(request.expedited_len()),
            (true, false) => {
                let len = target.capacity;
                if !(1..=data.len()).contains(&len) {
                    return Err(SdoAbort::LengthMismatch);
                }
                len
            }
            (false, indicated) => {
                let size = indicated.then(|| request.value());
                return self.start_download(target, size, od);
            }
        };
        od.write_at(target.position, &data[..len])?;
        self.respond_mux(command::of(scs::INITIATE_DOWNLOAD), 0);
        Ok(true)
    }

    fn start_download<O: ObjectDictionary + ?Sized>(
        &mut self,
        target: WriteTarget,
        size: Option<u32>,
        od: &mut O,
    ) -> Handled {
        Self::check_announced_size(&target, size)?;
        Self::open(&target, od)?;
        self.transfer = Transfer::Download(Download {
            toggle: false,
            size,
            target,
            len: 0,
        });
        self.respond_mux(command::of(scs::INITIATE_DOWNLOAD), 0);
        Ok(false)
    }

    pub(super) fn download_segment<O: ObjectDictionary + ?Sized>(
        &mut self,
        download: Download,
        toggle: bool,
        bytes: &[u8],
        last: bool,
        od: &mut O,
    ) -> Handled {
        if toggle != download.toggle {
            return Err(SdoAbort::ToggleBit);
        }
        let end = download.len + bytes.len();
        // One test of the announced size: data beyond it, or a last segment ending short of it
        // (an announced size is within the capacity, so beyond the capacity is beyond it too).
        if download
            .size
            .is_some_and(|size| end > size as usize || last && end != size as usize)
        {
            return Err(SdoAbort::LengthMismatch);
        }
        if end > download.target.capacity {
            return Err(SdoAbort::LengthTooHigh);
        }
        self.store(&download.target, download.len, bytes, od)?;
        if last {
            self.transfer = Transfer::Idle;
            self.commit(&download.target, end, od)?;
        } else if let Transfer::Download(open) = &mut self.transfer {
            // What changed, in place: writing the whole transfer back costs more flash.
            open.len = end;
            open.toggle = !toggle;
        }
        // The segment's toggle bit, acknowledged.
        let response = command::of(scs::DOWNLOAD_SEGMENT) | command::toggle_bit(toggle);
        self.respond(response, [0; SEGMENT_DATA_LEN]);
        Ok(last)
    }

    pub(super) fn initiate_upload<O: ObjectDictionary + ?Sized>(
        &mut self,
        mux: Multiplexer,
        od: &O,
    ) -> Handled {
        let (position, total) = Self::upload_len(mux, od)?;
        self.start_upload(position, total, od)
    }

    /// Answers an upload of `total` bytes: expedited when it fits, else the first step of a
    /// segmented upload.
    pub(super) fn start_upload<O: ObjectDictionary + ?Sized>(
        &mut self,
        position: usize,
        total: usize,
        od: &O,
    ) -> Handled {
        let mut data = [0u8; 4];
        if (1..=data.len()).contains(&total) {
            let read = od.read_at(position, 0, &mut data[..total])?;
            if read != total {
                return Err(SdoAbort::General);
            }
            // Expedited, the size indicated; the unused bytes are zero, as `data` was.
            let response = command::of(scs::INITIATE_UPLOAD) | command::expedited_bits(total as u8);
            self.respond_mux(response, u32::from_le_bytes(data));
        } else {
            let size = u32::try_from(total).map_err(|_| SdoAbort::LengthTooHigh)?;
            self.transfer = Transfer::Upload(Upload {
                toggle: false,
                position,
                offset: 0,
                total,
            });
            // Segmented, the size indicated (s).
            self.respond_mux(
                command::of(scs::INITIATE_UPLOAD) | command::SIZE_INDICATED,
                size,
            );
        }
        Ok(false)
    }

    pub(super) fn upload_segment<O: ObjectDictionary + ?Sized>(
        &mut self,
        upload: Upload,
        toggle: bool,
        od: &O,
    ) -> Handled {
        if toggle != upload.toggle {
            return Err(SdoAbort::ToggleBit);
        }
        let chunk = upload
            .total
            .saturating_sub(upload.offset)
            .min(SEGMENT_DATA_LEN);
        let mut bytes = [0u8; SEGMENT_DATA_LEN];
        let read = od.read_at(upload.position, upload.offset, &mut bytes[..chunk])?;
        if read != chunk {
            // The value shrank during the upload: what was announced cannot be delivered.
            return Err(SdoAbort::General);
        }
        let offset = upload.offset + chunk;
        let last = offset >= upload.total;
        if last {
            self.transfer = Transfer::Idle;
        } else if let Transfer::Upload(open) = &mut self.transfer {
            // What changed, in place, as for a download segment.
            open.offset = offset;
            open.toggle = !toggle;
        }
        // 7 - chunk unused bytes, zero as `bytes` was.
        let unused = (SEGMENT_DATA_LEN - chunk) as u8;
        let response =
            command::of(scs::UPLOAD_SEGMENT) | command::segment_bits(toggle, unused, last);
        self.respond(response, bytes);
        Ok(false)
    }
}
