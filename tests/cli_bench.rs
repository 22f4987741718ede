//! The bench commands as CANopen people type them (issue 20), through the binary against nodes
//! on an in-process socketcand hub (`bench_support`): entries by index or name, negative
//! values, `--timeout` as the whole wait, `nmt` confirming, `scan`'s legend and duplicate
//! node-IDs, `--block` refused a segmented answer, the `CHK` rules, `simulate` stopped by
//! SIGINT/SIGTERM and refusing a node-ID already on the bus.

mod bench_support;
mod process_support;
#[path = "../sim/tests/sim_support/mod.rs"]
mod sim_support;

use std::process::Command;
use std::time::{Duration, Instant};

use bench_support::{
    bench, eds, edsgen, logged_hub, segmented_bench, stderr, stdout, summary, twin_bench, Scratch,
    EDSGEN,
};
use process_support::{edsgen_simulate, Process};

#[test]
fn entries_are_named_by_index_in_every_usual_spelling_or_by_name() {
    let bench = bench();
    let cp = eds("cp301.eds");
    for entry in [
        "6041",
        "6041:0",
        "0x6041sub0",
        "6041sub0",
        "Statusword",
        "statusw",
    ] {
        let read = edsgen(&bench, &["sdo", "read", "--eds", &cp, "3", entry]);
        assert_eq!(
            (read.status.code(), stdout(&read)),
            (Some(0), "6041h:00h Statusword = 0 (0x0000)\n".to_string()),
            "{entry}: {}",
            stderr(&read)
        );
    }
    let sub = edsgen(
        &bench,
        &[
            "sdo",
            "read",
            "--eds",
            &cp,
            "3",
            "identity object/VENDOR-ID",
        ],
    );
    assert_eq!(
        stdout(&sub),
        "1018h:01h Identity object / Vendor-ID = 0 (0x00000000)\n",
        "{}",
        stderr(&sub)
    );
}

#[test]
fn an_unknown_or_ambiguous_name_is_exit_2_with_suggestions() {
    let bench = bench();
    let cp = eds("cp301.eds");
    let typo = edsgen(&bench, &["sdo", "read", "--eds", &cp, "3", "Statuswort"]);
    assert_eq!(typo.status.code(), Some(2));
    assert_eq!(
        stderr(&typo),
        "error: the description has no entry named `Statuswort`; did you mean:\n  6041:0  Statusword\n"
    );
    let ambiguous = edsgen(&bench, &["sdo", "read", "--eds", &cp, "3", "identity"]);
    assert_eq!(ambiguous.status.code(), Some(2));
    assert_eq!(
        stderr(&ambiguous),
        "error: `identity` names 4 entries; did you mean:\n  1018:0  Identity object / Number of entries\n  1018:1  Identity object / Vendor-ID\n  1018:2  Identity object / Product code\n  1018:3  Identity object / Revision number\n"
    );
    let no_eds = edsgen(&bench, &["sdo", "read", "3", "Statusword"]);
    assert_eq!(no_eds.status.code(), Some(2));
    assert_eq!(
        stderr(&no_eds),
        "error: `Statusword` is not an entry: give INDEX[:SUB] in hex (6041, 6041:0, 0x6041sub0), or a name with --eds FILE\n"
    );
}

#[test]
fn a_negative_value_is_written_without_a_double_dash() {
    let bench = bench();
    let cp = eds("cp301.eds");
    let write = edsgen(
        &bench,
        &["sdo", "write", "--eds", &cp, "3", "6042:0", "-1500"],
    );
    assert_eq!(
        (write.status.code(), stdout(&write)),
        (
            Some(0),
            "6042h:00h vl target velocity written\n".to_string()
        ),
        "{}",
        stderr(&write)
    );
    let read = edsgen(
        &bench,
        &["sdo", "read", "--eds", &cp, "3", "vl target velocity"],
    );
    assert_eq!(
        stdout(&read),
        "6042h:00h vl target velocity = -1500 (0xFA24)\n"
    );
}

#[test]
fn the_timeout_is_the_whole_wait_with_one_retry_inside_it() {
    let (hub, log) = logged_hub();
    let addr = hub.local_addr().to_string();
    let output = Command::new(EDSGEN)
        .args([
            "sdo",
            "read",
            "9",
            "1000",
            "--bus",
            &addr,
            "--timeout",
            "400",
        ])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(1));
    assert!(
        stderr(&output).contains("no answer, aborted with 0504 0000h"),
        "{}",
        stderr(&output)
    );
    // The hub logs on its own thread: wait for the last abort to be written.
    let requests = |text: &str| text.matches("609#4000100000000000").count();
    let aborts = |text: &str| text.matches("609#8000100000000405").count();
    let deadline = Instant::now() + Duration::from_secs(5);
    let text = loop {
        let text = String::from_utf8_lossy(&log.lock().unwrap()).into_owned();
        if aborts(&text) == 2 || Instant::now() > deadline {
            break text;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    assert_eq!((requests(&text), aborts(&text)), (2, 2), "{text}");
    hub.stop();
}

#[test]
fn nmt_reports_the_state_the_node_then_sends_or_no_answer() {
    let bench = bench();
    let heartbeat = edsgen(
        &bench,
        &["sdo", "write", "--type", "u16", "3", "1017", "50"],
    );
    assert_eq!(heartbeat.status.code(), Some(0), "{}", stderr(&heartbeat));
    for (verb, said) in [
        ("stop", "node 3: stopped\n"),
        ("start", "node 3: operational\n"),
        ("preop", "node 3: pre-operational\n"),
        ("reset-comm", "node 3: boot-up (now pre-operational)\n"),
    ] {
        let output = edsgen(&bench, &["nmt", verb, "3"]);
        assert_eq!(
            (output.status.code(), stdout(&output)),
            (Some(0), said.to_string()),
            "{verb}: {}",
            stderr(&output)
        );
    }
    let absent = edsgen(&bench, &["nmt", "start", "9"]);
    assert_eq!(absent.status.code(), Some(1));
    assert_eq!(
        stdout(&absent),
        "start sent; no answer: node 9 sent no heartbeat or boot-up within 500 ms\n"
    );
}

#[test]
fn scan_explains_its_marks_and_reports_two_nodes_sharing_a_node_id() {
    let bench = bench();
    let scan = edsgen(&bench, &["scan"]);
    assert_eq!(scan.status.code(), Some(0), "{}", stderr(&scan));
    let text = stdout(&scan);
    assert!(
        text.contains("\n3     ?                0x00000000"),
        "{text}"
    );
    assert!(
        text.ends_with(
            "2 node(s) found on can0\n\
             ?: the node sent no heartbeat and answered no guarding request (socketcand carries \
             no RTR; set its heartbeat, 1017h, to see its state)\n\
             -: the node does not have the entry, or refused to read it\n"
        ),
        "{text}"
    );
    let twins = twin_bench();
    let scan = edsgen(&twins, &["scan"]);
    assert_eq!(scan.status.code(), Some(1), "{}", stdout(&scan));
    assert!(
        stderr(&scan).contains(
            "error: duplicate node-ID: node 3 answered the scan 2 times: 2 devices share node-ID 3\n"
        ),
        "{}",
        stderr(&scan)
    );
}

/// A socketcand server that greets each client, records what it opens and carries nothing.
fn recording_server() -> (String, std::sync::mpsc::Receiver<String>) {
    use std::io::{Read, Write};
    let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = listener.local_addr().unwrap().to_string();
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for stream in listener.incoming() {
            let Ok(mut stream) = stream else { return };
            let tx = tx.clone();
            std::thread::spawn(move || {
                let _ = stream.write_all(b"< hi >");
                let mut buf = [0u8; 256];
                let mut seen = String::new();
                while let Ok(n @ 1..) = stream.read(&mut buf) {
                    seen.push_str(&String::from_utf8_lossy(&buf[..n]));
                    while let Some(end) = seen.find('>') {
                        let message: String = seen.drain(..=end).collect();
                        let message = message.trim().to_string();
                        if message.starts_with("< open") || message.starts_with("< rawmode") {
                            let _ = stream.write_all(b"< ok >");
                        }
                        if message.starts_with("< open") {
                            let _ = tx.send(message);
                        }
                    }
                }
            });
        }
    });
    (addr, rx)
}

#[test]
fn scan_opens_the_channel_it_is_given() {
    let (addr, opened) = recording_server();
    let output = Command::new(EDSGEN)
        .args([
            "scan",
            "--bus",
            &addr,
            "--channel",
            "can1",
            "--timeout",
            "100",
        ])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert!(
        stdout(&output).ends_with("0 node(s) found on can1\n"),
        "{}",
        stdout(&output)
    );
    // Both of scan's connections (the master's and the listener's) open can1.
    let channels: Vec<String> = opened.try_iter().collect();
    assert_eq!(channels, ["< open can1 >", "< open can1 >"]);
}

#[test]
fn block_read_answered_segmented_fails_under_block_and_says_so_otherwise() {
    let bench = segmented_bench();
    let scratch = Scratch::new("segmented-answer");
    let sim = scratch.path("sim.eds");
    let data: Vec<u8> = (0..100u8).collect();
    std::fs::write(scratch.path("in.bin"), &data).unwrap();
    let write = edsgen(
        &bench,
        &[
            "sdo",
            "write",
            "--eds",
            &sim,
            "--file",
            &scratch.path("in.bin"),
            "7",
            "2001:0",
        ],
    );
    assert_eq!(write.status.code(), Some(0), "{}", stderr(&write));
    let out = scratch.path("out.bin");
    let read = edsgen(
        &bench,
        &["sdo", "read", "--eds", &sim, "--out", &out, "7", "2001:0"],
    );
    assert_eq!(read.status.code(), Some(0), "{}", stderr(&read));
    assert_eq!(
        summary(&read),
        "2001h:00h Program: 100 bytes read by segmented transfer"
    );
    assert_eq!(std::fs::read(&out).unwrap(), data);
    std::fs::remove_file(&out).unwrap();
    let block = edsgen(
        &bench,
        &[
            "sdo", "read", "--eds", &sim, "--out", &out, "--block", "7", "2001:0",
        ],
    );
    assert_eq!(block.status.code(), Some(1));
    let text = stderr(&block);
    let lines: Vec<&str> = text.lines().collect();
    assert!(
        lines[0].starts_with("2001h:00h Program: 100 bytes read by segmented transfer in "),
        "{text}"
    );
    assert_eq!(
        lines[1..],
        ["error: 2001h:00h Program: the node answered the block upload with segmented transfer; --block takes only a block transfer (leave it out to accept the node's choice)"]
    );
    assert!(!std::path::Path::new(&out).exists());
}

#[test]
fn the_check_codes_are_in_rules_and_explain_but_not_validate_s_policy() {
    let run = |args: &[&str]| Command::new(EDSGEN).args(args).output().unwrap();
    let rules = run(&["rules"]);
    assert!(stdout(&rules).starts_with(
        "CHK001  error    (`edsgen check`) an object or sub-index of the description is missing on the device\n"
    ));
    for code in ["CHK001", "CHK002", "CHK003", "CHK004", "CHK005"] {
        let explained = run(&["explain", code]);
        assert_eq!(explained.status.code(), Some(0), "{code}");
        assert!(
            stdout(&explained)
                .contains("\nArea: a live device against its description (`edsgen check`).\n"),
            "{}",
            stdout(&explained)
        );
    }
    let policy = run(&["validate", "--allow", "CHK005", &eds("cp301.eds")]);
    assert_eq!(policy.status.code(), Some(2));
    assert_eq!(
        stderr(&policy),
        "error: --allow CHK005: `edsgen check` reports CHK005, not `edsgen validate`\n"
    );
}

/// `edsgen simulate` on a hub, stopped by `signal`: it stops its nodes and exits 0. The MS300
/// joins at its default node-ID, 1, beside the bench's nodes 3 and 5.
fn simulate_stops_on(signal: &str) {
    let bench = bench();
    let (simulate, announced) = edsgen_simulate(&["--card", "ms300", "--bus", &bench.addr], 1);
    assert_eq!(
        announced,
        [format!("simulating node 1 (card ms300) on {}", bench.addr)]
    );
    let kill = Command::new("kill")
        .args([signal, &simulate.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let exited = simulate.finish(Duration::from_secs(10));
    assert_eq!(exited.code, Some(0), "{signal}: {}", exited.stderr);
    assert_eq!(exited.stderr, "edsgen simulate: stopped 1 node(s)\n");
}

#[test]
fn simulate_stops_cleanly_on_sigterm() {
    simulate_stops_on("-TERM");
}

#[test]
fn simulate_stops_cleanly_on_sigint() {
    simulate_stops_on("-INT");
}

#[test]
fn simulate_refuses_a_node_id_that_already_answers() {
    let bench = bench();
    let simulate = Process::edsgen(&["simulate", "--card", "cp301@3", "--bus", &bench.addr]);
    let exited = simulate.finish(Duration::from_secs(10));
    assert_eq!(exited.code, Some(2));
    assert_eq!(
        exited.stderr,
        format!(
            "error: duplicate node-ID: node 3 already answers on the bus at {}; give the simulated device another one (FILE@ID, --card NAME@ID)\n",
            bench.addr
        )
    );
}
