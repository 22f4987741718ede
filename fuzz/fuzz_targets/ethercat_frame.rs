//! Fuzz the EtherCAT SubDevice with frames: the input is cut into frames (each prefixed by a
//! length byte) sent in turn, at 1 ms steps, to one SubDevice whose application has a mailbox
//! and a 4-byte outputs / 2-byte inputs image, so that frames can configure SyncManagers and
//! FMMUs, drive the AL state machine, the SII interface and the mailbox before later ones.
//!
//! Properties: nothing panics; a frame keeps its length; a frame that is not EtherCAT is neither
//! answered nor changed; an answered frame differs from what came only in datagram data,
//! working counters, ADPs and the source address's locally-administered bit (headers' commands,
//! indices, lengths and the EtherCAT header stay).
#![no_main]

use edsgen_runtime::Instant;
use edsgen_sim::ethercat::frame::{parse, Parsed};
use edsgen_sim::ethercat::{AlState, Application, SubDevice};
use libfuzzer_sys::fuzz_target;

struct App;

impl Application for App {
    fn mailbox(&mut self, _state: AlState, request: &[u8], answer: &mut [u8]) -> usize {
        let len = request.len().min(16).min(answer.len());
        for (a, r) in answer.iter_mut().zip(request[..len].iter().rev()) {
            *a = *r;
        }
        len
    }
    fn image_sizes(&self) -> (usize, usize) {
        (4, 2)
    }
    fn outputs(&mut self, _now: Instant, _outputs: &[u8]) {}
    fn inputs(&mut self, _now: Instant, inputs: &mut [u8]) {
        for (i, b) in inputs.iter_mut().zip([0xAB, 0xCD]) {
            *i = b;
        }
    }
}

/// An SII whose SyncM category (41) gives SM0/SM1 128-byte mailboxes at 0x1000/0x1080, SM2
/// outputs and SM3 inputs; the frames may offer it to the device (0x0500) or not.
fn sii() -> Vec<u8> {
    let mut sii = vec![0x5A; 0x80];
    sii.extend_from_slice(&[41, 0, 16, 0]);
    sii.extend_from_slice(&[0x00, 0x10, 128, 0, 0x26, 0, 1, 1]);
    sii.extend_from_slice(&[0x80, 0x10, 128, 0, 0x22, 0, 1, 2]);
    sii.extend_from_slice(&[0x00, 0x11, 4, 0, 0x64, 0, 1, 3]);
    sii.extend_from_slice(&[0x80, 0x11, 2, 0, 0x20, 0, 1, 4]);
    sii.extend_from_slice(&[0xFF, 0xFF]);
    sii
}

fuzz_target!(|input: &[u8]| {
    let mut device = SubDevice::new(sii(), App);
    let mut rest = input;
    let mut now = 0;
    while let Some((&len, tail)) = rest.split_first() {
        let len = usize::from(len).min(tail.len());
        let mut frame = tail[..len].to_vec();
        rest = &tail[len..];
        let before = frame.clone();
        now += 1_000;
        let answered = device.process_frame(Instant(now), &mut frame);
        assert_eq!(frame.len(), before.len());
        match parse(&before) {
            Parsed::NotEtherCat => {
                assert!(!answered);
                assert_eq!(frame, before);
            }
            Parsed::Datagrams { datagrams, .. } => {
                assert!(answered);
                assert_eq!(frame[..6], before[..6]);
                assert_eq!(frame[6] & !0x02, before[6] & !0x02);
                assert_eq!(frame[7..16], before[7..16]);
                for d in datagrams {
                    let h = d.header_at;
                    assert_eq!(frame[h..h + 2], before[h..h + 2]);
                    assert_eq!(frame[h + 4..h + 10], before[h + 4..h + 10]);
                }
            }
        }
    }
});
