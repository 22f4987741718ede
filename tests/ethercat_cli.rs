//! `edsgen ecat` in a build without the `ethercrab` feature says which feature to build with,
//! whatever follows it, and exits 2.

#[path = "process_support/mod.rs"]
mod process_support;

#[cfg(not(feature = "ethercrab"))]
#[test]
fn ecat_without_the_feature_says_which_feature_to_build_with() {
    use process_support::EDSGEN;
    for args in [
        &["ecat"][..],
        &["ecat", "scan", "--iface", "ecm"],
        &["ecat", "--help"],
    ] {
        let out = std::process::Command::new(EDSGEN)
            .args(args)
            .output()
            .expect("edsgen runs");
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert_eq!(out.stdout, b"", "{args:?}");
        assert_eq!(
            String::from_utf8_lossy(&out.stderr),
            "error: `edsgen ecat` is not in this build: it needs the `ethercrab` feature (cargo \
             install edsgen --features ethercrab, or cargo build --release --features ethercrab)\n",
            "{args:?}"
        );
    }
}

/// `edsgen simulate --ethercat` refuses a module choice the device does not allow before it
/// opens the interface, with EDS708's sentences and exit 2; `--module` without a bus that takes
/// it is refused too. The modular device is ETG.2001's two-axis example of the ESI corpus.
#[test]
fn simulate_refuses_modules_the_esi_device_does_not_allow() {
    use process_support::EDSGEN;
    let run = |args: &[&str]| {
        let out = std::process::Command::new(EDSGEN)
            .args(args)
            .output()
            .expect("edsgen runs");
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    };
    assert_eq!(
        run(&["simulate", "some.eds", "--module", "1=X"]),
        (
            Some(2),
            "error: --module goes with --profibus, --ethercat or --profinet\n".to_owned()
        )
    );
    let Some(corpus) = process_support::esi_corpus_dir() else {
        return;
    };
    let file = corpus.join(
        "synapticon__siitool/examples__ModulesSlots_DS402_Simple__ETG2001_ModulesSlots_CiA402.xml",
    );
    let file = file.to_str().expect("a path");
    let (code, stderr) = run(&[
        "simulate",
        "--ethercat",
        "no-such-interface",
        file,
        "--allow",
        "EDS307",
        "--module",
        "3=#x100",
        "--module",
        "1=#x999",
    ]);
    assert_eq!(code, Some(2), "{stderr}");
    assert_eq!(
        stderr,
        format!(
            "error: {file}: --module (EDS708): slot 3: the device has slots 1 to 2; no module \
             \"#x999\"; did you mean:\n  \"Position Mode\"\n  \"Position Mode\"\n  \
             \"Velocity Mode\"\n"
        )
    );
}
