//! `edsgen bus` as a user runs it: it prints where it listens, relays frames between socketcand
//! clients, logs them in the `candump -L` format, stops cleanly on Ctrl-C (SIGINT), and a port in
//! use or a bad address is a clear error with exit code 2.

use std::io::{BufRead, BufReader, Read};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use edsgen_runtime::transport::socketcand::SocketcandClient;
use edsgen_runtime::transport::Transport;
use edsgen_runtime::CanFrame;

const WAIT: Duration = Duration::from_secs(5);

/// The `edsgen bus` child, killed if the test ends before it exits.
struct Bus(Child);

impl Drop for Bus {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

impl Bus {
    /// Waits at most [`WAIT`] for the exit code.
    fn wait(&mut self) -> i32 {
        let deadline = Instant::now() + WAIT;
        loop {
            if let Some(status) = self.0.try_wait().unwrap() {
                return status.code().expect("killed by a signal");
            }
            assert!(Instant::now() < deadline, "edsgen bus did not stop");
            std::thread::sleep(Duration::from_millis(10));
        }
    }
}

fn edsgen_bus(args: &[&str]) -> Bus {
    let child = Command::new(env!("CARGO_BIN_EXE_edsgen"))
        .arg("bus")
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    Bus(child)
}

#[test]
fn bus_prints_its_address_relays_and_logs_frames_and_stops_on_ctrl_c() {
    let log = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_bus_relay.log");
    let mut bus = edsgen_bus(&["--listen", "127.0.0.1:0", "--log", log.to_str().unwrap()]);
    let mut stdout = BufReader::new(bus.0.stdout.take().unwrap());
    let mut first = String::new();
    stdout.read_line(&mut first).unwrap();
    let addr = first
        .strip_prefix("edsgen bus: socketcand hub listening on ")
        .and_then(|rest| rest.strip_suffix(", channel can0; Ctrl-C stops it\n"))
        .unwrap_or_else(|| panic!("unexpected first line {first:?}"));
    let addr: std::net::SocketAddr = addr.parse().unwrap();
    let mut second = String::new();
    stdout.read_line(&mut second).unwrap();
    assert_eq!(
        second,
        format!(
            "  python-can: can.Bus(interface=\"socketcand\", host=\"127.0.0.1\", port={}, channel=\"can0\")\n",
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
    let interrupted = Command::new("kill")
        .args(["-INT", &bus.0.id().to_string()])
        .status()
        .unwrap();
    assert!(interrupted.success());
    assert_eq!(bus.wait(), 0);
    let mut rest = String::new();
    stdout.read_to_string(&mut rest).unwrap();
    assert_eq!(rest, "edsgen bus: stopped after relaying 1 frame(s)\n");
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
    let mut bus = edsgen_bus(args);
    assert_eq!(bus.wait(), 2);
    let mut stderr = String::new();
    bus.0
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut stderr)
        .unwrap();
    stderr
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
    let mut bus = edsgen_bus(&["--listen", &listen]);
    drop(bus.0.stdout.take());
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
    let interrupted = Command::new("kill")
        .args(["-INT", &bus.0.id().to_string()])
        .status()
        .unwrap();
    assert!(interrupted.success());
    assert_eq!(bus.wait(), 0);
}
