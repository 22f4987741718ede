//! EDS029's help names the format the file's name says it is, not the CANopen formats alone.

use std::path::Path;

use edsgen_model::read::read_bytes;

fn help(name: &str) -> Option<String> {
    let read = read_bytes(Path::new(name), b"a\0b");
    assert_eq!(read.diagnostics.len(), 1, "{name}");
    assert_eq!(read.diagnostics[0].rule.code, "EDS029");
    read.diagnostics[0].help.clone()
}

#[test]
fn eds029_help_per_format() {
    assert_eq!(
        help("x.xml").as_deref(),
        Some("an XML description (XDD, XDC, ESI or GSDML) is text (an EtherCAT SII image is a `.bin` or `.sii`); is this the right file?")
    );
    assert_eq!(
        help("x.gsd").as_deref(),
        Some("a GSD is ASCII text; is this the right file?")
    );
    assert_eq!(
        help("x.eds").as_deref(),
        Some("an EDS or DCF is ASCII text; is this the right file?")
    );
    assert_eq!(
        help("x.xdd").as_deref(),
        Some("an XDD or XDC is XML text; is this the right file?")
    );
}
