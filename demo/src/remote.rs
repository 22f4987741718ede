//! The demo against devices elsewhere (`edsgen demo --bus HOST:PORT`): edsgen's blocking master on
//! a socketcand bus, in real time, with every frame it sends and receives tapped for the trace.
//! The drives may be `edsgen simulate --card cp301@2 --card goodrive350` or real ones; a fault
//! cannot be injected into them from here.

use std::sync::{Arc, Mutex};
use std::time::{Duration as StdDuration, SystemTime, UNIX_EPOCH};

use edsgen_host::master::blocking::Master;
use edsgen_host::socketcand::SocketcandClient;
use edsgen_host::Transport;
use edsgen_runtime::od::access::{Readable, Writable};
use edsgen_runtime::{CanFrame, Entry, OdValue};

use super::{Link, Trace};

/// Every frame a transport sends or receives, with the wall-clock time since the Unix epoch and
/// whether it was received.
type Tapped = Arc<Mutex<Vec<(StdDuration, bool, CanFrame)>>>;

/// A transport that records what passes through it.
struct Tap<T> {
    inner: T,
    log: Tapped,
}

fn since_epoch() -> StdDuration {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .unwrap_or_default()
}

impl<T: Transport> Transport for Tap<T> {
    fn send(&mut self, frame: &CanFrame) -> std::io::Result<()> {
        self.inner.send(frame)?;
        if let Ok(mut log) = self.log.lock() {
            log.push((since_epoch(), false, *frame));
        }
        Ok(())
    }

    fn recv_timeout(&mut self, timeout: StdDuration) -> std::io::Result<Option<CanFrame>> {
        let frame = self.inner.recv_timeout(timeout)?;
        if let (Some(frame), Ok(mut log)) = (frame, self.log.lock()) {
            log.push((since_epoch(), true, frame));
        }
        Ok(frame)
    }
}

/// How long each SDO answer may take on a real bus.
const SDO_TIMEOUT: StdDuration = StdDuration::from_secs(1);

/// The master on a socketcand bus.
pub struct Remote {
    master: Master<Tap<SocketcandClient>>,
    tapped: Tapped,
    /// Frames received since the last look.
    seen: Vec<CanFrame>,
    trace: Trace,
}

impl Remote {
    /// Joins the socketcand server at `addr`.
    pub fn connect(addr: &str, trace: Trace) -> Result<Self, String> {
        let client = SocketcandClient::connect(addr, "can0", StdDuration::from_secs(3))
            .map_err(|e| format!("cannot reach the bus at {addr}: {e}"))?;
        let tapped = Tapped::default();
        let mut master = Master::new(Tap {
            inner: client,
            log: Arc::clone(&tapped),
        });
        master.set_default_timeout(SDO_TIMEOUT);
        Ok(Remote {
            master,
            tapped,
            seen: Vec::new(),
            trace,
        })
    }

    /// Decodes what the tap recorded into the trace.
    fn drain(&mut self) {
        let tapped = match self.tapped.lock() {
            Ok(mut log) => std::mem::take(&mut *log),
            Err(_) => return,
        };
        for (at, received, frame) in tapped {
            if received {
                self.seen.push(frame);
            }
            self.trace.frame(at, &frame);
        }
    }
}

impl Link for Remote {
    fn trace(&mut self) -> &mut Trace {
        self.drain();
        &mut self.trace
    }

    fn into_trace(mut self) -> Trace {
        self.drain();
        self.trace
    }

    fn read<T: OdValue, D, A: Readable>(
        &mut self,
        node: u8,
        entry: Entry<T, D, A>,
    ) -> Result<T, String> {
        let value = self.master.read(node, entry).map_err(|e| e.to_string());
        self.drain();
        value
    }

    fn write<T: OdValue, D, A: Writable>(
        &mut self,
        node: u8,
        entry: Entry<T, D, A>,
        value: T,
    ) -> Result<(), String> {
        let written = self
            .master
            .write(node, entry, value)
            .map_err(|e| e.to_string());
        self.drain();
        written
    }

    fn send(&mut self, frame: CanFrame) -> Result<(), String> {
        let sent = self
            .master
            .transport_mut()
            .send(&frame)
            .map_err(|e| e.to_string());
        self.drain();
        sent
    }

    fn wait(&mut self, span: StdDuration) -> Result<(), String> {
        let waited = self.master.listen(span).map_err(|e| e.to_string());
        self.drain();
        waited
    }

    fn take_seen(&mut self, id: u16) -> Vec<CanFrame> {
        self.drain();
        let seen = std::mem::take(&mut self.seen);
        seen.into_iter()
            .filter(|f| f.std_id() == Some(id))
            .collect()
    }

    fn inject_goodrive350_fault(&mut self, _fault: u8) -> bool {
        false
    }

    fn remove_goodrive350_fault_cause(&mut self) -> bool {
        false
    }

    fn slack(&self) -> i16 {
        150
    }
}
