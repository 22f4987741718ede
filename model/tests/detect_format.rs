//! Which reader a file goes to: an `.eds` is an ODVA EDS when a line is a `[File]` or `[Device]`
//! header (white space around the name and before the `[` allowed, any case), else CiA 306.

use std::path::Path;

use edsgen_model::model::Format;
use edsgen_model::read::detect_format;

fn format_of(text: &[u8]) -> Format {
    detect_format(Path::new("x.eds"), text)
}

#[test]
fn odva_headers_anywhere_in_the_file_with_white_space_and_any_case() {
    for text in [
        &b"[File]\n"[..],
        b"; c\r\n[FileInfo]\r\n  \t[ device ] ; comment\r\n",
        b"[DeviceInfo]\nA=1\n\x0B[FILE]",
        b"x=\xE9\n[Device]",
        // Non-ASCII before the `]`: the line decoded alone (U+00A0 is white space).
        b"[\xC2\xA0File]\n",
        b"\xC2\xA0[File]\n",
    ] {
        assert_eq!(
            format_of(text),
            Format::OdvaEds,
            "{:?}",
            String::from_utf8_lossy(text)
        );
    }
}

#[test]
fn cia306_headers_and_near_misses_are_not_odva() {
    for text in [
        &b"[FileInfo]\n[DeviceInfo]\n"[..],
        b"x[File]\n",
        b"; [File]\n",
        b"][File]\n",
        b"[File\xE9]\n",
        b"\xE9[File]\n",
        b"[Fi\nle]\n",
        b"[Files]",
        b"",
        b"[",
    ] {
        assert_eq!(
            format_of(text),
            Format::Eds,
            "{:?}",
            String::from_utf8_lossy(text)
        );
    }
    assert_eq!(detect_format(Path::new("x.DCF"), b"[File]"), Format::Dcf);
}
