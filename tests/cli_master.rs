//! The bench commands end to end: `edsgen sdo|nmt|scan|check` as processes, through an
//! in-process socketcand hub on 127.0.0.1 (`bench_support`), against device nodes serving the
//! generated cp301 (node 3) and goodrive350 (node 5) cards, run by the transport driver; and
//! file transfers (`--file`, `--out`) with the simulator test device's DOMAIN.

mod bench_support;
#[path = "../sim/tests/sim_support/mod.rs"]
mod sim_support;

use std::path::Path;
use std::process::Command;

use bench_support::*;
use edsgen_host::hub::{Hub, HubOptions};
use edsgen_host::vbus::BusDevice;
use edsgen_runtime::frame::CanFrame;
use edsgen_runtime::node::Node;
use edsgen_runtime::time::Instant;
use edsgen_sim::canopen::RuntimeDictionary;

#[test]
fn sdo_read_and_write_are_typed_and_named_by_the_eds() {
    let bench = bench();
    let cp = eds("cp301.eds");
    let write = edsgen(
        &bench,
        &["sdo", "write", "--eds", &cp, "3", "6040:0", "0x000F"],
    );
    assert_eq!(
        stdout(&write),
        "6040h:00h Controlword written\n",
        "{}",
        stderr(&write)
    );
    assert_eq!(write.status.code(), Some(0));
    let read = edsgen(&bench, &["sdo", "read", "--eds", &cp, "3", "6040:0"]);
    assert_eq!(stdout(&read), "6040h:00h Controlword = 15 (0x000F)\n");
    let name = edsgen(
        &bench,
        &[
            "sdo",
            "read",
            "--eds",
            &eds("goodrive350.eds"),
            "5",
            "1008:0",
        ],
    );
    assert_eq!(
        stdout(&name),
        "1008h:00h Manufacturer device name = INVT CANopen\n"
    );
    let raw = edsgen(&bench, &["sdo", "read", "5", "1008:0"]);
    assert_eq!(
        stdout(&raw),
        "1008h:00h = 49 4E 56 54 20 43 41 4E 6F 70 65 6E\n"
    );
    let typed = edsgen(&bench, &["sdo", "read", "--type", "u32", "3", "1400:1"]);
    assert_eq!(stdout(&typed), "1400h:01h = 515 (0x00000203)\n");
}

#[test]
fn an_sdo_abort_is_an_error_with_its_code_and_meaning_and_exit_1() {
    let bench = bench();
    let output = edsgen(
        &bench,
        &["sdo", "write", "--type", "u16", "3", "6041:0", "1"],
    );
    assert_eq!(output.status.code(), Some(1));
    assert_eq!(
        stderr(&output),
        "error: SDO 6041h:00h on node 3: node aborted with 0601 0002h (attempt to write a read-only object)\n"
    );
    let missing = edsgen(&bench, &["sdo", "read", "3", "5FFF:0"]);
    assert_eq!(missing.status.code(), Some(1));
    assert!(
        stderr(&missing).contains("0602 0000h (object does not exist in the object dictionary)")
    );
    let silent = edsgen(&bench, &["sdo", "read", "9", "1000:0"]);
    assert_eq!(silent.status.code(), Some(1));
    assert!(stderr(&silent).contains("no answer, aborted with 0504 0000h"));
}

#[test]
fn bad_usage_exits_2() {
    let bench = bench();
    for args in [
        &["sdo", "read", "0", "1000:0"][..],
        &["sdo", "read", "3", "Statusword"],
        &["sdo", "write", "3", "6040:0", "1"],
        &["sdo", "read", "--timeout", "0", "3", "1000:0"],
        &["sdo", "write", "--type", "u8", "3", "6040:0", "300"],
        &["nmt", "start", "200"],
    ] {
        let output = edsgen(&bench, args);
        assert_eq!(
            output.status.code(),
            Some(2),
            "{args:?}: {}",
            stderr(&output)
        );
    }
    let nobus = Command::new(EDSGEN)
        .args(["nmt", "start", "all", "--bus", "127.0.0.1:1"])
        .output()
        .unwrap();
    assert_eq!(nobus.status.code(), Some(2));
}

#[test]
fn nmt_and_scan_show_the_nodes_states_and_identities() {
    let bench = bench();
    // socketcand carries no RTR (python-can's dialect), so states come from heartbeats.
    for node in ["3", "5"] {
        let heartbeat = edsgen(
            &bench,
            &["sdo", "write", "--type", "u16", node, "1017:0", "100"],
        );
        assert_eq!(heartbeat.status.code(), Some(0), "{}", stderr(&heartbeat));
    }
    let start = edsgen(&bench, &["nmt", "start", "3"]);
    assert_eq!(start.status.code(), Some(0), "{}", stderr(&start));
    let scan = edsgen(&bench, &["scan"]);
    assert_eq!(scan.status.code(), Some(0), "{}", stderr(&scan));
    let text = stdout(&scan);
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 5, "{text}");
    assert_eq!(
        lines[1],
        "3     operational      0x00000000  0x00000000  0x00000000  0x00000000  -"
    );
    assert_eq!(
        lines[2],
        "5     pre-operational  0x00000000  0x00000000  0x00000000  0x00000000  0x00000000"
    );
    assert_eq!(lines[3], "2 node(s) found on can0");
    assert_eq!(
        lines[4],
        "-: the node does not have the entry, or refused to read it"
    );
    let reset = edsgen(&bench, &["nmt", "reset", "all"]);
    assert_eq!(reset.status.code(), Some(0));
}

#[test]
fn check_of_the_device_its_description_describes_finds_no_difference() {
    let bench = bench();
    let output = edsgen(
        &bench,
        &["check", "--eds", &eds("cp301.eds"), "--node", "3"],
    );
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert!(stdout(&output).ends_with(": 0 error(s), 0 warning(s)\n"));
}

#[test]
fn check_finds_a_product_code_that_differs_and_a_changed_value() {
    let bench = bench();
    let dir = std::env::temp_dir().join(format!("edsgen-check-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("cp301-other-product.eds");
    let text = std::fs::read_to_string(eds("cp301.eds")).unwrap();
    let other = text.replace("ProductNumber=0x00000000", "ProductNumber=0x00001234");
    assert_ne!(text, other);
    std::fs::write(&path, other).unwrap();
    let path = path.display().to_string();
    let write = edsgen(
        &bench,
        &["sdo", "write", "--type", "u16", "3", "6040:0", "6"],
    );
    assert_eq!(write.status.code(), Some(0));
    let output = edsgen(
        &bench,
        &["check", "--eds", &path, "--node", "3", "--format", "json"],
    );
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    let json: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    let found: Vec<(String, String, String)> = json
        .as_array()
        .unwrap()
        .iter()
        .map(|d| {
            (
                d["code"].as_str().unwrap().to_string(),
                d["severity"].as_str().unwrap().to_string(),
                d["message"].as_str().unwrap().to_string(),
            )
        })
        .collect();
    assert_eq!(
        found,
        [
            (
                "CHK004".to_string(),
                "error".to_string(),
                "1018h:02h of node 3 is 0x00000000, the description says 0x00001234".to_string()
            ),
            (
                "CHK005".to_string(),
                "warning".to_string(),
                "6040h:00h Controlword of node 3 holds 6 (0x0006), the description's default is 0"
                    .to_string()
            ),
        ]
    );
}

#[test]
fn check_of_another_devices_description_finds_missing_objects() {
    let bench = bench();
    let output = edsgen(
        &bench,
        &["check", "--eds", &eds("goodrive350.eds"), "--node", "3"],
    );
    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    let text = stdout(&output);
    let first = format!(
        "error[CHK001]: object 1003h is missing on node 3\n   --> {}:135:1\n    |\n135 | [1003]\n    | ^^^^^^\n",
        eds("goodrive350.eds")
    );
    assert!(text.starts_with(&first), "{text}");
    // A constant holding another value is an error, not a warning.
    assert!(text.contains("error[CHK005]: 1008h:00h Manufacturer device name of node 3 holds \"\\0\\0\\0\\0\", the description's default is INVT CANopen"));
}

/// cp301.eds made a DCF: heartbeat 100 ms, TPDO1 on COB-ID 193h, event-driven, mapping `object`.
fn cp301_dcf(object: &str) -> (std::path::PathBuf, String) {
    let dir = std::env::temp_dir().join(format!("edsgen-dcf-{}-{object}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("cp301.dcf");
    let mut text = std::fs::read_to_string(eds("cp301.eds")).unwrap();
    for (section, value) in [
        ("[1017]\n", "100"),
        ("[1800sub1]\n", "0x193"),
        ("[1800sub2]\n", "254"),
        ("[1A00sub0]\n", "1"),
        ("[1A00sub1]\n", object),
    ] {
        assert!(text.contains(section));
        text = text.replace(section, &format!("{section}ParameterValue={value}\n"));
    }
    std::fs::write(&path, text).unwrap();
    let shown = path.display().to_string();
    (dir, shown)
}

#[test]
fn sdo_dcf_downloads_the_parameter_values_with_the_pdo_disabled_meanwhile() {
    let bench = bench();
    let (dir, dcf) = cp301_dcf("0x60440010");
    let output = edsgen(&bench, &["sdo", "dcf", "3", &dcf]);
    assert_eq!(
        stdout(&output),
        "5 value(s) written to node 3\n",
        "{}",
        stderr(&output)
    );
    for (address, value) in [
        ("1017:0", "100 (0x0064)"),
        ("1800:1", "403 (0x00000193)"),
        ("1800:2", "254 (0xFE)"),
        ("1A00:0", "1 (0x01)"),
        ("1A00:1", "1615069200 (0x60440010)"),
    ] {
        let read = edsgen(&bench, &["sdo", "read", "--eds", &dcf, "3", address]);
        assert!(
            stdout(&read).ends_with(&format!(" = {value}\n")),
            "{address}: {}",
            stdout(&read)
        );
    }
    let (bad_dir, bad) = cp301_dcf("0x10000020");
    let refused = edsgen(&bench, &["sdo", "dcf", "3", &bad]);
    assert_eq!(refused.status.code(), Some(1));
    assert_eq!(
        stderr(&refused),
        "error: SDO 1A00h:01h on node 3: node aborted with 0604 0041h (object cannot be mapped to the PDO)\n"
    );
    std::fs::remove_dir_all(dir).unwrap();
    std::fs::remove_dir_all(bad_dir).unwrap();
}

#[test]
fn sdo_write_file_and_read_out_move_64_kib_through_a_domain_byte_for_byte() {
    let bench = sim_bench();
    let scratch = Scratch::new("sdo-file");
    let (image, back, sim) = (
        scratch.path("image.bin"),
        scratch.path("back.bin"),
        scratch.path("sim.eds"),
    );
    let value = pattern(64 * 1024);
    std::fs::write(&image, &value).unwrap();
    let write = edsgen(
        &bench,
        &[
            "sdo", "write", "--eds", &sim, "4", "2001:0", "--file", &image,
        ],
    );
    assert_eq!(write.status.code(), Some(0), "{}", stderr(&write));
    assert_eq!(stdout(&write), "");
    assert_eq!(
        summary(&write),
        "2001h:00h Program: 65536 bytes written by block transfer"
    );
    let read = edsgen(
        &bench,
        &["sdo", "read", "--eds", &sim, "4", "2001:0", "--out", &back],
    );
    assert_eq!(read.status.code(), Some(0), "{}", stderr(&read));
    assert_eq!(
        summary(&read),
        "2001h:00h Program: 65536 bytes read by block transfer"
    );
    assert!(std::fs::read(&back).unwrap() == value, "read back");
    // Segmented both ways, without an EDS: the same bytes.
    let shorter = pattern(3000);
    std::fs::write(&image, &shorter).unwrap();
    let write = edsgen(
        &bench,
        &[
            "sdo",
            "write",
            "4",
            "2001:0",
            "--file",
            &image,
            "--segmented",
        ],
    );
    assert_eq!(
        summary(&write),
        "2001h:00h: 3000 bytes written by segmented transfer"
    );
    let read = edsgen(
        &bench,
        &["sdo", "read", "4", "2001:0", "--out", &back, "--segmented"],
    );
    assert_eq!(
        summary(&read),
        "2001h:00h: 3000 bytes read by segmented transfer"
    );
    assert!(std::fs::read(&back).unwrap() == shorter, "read back");
}

#[test]
fn sdo_file_transfers_stream_standard_input_and_output_as_raw_bytes() {
    let bench = sim_bench();
    let value = pattern(5000);
    let write = edsgen_with_input(
        &bench,
        &["sdo", "write", "4", "2001:0", "--file", "-"],
        value.clone(),
    );
    assert_eq!(
        summary(&write),
        "2001h:00h: 5000 bytes written by block transfer"
    );
    let read = edsgen(&bench, &["sdo", "read", "4", "2001:0", "--out", "-"]);
    assert_eq!(
        summary(&read),
        "2001h:00h: 5000 bytes read by block transfer"
    );
    assert!(read.stdout == value, "standard output holds the raw bytes");
    // A string read to standard output: its bytes, no line end added; the node sends so short
    // a value expedited.
    let name = edsgen(
        &bench,
        &["sdo", "read", "4", "2000:0", "--out", "-", "--segmented"],
    );
    assert_eq!(stdout(&name), "sim");
    assert_eq!(
        summary(&name),
        "2000h:00h: 3 bytes read by expedited transfer"
    );
}

#[test]
fn a_node_without_block_transfer_gets_and_gives_the_file_segmented() {
    let bench = sim_bench();
    // From standard input, which cannot be read twice: the bytes read before the node refused
    // the block transfer go again.
    let value = pattern(2000);
    let write = edsgen_with_input(
        &bench,
        &["sdo", "write", "6", "2001:0", "--file", "-"],
        value.clone(),
    );
    assert_eq!(
        summary(&write),
        "2001h:00h: 2000 bytes written by segmented transfer (the node refused block transfer)"
    );
    let read = edsgen(&bench, &["sdo", "read", "6", "2001:0", "--out", "-"]);
    assert_eq!(
        summary(&read),
        "2001h:00h: 2000 bytes read by segmented transfer (the node refused block transfer)"
    );
    assert!(read.stdout == value, "read back");
    // --block insists: the refusal is the error.
    let insisted = edsgen(
        &bench,
        &["sdo", "read", "6", "2001:0", "--out", "-", "--block"],
    );
    assert_eq!(insisted.status.code(), Some(1));
    assert_eq!(
        stderr(&insisted),
        "error: SDO 2001h:00h on node 6: node aborted with 0504 0001h (client/server command specifier not valid or unknown)\n"
    );
}

#[test]
fn a_file_too_long_for_the_domain_is_an_abort_with_its_code_and_exit_1() {
    let bench = sim_bench();
    let scratch = Scratch::new("sdo-file-abort");
    let (image, out) = (scratch.path("image.bin"), scratch.path("out.bin"));
    std::fs::write(&image, pattern(64 * 1024 + 1)).unwrap();
    for extra in [&[][..], &["--segmented"]] {
        let write = edsgen(
            &bench,
            &[
                &["sdo", "write", "4", "2001:0", "--file", &image][..],
                extra,
            ]
            .concat(),
        );
        assert_eq!(write.status.code(), Some(1), "{extra:?}");
        assert_eq!(
            stderr(&write),
            "error: SDO 2001h:00h on node 4: node aborted with 0607 0012h (data type does not match, length of service parameter too high)\n",
            "{extra:?}"
        );
    }
    // A read the node refuses leaves no file behind.
    let read = edsgen(&bench, &["sdo", "read", "4", "5FFF:0", "--out", &out]);
    assert_eq!(read.status.code(), Some(1));
    assert_eq!(
        stderr(&read),
        "error: SDO 5FFFh:00h on node 4: node aborted with 0602 0000h (object does not exist in the object dictionary)\n"
    );
    assert!(!Path::new(&out).exists());
}

/// A device whose SDO server stops answering properly after `left` responses: the next one is
/// an abort 0800 0000h (general error), as from a node that fails in the middle of an upload.
struct AbortsMidway<D>(D, usize);

impl<D: BusDevice> BusDevice for AbortsMidway<D> {
    fn handle_frame(&mut self, now: Instant, frame: &CanFrame) {
        self.0.handle_frame(now, frame);
    }
    fn poll_transmit(&mut self, now: Instant) -> Option<CanFrame> {
        let frame = self.0.poll_transmit(now)?;
        if frame.std_id() != Some(0x584) {
            return Some(frame);
        }
        if self.1 == 0 {
            let abort = [0x80, 0x01, 0x20, 0x00, 0x00, 0x00, 0x00, 0x08];
            return Some(CanFrame::new(0x584, &abort).unwrap());
        }
        self.1 -= 1;
        Some(frame)
    }
    fn poll_timeout(&self) -> Option<Instant> {
        self.0.poll_timeout()
    }
    fn handle_timeout(&mut self, now: Instant) {
        self.0.handle_timeout(now)
    }
}

#[test]
fn an_upload_that_fails_midway_leaves_the_out_file_as_it_was_and_no_partial_file() {
    let hub = Hub::start("127.0.0.1:0", HubOptions::default()).unwrap();
    let addr = hub.local_addr().to_string();
    let node = spawn_node(&addr, |clock| {
        let mut od = RuntimeDictionary::new(&sim_support::test_device(), 4);
        edsgen_runtime::ObjectDictionary::write(&mut od, 0x2001, 0, &pattern(3000)).unwrap();
        // The initiate response and 4 segments (28 bytes), then the abort.
        AbortsMidway(Node::new(od, 4, clock.now()).unwrap(), 5)
    });
    let bench = Bench {
        hub: Some(hub),
        nodes: vec![Box::new(move || drop(node.stop()))],
        addr,
    };
    let scratch = Scratch::new("sdo-out-midway");
    let (out, fresh) = (scratch.path("out.bin"), scratch.path("fresh.bin"));
    std::fs::write(&out, b"the value read before").unwrap();
    for path in [&out, &fresh] {
        let read = edsgen(
            &bench,
            &["sdo", "read", "4", "2001:0", "--out", path, "--segmented"],
        );
        assert_eq!(read.status.code(), Some(1));
        assert_eq!(
            stderr(&read),
            "error: SDO 2001h:00h on node 4: node aborted with 0800 0000h (general error)\n"
        );
        assert!(!Path::new(&format!("{path}.partial")).exists());
    }
    assert_eq!(std::fs::read(&out).unwrap(), b"the value read before");
    assert!(!Path::new(&fresh).exists());
}

#[test]
fn file_transfer_usage_errors_exit_2_with_their_messages() {
    let bench = sim_bench();
    let scratch = Scratch::new("sdo-file-usage");
    let (image, sim) = (scratch.path("image.bin"), scratch.path("sim.eds"));
    std::fs::write(&image, [1, 2, 3]).unwrap();
    let (missing, dir, nowhere) = (
        scratch.path("missing.bin"),
        scratch.path(""),
        scratch.path("no/such.bin"),
    );
    let cases: [(Vec<&str>, String); 8] = [
        (
            vec!["sdo", "write", "4", "2001:0", "01 02", "--file", &image],
            "error: the argument '[VALUE]' cannot be used with '--file <PATH>'".into(),
        ),
        (
            vec!["sdo", "write", "4", "2001:0"],
            "error: the following required arguments were not provided:".into(),
        ),
        (
            vec!["sdo", "write", "4", "2001:0", "--file", &missing],
            format!("error: cannot read `{missing}`: No such file or directory (os error 2)"),
        ),
        (
            vec!["sdo", "write", "4", "2001:0", "--file", &dir],
            format!("error: cannot read `{dir}`: it is a directory"),
        ),
        (
            vec!["sdo", "read", "4", "2001:0", "--out", &nowhere],
            format!("error: cannot write `{nowhere}`: No such file or directory (os error 2)"),
        ),
        (
            vec!["sdo", "write", "--eds", &sim, "4", "2002:0", "--file", &image],
            "error: 2002h:00h Target speed is UNSIGNED16: a file goes only to or from a DOMAIN, a string or an octet string".into(),
        ),
        (
            vec!["sdo", "read", "4", "2001:0", "--segmented"],
            "error: the following required arguments were not provided:".into(),
        ),
        (
            vec!["sdo", "write", "4", "2001:0", "--file", &image, "--segmented", "--block"],
            "error: the argument '--segmented' cannot be used with '--block'".into(),
        ),
    ];
    for (args, message) in cases {
        let output = edsgen(&bench, &args);
        assert_eq!(output.status.code(), Some(2), "{args:?}");
        assert_eq!(
            stderr(&output).lines().next(),
            Some(message.as_str()),
            "{args:?}: {}",
            stderr(&output)
        );
    }
}
