//! The hub and a python-can 4.6.1 client that stops reading (pinned in the venv of
//! `scripts/python-venv.sh`): the hub drops the oldest frames waiting for it rather than
//! disconnecting it, tells it with a socketcand error frame of class 004 (what python-can reads
//! as an error frame; any other `< error ... >` text would kill its receive thread), and once it
//! reads again it gets the error frame and then the newest frames, the last sent included.

mod process_support;

use std::io::Write;
use std::net::TcpStream;
use std::time::{Duration, Instant};

use edsgen_host::hub::{Hub, HubOptions, OVERFLOW_ERROR_CLASS};
use process_support::{python, Process};
use serde_json::{json, Value};

const WAIT: Duration = Duration::from_secs(60);

#[test]
fn a_python_can_client_that_stops_reading_is_told_of_the_drops_and_reads_on() {
    let Some(python) = python() else {
        return;
    };
    let options = HubOptions {
        queue_limit: 1000,
        ..HubOptions::default()
    };
    let hub = Hub::start("127.0.0.1:0", options).unwrap();
    let port = hub.local_addr().port().to_string();
    let mut reader = Process::python(&python, "scripts/hub_slow_reader.py", &["127.0.0.1", &port]);
    reader.stdout_line(|l| l == "READY", WAIT);
    // A sender that floods the bus until the hub drops frames for the python client.
    let mut sender = TcpStream::connect(hub.local_addr()).unwrap();
    sender.write_all(b"< open can0 >< rawmode >").unwrap();
    let deadline = Instant::now() + WAIT;
    let mut sent = 0u32;
    while hub.frames_dropped() == 0 {
        assert!(
            Instant::now() < deadline,
            "no frame dropped after {sent} sent"
        );
        let batch: String = (sent..sent + 500)
            .map(|k| {
                let [b0, b1, b2, b3] = k.to_le_bytes();
                format!("< send 181 4 {b0:x} {b1:x} {b2:x} {b3:x} >")
            })
            .collect();
        sender.write_all(batch.as_bytes()).unwrap();
        sent += 500;
    }
    sender.write_all(b"< send 7FF 1 aa >").unwrap();
    // The last frame reaches the hub before the python client reads again.
    while hub.frames_relayed() < u64::from(sent) + 1 {
        assert!(
            Instant::now() < deadline,
            "the hub did not take every frame"
        );
        std::thread::yield_now();
    }
    reader.send_line("read");
    let line = reader.stdout_line(|l| l.starts_with("RESULT "), WAIT);
    let result: Value = serde_json::from_str(line.strip_prefix("RESULT ").unwrap()).unwrap();
    assert_eq!(result["last"], json!(0x7FF), "{result}");
    assert_eq!(
        result["error_ids"],
        json!([OVERFLOW_ERROR_CLASS]),
        "{result}"
    );
    let (frames, errors) = (
        result["frames"].as_u64().unwrap(),
        result["errors"].as_u64().unwrap(),
    );
    assert!(errors >= 1, "{result}");
    // Every frame either reached the client or was counted as dropped.
    // (The newest frame reaching it shows that it was never disconnected.)
    assert_eq!(
        frames + hub.frames_dropped(),
        u64::from(sent) + 1,
        "{result}"
    );
}
