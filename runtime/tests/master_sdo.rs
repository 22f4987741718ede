//! The SDO client against the device's SDO server on the virtual bus: every transfer type both
//! ways with exact frames, typed reads and writes, aborts in both directions, the timeout, and
//! several servers served in parallel.

mod master_support;
mod node_support;

use edsgen_host::vbus::{BusDevice, ScriptedPeer, VirtualBus};
#[cfg(feature = "sdo-block")]
use edsgen_runtime::master::Transfer;
use edsgen_runtime::master::{Completed, Mode, SdoClient, SdoError};
use edsgen_runtime::node::Node;
use edsgen_runtime::wire::sdo::abort_meaning;
use edsgen_runtime::wire::sdo::Multiplexer;
use edsgen_runtime::Entry;
#[cfg(feature = "sdo-block")]
use master_support::pattern;
use master_support::DomainServer;
use node_support::node_od::TestOd;
use node_support::{frame, ms, show};

const WORD: Entry<u16> = Entry::new(0x2000, 0);
const CONST_WORD: Entry<u32> = Entry::new(0x2003, 0);
const DOMAIN: Multiplexer = Multiplexer::new(0x2100, 0);

/// The frames sent since the last call, as text, with their senders' index.
fn frames(bus: &mut VirtualBus) -> Vec<String> {
    bus.take_log().iter().map(|(_, _, f)| show(f)).collect()
}

/// Runs the bus in 1 ms steps until the client has a result, feeding `source` into a download
/// (and ending it there) and draining an upload into the returned bytes.
fn run_transfer<const B: usize>(
    bus: &mut VirtualBus,
    client: &mut SdoClient<B>,
    server: &mut dyn BusDevice,
    mut source: &[u8],
) -> (Result<Completed, SdoError>, Vec<u8>) {
    let mut received = Vec::new();
    for _ in 0..100_000 {
        let taken = client.write_data(source);
        source = &source[taken..];
        if source.is_empty() {
            // The end of a value of unannounced size (no effect on a sized one).
            client.end_data();
        }
        let mut chunk = [0u8; 100];
        loop {
            let n = client.read_data(&mut chunk);
            if n == 0 {
                break;
            }
            received.extend_from_slice(&chunk[..n]);
        }
        let until = bus.now() + edsgen_runtime::Duration::from_millis(1);
        bus.run_until(until, &mut [client, server]);
        if let Some(result) = client.poll_result() {
            let mut rest = vec![0u8; client.available()];
            client.read_data(&mut rest);
            received.extend(rest);
            return (result, received);
        }
    }
    panic!("no result");
}

#[test]
fn a_typed_expedited_write_and_read_match_the_manuals_frames() {
    let mut node = Node::new(TestOd::new(3), 3, ms(0)).unwrap();
    let mut client = SdoClient::<32>::new(3);
    let mut bus = VirtualBus::new(ms(0));
    bus.run_until(ms(1), &mut [&mut client, &mut node]);
    bus.take_log();

    client.write(ms(1), WORD, &0x1234).unwrap();
    bus.run_until(ms(2), &mut [&mut client, &mut node]);
    let done = client.poll_result().unwrap().unwrap();
    assert_eq!(
        (done.mux, done.size, done.upload),
        (Multiplexer::new(0x2000, 0), 2, false)
    );
    client.read(ms(2), WORD).unwrap();
    bus.run_until(ms(3), &mut [&mut client, &mut node]);
    assert!(client.poll_result().unwrap().is_ok());
    let value: u16 = client.take_value(&WORD).unwrap();
    assert_eq!(value, 0x1234);
    assert_eq!(
        frames(&mut bus),
        [
            "603: 2B 00 20 00 34 12 00 00",
            "583: 60 00 20 00 00 00 00 00",
            "603: 40 00 20 00 00 00 00 00",
            "583: 4B 00 20 00 34 12 00 00",
        ]
    );
}

#[test]
fn a_server_abort_is_the_result_with_its_code_and_meaning() {
    let mut node = Node::new(TestOd::new(3), 3, ms(0)).unwrap();
    let mut client = SdoClient::<32>::new(3);
    let mut bus = VirtualBus::new(ms(0));
    bus.run_until(ms(1), &mut [&mut client, &mut node]);
    bus.take_log();
    client.write(ms(1), CONST_WORD, &7).unwrap();
    bus.run_until(ms(2), &mut [&mut client, &mut node]);
    let error = client.poll_result().unwrap().unwrap_err();
    assert_eq!(error, SdoError::Server(0x0601_0002));
    assert_eq!(
        abort_meaning(error.code()),
        Some("attempt to write a read-only object")
    );
    assert_eq!(
        frames(&mut bus),
        [
            "603: 23 03 20 00 07 00 00 00",
            "583: 80 03 20 00 02 00 01 06",
        ]
    );
    // The channel is free again.
    assert!(!client.is_busy());
}

#[test]
fn no_answer_ends_in_abort_0504_0000_after_the_timeout_set_per_node() {
    let mut client = SdoClient::<32>::new(9);
    client.set_timeout(edsgen_runtime::Duration::from_millis(300));
    let mut bus = VirtualBus::new(ms(0));
    client.read(ms(0), WORD).unwrap();
    bus.run_until(ms(299), &mut [&mut client]);
    assert_eq!(client.poll_result(), None);
    bus.run_until(ms(400), &mut [&mut client]);
    assert_eq!(client.poll_result(), Some(Err(SdoError::Timeout)));
    let log: Vec<(u64, String)> = bus
        .take_log()
        .iter()
        .map(|(t, _, f)| (t.as_micros() / 1000, show(f)))
        .collect();
    assert_eq!(
        log,
        [
            (0, "609: 40 00 20 00 00 00 00 00".to_string()),
            (300, "609: 80 00 20 00 00 00 04 05".to_string()),
        ]
    );
}

#[test]
fn a_wrong_toggle_bit_makes_the_client_abort_0503_0000() {
    let mut client = SdoClient::<32>::new(5);
    let mut server = ScriptedPeer::new();
    // Initiate upload answered with 10 bytes to come, then a segment with toggle 1 first.
    server.send_at(ms(1), frame(0x585, &[0x41, 0x00, 0x21, 0x00, 10, 0, 0, 0]));
    server.send_at(ms(2), frame(0x585, &[0x10, 1, 2, 3, 4, 5, 6, 7]));
    let mut bus = VirtualBus::new(ms(0));
    client.upload(ms(0), DOMAIN, Mode::Normal).unwrap();
    bus.run_until(ms(3), &mut [&mut client, &mut server]);
    assert_eq!(
        client.poll_result(),
        Some(Err(SdoError::Client(0x0503_0000)))
    );
    assert_eq!(
        frames(&mut bus),
        [
            "605: 40 00 21 00 00 00 00 00",
            "585: 41 00 21 00 0A 00 00 00",
            "605: 60 00 00 00 00 00 00 00",
            "585: 10 01 02 03 04 05 06 07",
            "605: 80 00 21 00 00 00 03 05",
        ]
    );
}

#[test]
fn a_segmented_download_and_upload_of_a_domain_match_the_manuals_frames() {
    let mut server = DomainServer::new(4);
    let mut client = SdoClient::<32>::new(4);
    let mut bus = VirtualBus::new(ms(0));
    let value = b"edsgen master";
    client.download(ms(0), DOMAIN, 13, Mode::Normal).unwrap();
    let (result, _) = run_transfer(&mut bus, &mut client, &mut server, value);
    assert_eq!(result.unwrap().size, 13);
    assert_eq!(server.od.domain, value);
    client.upload(bus.now(), DOMAIN, Mode::Normal).unwrap();
    let (result, read) = run_transfer(&mut bus, &mut client, &mut server, &[]);
    assert_eq!(result.unwrap().size, 13);
    assert_eq!(read, value);
    assert_eq!(
        frames(&mut bus),
        [
            "604: 21 00 21 00 0D 00 00 00",
            "584: 60 00 21 00 00 00 00 00",
            "604: 00 65 64 73 67 65 6E 20",
            "584: 20 00 00 00 00 00 00 00",
            "604: 13 6D 61 73 74 65 72 00",
            "584: 30 00 00 00 00 00 00 00",
            "604: 40 00 21 00 00 00 00 00",
            "584: 41 00 21 00 0D 00 00 00",
            "604: 60 00 00 00 00 00 00 00",
            "584: 00 65 64 73 67 65 6E 20",
            "604: 70 00 00 00 00 00 00 00",
            "584: 13 6D 61 73 74 65 72 00",
        ]
    );
}

#[cfg(feature = "sdo-block")]
#[test]
fn a_block_download_and_upload_of_64_kib_stream_through_the_window_with_crc() {
    let mut server = DomainServer::new(6);
    let mut client: SdoClient = SdoClient::new(6);
    let mut bus = VirtualBus::new(ms(0));
    let value = pattern(64 * 1024);
    client
        .download(ms(0), DOMAIN, value.len() as u32, Mode::Block)
        .unwrap();
    let (result, _) = run_transfer(&mut bus, &mut client, &mut server, &value);
    assert_eq!(result.unwrap().size, 65536);
    assert!(server.od.domain == value, "the server holds the value sent");
    let sent = frames(&mut bus);
    assert_eq!(sent[0], "606: C6 00 21 00 00 00 01 00");
    // 65536 bytes: 9363 segments, the last with two bytes (5 unused), CRC over the value.
    let crc = crc16(&value);
    assert_eq!(
        sent[sent.len() - 2],
        format!("606: D5 {:02X} {:02X} 00 00 00 00 00", crc as u8, crc >> 8)
    );
    assert_eq!(sent.len(), 1 + 1 + 9363 + 74 + 2);

    client.upload(bus.now(), DOMAIN, Mode::Block).unwrap();
    let (result, read) = run_transfer(&mut bus, &mut client, &mut server, &[]);
    assert_eq!(result.unwrap().size, 65536);
    assert!(read == value, "the client read the value back");
    let sent = frames(&mut bus);
    assert_eq!(sent[0], "606: A4 00 21 00 7F 00 00 00");
    assert_eq!(sent[sent.len() - 1], "606: A1 00 00 00 00 00 00 00");
}

#[test]
fn a_segmented_download_of_unannounced_size_leaves_the_size_bit_clear() {
    let mut server = DomainServer::new(4);
    let mut client = SdoClient::<32>::new(4);
    let mut bus = VirtualBus::new(ms(0));
    // 14 bytes: two full segments, the second one the last (n = 0, c = 1).
    let value = b"edsgen streams";
    client
        .download_unsized(ms(0), DOMAIN, Mode::Normal)
        .unwrap();
    let (result, _) = run_transfer(&mut bus, &mut client, &mut server, value);
    assert_eq!(result.unwrap().size, 14);
    assert_eq!(server.od.domain, value);
    assert_eq!(
        frames(&mut bus),
        [
            "604: 20 00 21 00 00 00 00 00",
            "584: 60 00 21 00 00 00 00 00",
            "604: 00 65 64 73 67 65 6E 20",
            "584: 20 00 00 00 00 00 00 00",
            "604: 11 73 74 72 65 61 6D 73",
            "584: 30 00 00 00 00 00 00 00",
        ]
    );
}

#[test]
fn a_segment_of_unannounced_size_waits_until_it_is_known_whether_it_is_the_last() {
    let mut client = SdoClient::<32>::new(4);
    let response = |data: [u8; 8]| frame(0x584, &data);
    client
        .download_unsized(ms(0), DOMAIN, Mode::Normal)
        .unwrap();
    let initiate = client.poll_transmit(ms(0)).unwrap();
    assert_eq!(show(&initiate), "604: 20 00 21 00 00 00 00 00");
    client.handle_frame(ms(1), &response([0x60, 0x00, 0x21, 0x00, 0, 0, 0, 0]));
    assert_eq!(client.write_data(b"1234567"), 7);
    assert_eq!(
        client.poll_transmit(ms(1)),
        None,
        "7 bytes: the last or not?"
    );
    assert_eq!(client.write_data(b"8"), 1);
    let first = client.poll_transmit(ms(1)).unwrap();
    assert_eq!(show(&first), "604: 00 31 32 33 34 35 36 37");
    client.handle_frame(ms(2), &response([0x20, 0, 0, 0, 0, 0, 0, 0]));
    assert_eq!(
        client.poll_transmit(ms(2)),
        None,
        "1 byte: the last or not?"
    );
    client.end_data();
    assert_eq!(client.write_data(b"9"), 0, "the value has ended");
    let last = client.poll_transmit(ms(2)).unwrap();
    assert_eq!(show(&last), "604: 1D 38 00 00 00 00 00 00");
    client.handle_frame(ms(3), &response([0x30, 0, 0, 0, 0, 0, 0, 0]));
    let done = client.poll_result().unwrap().unwrap();
    assert_eq!((done.size, done.upload), (8, false));
}

#[cfg(feature = "sdo-block")]
#[test]
fn a_block_download_of_unannounced_size_tells_the_size_in_the_end_frame() {
    let mut server = DomainServer::new(6);
    let mut client = SdoClient::<32>::new(6);
    let mut bus = VirtualBus::new(ms(0));
    let value: Vec<u8> = (1..=20).collect();
    client.download_unsized(ms(0), DOMAIN, Mode::Block).unwrap();
    let (result, _) = run_transfer(&mut bus, &mut client, &mut server, &value);
    assert_eq!(result.unwrap().size, 20);
    assert_eq!(server.od.domain, value);
    // No size in the initiate request (C4: s clear); three segments, the last with 6 bytes, so
    // the end request says 1 byte unused (C5: n = 1).
    let [lo, hi] = crc16(&value).to_le_bytes();
    assert_eq!(
        frames(&mut bus),
        [
            "606: C4 00 21 00 00 00 00 00".to_string(),
            "586: A4 00 21 00 7F 00 00 00".into(),
            "606: 01 01 02 03 04 05 06 07".into(),
            "606: 02 08 09 0A 0B 0C 0D 0E".into(),
            "606: 83 0F 10 11 12 13 14 00".into(),
            "586: A2 03 7F 00 00 00 00 00".into(),
            format!("606: C5 {lo:02X} {hi:02X} 00 00 00 00 00"),
            "586: A1 00 00 00 00 00 00 00".into(),
        ]
    );
}

/// Found by the sdo_client fuzz target: the block download's end state was not counted as a
/// download, so its result said `upload: true`.
#[cfg(feature = "sdo-block")]
#[test]
fn a_completed_block_download_is_reported_as_a_download() {
    let mut server = DomainServer::new(6);
    let mut client = SdoClient::<32>::new(6);
    let mut bus = VirtualBus::new(ms(0));
    let value: Vec<u8> = (1..=20).collect();
    client.download(ms(0), DOMAIN, 20, Mode::Block).unwrap();
    let (result, _) = run_transfer(&mut bus, &mut client, &mut server, &value);
    assert_eq!(
        result,
        Ok(Completed {
            mux: DOMAIN,
            size: 20,
            upload: false,
            transfer: Transfer::Block,
        })
    );
    assert_eq!(server.od.domain, value);
}

#[cfg(feature = "sdo-block")]
#[test]
fn a_block_download_of_64_kib_of_unannounced_size_streams_through_the_window() {
    let mut server = DomainServer::new(6);
    let mut client: SdoClient = SdoClient::new(6);
    let mut bus = VirtualBus::new(ms(0));
    let value = pattern(64 * 1024);
    client.download_unsized(ms(0), DOMAIN, Mode::Block).unwrap();
    let (result, _) = run_transfer(&mut bus, &mut client, &mut server, &value);
    assert_eq!(result.unwrap().size, 65536);
    assert!(server.od.domain == value, "the server holds the value sent");
    let sent = frames(&mut bus);
    assert_eq!(sent[0], "606: C4 00 21 00 00 00 00 00");
    // 9363 segments, the last with two bytes (5 unused).
    let crc = crc16(&value);
    assert_eq!(
        sent[sent.len() - 2],
        format!("606: D5 {:02X} {:02X} 00 00 00 00 00", crc as u8, crc >> 8)
    );
    assert_eq!(sent[sent.len() - 1], "586: A1 00 00 00 00 00 00 00");
}

#[cfg(feature = "sdo-block")]
#[test]
fn a_block_upload_of_a_small_value_switches_to_expedited_under_the_threshold() {
    let mut server = DomainServer::new(6);
    server.od.word = 0xBEEF;
    let mut client: SdoClient = SdoClient::new(6);
    client.set_protocol_switch_threshold(4);
    let mut bus = VirtualBus::new(ms(0));
    client
        .upload(ms(0), Multiplexer::new(0x2101, 0), Mode::Block)
        .unwrap();
    let (result, read) = run_transfer(&mut bus, &mut client, &mut server, &[]);
    assert_eq!(result.unwrap().size, 2);
    assert_eq!(read, [0xEF, 0xBE]);
    assert_eq!(
        frames(&mut bus),
        [
            "606: A4 01 21 00 7F 04 00 00",
            "586: 4B 01 21 00 EF BE 00 00"
        ]
    );
}

#[cfg(feature = "sdo-block")]
#[test]
fn a_block_download_aborted_by_the_server_ends_with_its_code() {
    let mut server = DomainServer::new(6);
    let mut client: SdoClient = SdoClient::new(6);
    let mut bus = VirtualBus::new(ms(0));
    // 2101h is an UNSIGNED16: 9 bytes are too many.
    client
        .download(ms(0), Multiplexer::new(0x2101, 0), 9, Mode::Block)
        .unwrap();
    let (result, _) = run_transfer(&mut bus, &mut client, &mut server, &[1; 9]);
    assert_eq!(result, Err(SdoError::Server(0x0607_0012)));
}

/// CiA 301 lets a server answer a block upload request with a normal (here segmented) upload:
/// the result says which transfer the value took.
#[cfg(feature = "sdo-block")]
#[test]
fn a_block_upload_answered_segmented_or_by_block_says_which() {
    let mut client: SdoClient = SdoClient::new(5);
    let mut server = ScriptedPeer::new();
    server.send_at(ms(1), frame(0x585, &[0x41, 0x00, 0x21, 0x00, 10, 0, 0, 0]));
    server.send_at(ms(2), frame(0x585, &[0x00, 1, 2, 3, 4, 5, 6, 7]));
    server.send_at(ms(3), frame(0x585, &[0x19, 8, 9, 10, 0, 0, 0, 0]));
    let mut bus = VirtualBus::new(ms(0));
    client.upload(ms(0), DOMAIN, Mode::Block).unwrap();
    bus.run_until(ms(4), &mut [&mut client, &mut server]);
    assert_eq!(
        client.poll_result(),
        Some(Ok(Completed {
            mux: DOMAIN,
            size: 10,
            upload: true,
            transfer: Transfer::Segmented,
        }))
    );
    assert_eq!(
        frames(&mut bus),
        [
            "605: A4 00 21 00 7F 00 00 00",
            "585: 41 00 21 00 0A 00 00 00",
            "605: 60 00 00 00 00 00 00 00",
            "585: 00 01 02 03 04 05 06 07",
            "605: 70 00 00 00 00 00 00 00",
            "585: 19 08 09 0A 00 00 00 00",
        ]
    );

    let mut client: SdoClient = SdoClient::new(5);
    let mut server = ScriptedPeer::new();
    server.send_at(ms(1), frame(0x585, &[0xC2, 0x00, 0x21, 0x00, 3, 0, 0, 0]));
    server.send_at(ms(2), frame(0x585, &[0x81, 1, 2, 3, 0, 0, 0, 0]));
    server.send_at(ms(3), frame(0x585, &[0xD1, 0, 0, 0, 0, 0, 0, 0]));
    let mut bus = VirtualBus::new(ms(0));
    client.upload(ms(0), DOMAIN, Mode::Block).unwrap();
    bus.run_until(ms(4), &mut [&mut client, &mut server]);
    assert_eq!(
        client
            .poll_result()
            .map(|r| r.map(|done| (done.size, done.transfer))),
        Some(Ok((3, Transfer::Block)))
    );
    assert_eq!(
        frames(&mut bus)[6..],
        ["605: A1 00 00 00 00 00 00 00".to_string()]
    );
}

#[cfg(feature = "sdo-block")]
#[test]
fn a_block_upload_with_a_wrong_crc_is_aborted_0504_0004() {
    let mut client: SdoClient = SdoClient::new(5);
    let mut server = ScriptedPeer::new();
    server.send_at(ms(1), frame(0x585, &[0xC6, 0x00, 0x21, 0x00, 3, 0, 0, 0]));
    server.send_at(ms(2), frame(0x585, &[0x81, 1, 2, 3, 0, 0, 0, 0]));
    server.send_at(ms(3), frame(0x585, &[0xD1, 0x12, 0x34, 0, 0, 0, 0, 0]));
    let mut bus = VirtualBus::new(ms(0));
    client.upload(ms(0), DOMAIN, Mode::Block).unwrap();
    bus.run_until(ms(4), &mut [&mut client, &mut server]);
    assert_eq!(
        client.poll_result(),
        Some(Err(SdoError::Client(0x0504_0004)))
    );
    assert_eq!(
        frames(&mut bus),
        [
            "605: A4 00 21 00 7F 00 00 00",
            "585: C6 00 21 00 03 00 00 00",
            "605: A3 00 00 00 00 00 00 00",
            "585: 81 01 02 03 00 00 00 00",
            "605: A2 01 7F 00 00 00 00 00",
            "585: D1 12 34 00 00 00 00 00",
            "605: 80 00 21 00 04 00 04 05",
        ]
    );
}

#[cfg(feature = "sdo-block")]
#[test]
fn a_lost_block_segment_is_acknowledged_short_and_sent_again() {
    let mut client = SdoClient::<32>::new(5);
    let mut server = ScriptedPeer::new();
    // Block size 3 (the 32-byte window); segment 2 of 3 is lost.
    server.send_at(ms(1), frame(0x585, &[0xC6, 0x00, 0x21, 0x00, 15, 0, 0, 0]));
    server.send_at(ms(2), frame(0x585, &[0x01, 1, 2, 3, 4, 5, 6, 7]));
    server.send_at(ms(2), frame(0x585, &[0x83, 15, 0, 0, 0, 0, 0, 0]));
    server.send_at(ms(3), frame(0x585, &[0x01, 8, 9, 10, 11, 12, 13, 14]));
    server.send_at(ms(3), frame(0x585, &[0x82, 15, 0, 0, 0, 0, 0, 0]));
    let crc = crc16(&(1..=15).collect::<Vec<u8>>());
    server.send_at(
        ms(4),
        frame(0x585, &[0xD9, crc as u8, (crc >> 8) as u8, 0, 0, 0, 0, 0]),
    );
    let mut bus = VirtualBus::new(ms(0));
    client.upload(ms(0), DOMAIN, Mode::Block).unwrap();
    bus.run_until(ms(5), &mut [&mut client, &mut server]);
    assert_eq!(client.poll_result().unwrap().unwrap().size, 15);
    let mut read = [0u8; 20];
    assert_eq!(client.read_data(&mut read), 15);
    assert_eq!(read[..15], (1..=15).collect::<Vec<u8>>()[..]);
    let sent: Vec<String> = frames(&mut bus)
        .into_iter()
        .filter(|f| f.starts_with("605"))
        .collect();
    assert_eq!(
        sent,
        [
            "605: A4 00 21 00 03 00 00 00",
            "605: A3 00 00 00 00 00 00 00",
            "605: A2 01 02 00 00 00 00 00",
            "605: A2 02 02 00 00 00 00 00",
            "605: A1 00 00 00 00 00 00 00",
        ]
    );
}

#[test]
fn clients_of_three_servers_run_their_transfers_at_once() {
    let mut nodes: Vec<_> = [3u8, 4, 5]
        .iter()
        .map(|&id| Node::new(TestOd::new(id), id, ms(0)).unwrap())
        .collect();
    let mut clients: Vec<SdoClient<32>> =
        [3u8, 4, 5].iter().map(|&id| SdoClient::new(id)).collect();
    let mut bus = VirtualBus::new(ms(0));
    for (i, client) in clients.iter_mut().enumerate() {
        client.write(ms(0), WORD, &(100 + i as u16)).unwrap();
    }
    {
        let mut devices: Vec<&mut dyn BusDevice> = Vec::new();
        for node in nodes.iter_mut() {
            devices.push(node);
        }
        for client in clients.iter_mut() {
            devices.push(client);
        }
        bus.run_until(ms(1), &mut devices);
    }
    for (i, node) in nodes.iter().enumerate() {
        assert_eq!(node.od().get(0x2000, 0), 100 + i as u64);
    }
    for client in clients.iter_mut() {
        assert!(client.poll_result().unwrap().is_ok());
    }
    // The three requests go before any answer; each node's boot-up was already queued.
    assert_eq!(
        frames(&mut bus),
        [
            "603: 2B 00 20 00 64 00 00 00",
            "604: 2B 00 20 00 65 00 00 00",
            "605: 2B 00 20 00 66 00 00 00",
            "703: 00",
            "583: 60 00 20 00 00 00 00 00",
            "704: 00",
            "584: 60 00 20 00 00 00 00 00",
            "705: 00",
            "585: 60 00 20 00 00 00 00 00",
        ]
    );
}

#[cfg(feature = "sdo-block")]
/// CRC-16-CCITT (XMODEM), bit by bit: the reference the client's CRC is checked against.
fn crc16(bytes: &[u8]) -> u16 {
    let mut crc = 0u16;
    for &b in bytes {
        crc ^= u16::from(b) << 8;
        for _ in 0..8 {
            crc = if crc & 0x8000 != 0 {
                (crc << 1) ^ 0x1021
            } else {
                crc << 1
            };
        }
    }
    crc
}
