//! Record access of the AR (p-net's `pf_cmrdr`, `pf_cmwrr`): Read and Write of a submodule's
//! records, with their exact length; RealIdentificationData (0xF000) and I&M0 (0xAFF0) read back
//! from the device's configuration.

use super::super::wire::append;
use super::super::wire::blocks::*;
use super::super::wire::rpc::*;
use super::{ArEvent, Cm};

impl Cm {
    /// The record access header that starts `args`, and the record data after it.
    fn iod(args: &[u8], expect: u16, code: u8) -> Result<(IodHeader, &[u8]), PnioStatus> {
        let err = PnioStatus::new(code, PnioStatus::DECODE_PNIORW, 0xB8, 0);
        let mut r = Reader::new(args);
        let (block_type, len) = (r.u16().ok_or(err)?, r.u16().ok_or(err)?);
        let body = r.take(usize::from(len)).ok_or(err)?;
        if block_type != expect || len < 2 {
            return Err(err);
        }
        let header = IodHeader::parse(block_type, &body[2..]).ok_or(err)?;
        Ok((header, r.rest()))
    }

    pub(super) fn read(&mut self, args: &[u8], implicit: bool) -> Result<Vec<u8>, PnioStatus> {
        let code = PnioStatus::CODE_READ;
        let rw = |c1| PnioStatus::new(code, PnioStatus::DECODE_PNIORW, c1, 0);
        let (req, _) = Self::iod(args, IOD_READ_REQ, code)?;
        if !implicit && self.ar_of(req.ar_uuid, None).is_none() {
            return Err(rw(0xB5));
        }
        let mut data = Vec::new();
        if req.index == 0xF000 {
            let real = RealIdentificationData {
                apis: vec![ApiIdent {
                    api: 0,
                    modules: self
                        .config
                        .slots
                        .iter()
                        .map(|s| SlotIdent {
                            slot: s.slot,
                            module_ident: s.module_ident,
                            state: 0,
                            submodules: s
                                .submodules
                                .iter()
                                .map(|sub| (sub.subslot, sub.ident, 0))
                                .collect(),
                        })
                        .collect(),
                }],
            };
            append_block(&mut data, |b| real.emit(b));
        } else {
            self.config
                .submodule(req.slot, req.subslot)
                .ok_or(rw(0xB2))?;
            if req.index == 0xAFF0 {
                self.im0(&mut data);
            } else {
                let (_, value) = self
                    .records
                    .iter()
                    .find(|(at, _)| *at == (req.slot, req.subslot, req.index))
                    .ok_or(rw(0xB0))?;
                data = value.clone();
            }
        }
        let len = data
            .len()
            .min(usize::try_from(req.record_length).unwrap_or(usize::MAX));
        data.truncate(len);
        let mut out = Vec::new();
        append(&mut out, |b| {
            req.response(len as u32, PnioStatus::OK).emit(b)
        });
        out.extend_from_slice(&data);
        Ok(out)
    }

    /// I&M0 (version 1.1): VendorID, OrderID, serial number, revisions, I&M0 only supported.
    fn im0(&self, out: &mut Vec<u8>) {
        emit_block(out, IM0, 0, |o| {
            o.extend_from_slice(&self.vendor_id.to_be_bytes());
            let mut order = self.order_id.as_bytes().to_vec();
            order.resize(20, b' ');
            o.extend_from_slice(&order);
            let mut serial = b"0001".to_vec();
            serial.resize(16, b' ');
            o.extend_from_slice(&serial);
            o.extend_from_slice(&[0, 1]); // hardware revision
            o.extend_from_slice(b"V"); // software revision prefix
            o.extend_from_slice(&[1, 0, 0]);
            o.extend_from_slice(&[0, 0]); // revision counter
            o.extend_from_slice(&[0, 0]); // profile ID: none
            o.extend_from_slice(&[0, 0]); // profile specific type
            o.extend_from_slice(&[1, 1]); // I&M version 1.1
            o.extend_from_slice(&[0, 0]); // I&M supported: I&M0 only
        });
    }

    pub(super) fn write(&mut self, args: &[u8]) -> Result<Vec<u8>, PnioStatus> {
        let code = PnioStatus::CODE_WRITE;
        let rw = |c1| PnioStatus::new(code, PnioStatus::DECODE_PNIORW, c1, 0);
        let (req, data) = Self::iod(args, IOD_WRITE_REQ, code)?;
        if self.ar_of(req.ar_uuid, None).is_none() {
            return Err(rw(0xB5));
        }
        let data = data
            .get(..usize::try_from(req.record_length).unwrap_or(usize::MAX))
            .ok_or(rw(0xB1))?;
        self.config
            .submodule(req.slot, req.subslot)
            .ok_or(rw(0xB2))?;
        let (_, value) = self
            .records
            .iter_mut()
            .find(|(at, _)| *at == (req.slot, req.subslot, req.index))
            .ok_or(rw(0xB0))?;
        if value.len() != data.len() {
            return Err(rw(0xB1));
        }
        value.copy_from_slice(data);
        self.events.push(ArEvent::RecordWritten {
            slot: req.slot,
            subslot: req.subslot,
            index: req.index,
            data: data.to_vec(),
        });
        let mut out = Vec::new();
        append(&mut out, |b| {
            req.response(req.record_length, PnioStatus::OK).emit(b)
        });
        Ok(out)
    }

    /// Sets the content of the record at (slot, subslot, index), if the GSDML has it with
    /// this length (the application's own values, such as the drive's parameters).
    pub fn set_record(&mut self, at: (u16, u16, u16), data: &[u8]) {
        if let Some((_, value)) = self.records.iter_mut().find(|(a, _)| *a == at) {
            if value.len() == data.len() {
                value.copy_from_slice(data);
            }
        }
    }
}
