//! `edsgen scan`: the nodes on the bus (an SDO upload of 1000h to every node-ID at once), each
//! with its NMT state (last heartbeat, else a guarding RTR) and identity (1000h, 1018h:1–4),
//! and a legend for what could not be known. A second connection hears every answer: two
//! answers from one node-ID are two devices sharing it, reported (exit 1).

use std::collections::BTreeMap;
use std::process::ExitCode;
use std::time::Duration;

use edsgen_host::Transport;

use edsgen_host::master::blocking::MasterError;
use edsgen_runtime::master::identity::IDENTITY_ENTRIES;
use edsgen_runtime::wire::heartbeat::NmtState;

use crate::cmd::{fail, BusArgs};

/// Runs `edsgen scan`.
pub fn run(bus: &BusArgs) -> ExitCode {
    let mut listener = match bus.open() {
        Ok(listener) => listener,
        Err(message) => return fail(message),
    };
    let mut master = match bus.connect() {
        Ok(master) => master,
        Err(message) => return fail(message),
    };
    let wait = Duration::from_millis(bus.timeout);
    let found = match master.scan(wait) {
        Ok(found) => found,
        Err(e) => return fail(e),
    };
    let answers = match answers_to_the_scan(listener.as_mut()) {
        Ok(answers) => answers,
        Err(e) => return fail(format!("bus: {e}")),
    };
    let (mut unknown_state, mut unreadable) = (false, false);
    println!("node  state            device type  vendor-ID   product     revision    serial");
    for node_id in &found {
        let state = match master.query_state(*node_id, Duration::from_millis(100)) {
            Ok(Some(state)) => state_name(state),
            Ok(None) => {
                unknown_state = true;
                "?"
            }
            Err(e) => return fail(e),
        };
        let mut identity = Vec::new();
        for entry in IDENTITY_ENTRIES {
            identity.push(match master.read(*node_id, entry) {
                Ok(value) => format!("0x{value:08X}"),
                Err(MasterError::Io(e)) => return fail(format!("bus: {e}")),
                Err(_) => {
                    unreadable = true;
                    "-".to_string()
                }
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
    println!("{} node(s) found on {}", found.len(), bus.channel);
    if unknown_state {
        println!(
            "?: the node sent no heartbeat and answered no guarding request (socketcand carries \
             no RTR; set its heartbeat, 1017h, to see its state)"
        );
    }
    if unreadable {
        println!("-: the node does not have the entry, or refused to read it");
    }
    if let Some(note) = super::lss::unconfigured_note(&mut master) {
        println!("{note}");
    }
    let shared: Vec<_> = answers.iter().filter(|(_, &n)| n > 1).collect();
    for (node_id, count) in &shared {
        eprintln!(
            "error: duplicate node-ID: node {node_id} answered the scan {count} times: \
             {count} devices share node-ID {node_id}"
        );
    }
    if shared.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

/// How many answers each node-ID gave the scan's read of 1000h (a response or an abort on
/// 580h + node-ID), as a listener on the bus heard them; the ones still on their way within a
/// short while included.
fn answers_to_the_scan(listener: &mut dyn Transport) -> std::io::Result<BTreeMap<u8, usize>> {
    let mut answers = BTreeMap::new();
    // A busy bus never falls silent: the frames heard during the scan, and half a second more.
    let end = std::time::Instant::now() + Duration::from_millis(500);
    while std::time::Instant::now() < end {
        let Some(frame) = listener.recv_timeout(Duration::from_millis(50))? else {
            break;
        };
        let Some(node_id) = frame
            .std_id()
            .filter(|id| (0x581..=0x5FF).contains(id))
            .map(|id| (id - 0x580) as u8)
        else {
            continue;
        };
        let data = frame.data();
        let about_1000 = data.len() == 8 && data[1..4] == [0x00, 0x10, 0x00];
        let initiate_or_abort = data.first().is_some_and(|b| b >> 5 == 2 || *b == 0x80);
        if about_1000 && initiate_or_abort {
            *answers.entry(node_id).or_insert(0) += 1;
        }
    }
    Ok(answers)
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
