//! `Builder` (the build.rs entry point): writes one module per device under its snake-case name,
//! reports warnings, and fails with the rendered diagnostics on errors.

use std::path::{Path, PathBuf};

use edsgen_codegen::{emit, Builder};

use edsgen_model::read;

fn card(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../eds")
        .join(name)
}

fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("edsgen-builder-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn writes_one_module_per_device_with_warnings() {
    let out = temp_dir("ok");
    let output = Builder::new()
        .device(card("hd1e.eds"))
        .device_as(card("cp301.eds"), "CP-301 card")
        .out_dir(&out)
        .cargo_output(false)
        .generate_to()
        .unwrap();
    let names: Vec<_> = output.modules.iter().map(|(m, _)| m.as_str()).collect();
    assert_eq!(names, ["hd1e", "cp_301_card"]);
    let written = std::fs::read_to_string(out.join("hd1e.rs")).unwrap();
    let device = read::read_file(&card("hd1e.eds")).unwrap().device;
    assert_eq!(written, emit::generate(&device, "hd1e").unwrap());
    assert!(std::fs::read_to_string(out.join("cp_301_card.rs"))
        .unwrap()
        .contains("\npub mod cp_301_card {\n"));
    // hd1e.eds has a 16-bit sub-index 0 on 2000h (the card really has it): a warning, not an error.
    assert!(
        output.warnings.iter().any(|w| w.contains("EDS308")),
        "{:?}",
        output.warnings
    );
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn errors_fail_with_rendered_diagnostics() {
    let out = temp_dir("err");
    let bad = out.join("bad.eds");
    std::fs::write(&bad, "[FileInfo]\nFileName=bad.eds\n[1000]\nParameterName=Device type\nObjectType=0x7\nDataType=0x0007\nAccessType=ro\nDefaultValue=0x1FFFFFFFF\nPDOMapping=0\n").unwrap();
    let err = Builder::new()
        .device(card("hd1e.eds"))
        .device(&bad)
        .out_dir(&out)
        .cargo_output(false)
        .generate()
        .unwrap_err();
    let message = err.message();
    assert!(message.contains("error[EDS013]"), "{message}");
    assert!(message.contains("bad.eds:8"), "{message}");
    assert!(!out.join("bad.rs").exists());
    // The good device was still generated: one build shows every device's problems.
    assert!(out.join("hd1e.rs").exists());
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn missing_file_and_duplicate_module_are_errors() {
    let out = temp_dir("dup");
    let err = Builder::new()
        .device(card("hd1e.eds"))
        .device_as(card("cp301.eds"), "hd1e")
        .device(out.join("absent.eds"))
        .out_dir(&out)
        .cargo_output(false)
        .generate()
        .unwrap_err();
    let message = err.message();
    assert!(
        message.contains("two devices would both be module `hd1e`"),
        "{message}"
    );
    assert!(message.contains("cannot read"), "{message}");
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn allowed_warnings_are_silenced_but_errors_still_fail() {
    let out = temp_dir("allow");
    let output = Builder::new()
        .device(card("hd1e.eds"))
        .allow("eds308")
        .out_dir(&out)
        .cargo_output(false)
        .generate_to()
        .unwrap();
    assert_eq!(output.warnings, Vec::<String>::new());
    assert!(out.join("hd1e.rs").exists());

    let bad = out.join("bad.eds");
    std::fs::write(&bad, "[FileInfo]\nFileName=bad.eds\n[1000]\nParameterName=Device type\nObjectType=0x7\nDataType=0x0007\nAccessType=ro\nDefaultValue=0x1FFFFFFFF\nPDOMapping=0\n").unwrap();
    let err = Builder::new()
        .device(&bad)
        .allow("EDS013")
        .out_dir(&out)
        .cargo_output(false)
        .generate()
        .unwrap_err();
    assert!(err.message().contains("error[EDS013]"), "{}", err.message());

    let err = Builder::new()
        .device(card("hd1e.eds"))
        .allow("EDS999")
        .out_dir(&out)
        .cargo_output(false)
        .generate()
        .unwrap_err();
    assert_eq!(
        err.message(),
        "error: edsgen: Builder::allow(\"EDS999\"): no such rule; did you mean EDS820? (see `edsgen rules`)\n"
    );
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn the_overlay_beside_a_device_sets_capacities_and_its_errors_fail_the_build() {
    let out = temp_dir("overlay");
    let eds = out.join("goodrive350.eds");
    std::fs::copy(card("goodrive350.eds"), &eds).unwrap();
    let build = || {
        Builder::new()
            .device(&eds)
            .allow("EDS308")
            .out_dir(&out)
            .cargo_output(false)
            .generate_to()
    };
    build().unwrap();
    let plain = std::fs::read_to_string(out.join("goodrive350.rs")).unwrap();
    assert!(plain
        .contains("pub const MANUFACTURER_DEVICE_NAME: Entry<FixedBytes<12>, super::Od, Const>"));

    std::fs::write(out.join("goodrive350.toml"), "[capacity]\n1008 = 48\n").unwrap();
    build().unwrap();
    let with_overlay = std::fs::read_to_string(out.join("goodrive350.rs")).unwrap();
    assert!(
        with_overlay.contains(
            "pub const MANUFACTURER_DEVICE_NAME: Entry<FixedBytes<48>, super::Od, Const>"
        ),
        "{with_overlay}"
    );

    std::fs::write(out.join("goodrive350.toml"), "[capacity]\n1000 = 48\n").unwrap();
    let message = build().unwrap_err().message().to_owned();
    assert!(
        message.contains(
            "error[EDS708]: 1000h sub 0 `Device type` is not a string, octet string or domain"
        ),
        "{message}"
    );
    assert!(message.contains("goodrive350.toml:2:1"), "{message}");
    let _ = std::fs::remove_dir_all(&out);
}

/// The child half of `a_failed_build_prints_its_diagnostics_once`: a build.rs `main` that returns
/// the builder's error, as the README shows, printing it as `main` would (`Error: {:?}`).
#[test]
fn failing_build_script_child() {
    let Some(bad) = std::env::var_os("EDSGEN_FAILING_BUILD") else {
        return;
    };
    let result = Builder::new()
        .device(PathBuf::from(bad))
        .out_dir(std::env::temp_dir())
        .cargo_output(false)
        .generate();
    if let Err(err) = result {
        eprintln!("Error: {err:?}");
    }
}

#[test]
fn a_failed_build_prints_its_diagnostics_once() {
    let out = temp_dir("once");
    let bad = out.join("bad.eds");
    std::fs::write(&bad, "[FileInfo]\nFileName=bad.eds\n").unwrap();
    let child = std::process::Command::new(std::env::current_exe().unwrap())
        .args(["--exact", "failing_build_script_child", "--nocapture"])
        .env("EDSGEN_FAILING_BUILD", &bad)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&child.stderr);
    assert_eq!(stderr.matches("error[EDS105]").count(), 1, "{stderr}");
    let _ = std::fs::remove_dir_all(&out);
}
