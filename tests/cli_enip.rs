//! `edsgen enip list|get|set` against the simulated card (`edsgen simulate --enip`) on 127.0.0.1:
//! the identity matched to the card's EDS, attributes read and written by explicit messaging,
//! refusals with their CIP status and exit 1, bad usage with exit 2; parameters of the card's EDS
//! and of a generic ODVA EDS by name, typed, scaled and named, written after their type and
//! limits are checked.

mod process_support;

use std::process::Command;
use std::time::Duration;

use process_support::{Process, EDSGEN};

fn adapter() -> (Process, String) {
    serve(&["--card", "goodrive350-enip"])
}

/// `edsgen simulate --enip 127.0.0.1:PORT ARGS` on a free port, once it says it serves.
fn serve(args: &[&str]) -> (Process, String) {
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("a free port")
        .port();
    let address = format!("127.0.0.1:{port}");
    let process = Process::edsgen(&[&["simulate", "--enip", &address], args].concat());
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
    let (code, stdout, stderr) = edsgen(&[
        "enip",
        "list",
        &address,
        "--eds",
        "eds/goodrive350-enip.eds",
    ]);
    assert_eq!(code, Some(0));
    assert_eq!(
        stderr,
        format!(
            "listening 1.5 s for ListIdentity answers from {address} (maximum delay 1000 ms)\n"
        )
    );
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
    // A mismatch is exit 1, as `check` and `validate` say a difference.
    assert_eq!(code, Some(1));
    assert!(
        stdout.ends_with("\tdoes not match codegen/tests/odva/io.eds\n"),
        "{stdout}"
    );
    assert_eq!(edsgen(&["enip", "get", &address, "@1/1/3"]).1, "5E 01\n");
    // Get_Attributes_All of the Identity: vendor, device type, product code, revision 1.10,
    // status, serial, the name as a short string.
    assert_eq!(
        edsgen(&["enip", "get", &address, "@1/1"]),
        (
            Some(0),
            "00 00 0C 00 5E 01 01 0A 00 00 01 00 35 00 1C 47 6F 6F 64 72 69 76 65 33 35 30 20 45 \
             74 68 65 72 4E 65 74 2F 49 50 20 63 61 72 64\n"
                .to_owned(),
            String::new()
        )
    );
    // Any service: Get_Attribute_Single by its code; one the Identity lacks is refused.
    assert_eq!(
        edsgen(&["enip", "service", &address, "0x0E", "@1/1/3"]).1,
        "5E 01\n"
    );
    assert_eq!(
        edsgen(&["enip", "service", &address, "0x4B", "@1/1"]),
        (
            Some(1),
            String::new(),
            "error: @1/1: service not supported (general status 0x08)\n".to_owned()
        )
    );
    for (args, message) in [
        (
            &["service", &address, "0x80", "@1/1"][..],
            "error: `0x80` is not a CIP service code (0..0x7F, decimal or hex with 0x)\n",
        ),
        (
            &["service", &address, "5", "@1/1", "zz"],
            "error: `zz` is not hex bytes\n",
        ),
        (
            &["set", &address, "@1/1", "00"],
            "error: `@1/1` is not @CLASS/INSTANCE/ATTRIBUTE\n",
        ),
    ] {
        let out = edsgen(&[&["enip"], args].concat());
        assert_eq!((out.0, out.2.as_str()), (Some(2), message));
    }
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
    // Bound to every address, the adapter reports the one a request reaches it at (ListIdentity's
    // sockaddr: family 2, port 44818, then the address), not 0.0.0.0.
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("a free port")
        .port();
    let wildcard = Process::edsgen(&[
        "simulate",
        "--enip",
        &format!("0.0.0.0:{port}"),
        "--card",
        "goodrive350-enip",
    ]);
    wildcard.stderr_line(|l| l.starts_with("serving"), Duration::from_secs(10));
    let socket = std::net::UdpSocket::bind("127.0.0.1:0").expect("a UDP socket");
    socket
        .set_read_timeout(Some(Duration::from_secs(3)))
        .expect("a timeout");
    let mut request = [0u8; 24];
    request[0] = 0x63;
    socket.send_to(&request, ("127.0.0.1", port)).expect("sent");
    let mut reply = [0u8; 200];
    let n = socket.recv(&mut reply).expect("an answer");
    assert!(n > 40);
    assert_eq!(&reply[32..40], &[0, 2, 0xAF, 0x12, 127, 0, 0, 1]);
    drop(wildcard);
    // An address the host does not have, to serve on or to send from.
    assert_eq!(
        edsgen(&["enip", "list", "--from", "192.0.2.77"]),
        (
            Some(2),
            String::new(),
            "error: cannot open a UDP socket on 192.0.2.77: Cannot assign requested address (os \
             error 99): it is not an address of this host\n"
                .to_owned()
        )
    );
    assert_eq!(
        edsgen(&[
            "simulate",
            "--enip",
            "192.0.2.77",
            "--card",
            "goodrive350-enip"
        ]),
        (
            Some(2),
            String::new(),
            "error: cannot serve on 192.0.2.77:44818: Cannot assign requested address (os error \
             99): it is not an address of this host\n"
                .to_owned()
        )
    );
    // An instance alone: Get_Attributes_All (the assembly's data); a class alone is no path.
    assert_eq!(
        &edsgen(&["enip", "get", &address, "@4/100"]).1[..30],
        "00 00 00 00 00 00 00 00 03 41 "
    );
    assert_eq!(
        edsgen(&["enip", "get", &address, "@4"]),
        (
            Some(2),
            String::new(),
            "error: `@4` is not @CLASS/INSTANCE[/ATTRIBUTE]\n".to_owned()
        )
    );
}

const CARD: &str = "eds/goodrive350-enip.eds";

/// `edsgen enip ARGS --eds FILE`: exit code, stdout, stderr.
fn with_eds(file: &str, args: &[&str]) -> (Option<i32>, String, String) {
    edsgen(&[&["enip"], args, &["--eds", file]].concat())
}

fn ok(stdout: &str) -> (Option<i32>, String, String) {
    (Some(0), stdout.to_owned(), String::new())
}

fn error(code: i32, stderr: &str) -> (Option<i32>, String, String) {
    (Some(code), String::new(), stderr.to_owned())
}

#[test]
fn parameters_of_the_cards_eds_by_name() {
    let (_adapter, a) = adapter();
    // The drive at rest: SW 0x4103; the PKW channel idle, its enumeration's text.
    assert_eq!(
        with_eds(CARD, &["get", &a, "SW"]),
        ok("Param22 SW = 16643 (0x4103)\n")
    );
    assert_eq!(
        with_eds(CARD, &["get", &a, "pkw1 RES"]),
        ok("Param18 PKW1 response = 0 (0x0000) \"No response\"\n")
    );
    assert_eq!(
        with_eds(CARD, &["get", &a, "Transmitted PZD2"]),
        ok("Param23 Transmitted PZD2 = 0.00 Hz (raw 0)\n")
    );
    // A PKW read of P00.10 through the output assembly, member by member (each write reads
    // assembly 150 and writes it back with the member replaced): address 10, then task
    // "Read a parameter" by a prefix of its text.
    assert_eq!(
        with_eds(CARD, &["set", &a, "Param3", "10"]),
        ok("Param3 PKW2 address written\n")
    );
    assert_eq!(
        with_eds(CARD, &["set", &a, "PKW1 task", "read"]),
        ok("Param2 PKW1 task written\n")
    );
    assert_eq!(
        with_eds(CARD, &["get", &a, "Param2"]),
        ok("Param2 PKW1 task = 1 (0x0001) \"Read a parameter\"\n")
    );
    assert_eq!(
        with_eds(CARD, &["get", &a, "PKW1 response"]),
        ok("Param18 PKW1 response = 1 (0x0001) \"Value, one word\"\n")
    );
    // P00.10, the maximum output frequency: 50.00 Hz.
    assert_eq!(
        with_eds(CARD, &["get", &a, "Param21"]),
        ok("Param21 PKW4 value low = 5000 (0x1388)\n")
    );
    // Two parameters share the name: which one?
    assert_eq!(
        with_eds(CARD, &["get", &a, "PKW2 address"]),
        error(
            2,
            "error: `PKW2 address` names 2 parameters; did you mean:\n  \
             Param3  PKW2 address\n  Param19  PKW2 address\n"
        )
    );
    // Checked before sending: the type's range, read-only, a value of no kind it takes.
    assert_eq!(
        with_eds(CARD, &["set", &a, "CW", "70000"]),
        error(2, "error: Param6 CW: 70000 is outside 0 ..= 65535\n")
    );
    assert_eq!(
        with_eds(CARD, &["set", &a, "SW", "1"]),
        error(
            2,
            "error: Param22 SW is read-only (its descriptor's bit 4)\n"
        )
    );
    assert_eq!(
        with_eds(CARD, &["set", &a, "PKW1 task", "write"]),
        error(
            2,
            "error: Param2 PKW1 task: `write` is not a number; it takes 0 \"No \
             task\", 1 \"Read a parameter\", 2 \"Write one word (RAM)\", 3 \"Write two words \
             (RAM)\", 4 \"Write one word (RAM and EEPROM)\", 5 \"Write two words (RAM and \
             EEPROM)\"\n"
        )
    );
    // The PKW task's limits are 0..=5.
    assert_eq!(
        with_eds(CARD, &["set", &a, "PKW1 task", "6"]),
        error(2, "error: Param2 PKW1 task: 6 is outside 0 ..= 5\n")
    );
    // The RPI is no member and has no link path: attribute 1 of its Parameter object.
    assert_eq!(
        with_eds(CARD, &["get", &a, "RPI"]),
        ok("Param1 RPI = 50000 (0x0000C350) us\n")
    );
    assert_eq!(
        with_eds(CARD, &["set", &a, "RPI", "100000"]),
        ok("Param1 RPI written\n")
    );
    assert_eq!(
        with_eds(CARD, &["get", &a, "Param1"]),
        ok("Param1 RPI = 100000 (0x000186A0) us\n")
    );
    // The same Parameter object by its path: the descriptor and the value's refusals.
    assert_eq!(edsgen(&["enip", "get", &a, "@0x0F/1/5"]), ok("C8\n"));
    assert_eq!(
        edsgen(&["enip", "set", &a, "@0x0F/1/1", "00 00 00 00"]),
        error(
            1,
            "error: @0x0F/1/1: invalid attribute value (general status 0x09)\n"
        )
    );
    assert_eq!(
        edsgen(&["enip", "set", &a, "@0x0F/22/1", "00 00"]),
        error(
            1,
            "error: @0x0F/22/1: attribute not settable (general status 0x0e)\n"
        )
    );
    // PKW1 task (Param2) through the Parameter object is the same bits of assembly 150.
    assert_eq!(edsgen(&["enip", "get", &a, "@0x0F/2/1"]), ok("01 00\n"));
    // --eds with an attribute's path: said to be unused, the bytes in hex.
    assert_eq!(
        with_eds(CARD, &["get", &a, "@1/1/3"]),
        (
            Some(0),
            "5E 01\n".to_owned(),
            "warning: --eds eds/goodrive350-enip.eds is not used with @CLASS/INSTANCE/ATTRIBUTE \
             (its bytes are in hex): name a parameter to have its value typed\n"
                .to_owned()
        )
    );
    // A name without --eds.
    assert_eq!(
        edsgen(&["enip", "get", &a, "SW"]),
        error(
            2,
            "error: `SW` is not @CLASS/INSTANCE/ATTRIBUTE: give a parameter name with --eds FILE\n"
        )
    );
}

#[test]
fn parameters_of_a_generic_eds_by_name() {
    const IO: &str = "codegen/tests/odva/io.eds";
    let (_adapter, a) = serve(&[IO]);
    // Speed: default 1500, scaled by 1/10 with one decimal, in rpm.
    assert_eq!(
        with_eds(IO, &["get", &a, "speed"]),
        ok("Param1 Speed = 150.0 rpm (raw 1500)\n")
    );
    assert_eq!(
        with_eds(IO, &["get", &a, "Mo"]),
        ok("Param2 Mode = 0 (0x00) \"Off\"\n")
    );
    assert_eq!(
        with_eds(IO, &["get", &a, "Sped"]),
        error(
            2,
            "error: the EDS has no parameter named `Sped`; did you mean:\n  Param1  Speed\n"
        )
    );
    // Engineering values are checked against the limits in engineering units.
    assert_eq!(
        with_eds(IO, &["set", &a, "Speed", "300.1"]),
        error(
            2,
            "error: Param1 Speed: 300.1 is outside 0.0 ..= 300.0 rpm\n"
        )
    );
    // Mode is in the input assembly, which the adapter produces: refused by the device.
    assert_eq!(
        with_eds(IO, &["set", &a, "Mode", "fast"]),
        error(
            1,
            "error: Param2 Mode: attribute not settable (general status 0x0e)\n"
        )
    );
    assert_eq!(
        with_eds(IO, &["set", &a, "Mode", "3"]),
        error(2, "error: Param2 Mode: 3 is outside 0 ..= 2\n")
    );
    // The RPI, in no assembly: the adapter's Parameter object keeps it.
    assert_eq!(
        with_eds(IO, &["get", &a, "RPI"]),
        ok("Param3 RPI = 50000 (0x0000C350) us\n")
    );
    assert_eq!(
        with_eds(IO, &["set", &a, "RPI", "0x4E20"]),
        ok("Param3 RPI written\n")
    );
    assert_eq!(
        with_eds(IO, &["get", &a, "RPI"]),
        ok("Param3 RPI = 20000 (0x00004E20) us\n")
    );
}

/// SIGINT and SIGTERM stop the adapter cleanly: exit 0 and a `stopped:` line with what it
/// served.
#[test]
fn the_adapter_stops_on_sigint_and_sigterm() {
    for signal in ["-INT", "-TERM"] {
        let (adapter, address) = serve(&["codegen/tests/odva/io.eds"]);
        assert_eq!(edsgen(&["enip", "get", &address, "@1/1/3"]).1, "07 00\n");
        let sent = Command::new("kill")
            .args([signal, &adapter.id().to_string()])
            .status()
            .expect("kill runs");
        assert!(sent.success());
        let exited = adapter.finish(Duration::from_secs(10));
        assert_eq!(
            (exited.code, exited.stderr.as_str()),
            (Some(0), "stopped: 1 clients served, 0 connections opened\n"),
            "{signal}"
        );
    }
}
