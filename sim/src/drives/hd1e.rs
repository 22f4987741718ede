//! The HD1-E CANopen card in an HD1 (or INVT GD/CHV) inverter, as the manual fragment describes
//! it: PDO1 reads and writes the inverter's parameters with the response and error codes of
//! Tables 20 and 21 ([`super::pdo1`]). The fragment documents no drive control, so the
//! inverter stands still; its parameter table is Table 19's (P10.00, P10.01).

use edsgen_host::vbus::BusDevice;
use edsgen_runtime::node::InvalidNodeId;
use edsgen_runtime::{CanFrame, Event, Instant, Node};

use super::pdo1;
use super::vfd::{Modify, ParameterSpec, Parameters};
use crate::cards::hd1e::Od;

/// Table 19: P10.00 simple PLC (0–2), P10.01 simple PLC memory (0–1), both modifiable at any
/// time (○), default 0.
static PARAMETERS: [ParameterSpec; 2] = [
    ParameterSpec {
        address: 0x0A00,
        default: 0,
        min: 0,
        max: 2,
        modify: Modify::Always,
    },
    ParameterSpec {
        address: 0x0A01,
        default: 0,
        min: 0,
        max: 1,
        modify: Modify::Always,
    },
];

/// The simulated HD1-E card and its inverter's parameters. Runs on any bus as a [`BusDevice`].
pub struct Hd1e {
    node: Node<Od>,
    parameters: Parameters,
}

impl Hd1e {
    /// A card that has just powered up at `node_id`.
    pub fn new(node_id: u8, now: Instant) -> Result<Self, InvalidNodeId> {
        Ok(Hd1e {
            node: Node::new(Od::new(node_id), node_id, now)?,
            parameters: Parameters::new(&PARAMETERS),
        })
    }

    /// The card's device node.
    pub fn node(&self) -> &Node<Od> {
        &self.node
    }

    /// A parameter's value.
    pub fn parameter(&self, address: u16) -> Option<u16> {
        self.parameters.get(address)
    }
}

impl BusDevice for Hd1e {
    fn handle_frame(&mut self, now: Instant, frame: &CanFrame) {
        self.node.handle_frame(now, frame);
        while let Some(event) = self.node.poll_event() {
            if event == (Event::RpdoReceived { pdo: 0 }) {
                let drive = pdo1::DriveState {
                    running: false,
                    faulted: false,
                };
                if pdo1::serve(self.node.od_mut(), &mut self.parameters, drive) {
                    self.node.trigger_tpdo(0);
                }
            }
        }
    }

    fn poll_transmit(&mut self, now: Instant) -> Option<CanFrame> {
        self.node.poll_transmit(now)
    }

    fn poll_timeout(&self) -> Option<Instant> {
        self.node.poll_timeout()
    }

    fn handle_timeout(&mut self, now: Instant) {
        self.node.handle_timeout(now);
    }
}
