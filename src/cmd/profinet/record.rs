//! `pn im IFACE NAME` and `pn record IFACE NAME --slot S --subslot SS --index I`: records read
//! without a connection, as an engineering tool reads them (RPC ReadImplicit with the NIL AR
//! UUID on UDP 34964, after a DCP Identify by name for the device's IP and object UUID). `im`
//! reads I&M0 (index 0xAFF0 of the access point's subslot 0.1) and prints it in words; `record`
//! prints any record as a hex dump. Exit 0; 1 when the device is not found, has no IP, refuses
//! the read or does not answer; 2 for usage and I/O problems.

use std::net::Ipv4Addr;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use edsgen_runtime::profinet::wire::dcp;
use edsgen_runtime::profinet::wire::rpc::{Uuid, RPC_PORT};
use edsgen_sim::profinet::controller::{read_data, read_implicit, response};
use edsgen_sim::profinet::driver::{RawSocket, RpcSocket};

use super::dcp_verbs::{check_name, find_by_name, show_mac};
use crate::cmd::fail;

/// I&M0's index.
pub const IM0_INDEX: u16 = 0xAFF0;

/// How long the device may take to answer the read.
const READ_WAIT: Duration = Duration::from_secs(3);

/// Why a read did not give the record: usage or I/O (exit 2), or the device (exit 1).
enum Failed {
    Usage(String),
    Device(String),
}

impl Failed {
    fn exit(self) -> ExitCode {
        match self {
            Failed::Usage(message) => fail(message),
            Failed::Device(message) => {
                eprintln!("{message}");
                ExitCode::from(1)
            }
        }
    }
}

/// `pn record`: the record's bytes as a hex dump, 16 a line after their offset.
pub fn record(iface: &str, name: &str, at: (u16, u16, u16)) -> ExitCode {
    let data = match read(iface, name, at) {
        Ok(data) => data,
        Err(failed) => return failed.exit(),
    };
    println!(
        "record {:#06x} of slot {} subslot {:#06x}: {} bytes",
        at.2,
        at.0,
        at.1,
        data.len()
    );
    for (line, chunk) in data.chunks(16).enumerate() {
        let bytes: Vec<String> = chunk.iter().map(|b| format!("{b:02x}")).collect();
        println!("{:04x}  {}", line * 16, bytes.join(" "));
    }
    ExitCode::SUCCESS
}

/// `pn im`: I&M0 in words.
pub fn im(iface: &str, name: &str) -> ExitCode {
    let data = match read(iface, name, (0, 1, IM0_INDEX)) {
        Ok(data) => data,
        Err(failed) => return failed.exit(),
    };
    match im0_lines(&data) {
        Some(lines) => {
            for line in lines {
                println!("{line}");
            }
            ExitCode::SUCCESS
        }
        None => {
            let bytes: Vec<String> = data.iter().map(|b| format!("{b:02x}")).collect();
            eprintln!(
                "the device's I&M0 is not an I&M0 block (BlockType 0x0020, 54 bytes): {}",
                bytes.join(" ")
            );
            ExitCode::from(1)
        }
    }
}

/// I&M0 (the block, BlockType 0x0020) in words, one field a line; `None` when `data` is not
/// that block.
pub fn im0_lines(data: &[u8]) -> Option<Vec<String>> {
    let block_type = u16::from_be_bytes([*data.first()?, *data.get(1)?]);
    // BlockType, BlockLength, BlockVersion, then the 54 bytes of I&M0.
    let body = data.get(6..60).filter(|_| block_type == 0x0020)?;
    let u16_at = |i: usize| u16::from_be_bytes([body[i], body[i + 1]]);
    let text = |range: std::ops::Range<usize>| {
        String::from_utf8_lossy(&body[range])
            .trim_end_matches([' ', '\0'])
            .to_owned()
    };
    let software = format!(
        "{}{}.{}.{}",
        char::from(body[40]),
        body[41],
        body[42],
        body[43]
    );
    let supported = u16_at(52);
    let mut records = vec!["I&M0".to_owned()];
    records.extend(
        (1..=15)
            .filter(|n| supported & (1 << n) != 0)
            .map(|n| format!("I&M{n}")),
    );
    Some(vec![
        format!("vendor ID: {:#06x}", u16_at(0)),
        format!("order ID: {}", text(2..22)),
        format!("serial number: {}", text(22..38)),
        format!("hardware revision: {}", u16_at(38)),
        format!("software revision: {software}"),
        format!("revision counter: {}", u16_at(44)),
        format!(
            "profile: {:#06x}, specific type {:#06x}",
            u16_at(46),
            u16_at(48)
        ),
        format!(
            "I&M version: {}.{}, records: {}",
            body[50],
            body[51],
            records.join(", ")
        ),
    ])
}

/// Reads record `at` of the device named `name` on `iface` by ReadImplicit.
fn read(iface: &str, name: &str, at: (u16, u16, u16)) -> Result<Vec<u8>, Failed> {
    check_name(name).map_err(Failed::Usage)?;
    let mut raw = RawSocket::open(iface, Duration::from_millis(100))
        .map_err(|e| Failed::Usage(format!("cannot open `{iface}`: {e}")))?;
    let (mac, blocks) = find_by_name(&mut raw, name)
        .map_err(|e| Failed::Usage(format!("cannot send on `{iface}`: {e}")))?
        .ok_or_else(|| {
            Failed::Device(format!(
                "no device named `{name}` answered on {iface} within 2 s"
            ))
        })?;
    let get = |option| {
        blocks
            .iter()
            .find(|b| b.0 == option)
            .map(|b| b.2.clone())
            .unwrap_or_default()
    };
    let ip: [u8; 4] = get(dcp::IP_PARAMETER)
        .get(..4)
        .and_then(|a| a.try_into().ok())
        .filter(|a| *a != [0; 4])
        .ok_or_else(|| {
            Failed::Device(format!(
                "`{name}` ({}) has no IP: give it one with `edsgen pn set-ip {iface} {name} ADDR/PREFIX`",
                show_mac(&mac)
            ))
        })?;
    let ids = get(dcp::DEVICE_ID);
    let (vendor, device) = match ids[..] {
        [a, b, c, d, ..] => (u16::from_be_bytes([a, b]), u16::from_be_bytes([c, d])),
        _ => (0, 0),
    };
    let instance = match get(dcp::DEVICE_INSTANCE)[..] {
        [high, low, ..] => u16::from_be_bytes([high, low]),
        _ => 1,
    };
    let object = Uuid::pnio_object(instance, device, vendor);
    let mut activity = [0u8; 16];
    activity[..4].copy_from_slice(&std::process::id().to_be_bytes());
    activity[4..10].copy_from_slice(&mac);
    let pdu = read_implicit(object, Uuid(activity), at);
    let answer = call(iface, ip, &pdu)?.ok_or_else(|| {
        Failed::Device(format!(
            "`{name}` at {} did not answer the read within {} s",
            Ipv4Addr::from(ip),
            READ_WAIT.as_secs()
        ))
    })?;
    let (status, args) = response(&answer)
        .ok_or_else(|| Failed::Device(format!("`{name}`'s answer is not a DCE/RPC response")))?;
    if !status.is_ok() {
        let s = status.0;
        return Err(Failed::Device(format!(
            "`{name}` refused the read of record {:#06x} of slot {} subslot {:#06x}: PNIOStatus {:02x} {:02x} {:02x} {:02x}{}",
            at.2,
            at.0,
            at.1,
            s[0],
            s[1],
            s[2],
            s[3],
            error_code1(s[2]).map_or(String::new(), |w| format!(" ({w})"))
        )));
    }
    read_data(&args).map(<[u8]>::to_vec).ok_or_else(|| {
        Failed::Device(format!(
            "`{name}`'s answer carries no IODReadResHeader and record data"
        ))
    })
}

/// ErrorCode1 of a record access (PNIORW), in words.
fn error_code1(code: u8) -> Option<&'static str> {
    Some(match code {
        0xB0 => "invalid index",
        0xB1 => "write length error",
        0xB2 => "invalid slot or subslot",
        0xB3 => "type conflict",
        0xB4 => "invalid area",
        0xB5 => "state conflict",
        0xB6 => "access denied",
        0xB7 => "invalid range",
        0xB8 => "invalid parameter",
        0xB9 => "invalid type",
        0xC0 => "read constraint conflict",
        0xC3 => "resource busy",
        _ => return None,
    })
}

/// Sends `pdu` to UDP 34964 at `ip` from a socket of `iface` and waits for the answer from
/// there (`None` after [`READ_WAIT`]).
fn call(iface: &str, ip: [u8; 4], pdu: &[u8]) -> Result<Option<Vec<u8>>, Failed> {
    let io = |e: std::io::Error| Failed::Usage(format!("UDP on `{iface}`: {e}"));
    let socket = RpcSocket::open_client(iface).map_err(io)?;
    socket.send((ip, RPC_PORT), pdu).map_err(io)?;
    let until = Instant::now() + READ_WAIT;
    let mut buf = vec![0u8; 8192];
    while Instant::now() < until {
        match socket.recv(&mut buf).map_err(io)? {
            Some((n, (from, _))) if from == ip => {
                return Ok(Some(buf.get(..n).unwrap_or_default().to_vec()))
            }
            Some(_) => {}
            None => std::thread::sleep(Duration::from_millis(2)),
        }
    }
    Ok(None)
}

#[cfg(test)]
mod tests {
    use super::im0_lines;

    #[test]
    fn i_m0_is_printed_in_words() {
        let mut im0 = vec![0x00, 0x20, 0x00, 0x38, 0x01, 0x00, 0x03, 0x50];
        im0.extend_from_slice(b"INVT Goodrive350    0001            ");
        im0.extend_from_slice(&[0, 1, b'V', 1, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 0, 0x1E]);
        assert_eq!(
            im0_lines(&im0).expect("I&M0"),
            [
                "vendor ID: 0x0350",
                "order ID: INVT Goodrive350",
                "serial number: 0001",
                "hardware revision: 1",
                "software revision: V1.0.0",
                "revision counter: 0",
                "profile: 0x0000, specific type 0x0000",
                "I&M version: 1.1, records: I&M0, I&M1, I&M2, I&M3, I&M4",
            ]
        );
        assert_eq!(im0_lines(&im0[..59]), None);
        im0[1] = 0x21;
        assert_eq!(im0_lines(&im0), None);
    }
}
