//! The INVT Goodrive350's PKW/PZD protocol, one protocol on three buses: the PROFIBUS-DP card
//! (manual chapter 2), the PROFINET card (chapter 4) and the EtherNet/IP card (chapter 5) carry
//! the same 16 words each way. Wire types only, `no_std`, no allocation:
//!
//! - [`pkw`]: the parameter channel, PKW1–PKW4: a [`PkwRequest`] (task, parameter address,
//!   value) and a [`PkwResponse`] (response code, value or error number 1..9), from and to four
//!   words (Tables 2-9 to 2-11, 5-11, 5-12).
//! - [`control`]: the control word and status word as typed fields (Tables 2-5 and 2-7, and the
//!   EtherNet/IP card's by-bit Tables 5-6 and 5-9 that P16.56 = 1 selects).
//! - [`image`]: the 16-word images (PKW1–PKW4, CW or SW, PZD2–PZD12) from and to bytes, with the
//!   byte order as a parameter (big-endian on PROFIBUS and PROFINET).
//!
//! These codes are INVT's, not PROFIdrive's: PROFIdrive packs a task ID into bits 15–12 of PKW1
//! with the parameter number below it, and its request 4 means "request description". A
//! PROFIdrive decoder misreads every Goodrive350 reply; these types do not.
//!
//! No bus-neutral image trait: the three cards carry the same two fixed 32-byte images, so
//! [`OutputImage`] and [`InputImage`] with a [`ByteOrder`] serve all three.

pub mod control;
pub mod image;
pub mod pkw;

pub use control::{Command, ControlWord, RunState, RunStopMode, StatusWord, WordLayout};
pub use image::{ByteOrder, InputImage, OutputImage, IMAGE_BYTES, IMAGE_WORDS, PZD_WORDS};
pub use pkw::{ErrorNumber, PkwRequest, PkwResponse, ResponseError, Task};
