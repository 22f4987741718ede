//! What the decoder's lines say about values and codes: a value typed by its data type, the
//! CiA 301 meanings of SDO abort codes and error-register bits as the decoder prints them (the
//! tables themselves are the runtime's: `wire::sdo::abort_meaning`, `wire::emcy::meaning`).

use edsgen_runtime::od::typed::get_bits;
use edsgen_runtime::wire::sdo::abort_meaning;
use edsgen_runtime::DataType;

/// A value's little-endian bytes as text, typed by `data_type`: integers in decimal (unsigned
/// ones above 255 with their hexadecimal beside), REALs as decimals, strings quoted, octet
/// strings and domains as hex bytes. Bytes that do not fit the type are shown as hex bytes.
pub fn value(data_type: Option<DataType>, bytes: &[u8]) -> String {
    let Some(data_type) = data_type else {
        return hex_bytes(bytes);
    };
    if data_type
        .fixed_size()
        .is_some_and(|size| size != bytes.len())
    {
        return format!("{} (not {data_type:?})", hex_bytes(bytes));
    }
    let raw = get_bits(bytes, 0, 8 * bytes.len().min(8) as u32);
    let bits = 8 * bytes.len() as u32;
    match data_type {
        DataType::Boolean => match raw {
            0 => "false".into(),
            1 => "true".into(),
            _ => format!("{raw} (not BOOLEAN)"),
        },
        DataType::Integer8
        | DataType::Integer16
        | DataType::Integer24
        | DataType::Integer32
        | DataType::Integer40
        | DataType::Integer48
        | DataType::Integer56
        | DataType::Integer64 => {
            let shift = 64 - bits;
            (((raw << shift) as i64) >> shift).to_string()
        }
        DataType::Real32 => format!("{:?}", f32::from_bits(raw as u32)),
        DataType::Real64 => format!("{:?}", f64::from_bits(raw)),
        DataType::VisibleString => format!("{:?}", String::from_utf8_lossy(bytes)),
        DataType::UnicodeString => {
            let units: Vec<u16> = bytes
                .chunks(2)
                .map(|c| u16::from_le_bytes([c[0], *c.get(1).unwrap_or(&0)]))
                .collect();
            format!("{:?}", String::from_utf16_lossy(&units))
        }
        DataType::OctetString | DataType::Domain => hex_bytes(bytes),
        DataType::TimeOfDay | DataType::TimeDifference => {
            format!("{} days {} ms", raw >> 32, raw & 0x0FFF_FFFF)
        }
        _ if raw > 255 => format!("{raw} (0x{raw:0width$X})", width = 2 * bytes.len()),
        _ => raw.to_string(),
    }
}

/// The start of a long value: a string's first 64 characters, else the first 16 bytes in hex,
/// followed by `...`.
pub fn summary(data_type: Option<DataType>, bytes: &[u8]) -> String {
    match data_type {
        Some(DataType::VisibleString) => {
            let text: String = String::from_utf8_lossy(bytes).chars().take(64).collect();
            format!("{text:?}...")
        }
        _ => format!("{} ...", hex_bytes(&bytes[..bytes.len().min(16)])),
    }
}

/// Bytes as upper-case hex pairs separated by spaces (`01 A2`), or `(empty)`.
pub fn hex_bytes(bytes: &[u8]) -> String {
    if bytes.is_empty() {
        return "(empty)".into();
    }
    let pairs: Vec<String> = bytes.iter().map(|b| format!("{b:02X}")).collect();
    pairs.join(" ")
}

/// An SDO abort code as `0609 0031 value of parameter written too high` (CiA 301 table 22).
pub fn abort(code: u32) -> String {
    let meaning = abort_meaning(code).unwrap_or("unknown abort code");
    format!("{:04X} {:04X} {meaning}", code >> 16, code & 0xFFFF)
}

/// The bits set in an error register (1001h), by name: `generic, communication`, or `none`.
pub fn error_register(register: u8) -> String {
    const BITS: [&str; 8] = [
        "generic",
        "current",
        "voltage",
        "temperature",
        "communication",
        "device profile specific",
        "reserved",
        "manufacturer specific",
    ];
    let set: Vec<&str> = BITS
        .iter()
        .enumerate()
        .filter(|(bit, _)| register & (1 << bit) != 0)
        .map(|(_, name)| *name)
        .collect();
    if set.is_empty() {
        "none".into()
    } else {
        set.join(", ")
    }
}

/// A TIME_OF_DAY message's 6 bytes (milliseconds after midnight in bits 0–27, days since
/// 1984-01-01 in bytes 4–5) as `2026-11-24 15:04:05.123`; `None` for another length.
pub fn time_of_day(data: &[u8]) -> Option<String> {
    let &[a, b, c, d, e, f] = data else {
        return None;
    };
    let ms = u32::from_le_bytes([a, b, c, d]) & 0x0FFF_FFFF;
    let days = i64::from(u16::from_le_bytes([e, f]));
    // Days since 1984-01-01 to a civil date (the proleptic Gregorian calendar, counted in
    // 400-year eras from 0000-03-01).
    let z = days + 724_581; // days from 0000-03-01 to 1984-01-01
    let (era, doe) = (z / 146_097, z % 146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    let (h, m, sec, milli) = (ms / 3_600_000, ms / 60_000 % 60, ms / 1000 % 60, ms % 1000);
    Some(format!(
        "{year:04}-{month:02}-{day:02} {h:02}:{m:02}:{sec:02}.{milli:03}"
    ))
}
