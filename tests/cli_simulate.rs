//! `edsgen simulate` and `edsgen decode` on the command line: exit codes and messages for bad
//! usage (unreadable files, bad node-IDs, an unreachable or vanishing hub, malformed log lines,
//! an overlay with errors), several devices in one process on one hub, `--trace`, and the
//! overlay beside a file. Every wait is bounded; children are killed when their guard drops.

mod process_support;
#[path = "../sim/tests/sim_support/mod.rs"]
mod sim_support;

use std::path::PathBuf;
use std::process::{Command, Output};
use std::time::{Duration, Instant};

use edsgen_host::hub::{Hub, HubOptions};
use edsgen_host::master::blocking::{Master, MasterError};
use edsgen_host::socketcand::SocketcandClient;
use edsgen_host::Transport;
use edsgen_runtime::master::{Mode, SdoError};
use edsgen_runtime::wire::sdo::Multiplexer;
use edsgen_runtime::CanFrame;

use process_support::{Process, EDSGEN};

/// How long a line or an exit may take.
const WAIT: Duration = Duration::from_secs(10);

fn edsgen(args: &[&str]) -> Output {
    Command::new(EDSGEN)
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap()
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn hub() -> Hub {
    Hub::start("127.0.0.1:0", HubOptions::default()).unwrap()
}

/// A client of `hub` receiving until `wanted` frames matched, at most 10 s.
fn receive(
    client: &mut SocketcandClient,
    count: usize,
    wanted: impl Fn(&CanFrame) -> bool,
) -> Vec<CanFrame> {
    let deadline = Instant::now() + Duration::from_secs(10);
    let mut got = Vec::new();
    while got.len() < count {
        assert!(Instant::now() < deadline, "only {got:?}");
        if let Some(frame) = client.recv_timeout(Duration::from_millis(50)).unwrap() {
            if wanted(&frame) {
                got.push(frame);
            }
        }
    }
    got
}

#[test]
fn simulate_refuses_an_unreadable_file() {
    let out = edsgen(&["simulate", "nope.eds@3"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(stderr(&out), "error: cannot read `nope.eds`: not a file\n");
}

#[test]
fn simulate_refuses_bad_and_missing_node_ids() {
    let out = edsgen(&["simulate", "eds/cp301.eds@200"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        stderr(&out),
        "error: eds/cp301.eds@200: node-ID 200 is not in 1..=127 (or 255: unconfigured, for LSS)\n"
    );
    let out = edsgen(&["simulate", "eds/cp301.eds", "--node-id", "0"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("invalid value '0' for '--node-id <N>': node-ID 0 is not in 1..=127"),
        "{}",
        stderr(&out)
    );
    let out = edsgen(&["simulate", "eds/cp301.eds"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        stderr(&out),
        "error: no node-ID for `eds/cp301.eds`: give --node-id N or write eds/cp301.eds@N\n"
    );
    let out = edsgen(&["simulate", "eds/cp301.eds@3", "eds/ms300.eds@0x03"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        stderr(&out),
        "error: node-ID 3 is given to both `eds/cp301.eds` and `eds/ms300.eds`\n"
    );
}

#[test]
fn simulate_takes_a_dcf_node_id_only_in_range_and_one_node_id_per_file() {
    let dcf = sim_support::DEVICE_EDS.to_owned() + "\n[DeviceComissioning]\nNodeID=0xFF\n";
    let path = log_file("unconfigured.dcf", &dcf);
    let out = edsgen(&["simulate", path.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        stderr(&out),
        format!(
            "error: {}: the DCF's NodeID 255 is not in 1..=127; give --node-id\n",
            path.display()
        )
    );
    let out = edsgen(&[
        "simulate",
        "eds/cp301.eds",
        "--node-id",
        "3",
        "--node-id",
        "4",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(stderr(&out), "error: 2 --node-id for 1 file(s)\n");
}

#[test]
fn simulate_says_when_the_hub_is_unreachable() {
    // A port nobody listens on: bound, then released.
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let addr = format!("127.0.0.1:{port}");
    let out = edsgen(&["simulate", "eds/cp301.eds@3", "--bus", &addr]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).starts_with(&format!("error: cannot reach the bus at {addr}: ")),
        "{}",
        stderr(&out)
    );
}

#[test]
#[cfg(not(feature = "socketcan"))]
fn simulate_says_socketcan_is_not_built_in() {
    let out = edsgen(&["simulate", "eds/cp301.eds@3", "--socketcan", "can0"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        stderr(&out),
        "error: cannot open SocketCAN interface `can0`: this edsgen is built without the `socketcan` feature; join a socketcand hub with --bus\n"
    );
}

#[test]
fn simulate_exits_2_when_the_hub_goes_away() {
    let hub = hub();
    let addr = hub.local_addr().to_string();
    let sim = Process::edsgen(&["simulate", "eds/cp301.eds@3", "--bus", &addr]);
    let announced = format!("simulating node 3 (eds/cp301.eds) on {addr}");
    sim.stderr_line(|l| l == announced, WAIT);
    hub.stop();
    let line = sim.stderr_line(|l| l.starts_with("error:"), WAIT);
    assert!(
        line.starts_with(&format!("error: the bus at {addr} went away")),
        "{line}"
    );
    assert_eq!(sim.finish(WAIT).code, Some(2));
}

#[test]
fn several_devices_in_one_process_answer_and_trace() {
    let hub = hub();
    let addr = hub.local_addr().to_string();
    let sim = Process::edsgen(&[
        "simulate",
        "eds/cp301.eds@1",
        "eds/goodrive350.eds",
        "--node-id",
        "9",
        "--node-id",
        "2",
        "--bus",
        &addr,
        "--trace",
    ]);
    sim.stderr_line(|l| l.starts_with("simulating node 1 "), WAIT);
    sim.stderr_line(|l| l.starts_with("simulating node 2 "), WAIT);
    let mut master = SocketcandClient::connect(&addr, "can0", Duration::from_secs(3)).unwrap();
    std::thread::sleep(Duration::from_millis(100)); // the hub's quiet period after rawmode
                                                    // Reset both: two boot-ups.
    master
        .send(&CanFrame::new(0x000, &[0x81, 0x00]).unwrap())
        .unwrap();
    let mut boot = receive(&mut master, 2, |f| f.data() == [0x00]);
    boot.sort_by_key(|f| f.std_id());
    assert_eq!(boot[0].std_id(), Some(0x701));
    assert_eq!(boot[1].std_id(), Some(0x702));
    // Each answers its own SDO: 1018h:00 of the Goodrive350 at node 2.
    master
        .send(&CanFrame::new(0x602, &[0x40, 0x18, 0x10, 0x00, 0, 0, 0, 0]).unwrap())
        .unwrap();
    let answer = receive(&mut master, 1, |f| f.std_id() == Some(0x582));
    assert_eq!(answer[0].data()[..4], [0x4F, 0x18, 0x10, 0x00]);
    // The trace decodes what the master sent and what the nodes answered.
    sim.stdout_line(
        |l| l.ends_with("000  NMT        reset node, all nodes"),
        WAIT,
    );
    sim.stdout_line(|l| l.ends_with("702  HEARTBEAT  node 2 boot-up"), WAIT);
    sim.stdout_line(
        |l| l.contains("582  SDO        node 2 read 1018:00 Identity object: "),
        WAIT,
    );
}

/// The simulator's test device written as `NAME.eds` in a folder of its own, with `overlay` as
/// `NAME.toml` beside it if given.
fn device_files(name: &str, overlay: Option<&str>) -> PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli-simulate-overlay");
    std::fs::create_dir_all(&dir).unwrap();
    let eds = dir.join(format!("{name}.eds"));
    std::fs::write(&eds, sim_support::DEVICE_EDS).unwrap();
    let toml = eds.with_extension("toml");
    match overlay {
        Some(text) => std::fs::write(&toml, text).unwrap(),
        None => assert!(!toml.exists()),
    }
    eds
}

#[test]
fn simulate_applies_the_overlay_beside_the_file() {
    // 2000h, a writable VISIBLE_STRING with "sim" as default: 32 bytes without an overlay, 100
    // with one.
    let with = device_files("with-overlay", Some("[capacity]\n2000 = 100\n"));
    let without = device_files("without-overlay", None);
    let hub = hub();
    let addr = hub.local_addr().to_string();
    let with_arg = format!("{}@9", with.display());
    let without_arg = format!("{}@10", without.display());
    let sim = Process::edsgen(&["simulate", &with_arg, &without_arg, "--bus", &addr]);
    sim.stderr_line(|l| l.starts_with("simulating node 9 "), WAIT);
    sim.stderr_line(|l| l.starts_with("simulating node 10 "), WAIT);
    let client = SocketcandClient::connect(&addr, "can0", WAIT).unwrap();
    let mut master = Master::new(client);
    let label = Multiplexer::new(0x2000, 0);
    let text: Vec<u8> = (0..100u8).map(|i| b'a' + i % 26).collect();
    master.download(9, label, &text, Mode::Normal).unwrap();
    assert_eq!(master.upload(9, label, Mode::Normal).unwrap(), text);
    master
        .download(10, label, &text[..32], Mode::Normal)
        .unwrap();
    // One byte more than each holds: 0607 0012 (data type length too high).
    let mut refused =
        |node_id, value: &[u8]| match master.download(node_id, label, value, Mode::Normal) {
            Err(MasterError::Sdo {
                error: SdoError::Server(code),
                ..
            }) => code,
            other => panic!("{other:?}"),
        };
    assert_eq!(refused(10, &text[..33]), 0x0607_0012);
    assert_eq!(refused(9, &[text.as_slice(), b"!"].concat()), 0x0607_0012);
}

#[test]
fn simulate_refuses_an_overlay_with_errors_and_shows_them_at_their_line() {
    let eds = device_files("bad-overlay", Some("[capacity]\n2002 = 100\n"));
    let out = edsgen(&["simulate", &format!("{}@9", eds.display())]);
    assert_eq!(out.status.code(), Some(2));
    let toml = eds.with_extension("toml");
    let toml = toml.display();
    assert_eq!(
        stderr(&out),
        format!(
            "error: the overlay `{toml}` cannot be applied:\n\
             error[EDS708]: 2002h sub 0 `Target speed` is not a string, octet string or domain\n \
             --> {toml}:2:1\n  |\n2 | 2002 = 100\n  | ^^^^ only those have a capacity\n  |\n"
        )
    );
}

fn log_file(name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("edsgen-cli-bus-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn decode_warns_about_a_malformed_line_with_its_number_and_goes_on() {
    let log = log_file(
        "bad.log",
        "(1700000000.000000) can0 000#0103\nnot a frame\n(1700000000.100000) can0 703#05\n",
    );
    let out = edsgen(&["decode", log.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0));
    assert!(
        stderr(&out).starts_with("warning: line 2: bad candump line"),
        "{}",
        stderr(&out)
    );
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "1700000000.000000  000  NMT        start node 3\n\
         1700000000.100000  703  HEARTBEAT  node 3 operational\n"
    );
}

#[test]
fn decode_reads_standard_input_and_names_entries_from_the_eds() {
    let mut decode = Process::edsgen(&["decode", "--eds", "eds/cp301.eds", "--node-id", "3"]);
    decode.send_line("(1700000000.000000) can0 603#2B17100064000000");
    decode.send_line("(1700000000.001000) can0 583#6017100000000000");
    let out = decode.finish(WAIT);
    assert_eq!(out.code, Some(0));
    assert_eq!(
        out.stdout,
        "1700000000.001000  583  SDO        node 3 write 1017:00 Producer heartbeat time = 100\n"
    );
}

#[test]
fn decode_refuses_unpaired_descriptions_and_missing_files() {
    let out = edsgen(&["decode", "--eds", "eds/cp301.eds"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        stderr(&out),
        "error: 1 --eds but 0 --node-id: give each description its node-ID (`--eds FILE --node-id N`)\n"
    );
    let out = edsgen(&["decode", "nope.log"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).starts_with("error: cannot read `nope.log`: "),
        "{}",
        stderr(&out)
    );
    let out = edsgen(&["decode", "--eds", "nope.eds", "--node-id", "3", "nope.log"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(stderr(&out), "error: cannot read `nope.eds`: not a file\n");
}
