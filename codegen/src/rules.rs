//! The rule catalogue: every diagnostic edsgen can emit, with its stable code and default severity.
//!
//! Codes never change meaning once published. Numbering by area: `EDS0xx` text and values (the
//! readers), `EDS1xx` `[FileInfo]`/`[DeviceInfo]`, `EDS2xx` object lists, `EDS3xx` objects and
//! sub-objects, `EDS4xx` PDOs, `EDS5xx` DCF, commissioning, modules and the rest, `EDS6xx` XML
//! (XDD/XDC), `EDS7xx` code generation. `edsgen rules` prints this table.

use crate::diag::Severity;

/// One validation rule.
#[derive(Debug, PartialEq, Eq)]
pub struct Rule {
    /// Stable code, e.g. `EDS301`.
    pub code: &'static str,
    /// Default severity.
    pub severity: Severity,
    /// What the rule checks, in one line.
    pub summary: &'static str,
}

macro_rules! rules {
    ($($name:ident = $code:literal $sev:ident $summary:literal;)*) => {
        $(
            #[doc = $summary]
            pub static $name: Rule = Rule { code: $code, severity: Severity::$sev, summary: $summary };
        )*
        /// Every rule, in code order.
        pub static ALL: &[&Rule] = &[$(&$name),*];
    };
}

rules! {
    // ---- EDS0xx: text and values (readers) ----
    UNPARSEABLE_LINE = "EDS001" Error "a line that is not blank, a comment, a [section] or key=value";
    NON_ASCII = "EDS002" Warning "bytes outside ASCII (the file was decoded as UTF-8 or Windows-1252)";
    LONG_LINE = "EDS003" Warning "a line longer than 255 characters";
    INLINE_COMMENT = "EDS004" Warning "a comment not in column 1, or an inline `;` comment after a value";
    DUPLICATE_SECTION = "EDS005" Error "a section appears twice (case-insensitive); the last one wins";
    DUPLICATE_KEY = "EDS006" Error "a key appears twice in one section; the last one wins";
    KEY_SPELLING = "EDS007" Warning "whitespace before `=`, around a section name, or a key with characters other than [A-Za-z0-9_]";
    CASE_ONLY_MATCH = "EDS008" Info "a section or key that matches its canonical name only case-insensitively";
    UNKNOWN_ITEM = "EDS009" Info "an unknown section or key (kept, not interpreted)";
    LEADING_ZEROS = "EDS010" Warning "a numbered key or a section name with extra leading zeros";
    BAD_NUMBER = "EDS011" Error "a value that should be a number is not one";
    BAD_VALUE = "EDS012" Error "a value cannot be parsed for its data type";
    OUT_OF_RANGE = "EDS013" Error "a value outside the range of its data type";
    TWOS_COMPLEMENT = "EDS014" Info "an unsigned hex literal read as two's complement for a signed type";
    NODEID_FORMULA = "EDS015" Error "a $NODEID formula that is not `$NODEID + number`, or on a non-integer type";
    NODEID_DIALECT = "EDS016" Warning "a $NODEID formula in a form the spec does not define (postfix, other case)";
    OCTAL_LITERAL = "EDS017" Info "an integer with a leading 0 read as octal, as CiA 306 says";
    QUOTED_STRING = "EDS018" Info "a string value wrapped in quotes (kept literally, per the spec)";
    REAL_BIT_PATTERN = "EDS019" Warning "a REAL value written as a hex integer (read as an IEEE 754 bit pattern)";
    FLOAT_ON_INTEGER = "EDS020" Warning "a float literal on an integer type";
    BAD_BOOLEAN = "EDS021" Warning "a boolean key that is not 0 or 1";
    EMPTY_FILE = "EDS022" Error "the file holds no sections";

    // ---- EDS7xx: code generation ----
    NAME_COLLISION = "EDS701" Info "a generated Rust name collided with an earlier one and was made unique";
    UNREPRESENTABLE_TYPE = "EDS702" Error "an entry's data type cannot be represented in generated code";
    UNREPRESENTABLE_VALUE = "EDS703" Error "a default or parameter value does not fit its entry's Rust type";
    UNTYPED_PDO = "EDS704" Warning "a default PDO mapping cannot be typed; no PDO struct is generated for it";
    NO_DEFAULT = "EDS705" Info "an entry without a default value; its generated field starts at zero or empty";
    UNUSABLE_LIMIT = "EDS706" Warning "a LowLimit or HighLimit the generated write cannot check (not a constant of the entry's type)";
    CAPACITY_TOO_LARGE = "EDS707" Error "a string, octet string or domain longer than 65535 bytes";
}

/// Looks a rule up by its code.
pub fn by_code(code: &str) -> Option<&'static Rule> {
    ALL.iter()
        .copied()
        .find(|r| r.code.eq_ignore_ascii_case(code))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_are_unique_and_sorted() {
        for pair in ALL.windows(2) {
            assert!(
                pair[0].code < pair[1].code,
                "{} then {}",
                pair[0].code,
                pair[1].code
            );
        }
    }
}
