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
    assert!(code_text.contains("pub const LABEL: Entry<FixedBytes<32>>"));

    std::fs::write(path.with_extension("toml"), "[capacity]\n2000 = 200\n").unwrap();
    let out = run(&["generate", p]);
    assert_eq!(code(&out), 0, "{}", String::from_utf8_lossy(&out.stderr));
    let with_overlay = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(with_overlay.contains("pub const LABEL: Entry<FixedBytes<200>>"));
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
        ),
        words(&code_text),
        "the overlay changes the capacity (type, docs, descriptor, image size) and nothing else"
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
fn generate_of_a_missing_file_exits_2() {
    let out = run(&["generate", "/nonexistent/edsgen/none.eds"]);
    assert_eq!(code(&out), 2);
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "error: cannot read `/nonexistent/edsgen/none.eds`: not a file\n"
    );
}
