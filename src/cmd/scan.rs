//! `edsgen scan`: the nodes on the bus (an SDO upload of 1000h to every node-ID at once), each
//! with its NMT state (last heartbeat, else a guarding RTR) and identity (1000h, 1018h:1–4).

use std::process::ExitCode;
use std::time::Duration;

use edsgen_runtime::master::blocking::MasterError;
use edsgen_runtime::master::identity::IDENTITY_ENTRIES;
use edsgen_runtime::wire::heartbeat::NmtState;

use super::{fail, BusArgs};

/// Runs `edsgen scan`.
pub fn run(bus: &BusArgs) -> ExitCode {
    let mut master = match bus.connect() {
        Ok(master) => master,
        Err(message) => return fail(message),
    };
    let wait = Duration::from_millis(bus.timeout);
    let found = match master.scan(wait) {
        Ok(found) => found,
        Err(e) => return fail(e),
    };
    println!("node  state            device type  vendor-ID   product     revision    serial");
    for node_id in &found {
        let state = match master.query_state(*node_id, Duration::from_millis(100)) {
            Ok(state) => state.map_or("?", state_name),
            Err(e) => return fail(e),
        };
        let mut identity = Vec::new();
        for entry in IDENTITY_ENTRIES {
            identity.push(match master.read(*node_id, entry) {
                Ok(value) => format!("0x{value:08X}"),
                Err(MasterError::Io(e)) => return fail(format!("bus: {e}")),
                Err(_) => "-".to_string(),
            });
        }
        println!(
            "{node_id:<5} {state:<16} {}",
            identity
                .iter()
                .map(|v| format!("{v:<11}"))
                .collect::<Vec<_>>()
                .join(" ")
                .trim_end()
        );
    }
    println!("{} node(s) found", found.len());
    ExitCode::SUCCESS
}

/// The state as CiA 301 names it.
pub fn state_name(state: NmtState) -> &'static str {
    match state {
        NmtState::Initialising => "initialising",
        NmtState::Stopped => "stopped",
        NmtState::Operational => "operational",
        NmtState::PreOperational => "pre-operational",
    }
}
