//! The simulated EtherNet/IP adapter (`edsgen simulate --enip`) read by a real third-party
//! client: PyPI `cpppo` 5.2.5 (pinned in scripts/python-venv.sh) gets the Identity object's
//! attributes and assembly 100 by explicit messaging (SendRRData, Get_Attribute_Single) and lists
//! the identity (ListIdentity), over TCP on 127.0.0.1; the card's and a generic ODVA EDS's (with
//! its Parameter object). Its
//! `client.implicit` opens a class-3 connection (Forward_Open, transport 0xA3, to the Message
//! Router) and reads and writes over it by SendUnitData.

mod process_support;

use std::process::Command;
use std::time::Duration;

use process_support::{python, root, Process};

/// `edsgen simulate --enip 127.0.0.1:PORT ARGS` on a free port, once it says it serves.
fn adapter(args: &[&str]) -> (Process, String) {
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("a free port")
        .port();
    let address = format!("127.0.0.1:{port}");
    let process = Process::edsgen(&[&["simulate", "--enip", &address], args].concat());
    let line = process.stderr_line(|l| l.starts_with("serving"), Duration::from_secs(10));
    assert!(line.contains(&address), "{line}");
    (process, address)
}

/// cpppo's `get_attribute` of `paths` (simple device, no routing): the values it prints, in
/// order.
fn get_attributes(python: &std::path::Path, address: &str, paths: &[&str]) -> Vec<String> {
    let out = Command::new(python)
        .args(["-m", "cpppo.server.enip.get_attribute", "-S", "-a", address])
        .args(paths)
        .current_dir(root())
        .output()
        .expect("cpppo runs");
    let text =
        String::from_utf8_lossy(&out.stdout).into_owned() + &String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{text}");
    text.lines()
        .filter_map(|l| l.split_once(" == ").map(|(_, v)| v.trim().to_owned()))
        .collect()
}

#[test]
fn cpppo_reads_the_cards_identity_and_input_assembly() {
    let Some(python) = python() else { return };
    let (_adapter, address) = adapter(&["--card", "goodrive350-enip"]);
    let values = get_attributes(
        &python,
        &address,
        &["@1/1/1", "@1/1/2", "@1/1/3", "@1/1/4", "@1/1/7", "@4/100/3"],
    );
    let mut name = vec![28u8];
    name.extend_from_slice(b"Goodrive350 EtherNet/IP card");
    // The drive at rest: SW 0x4103 (stopped, ready, communication control), little-endian.
    let mut input = vec![0u8; 32];
    input[8] = 0x03;
    input[9] = 0x41;
    assert_eq!(
        values,
        vec![
            "[0, 0]".to_owned(),
            "[12, 0]".to_owned(),
            "[94, 1]".to_owned(),
            "[1, 10]".to_owned(),
            format!("{name:?}"),
            format!("{input:?}"),
        ]
    );
    // ListIdentity over UDP, at the adapter's port.
    let (host, port) = address.split_once(':').expect("host:port");
    let script = format!(
        "from cpppo.server import enip\n\
         from cpppo.server.enip import client\n\
         with client.client(host='{host}', port={port}, udp=True, broadcast=False) as conn:\n\
         \x20   conn.list_identity(timeout=2.0)\n\
         \x20   response, _ = client.await_response(conn, timeout=2.0)\n\
         \x20   print(enip.enip_format(response))\n"
    );
    let out = Command::new(&python)
        .args(["-c", &script])
        .output()
        .expect("cpppo runs");
    let text = String::from_utf8_lossy(&out.stdout);
    for wanted in [
        "identity_object.product_name': 'Goodrive350 EtherNet/IP card'",
        "identity_object.product_code': 350",
        "identity_object.device_type': 12",
        "identity_object.serial_number': 3473409",
    ] {
        assert!(
            text.contains(wanted),
            "{wanted} not in {text}{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

#[test]
fn cpppo_reads_a_generic_edss_assembly_with_its_defaults() {
    let Some(python) = python() else { return };
    let (_adapter, address) = adapter(&["codegen/tests/odva/io.eds"]);
    // Inputs: Speed 1500 (0x05DC) and Mode 0; Outputs: Speed 1500.
    assert_eq!(
        get_attributes(&python, &address, &["@4/100/3", "@4/150/3", "@1/1/1"]),
        vec!["[220, 5, 0]", "[220, 5]", "[52, 18]"]
    );
    // The Parameter object (class 0x0F): its max instance; Param3 `RPI`, in no assembly, at
    // its default 50000 with its name; Param1 `Speed`, the bits of assembly 100.
    assert_eq!(
        get_attributes(
            &python,
            &address,
            &["@15/0/2", "@15/3/1", "@15/3/7", "@15/3/5", "@15/1/1"]
        ),
        vec![
            "[3, 0]",
            "[80, 195, 0, 0]",
            "[3, 82, 80, 73]",
            "[200]",
            "[220, 5]"
        ]
    );
}

/// cpppo's `client.implicit` (class 3, transport 0xA3, connection path `@2/1`): Forward_Open,
/// then each operation of `paths` by SendUnitData, then Forward_Close. Prints the transport, one
/// `value status` line per operation, and `closed`.
const CLASS3: &str = "\
import sys
from cpppo.server.enip import client
from cpppo.server.enip.get_attribute import attribute_operations
host, port = sys.argv[1].split(':')
conn = client.implicit(host=host, port=int(port), timeout=5.0, connection_path='@2/1')
print('transport', hex(conn.requested.forward_open.transport_class_triggers))
with conn:
    ops = attribute_operations(sys.argv[2:], route_path=False, send_path='')
    for _, _, _, _, sts, val in conn.synchronous(operations=ops, timeout=5.0):
        print(val, sts)
conn.close()
print('closed')
";

#[test]
fn cpppo_reads_and_writes_over_a_class3_connection() {
    let Some(python) = python() else { return };
    let (adapter, address) = adapter(&["--card", "goodrive350-enip"]);
    let out = Command::new(&python)
        .args(["-c", CLASS3, &address])
        .args([
            "@1/1/1",
            "@1/1/3",
            "@1/1/7",
            "@4/100/3",
            "@1/1/99",
            "@4/100/3=(SINT)1",
        ])
        .current_dir(root())
        .output()
        .expect("cpppo runs");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{text}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut name = vec![28u8];
    name.extend_from_slice(b"Goodrive350 EtherNet/IP card");
    let mut input = vec![0u8; 32];
    input[8] = 0x03;
    input[9] = 0x41;
    let expected = [
        "transport 0xa3".to_owned(),
        "[0, 0] 0".to_owned(),
        "[94, 1] 0".to_owned(),
        format!("{name:?} 0"),
        format!("{input:?} 0"),
        // Attribute not supported; the input assembly not settable.
        "None 20".to_owned(),
        "None 14".to_owned(),
        "closed".to_owned(),
    ];
    assert_eq!(text.lines().collect::<Vec<_>>(), expected);
    // The adapter opened a connection and Forward_Close closed it.
    let opened = adapter.stderr_line(|l| l.starts_with("connection"), Duration::from_secs(5));
    assert!(opened.ends_with(" opened"), "{opened}");
    let closed = adapter.stderr_line(|l| l.starts_with("connection"), Duration::from_secs(5));
    assert_eq!(closed, opened.replace(" opened", " closed"));
}

/// Several adapters in one process, one per address of the host (issue 31): the card on
/// 127.0.0.2 and 127.0.0.3 at the same port, each read by cpppo at its own address; SIGINT
/// stops both, each with its `stopped:` line.
#[test]
fn one_adapter_per_address_in_one_process() {
    let Some(python) = python() else { return };
    let port = std::net::TcpListener::bind("127.0.0.2:0")
        .and_then(|l| l.local_addr())
        .expect("a free port")
        .port();
    let (a, b) = (format!("127.0.0.2:{port}"), format!("127.0.0.3:{port}"));
    let both = format!("{a},{b}");
    let process = Process::edsgen(&["simulate", "--enip", &both, "--card", "goodrive350-enip"]);
    // The two adapters start in either order.
    let serving = |address: &str| format!("serving card goodrive350-enip on {address} ");
    let mut started: Vec<String> = (0..2)
        .map(|_| process.stderr_line(|l| l.starts_with("serving"), Duration::from_secs(10)))
        .collect();
    started.sort();
    assert!(started[0].starts_with(&serving(&a)), "{started:?}");
    assert!(started[1].starts_with(&serving(&b)), "{started:?}");
    let mut name = vec![28u8];
    name.extend_from_slice(b"Goodrive350 EtherNet/IP card");
    for address in [&a, &b] {
        assert_eq!(
            get_attributes(&python, address, &["@1/1/7"]),
            vec![format!("{name:?}")]
        );
    }
    let pid = process.id().to_string();
    let killed = Command::new("kill").args(["-INT", &pid]).status();
    assert!(killed.is_ok_and(|s| s.success()));
    let exited = process.finish(Duration::from_secs(10));
    assert_eq!(exited.code, Some(0), "{exited:?}");
    for address in [&a, &b] {
        let stopped = format!("{address}: stopped: 1 clients served, 0 connections opened");
        assert!(exited.stderr.lines().any(|l| l == stopped), "{exited:?}");
    }
}
