//! Discovery at the bench: two simulated adapters (`edsgen simulate --enip ADDR FILE.eds`, each
//! bound to its own unicast address) in one private network namespace, `edsgen enip list` in
//! another, joined by a veth pair, neither with a default route. A directed broadcast finds both,
//! each answering with its own address; the limited broadcast without a route is a clear error
//! (exit 2) until `--from` names the address to send from. Needs root: outside root the test
//! says so and passes; under `CI=true` it fails instead.

mod process_support;

use std::process::Command;
use std::time::Duration;

use process_support::netns::{is_root, VethPair};
use process_support::{skip, Process, EDSGEN};

/// `edsgen enip list ARGS` in the scanner's namespace: exit code, stdout lines sorted, stderr.
fn list(ns: &VethPair, args: &[&str]) -> (Option<i32>, Vec<String>, String) {
    let out = Command::new("ip")
        .args(["netns", "exec", ns.master(), EDSGEN, "enip", "list"])
        .args(args)
        .current_dir(process_support::root())
        .output()
        .expect("edsgen runs");
    let mut lines: Vec<String> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(str::to_owned)
        .collect();
    lines.sort();
    (
        out.status.code(),
        lines,
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn a_broadcast_finds_every_adapter_by_its_own_address() {
    if !is_root() {
        skip::<()>("not root: no network namespaces for the discovery test");
        return;
    }
    let ns = VethPair::new(
        "ed",
        &["10.232.0.1/24", "10.232.0.3/24"],
        &["10.232.0.2/24"],
    );
    let adapters: Vec<Process> = ["10.232.0.1", "10.232.0.3"]
        .iter()
        .map(|address| {
            let adapter = Process::start(
                Command::new("ip")
                    .current_dir(process_support::root())
                    .args([
                        "netns",
                        "exec",
                        ns.devices(),
                        EDSGEN,
                        "simulate",
                        "--enip",
                        address,
                        "codegen/tests/odva/io.eds",
                    ]),
            );
            adapter.stderr_line(|l| l.starts_with("serving"), Duration::from_secs(10));
            adapter
        })
        .collect();
    let (code, found, stderr) = list(&ns, &["10.232.0.255"]);
    assert_eq!(code, Some(0), "{stderr}");
    let addresses: Vec<&str> = found
        .iter()
        .map(|l| l.split('\t').next().unwrap_or(""))
        .collect();
    assert_eq!(addresses, ["10.232.0.1", "10.232.0.3"], "{found:?}");
    assert_eq!(
        stderr,
        "listening 1.5 s for ListIdentity answers from 10.232.0.255:44818 (maximum delay 1000 \
         ms)\n"
    );
    // No default route: the limited broadcast cannot leave without --from.
    let (code, lines, stderr) = list(&ns, &[]);
    assert_eq!((code, lines.len()), (Some(2), 0));
    assert_eq!(
        stderr,
        "error: cannot send to 255.255.255.255:44818: Network is unreachable (os error 101); \
         with no default route, name an address of the interface to send from with --from ADDR\n"
    );
    // With --from the limited broadcast finds the same two.
    let (code, with_from, _) = list(&ns, &["--from", "10.232.0.2"]);
    assert_eq!((code, with_from), (Some(0), found));
    drop(adapters);
}
