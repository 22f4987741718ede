//! What the decoder's lines say about values and codes: a value typed by its data type, the
//! CiA 301 meanings of SDO abort codes, emergency error codes and error-register bits.

use edsgen_runtime::typed::get_bits;
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
    let meaning = match code {
        0x0503_0000 => "toggle bit not alternated",
        0x0504_0000 => "SDO protocol timed out",
        0x0504_0001 => "client/server command specifier not valid or unknown",
        0x0504_0002 => "invalid block size",
        0x0504_0003 => "invalid sequence number",
        0x0504_0004 => "CRC error",
        0x0504_0005 => "out of memory",
        0x0601_0000 => "unsupported access to an object",
        0x0601_0001 => "attempt to read a write only object",
        0x0601_0002 => "attempt to write a read only object",
        0x0602_0000 => "object does not exist in the object dictionary",
        0x0604_0041 => "object cannot be mapped to the PDO",
        0x0604_0042 => "the number and length of the objects to be mapped would exceed PDO length",
        0x0604_0043 => "general parameter incompatibility",
        0x0604_0047 => "general internal incompatibility in the device",
        0x0606_0000 => "access failed due to a hardware error",
        0x0607_0010 => "data type does not match, length of service parameter does not match",
        0x0607_0012 => "data type does not match, length of service parameter too high",
        0x0607_0013 => "data type does not match, length of service parameter too low",
        0x0609_0011 => "sub-index does not exist",
        0x0609_0030 => "invalid value for parameter",
        0x0609_0031 => "value of parameter written too high",
        0x0609_0032 => "value of parameter written too low",
        0x0609_0036 => "maximum value is less than minimum value",
        0x060A_0023 => "resource not available: SDO connection",
        0x0800_0000 => "general error",
        0x0800_0020 => "data cannot be transferred or stored to the application",
        0x0800_0021 => "data cannot be transferred or stored because of local control",
        0x0800_0022 => "data cannot be transferred or stored because of the present device state",
        0x0800_0023 => "object dictionary dynamic generation fails or no object dictionary",
        0x0800_0024 => "no data available",
        _ => "unknown abort code",
    };
    format!("{:04X} {:04X} {meaning}", code >> 16, code & 0xFFFF)
}

/// The CiA 301 meaning of an emergency error code (the most specific one the code has).
pub fn emergency(code: u16) -> &'static str {
    match code {
        0x0000 => "error reset or no error",
        0x8110 => "CAN overrun (objects lost)",
        0x8120 => "CAN in error passive mode",
        0x8130 => "life guard error or heartbeat error",
        0x8140 => "recovered from bus off",
        0x8150 => "CAN-ID collision",
        0x8210 => "PDO not processed due to length error",
        0x8220 => "PDO length exceeded",
        0x8230 => "DAM MPDO not processed, destination object not available",
        0x8240 => "unexpected SYNC data length",
        0x8250 => "RPDO timeout",
        _ => match code >> 8 {
            0x10 => "generic error",
            0x20 => "current",
            0x21 => "current, device input side",
            0x22 => "current inside the device",
            0x23 => "current, device output side",
            0x30 => "voltage",
            0x31 => "mains voltage",
            0x32 => "voltage inside the device",
            0x33 => "output voltage",
            0x40 => "temperature",
            0x41 => "ambient temperature",
            0x42 => "device temperature",
            0x50 => "device hardware",
            0x60 => "device software",
            0x61 => "internal software",
            0x62 => "user software",
            0x63 => "data set",
            0x70 => "additional modules",
            0x80 => "monitoring",
            0x81 => "communication",
            0x82 => "protocol error",
            0x90 => "external error",
            0xF0 => "additional functions",
            0xFF => "device specific",
            _ => "unknown error code",
        },
    }
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
