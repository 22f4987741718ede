//! The `edsgen validate` command line: exit codes (0 clean, 1 errors or denied warnings, 2 usage
//! and I/O), the exact JSON output, and the exact rustc-style rendering of a diagnostic.

use std::path::PathBuf;
use std::process::{Command, Output};

const EDSGEN: &str = env!("CARGO_BIN_EXE_edsgen");

/// A small clean device; tests derive broken ones from it with `str::replace`.
const CLEAN: &str = "\
[FileInfo]
FileName=cli.eds
FileVersion=1
FileRevision=0
EDSVersion=4.0
Description=cli test device
CreationTime=09:00AM
CreationDate=01-31-2026
CreatedBy=edsgen
ModificationTime=09:00AM
ModificationDate=01-31-2026
ModifiedBy=edsgen

[DeviceInfo]
VendorName=edsgen
VendorNumber=0x1234
ProductName=cli
ProductNumber=0x1
RevisionNumber=0x2
OrderCode=C-1
BaudRate_10=0
BaudRate_20=0
BaudRate_50=0
BaudRate_125=0
BaudRate_250=1
BaudRate_500=0
BaudRate_800=0
BaudRate_1000=0
SimpleBootUpMaster=0
SimpleBootUpSlave=1
Granularity=8
DynamicChannelsSupported=0
GroupMessaging=0
NrOfRXPDO=0
NrOfTXPDO=0
LSS_Supported=0

[DummyUsage]
Dummy0001=0
Dummy0002=1
Dummy0003=1
Dummy0004=1
Dummy0005=1
Dummy0006=1
Dummy0007=1

[MandatoryObjects]
SupportedObjects=3
1=0x1000
2=0x1001
3=0x1018

[OptionalObjects]
SupportedObjects=1
1=0x1017

[ManufacturerObjects]
SupportedObjects=1
1=0x2000

[1000]
ParameterName=Device type
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=0
PDOMapping=0

[1001]
ParameterName=Error register
ObjectType=0x7
DataType=0x0005
AccessType=ro
DefaultValue=0
PDOMapping=0

[1017]
ParameterName=Producer heartbeat time
ObjectType=0x7
DataType=0x0006
AccessType=rw
DefaultValue=0
PDOMapping=0

[1018]
ParameterName=Identity object
ObjectType=0x9
SubNumber=4

[1018sub0]
ParameterName=Highest sub-index supported
ObjectType=0x7
DataType=0x0005
AccessType=ro
DefaultValue=3
PDOMapping=0

[1018sub1]
ParameterName=Vendor-ID
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=0x1234
PDOMapping=0

[1018sub2]
ParameterName=Product code
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=0x1
PDOMapping=0

[1018sub3]
ParameterName=Revision number
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=0x2
PDOMapping=0

[2000]
ParameterName=Speed
ObjectType=0x7
DataType=0x0006
AccessType=rw
DefaultValue=0
PDOMapping=0
";

/// Writes `text` to a fresh file named `name` in a per-test directory.
fn file(test: &str, name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("edsgen-cli-{}-{test}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn run(args: &[&str]) -> Output {
    Command::new(EDSGEN)
        .args(args)
        .env("NO_COLOR", "1")
        .output()
        .unwrap()
}

fn code(out: &Output) -> i32 {
    out.status.code().unwrap()
}

/// An unknown data type on 2000h: one error (EDS314).
fn with_error() -> String {
    CLEAN.replace(
        "ParameterName=Speed\nObjectType=0x7\nDataType=0x0006",
        "ParameterName=Speed\nObjectType=0x7\nDataType=0x0099",
    )
}

/// EDSVersion `4`: one warning (EDS102).
fn with_warning() -> String {
    CLEAN.replace("EDSVersion=4.0", "EDSVersion=4")
}

#[test]
fn clean_file_exits_0() {
    let path = file("clean", "clean.eds", CLEAN);
    let out = run(&["validate", path.to_str().unwrap()]);
    assert_eq!(code(&out), 0, "{}", String::from_utf8_lossy(&out.stdout));
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "1 file(s) checked: 0 error(s), 0 warning(s)\n"
    );
}

#[test]
fn errors_exit_1() {
    let path = file("errors", "bad.eds", &with_error());
    assert_eq!(code(&run(&["validate", path.to_str().unwrap()])), 1);
}

#[test]
fn warnings_exit_0_unless_denied() {
    let path = file("warnings", "warn.eds", &with_warning());
    let p = path.to_str().unwrap();
    assert_eq!(code(&run(&["validate", p])), 0);
    assert_eq!(code(&run(&["validate", "--deny", "warnings", p])), 1);
}

#[test]
fn missing_file_exits_2() {
    let out = run(&["validate", "/nonexistent/edsgen/none.eds"]);
    assert_eq!(code(&out), 2);
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("cannot read `/nonexistent/edsgen/none.eds`")
    );
}

#[test]
fn bad_usage_exits_2() {
    assert_eq!(code(&run(&["validate"])), 2);
    assert_eq!(code(&run(&["validate", "--format", "yaml", "x.eds"])), 2);
    assert_eq!(code(&run(&["no-such-command"])), 2);
}

#[test]
fn json_output_is_exact() {
    let path = file("json", "bad.eds", &with_error());
    let p = path.to_str().unwrap();
    let out = run(&["validate", "--format", "json", p]);
    assert_eq!(code(&out), 1);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    // At the DataType value, not the section header.
    let line = with_error()
        .lines()
        .position(|l| l == "DataType=0x0099")
        .unwrap()
        + 1;
    assert_eq!(
        json,
        serde_json::json!([{
            "file": p,
            "line": line,
            "column": 10,
            "severity": "error",
            "code": "EDS314",
            "message": "2000h has DataType 0099h, which is not a basic type nor defined in this file",
            "help": "use a CiA 301 basic type (0x0001..0x001B), or describe the DEFTYPE/DEFSTRUCT object",
        }])
    );
}

#[test]
fn human_output_is_rustc_style() {
    let path = file("human", "warn.eds", &with_warning());
    let out = run(&["validate", path.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&out.stdout).replace(path.to_str().unwrap(), "warn.eds");
    insta::assert_snapshot!(text);
}

/// CLEAN with 2000h a writable VISIBLE_STRING (capacity 32 by the generator's rule).
fn with_string() -> String {
    CLEAN.replace(
        "ParameterName=Speed\nObjectType=0x7\nDataType=0x0006\nAccessType=rw\nDefaultValue=0",
        "ParameterName=Label\nObjectType=0x7\nDataType=0x0009\nAccessType=rw\nDefaultValue=drive",
    )
}

#[test]
fn generate_applies_the_overlay_beside_the_file() {
    let path = file("overlay", "dev.eds", &with_string());
    let p = path.to_str().unwrap();
    let out = run(&["generate", p]);
    assert_eq!(code(&out), 0, "{}", String::from_utf8_lossy(&out.stderr));
    let code_text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(code_text.contains("pub const LABEL: Entry<FixedBytes<32>, super::Od>"));

    std::fs::write(path.with_extension("toml"), "[capacity]\n2000 = 200\n").unwrap();
    let out = run(&["generate", p]);
    assert_eq!(code(&out), 0, "{}", String::from_utf8_lossy(&out.stderr));
    let with_overlay = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(with_overlay.contains("pub const LABEL: Entry<FixedBytes<200>, super::Od>"));
    let image_size = |code: &str| {
        let line = code.lines().find(|l| l.contains("const IMAGE_SIZE: usize"));
        line.unwrap_or_default().to_owned()
    };
    // The string's room in the value image grows by 200 - 32 bytes.
    let (before, after) = (image_size(&code_text), image_size(&with_overlay));
    let number = |line: &str| {
        line.trim_end_matches(';')
            .rsplit(' ')
            .next()
            .map(str::to_owned)
    };
    let parsed = |line: &str| number(line).and_then(|n| n.parse::<usize>().ok());
    assert_eq!(parsed(&after), parsed(&before).map(|n| n + 168));
    // Compared without whitespace: a longer type can move a line break.
    let words = |code: &str| code.split_whitespace().collect::<String>();
    assert_eq!(
        words(
            &with_overlay
                .replace(&after, &before)
                .replace("FixedBytes<200>", "FixedBytes<32>")
                .replace("capacity 200 bytes", "capacity 32 bytes")
                .replace("A::Rw, false, 200)", "A::Rw, false, 32)")
                .replace("STAGE_SIZE: usize = 200;", "STAGE_SIZE: usize = 32;")
        ),
        words(&code_text),
        "the overlay changes the capacity (type, docs, descriptor, image size, the staging \
         bound of a download) and nothing else"
    );
}

#[test]
fn generate_reports_overlay_errors_at_their_line_and_exits_1() {
    let path = file("overlay-bad", "dev.eds", &with_string());
    let overlay = path.with_extension("toml");
    std::fs::write(&overlay, "# capacities\n[capacity]\n2000 = 3\n").unwrap();
    let out = run(&["generate", path.to_str().unwrap()]);
    assert_eq!(code(&out), 1);
    assert!(out.stdout.is_empty());
    let stderr =
        String::from_utf8_lossy(&out.stderr).replace(overlay.to_str().unwrap(), "dev.toml");
    assert_eq!(
        stderr,
        "\
error[EDS708]: 2000h sub 0 `Label` holds 5 bytes by default, more than the capacity 3
 --> dev.toml:3:8
  |
3 | 2000 = 3
  |        ^
  |
  = help: give it at least 5 bytes

"
    );
}

#[test]
fn validate_applies_the_overlay_and_reports_its_errors_under_its_name() {
    let path = file("overlay-validate", "dev.eds", &with_string());
    let overlay = path.with_extension("toml");
    std::fs::write(&overlay, "# capacities\n[capacity]\n2000 = 3\n").unwrap();
    let out = run(&["validate", path.to_str().unwrap()]);
    assert_eq!(code(&out), 1);
    let stdout =
        String::from_utf8_lossy(&out.stdout).replace(overlay.to_str().unwrap(), "dev.toml");
    assert_eq!(
        stdout,
        "\
error[EDS708]: 2000h sub 0 `Label` holds 5 bytes by default, more than the capacity 3
 --> dev.toml:3:8
  |
3 | 2000 = 3
  |        ^
  |
  = help: give it at least 5 bytes

1 file(s) checked: 1 error(s), 0 warning(s)
"
    );
    // Sizes the generated code cannot hold are found by validate too (EDS707), once the overlay
    // sets the capacity: 65535 bytes and a 2-byte length overflow the value image.
    std::fs::write(&overlay, "[capacity]\n2000 = 65535\n").unwrap();
    let out = run(&["validate", path.to_str().unwrap()]);
    assert_eq!(code(&out), 1);
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        stdout.starts_with(
            "error[EDS707]: 2000h `Label`: with this object the device's values need more than \
             65535 bytes in all"
        ),
        "{stdout}"
    );
}

#[test]
fn generate_of_a_missing_file_exits_2() {
    let out = run(&["generate", "/nonexistent/edsgen/none.eds"]);
    assert_eq!(code(&out), 2);
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "error: cannot read `/nonexistent/edsgen/none.eds`: not a file\n"
    );
}

#[test]
fn deny_warnings_says_so_in_the_summary_and_the_json() {
    let path = file("deny", "warn.eds", &with_warning());
    let p = path.to_str().unwrap();
    let out = run(&["validate", "--deny", "warnings", p]);
    assert_eq!(code(&out), 1);
    let text = String::from_utf8_lossy(&out.stdout).replace(p, "warn.eds");
    assert_eq!(
        text,
        "error[EDS102]: EDSVersion `4` is not of the form x.y (denied by `--deny warnings`)\n \
         --> warn.eds:5:12\n  |\n5 | EDSVersion=4\n  |            ^ expected e.g. 4.0\n  |\n  \
         = help: write `EDSVersion=4.0`\n\n\
         1 file(s) checked: 1 error(s) (1 of them denied by --deny warnings), 0 warning(s)\n"
    );
    let out = run(&["validate", "--format", "json", "--deny", "EDS102", p]);
    assert_eq!(code(&out), 1);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json[0]["severity"], "error");
    assert_eq!(json[0]["code"], "EDS102");
    assert_eq!(json[0]["denied"], "--deny EDS102");
    assert_eq!(json.as_array().unwrap().len(), 1);
}

#[test]
fn allow_silences_a_warning_but_not_an_error_and_unknown_codes_are_usage_errors() {
    let warn = file("allow", "warn.eds", &with_warning());
    let out = run(&[
        "validate",
        "--deny",
        "warnings",
        "--allow",
        "eds102",
        warn.to_str().unwrap(),
    ]);
    assert_eq!(code(&out), 0);
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "1 file(s) checked: 0 error(s), 0 warning(s); 1 allowed by --allow EDS102\n"
    );
    let bad = file("allow", "bad.eds", &with_error());
    assert_eq!(
        code(&run(&[
            "validate",
            "--allow",
            "EDS314",
            bad.to_str().unwrap()
        ])),
        1
    );
    let out = run(&["validate", "--allow", "EDS999", bad.to_str().unwrap()]);
    assert_eq!(code(&out), 2);
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "error: --allow EDS999: no such rule; did you mean EDS820? (`edsgen rules` lists them)\n"
    );
    let out = run(&[
        "validate",
        "--allow",
        "EDS102",
        "--deny",
        "EDS102",
        bad.to_str().unwrap(),
    ]);
    assert_eq!(code(&out), 2);
}

#[test]
fn quiet_and_min_severity_hide_but_still_count() {
    // An unknown key (EDS009, info) and EDSVersion `4` (EDS102, warning).
    let text = with_warning().replace("CreatedBy=edsgen", "CreatedBy=edsgen\nColour=blue");
    let path = file("quiet", "q.eds", &text);
    let p = path.to_str().unwrap();
    let all = String::from_utf8_lossy(&run(&["validate", p]).stdout).into_owned();
    assert!(all.contains("info[EDS009]"), "{all}");
    let out = run(&["validate", "--quiet", p]);
    let quiet = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(!quiet.contains("info["), "{quiet}");
    assert!(quiet.contains("warning[EDS102]"), "{quiet}");
    assert!(
        quiet.ends_with(
            "1 file(s) checked: 0 error(s), 1 warning(s); 1 not shown (below warning)\n"
        ),
        "{quiet}"
    );
    let out = run(&["validate", "--min-severity", "error", p]);
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "1 file(s) checked: 0 error(s), 1 warning(s); 2 not shown (below error)\n"
    );
}

#[test]
fn explain_prints_the_rule_and_what_its_severity_does() {
    let out = run(&["explain", "eds102"]);
    assert_eq!(code(&out), 0);
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "EDS102 (warning): EDSVersion is missing (meaning 3.0) or is not of the form x.y\n\n\
         Why it matters: Readers that switch behaviour on the version (python canopen, vendor \
         tools) treat the file as 3.0, which can differ from what the author wrote it for.\n\
         Area: [FileInfo] and [DeviceInfo].\n\
         A warning fails `edsgen validate` only under `--deny warnings` or `--deny EDS102`. \
         `--allow EDS102` (in build.rs `Builder::allow(\"EDS102\")`) silences it where the \
         description cannot avoid it without lying about the device.\n"
    );
    let out = run(&["explain", "EDS999"]);
    assert_eq!(code(&out), 2);
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "error: explain EDS999: no such rule; did you mean EDS820? (`edsgen rules` lists them)\n"
    );
}

#[test]
fn io_errors_are_in_the_json_and_not_counted_as_checked() {
    let clean = file("io", "clean.eds", CLEAN);
    let dir = clean.parent().unwrap().join("a-directory.eds");
    std::fs::create_dir_all(&dir).unwrap();
    let (c, d) = (clean.to_str().unwrap(), dir.to_str().unwrap());
    let out = run(&["validate", "--format", "json", c, d]);
    assert_eq!(code(&out), 2);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(
        json,
        serde_json::json!([{
            "file": d, "line": 0, "column": 0, "severity": "error", "code": "EDS000",
            "message": format!("cannot read `{d}`: Is a directory (os error 21)"), "help": null,
        }])
    );
    let out = run(&["validate", c, d]);
    assert_eq!(code(&out), 2);
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "1 file(s) checked, 1 not readable: 0 error(s), 0 warning(s)\n"
    );
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        format!("error[EDS000]: cannot read `{d}`: Is a directory (os error 21)\n --> {d}\n\n")
    );
}

#[test]
fn empty_and_binary_files_get_one_diagnostic_and_dump_refuses_them() {
    let empty = file("binary", "empty.eds", "");
    let binary = empty.with_file_name("binary.eds");
    std::fs::write(
        &binary,
        b"\x7fELF\x02\x01\x01\x00\x1b[2J\x1b]0;owned\x07\n[x]\n",
    )
    .unwrap();
    let (e, b) = (empty.to_str().unwrap(), binary.to_str().unwrap());
    let out = run(&["validate", e, b]);
    assert_eq!(code(&out), 1);
    assert_eq!(
        String::from_utf8_lossy(&out.stdout)
            .replace(e, "empty.eds")
            .replace(b, "binary.eds"),
        "error[EDS022]: the file is empty\n --> empty.eds\n\n\
         error[EDS029]: not a text file: NUL byte at offset 7\n --> binary.eds\n \
         = help: an EDS or DCF is ASCII text; is this the right file?\n\n\
         2 file(s) checked: 2 error(s), 0 warning(s)\n"
    );
    for path in [e, b] {
        let out = run(&["dump", path]);
        assert_eq!(code(&out), 1, "{path}");
        assert!(out.stdout.is_empty());
        assert!(!out.stderr.contains(&0x1b));
    }
    // `devices` gives the same answer for the same files, not "not an ESI file" (a usage error).
    let out = run(&["devices", b]);
    assert_eq!(code(&out), 1);
    assert!(out.stdout.is_empty());
    assert_eq!(
        String::from_utf8_lossy(&out.stderr).replace(b, "binary.eds"),
        "error[EDS029]: not a text file: NUL byte at offset 7\n --> binary.eds\n \
         = help: an EDS or DCF is ASCII text; is this the right file?\n\n"
    );
    let out = run(&["devices", e]);
    assert_eq!(code(&out), 1);
    assert_eq!(
        String::from_utf8_lossy(&out.stderr).replace(e, "empty.eds"),
        "error[EDS022]: the file is empty\n --> empty.eds\n\n"
    );
}

#[test]
fn utf16_is_labelled_utf16() {
    let text: Vec<u8> = [0xFF, 0xFE]
        .into_iter()
        .chain(CLEAN.encode_utf16().flat_map(u16::to_le_bytes))
        .collect();
    let path = file("utf16", "wide.eds", "");
    std::fs::write(&path, text).unwrap();
    let out = run(&["validate", "--format", "json", path.to_str().unwrap()]);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json[0]["code"], "EDS002");
    assert_eq!(
        json[0]["message"],
        "the file is UTF-16 (little-endian); it was decoded as such"
    );
    assert_eq!(json.as_array().unwrap().len(), 1, "{json}");
}

#[test]
fn xml_nested_too_deep_is_refused_without_a_crash() {
    let deep = format!("{}{}", "<a>".repeat(20_000), "</a>".repeat(20_000));
    let path = file("deep", "deep.xdd", &deep);
    for command in ["validate", "dump", "generate"] {
        let out = run(&[command, path.to_str().unwrap()]);
        assert_eq!(code(&out), 1, "{command}");
        let all = [out.stdout, out.stderr].concat();
        assert!(
            String::from_utf8_lossy(&all)
                .contains("error[EDS601]: the XML nests elements more than 256 deep"),
            "{command}"
        );
    }
}

/// CLEAN with a DEFTYPE 0060h (`DataType` `deftype_type`) and 2000h typed 0060h.
fn with_deftype(deftype_type: &str) -> String {
    CLEAN
        .replace(
            "ParameterName=Speed\nObjectType=0x7\nDataType=0x0006",
            "ParameterName=Speed\nObjectType=0x7\nDataType=0x0060",
        )
        .replace(
            "[1000]",
            &format!("[0060]\nParameterName=Profile type\nObjectType=0x5\nDataType={deftype_type}\nAccessType=ro\n\n[1000]"),
        )
}

#[test]
fn a_clean_validate_means_generate_succeeds() {
    let long = format!("{}\n", "x".repeat(70_000));
    let big_string = with_string().replace("DefaultValue=drive\n", &format!("DefaultValue={long}"));
    let two_labels = with_string()
        .replace(
            "SupportedObjects=1\n1=0x2000",
            "SupportedObjects=2\n1=0x2000\n2=0x2001",
        )
        .replace(
            "DefaultValue=drive\n",
            &format!("DefaultValue={}\n", "y".repeat(40_000)),
        );
    let big_image = format!(
        "{two_labels}\n[2001]\nParameterName=Other\nObjectType=0x7\nDataType=0x0009\nAccessType=ro\nDefaultValue={}\nPDOMapping=0\n",
        "z".repeat(40_000)
    );
    let cases = [
        ("deftype.eds", with_deftype("0x0007"), None),
        ("selfref.eds", with_deftype("0x0060"), Some("EDS314")),
        ("string.eds", big_string, Some("EDS707")),
        ("image.eds", big_image, Some("EDS707")),
    ];
    for (name, text, error) in cases {
        let path = file("clean-means-generate", name, &text);
        let p = path.to_str().unwrap();
        let validated = run(&["validate", "--format", "json", p]);
        let json: serde_json::Value = serde_json::from_slice(&validated.stdout).unwrap();
        let mut errors: Vec<&str> = json
            .as_array()
            .unwrap()
            .iter()
            .filter(|d| d["severity"] == "error")
            .map(|d| d["code"].as_str().unwrap())
            .collect();
        errors.dedup();
        let generated = run(&["generate", p]);
        match error {
            None => {
                assert_eq!(errors, Vec::<&str>::new(), "{name}");
                assert_eq!(
                    code(&generated),
                    0,
                    "{name}: {}",
                    String::from_utf8_lossy(&generated.stderr)
                );
            }
            Some(rule) => {
                assert_eq!(errors, vec![rule], "{name}");
                assert_eq!(code(&validated), 1, "{name}");
                assert_eq!(code(&generated), 1, "{name}");
            }
        }
    }
}

#[test]
fn device_picks_one_device_of_an_esi_file() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/codegen/tests/esi/drive.xml");
    for choice in ["TD-2", "#x00009253"] {
        let out = run(&["dump", "--device", choice, path]);
        assert_eq!(code(&out), 0, "{choice}");
        let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(json["format"], "esi");
        assert_eq!(json["ethercat"]["type_name"], "TD-2");
        assert_eq!(json["ethercat"]["other_devices"][0]["type_name"], "TD-1");
        assert_eq!(json["device_info"]["product_number"], 0x9253);
    }
    // The first device by default.
    let out = run(&["dump", path]);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["ethercat"]["type_name"], "TD-1");
    assert_eq!(json["ethercat"]["rx_pdos"][0]["bits"], 56);
    // A choice no device matches: an error, listing the devices, for each command.
    for command in ["validate", "dump", "generate"] {
        let out = run(&[command, "--device", "TD-9", path]);
        assert_eq!(code(&out), 1, "{command}");
        let all = String::from_utf8_lossy(&[out.stdout, out.stderr].concat()).into_owned();
        assert!(
            all.contains(
                "error[EDS801]: no device of the file is named `TD-9`; it has TD-1 (#x00009252), \
                 TD-2 (#x00009253)"
            ),
            "{command}: {all}"
        );
    }
}

#[test]
fn devices_lists_the_devices_of_an_esi_file() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/codegen/tests/esi/drive.xml");
    let out = run(&["devices", path]);
    assert_eq!(code(&out), 0);
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "TD-1\t#x00009252\t#x00000001\tprofile 402\tout 56 bits\tin 16 bits\tTest drive\n\
         TD-2\t#x00009253\t#x00000002\tprofile -\tout 0 bits\tin 0 bits\tSecond test drive\n"
    );
    assert!(out.stderr.is_empty());
    // A CANopen description is no ESI file: a usage error.
    let eds = file("devices", "clean.eds", CLEAN);
    let out = run(&["devices", eds.to_str().unwrap()]);
    assert_eq!(code(&out), 2);
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        format!(
            "error: {}: not an ESI file; a CANopen description has one device\n",
            eds.display()
        )
    );
    // A file of modules without a device: its diagnostics, exit 1.
    let xml = file(
        "devices",
        "modules.xml",
        "<EtherCATModule><Modules><Module/></Modules></EtherCATModule>\n",
    );
    let out = run(&["devices", xml.to_str().unwrap()]);
    assert_eq!(code(&out), 1);
    assert!(out.stdout.is_empty());
    assert!(String::from_utf8_lossy(&out.stderr)
        .contains("error[EDS801]: the file describes no Device"));
}
