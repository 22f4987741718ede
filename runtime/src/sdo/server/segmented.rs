//! Expedited and segmented (normal) transfers in both directions: the initiate requests and the
//! segments that follow them.

use crate::od::{ObjectDictionary, SdoAbort};
use crate::wire::sdo::command::{ccs, scs};
use crate::wire::sdo::{command, Frame, SEGMENT_DATA_LEN};

use super::{Handled, SdoServer, Segmented, Transfer, WriteTarget};

impl SdoServer {
    /// Answers a download into `target`: writes an expedited value, or starts a segmented
    /// download.
    pub(super) fn initiate_download<O: ObjectDictionary + ?Sized>(
        &mut self,
        target: WriteTarget,
        request: Frame<'_>,
        od: &mut O,
    ) -> Handled {
        if request.expedited() {
            // The size indicated, else the entry's, which must fit the four bytes.
            let len = if request.size_indicated() {
                usize::from(request.expedited_len())
            } else {
                target.capacity
            };
            let data = request.data();
            if !(1..=data.len()).contains(&len) {
                return Err(SdoAbort::LengthMismatch);
            }
            od.write_at(target.position, &data[..len])?;
        } else {
            let size = request.size_indicated().then(|| request.value());
            Self::check_announced_size(&target, size)?;
            Self::open(&target, od)?;
            self.transfer = Transfer::Segmented(Segmented {
                download: true,
                toggle: false,
                sized: size.is_some(),
                target,
                end: size.map_or(target.capacity, |size| size as usize),
                offset: 0,
            });
        }
        self.respond_mux(command::of(scs::INITIATE_DOWNLOAD), 0);
        Ok(())
    }

    /// A download or upload segment: one step for both directions, which share the toggle, the
    /// length and the end. A download's segment is checked against where the transfer ends
    /// (data beyond it, or a last segment short of an announced size) and stored; an upload's
    /// is read from the dictionary. The last one ends the transfer, a download's committing it.
    pub(super) fn segment<O: ObjectDictionary + ?Sized>(
        &mut self,
        request: Frame<'_>,
        od: &mut O,
    ) -> Handled {
        let download = request.specifier() == ccs::DOWNLOAD_SEGMENT;
        let transfer = match self.transfer {
            Transfer::Segmented(transfer) if transfer.download == download => transfer,
            _ => return Err(SdoAbort::InvalidCommand),
        };
        let toggle = request.toggle();
        if toggle != transfer.toggle {
            return Err(SdoAbort::ToggleBit);
        }
        // An upload's bytes; a download's response carries none, zero as this was.
        let mut data = [0u8; SEGMENT_DATA_LEN];
        let (len, last) = if download {
            let bytes = request.segment_data();
            let end = transfer.offset + bytes.len();
            // An announced size is within the capacity: beyond it is a mismatch, beyond the
            // capacity without one too long.
            if end > transfer.end || transfer.sized && request.last() && end != transfer.end {
                return Err(if transfer.sized {
                    SdoAbort::LengthMismatch
                } else {
                    SdoAbort::LengthTooHigh
                });
            }
            self.store(&transfer.target, transfer.offset, bytes, od)?;
            (bytes.len(), request.last())
        } else {
            let len = transfer
                .end
                .saturating_sub(transfer.offset)
                .min(SEGMENT_DATA_LEN);
            let read = od.read_at(transfer.target.position, transfer.offset, &mut data[..len])?;
            if read != len {
                // The value shrank during the upload: what was announced cannot be delivered.
                return Err(SdoAbort::General);
            }
            (len, transfer.offset + len >= transfer.end)
        };
        let offset = transfer.offset + len;
        if last {
            self.transfer = Transfer::Idle;
            if download {
                self.commit(&transfer.target, offset, od)?;
            }
        } else if let Transfer::Segmented(open) = &mut self.transfer {
            // What changed, in place: writing the whole transfer back costs more flash.
            open.offset = offset;
            open.toggle = !toggle;
        }
        // The segment's toggle bit, acknowledged; an upload's says how many of its 7 bytes
        // are unused and whether it is the last.
        let response = if download {
            command::of(scs::DOWNLOAD_SEGMENT) | command::toggle_bit(toggle)
        } else {
            let unused = (SEGMENT_DATA_LEN - len) as u8;
            command::of(scs::UPLOAD_SEGMENT) | command::segment_bits(toggle, unused, last)
        };
        self.respond(response, data);
        Ok(())
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
            self.transfer = Transfer::Segmented(Segmented {
                download: false,
                toggle: false,
                sized: true,
                // Fixed: nothing is open in the dictionary for an upload, nothing to release.
                target: WriteTarget {
                    position,
                    capacity: total,
                    fixed: true,
                },
                end: total,
                offset: 0,
            });
            // Segmented, the size indicated (s).
            self.respond_mux(
                command::of(scs::INITIATE_UPLOAD) | command::SIZE_INDICATED,
                size,
            );
        }
        Ok(())
    }
}
