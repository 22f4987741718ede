//! `edsgen rules` and `edsgen explain`: every rule with why it matters, one exact explanation per
//! format's area, and the nearest code offered for a mistyped one.

use std::process::{Command, Output};

const EDSGEN: &str = env!("CARGO_BIN_EXE_edsgen");

fn run(args: &[&str]) -> Output {
    Command::new(EDSGEN).args(args).output().unwrap()
}

fn stdout(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// `explain CODE`'s output, asserting it succeeded.
fn explain(code: &str) -> String {
    let out = run(&["explain", code]);
    assert_eq!(out.status.code(), Some(0), "{code}");
    stdout(&out)
}

const ERROR_EFFECT: &str = "An error fails `edsgen validate` (exit 1) and the build: the file \
    breaks the standard or code generated from it would be wrong.";

#[test]
fn rules_prints_each_rule_with_why_it_matters() {
    let out = run(&["rules"]);
    assert_eq!(out.status.code(), Some(0));
    let text = stdout(&out);
    assert!(text.starts_with(
        "CHK001  error    (`edsgen check`) an object or sub-index of the description is missing on the device\n\
         \x20                why: A master configured from the description reads or writes that entry at start-up and gets an SDO abort, so the node never reaches Operational.\n"
    ));
    assert!(text.contains("PN018   warning  an access point's DNS_CompatibleName"));
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 2 * edsgen_model::rules::ALL.len());
    for pair in lines.chunks(2) {
        assert!(pair[1].starts_with("                 why: "), "{pair:?}");
    }
    let json: serde_json::Value =
        serde_json::from_slice(&run(&["rules", "--format", "json"]).stdout).unwrap();
    assert_eq!(
        json[0]["why"],
        "A master configured from the description reads or writes that entry at start-up and gets an SDO abort, so the node never reaches Operational."
    );
}

#[test]
fn explain_an_odva_eds_code() {
    assert_eq!(
        explain("cip030"),
        format!(
            "CIP030 (error): a connection size that disagrees with the size of the assembly it names as its format (or that its path names)\n\n\
             Why it matters: The scanner opens the connection with the size the EDS states; the adapter answers from its assembly, and a Forward_Open with the wrong size is refused (status 0x01/0x0109).\n\
             Area: ODVA EDS connections and their paths.\n\
             {ERROR_EFFECT} `--allow CIP030` and `Builder::allow(\"CIP030\")` do not silence errors.\n"
        )
    );
}

#[test]
fn explain_an_xdd_code() {
    assert_eq!(
        explain("EDS605"),
        format!(
            "EDS605 (error): a uniqueIDRef that names no parameter (or a dataTypeIDRef that names no data type)\n\n\
             Why it matters: The entry has no parameter or type, so tools cannot tell its size, access or default.\n\
             Area: XML descriptions (XDD, XDC).\n\
             {ERROR_EFFECT} `--allow EDS605` and `Builder::allow(\"EDS605\")` do not silence errors.\n"
        )
    );
}

#[test]
fn explain_an_esi_code() {
    assert_eq!(
        explain("EDS819"),
        format!(
            "EDS819 (error): an RxPdo whose Index is a TxPDO mapping object (1A00h-1BFFh), or a TxPdo whose Index is an RxPDO one (1600h-17FFh): the directions are swapped\n\n\
             Why it matters: The master configures the PDOs in the wrong direction: outputs arrive where the device sends inputs, and the SubDevice cannot reach Op.\n\
             Area: EtherCAT descriptions (ESI) and SII images.\n\
             {ERROR_EFFECT} `--allow EDS819` and `Builder::allow(\"EDS819\")` do not silence errors.\n"
        )
    );
}

#[test]
fn explain_a_gsd_code() {
    assert_eq!(
        explain("GSD016"),
        "GSD016 (warning): a supported baud rate without MaxTsdr (a MaxTsdr for a rate not supported is harmless, and not reported)\n\n\
         Why it matters: A master running at that baud rate cannot compute its bus timing for the slave and uses a guess, which can give timeouts.\n\
         Area: PROFIBUS-DP GSD modules, parameters and bus timing.\n\
         A warning fails `edsgen validate` only under `--deny warnings` or `--deny GSD016`. `--allow GSD016` (in build.rs `Builder::allow(\"GSD016\")`) silences it where the description cannot avoid it without lying about the device.\n"
    );
}

#[test]
fn explain_a_gsdml_code() {
    assert_eq!(
        explain("PN018"),
        "PN018 (warning): an access point's DNS_CompatibleName (its default name of station) that PROFINET's name rules forbid in any case: DNS labels of letters, digits and `-`, at most 240 characters (capitals pass: controllers lowercase the name)\n\n\
         Why it matters: A controller assigns the device that name by DCP; a device refuses a name that breaks the rules, and the controller cannot connect.\n\
         Area: PROFINET GSDML: identity, access points, modules, records and diagnosis.\n\
         A warning fails `edsgen validate` only under `--deny warnings` or `--deny PN018`. `--allow PN018` (in build.rs `Builder::allow(\"PN018\")`) silences it where the description cannot avoid it without lying about the device.\n"
    );
}

#[test]
fn explain_an_info_code_of_the_readers() {
    assert_eq!(
        explain("CIP002"),
        "CIP002 (info): ODVA EDS: a section or key this reader does not interpret (kept as written); the specification's class sections (`[... Class]`, `[ClassN_VendorM]`) are kept without a report\n\n\
         Why it matters: Nothing generated depends on it, but a key that is a misspelling of a known one means the value the author meant is silently ignored.\n\
         Area: ODVA EDS text, sections and identity (reported while reading).\n\
         An info never fails anything; `--quiet` hides it, `--allow CIP002` silences it, `--deny CIP002` makes it an error.\n"
    );
}

#[test]
fn explain_an_ethercat_check_code() {
    assert_eq!(
        explain("CHK007"),
        "CHK007 (error): (`edsgen ecat check`) a SyncManager of the SubDevice's SII (kind, start, length, control byte, enable), or its ESC's SyncManager count, differs from the ESI\n\n\
         Why it matters: The master programs the SyncManagers from the ESI; a SII that disagrees leaves mailbox or process data at other addresses, and the SubDevice stays in Init or SafeOp.\n\
         Area: a live device against its description (`edsgen check`).\n\
         `edsgen ecat check` reports it where the device differs from its description: an error fails the check (exit 1); a warning only under `--deny-warnings`. It says nothing about the description file itself (`edsgen validate` does).\n"
    );
}

#[test]
fn every_code_explains_with_why_and_its_area() {
    for rule in edsgen_model::rules::ALL {
        let text = explain(rule.code);
        assert!(
            text.contains(&format!("\n\nWhy it matters: {}\nArea: ", rule.why)),
            "{text}"
        );
        assert!(!text.contains("not numbered by area"), "{text}");
    }
}

#[test]
fn an_unknown_code_is_offered_the_nearest_one() {
    let refused = |args: &[&str]| {
        let out = run(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    assert_eq!(
        refused(&["explain", "EDS999"]),
        "error: explain EDS999: no such rule; did you mean EDS820? (`edsgen rules` lists them)\n"
    );
    assert_eq!(
        refused(&["explain", "pn21"]),
        "error: explain pn21: no such rule; did you mean PN019? (`edsgen rules` lists them)\n"
    );
    assert_eq!(
        refused(&["explain", "CPI023"]),
        "error: explain CPI023: no such rule; did you mean CIP023? (`edsgen rules` lists them)\n"
    );
    assert_eq!(
        refused(&["explain", "GSD20"]),
        "error: explain GSD20: no such rule; did you mean GSD017? (`edsgen rules` lists them)\n"
    );
    assert_eq!(
        refused(&["explain", "XYZ999"]),
        "error: explain XYZ999: no such rule (`edsgen rules` lists them)\n"
    );
    assert_eq!(
        refused(&["validate", "--deny", "CIP99", "x.eds"]),
        "error: --deny CIP99: no such rule; did you mean CIP032? (`edsgen rules` lists them)\n"
    );
}
