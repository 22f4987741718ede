//! `edsgen nmt start|stop|preop|reset|reset-comm NODE|all`: one NMT command, confirmed by what
//! the node says next: its state from its next heartbeat (a boot-up message after a reset),
//! else from a guarding RTR; "no answer" (exit 1) when it says nothing within `--timeout` (give
//! more than the heartbeat period), and exit 1 when it reports another state than the command
//! asks for.

use std::collections::BTreeMap;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use clap::ValueEnum;
use edsgen_runtime::wire::heartbeat::{ErrorControlRepr, NmtState};
use edsgen_runtime::wire::nmt::NmtCommand;

use super::scan::state_name;
use crate::cmd::{fail, parse_node_id, BusArgs};

/// The NMT commands by their bench names.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum NmtVerb {
    /// Start remote node (to operational).
    Start,
    /// Stop remote node.
    Stop,
    /// Enter pre-operational.
    Preop,
    /// Reset node (application and communication).
    Reset,
    /// Reset communication.
    ResetComm,
}

impl NmtVerb {
    fn command(self) -> NmtCommand {
        match self {
            NmtVerb::Start => NmtCommand::Start,
            NmtVerb::Stop => NmtCommand::Stop,
            NmtVerb::Preop => NmtCommand::EnterPreOperational,
            NmtVerb::Reset => NmtCommand::ResetNode,
            NmtVerb::ResetComm => NmtCommand::ResetCommunication,
        }
    }
}

/// Runs `edsgen nmt VERB NODE`.
pub fn run(bus: &BusArgs, verb: NmtVerb, node: &str) -> ExitCode {
    let node_id = if node == "all" {
        0
    } else {
        match parse_node_id(node) {
            Ok(id) => id,
            Err(message) => return fail(format!("{message} (or `all`)")),
        }
    };
    let mut master = match bus.connect() {
        Ok(master) => master,
        Err(message) => return fail(message),
    };
    if let Err(e) = master.nmt(verb.command(), node_id) {
        return fail(e);
    }
    // What the nodes say next, straight from the bus: each node's first heartbeat or boot-up.
    let wait = Duration::from_millis(bus.timeout);
    let end = Instant::now() + wait;
    let mut seen: BTreeMap<u8, Said> = BTreeMap::new();
    while let Some(left) = end.checked_duration_since(Instant::now()) {
        let frame = match master.transport_mut().recv_timeout(left) {
            Ok(Some(frame)) => frame,
            Ok(None) => break,
            Err(e) => return fail(format!("bus: {e}")),
        };
        let from = frame
            .std_id()
            .filter(|id| (0x701..=0x77F).contains(id))
            .map(|id| (id - 0x700) as u8)
            .filter(|&id| node_id == 0 || id == node_id);
        let said = (!frame.is_remote())
            .then(|| ErrorControlRepr::parse(frame.data()))
            .flatten();
        if let (Some(from), Some(said)) = (from, said) {
            let said = if said == ErrorControlRepr::BOOT_UP {
                Said::BootUp
            } else {
                Said::State(said.state)
            };
            // A heartbeat already on its way when the command went may still say the old
            // state: a single node's answer counts once it is the state asked for, else the
            // last one within the wait does.
            seen.insert(from, said);
            if node_id != 0 && verb.expects(said) {
                break;
            }
        }
    }
    // A node without heartbeats may still answer a guarding RTR.
    if node_id != 0 && seen.is_empty() {
        match master.query_state(node_id, Duration::from_millis(100)) {
            Ok(Some(state)) => {
                seen.insert(node_id, Said::State(state));
            }
            Ok(None) => {}
            Err(e) => return fail(e),
        }
    }
    if seen.is_empty() {
        let who = if node_id == 0 {
            "no node sent a".to_owned()
        } else {
            format!("node {node_id} sent no")
        };
        println!(
            "{} sent; no answer: {who} heartbeat or boot-up within {} ms",
            verb.shown(),
            bus.timeout
        );
        return ExitCode::from(1);
    }
    let mut all_as_asked = true;
    for (id, said) in &seen {
        let as_asked = verb.expects(*said);
        all_as_asked &= as_asked;
        let note = if as_asked {
            ""
        } else {
            " (not what was asked)"
        };
        println!("node {id}: {}{note}", said.shown());
    }
    if all_as_asked {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

/// What a node said after the command.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Said {
    /// Its boot-up message.
    BootUp,
    /// Its state, by heartbeat or guarding answer.
    State(NmtState),
}

impl Said {
    fn shown(self) -> String {
        match self {
            Said::BootUp => "boot-up (now pre-operational)".to_owned(),
            Said::State(state) => state_name(state).to_owned(),
        }
    }
}

impl NmtVerb {
    /// The command as the report names it.
    fn shown(self) -> &'static str {
        match self {
            NmtVerb::Start => "start",
            NmtVerb::Stop => "stop",
            NmtVerb::Preop => "preop",
            NmtVerb::Reset => "reset",
            NmtVerb::ResetComm => "reset-comm",
        }
    }

    /// Whether `said` is what a node obeying the command says next.
    fn expects(self, said: Said) -> bool {
        match self {
            NmtVerb::Start => said == Said::State(NmtState::Operational),
            NmtVerb::Stop => said == Said::State(NmtState::Stopped),
            NmtVerb::Preop => said == Said::State(NmtState::PreOperational),
            NmtVerb::Reset | NmtVerb::ResetComm => said == Said::BootUp,
        }
    }
}
