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
    COMMISSIONING_SPELLING = "EDS023" Info "the DCF section is spelled [DeviceCommissioning] (two m); read as the spec's [DeviceComissioning]";
    ORPHAN_SECTION = "EDS024" Warning "a sub-index, name, value, denotation or link section (or entry) for an object or sub-index the file does not describe (kept, not interpreted)";

    // ---- EDS6xx: XML (XDD/XDC) ----
    XML_MALFORMED = "EDS601" Error "the file is not well-formed XML; nothing could be read";
    XML_NO_OBJECT_LIST = "EDS602" Error "an XML description without a CANopenObjectList";
    XML_MISSING_ATTRIBUTE = "EDS603" Error "a required attribute is missing (CANopenObject@index, CANopenSubObject@subIndex, @name, @objectType)";
    XML_BAD_ATTRIBUTE = "EDS604" Error "an attribute or element value that cannot be read (hexBinary, number, boolean, enumeration)";
    XML_UNRESOLVED_REF = "EDS605" Error "a uniqueIDRef that names no parameter (or a dataTypeIDRef that names no data type)";
    XML_DUPLICATE = "EDS606" Error "an index, sub-index or uniqueID described twice; the last one wins";
    XML_SUBS_ON_VAR = "EDS607" Error "CANopenSubObject elements inside a VAR or DOMAIN object (ignored)";
    XML_TYPE_CONFLICT = "EDS608" Warning "the parameter disagrees with the object: data type (the parameter wins) or access direction vs PDOmapping (PDOmapping wins)";
    XML_UNKNOWN_TYPE = "EDS609" Warning "a parameter data type with no CANopen equivalent (variableRef, struct, array on a VAR)";

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
