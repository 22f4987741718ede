//! The blocking master's SDO transfers: typed and raw reads and writes, streamed uploads and
//! downloads (the [`Feed`]s a download's bytes come from) and configuration downloads.

use std::io;

use crate::Transport;
use edsgen_runtime::master::sdo_client::{Mode, SdoClient, SdoError, StartError};
use edsgen_runtime::od::access::{Readable, Writable};
use edsgen_runtime::od::entry::{Entry, OdValue};
use edsgen_runtime::wire::sdo::Multiplexer;

use super::{Master, MasterError};

impl<T: Transport> Master<T> {
    /// Reads `entry` of `node_id`, typed (an address of any device's generated module).
    pub fn read<V: OdValue, D, A: Readable>(
        &mut self,
        node_id: u8,
        entry: Entry<V, D, A>,
    ) -> Result<V, MasterError> {
        let mux = Multiplexer::new(entry.index, entry.sub);
        let bytes = self.upload(node_id, mux, Mode::Normal)?;
        entry.decode(&bytes).ok_or(MasterError::Length {
            node_id,
            mux,
            got: bytes.len(),
        })
    }

    /// Writes `value` to `entry` of `node_id`.
    pub fn write<V: OdValue, D, A: Writable>(
        &mut self,
        node_id: u8,
        entry: Entry<V, D, A>,
        value: V,
    ) -> Result<(), MasterError> {
        let now = self.clock.now();
        let client = self.client(node_id)?;
        match client.write(now, entry, &value) {
            Ok(()) => {}
            Err(StartError::Value) => return Err(MasterError::Value),
            Err(StartError::Busy) => return Err(MasterError::Busy(node_id)),
        }
        self.finish(node_id, &mut [].as_slice(), &mut Vec::new())
            .map(|_| ())
    }

    /// Reads the value of (index, sub) as bytes, by `mode`.
    pub fn upload(
        &mut self,
        node_id: u8,
        mux: Multiplexer,
        mode: Mode,
    ) -> Result<Vec<u8>, MasterError> {
        let mut value = Vec::new();
        self.upload_to(node_id, mux, mode, &mut value)?;
        Ok(value)
    }

    /// Reads the value of (index, sub) into `sink` as it arrives (a domain of any length);
    /// returns its length. On an error what `sink` took is part of a value at most, never the
    /// value: discard it (`edsgen sdo read --out FILE` writes to `FILE.partial` and renames it
    /// only on success). [`upload`](Self::upload) hands back a value only when complete.
    pub fn upload_to(
        &mut self,
        node_id: u8,
        mux: Multiplexer,
        mode: Mode,
        sink: &mut impl io::Write,
    ) -> Result<u32, MasterError> {
        let mut sink = CountingSink {
            inner: sink,
            count: 0,
        };
        let mut retries = self.read_retries;
        loop {
            let now = self.clock.now();
            if self.client(node_id)?.upload(now, mux, mode).is_err() {
                return Err(MasterError::Busy(node_id));
            }
            match self.finish(node_id, &mut [].as_slice(), &mut sink) {
                Err(MasterError::Sdo {
                    error: SdoError::Timeout,
                    ..
                }) if retries > 0 && sink.count == 0 => retries -= 1,
                result => return result.map(|done| done.size),
            }
        }
    }

    /// Writes `data` to (index, sub) by `mode`.
    pub fn download(
        &mut self,
        node_id: u8,
        mux: Multiplexer,
        data: &[u8],
        mode: Mode,
    ) -> Result<(), MasterError> {
        let now = self.clock.now();
        let size = u32::try_from(data.len()).map_err(|_| MasterError::Value)?;
        if self
            .client(node_id)?
            .download(now, mux, size, mode)
            .is_err()
        {
            return Err(MasterError::Busy(node_id));
        }
        self.finish(node_id, &mut &data[..], &mut io::sink())
            .map(|_| ())
    }

    /// Writes to (index, sub) by `mode` a value read from `source` until its end, of a length
    /// not known up front (a file, a generated image): the size is not indicated (see
    /// [`SdoClient::download_unsized`]). Returns the value's length. An error of `source`
    /// aborts the transfer (0800 0000) and is returned as [`MasterError::Io`].
    pub fn download_from(
        &mut self,
        node_id: u8,
        mux: Multiplexer,
        mode: Mode,
        source: &mut impl io::Read,
    ) -> Result<u32, MasterError> {
        let now = self.clock.now();
        if self
            .client(node_id)?
            .download_unsized(now, mux, mode)
            .is_err()
        {
            return Err(MasterError::Busy(node_id));
        }
        let mut source = ReadFeed::new(source);
        self.finish(node_id, &mut source, &mut io::sink())
            .map(|done| done.size)
    }

    /// Downloads a configuration (a DCF's ParameterValues) in the safe order of
    /// [`download_order`](edsgen_runtime::master::dcf::download_order); the first write the node refuses is the
    /// error (naming the entry).
    pub fn download_configuration<V: AsRef<[u8]>>(
        &mut self,
        node_id: u8,
        entries: &[(Multiplexer, V)],
    ) -> Result<(), MasterError> {
        for (mux, value) in edsgen_runtime::master::dcf::download_order(entries) {
            value.with_bytes(|bytes| self.download(node_id, mux, bytes, Mode::Normal))?;
        }
        Ok(())
    }
}

/// Where a download's bytes come from.
pub(in crate::master) trait Feed {
    /// Gives `client` as many bytes as its window takes now (and ends a value of unannounced
    /// size at the source's end).
    fn feed(&mut self, client: &mut SdoClient) -> io::Result<()>;
}

/// A value in memory, of known size.
impl Feed for &[u8] {
    fn feed(&mut self, client: &mut SdoClient) -> io::Result<()> {
        let taken = client.write_data(self);
        *self = &self[taken..];
        Ok(())
    }
}

/// A value read from a reader until its end, of unannounced size.
pub(in crate::master) struct ReadFeed<R> {
    reader: R,
    chunk: [u8; 256],
    /// The chunk's bytes not yet taken by the client.
    start: usize,
    end: usize,
    done: bool,
}

impl<R: io::Read> ReadFeed<R> {
    pub(in crate::master) fn new(reader: R) -> Self {
        ReadFeed {
            reader,
            chunk: [0; 256],
            start: 0,
            end: 0,
            done: false,
        }
    }
}

impl<R: io::Read> Feed for ReadFeed<R> {
    fn feed(&mut self, client: &mut SdoClient) -> io::Result<()> {
        loop {
            if self.start == self.end && !self.done {
                let n = loop {
                    match self.reader.read(&mut self.chunk) {
                        Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                        result => break result?,
                    }
                };
                (self.start, self.end) = (0, n);
                self.done = n == 0;
            }
            if self.done {
                client.end_data();
                return Ok(());
            }
            let taken = client.write_data(&self.chunk[self.start..self.end]);
            self.start += taken;
            if taken == 0 {
                return Ok(()); // the window is full
            }
        }
    }
}

/// A sink that counts what it was given, so that a read is repeated only if nothing of it
/// reached the caller.
struct CountingSink<'a, W> {
    inner: &'a mut W,
    count: usize,
}

impl<W: io::Write> io::Write for CountingSink<'_, W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = self.inner.write(buf)?;
        self.count += n;
        Ok(n)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush()
    }
}

pub(super) fn drain(client: &mut SdoClient, sink: &mut impl io::Write) -> io::Result<()> {
    let mut chunk = [0u8; 256];
    loop {
        let n = client.read_data(&mut chunk);
        if n == 0 {
            return Ok(());
        }
        sink.write_all(&chunk[..n])?;
    }
}
