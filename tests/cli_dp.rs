//! `edsgen simulate --profibus TTY` against a third-party DP master: pyprofibus 1.13 (its DPM1
//! with the serial PHY, pinned in scripts/python-venv.sh) on the other end of a pseudo-terminal
//! pair (`scripts/dp_master.py`), configured from the card's GSD (and from the same file given
//! as FILE.gsd): data exchange reached, a PKW read (§2.6 example 1) and a run command through
//! it. Without the venv the test is skipped (`process_support`); under `CI=true` it fails.

mod process_support;

use std::time::Duration;

use process_support::{python, Process};

const WAIT: Duration = Duration::from_secs(20);

/// Runs the master against `edsgen simulate --profibus PTY` with `slave_args`; the simulator's
/// stderr lines up to data exchange and the master's step lines.
fn exchange(slave_args: &[&str], master_args: &[&str]) -> Option<Vec<String>> {
    let python = python()?;
    let master = Process::python(&python, "scripts/dp_master.py", master_args);
    let pty = master.stdout_line(|l| l.starts_with("PTY "), WAIT);
    let pty = pty.trim_start_matches("PTY ").to_owned();
    let mut args = vec!["simulate", "--profibus", pty.as_str()];
    args.extend_from_slice(slave_args);
    let slave = Process::edsgen(&args);
    slave.stderr_line(|l| l.starts_with("simulating DP slave"), WAIT);
    slave.stderr_line(|l| l == "data exchange", WAIT);
    let lines = vec![
        master.stdout_line(|l| l.starts_with("DATA_EXCHANGE"), WAIT),
        master.stdout_line(|l| l.starts_with("PKW_READ"), WAIT),
        master.stdout_line(|l| l.starts_with("RUN"), WAIT),
    ];
    let exited = master.finish(WAIT);
    assert_eq!(exited.code, Some(0), "{exited:?}");
    Some(lines)
}

#[test]
fn pyprofibus_exchanges_data_with_the_card() {
    let gsd = "eds/goodrive350-dp.gsd";
    let Some(lines) = exchange(&["--card", "goodrive350-dp"], &[gsd, "2"]) else {
        return;
    };
    assert_eq!(
        lines,
        [
            "DATA_EXCHANGE",
            // Response 1, address 10 (P00.10), value 5000 (the manual's "50 00"): 13 88h.
            "PKW_READ 0001000a00001388",
            // SW 4101h (forward, ready, communication control), PZD2 1000 (10.00 Hz).
            "RUN 410103e8",
        ]
    );
}

/// Any GSD file: the slave echoes its outputs (here the card's file read as FILE.gsd@5).
#[test]
fn pyprofibus_exchanges_data_with_a_slave_from_a_gsd_file() {
    let gsd = "eds/goodrive350-dp.gsd";
    let Some(lines) = exchange(&["eds/goodrive350-dp.gsd@5"], &[gsd, "5", "echo"]) else {
        return;
    };
    assert_eq!(
        lines,
        ["DATA_EXCHANGE", "PKW_READ 0001000a00000000", "RUN 000103e8",]
    );
}

#[test]
fn bad_usage_exits_2() {
    let exited = Process::edsgen(&[
        "simulate",
        "--profibus",
        "/nonexistent/tty",
        "--card",
        "goodrive350-dp",
    ])
    .finish(WAIT);
    assert_eq!(exited.code, Some(2));
    assert!(
        exited.stderr.contains("cannot open /nonexistent/tty"),
        "{exited:?}"
    );
    let exited =
        Process::edsgen(&["simulate", "--profibus", "/dev/null", "--card", "cp301"]).finish(WAIT);
    assert_eq!(exited.code, Some(2));
    assert!(exited.stderr.contains("no DP card `cp301`"), "{exited:?}");
    let exited = Process::edsgen(&[
        "simulate",
        "--profibus",
        "/dev/null",
        "--card",
        "goodrive350-dp@126",
    ])
    .finish(WAIT);
    assert_eq!(exited.code, Some(2));
    assert!(
        exited.stderr.contains("bad station address `126`"),
        "{exited:?}"
    );
    let exited = Process::edsgen(&[
        "simulate",
        "--profibus",
        "/dev/null",
        "--card",
        "goodrive350-dp@4",
        "eds/goodrive350-dp.gsd@4",
    ])
    .finish(WAIT);
    assert_eq!(exited.code, Some(2));
    assert_eq!(exited.stderr, "error: two slaves at station address 4\n");
    // A --module goes after the FILE it plugs: before any, or after a card, is refused.
    for args in [
        &["--module", "PPO 3", "eds/goodrive350-dp.gsd@4"][..],
        &[
            "eds/goodrive350-dp.gsd@4",
            "--card",
            "goodrive350-dp@3",
            "--module",
            "PPO 3",
        ][..],
    ] {
        let mut all = vec!["simulate", "--profibus", "/dev/null"];
        all.extend_from_slice(args);
        let exited = Process::edsgen(&all).finish(WAIT);
        assert_eq!(exited.code, Some(2), "{exited:?}");
        let first = exited.stderr.lines().next().unwrap_or_default().to_owned();
        let expected = if args[0] == "--module" {
            "error: --module `PPO 3` comes before any FILE: put it after the FILE it plugs"
        } else {
            "error: --module `PPO 3` follows a --card: a card's modules are its own; put --module after the FILE it plugs"
        };
        assert_eq!(first, expected);
    }
    // A module the GSD does not have, after its FILE: its name and the nearest.
    let exited = Process::edsgen(&[
        "simulate",
        "--profibus",
        "/dev/null",
        "eds/goodrive350-dp.gsd@4",
        "--module",
        "4 PKW + 2 PZD",
    ])
    .finish(WAIT);
    assert_eq!(exited.code, Some(2), "{exited:?}");
    assert!(
        exited.stderr.contains("no module \"4 PKW + 2 PZD\""),
        "{exited:?}"
    );
}

/// Three slaves on one line (issue 31), each at its own address: two cards and a slave from a
/// GSD file; pyprofibus exchanges data with all three.
#[test]
fn pyprofibus_exchanges_data_with_three_slaves_on_one_line() {
    let Some(python) = python() else { return };
    let gsd = "eds/goodrive350-dp.gsd";
    let master = Process::python(
        &python,
        "scripts/dp_master_many.py",
        &[gsd, "3:card", "4:card", "5:echo"],
    );
    let pty = master.stdout_line(|l| l.starts_with("PTY "), WAIT);
    let pty = pty.trim_start_matches("PTY ").to_owned();
    let slave = Process::edsgen(&[
        "simulate",
        "--profibus",
        &pty,
        "--card",
        "goodrive350-dp@3",
        "--card",
        "goodrive350-dp@4",
        "eds/goodrive350-dp.gsd@5",
    ]);
    let exited = master.finish(Duration::from_secs(40));
    assert_eq!(exited.code, Some(0), "{exited:?}");
    // The master gone, the line closes and the simulator ends.
    let served = slave.finish(WAIT);
    for address in [3, 4, 5] {
        let line = format!("station {address}: data exchange");
        assert!(served.stderr.lines().any(|l| l == line), "{served:?}");
    }
    assert_eq!(
        exited.stdout.lines().collect::<Vec<_>>(),
        [
            "OK 3 0001000a00001388",
            "OK 4 0001000a00001388",
            "OK 5 05a55a05"
        ]
    );
}

/// `edsgen dp scan` asks every address once, in the time it states first, and finds the
/// simulated card on the other end of a pseudo-terminal pair; with nobody there it exits 1.
#[test]
fn dp_scan_finds_the_simulated_card() {
    let Some(python) = python() else { return };
    let pair = Process::python(&python, "scripts/pty_pair.py", &[]);
    let line = pair.stdout_line(|l| l.starts_with("PTY "), WAIT);
    let ends: Vec<&str> = line.split(' ').skip(1).collect();
    let (a, b) = (ends[0].to_owned(), ends[1].to_owned());
    let empty = Process::edsgen(&["dp", "scan", &a]).finish(WAIT);
    assert_eq!(empty.code, Some(1), "{empty:?}");
    assert_eq!(
        empty.stderr,
        format!(
            "scanning addresses 0 to 125 on {a} at 19200 baud: 30 ms an address, 3.8 s\n\
             no DP slave answered on {a}\n"
        )
    );
    let slave = Process::edsgen(&["simulate", "--profibus", &b, "--card", "goodrive350-dp"]);
    slave.stderr_line(|l| l.starts_with("simulating DP slave 2"), WAIT);
    let scan = Process::edsgen(&["dp", "scan", &a]).finish(WAIT);
    assert_eq!(scan.code, Some(0), "{scan:?}");
    assert_eq!(scan.stdout, "station 2: Ident_Number 0350h, no master\n");
}

/// `edsgen dp io` brings the simulated card to data exchange from its GSD and overlay, sends a
/// PKW read of P00.10 by name and prints the inputs by name, the PKW response and status word
/// in words; a missing station and an Ident_Number mismatch are named at once.
#[test]
fn dp_io_reads_a_parameter_by_name() {
    let Some(python) = python() else { return };
    let pair = Process::python(&python, "scripts/pty_pair.py", &[]);
    let line = pair.stdout_line(|l| l.starts_with("PTY "), WAIT);
    let ends: Vec<&str> = line.split(' ').skip(1).collect();
    let (a, b) = (ends[0].to_owned(), ends[1].to_owned());
    let slave = Process::edsgen(&["simulate", "--profibus", &b, "--card", "goodrive350-dp"]);
    slave.stderr_line(|l| l.starts_with("simulating DP slave 2"), WAIT);
    let gsd = "eds/goodrive350-dp.gsd";
    let io = Process::edsgen(&[
        "dp",
        "io",
        &a,
        "--gsd",
        gsd,
        "--address",
        "2",
        "--cycles",
        "10",
        "pkw1=1",
        "pkw2=10",
    ])
    .finish(WAIT);
    assert_eq!(io.code, Some(0), "{io:?}");
    let mut expected = vec![
        "pkw1 = 1 (0x0001)",
        "pkw2 = 10 (0x000A)",
        "pkw3 = 0 (0x0000)",
        "pkw4 = 5000 (0x1388)",
        "sw = 16643 (0x4103)",
    ];
    let zeros: Vec<String> = (2..=12).map(|n| format!("pzd{n} = 0 (0x0000)")).collect();
    expected.extend(zeros.iter().map(String::as_str));
    expected.extend(["pkw: parameter P00.10 = 5000", "sw: stopped, ready"]);
    assert_eq!(io.stdout.lines().collect::<Vec<_>>(), expected);
    // On a loaded machine profirust may miss an answer; nothing else goes to stderr.
    let known = ["station 2: stopped answering", "station 2: answers again"];
    assert!(io.stderr.lines().all(|l| known.contains(&l)), "{io:?}");
    let bad =
        Process::edsgen(&["dp", "io", &a, "--gsd", gsd, "--address", "2", "nope=1"]).finish(WAIT);
    assert_eq!(bad.code, Some(2));
    assert_eq!(
        bad.stderr,
        "error: `nope=1`: no output `nope` (the outputs are pkw1, ... pzd12)\n"
    );
    let missing = Process::edsgen(&["dp", "io", &a, "--gsd", gsd, "--address", "3"]).finish(WAIT);
    assert_eq!(missing.code, Some(1));
    assert_eq!(
        missing.stderr,
        format!("station 3 does not answer on {a} (station missing)\n")
    );
    let other = std::env::temp_dir().join(format!("edsgen-dp-io-{}.gsd", std::process::id()));
    let text = std::fs::read_to_string(gsd).expect("the card's GSD");
    let text = text.replace(
        "Ident_Number        = 0x0350",
        "Ident_Number        = 0x0351",
    );
    std::fs::write(&other, text).expect("a temporary GSD");
    let other_path = other.to_string_lossy().into_owned();
    let mismatch =
        Process::edsgen(&["dp", "io", &a, "--gsd", &other_path, "--address", "2"]).finish(WAIT);
    let _ = std::fs::remove_file(&other);
    assert_eq!(mismatch.code, Some(1));
    assert_eq!(
        mismatch.stderr,
        "station 2 is Ident_Number 0350h, the GSD file's is 0351h (Ident_Number mismatch)\n"
    );
}

/// The card's manual workflow in one session: a session that ends leaves the watchdog to
/// expire, the drive trips E-DP (fault 29, P07.27 read through PKW); the next session resets the
/// fault and runs the drive from lines on standard input, and prints the ramp to 10.00 Hz.
#[test]
fn dp_io_resets_e_dp_and_runs_the_drive_in_one_session() {
    let Some(python) = python() else { return };
    let pair = Process::python(&python, "scripts/pty_pair.py", &[]);
    let line = pair.stdout_line(|l| l.starts_with("PTY "), WAIT);
    let ends: Vec<&str> = line.split(' ').skip(1).collect();
    let (a, b) = (ends[0].to_owned(), ends[1].to_owned());
    let slave = Process::edsgen(&["simulate", "--profibus", &b, "--card", "goodrive350-dp"]);
    slave.stderr_line(|l| l.starts_with("simulating DP slave 2"), WAIT);
    let gsd = "eds/goodrive350-dp.gsd";
    let args = ["dp", "io", &a, "--gsd", gsd, "--address", "2"];
    let first = Process::edsgen(&[&args[..], &["--cycles", "3"]].concat()).finish(WAIT);
    assert_eq!(first.code, Some(0), "{first:?}");
    slave.stderr_line(
        |l| l == "wait for parameters (the watchdog expired: E-DP)",
        WAIT,
    );
    let settings = ["--cycles", "40", "pkw1=1", "pkw2=0x071B", "pzd2=1000"];
    let mut session = Process::edsgen(&[&args[..], &settings].concat());
    session.send_line("reset");
    session.send_line("run");
    let done = session.finish(WAIT);
    assert_eq!(done.code, Some(0), "{done:?}");
    let lines: Vec<&str> = done.stdout.lines().collect();
    // Before the reset: P07.27 = 29 (E-DP), the SW's state 4 (fault).
    assert_eq!(lines[3..5], ["pkw4 = 29 (0x001D)", "sw = 16644 (0x4104)"]);
    assert!(lines.contains(&"pkw: parameter P07.27 = 29"), "{lines:?}");
    assert!(lines.contains(&"sw: fault, ready"), "{lines:?}");
    let stopped = lines.iter().position(|l| *l == "sw: stopped, ready");
    let running = lines
        .iter()
        .position(|l| *l == "sw: running forward, ready");
    assert!(stopped.is_some() && running > stopped, "{lines:?}");
    assert!(lines.contains(&"pzd2 = 1000 (0x03E8)"), "{lines:?}");
}

/// SIGINT and SIGTERM stop the simulated slave cleanly: exit 0 and a `stopped:` line, also
/// when it was started the way a script starts it in the background.
#[test]
fn the_simulated_slave_stops_on_sigint_and_sigterm() {
    let Some(python) = python() else { return };
    for signal in ["-INT", "-TERM"] {
        let pair = Process::python(&python, "scripts/pty_pair.py", &[]);
        let line = pair.stdout_line(|l| l.starts_with("PTY "), WAIT);
        let b = line.split(' ').nth(2).expect("two ends").to_owned();
        let slave = Process::edsgen(&["simulate", "--profibus", &b, "--card", "goodrive350-dp"]);
        slave.stderr_line(|l| l.starts_with("simulating DP slave 2"), WAIT);
        let sent = std::process::Command::new("kill")
            .args([signal, &slave.id().to_string()])
            .status()
            .expect("kill runs");
        assert!(sent.success());
        let exited = slave.finish(WAIT);
        assert_eq!(exited.code, Some(0), "{signal}: {exited:?}");
        assert!(
            exited
                .stderr
                .ends_with(&format!("stopped: DP slave 2 on {b}\n")),
            "{signal}: {exited:?}"
        );
    }
}
