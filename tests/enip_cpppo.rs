//! The simulated EtherNet/IP adapter (`edsgen simulate --enip`) read by a real third-party
//! client: PyPI `cpppo` 5.2.5 (pinned in scripts/python-venv.sh) gets the Identity object's
//! attributes and assembly 100 by explicit messaging (SendRRData, Get_Attribute_Single) and lists
//! the identity (ListIdentity), over TCP on 127.0.0.1; the card's and a generic ODVA EDS's.

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
}
