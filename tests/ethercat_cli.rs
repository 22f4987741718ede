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
