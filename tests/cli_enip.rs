//! `edsgen enip list|get|set` against the simulated card (`edsgen simulate --enip`) on 127.0.0.1:
//! the identity matched to the card's EDS, attributes read and written by explicit messaging,
//! refusals with their CIP status and exit 1, bad usage with exit 2.

mod process_support;

use std::process::Command;
use std::time::Duration;

use process_support::{Process, EDSGEN};

fn adapter() -> (Process, String) {
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("a free port")
        .port();
    let address = format!("127.0.0.1:{port}");
    let process = Process::edsgen(&["simulate", "--enip", &address, "--card", "goodrive350-enip"]);
    process.stderr_line(|l| l.starts_with("serving"), Duration::from_secs(10));
    (process, address)
}

fn edsgen(args: &[&str]) -> (Option<i32>, String, String) {
    let out = Command::new(EDSGEN)
        .args(args)
        .current_dir(process_support::root())
        .output()
        .expect("edsgen runs");
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn list_get_set_against_the_simulated_card() {
    let (_adapter, address) = adapter();
    let (code, stdout, _) = edsgen(&[
        "enip",
        "list",
        &address,
        "--eds",
        "eds/goodrive350-enip.eds",
    ]);
    assert_eq!(code, Some(0));
    assert_eq!(
        stdout,
        "127.0.0.1\tvendor 0\tdevice type 12\tproduct code 350\trevision 1.10\tserial 0x00350001\t\
         Goodrive350 EtherNet/IP card\tmatches eds/goodrive350-enip.eds\n"
    );
    let (code, stdout, _) = edsgen(&[
        "enip",
        "list",
        &address,
        "--eds",
        "codegen/tests/odva/io.eds",
    ]);
    assert_eq!(code, Some(0));
    assert!(
        stdout.ends_with("\tdoes not match codegen/tests/odva/io.eds\n"),
        "{stdout}"
    );
    assert_eq!(edsgen(&["enip", "get", &address, "@1/1/3"]).1, "5E 01\n");
    // The drive at rest in assembly 100: SW 0x4103 in word 4, little-endian.
    let (code, stdout, _) = edsgen(&["enip", "get", &address, "@4/100/3"]);
    assert_eq!(code, Some(0));
    assert_eq!(&stdout[..30], "00 00 00 00 00 00 00 00 03 41 ");
    // Assembly 150 takes exactly its 32 bytes.
    let value = "00".repeat(32);
    assert_eq!(
        edsgen(&["enip", "set", &address, "@4/150/3", &value]).0,
        Some(0)
    );
    assert_eq!(
        edsgen(&["enip", "set", &address, "@4/150/3", "01 00"]),
        (
            Some(1),
            String::new(),
            "error: @4/150/3: not enough data (general status 0x13)\n".to_owned()
        )
    );
    assert_eq!(
        edsgen(&["enip", "get", &address, "@1/1/99"]),
        (
            Some(1),
            String::new(),
            "error: @1/1/99: attribute not supported (general status 0x14)\n".to_owned()
        )
    );
    assert_eq!(
        edsgen(&["enip", "get", &address, "@0x70/1/1"]).2,
        "error: @0x70/1/1: path destination unknown (general status 0x05)\n"
    );
    assert_eq!(
        edsgen(&["enip", "get", &address, "@4/100"]),
        (
            Some(2),
            String::new(),
            "error: `@4/100` is not @CLASS/INSTANCE/ATTRIBUTE\n".to_owned()
        )
    );
}
