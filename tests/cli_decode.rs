//! `edsgen decode` through the binary: every log format read from standard input, recognised by
//! its content; unreadable lines are warnings with their numbers and reading goes on; bytes that
//! are not UTF-8 never stop it; a log with no frame exits 1; a closed standard output ends it
//! quietly with exit 0.

mod process_support;

use std::io::{BufRead, BufReader, Write};
use std::process::{Command, Output, Stdio};

use process_support::EDSGEN;

/// `edsgen decode ARGS` with `log` on standard input.
fn decode(args: &[&str], log: &[u8]) -> Output {
    let mut child = Command::new(EDSGEN)
        .arg("decode")
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let log = log.to_vec();
    let writer = std::thread::spawn(move || {
        let _ = stdin.write_all(&log);
    });
    let out = child.wait_with_output().unwrap();
    writer.join().unwrap();
    out
}

fn text(bytes: &[u8]) -> &str {
    std::str::from_utf8(bytes).unwrap()
}

#[test]
fn candump_default_output_with_and_without_timestamps() {
    let log = b"  can0  701   [1]  05\n\
                (1700000000.250000)  can0  TX - -  000   [2]  01 05\n\
                (0.500)  can0  705   [1]  remote request\n";
    let out = decode(&[], log);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert_eq!(
        text(&out.stdout),
        "0.000000  701  HEARTBEAT  node 1 operational\n\
         1700000000.250000  000  NMT        start node 5\n\
         0.500000  705  GUARD      node 5 request\n"
    );
    assert_eq!(text(&out.stderr), "");
}

#[test]
fn unreadable_lines_and_bytes_are_warnings_and_the_rest_is_decoded() {
    let log = b"(1700000000.000000) can0 701#05\n\
                (1700000000.001000) can0 701#\xFF\xFE\n\
                garbage\n\
                (1700000000.002000) can0 702#7F\n";
    let out = decode(&[], log);
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(
        text(&out.stdout),
        "1700000000.000000  701  HEARTBEAT  node 1 operational\n\
         1700000000.002000  702  HEARTBEAT  node 2 pre-operational\n"
    );
    assert_eq!(
        text(&out.stderr),
        "warning: line 2: bad candump line: bad data `\u{FFFD}\u{FFFD}`: expected pairs of hex digits\n\
         warning: line 3: bad candump line: expected `(SECONDS) CHANNEL ID#DATA`, found `garbage`\n\
         warning: 1 line(s) held bytes that are not UTF-8 (read as U+FFFD)\n"
    );
}

#[test]
fn many_unreadable_lines_show_the_first_twenty_and_a_count() {
    let mut log = b"(1.0) can0 701#05\n".to_vec();
    for _ in 0..25 {
        log.extend_from_slice(b"(1.0) can0 701#0\n");
    }
    let out = decode(&[], &log);
    assert_eq!(out.status.code(), Some(0));
    let stderr = text(&out.stderr);
    assert_eq!(stderr.lines().count(), 21, "{stderr}");
    assert!(stderr.starts_with(
        "warning: line 2: bad candump line: bad data `0`: expected pairs of hex digits\n"
    ));
    assert!(stderr.ends_with(
        "warning: line 21: bad candump line: bad data `0`: expected pairs of hex digits\n\
         warning: 25 line(s) could not be read in all (the first 20 are shown)\n"
    ));
}

#[test]
fn a_log_with_nothing_to_decode_exits_1() {
    let no_frame = "error: no CAN frame in the log (candump -L or default, Vector ASC and PCAN TRC are read)\n";
    let out = decode(&[], b"");
    assert_eq!((out.status.code(), text(&out.stderr)), (Some(1), no_frame));
    let out = decode(&[], b"hello\n");
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        text(&out.stderr),
        format!("warning: line 1: bad log line: not a line of a log format edsgen reads (candump, ASC, TRC): `hello`\n{no_frame}")
    );
    // Only CAN FD frames: nothing classic to decode.
    let out = decode(&[], b"(1.0) can0 123##1AABB\n");
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        text(&out.stderr),
        format!("warning: skipped 1 CAN FD frame(s)\n{no_frame}")
    );
    assert_eq!(text(&out.stdout), "");
}

#[test]
fn a_closed_standard_output_ends_decoding_quietly() {
    let path = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_decode_long.log");
    let log: String = (0..50_000)
        .map(|i| format!("(1700000000.{i:06}) can0 701#05\n"))
        .collect();
    std::fs::write(&path, log).unwrap();
    let mut child = Command::new(EDSGEN)
        .args(["decode", path.to_str().unwrap()])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut first)
        .unwrap();
    // The reader is dropped: the pipe is closed, as `edsgen decode log | head -1` does.
    assert_eq!(
        first,
        "1700000000.000000  701  HEARTBEAT  node 1 operational\n"
    );
    let out = child.wait_with_output().unwrap();
    assert_eq!(
        (out.status.code(), text(&out.stderr)),
        (Some(0), ""),
        "a panic or an error on a closed pipe"
    );
}

#[test]
fn long_transfers_are_summarised_unless_full_is_given() {
    // A segmented upload of 100 bytes from node 3.
    let mut log = String::from(
        "(1.000000) can0 603#4000200000000000\n(1.001000) can0 583#4100200064000000\n",
    );
    let value: Vec<u8> = (0..100).collect();
    for (i, chunk) in value.chunks(7).enumerate() {
        let toggle = (i % 2) as u8 * 0x10;
        let last = (i + 1) * 7 >= value.len();
        let unused = 7 - chunk.len() as u8;
        let command = toggle | if last { unused << 1 | 1 } else { 0 };
        log.push_str(&format!(
            "(2.{i:06}) can0 603#{:02X}00000000000000\n",
            0x60 | toggle
        ));
        let data: String = chunk.iter().map(|b| format!("{b:02X}")).collect();
        log.push_str(&format!("(2.{i:06}) can0 583#{command:02X}{data}\n"));
    }
    let out = decode(&[], log.as_bytes());
    assert_eq!(
        text(&out.stdout),
        "2.000014  583  SDO        node 3 read 2000:00 = 00 01 02 03 04 05 06 07 08 09 0A 0B 0C 0D 0E 0F ... (segmented, 100 bytes; --full shows all)\n"
    );
    let out = decode(&["--full"], log.as_bytes());
    let hex: Vec<String> = value.iter().map(|b| format!("{b:02X}")).collect();
    assert_eq!(
        text(&out.stdout),
        format!(
            "2.000014  583  SDO        node 3 read 2000:00 = {} (segmented, 100 bytes)\n",
            hex.join(" ")
        )
    );
}
