//! The card's cyclic exchange against hand-built RT frames: CW commands and a PKW read in the
//! output frame, the drive's answer in the input frame, byte for byte where the manual fixes
//! the bytes; frames of other FrameIDs ignored; the watchdog's E-PN.

use super::*;
use crate::drives::pkw_pzd::Bus;

const DEVICE: Mac = [0x02, 0x00, 0x00, 0x00, 0x03, 0x50];
const CONTROLLER: Mac = [0x02, 0x00, 0x00, 0x00, 0x00, 0x01];
const MS: fn(u64) -> Instant = Instant::from_millis;

fn card() -> CardCycle {
    let layout = card_layout(CONTROLLER, DEVICE, Duration::from_millis(4), 3);
    CardCycle::new(
        layout,
        PkwPzdDrive::bus_controlled(Bus::Profinet, MS(0)),
        MS(0),
    )
}

/// An output frame of `words` (big-endian) with IOPS and IOCS good.
fn output_frame(frame_id: u16, words: [u16; 16]) -> Vec<u8> {
    let mut f = Vec::new();
    f.extend_from_slice(&DEVICE);
    f.extend_from_slice(&CONTROLLER);
    f.extend_from_slice(&[0x88, 0x92]);
    f.extend_from_slice(&frame_id.to_be_bytes());
    for w in words {
        f.extend_from_slice(&w.to_be_bytes());
    }
    f.extend_from_slice(&[0x80, 0x80, 0, 0, 0, 0, 0, 0]); // IOPS, IOCS, padding to 40
    f.extend_from_slice(&[0x00, 0x80, 0x35, 0x00]);
    f
}

/// The input frame's 16 words.
fn input_words(frame: &[u8]) -> [u16; 16] {
    assert_eq!(frame[..12], [CONTROLLER, DEVICE].concat());
    assert_eq!(frame[12..16], [0x88, 0x92, 0xC0, 0x01]);
    let mut words = [0u16; 16];
    for (n, w) in words.iter_mut().enumerate() {
        *w = u16::from_be_bytes([frame[16 + 2 * n], frame[17 + 2 * n]]);
    }
    // IOPS and IOCS good, DataStatus 0x35.
    assert_eq!(frame[48..50], [0x80, 0x80]);
    assert_eq!(frame[58], 0x35);
    words
}

#[test]
fn run_forward_and_a_pkw_read_come_back_in_the_input_frame() {
    let mut card = card();
    // PKW: read (1) P00.10 (address 10); CW 1 = run forward; PZD2 = 5000 (50.00 Hz).
    let mut words = [0u16; 16];
    words[0] = 1;
    words[1] = 10;
    words[4] = 0x0001;
    words[5] = 5000;
    card.handle(MS(1), &output_frame(0xC000, words));
    let frame = card.poll_transmit(MS(1)).expect("an input frame");
    assert_eq!(frame.len(), 14 + 2 + 40 + 4);
    let input = input_words(&frame);
    // Response 1 (one word), P00.10's default 50.00 Hz in PKW4.
    assert_eq!(input[..4], [1, 10, 0, 5000]);
    // SW: running forward (1), ready (bit 8), communication control (bits 13-14 = 2).
    assert_eq!(input[4], 0x4101);
    // The next frame is due one interval later.
    assert_eq!(card.poll_transmit(MS(2)), None);
    assert!(card.poll_transmit(MS(5)).is_some());
}

#[test]
fn other_frame_ids_and_short_frames_change_nothing() {
    let mut card = card();
    let mut words = [0u16; 16];
    words[4] = 0x0001;
    card.handle(MS(1), &output_frame(0xC005, words));
    card.handle(MS(1), &output_frame(0xC000, words)[..40]);
    let input = input_words(&card.poll_transmit(MS(1)).expect("a frame"));
    // Still stopped (3).
    assert_eq!(input[4] & 0xFF, 3);
}

#[test]
fn the_watchdog_trips_e_pn() {
    let mut card = card();
    let mut words = [0u16; 16];
    words[4] = 0x0001;
    words[5] = 5000;
    card.handle(MS(1), &output_frame(0xC000, words));
    // 3 intervals of 4 ms after the last frame.
    assert!(card.poll_timeout() <= MS(13));
    card.handle_timeout(MS(13));
    assert_eq!(card.drive().vfd().fault(), Some(57));
    let input = input_words(&card.poll_transmit(MS(13)).expect("a frame"));
    assert_eq!(input[4] & 0xFF, 4);
}
