//! The demo over a real wire (root only: a visible skip otherwise, a failure under `CI=true`):
//! the [`edsgen_demo::netns`] guard makes namespaces, veth pairs and addresses, runs programs inside
//! and leaves nothing behind, also when the code using it panics.

mod process_support;

use std::process::{Command, Stdio};
use std::time::Duration;

use edsgen_demo::netns::{is_root, End, Network};
use process_support::skip;

/// The output of `ip ARGS` (empty when `ip` fails).
fn ip(args: &[&str]) -> String {
    Command::new("ip")
        .args(args)
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).into_owned())
        .unwrap_or_default()
}

/// Whether the host has a link of that name.
fn host_link(name: &str) -> bool {
    Command::new("ip")
        .args(["link", "show", name])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

fn namespaces() -> String {
    ip(&["netns", "list"])
}

#[test]
fn a_network_is_made_used_and_removed_without_a_trace() {
    if !is_root() {
        skip::<()>("not root: no network namespaces for the netns guard test");
        return;
    }
    let (names, links, pid);
    {
        let mut net = Network::create("t-netns", 2).expect("two namespaces");
        names = net.namespaces().to_vec();
        assert_eq!(names.len(), 2);
        let me = std::process::id();
        assert!(names[0].starts_with(&format!("edsgen-t-netns-{me}-")));
        let listed = namespaces();
        assert!(
            names.iter().all(|n| listed.contains(n.as_str())),
            "{listed}"
        );
        let (a, b) = net
            .veth(End::Namespace(0), End::Namespace(1))
            .expect("a veth pair between the namespaces");
        let (host, inside) = net
            .veth(End::Host, End::Namespace(0))
            .expect("a veth pair from the host");
        assert!(a.starts_with(&format!("tne{me}a")), "{a}");
        assert!(host_link(&host) && !host_link(&a) && !host_link(&b));
        net.address(0, &a, "10.233.0.1/24").expect("an address");
        net.address(1, &b, "10.233.0.2/24").expect("an address");
        let shown = ip(&["-n", &names[0], "-o", "addr", "show", "dev", &a]);
        assert!(shown.contains("inet 10.233.0.1/24"), "{shown}");
        let shown = ip(&["-n", &names[0], "-o", "link", "show", "dev", &inside]);
        assert!(shown.contains("state UP"), "{shown}");
        // A program inside namespace 1 sees its end and address, not the host's links.
        let mut command = net.command(1, "ip").expect("namespace 1");
        command.args(["-o", "addr", "show"]).stdout(Stdio::piped());
        let id = net.spawn(&mut command).expect("ip inside");
        let stdout = net.child(id).and_then(|c| c.stdout.take()).expect("stdout");
        let status = net.wait(id, Duration::from_secs(10)).expect("ip exits");
        assert!(status.success());
        let text = std::io::read_to_string(stdout).expect("its output");
        assert!(
            text.contains(&format!("{b}    inet 10.233.0.2/24")),
            "{text}"
        );
        assert!(!text.contains(&host), "{text}");
        // A long-running one is stopped on drop.
        let mut command = net.command(0, "sleep").expect("namespace 0");
        command.arg("600");
        let id = net.spawn(&mut command).expect("sleep inside");
        pid = net.child(id).expect("running").id();
        links = vec![host];
    }
    let listed = namespaces();
    assert!(
        names.iter().all(|n| !listed.contains(n.as_str())),
        "{listed}"
    );
    assert!(!host_link(&links[0]));
    assert!(!std::path::Path::new(&format!("/proc/{pid}")).exists());
}

#[test]
fn a_network_is_removed_when_its_user_panics() {
    if !is_root() {
        skip::<()>("not root: no network namespaces for the netns guard test");
        return;
    }
    let made = std::sync::Mutex::new(None);
    let result = std::panic::catch_unwind(|| {
        let mut net = Network::create("t-panic", 1).expect("a namespace");
        let (host, _) = net.veth(End::Host, End::Namespace(0)).expect("a pair");
        *made.lock().expect("not poisoned") = Some((net.namespaces()[0].clone(), host));
        panic!("the user of the network fails");
    });
    assert!(result.is_err());
    let (name, host) = made.into_inner().expect("not poisoned").expect("made");
    assert!(!namespaces().contains(&name));
    assert!(!host_link(&host));
}

/// `edsgen demo ARGS` as run by this test: its exit code, standard output and error, and the
/// namespaces and links it left behind (those named with its process ID).
#[derive(Debug)]
struct Demo {
    code: Option<i32>,
    stdout: String,
    stderr: String,
    left: Vec<String>,
}

fn demo(args: &[&str]) -> Demo {
    let mut command = Command::new(process_support::EDSGEN);
    command.arg("demo").args(args);
    run(&mut command, |_| {})
}

/// Runs `edsgen demo ARGS`, asserting that all its `total` steps passed and that it left
/// nothing behind.
fn demo_passing(args: &[&str], total: usize) -> Demo {
    let run = demo(args);
    assert_eq!(run.code, Some(0), "{}\n{}", run.stdout, run.stderr);
    let summary = format!("\n{total} step(s): {total} as the manuals say, 0 not\n");
    assert!(run.stdout.ends_with(&summary), "{}", run.stdout);
    assert!(run.left.is_empty(), "left behind: {:?}", run.left);
    run
}

/// Runs `command` (an `edsgen demo`), `meanwhile` given its process ID; see [`Demo`].
fn run(command: &mut Command, meanwhile: impl FnOnce(u32)) -> Demo {
    let child = command
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("edsgen demo runs");
    let pid = child.id();
    meanwhile(pid);
    let output = child.wait_with_output().expect("edsgen demo ends");
    let mut left: Vec<String> = namespaces()
        .lines()
        .filter(|l| l.contains(&format!("-{pid}-")))
        .map(str::to_owned)
        .collect();
    left.extend(
        ip(&["-o", "link", "show"])
            .lines()
            .filter(|l| l.contains(&pid.to_string()))
            .map(str::to_owned),
    );
    Demo {
        code: output.status.code(),
        stdout: String::from_utf8_lossy(&output.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&output.stderr).into_owned(),
        left,
    }
}

/// The step lines (`ok` or `FAIL`) of the section whose heading starts with `heading`.
fn section_steps<'a>(stdout: &'a str, heading: &str) -> Vec<&'a str> {
    stdout
        .lines()
        .skip_while(|l| !l.starts_with(heading))
        .skip(1)
        .take_while(|l| !l.starts_with("== "))
        .filter(|l| l.starts_with("  ok ") || l.starts_with("  FAIL "))
        .collect()
}

/// Root and ethercrab: the EC-TX508 over a veth pair, driven by ethercrab, every step as the
/// in-process run's plus discovery, SDO and Op; nothing left behind.
#[cfg(feature = "ethercrab")]
#[test]
fn demo_ethercat_drives_the_ec_tx508_over_a_veth_pair() {
    if !is_root() {
        skip::<()>("not root: no network namespace for edsgen demo --ethercat");
        return;
    }
    let run = demo_passing(&["--ethercat"], 62);
    let steps = section_steps(&run.stdout, "== EC-TX508 (EtherCAT over a veth pair");
    let names: Vec<&str> = steps
        .iter()
        .map(|l| l[8..].split(": ").next().unwrap_or_default())
        .collect();
    assert_eq!(
        names,
        [
            "discovery",
            "6060h = 9 by CoE SDO in Pre-Op, read back (typed od::OPERATION_MODE)",
            "Pre-Op → Safe-Op → Op",
            "6060h = 9",
            "operation enabled by 06h, 07h, 0Fh",
            "60FFh = 300",
            "606Ch follows the target on its ramp to 300 rpm, 6041h bit 10 target reached",
            "a drive fault",
            "a fault reset by a rising edge of bit 7, every other cycle until the cause is gone",
            "operation enabled again by 06h, 07h, 0Fh",
            "shut down by 00h (disable voltage)",
        ]
    );
    for line in [
        "  ok    discovery: the EC-TX508 by its identity and its SII name: 1 SubDevice, vendor \
         0x4d8, product 0x9252, revision 1, \"EC-TX508\"",
        "  ok    6060h = 9 by CoE SDO in Pre-Op, read back (typed od::OPERATION_MODE): 9",
        "  ok    Pre-Op → Safe-Op → Op: the 21-byte outputs (1600h), the 23-byte inputs \
         (1A00h): (21, 23)",
        "  ok    606Ch follows the target on its ramp to 300 rpm, 6041h bit 10 target reached: \
         (300, true)",
    ] {
        assert!(run.stdout.contains(line), "{line}\n{}", run.stdout);
    }
    // Each controlword sent until its effect shows (a cycle later on the wire).
    assert!(
        run.stdout
            .contains("  ok    operation enabled by 06h, 07h, 0Fh: 06h, 06h, 07h, 07h, 0Fh, 0Fh\n"),
        "{}",
        run.stdout
    );
    // The fault went in and out through the simulator's standard input; it stopped on SIGTERM.
    for said in [
        "  simulator: drive fault raised at ",
        "  simulator: drive fault cause removed at ",
        "  simulator: stopped: ",
    ] {
        assert!(run.stdout.contains(said), "{said}\n{}", run.stdout);
    }
    // The other sections as in the plain run.
    assert!(run.stdout.contains("\n== Goodrive350 EtherNet/IP card"));
}

/// Without the `ethercrab` feature: `--ethercat` says so and the EC-TX508 runs in this process.
#[cfg(not(feature = "ethercrab"))]
#[test]
fn demo_ethercat_without_ethercrab_says_so_and_runs_in_process() {
    let run = demo(&["--ethercat"]);
    assert_eq!(run.code, Some(0), "{}\n{}", run.stdout, run.stderr);
    assert_eq!(
        run.stderr,
        "demo --ethercat needs edsgen built with the `ethercrab` feature (cargo build \
         --features ethercrab); the EC-TX508 runs in this process instead\n"
    );
    assert!(run
        .stdout
        .contains("\n== EC-TX508 (EtherCAT, simulated in this process)"));
    assert!(run
        .stdout
        .ends_with("\n59 step(s): 59 as the manuals say, 0 not\n"));
    assert!(run.left.is_empty(), "left behind: {:?}", run.left);
}

/// `--faults-on-stdin` switches the EC-TX508's drive faults; with an ESI file it is a usage
/// error (exit 2), before any interface is opened.
#[test]
fn simulate_faults_on_stdin_is_for_the_ec_tx508_card() {
    let output = Command::new(process_support::EDSGEN)
        .args([
            "simulate",
            "--ethercat",
            "nonexistent0",
            "--faults-on-stdin",
        ])
        .arg(process_support::root().join("eds/ec-tx508.xml"))
        .output()
        .expect("edsgen simulate runs");
    assert_eq!(output.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&output.stderr),
        "error: --faults-on-stdin switches the faults of --card ec-tx508's drive\n"
    );
}

/// Root: the EtherNet/IP card between two namespaces, the adapter in one, the demo's scanner in
/// the other, every step as in the in-process run; nothing left behind.
#[test]
fn demo_enip_drives_the_card_between_two_namespaces() {
    if !is_root() {
        skip::<()>("not root: no network namespaces for edsgen demo --enip");
        return;
    }
    let run = demo_passing(&["--enip"], 59);
    let steps = section_steps(
        &run.stdout,
        "== Goodrive350 EtherNet/IP card: a class-1 scanner from the generated images, over TCP \
         44818 and UDP 2222 between two network namespaces",
    );
    assert_eq!(steps.len(), 8, "{}", run.stdout);
    assert_eq!(
        steps[..6],
        [
            "  ok    RegisterSession, Identity product code (@1/1/3): session 1, product code 350",
            "  ok    Forward_Open 150 -> 100 at 50 ms (EXCLUSIVE_OWNER): reply [D4, 00, 00, 00, \
             01, 00, 00, 10]",
            "  ok    PKW write P16.32 = 1 (received PZD2: set frequency): Word { address: 4128, \
             value: 1 }",
            "  ok    PKW write P16.43 = 1 (transmitted PZD2: running frequency): Word { address: \
             4139, value: 1 }",
            "  ok    PKW read P00.10 (keypad frequency): Word { address: 10, value: 5000 }: 50.00 \
             Hz",
            "  ok    PKW write P07.27 refused (read only, error 7): Refused { address: 1819, \
             error: ReadOnly }",
        ]
    );
    // In real time: the ramp where it is after 41 RPIs of about 50 ms.
    assert!(
        steps[6].starts_with(
            "  ok    run forward at 25.00 Hz (CW 0x0001, PZD2 2500): SW 0x4101, transmitted PZD2 "
        ),
        "{}",
        steps[6]
    );
    // The connection closed by the adapter (its T→O datagrams stop), the fault read back by
    // explicit messaging; the adapter's own log says the same.
    assert!(
        steps[7].starts_with(
            "  ok    scanner stops producing: timeout after 4 x RPI, fault E-EIP: the adapter's \
             T→O datagrams stopped "
        ) && steps[7].ends_with(" ms after the scanner's last O→T; SW state Some(Fault)"),
        "{}",
        steps[7]
    );
    assert!(
        run.stdout.contains(
            "\n  adapter: connection 0x10000001 opened\n  adapter: connection 0x10000001 timed \
             out\n  adapter: drive fault E-EIP\n"
        ),
        "{}",
        run.stdout
    );
}

/// Root: Ctrl-C while the demo runs `flag` over a wire (namespaces tagged `tag`) removes its
/// namespaces and pair, stops the programs in them, and exits 130.
fn interrupted_on_the_wire(flag: &str, tag: &str) {
    let mut command = Command::new(process_support::EDSGEN);
    command.args(["demo", flag]);
    let run = run(&mut command, |pid| {
        // Once a program runs in each of its two namespaces (the card, then the other end),
        // SIGINT.
        let started = std::time::Instant::now();
        let both_running = || {
            let listed = namespaces();
            let mine: Vec<&str> = listed
                .lines()
                .filter_map(|l| l.split_whitespace().next())
                .filter(|n| n.starts_with(&format!("edsgen-{tag}-{pid}-")))
                .collect();
            mine.len() == 2
                && mine
                    .iter()
                    .all(|n| !ip(&["netns", "pids", n]).trim().is_empty())
        };
        while started.elapsed() < Duration::from_secs(30) && !both_running() {
            std::thread::sleep(Duration::from_millis(20));
        }
        let sent = Command::new("kill")
            .args(["-INT", &pid.to_string()])
            .status()
            .expect("kill");
        assert!(sent.success());
    });
    assert_eq!(run.code, Some(130), "{run:?}");
    assert_eq!(run.stderr, "interrupted: network namespaces removed\n");
    assert!(run.left.is_empty(), "left behind: {:?}", run.left);
}

/// Root: Ctrl-C during `demo --enip`: nothing left behind, exit 130.
#[test]
fn demo_interrupted_on_the_wire_leaves_nothing_behind() {
    if !is_root() {
        skip::<()>("not root: no network namespaces for edsgen demo --enip");
        return;
    }
    interrupted_on_the_wire("--enip", "enip");
}

/// Root: Ctrl-C during `demo --profinet`: nothing left behind, exit 130.
#[test]
fn demo_profinet_interrupted_leaves_nothing_behind() {
    if !is_root() {
        skip::<()>("not root: no network namespaces for edsgen demo --profinet");
        return;
    }
    interrupted_on_the_wire("--profinet", "pn");
}

/// Root: the PROFINET card between two namespaces, `edsgen simulate --profinet` in one, the
/// demo's controller in the other, every step as in the in-process run (the ramp and the
/// watchdog in real time), together with `--enip` (and `--ethercat` where edsgen has
/// ethercrab); nothing left behind.
#[test]
fn demo_profinet_drives_the_card_between_two_namespaces() {
    if !is_root() {
        skip::<()>("not root: no network namespaces for edsgen demo --profinet");
        return;
    }
    let mut args = vec!["--enip", "--profinet"];
    let total = if cfg!(feature = "ethercrab") {
        args.push("--ethercat");
        62
    } else {
        59
    };
    let run = demo_passing(&args, total);
    if cfg!(feature = "ethercrab") {
        assert!(run
            .stdout
            .contains("\n== EC-TX508 (EtherCAT over a veth pair"));
    }
    assert!(run.stdout.contains(
        "\n== Goodrive350 EtherNet/IP card: a class-1 scanner from the generated images, over \
         TCP 44818 and UDP 2222 between two network namespaces\n"
    ));
    let heading = "== Goodrive350 PROFINET card: DCP, an AR over RPC on UDP 34964, RT_CLASS_1 \
                   frames every 4 ms, between two network namespaces";
    let steps = section_steps(&run.stdout, heading);
    assert_eq!(steps.len(), 9, "{}", run.stdout);
    assert_eq!(
        steps[..3],
        [
            "  ok    DCP Identify all: the card answers with its GSDML's name and IDs: \
             (\"goodrive350-pn\", (848, 848))",
            "  ok    DCP Set name of station `gd350-line-1`, then Identify by that name: \
             (Some(0), true)",
            "  ok    RPC Connect (IOCRs, AlarmCR, expected submodules), PrmEnd, \
             ApplicationReady: ((49153, 49410), [\"Connected\", \"PrmEnd\", \"DataStart\"])",
        ]
    );
    // In real time: P00.11's 10.0 s to 50.00 Hz, in as many cycles as the clock allowed.
    let ramp = steps[3]
        .strip_prefix(
            "  ok    CW 1 (run forward) and PZD2 5000: the drive ramps to 50.00 Hz: (1, 5000) \
             after ",
        )
        .unwrap_or_else(|| panic!("{}", steps[3]));
    let ms: u64 = ramp
        .rsplit_once(" cycles (")
        .and_then(|(_, ms)| ms.strip_suffix(" ms)"))
        .and_then(|ms| ms.parse().ok())
        .unwrap_or_else(|| panic!("{ramp}"));
    assert!((9_900..=12_000).contains(&ms), "{ramp}");
    assert_eq!(
        steps[4..6],
        [
            "  ok    PKW read of P00.11 (acceleration time): Word { address: 11, value: 100 }",
            "  ok    PKW write without CW bit 8 (enable writing): refused: Refused { address: \
             11, error: InvalidCommand }",
        ]
    );
    assert!(
        steps[6].starts_with("  ok    CW 5 (stop): the drive decelerates and stops: 0 after "),
        "{}",
        steps[6]
    );
    assert_eq!(
        steps[7],
        "  ok    RPC Release: the AR ends and the card stops sending: (true, [\"Released\"], \
         true)"
    );
    // The watchdog of 100 × 4 ms, seen at the card's last input frame; E-PN read back by PKW
    // in a third AR.
    let watchdog = steps[8]
        .strip_prefix(
            "  ok    the controller stops sending: watchdog, E-PN (fault 57), the AR aborted: \
             (Some(57), true, true); the card's input frames stopped ",
        )
        .and_then(|s| {
            s.strip_suffix(" ms after the controller's last output frame (watchdog 100 × 4 ms)")
        })
        .and_then(|ms| ms.parse::<u64>().ok())
        .unwrap_or_else(|| panic!("{}", steps[8]));
    assert!((360..=600).contains(&watchdog), "{}", steps[8]);
    // The card's own log: the name set, three ARs, the second aborted by its watchdog, and its
    // clean stop when the demo ends it with SIGTERM.
    let said: Vec<&str> = run
        .stdout
        .lines()
        .filter_map(|l| l.strip_prefix("  device: "))
        .filter(|l| !l.starts_with("PROFINET device") && !l.starts_with("RPC on"))
        .collect();
    let ar = |end| {
        [
            "AR connected (ARType 0x0001): input FrameID 0xc001, output FrameID 0xc102, every \
             4000 us",
            "PrmEnd: ApplicationReady sent",
            "ApplicationReady confirmed: cyclic data exchange",
            end,
        ]
    };
    let mut expected = vec!["name of station set to `gd350-line-1`"];
    expected.extend(ar("AR released"));
    expected.extend(ar("AR aborted"));
    expected.extend(ar("AR released"));
    expected.push("stopped: 3 ARs connected");
    assert_eq!(said, expected, "{}", run.stdout);
}

/// Root: the bundled cards as one machine (`demo --machine`): `edsgen simulate --machine` in a
/// namespace, each bus driven from the far side of its wire, the EC-TX508's fault through the
/// machine's standard input by name, SIGTERM stopping every bus; nothing left behind.
#[test]
fn demo_machine_drives_every_bus_of_one_machine() {
    if !is_root() {
        skip::<()>("not root: no network namespaces for edsgen demo --machine");
        return;
    }
    let ethercrab = cfg!(feature = "ethercrab");
    let run = demo_passing(&["--machine"], if ethercrab { 62 } else { 59 });
    for heading in [
        "\n== the bundled cards as one machine: `edsgen simulate --machine` in a network \
         namespace, each bus driven from the far side of its wire\n",
        "\n== CP301 and Goodrive350 on the machine's CANopen bus, from its namespace\n",
        "\n== Goodrive350 EtherNet/IP card on the machine, from the masters' namespace\n",
        "\n== Goodrive350 PROFINET card on the machine, from the masters' namespace\n",
        "\n== what the machine said\n",
        "\n== Goodrive350 DP card (station 2) on the machine's PROFIBUS line: profirust's master \
         on /dev/pts/",
    ] {
        assert!(run.stdout.contains(heading), "{heading}\n{}", run.stdout);
    }
    for line in [
        "  machine.toml: devices = [\"cp301@2\", \"goodrive350@3\"]\n",
        "  ok    6044h at 1.1 s: 1500 rpm: 1500\n",
        "  ok    fault OUT1 injected, and its reset: not run: the drive is not in this process\n",
        "  ok    SIGTERM stops the machine: every bus, then `stopped: machine`: exit status: 0\n",
        "  machine: [enip 192.168.250.1] drive fault E-EIP\n",
        "  machine: [canopen bus 127.0.0.1:29536] edsgen simulate: stopped 2 node(s)\n",
    ] {
        assert!(run.stdout.contains(line), "{line}\n{}", run.stdout);
    }
    for said in [
        "] name of station set to `gd350-line-1`\n",
        "] wait for parameters (the watchdog expired: E-DP)\n",
    ] {
        assert!(run.stdout.contains(said), "{said}\n{}", run.stdout);
    }
    assert!(
        run.stdout.contains(
            "  ok    the master falls silent: the card's DP watchdog (200 ms) ends data exchange, \
             Slave_Diag says station not ready and asks for parameters (Prm_Req): diagnosis 02 05 \
             00 FF 03 50\n"
        ),
        "{}",
        run.stdout
    );
    if ethercrab {
        assert!(
            run.stdout
                .contains("\n== EC-TX508 on the machine's EtherCAT link: ethercrab on "),
            "{}",
            run.stdout
        );
        for said in [
            "] drive fault raised at ",
            "] drive fault cause removed at ",
        ] {
            assert!(run.stdout.contains(said), "{said}\n{}", run.stdout);
        }
    } else {
        assert!(
            run.stderr.contains(
                "demo --machine drives the EC-TX508 with ethercrab, which needs edsgen built \
                 with the `ethercrab` feature"
            ),
            "{}",
            run.stderr
        );
    }
}

/// edsgen as an unprivileged user: itself when the test is not root, else as `nobody` through
/// setpriv (`None` where setpriv cannot run it so).
fn as_nobody() -> Option<Command> {
    if !is_root() {
        return Some(Command::new(process_support::EDSGEN));
    }
    let nobody = ["--reuid=65534", "--regid=65534", "--clear-groups"];
    let nobody_can_run = Command::new("setpriv")
        .args(nobody)
        .args(["test", "-x"])
        .arg(process_support::EDSGEN)
        .status()
        .is_ok_and(|s| s.success());
    if !nobody_can_run {
        return None;
    }
    let mut command = Command::new("setpriv");
    command.args(nobody).arg(process_support::EDSGEN);
    Some(command)
}

/// Not root (here as `nobody` through setpriv when the test runs as root): `--ethercat`,
/// `--enip` and `--profinet` say so on stderr, and every section runs in this process as
/// without them.
#[test]
fn demo_on_the_wire_without_root_says_so_and_runs_in_process() {
    let Some(mut command) = as_nobody() else {
        // Root runs the wire tests above; this one needs an unprivileged user.
        println!("demo_on_the_wire_without_root: setpriv cannot run edsgen as nobody here");
        return;
    };
    command.args(["demo", "--ethercat", "--enip", "--profinet"]);
    let run = run(&mut command, |_| {});
    assert_eq!(run.code, Some(0), "{run:?}");
    let ethercat = if cfg!(feature = "ethercrab") {
        "demo --ethercat needs root (for network namespaces and a veth pair)"
    } else {
        "demo --ethercat needs edsgen built with the `ethercrab` feature (cargo build \
         --features ethercrab)"
    };
    assert_eq!(
        run.stderr,
        format!(
            "{ethercat}; the EC-TX508 runs in this process instead\n\
             demo --enip needs root (for network namespaces and a veth pair); the EtherNet/IP \
             card runs in this process instead\n\
             demo --profinet needs root (for network namespaces and a veth pair); the PROFINET \
             card runs in this process instead\n"
        )
    );
    assert!(run
        .stdout
        .contains("\n== EC-TX508 (EtherCAT, simulated in this process)"));
    assert!(run.stdout.contains(
        "\n== Goodrive350 EtherNet/IP card: a class-1 scanner from the generated images\n"
    ));
    assert!(run.stdout.contains(
        "\n== Goodrive350 PROFINET card (simulated in this process): DCP, an AR over RPC, \
         RT_CLASS_1 frames every 4 ms\n"
    ));
    assert!(run
        .stdout
        .ends_with("\n59 step(s): 59 as the manuals say, 0 not\n"));
}

/// Not root, `--machine`: said on stderr, and the whole demo runs in this process.
#[test]
fn demo_machine_without_root_says_so_and_runs_in_process() {
    let Some(mut command) = as_nobody() else {
        println!("demo_machine_without_root: setpriv cannot run edsgen as nobody here");
        return;
    };
    command.args(["demo", "--machine"]);
    let run = run(&mut command, |_| {});
    assert_eq!(run.code, Some(0), "{run:?}");
    assert_eq!(
        run.stderr,
        "demo --machine needs root (for network namespaces and a veth pair); every card runs in \
         this process instead\n"
    );
    assert!(run
        .stdout
        .ends_with("\n59 step(s): 59 as the manuals say, 0 not\n"));
}
