//! The demo on the in-memory bus: a master of one SDO client per node, the simulated CP301 and
//! Goodrive350, and the bus's own clock, so that the manuals' ramps of several seconds run in no
//! time and every run gives the same frames at the same instants.

use std::collections::VecDeque;
use std::time::Duration as StdDuration;

use edsgen_host::vbus::{BusDevice, VirtualBus};
use edsgen_runtime::master::SdoClient;
use edsgen_runtime::od::access::{Readable, Writable};
use edsgen_runtime::{CanFrame, Duration, Entry, Instant, OdValue};

use super::{Link, Trace, CP301_NODE, GOODRIVE350_NODE};
use edsgen_sim::drives::{Cp301, Goodrive350};

/// The master's side of the bus: one SDO client per node, and frames to send (NMT, PDOs).
#[derive(Default)]
struct DemoMaster {
    clients: Vec<SdoClient>,
    outbox: VecDeque<CanFrame>,
}

impl DemoMaster {
    fn client(&mut self, node: u8) -> &mut SdoClient {
        match self.clients.iter().position(|c| c.node_id() == node) {
            Some(i) => &mut self.clients[i],
            None => {
                self.clients.push(SdoClient::new(node));
                let last = self.clients.len() - 1;
                &mut self.clients[last]
            }
        }
    }
}

impl BusDevice for DemoMaster {
    fn handle_frame(&mut self, now: Instant, frame: &CanFrame) {
        for client in &mut self.clients {
            client.handle_frame(now, frame);
        }
    }
    fn poll_transmit(&mut self, now: Instant) -> Option<CanFrame> {
        if let Some(frame) = self.outbox.pop_front() {
            return Some(frame);
        }
        self.clients.iter_mut().find_map(|c| c.poll_transmit(now))
    }
    fn poll_timeout(&self) -> Option<Instant> {
        self.clients.iter().filter_map(|c| c.poll_timeout()).min()
    }
    fn handle_timeout(&mut self, now: Instant) {
        for client in &mut self.clients {
            client.handle_timeout(now);
        }
    }
}

/// How long an SDO answer may take on the in-memory bus (it takes none: the bus is instant).
const SDO_WAIT: Duration = Duration::from_millis(100);

/// The in-memory bus with the master and the two drives.
pub struct InMemory {
    bus: VirtualBus,
    master: DemoMaster,
    cp301: Cp301,
    goodrive350: Goodrive350,
    /// Frames the drives sent since the last look.
    seen: Vec<CanFrame>,
    trace: Trace,
}

impl InMemory {
    /// The drives powered up at time 0.
    pub fn new(trace: Trace) -> Result<Self, String> {
        let now = Instant::from_millis(0);
        let mut link = InMemory {
            bus: VirtualBus::new(now),
            master: DemoMaster::default(),
            cp301: Cp301::new(CP301_NODE, now).map_err(|e| format!("{e:?}"))?,
            goodrive350: Goodrive350::new(GOODRIVE350_NODE, now).map_err(|e| format!("{e:?}"))?,
            seen: Vec::new(),
            trace,
        };
        link.run_until(now);
        Ok(link)
    }

    /// Runs the bus to `until`, decoding every frame into the trace.
    fn run_until(&mut self, until: Instant) {
        self.bus.run_until(
            until,
            &mut [&mut self.master, &mut self.cp301, &mut self.goodrive350],
        );
        for (at, sender, frame) in self.bus.take_log() {
            if sender != 0 {
                self.seen.push(frame);
            }
            self.trace
                .frame(StdDuration::from_micros(at.as_micros()), &frame);
        }
    }

    /// Runs the bus until node's SDO client has a result, at most [`SDO_WAIT`].
    fn sdo_result(&mut self, node: u8) -> Result<(), String> {
        let deadline = self.bus.now() + SDO_WAIT;
        loop {
            self.run_until(self.bus.now());
            if let Some(result) = self.master.client(node).poll_result() {
                return result
                    .map(|_| ())
                    .map_err(|e| format!("SDO abort {:08X}h", e.code()));
            }
            if self.bus.now() >= deadline {
                return Err("no SDO answer".into());
            }
            self.run_until(self.bus.now() + Duration::from_millis(1));
        }
    }
}

impl Link for InMemory {
    fn trace(&mut self) -> &mut Trace {
        &mut self.trace
    }

    fn into_trace(self) -> Trace {
        self.trace
    }

    fn read<T: OdValue, D, A: Readable>(
        &mut self,
        node: u8,
        entry: Entry<T, D, A>,
    ) -> Result<T, String> {
        let now = self.bus.now();
        self.master
            .client(node)
            .read(now, entry)
            .map_err(|e| format!("{e:?}"))?;
        self.sdo_result(node)?;
        self.master
            .client(node)
            .take_value(&entry)
            .ok_or_else(|| "a value of the wrong length".to_string())
    }

    fn write<T: OdValue, D, A: Writable>(
        &mut self,
        node: u8,
        entry: Entry<T, D, A>,
        value: T,
    ) -> Result<(), String> {
        let now = self.bus.now();
        self.master
            .client(node)
            .write(now, entry, &value)
            .map_err(|e| format!("{e:?}"))?;
        self.sdo_result(node)
    }

    fn send(&mut self, frame: CanFrame) -> Result<(), String> {
        self.master.outbox.push_back(frame);
        self.run_until(self.bus.now());
        Ok(())
    }

    fn wait(&mut self, span: StdDuration) -> Result<(), String> {
        let span = Duration::from_micros(span.as_micros() as u64);
        self.run_until(self.bus.now() + span);
        Ok(())
    }

    fn take_seen(&mut self, id: u16) -> Vec<CanFrame> {
        let seen = std::mem::take(&mut self.seen);
        seen.into_iter()
            .filter(|f| f.std_id() == Some(id))
            .collect()
    }

    fn inject_goodrive350_fault(&mut self, fault: u8) -> bool {
        self.goodrive350.inject_fault(self.bus.now(), fault);
        self.run_until(self.bus.now());
        true
    }

    fn remove_goodrive350_fault_cause(&mut self) -> bool {
        self.goodrive350.remove_fault_cause();
        true
    }

    fn slack(&self) -> i16 {
        0
    }
}
