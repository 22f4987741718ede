//! A minimal CANopen device on a Cortex-M4F: the edsgen runtime's `Node` (NMT, heartbeat, SDO
//! server, 4 RPDOs + 4 TPDOs, SYNC, EMCY; SDO block transfer and node guarding with the `full`
//! feature) serving a hand-written OD of the CiA 301 communication objects only.
//! `scripts/firmware-size.sh` builds it and prints its flash and RAM use.
#![no_std]
#![no_main]

#[path = "../common.rs"]
mod common;
#[path = "../minimal_od.rs"]
mod minimal_od;

use cortex_m_rt::entry;
use edsgen_runtime::Node;

/// The node's RAM (its state and the OD's values), which lives on `main`'s stack rather than in
/// `.bss`; kept in the image so that `scripts/firmware-size.sh` can report it.
#[used]
#[export_name = "EDSGEN_NODE_RAM_BYTES"]
static NODE_RAM_BYTES: u32 = core::mem::size_of::<Node<minimal_od::MinimalOd>>() as u32;

#[entry]
fn main() -> ! {
    let (now, _) = common::receive();
    let od = minimal_od::MinimalOd::new(common::NODE_ID);
    // Borrowed where it lies rather than moved out of the `Result`: one copy of the node.
    let mut created = Node::new(od, common::NODE_ID, now);
    let Ok(node) = &mut created else {
        panic!("node-ID out of range");
    };
    common::run(node)
}
