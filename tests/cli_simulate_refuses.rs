//! One rule for every simulator: `edsgen simulate` refuses a description with errors before
//! serving it, on every bus, with the errors as `edsgen validate` shows them and the `--allow`
//! that serves it anyway (exit 2); with that `--allow` it goes on to serve. Each file is one of
//! the repository's own with one error written into it.

mod process_support;

use std::path::PathBuf;
use std::time::Duration;

use edsgen_host::hub::{Hub, HubOptions};
use process_support::{root, Process};

/// How long a line or an exit may take.
const WAIT: Duration = Duration::from_secs(10);

/// `name` in a private folder: the repository file `from` with its first `wrong` made `bad`.
fn broken(name: &str, from: &str, wrong: &str, bad: &str) -> String {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("cli-simulate-refuses");
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(root().join(from)).unwrap();
    assert!(text.contains(wrong), "{from} has no `{wrong}`");
    let path = dir.join(name);
    std::fs::write(&path, text.replacen(wrong, bad, 1)).unwrap();
    path.display().to_string()
}

/// Runs `edsgen simulate ARGS` to its end; asserts exit 2 and the whole of standard error.
fn refused(args: &[&str], stderr: &str) {
    let exited = Process::edsgen(&[&["simulate"], args].concat()).finish(WAIT);
    assert_eq!(exited.code, Some(2), "{exited:?}");
    assert_eq!(exited.stderr, stderr);
}

/// Runs `edsgen simulate ARGS` to its end; asserts exit 2 and the last line of standard error
/// (what comes after the description's judgement: the bus cannot be opened).
fn got_past_the_judgement(args: &[&str], last: &str) {
    let exited = Process::edsgen(&[&["simulate"], args].concat()).finish(WAIT);
    assert_eq!(exited.code, Some(2), "{exited:?}");
    assert_eq!(exited.stderr.lines().last(), Some(last), "{exited:?}");
}

#[test]
fn canopen_refuses_an_eds_with_an_error_and_serves_it_with_allow() {
    let eds = broken(
        "cp301.eds",
        "eds/cp301.eds",
        "DefaultValue=0x00000000",
        "DefaultValue=0x0000000Z",
    );
    let at = format!("{eds}@9");
    refused(
        &[&at],
        &format!(
            "error[EDS012]: `0x0000000Z` cannot be read as UNSIGNED32
   --> {eds}:143:14
    |
143 | DefaultValue=0x0000000Z
    |              ^^^^^^^^^^ not an integer
    |
    = help: write a decimal, `0x` hexadecimal or `$NODEID+n` value for UNSIGNED32

error: `{eds}` has 1 error (EDS012): not served; `--allow EDS012` serves it anyway
"
        ),
    );
    let hub = Hub::start("127.0.0.1:0", HubOptions::default()).unwrap();
    let bus = hub.local_addr().to_string();
    let sim = Process::edsgen(&["simulate", &at, "--bus", &bus, "--allow", "EDS012"]);
    let line = sim.stderr_line(|l| l.starts_with("simulating"), WAIT);
    assert_eq!(line, format!("simulating node 9 ({eds}) on {bus}"));
}

#[test]
fn enip_refuses_an_odva_eds_with_an_error_and_serves_it_with_allow() {
    let eds = broken("io.eds", "tests/enip/io.eds", "16,Param5", "24,Param5");
    let address = {
        let free = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
        free.local_addr().unwrap().to_string()
    };
    refused(
        &["--enip", &address, &eds],
        &format!(
            "error[CIP020]: Assem100 `Inputs` is 5 bytes (40 bits) but its 3 members add up to 48 bits
  --> {eds}:49:17
   |
49 |                 5,
   |                 ^ size of the assembly
   |
   = help: read as bits, the members fill 6 bytes, not 5: correct the members (to 33 to 40 bits) or the size (to 6), whichever is wrong

error: `{eds}` has 1 error (CIP020): not served; `--allow CIP020` serves it anyway
"
        ),
    );
    let sim = Process::edsgen(&["simulate", "--enip", &address, &eds, "--allow", "CIP020"]);
    let line = sim.stderr_line(|l| l.starts_with("serving"), WAIT);
    assert!(
        line.starts_with(&format!("serving `{eds}` on {address}")),
        "{line}"
    );
}

#[test]
fn ethercat_refuses_an_esi_with_an_error_and_serves_it_with_allow() {
    let esi = broken(
        "io.xml",
        "tests/esi/io-no-mailbox.xml",
        "<BitLen>8</BitLen>",
        "<BitLen>8x</BitLen>",
    );
    refused(
        &["--ethercat", "nosuchif0", &esi],
        &format!(
            "error[EDS604]: `BitLen` is `8x`, not a number
  --> {esi}:34:21
   |
34 |             <BitLen>8x</BitLen>
   |                     ^^
   |

error: `{esi}` has 1 error (EDS604): not served; `--allow EDS604` serves it anyway
"
        ),
    );
    got_past_the_judgement(
        &["--ethercat", "nosuchif0", &esi, "--allow", "EDS604"],
        "error: cannot open nosuchif0: no interface `nosuchif0`: No such file or directory (os error 2)",
    );
}

#[test]
fn profinet_refuses_a_gsdml_with_an_error_and_serves_it_with_allow() {
    let gsdml = broken(
        "pn.xml",
        "eds/goodrive350-pn.xml",
        "DataType=\"Unsigned16\"",
        "DataType=\"Unsigned17\"",
    );
    refused(
        &["--profinet", "nosuchif0", &gsdml],
        &format!(
            "error[PN003]: `Unsigned17` is not a GSDML data type
   --> {gsdml}:106:39
    |
106 |                   <DataItem DataType=\"Unsigned17\" TextId=\"T_IN_1\"/>
    |                                       ^^^^^^^^^^ unknown type
    |
    = help: GSDML types are Unsigned8..64, Integer8..64, Float32/64, OctetString, VisibleString, ...

error: `{gsdml}` has 1 error (PN003): not served; `--allow PN003` serves it anyway
"
        ),
    );
    got_past_the_judgement(
        &["--profinet", "nosuchif0", &gsdml, "--allow", "PN003"],
        "error: cannot open `nosuchif0` for PROFINET: no interface `nosuchif0`: No such file or directory (os error 2)",
    );
}

#[test]
fn profibus_refuses_a_gsd_with_an_error_and_serves_it_with_allow() {
    let gsd = broken(
        "dp.gsd",
        "eds/goodrive350-dp.gsd",
        "User_Prm_Data_Len   = 0",
        "User_Prm_Data_Len   = 0\nUser_Prm_Data = 0x00,0x01",
    );
    refused(
        &["--profibus", "/nonexistent/tty", &gsd],
        &format!(
            "error[GSD013]: User_Prm_Data has 2 bytes, User_Prm_Data_Len says 0
  --> {gsd}:74:1
   |
74 | User_Prm_Data_Len   = 0
   | ^^^^^^^^^^^^^^^^^^^^^^^
   |

error: `{gsd}` has 1 error (GSD013): not served; `--allow GSD013` serves it anyway
"
        ),
    );
    got_past_the_judgement(
        &["--profibus", "/nonexistent/tty", &gsd, "--allow", "GSD013"],
        "error: cannot open /nonexistent/tty: No such file or directory (os error 2)",
    );
}

#[test]
fn allow_takes_only_rule_codes() {
    refused(
        &["--card", "cp301", "--allow", "XYZ999"],
        "error: --allow XYZ999: no such rule (`edsgen rules` lists them)\n",
    );
}
