//! The parameter channel PKW1–PKW4 (manual Tables 2-9 to 2-11; the same as Tables 4-9/4-10 and
//! 5-11/5-12): PKW1 the task or response code, PKW2 the parameter address (group in the high
//! byte, number in the low byte: P00.10 is 000Ah, P15.13 is 0F0Dh), PKW3 the high word of the
//! value or the error number, PKW4 the low word.
//!
//! Table 2-10 names a rejection "4" for the write tasks that Table 2-11 never defines. Choice:
//! a response code 4 is read as a refusal like 3, with an error number in PKW3
//! ([`PkwResponse::RefusedWrite`], so that nothing a real drive sends is lost), and a drive
//! built on these types sends 3, which both tables define.

/// A task (request number, PKW1 from the master; Table 2-10).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Task {
    /// 0: no task.
    None,
    /// 1: read a parameter's value.
    Read,
    /// 2: write one word to RAM ("not supported currently").
    WriteRam,
    /// 3: write two words to RAM ("not supported currently").
    WriteRamDouble,
    /// 4: write one word to RAM and EEPROM.
    WriteEeprom,
    /// 5: write two words to RAM and EEPROM ("not supported currently").
    WriteEepromDouble,
    /// A number the manual does not define (a drive refuses it with error 1).
    Other(u16),
}

impl Task {
    /// The task of a PKW1 word.
    pub const fn from_code(code: u16) -> Self {
        match code {
            0 => Task::None,
            1 => Task::Read,
            2 => Task::WriteRam,
            3 => Task::WriteRamDouble,
            4 => Task::WriteEeprom,
            5 => Task::WriteEepromDouble,
            other => Task::Other(other),
        }
    }

    /// The PKW1 word of this task.
    pub const fn code(self) -> u16 {
        match self {
            Task::None => 0,
            Task::Read => 1,
            Task::WriteRam => 2,
            Task::WriteRamDouble => 3,
            Task::WriteEeprom => 4,
            Task::WriteEepromDouble => 5,
            Task::Other(code) => code,
        }
    }

    /// Whether the task writes (2 to 5).
    pub const fn is_write(self) -> bool {
        matches!(
            self,
            Task::WriteRam | Task::WriteRamDouble | Task::WriteEeprom | Task::WriteEepromDouble
        )
    }
}

/// An error number (PKW3 of a refusal, Table 2-11).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ErrorNumber {
    /// 1: invalid command.
    InvalidCommand,
    /// 2: invalid data address.
    InvalidAddress,
    /// 3: invalid data value.
    InvalidValue,
    /// 4: operation failure.
    OperationFailure,
    /// 5: password error.
    PasswordError,
    /// 6: data frame error.
    FrameError,
    /// 7: parameter read only.
    ReadOnly,
    /// 8: parameter cannot be modified during VFD running.
    WhileRunning,
    /// 9: password protection.
    PasswordProtection,
    /// A number the manual does not define (kept as received).
    Other(u16),
}

impl ErrorNumber {
    /// The error number of a PKW3 word.
    pub const fn from_code(code: u16) -> Self {
        match code {
            1 => ErrorNumber::InvalidCommand,
            2 => ErrorNumber::InvalidAddress,
            3 => ErrorNumber::InvalidValue,
            4 => ErrorNumber::OperationFailure,
            5 => ErrorNumber::PasswordError,
            6 => ErrorNumber::FrameError,
            7 => ErrorNumber::ReadOnly,
            8 => ErrorNumber::WhileRunning,
            9 => ErrorNumber::PasswordProtection,
            other => ErrorNumber::Other(other),
        }
    }

    /// The PKW3 word of this error.
    pub const fn code(self) -> u16 {
        match self {
            ErrorNumber::InvalidCommand => 1,
            ErrorNumber::InvalidAddress => 2,
            ErrorNumber::InvalidValue => 3,
            ErrorNumber::OperationFailure => 4,
            ErrorNumber::PasswordError => 5,
            ErrorNumber::FrameError => 6,
            ErrorNumber::ReadOnly => 7,
            ErrorNumber::WhileRunning => 8,
            ErrorNumber::PasswordProtection => 9,
            ErrorNumber::Other(code) => code,
        }
    }

    /// The manual's text for the error.
    pub const fn text(self) -> &'static str {
        match self {
            ErrorNumber::InvalidCommand => "invalid command",
            ErrorNumber::InvalidAddress => "invalid data address",
            ErrorNumber::InvalidValue => "invalid data value",
            ErrorNumber::OperationFailure => "operation failure",
            ErrorNumber::PasswordError => "password error",
            ErrorNumber::FrameError => "data frame error",
            ErrorNumber::ReadOnly => "parameter read only",
            ErrorNumber::WhileRunning => "parameter cannot be modified during VFD running",
            ErrorNumber::PasswordProtection => "password protection",
            ErrorNumber::Other(_) => "undefined error number",
        }
    }
}

/// A request on PKW1–PKW4 (master to drive).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PkwRequest {
    /// PKW1.
    pub task: Task,
    /// PKW2: the parameter address.
    pub address: u16,
    /// PKW3 (high word) and PKW4 (low word); a one-word write's value is PKW4, a read's is not
    /// used ("no longer valid").
    pub value: u32,
}

impl PkwRequest {
    /// A read of the parameter at `address`.
    pub const fn read(address: u16) -> Self {
        PkwRequest {
            task: Task::Read,
            address,
            value: 0,
        }
    }

    /// A one-word write to RAM and EEPROM (task 4, the one write the manual supports).
    pub const fn write(address: u16, value: u16) -> Self {
        PkwRequest {
            task: Task::WriteEeprom,
            address,
            value: value as u32,
        }
    }

    /// The request in four words. Total: every four words are some request.
    pub const fn from_words(words: [u16; 4]) -> Self {
        PkwRequest {
            task: Task::from_code(words[0]),
            address: words[1],
            value: (words[2] as u32) << 16 | words[3] as u32,
        }
    }

    /// The four words PKW1–PKW4.
    pub const fn to_words(self) -> [u16; 4] {
        [
            self.task.code(),
            self.address,
            (self.value >> 16) as u16,
            self.value as u16,
        ]
    }
}

/// A response on PKW1–PKW4 (drive to master, Table 2-11). PKW2 echoes the address.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PkwResponse {
    /// 0: no response (all four words zero when sent).
    None,
    /// 1: the parameter's value, one word (in PKW4; PKW3 zero).
    Word {
        /// PKW2.
        address: u16,
        /// PKW4.
        value: u16,
    },
    /// 2: the parameter's value, two words (PKW3 high, PKW4 low).
    DoubleWord {
        /// PKW2.
        address: u16,
        /// PKW3 and PKW4.
        value: u32,
    },
    /// 3: the task cannot be executed; the error number is in PKW3 (PKW4 zero).
    Refused {
        /// PKW2.
        address: u16,
        /// PKW3.
        error: ErrorNumber,
    },
    /// 4: Table 2-10's undefined write rejection, read like 3 (see the module comment).
    RefusedWrite {
        /// PKW2.
        address: u16,
        /// PKW3.
        error: ErrorNumber,
    },
}

/// Why four words are no response.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ResponseError {
    /// PKW1 holds a response code the manual does not define (5 and above).
    UnknownResponse(u16),
}

impl PkwResponse {
    /// The response in four words.
    pub const fn from_words(words: [u16; 4]) -> Result<Self, ResponseError> {
        let [code, address, high, low] = words;
        Ok(match code {
            0 => PkwResponse::None,
            1 => PkwResponse::Word {
                address,
                value: low,
            },
            2 => PkwResponse::DoubleWord {
                address,
                value: (high as u32) << 16 | low as u32,
            },
            3 => PkwResponse::Refused {
                address,
                error: ErrorNumber::from_code(high),
            },
            4 => PkwResponse::RefusedWrite {
                address,
                error: ErrorNumber::from_code(high),
            },
            other => return Err(ResponseError::UnknownResponse(other)),
        })
    }

    /// The four words PKW1–PKW4.
    pub const fn to_words(self) -> [u16; 4] {
        match self {
            PkwResponse::None => [0; 4],
            PkwResponse::Word { address, value } => [1, address, 0, value],
            PkwResponse::DoubleWord { address, value } => {
                [2, address, (value >> 16) as u16, value as u16]
            }
            PkwResponse::Refused { address, error } => [3, address, error.code(), 0],
            PkwResponse::RefusedWrite { address, error } => [4, address, error.code(), 0],
        }
    }

    /// The response code (PKW1).
    pub const fn code(self) -> u16 {
        self.to_words()[0]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_round_trip() {
        for code in 0..12 {
            assert_eq!(Task::from_code(code).code(), code);
            assert_eq!(ErrorNumber::from_code(code).code(), code);
        }
        assert_eq!(Task::from_code(6), Task::Other(6));
        assert_eq!(ErrorNumber::from_code(0), ErrorNumber::Other(0));
        assert_eq!(ErrorNumber::from_code(10), ErrorNumber::Other(10));
        assert!(Task::WriteEeprom.is_write() && !Task::Read.is_write());
    }

    #[test]
    fn requests_from_and_to_words() {
        // §2.6 example 2: task 4, address 10 (P00.10), value 5000 (0x1388) in PKW4.
        let request = PkwRequest::from_words([0x0004, 0x000A, 0x0000, 0x1388]);
        assert_eq!(request, PkwRequest::write(10, 5000));
        assert_eq!(request.to_words(), [4, 10, 0, 5000]);
        let double = PkwRequest::from_words([3, 0x0F0D, 0x0001, 0x0002]);
        assert_eq!(double.value, 0x0001_0002);
        assert_eq!(double.task, Task::WriteRamDouble);
    }

    #[test]
    fn responses_from_and_to_words() {
        let cases = [
            ([0, 0, 0, 0], PkwResponse::None),
            (
                [1, 10, 0, 5000],
                PkwResponse::Word {
                    address: 10,
                    value: 5000,
                },
            ),
            (
                [2, 10, 0x0001, 0x86A0],
                PkwResponse::DoubleWord {
                    address: 10,
                    value: 100_000,
                },
            ),
            (
                [3, 0x071B, 7, 0],
                PkwResponse::Refused {
                    address: 0x071B,
                    error: ErrorNumber::ReadOnly,
                },
            ),
            (
                [4, 10, 4, 0],
                PkwResponse::RefusedWrite {
                    address: 10,
                    error: ErrorNumber::OperationFailure,
                },
            ),
        ];
        for (words, response) in cases {
            assert_eq!(PkwResponse::from_words(words), Ok(response));
            assert_eq!(response.to_words(), words);
            assert_eq!(response.code(), words[0]);
        }
        assert_eq!(
            PkwResponse::from_words([5, 0, 0, 0]),
            Err(ResponseError::UnknownResponse(5))
        );
        assert_eq!(
            ErrorNumber::WhileRunning.text(),
            "parameter cannot be modified during VFD running"
        );
    }
}
