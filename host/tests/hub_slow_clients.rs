//! The socketcand hub under load and beside clients that do not read: nobody is disconnected for
//! being slow, a client that reads loses nothing, the frames dropped for the others are counted,
//! reported to the hub's notices and signalled to them as an error frame; and 50 clients sending
//! 1,000 frames each to one another lose nothing. Each test stops by itself (bounded waits).

use std::io::{Read, Write};
use std::net::TcpStream;
use std::sync::{Arc, Mutex};
use std::thread;
use std::time::{Duration, Instant};

use edsgen_host::hub::{Hub, HubOptions};
use edsgen_host::socketcand::{MessageScanner, SocketcandClient};
use edsgen_host::Transport;
use edsgen_runtime::{CanFrame, CanId};

const WAIT: Duration = Duration::from_secs(10);

/// A client that does python-can's handshake and then only writes (or nothing at all).
fn raw_client(hub: &Hub) -> TcpStream {
    let mut stream = TcpStream::connect(hub.local_addr()).unwrap();
    stream.set_read_timeout(Some(WAIT)).unwrap();
    let reply = |stream: &mut TcpStream, expected: &str| {
        let mut chunk = [0u8; 64];
        let n = stream.read(&mut chunk).unwrap();
        assert_eq!(std::str::from_utf8(&chunk[..n]).unwrap(), expected);
    };
    reply(&mut stream, "< hi >");
    stream.write_all(b"< open can0 >").unwrap();
    reply(&mut stream, "< ok >");
    stream.write_all(b"< rawmode >").unwrap();
    reply(&mut stream, "< ok >");
    stream
}

fn standard_id(frame: &CanFrame) -> u16 {
    match frame.id() {
        CanId::Standard(id) => id,
        CanId::Extended(id) => panic!("extended identifier {id:X}"),
    }
}

fn counted(id: u16, k: u32) -> CanFrame {
    CanFrame::new(id, &k.to_le_bytes()).unwrap()
}

#[test]
fn send_only_and_never_reading_clients_are_not_reset_and_a_reader_loses_nothing() {
    let notices = Arc::new(Mutex::new(Vec::<String>::new()));
    let options = HubOptions {
        queue_limit: 1000,
        notices: Some(Box::new({
            let notices = Arc::clone(&notices);
            move |text| notices.lock().unwrap_or_else(|e| e.into_inner()).push(text)
        })),
        ..HubOptions::default()
    };
    let hub = Hub::start("127.0.0.1:0", options).unwrap();
    let mut reader = SocketcandClient::connect(hub.local_addr(), "can0", WAIT).unwrap();
    let mut senders: Vec<TcpStream> = (0..3).map(|_| raw_client(&hub)).collect();
    let mut never_reads = raw_client(&hub);
    // Rounds of 200 frames from each sender, read by the reader before the next round: the
    // reader keeps up, the other clients' socket buffers and then their outboxes fill.
    let stuck_clients = 4;
    let mut n = 0u32;
    let reported = |notices: &[String]| {
        let clients: std::collections::BTreeSet<&str> = notices
            .iter()
            .filter_map(|n| n.split_once(" reads too slowly").map(|(who, _)| who))
            .collect();
        clients.len()
    };
    while reported(&notices.lock().unwrap()) < stuck_clients {
        assert!(n < 1_000_000, "drops not reported: {:?}", notices.lock());
        for (i, sender) in senders.iter_mut().enumerate() {
            let mut batch = String::new();
            for k in n..n + 200 {
                let [b0, b1, b2, b3] = k.to_le_bytes();
                batch.push_str(&format!("< send 18{i} 4 {b0:x} {b1:x} {b2:x} {b3:x} >"));
            }
            sender.write_all(batch.as_bytes()).unwrap();
        }
        let mut next = [n; 3];
        for _ in 0..600 {
            let frame = reader.recv_timeout(WAIT).unwrap().expect("a frame");
            let i = usize::from(standard_id(&frame) - 0x180);
            assert_eq!(frame, counted(0x180 + i as u16, next[i]), "from sender {i}");
            next[i] += 1;
        }
        assert_eq!(next, [n + 200; 3]);
        n += 200;
    }
    assert_eq!(hub.clients(), 5, "a client was disconnected");
    assert_eq!(hub.frames_relayed(), 3 * u64::from(n));
    assert!(hub.frames_dropped() > 0);
    for notice in notices.lock().unwrap().iter() {
        assert!(
            notice.contains(") reads too slowly: dropped its ") && notice.ends_with(" in all)"),
            "{notice}"
        );
    }
    // The never-reading client is still connected: what it finally reads has the error frame
    // where frames went missing, and ends with the newest frame.
    senders[0].write_all(b"< send 7FF 1 aa >").unwrap();
    let mut scanner = MessageScanner::new();
    let (mut errors, mut last) = (0, Vec::new());
    let deadline = Instant::now() + WAIT;
    while last != b" frame 7FF" {
        assert!(Instant::now() < deadline, "the newest frame never came");
        let mut chunk = [0u8; 65536];
        let read = never_reads.read(&mut chunk).unwrap();
        assert!(read > 0, "the hub closed the never-reading client");
        scanner.push(&chunk[..read]);
        while let Some(body) = scanner.next_message() {
            if body.starts_with(b" error 004 ") {
                errors += 1;
            }
            last = body.get(..10).unwrap_or(&body).to_vec();
        }
    }
    assert!(errors >= 1, "no error frame told the client of the drops");
    assert_eq!(
        reader.recv_timeout(WAIT).unwrap(),
        CanFrame::new(0x7FF, &[0xAA])
    );
    // The send-only clients are still heard.
    for (i, sender) in senders.iter_mut().enumerate() {
        sender
            .write_all(format!("< send 2{i}0 0  >").as_bytes())
            .unwrap();
        assert_eq!(
            reader.recv_timeout(WAIT).unwrap(),
            CanFrame::new(0x200 + 0x10 * i as u16, &[])
        );
    }
    drop(never_reads);
    drop(senders);
    hub.stop();
    let notices = notices.lock().unwrap();
    let left = notices
        .iter()
        .filter(|n| n.contains(" left; ") && n.ends_with(" frame(s) were dropped for it in all"))
        .count();
    assert_eq!(left, stuck_clients, "{notices:?}");
}

#[test]
fn fifty_clients_sending_a_thousand_frames_each_lose_nothing() {
    const CLIENTS: usize = 50;
    const FRAMES: u32 = 1000;
    let hub = Hub::start("127.0.0.1:0", HubOptions::default()).unwrap();
    let clients: Vec<SocketcandClient> = (0..CLIENTS)
        .map(|_| SocketcandClient::connect(hub.local_addr(), "can0", WAIT).unwrap())
        .collect();
    let deadline = Instant::now() + Duration::from_secs(300);
    let threads: Vec<_> = clients
        .into_iter()
        .enumerate()
        .map(|(me, mut client)| {
            thread::spawn(move || {
                let id = 0x100 + me as u16;
                for k in 0..FRAMES {
                    client.send(&counted(id, k)).unwrap();
                }
                // From each other client, its frames in order.
                let mut next = [0u32; CLIENTS];
                let mut received = 0;
                while received < (CLIENTS - 1) * FRAMES as usize {
                    assert!(Instant::now() < deadline, "client {me}: too slow");
                    let frame = client.recv_timeout(WAIT).unwrap().expect("a frame");
                    let from = usize::from(standard_id(&frame) - 0x100);
                    assert_ne!(from, me, "an echo");
                    assert_eq!(frame, counted(0x100 + from as u16, next[from]));
                    next[from] += 1;
                    received += 1;
                }
                next
            })
        })
        .collect();
    for (me, thread) in threads.into_iter().enumerate() {
        let next = thread.join().unwrap();
        for (from, &count) in next.iter().enumerate() {
            assert_eq!(count, if from == me { 0 } else { FRAMES });
        }
    }
    assert_eq!(hub.frames_relayed(), CLIENTS as u64 * u64::from(FRAMES));
    assert_eq!(hub.frames_dropped(), 0);
}
