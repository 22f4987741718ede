//! The async master's SDO channels: one SDO client per node with the transfers queued for it,
//! run side by side by the driver thread, each completing its future when it ends.

use std::collections::{BTreeMap, VecDeque};
use std::io;

use crate::Transport;
use edsgen_runtime::master::sdo_client::{Mode, SdoClient, SdoError, StartError};
use edsgen_runtime::time::{Duration, Instant};
use edsgen_runtime::wire::sdo::Multiplexer;

use super::super::blocking::{Feed, MasterError, ReadFeed};
use super::slot::{Done, Reply};

/// A reader a download of unannounced size takes its bytes from, on the driver thread.
pub(super) type Source = ReadFeed<Box<dyn io::Read + Send>>;

pub(super) enum Transfer {
    Upload(Multiplexer, Mode),
    Download(Multiplexer, Vec<u8>, Mode),
    DownloadFrom(Multiplexer, Box<Source>, Mode),
}

pub(super) struct Job {
    pub(super) transfer: Transfer,
    pub(super) reply: Reply,
    /// Download: bytes handed to the client so far. Upload: bytes received.
    pub(super) sent: usize,
    pub(super) received: Vec<u8>,
    /// The source's error that ended the transfer.
    pub(super) failed: Option<io::Error>,
    /// Upload: how many more times it is tried after a timeout before any byte arrived.
    pub(super) retries: u8,
}

/// One node's SDO channel and the transfers waiting for it.
pub(super) struct Channel {
    pub(super) client: SdoClient,
    /// The timeout was set for this node ([`AsyncMaster::set_timeout`](super::AsyncMaster::set_timeout)), not by default.
    pub(super) own_timeout: bool,
    pub(super) current: Option<Job>,
    pub(super) queue: VecDeque<Job>,
}

pub(super) fn channel(
    channels: &mut BTreeMap<u8, Channel>,
    node_id: u8,
    timeout: Duration,
) -> &mut Channel {
    channels.entry(node_id).or_insert_with(|| {
        let mut client = SdoClient::new(node_id);
        client.set_timeout(timeout);
        Channel {
            client,
            own_timeout: false,
            current: None,
            queue: VecDeque::new(),
        }
    })
}

/// Starts the next transfer of an idle channel, moves data in and out of a busy one, sends its
/// frames and completes its future when it ends.
pub(super) fn run_channel<T: Transport>(
    channel: &mut Channel,
    now: Instant,
    transport: &mut T,
) -> io::Result<()> {
    complete(channel);
    if channel.current.is_none() {
        if let Some(job) = channel.queue.pop_front() {
            let client = &mut channel.client;
            let started = match &job.transfer {
                Transfer::Upload(mux, mode) => client.upload(now, *mux, *mode),
                Transfer::Download(mux, data, mode) => u32::try_from(data.len())
                    .map_err(|_| StartError::Value)
                    .and_then(|size| client.download(now, *mux, size, *mode)),
                Transfer::DownloadFrom(mux, _, mode) => client.download_unsized(now, *mux, *mode),
            };
            match started {
                Ok(()) => channel.current = Some(job),
                Err(StartError::Value) => job.reply.send(Err(MasterError::Value)),
                Err(StartError::Busy) => job.reply.send(Err(MasterError::Busy(client.node_id()))),
            }
        }
    }
    let client = &mut channel.client;
    if client.poll_timeout().is_some_and(|at| at <= now) {
        client.handle_timeout(now);
    }
    if let Some(job) = channel.current.as_mut() {
        match &mut job.transfer {
            Transfer::Download(_, data, _) => job.sent += client.write_data(&data[job.sent..]),
            Transfer::DownloadFrom(_, source, _) => {
                if let Err(e) = source.feed(client) {
                    job.failed = Some(e);
                    client.abort(edsgen_runtime::od::SdoAbort::General.code());
                }
            }
            Transfer::Upload(..) => {}
        }
        drain(client, &mut job.received);
    }
    while let Some(frame) = client.poll_transmit(now) {
        transport.send(&frame)?;
    }
    complete(channel);
    Ok(())
}

/// Completes the channel's transfer if it has ended (or queues a read that timed out before any
/// byte arrived again, if it has retries left).
pub(super) fn complete(channel: &mut Channel) {
    let client = &mut channel.client;
    let Some(result) = client.poll_result() else {
        return;
    };
    if let Some(mut job) = channel.current.take() {
        drain(client, &mut job.received);
        if result == Err(SdoError::Timeout) && job.retries > 0 && job.received.is_empty() {
            job.retries -= 1;
            channel.queue.push_front(job);
            return;
        }
        let (node_id, mux) = (client.node_id(), client.mux());
        let outcome = match (result, job.failed.take()) {
            (_, Some(e)) => Err(MasterError::Io(e)),
            (Ok(done), None) => Ok(Done {
                bytes: core::mem::take(&mut job.received),
                size: done.size,
            }),
            (Err(error), None) => Err(MasterError::Sdo {
                node_id,
                mux,
                error,
            }),
        };
        job.reply.send(outcome);
    }
}

pub(super) fn drain(client: &mut SdoClient, into: &mut Vec<u8>) {
    let mut chunk = [0u8; 256];
    loop {
        let n = client.read_data(&mut chunk);
        if n == 0 {
            return;
        }
        into.extend_from_slice(&chunk[..n]);
    }
}
