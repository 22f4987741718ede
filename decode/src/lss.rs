//! Layer setting services (CiA 305) as the decoder prints them: the master's requests on 7E5h
//! and the slaves' responses on 7E4h, by name, with their values and error codes. The first
//! byte is the command specifier; the layouts are those of CiA 305 (values little-endian).

/// The text of an LSS frame: `master` for 7E5h (master to slaves), else 7E4h.
pub fn describe(master: bool, data: &[u8]) -> String {
    let Some((&command, rest)) = data.split_first() else {
        return "(empty)".into();
    };
    let text = if master {
        request(command, rest)
    } else {
        response(command, rest)
    };
    text.unwrap_or_else(|| {
        let who = if master { "request" } else { "response" };
        format!(
            "unknown {who} {command:02X}h: {}",
            super::text::hex_bytes(data)
        )
    })
}

fn u32_at(rest: &[u8], at: usize) -> Option<u32> {
    let bytes = rest.get(at..at + 4)?;
    Some(u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]))
}

/// The identity fields, in the order of the selective and inquire services.
const FIELDS: [&str; 4] = [
    "vendor-ID",
    "product code",
    "revision number",
    "serial number",
];

fn request(command: u8, rest: &[u8]) -> Option<String> {
    Some(match command {
        0x04 => match rest.first()? {
            0 => "switch state global: waiting".into(),
            1 => "switch state global: configuration".into(),
            mode => format!("switch state global: mode {mode} (not 0 or 1)"),
        },
        0x40..=0x43 => format!(
            "switch state selective: {} {:#010X}",
            FIELDS[usize::from(command - 0x40)],
            u32_at(rest, 0)?
        ),
        0x11 => format!("configure node-ID {}", rest.first()?),
        0x13 => {
            let (&table, &index) = (rest.first()?, rest.get(1)?);
            format!("configure bit timing: {}", bit_timing(table, index))
        }
        0x15 => {
            let delay = u16::from_le_bytes([*rest.first()?, *rest.get(1)?]);
            format!("activate bit timing, switch delay {delay} ms")
        }
        0x17 => "store configuration".into(),
        0x46..=0x4B => {
            const BOUNDS: [&str; 6] = [
                "vendor-ID",
                "product code",
                "revision number low",
                "revision number high",
                "serial number low",
                "serial number high",
            ];
            format!(
                "identify remote slave: {} {:#010X}",
                BOUNDS[usize::from(command - 0x46)],
                u32_at(rest, 0)?
            )
        }
        0x4C => "identify non-configured remote slave".into(),
        0x51 => {
            let id = u32_at(rest, 0)?;
            let (bit, sub, next) = (*rest.get(4)?, *rest.get(5)?, *rest.get(6)?);
            if bit == 0x80 {
                "fastscan: reset (are there non-configured slaves?)".into()
            } else {
                let field = |n: u8| FIELDS.get(usize::from(n)).copied().unwrap_or("(no field)");
                format!(
                    "fastscan: {} {id:#010X}, bits 31..{bit} checked, next {}",
                    field(sub),
                    field(next)
                )
            }
        }
        0x5A..=0x5D => format!("inquire {}", FIELDS[usize::from(command - 0x5A)]),
        0x5E => "inquire node-ID".into(),
        _ => return None,
    })
}

fn response(command: u8, rest: &[u8]) -> Option<String> {
    Some(match command {
        0x44 => "switch state selective: the slave is in configuration".into(),
        0x11 => format!(
            "configure node-ID: {}",
            outcome(rest, "node-ID out of range")?
        ),
        0x13 => format!(
            "configure bit timing: {}",
            outcome(rest, "bit timing not supported")?
        ),
        0x17 => format!("store configuration: {}", store_outcome(rest)?),
        0x4F => "identify slave: a slave matches".into(),
        0x50 => "identify non-configured slave: a non-configured slave is there".into(),
        0x5A..=0x5D => format!(
            "{} = {:#010X}",
            FIELDS[usize::from(command - 0x5A)],
            u32_at(rest, 0)?
        ),
        0x5E => match rest.first()? {
            0xFF => "node-ID = FFh (not configured)".into(),
            id => format!("node-ID = {id}"),
        },
        _ => return None,
    })
}

/// An error code of configure node-ID or bit timing: 0 success, 1 the service's own error,
/// FFh implementation specific (with the specific error in the next byte).
fn outcome(rest: &[u8], error_1: &str) -> Option<String> {
    Some(match rest.first()? {
        0 => "success".into(),
        1 => format!("error 1, {error_1}"),
        0xFF => format!(
            "error FFh, implementation specific {:02X}h",
            rest.get(1).copied().unwrap_or(0)
        ),
        code => format!("error {code} (reserved)"),
    })
}

fn store_outcome(rest: &[u8]) -> Option<String> {
    Some(match rest.first()? {
        2 => "error 2, storage media access error".into(),
        _ => outcome(rest, "store configuration not supported")?,
    })
}

/// A bit timing table entry: table 0 is CiA's (CiA 305 table 3).
fn bit_timing(table: u8, index: u8) -> String {
    const RATES: [&str; 10] = [
        "1000 kbit/s",
        "800 kbit/s",
        "500 kbit/s",
        "250 kbit/s",
        "125 kbit/s",
        "(reserved)",
        "50 kbit/s",
        "20 kbit/s",
        "10 kbit/s",
        "automatic bit rate detection",
    ];
    match (table, RATES.get(usize::from(index))) {
        (0, Some(rate)) => format!("{rate} (table 0, index {index})"),
        _ => format!("table {table}, index {index}"),
    }
}

#[cfg(test)]
mod tests {
    use super::describe;

    #[test]
    fn every_request_by_name() {
        let cases: [(&[u8], &str); 20] = [
            (
                &[0x04, 0x01, 0, 0, 0, 0, 0, 0],
                "switch state global: configuration",
            ),
            (&[0x04, 0x00], "switch state global: waiting"),
            (&[0x04, 0x07], "switch state global: mode 7 (not 0 or 1)"),
            (
                &[0x40, 0x78, 0x56, 0x34, 0x12, 0, 0, 0],
                "switch state selective: vendor-ID 0x12345678",
            ),
            (
                &[0x41, 1, 0, 0, 0, 0, 0, 0],
                "switch state selective: product code 0x00000001",
            ),
            (
                &[0x42, 2, 0, 0, 0, 0, 0, 0],
                "switch state selective: revision number 0x00000002",
            ),
            (
                &[0x43, 3, 0, 0, 0, 0, 0, 0],
                "switch state selective: serial number 0x00000003",
            ),
            (&[0x11, 0x05, 0, 0, 0, 0, 0, 0], "configure node-ID 5"),
            (
                &[0x13, 0x00, 0x03, 0, 0, 0, 0, 0],
                "configure bit timing: 250 kbit/s (table 0, index 3)",
            ),
            (
                &[0x13, 0x01, 0x03, 0, 0, 0, 0, 0],
                "configure bit timing: table 1, index 3",
            ),
            (
                &[0x15, 0xE8, 0x03, 0, 0, 0, 0, 0],
                "activate bit timing, switch delay 1000 ms",
            ),
            (&[0x17, 0, 0, 0, 0, 0, 0, 0], "store configuration"),
            (
                &[0x46, 0x78, 0x56, 0x34, 0x12, 0, 0, 0],
                "identify remote slave: vendor-ID 0x12345678",
            ),
            (
                &[0x4B, 0xFF, 0xFF, 0, 0, 0, 0, 0],
                "identify remote slave: serial number high 0x0000FFFF",
            ),
            (
                &[0x4C, 0, 0, 0, 0, 0, 0, 0],
                "identify non-configured remote slave",
            ),
            (
                &[0x51, 0, 0, 0, 0, 0x80, 0, 0],
                "fastscan: reset (are there non-configured slaves?)",
            ),
            (
                &[0x51, 0x00, 0x00, 0x00, 0x12, 24, 0, 0],
                "fastscan: vendor-ID 0x12000000, bits 31..24 checked, next vendor-ID",
            ),
            (
                &[0x51, 0x78, 0x56, 0x34, 0x12, 0, 0, 1],
                "fastscan: vendor-ID 0x12345678, bits 31..0 checked, next product code",
            ),
            (&[0x5D, 0, 0, 0, 0, 0, 0, 0], "inquire serial number"),
            (&[0x5E, 0, 0, 0, 0, 0, 0, 0], "inquire node-ID"),
        ];
        for (data, text) in cases {
            assert_eq!(describe(true, data), text, "{data:02X?}");
        }
        assert_eq!(describe(true, &[0x5A]), "inquire vendor-ID");
        assert_eq!(describe(true, &[0x99, 1]), "unknown request 99h: 99 01");
        assert_eq!(describe(true, &[0x40, 1]), "unknown request 40h: 40 01");
        assert_eq!(describe(true, &[]), "(empty)");
    }

    #[test]
    fn every_response_with_its_values_and_error_codes() {
        let cases: [(&[u8], &str); 14] = [
            (
                &[0x44, 0, 0, 0, 0, 0, 0, 0],
                "switch state selective: the slave is in configuration",
            ),
            (&[0x11, 0, 0, 0, 0, 0, 0, 0], "configure node-ID: success"),
            (
                &[0x11, 1, 0, 0, 0, 0, 0, 0],
                "configure node-ID: error 1, node-ID out of range",
            ),
            (
                &[0x11, 0xFF, 0x2A, 0, 0, 0, 0, 0],
                "configure node-ID: error FFh, implementation specific 2Ah",
            ),
            (
                &[0x13, 1, 0, 0, 0, 0, 0, 0],
                "configure bit timing: error 1, bit timing not supported",
            ),
            (&[0x17, 0, 0, 0, 0, 0, 0, 0], "store configuration: success"),
            (
                &[0x17, 1, 0, 0, 0, 0, 0, 0],
                "store configuration: error 1, store configuration not supported",
            ),
            (
                &[0x17, 2, 0, 0, 0, 0, 0, 0],
                "store configuration: error 2, storage media access error",
            ),
            (
                &[0x4F, 0, 0, 0, 0, 0, 0, 0],
                "identify slave: a slave matches",
            ),
            (
                &[0x50, 0, 0, 0, 0, 0, 0, 0],
                "identify non-configured slave: a non-configured slave is there",
            ),
            (
                &[0x5A, 0x78, 0x56, 0x34, 0x12, 0, 0, 0],
                "vendor-ID = 0x12345678",
            ),
            (
                &[0x5C, 0x01, 0x00, 0x02, 0x00, 0, 0, 0],
                "revision number = 0x00020001",
            ),
            (&[0x5E, 0x05, 0, 0, 0, 0, 0, 0], "node-ID = 5"),
            (
                &[0x5E, 0xFF, 0, 0, 0, 0, 0, 0],
                "node-ID = FFh (not configured)",
            ),
        ];
        for (data, text) in cases {
            assert_eq!(describe(false, data), text, "{data:02X?}");
        }
        assert_eq!(
            describe(false, &[0x11, 7]),
            "configure node-ID: error 7 (reserved)"
        );
        assert_eq!(describe(false, &[0x04, 1]), "unknown response 04h: 04 01");
    }
}
