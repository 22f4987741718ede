//! Fuzz the socketcand codec as a peer drives it: any bytes, cut into reads of any size, through
//! the `MessageScanner` and `Message::parse` (what the hub does with a client's bytes and the
//! client with the server's).
//!
//! Properties: nothing panics; the scanner's bodies hold no `<` or `>`; and every message that
//! parses re-emits to text that scans back to one body which parses to the same message (a
//! round trip). The dialect's one loss is accounted for: it has no remote flag, so a `frame`
//! message never carries one and a `send` marks it by a length without bytes, which
//! `Message::parse` never reads as a remote request of length 0.
//!
//! The first input byte sets the read size (1 to 64 bytes); the rest is the stream.
#![no_main]

use edsgen_host::socketcand::{Message, MessageScanner};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|input: &[u8]| {
    let Some((&cut, stream)) = input.split_first() else {
        return;
    };
    let read_size = usize::from(cut % 64) + 1;
    let mut scanner = MessageScanner::new();
    for read in stream.chunks(read_size) {
        scanner.push(read);
        while let Some(body) = scanner.next_message() {
            assert!(
                !body.contains(&b'<') && !body.contains(&b'>'),
                "a body with a bracket: {body:?}"
            );
            if let Ok(message) = Message::parse(&body) {
                round_trip(&message);
            }
        }
    }
    let _ = scanner.has_partial();
});

/// Emits `message`, scans it back whole, and checks it parses to the same message.
fn round_trip(message: &Message) {
    let mut text = Vec::new();
    message.emit(&mut text);
    let mut scanner = MessageScanner::new();
    scanner.push(&text);
    let body = scanner
        .next_message()
        .unwrap_or_else(|| panic!("{message:?} emitted as {text:?}: no message in it"));
    assert_eq!(
        scanner.next_message(),
        None,
        "{message:?} emitted as {text:?}: more than one message"
    );
    let again = Message::parse(&body)
        .unwrap_or_else(|e| panic!("{message:?} emitted as {text:?} does not parse: {e}"));
    assert_eq!(
        &again,
        message,
        "emitted as {:?}",
        String::from_utf8_lossy(&text)
    );
}
