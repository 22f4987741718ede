//! Shared helpers of the master tests: an SDO server with a large domain on the virtual bus.
#![allow(dead_code)]

use edsgen_host::vbus::BusDevice;
use edsgen_runtime::sdo::SdoServer;
use edsgen_runtime::{
    Access, CanFrame, DataType, Duration, EntryDescriptor, Instant, ObjectDictionary, SdoAbort,
};

/// A dictionary with a DOMAIN at 2100h:00 (up to 64 KiB) and an UNSIGNED16 at 2101h:00.
#[derive(Debug, Default)]
pub struct DomainOd {
    pub domain: Vec<u8>,
    pub word: u16,
    /// A download into the domain until it completes.
    pub incoming: Option<Vec<u8>>,
}

const ENTRIES: [EntryDescriptor; 2] = [
    EntryDescriptor::new(0x2100, 0, DataType::Domain, Access::Rw, false),
    EntryDescriptor::new(0x2101, 0, DataType::Unsigned16, Access::Rw, false),
];

/// The domain's capacity.
pub const DOMAIN_CAPACITY: usize = 64 * 1024;

impl ObjectDictionary for DomainOd {
    fn entry_count(&self) -> usize {
        ENTRIES.len()
    }

    fn entry(&self, position: usize) -> Option<EntryDescriptor> {
        ENTRIES.get(position).copied()
    }
    fn capacity(&self, position: usize) -> Option<usize> {
        Some(if position == 0 { DOMAIN_CAPACITY } else { 2 })
    }
    fn value_len(&self, index: u16, sub: u8) -> Result<usize, SdoAbort> {
        match self.locate(index, sub)? {
            0 => Ok(self.domain.len()),
            _ => Ok(2),
        }
    }
    fn read(&self, index: u16, sub: u8, offset: usize, buf: &mut [u8]) -> Result<usize, SdoAbort> {
        let word = self.word.to_le_bytes();
        let value: &[u8] = match self.locate(index, sub)? {
            0 => &self.domain,
            _ => &word,
        };
        let rest = value.get(offset..).unwrap_or(&[]);
        let n = rest.len().min(buf.len());
        buf[..n].copy_from_slice(&rest[..n]);
        Ok(n)
    }
    fn write(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<(), SdoAbort> {
        match self.locate(index, sub)? {
            0 => self.domain = data.to_vec(),
            _ => {
                let bytes: [u8; 2] = data.try_into().map_err(|_| SdoAbort::LengthMismatch)?;
                self.word = u16::from_le_bytes(bytes);
            }
        }
        Ok(())
    }
    /// The domain (position 0) takes a download piece by piece, into `incoming` until it
    /// completes.
    fn begin_write(&mut self, _position: usize) -> Result<(), SdoAbort> {
        self.incoming = Some(Vec::new());
        Ok(())
    }
    fn write_part(&mut self, position: usize, offset: usize, data: &[u8]) -> Result<(), SdoAbort> {
        if position != 0 || offset + data.len() > DOMAIN_CAPACITY {
            return Err(SdoAbort::LengthTooHigh);
        }
        let incoming = self.incoming.as_mut().ok_or(SdoAbort::General)?;
        incoming.truncate(offset);
        incoming.extend_from_slice(data);
        Ok(())
    }
    fn commit_write(&mut self, position: usize, len: usize) -> Result<(), SdoAbort> {
        let mut incoming = self.incoming.take().ok_or(SdoAbort::General)?;
        if position == 0 {
            incoming.truncate(len);
            self.domain = incoming;
        }
        Ok(())
    }
    fn abort_write(&mut self, _position: usize) {
        self.incoming = None;
    }
}

/// An SDO server of `node_id` serving a [`DomainOd`], with a 64 KiB download buffer.
pub struct DomainServer {
    pub node_id: u8,
    pub od: DomainOd,
    server: Box<SdoServer>,
}

impl DomainServer {
    pub fn new(node_id: u8) -> Self {
        DomainServer {
            node_id,
            od: DomainOd::default(),
            server: Box::new(SdoServer::new(Duration::from_millis(1000))),
        }
    }
}

impl BusDevice for DomainServer {
    fn handle_frame(&mut self, now: Instant, frame: &CanFrame) {
        if frame.std_id() == Some(0x600 + u16::from(self.node_id)) {
            self.server.handle(now, frame.data(), &mut self.od);
        }
    }
    fn poll_transmit(&mut self, now: Instant) -> Option<CanFrame> {
        let data = self.server.poll_transmit(now, &self.od)?;
        CanFrame::new(0x580 + u16::from(self.node_id), &data)
    }
    fn poll_timeout(&self) -> Option<Instant> {
        self.server.poll_timeout()
    }
    fn handle_timeout(&mut self, now: Instant) {
        self.server.handle_timeout(now, &mut self.od)
    }
}

/// A value of `len` bytes that shows misplaced bytes: byte i is (i * 7 + i / 251) mod 256.
pub fn pattern(len: usize) -> Vec<u8> {
    (0..len).map(|i| (i * 7 + i / 251) as u8).collect()
}
