//! The async master's driver thread: it owns the transport, takes the [`AsyncMaster`]'s
//! requests, runs the SDO channels, the node monitor and the EMCY consumer on its clock, and
//! hands outcomes and events back.

use std::collections::BTreeMap;
use std::sync::mpsc::{Receiver, TryRecvError};
use std::time::Duration as StdDuration;

use crate::driver::MonotonicClock;
use crate::Transport;
use edsgen_runtime::frame::CanFrame;
use edsgen_runtime::master::emcy::Emergency;
use edsgen_runtime::master::nmt::{NodeMonitor, Watch};
use edsgen_runtime::master::sdo_client::DEFAULT_TIMEOUT;
use edsgen_runtime::time::{Duration, Instant};
use edsgen_runtime::wire::heartbeat::ErrorControlRepr;

use super::super::blocking::{MasterError, MasterEvent};
use super::channel::{channel, run_channel, Channel, Job, Transfer};
use super::lss::{LssChannel, LssJob};
use super::slot::{Done, EventSender, Reply};
#[cfg(doc)]
use super::AsyncMaster;

/// How long the driver thread waits for a frame before it looks for new requests again.
const POLL: StdDuration = StdDuration::from_millis(1);

pub(super) enum Request {
    Sdo(u8, Job),
    Frame(CanFrame, Reply),
    Timeout(u8, Duration),
    DefaultTimeout(Duration),
    ReadRetries(u8),
    WaitBoot(u8, Duration, Reply),
    Watch(u8, Watch, Reply),
    Lss(LssJob),
}

/// A wait for a node's boot-up: the node, until when, and the future to complete.
type BootWait = (u8, Instant, Reply);

/// The driver thread: requests in, transfers run side by side, outcomes out, until the
/// [`AsyncMaster`] is dropped and nothing is pending, or the transport fails.
pub(super) fn drive<T: Transport>(
    mut transport: T,
    requests: Receiver<Request>,
    events: EventSender,
) {
    let clock = MonotonicClock::new();
    let mut monitor: Box<NodeMonitor<127>> = Box::default();
    let mut default_timeout = DEFAULT_TIMEOUT;
    let mut read_retries = 1;
    let mut channels: BTreeMap<u8, Channel> = BTreeMap::new();
    let mut lss = LssChannel::default();
    let mut boot_waits: Vec<BootWait> = Vec::new();
    let mut booted: Vec<u8> = Vec::new();
    let mut open = true;
    loop {
        while open {
            match requests.try_recv() {
                Ok(Request::Sdo(node_id, mut job)) => {
                    if let Transfer::Upload(..) = job.transfer {
                        job.retries = read_retries;
                    }
                    let channel = channel(&mut channels, node_id, default_timeout);
                    channel.queue.push_back(job)
                }
                Ok(Request::Timeout(node_id, timeout)) => {
                    let channel = channel(&mut channels, node_id, default_timeout);
                    channel.client.set_timeout(timeout);
                    channel.own_timeout = true;
                }
                Ok(Request::DefaultTimeout(timeout)) => {
                    default_timeout = timeout;
                    for channel in channels.values_mut().filter(|c| !c.own_timeout) {
                        channel.client.set_timeout(timeout);
                    }
                }
                Ok(Request::ReadRetries(retries)) => read_retries = retries,
                Ok(Request::WaitBoot(node_id, timeout, reply)) => {
                    if let Some(i) = booted.iter().position(|&id| id == node_id) {
                        booted.remove(i);
                        reply.send(Ok(Done::default()));
                    } else {
                        boot_waits.push((node_id, clock.now() + timeout, reply));
                    }
                }
                Ok(Request::Frame(frame, reply)) => match transport.send(&frame) {
                    Ok(()) => reply.send(Ok(Done::default())),
                    Err(e) => return reply.send(Err(MasterError::Io(e))),
                },
                Ok(Request::Watch(node_id, watch, reply)) => {
                    let watched = monitor.watch(clock.now(), node_id, watch);
                    reply.send(match watched {
                        Ok(()) => Ok(Done::default()),
                        Err(_) => Err(MasterError::NodeId(node_id)),
                    });
                }
                Ok(Request::Lss(job)) => lss.push(job),
                Err(TryRecvError::Empty) => break,
                Err(TryRecvError::Disconnected) => open = false,
            }
        }
        let now = clock.now();
        let mut deadline: Option<Instant> = None;
        let mut busy = false;
        for channel in channels.values_mut() {
            if run_channel(channel, now, &mut transport).is_err() {
                // The bus is gone: every pending future learns it from its dropped reply.
                return;
            }
            busy |= channel.current.is_some() || !channel.queue.is_empty();
            deadline = match (deadline, channel.client.poll_timeout()) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            };
        }
        if lss.run(now, &mut transport).is_err() {
            return;
        }
        busy |= lss.is_busy();
        if let Some(at) = lss.poll_timeout() {
            deadline = Some(deadline.map_or(at, |d| d.min(at)));
        }
        let (overdue, waiting): (Vec<BootWait>, Vec<BootWait>) =
            boot_waits.drain(..).partition(|(_, at, _)| *at <= now);
        boot_waits = waiting;
        for (_, _, reply) in overdue {
            reply.send(Err(MasterError::Timeout));
        }
        for (_, at, _) in &boot_waits {
            deadline = Some(deadline.map_or(*at, |d| d.min(*at)));
        }
        if monitor.poll_timeout().is_some_and(|at| at <= now) {
            monitor.handle_timeout(now);
        }
        while let Some(frame) = monitor.poll_transmit(now) {
            if transport.send(&frame).is_err() {
                return;
            }
        }
        while let Some(event) = monitor.poll_event() {
            events.send(MasterEvent::Monitor(event));
        }
        if let Some(at) = monitor.poll_timeout() {
            deadline = Some(deadline.map_or(at, |d| d.min(at)));
        }
        if !open && !busy {
            return;
        }
        let wait = match deadline {
            Some(at) => POLL.min(StdDuration::from_micros((at - now).as_micros())),
            None => POLL,
        };
        match transport.recv_timeout(wait) {
            Ok(Some(frame)) => {
                monitor.handle_frame(clock.now(), &frame);
                lss.handle_frame(clock.now(), &frame);
                while let Some(event) = monitor.poll_event() {
                    events.send(MasterEvent::Monitor(event));
                }
                if let Some(emergency) = Emergency::from_frame(&frame) {
                    events.send(MasterEvent::Emergency(emergency));
                }
                let server = frame
                    .std_id()
                    .filter(|id| (0x581..=0x5FF).contains(id))
                    .map(|id| (id - 0x580) as u8);
                if let Some(channel) = server.and_then(|id| channels.get_mut(&id)) {
                    channel.client.handle_frame(clock.now(), &frame);
                }
                if let Some(node_id) = boot_up(&frame) {
                    events.send(MasterEvent::BootUp(node_id));
                    match boot_waits.iter().position(|(id, _, _)| *id == node_id) {
                        Some(i) => boot_waits.remove(i).2.send(Ok(Done::default())),
                        None if !booted.contains(&node_id) => booted.push(node_id),
                        None => {}
                    }
                }
            }
            Ok(None) => {}
            Err(_) => return,
        }
    }
}

/// The node whose boot-up message `frame` is.
pub(super) fn boot_up(frame: &CanFrame) -> Option<u8> {
    let id = frame.std_id().filter(|id| (0x701..=0x77F).contains(id))?;
    let message = ErrorControlRepr::parse(frame.data()).filter(|_| !frame.is_remote())?;
    (message == ErrorControlRepr::BOOT_UP).then_some((id - 0x700) as u8)
}
