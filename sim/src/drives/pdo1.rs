//! INVT's PDO1 parameter-access protocol, shared by the EC-TX105 (Goodrive350 manual §3.5.2) and
//! the HD1-E (its manual's §8.2, Tables 19–21), whose texts and tables are the same: a request in
//! 2100h:00–02 (request code, parameter address, data) carried by PDO1 Rx, answered in
//! 2000h:00–02 (response code, error code, data) and sent on PDO1 Tx.

use edsgen_runtime::ObjectDictionary;

use super::vfd::{ParameterError, Parameters};
use super::{read_u16, write_u16};

/// 2000h: the response (sub 00 code, 01 error, 02 data).
pub const RESPONSE: u16 = 0x2000;
/// 2100h: the request (sub 00 code, 01 parameter address, 02 data).
pub const REQUEST: u16 = 0x2100;

/// Response codes (EC-TX105 Table 3-15, HD1-E Table 20).
pub mod response {
    /// Read or write succeeded.
    pub const SUCCESS: u16 = 1;
    /// Read or write failed: see the error code.
    pub const ERROR: u16 = 3;
}

/// Error codes (EC-TX105 Table 3-16, HD1-E Table 21).
pub mod error_code {
    /// 01h: the request code is not allowed (or the drive is faulted).
    pub const INVALID_COMMAND: u16 = 0x01;
    /// 02h: no parameter at the address.
    pub const INVALID_ADDRESS: u16 = 0x02;
    /// 04h: the value is outside the parameter's range.
    pub const OPERATION_FAILED: u16 = 0x04;
    /// 07h: the parameter is read-only.
    pub const READ_ONLY: u16 = 0x07;
    /// 08h: the parameter cannot be changed while the drive runs.
    pub const WHILE_RUNNING: u16 = 0x08;
}

/// The drive's state as the protocol needs it.
#[derive(Debug, Clone, Copy)]
pub struct DriveState {
    /// The output is live: parameters marked "stopped only" refuse writes (08h).
    pub running: bool,
    /// A fault is active: writes are refused (01h, "the slave station is in the faulty state").
    pub faulted: bool,
}

/// Serves the request in the dictionary's 2100h:00–02 from `parameters` and writes the answer
/// into 2000h:00–02; `false` for request code 0 (no task), which gets no answer. Request code 1
/// reads, 2 writes; 4 (RAM and EEPROM, "reserved") and any other code are refused with 01h.
pub fn serve<O: ObjectDictionary>(
    od: &mut O,
    parameters: &mut Parameters,
    drive: DriveState,
) -> bool {
    let code = read_u16(od, REQUEST, 0);
    let address = read_u16(od, REQUEST, 1);
    let data = read_u16(od, REQUEST, 2);
    let answer = match code {
        0 => return false,
        1 => parameters.get(address).ok_or(error_code::INVALID_ADDRESS),
        2 if drive.faulted => Err(error_code::INVALID_COMMAND),
        2 => parameters
            .set(address, data, drive.running)
            .map(|()| data)
            .map_err(|error| match error {
                ParameterError::NoSuchParameter => error_code::INVALID_ADDRESS,
                ParameterError::ReadOnly => error_code::READ_ONLY,
                ParameterError::OutOfRange => error_code::OPERATION_FAILED,
                ParameterError::WhileRunning => error_code::WHILE_RUNNING,
            }),
        _ => Err(error_code::INVALID_COMMAND),
    };
    let (response, error, value) = match answer {
        Ok(value) => (response::SUCCESS, 0, value),
        Err(error) => (response::ERROR, error, 0),
    };
    write_u16(od, RESPONSE, 0, response);
    write_u16(od, RESPONSE, 1, error);
    write_u16(od, RESPONSE, 2, value);
    true
}
