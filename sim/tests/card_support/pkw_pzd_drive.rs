//! The drive behind a Goodrive350 bus card answering the card's generated images: one scenario
//! for every card that carries the 16-word PKW/PZD images, each card test saying how its images
//! are laid out in bytes and checking its own fields in the answers.

use edsgen_runtime::pkw_pzd::control::cw_bit;
use edsgen_runtime::pkw_pzd::{
    ByteOrder, Command, ControlWord, ErrorNumber, InputImage, OutputImage, PkwRequest, PkwResponse,
    RunState, WordLayout, IMAGE_BYTES,
};
use edsgen_runtime::{Duration, Instant};
use edsgen_sim::drives::pkw_pzd::{Bus, PkwPzdDrive};

/// The drive's answers, as the card's input type reads them.
pub struct Answers<I> {
    /// P00.10 as the drive holds it.
    pub keypad: u16,
    /// To a PKW read of P00.10.
    pub read: I,
    /// To a PKW write of P07.27 (present fault, 0x071B), which is read only.
    pub refused: I,
    /// To run forward with the frequency 2500 in PZD2, at 100 ms and one second later.
    pub first: I,
    pub later: I,
}

/// Sends the drive on `bus` a PKW read of P00.10, a write of the read-only P07.27 (refused with
/// Table 5-12's error 7) and run forward with PZD2 2500, each image as the card's output type
/// lays it out (`encode`, in the bytes' `order`), and reads the answers as its input type does
/// (`decode`). Asserts what the runtime's typed view of them (`typed`) says: P00.10's value,
/// the refusal, the drive running forward.
pub fn drive_answers<I>(
    bus: Bus,
    order: ByteOrder,
    encode: impl Fn(&OutputImage) -> [u8; IMAGE_BYTES],
    decode: impl Fn(&[u8; IMAGE_BYTES]) -> I,
    typed: impl Fn(&I) -> InputImage,
) -> Answers<I> {
    let t0 = Instant::from_micros(0);
    let mut drive = PkwPzdDrive::bus_controlled(bus, t0);
    let mut cycle = |ms: u64, image: &OutputImage| {
        let at = t0 + Duration::from_micros(ms * 1000);
        decode(&drive.exchange_bytes(at, &encode(image), order))
    };
    let read = cycle(
        0,
        &OutputImage {
            pkw: PkwRequest::read(10),
            control: ControlWord(0),
            pzd: [0; 11],
        },
    );
    let refused = cycle(
        50,
        &OutputImage {
            pkw: PkwRequest::write(0x071B, 1),
            control: ControlWord(0).with(cw_bit::ENABLE_WRITE, true),
            pzd: [0; 11],
        },
    );
    let run = OutputImage {
        pkw: PkwRequest::from_words([0; 4]),
        control: ControlWord::new(Command::RunForward, WordLayout::ByByte),
        pzd: [2500, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
    };
    let first = cycle(100, &run);
    let later = cycle(1100, &run);
    let keypad = drive.parameter(10).expect("P00.10");
    assert_eq!(
        typed(&read).pkw,
        PkwResponse::Word {
            address: 10,
            value: keypad
        }
    );
    assert_eq!(
        typed(&refused).pkw,
        PkwResponse::Refused {
            address: 0x071B,
            error: ErrorNumber::ReadOnly
        }
    );
    let status = typed(&later).status;
    assert_eq!(status.state(WordLayout::ByByte), Some(RunState::Forward));
    Answers {
        keypad,
        read,
        refused,
        first,
        later,
    }
}
