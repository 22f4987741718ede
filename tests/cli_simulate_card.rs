//! `edsgen simulate --card`: the bundled cards with their drives' behaviour on a hub, reached by
//! edsgen's own blocking master through the socketcand protocol, as an integrator would at the
//! bench: typed SDO to a CP301 and the Goodrive350's PDO1 parameter protocol.

mod process_support;

use std::process::Command;
use std::time::{Duration, Instant};

use edsgen_host::hub::{Hub, HubOptions};
use edsgen_host::master::blocking::Master;
use edsgen_host::socketcand::SocketcandClient;
use edsgen_host::Transport;
use edsgen_runtime::wire::nmt::NmtCommand;
use edsgen_runtime::CanFrame;
use edsgen_sim::cards::cp301::od;
use process_support::{edsgen_simulate, Process, EDSGEN};

/// Starts `edsgen simulate` and waits until it has announced `nodes` nodes.
fn simulate(args: &[&str], nodes: usize) -> Process {
    let (running, announced) = edsgen_simulate(args, nodes);
    assert_eq!(
        announced,
        [
            "simulating node 3 (card goodrive350) on ".to_string(),
            "simulating node 2 (card cp301) on ".to_string(),
        ]
        .map(|prefix| format!("{prefix}{}", args[args.len() - 1]))
    );
    running
}

#[test]
fn bundled_cards_behave_on_a_hub_for_edsgen_s_master() {
    let hub = Hub::start("127.0.0.1:0", HubOptions::default()).expect("a hub on loopback");
    let addr = hub.local_addr().to_string();
    let _simulating = simulate(
        &["--card", "goodrive350", "--card", "cp301@2", "--bus", &addr],
        2,
    );
    let client = SocketcandClient::connect(&addr, "can0", Duration::from_secs(3)).expect("joins");
    let mut master = Master::new(client);
    master.set_default_timeout(Duration::from_secs(2));

    // CP301 (node 2): CiA 402 by typed SDO through the generated addresses.
    master.write(2, od::CONTROLWORD, 0x06).expect("6040h = 06h");
    assert_eq!(master.read(2, od::STATUSWORD).expect("6041h"), 0x0631);

    // Goodrive350 (node 3): operational, then PDO1 writes P00.01 = 2 and answers on PDO1 Tx.
    master.nmt(NmtCommand::Start, 3).expect("NMT start");
    let transport = master.transport_mut();
    let request = CanFrame::new(0x203, &[0x02, 0x00, 0x01, 0x00, 0x02, 0x00]).expect("PDO1 Rx");
    transport.send(&request).expect("sent");
    let deadline = Instant::now() + Duration::from_secs(5);
    let answer = loop {
        let left = deadline.saturating_duration_since(Instant::now());
        assert!(!left.is_zero(), "no PDO1 Tx answer");
        if let Some(frame) = transport.recv_timeout(left).expect("the bus stays") {
            if frame.std_id() == Some(0x183) && frame.data()[0] != 0 {
                break frame;
            }
        }
    };
    assert_eq!(
        answer.data(),
        [0x01, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00]
    );
}

#[test]
fn an_unknown_card_is_a_usage_error() {
    let out = Command::new(EDSGEN)
        .args(["simulate", "--card", "cp302"])
        .output()
        .expect("edsgen runs");
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "error: no card `cp302`: the bundled cards are cp301, ms300, goodrive350, rd11, hd1e\n"
    );
}
