//! `edsgen nmt start|stop|preop|reset|reset-comm NODE|all`: one NMT command (no answer to wait
//! for; `scan` shows the states after).

use std::process::ExitCode;

use clap::ValueEnum;
use edsgen_runtime::wire::nmt::NmtCommand;

use super::{fail, parse_node_id, BusArgs};

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
    match master.nmt(verb.command(), node_id) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => fail(e),
    }
}
