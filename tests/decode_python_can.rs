//! `edsgen decode` on logs written by a third party: python-can 4.6.1's own writers (pinned in
//! the venv) write one CANopen session as candump -L, Vector ASC, PCAN TRC 1.0 and 2.1
//! (`scripts/write_can_logs.py`), and each decodes to the same text; what a writer kept and the
//! decoder skips (CAN FD, error frames) is counted on standard error.

mod process_support;

use std::process::Command;

use process_support::{python, root, EDSGEN};

/// The session as the decoder tells it (the script's frames, node 5, no description).
const SESSION: &str = "\
1764000000.000000  000  NMT        start node 5
1764000000.001000  705  HEARTBEAT  node 5 pre-operational
1764000000.003000  585  SDO        node 5 write 1017:00 = E8 03
1764000000.005000  585  SDO        node 5 read 1018:01 = 78 56 34 12
1764000000.011000  585  SDO        node 5 read 1008:00 = 65 64 73 67 65 6E 2D 6C 6F 67 (segmented, 10 bytes)
1764000000.012000  7E5  LSS        switch state global: configuration
1764000000.013000  7E5  LSS        inquire vendor-ID
1764000000.014000  7E4  LSS        vendor-ID = 0x00000123
1764000000.015000  080  SYNC
1764000000.016000  185  TPDO1      node 5 01 02
1764000000.017000  085  EMCY       node 5 8110 CAN overrun (objects lost); register 11h (generic, communication); manufacturer 00 00 00 00 00
1764000000.018000  18FF0005  RAW        AA
1764000000.021000  705  HEARTBEAT  node 5 operational
";

#[test]
fn logs_written_by_python_can_in_every_format_decode_to_the_same_text() {
    let Some(python) = python() else {
        return;
    };
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("decode-python-can-{}", std::process::id()));
    let written = Command::new(&python)
        .arg(root().join("scripts/write_can_logs.py"))
        .arg(&dir)
        // The ASC writer dates its triggerblock in local time; the decoder reads it as UTC.
        .env("TZ", "UTC")
        .output()
        .expect("run scripts/write_can_logs.py");
    assert!(
        written.status.success(),
        "{}",
        String::from_utf8_lossy(&written.stderr)
    );
    let skipped = "warning: skipped 1 CAN FD frame(s)\n\
                   warning: skipped 1 error frame(s) and bus status line(s)\n";
    // python-can's TRC writer leaves CAN FD and error frames out.
    let cases = [
        ("session.log", skipped),
        ("session.asc", skipped),
        ("session-1.0.trc", ""),
        ("session-2.1.trc", ""),
    ];
    for (file, stderr) in cases {
        let out = Command::new(EDSGEN)
            .arg("decode")
            .arg(dir.join(file))
            .output()
            .unwrap();
        assert_eq!(
            (
                out.status.code(),
                String::from_utf8_lossy(&out.stdout).as_ref(),
                String::from_utf8_lossy(&out.stderr).as_ref()
            ),
            (Some(0), SESSION, stderr),
            "{file}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
