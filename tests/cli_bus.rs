//! `edsgen bus` as a user runs it: it prints where it listens, relays frames between socketcand
//! clients, logs them in the `candump -L` format, stops cleanly on Ctrl-C (SIGINT), and a port in
//! use or a bad address is a clear error with exit code 2.

mod process_support;

use std::process::Command;
use std::time::{Duration, Instant};

use edsgen_host::socketcand::SocketcandClient;
use edsgen_host::Transport;
use edsgen_runtime::CanFrame;
use process_support::{Process, EDSGEN};

const WAIT: Duration = Duration::from_secs(5);

fn edsgen_bus(args: &[&str]) -> Process {
    Process::edsgen(&[&["bus"], args].concat())
}

/// Sends Ctrl-C (SIGINT) to `process`.
fn interrupt(process: &Process) {
    let interrupted = Command::new("kill")
        .args(["-INT", &process.id().to_string()])
        .status()
        .unwrap();
    assert!(interrupted.success());
}

#[test]
fn bus_prints_its_address_relays_and_logs_frames_and_stops_on_ctrl_c() {
    let log = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_bus_relay.log");
    let bus = edsgen_bus(&["--listen", "127.0.0.1:0", "--log", log.to_str().unwrap()]);
    let first = bus.stdout_line(|_| true, WAIT);
    let addr = first
        .strip_prefix("edsgen bus: socketcand hub listening on ")
        .and_then(|rest| rest.strip_suffix(", channel can0; Ctrl-C stops it"))
        .unwrap_or_else(|| panic!("unexpected first line {first:?}"));
    let addr: std::net::SocketAddr = addr.parse().unwrap();
    assert_eq!(
        bus.stdout_line(|_| true, WAIT),
        format!(
            "  python-can: can.Bus(interface=\"socketcand\", host=\"127.0.0.1\", port={}, channel=\"can0\")",
            addr.port()
        )
    );
    let mut a = SocketcandClient::connect(addr, "can0", WAIT).unwrap();
    let mut b = SocketcandClient::connect(addr, "can0", WAIT).unwrap();
    a.send(&CanFrame::new(0x603, &[0x2B, 0x17, 0x10, 0, 0xE8, 0x03, 0, 0]).unwrap())
        .unwrap();
    assert_eq!(
        b.recv_timeout(WAIT).unwrap(),
        CanFrame::new(0x603, &[0x2B, 0x17, 0x10, 0, 0xE8, 0x03, 0, 0])
    );
    interrupt(&bus);
    let exited = bus.finish(WAIT);
    assert_eq!(exited.code, Some(0));
    assert_eq!(
        exited.stdout,
        "edsgen bus: stopped after relaying 1 frame(s)\n"
    );
    let logged = std::fs::read_to_string(&log).unwrap();
    let line = logged.strip_suffix('\n').unwrap();
    assert_eq!(
        line.split_once(") ").unwrap().1,
        "can0 603#2B171000E8030000",
        "{logged}"
    );
    assert!(
        b.recv_timeout(WAIT).is_err(),
        "the client sees the hub go away"
    );
}

fn stderr_of_failed_start(args: &[&str]) -> String {
    let exited = edsgen_bus(args).finish(WAIT);
    assert_eq!(exited.code, Some(2));
    exited.stderr
}

#[test]
fn bus_on_a_port_in_use_is_an_error_with_exit_code_2() {
    let taken = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = taken.local_addr().unwrap().to_string();
    assert_eq!(
        stderr_of_failed_start(&["--listen", &addr]),
        format!("error: cannot listen on {addr}: the address is in use (another hub?)\n")
    );
}

#[test]
fn bus_with_a_bad_address_or_log_path_is_an_error_with_exit_code_2() {
    assert_eq!(
        stderr_of_failed_start(&["--listen", "nonsense"]),
        "error: cannot listen on nonsense: invalid socket address\n"
    );
    let missing = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("no/such/dir/bus.log");
    assert_eq!(
        stderr_of_failed_start(&[
            "--listen",
            "127.0.0.1:0",
            "--log",
            missing.to_str().unwrap()
        ]),
        format!(
            "error: cannot create the log {}: No such file or directory (os error 2)\n",
            missing.display()
        )
    );
}

#[test]
fn bus_goes_on_and_stops_cleanly_when_its_output_is_closed() {
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let listen = format!("127.0.0.1:{port}");
    let bus =
        Process::start_without_stdout(Command::new(EDSGEN).args(["bus", "--listen", &listen]));
    let deadline = Instant::now() + WAIT;
    let mut a = loop {
        match SocketcandClient::connect(listen.as_str(), "can0", WAIT) {
            Ok(client) => break client,
            Err(e) => assert!(Instant::now() < deadline, "the hub never listened: {e}"),
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let mut b = SocketcandClient::connect(listen.as_str(), "can0", WAIT).unwrap();
    a.send(&CanFrame::new(0x080, &[]).unwrap()).unwrap();
    assert_eq!(b.recv_timeout(WAIT).unwrap(), CanFrame::new(0x080, &[]));
    interrupt(&bus);
    assert_eq!(bus.finish(WAIT).code, Some(0));
}

#[test]
fn bus_serves_only_its_channel_and_refuses_another_as_socketcand_does() {
    let bus = edsgen_bus(&["--listen", "127.0.0.1:0", "--channel", "vcan1"]);
    let first = bus.stdout_line(|_| true, WAIT);
    let addr = first
        .strip_prefix("edsgen bus: socketcand hub listening on ")
        .and_then(|rest| rest.strip_suffix(", channel vcan1; Ctrl-C stops it"))
        .unwrap_or_else(|| panic!("unexpected first line {first:?}"));
    let error = SocketcandClient::connect(addr, "can0", WAIT).err().unwrap();
    assert_eq!(
        error.to_string(),
        format!("socketcand server {addr}: expected Ok after `< open can0 >`, got `< error could not open bus >`")
    );
    let mut a = SocketcandClient::connect(addr, "vcan1", WAIT).unwrap();
    let mut b = SocketcandClient::connect(addr, "vcan1", WAIT).unwrap();
    a.send(&CanFrame::new(0x701, &[0x05]).unwrap()).unwrap();
    assert_eq!(b.recv_timeout(WAIT).unwrap(), CanFrame::new(0x701, &[0x05]));
    interrupt(&bus);
    assert_eq!(bus.finish(WAIT).code, Some(0));
}

#[test]
fn bus_keeps_a_client_that_does_not_read_and_reports_the_frames_dropped_for_it() {
    let bus = edsgen_bus(&["--listen", "127.0.0.1:0", "--queue-limit", "100"]);
    let first = bus.stdout_line(|_| true, WAIT);
    let addr = first
        .strip_prefix("edsgen bus: socketcand hub listening on ")
        .and_then(|rest| rest.strip_suffix(", channel can0; Ctrl-C stops it"))
        .unwrap_or_else(|| panic!("unexpected first line {first:?}"))
        .to_owned();
    bus.stdout_line(|l| l.starts_with("  python-can: "), WAIT);
    // A client that never reads, and a sender that floods the bus until the hub says so.
    let _deaf = SocketcandClient::connect(addr.as_str(), "can0", WAIT).unwrap();
    let mut sender = SocketcandClient::connect(addr.as_str(), "can0", WAIT).unwrap();
    let noticed = std::sync::atomic::AtomicBool::new(false);
    let (line, sent) = std::thread::scope(|scope| {
        let flood = scope.spawn(|| {
            let frame = CanFrame::new(0x181, &[1, 2, 3, 4]).unwrap();
            let deadline = Instant::now() + Duration::from_secs(60);
            let mut sent = 0u64;
            while !noticed.load(std::sync::atomic::Ordering::SeqCst) {
                assert!(Instant::now() < deadline, "no notice after {sent} frames");
                for _ in 0..1000 {
                    sender.send(&frame).unwrap();
                }
                sent += 1000;
            }
            sent
        });
        let line = bus.stderr_line(
            |l| l.contains(" reads too slowly: "),
            Duration::from_secs(60),
        );
        noticed.store(true, std::sync::atomic::Ordering::SeqCst);
        (line, flood.join().unwrap())
    });
    assert!(
        line.starts_with("edsgen bus: client 1 (127.0.0.1:")
            && line.contains(") reads too slowly: dropped its 1 oldest frame(s) (1 in all)"),
        "{line}"
    );
    // Once a new client gets the sender's next frame, the hub has relayed all before it.
    let mut last = SocketcandClient::connect(addr.as_str(), "can0", WAIT).unwrap();
    sender.send(&CanFrame::new(0x7FF, &[]).unwrap()).unwrap();
    // (It may get the end of the flood first.)
    let deadline = Instant::now() + WAIT;
    while last.recv_timeout(WAIT).unwrap() != CanFrame::new(0x7FF, &[]) {
        assert!(Instant::now() < deadline, "the last frame never came");
    }
    interrupt(&bus);
    let exited = bus.finish(WAIT);
    assert_eq!(exited.code, Some(0));
    assert_eq!(
        exited.stdout,
        format!("edsgen bus: stopped after relaying {} frame(s)\n", sent + 1)
    );
    assert!(
        exited
            .stderr
            .contains(" frame(s) were dropped for clients that read too slowly\n"),
        "{}",
        exited.stderr
    );
}
