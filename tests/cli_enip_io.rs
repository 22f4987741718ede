//! `edsgen enip io` against the simulated adapter (`edsgen simulate --enip`), no root needed:
//! the Goodrive350 card configured through the PKW channel, run forward at a frequency set
//! through PZD2, its SW reporting running and its transmitted PZD2 ramping; an ODVA EDS served
//! as written (`tests/enip/io.eds`: outputs of several kinds written by name, inputs decoded by
//! name, a Large_Forward_Open); Ctrl-C closing the connection; a device that stops producing and
//! a Forward_Open refusal (exit 1); bad usage (exit 2).
//!
//! Each adapter gets a loopback address of its own (127.x.y.z, from the process ID and a
//! counter): class-1 I/O is UDP 2222 of that address, which two adapters on one address could
//! not share. The scanner's T→O socket is on 127.0.0.1, port 2222 when free, else one it asks
//! for with the Forward_Open's T→O sockaddr item.

mod process_support;

use std::process::Command;
use std::sync::atomic::{AtomicU32, Ordering};

use process_support::{Process, EDSGEN, START_TIMEOUT};

/// A loopback address no other adapter of this machine's tests uses now.
fn loopback() -> String {
    static NEXT: AtomicU32 = AtomicU32::new(1);
    let pid = std::process::id();
    let n = NEXT.fetch_add(1, Ordering::Relaxed);
    format!(
        "127.{}.{}.{}",
        100 + pid % 100,
        1 + (pid / 100) % 250,
        1 + n % 250
    )
}

/// `edsgen simulate --enip` on a fresh loopback address with `what` (`--card NAME` or a file).
fn adapter(what: &[&str]) -> (Process, String) {
    let ip = loopback();
    let port = std::net::TcpListener::bind(format!("{ip}:0"))
        .and_then(|l| l.local_addr())
        .expect("a free port")
        .port();
    let address = format!("{ip}:{port}");
    let process = Process::edsgen(&[&["simulate", "--enip", address.as_str()], what].concat());
    let serving = process.stderr_line(|l| l.starts_with("serving"), START_TIMEOUT);
    assert!(
        serving.ends_with("(EtherNet/IP; class-1 I/O on UDP 2222)"),
        "{serving}"
    );
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

/// `edsgen enip io ADDR --eds FILE ARGS...`, which must succeed; its lines.
fn io(address: &str, eds: &str, args: &[&str]) -> Vec<String> {
    let (code, stdout, stderr) = edsgen(&[&["enip", "io", address, "--eds", eds], args].concat());
    assert_eq!(code, Some(0), "{stderr}");
    assert_eq!(stderr, "");
    stdout.lines().map(str::to_owned).collect()
}

/// The value of `name=` in a line (up to the next `, `: for names whose values hold none).
fn field<'a>(line: &'a str, name: &str) -> &'a str {
    let start = line
        .find(&format!(" {name}="))
        .unwrap_or_else(|| panic!("no {name} in {line}"))
        + name.len()
        + 2;
    let rest = &line[start..];
    &rest[..rest.find(", ").unwrap_or(rest.len())]
}

const CARD_EDS: &str = "eds/goodrive350-enip.eds";

/// The rest of a card input line after SW and PZD2: PZD3-PZD12 at zero.
const QUIET_PZD: &str = "Transmitted PZD3=0, Transmitted PZD4=0, Transmitted PZD5=0, \
     Transmitted PZD6=0, Transmitted PZD7=0, Transmitted PZD8=0, Transmitted PZD9=0, \
     Transmitted PZD10=0, Transmitted PZD11=0, Transmitted PZD12=0";

#[test]
fn the_card_configured_through_pkw_runs_and_ramps_through_pzd() {
    let (_card, address) = adapter(&["--card", "goodrive350-enip"]);
    // P16.32 = 1 (received PZD2 is the set frequency), written to RAM and EEPROM with the
    // CW's write-enable bit (8) set.
    let lines = io(
        &address,
        CARD_EDS,
        &[
            "PKW1 task=Write one word (RAM and EEPROM)",
            "pkw2_address=0x1020",
            "PKW4 value low=1",
            "CW=0x0100",
            "--rpi",
            "20",
            "--cycles",
            "4",
        ],
    );
    assert_eq!(lines.len(), 4);
    // The first T→O datagram comes as the connection opens: the drive at rest (Table 5-8: 3
    // stopped, bit 8 ready, bit 14 the run/stop mode), no PKW response yet.
    assert_eq!(
        lines[0],
        format!(
            "1: PKW1 response=No response, PKW2 address=0, PKW3 value high=0, PKW4 value low=0, \
             SW=0x4103, Transmitted PZD2=0.00 Hz, {QUIET_PZD}"
        )
    );
    assert_eq!(
        lines[3],
        format!(
            "4: PKW1 response=Value, one word, PKW2 address=4128, PKW3 value high=0, \
             PKW4 value low=1, SW=0x4103, Transmitted PZD2=0.00 Hz, {QUIET_PZD}"
        )
    );
    // P16.43 = 1 (transmitted PZD2 is the running frequency).
    let lines = io(
        &address,
        CARD_EDS,
        &[
            "PKW1 task=4",
            "PKW2 address=4139",
            "PKW4 value low=1",
            "CW=0x0100",
            "--rpi",
            "20",
            "--cycles",
            "4",
        ],
    );
    assert!(
        lines[3].starts_with("4: PKW1 response=Value, one word, PKW2 address=4139, "),
        "{}",
        lines[3]
    );
    // A read-only parameter (P07.27) refused with error 7 in PKW3.
    let lines = io(
        &address,
        CARD_EDS,
        &[
            "PKW1 task=4",
            "PKW2 address=0x071B",
            "PKW4 value low=1",
            "CW=0x0100",
            "--rpi",
            "20",
            "--cycles",
            "4",
        ],
    );
    assert!(
        lines[3].starts_with(
            "4: PKW1 response=Refused (error in PKW3), PKW2 address=1819, PKW3 value high=7, "
        ),
        "{}",
        lines[3]
    );
    // Run forward (CW 1, Table 5-5) at 25.00 Hz through PZD2 (0.01 Hz).
    let lines = io(
        &address,
        CARD_EDS,
        &[
            "CW=1",
            "Received PZD2=25.00",
            "--rpi",
            "20",
            "--cycles",
            "30",
        ],
    );
    assert_eq!(lines.len(), 30);
    // The last run's Forward_Close stopped the drive (command 5) with no PKW task: at rest,
    // no PKW response.
    assert_eq!(
        lines[0],
        format!(
            "1: PKW1 response=No response, PKW2 address=0, PKW3 value high=0, PKW4 value low=0, \
             SW=0x4103, Transmitted PZD2=0.00 Hz, {QUIET_PZD}"
        )
    );
    let running: Vec<&String> = lines
        .iter()
        .filter(|l| field(l, "SW") == "0x4101")
        .collect();
    assert!(running.len() >= 25, "{lines:#?}");
    let hertz: Vec<f64> = running
        .iter()
        .map(|l| {
            let text = field(l, "Transmitted PZD2");
            text.strip_suffix(" Hz")
                .and_then(|t| t.parse().ok())
                .unwrap_or_else(|| panic!("{text}"))
        })
        .collect();
    assert!(hertz.windows(2).all(|w| w[0] <= w[1]), "{hertz:?}");
    assert!(hertz[hertz.len() - 1] > hertz[0], "{hertz:?}");
    assert!(hertz.iter().all(|&h| h <= 25.0), "{hertz:?}");
}

const TEST_EDS: &str = "tests/enip/io.eds";

#[test]
fn an_ods_eds_served_as_written_read_and_written_by_name() {
    let (_adapter, address) = adapter(&[TEST_EDS]);
    let lines = io(
        &address,
        TEST_EDS,
        &[
            "Mode=fast",
            "Setpoint=-12.5",
            // `ParamN` as `enip get|set` take it, in any case.
            "Param3=2.25",
            "param4=1",
            "--cycles",
            "2",
        ],
    );
    assert_eq!(
        lines,
        [
            "1: Status=0x0103, Temperature=-40 degC, Mode echo=Slow",
            "2: Status=0x0103, Temperature=-40 degC, Mode echo=Slow"
        ]
    );
    // Assembly 150 as the connection left it: Mode 2, Setpoint -125 (0.1 bar), Enable in bit
    // 24, seven bits of padding, Gain 2.25 as a REAL.
    assert_eq!(
        edsgen(&["enip", "get", &address, "@4/150/3"]).1,
        "02 83 FF 01 00 00 10 40\n"
    );
    // The defaults where no value is given: Mode Off, Setpoint -2.5 bar, Gain 1.5.
    io(&address, TEST_EDS, &["--cycles", "1"]);
    assert_eq!(
        edsgen(&["enip", "get", &address, "@4/150/3"]).1,
        "00 E7 FF 00 00 00 C0 3F\n"
    );
    // 600 bytes O→T need a Large_Forward_Open.
    let lines = io(
        &address,
        TEST_EDS,
        &["--connection", "big owner", "Mode=Slow", "--cycles", "1"],
    );
    assert_eq!(
        lines,
        ["1: Status=0x0103, Temperature=-40 degC, Mode echo=Slow"]
    );
    let (_, big, _) = edsgen(&["enip", "get", &address, "@4/151/3"]);
    assert_eq!(big.len(), 600 * 3);
    assert!(big.starts_with("01 00 00 "), "{}", &big[..12]);
    // Another EDS's connection: the adapter refuses its sizes.
    assert_eq!(
        edsgen(&[
            "enip",
            "io",
            &address,
            "--eds",
            "codegen/tests/odva/io.eds",
            "--cycles",
            "1"
        ]),
        (
            Some(1),
            String::new(),
            "error: Forward_Open of Connection1 `Exclusive Owner` refused: invalid O→T size \
             (general status 0x01, extended status 0x0127); the device expects 14 bytes\n"
                .to_owned()
        )
    );
}

#[test]
fn ctrl_c_closes_the_connection() {
    let (adapter, address) = adapter(&[TEST_EDS]);
    let io = Process::edsgen(&["enip", "io", &address, "--eds", TEST_EDS]);
    let first = io.stdout_line(|_| true, START_TIMEOUT);
    assert_eq!(
        first,
        "1: Status=0x0103, Temperature=-40 degC, Mode echo=Slow"
    );
    adapter.stderr_line(|l| l.ends_with(" opened"), START_TIMEOUT);
    let interrupted = Command::new("kill")
        .args(["-INT", &io.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(interrupted.success());
    let exited = io.finish(START_TIMEOUT);
    assert_eq!(exited.code, Some(0), "{}", exited.stderr);
    adapter.stderr_line(|l| l.ends_with(" closed"), START_TIMEOUT);
}

#[test]
fn a_device_that_stops_producing_times_the_connection_out() {
    let (adapter, address) = adapter(&[TEST_EDS]);
    let io = Process::edsgen(&["enip", "io", &address, "--eds", TEST_EDS, "--rpi", "10"]);
    io.stdout_line(|l| l.starts_with("1: "), START_TIMEOUT);
    // The adapter is killed: no T→O data for 16 × 10 ms.
    drop(adapter);
    let exited = io.finish(START_TIMEOUT);
    assert_eq!(exited.code, Some(1), "{}", exited.stderr);
    assert_eq!(
        exited.stderr,
        "error: no T→O data for 160 ms: the connection timed out\n"
    );
}

#[test]
fn bad_usage_exits_2_before_connecting() {
    // Nothing listens there: every case fails before a connection is tried.
    let address = "127.0.0.1:9";
    let case = |args: &[&str]| {
        let (code, stdout, stderr) =
            edsgen(&[&["enip", "io", address, "--eds", TEST_EDS], args].concat());
        assert_eq!((code, stdout.as_str()), (Some(2), ""), "{stderr}");
        stderr
    };
    assert_eq!(
        case(&["Setpont=3"]),
        "error: `Setpont` is no output member of Connection1 `Exclusive Owner`; did you mean \
         `Setpoint`, `Enable`, `Gain`, `Mode`?\n"
    );
    assert_eq!(
        case(&["Temperature=3"]),
        "error: `Temperature` is an input (T→O) of Connection1 `Exclusive Owner`, not an \
         output\n"
    );
    assert_eq!(
        case(&["Setpoint=101"]),
        "error: `Setpoint=101`: 101 is outside -100.0 ..= 100.0 bar\n"
    );
    assert_eq!(
        case(&["Setpoint=0.05"]),
        "error: `Setpoint=0.05`: not a whole step of the parameter (0.5 raw)\n"
    );
    assert_eq!(
        case(&["Mode=Medium"]),
        "error: `Mode=Medium`: `Medium` is not a number; it takes 0 \"Off\", 1 \"Slow\", 2 \"Fast\"\n"
    );
    assert_eq!(case(&["Mode=3"]), "error: `Mode=3`: 3 is outside 0 ..= 2\n");
    assert_eq!(
        case(&["Setpoint=0x8000"]),
        "error: `Setpoint=0x8000`: 0x8000 (-32768 raw) is outside -1000 ..= 1000 raw\n"
    );
    assert_eq!(
        case(&["Mode=0x100"]),
        "error: `Mode=0x100`: 0x100 has more than 8 bits\n"
    );
    assert_eq!(case(&["Mode"]), "error: `Mode` is not NAME=VALUE\n");
    assert_eq!(
        case(&["--connection", "7"]),
        "error: `tests/enip/io.eds` has no connection `7`: it has Connection1 `Exclusive \
         Owner`, Connection2 `Big Owner`\n"
    );
    assert_eq!(
        case(&["--rpi", "5"]),
        "error: --rpi: 5000 µs is outside 10000..1000000 µs (Param8 `RPI`)\n"
    );
    // An EDS without [Connection Manager], and a CiA 306 EDS.
    let dir = std::env::temp_dir().join(format!("edsgen-enip-io-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let bare = dir.join("bare.eds");
    std::fs::write(
        &bare,
        "[File]\nRevision = 1.0;\n[Device]\nVendCode = 1;\nProdType = 12;\nProdCode = 1;\n\
         MajRev = 1;\nMinRev = 1;\nProdName = \"Bare\";\n",
    )
    .expect("written");
    let bare = bare.to_string_lossy().into_owned();
    let (code, _, stderr) = edsgen(&["enip", "io", address, "--eds", &bare]);
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(code, Some(2));
    assert_eq!(
        stderr,
        format!("error: `{bare}` has no connection in [Connection Manager]\n")
    );
    let (code, _, stderr) = edsgen(&["enip", "io", address, "--eds", "eds/goodrive350.eds"]);
    assert_eq!(code, Some(2));
    assert_eq!(stderr, "error: `eds/goodrive350.eds` is not an ODVA EDS\n");
}
