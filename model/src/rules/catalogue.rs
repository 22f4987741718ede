//! The catalogue itself: each rule's code, severity and summary on one line, why it matters on
//! the next, in code order (the table sorts by code).

use super::{Rule, Severity};

macro_rules! rules {
    ($($name:ident = $code:literal $sev:ident $summary:literal why $why:literal;)*) => {
        $(
            #[doc = $summary]
            // Summaries name sections like `[FileInfo]`, which rustdoc would read as links.
            #[allow(rustdoc::broken_intra_doc_links)]
            pub static $name: Rule =
                Rule { code: $code, severity: Severity::$sev, summary: $summary, why: $why };
        )*
        /// Every rule, in code order.
        pub static ALL: &[&Rule] = &[$(&$name),*];
    };
}

rules! {
    // ---- CHK0xx: a live device against its description (`edsgen check`) ----
    CHK_MISSING = "CHK001" Error "(`edsgen check`) an object or sub-index of the description is missing on the device"
        why "A master configured from the description reads or writes that entry at start-up and gets an SDO abort, so the node never reaches Operational.";
    CHK_LENGTH = "CHK002" Error "(`edsgen check`) the device's value has a length other than its data type's"
        why "A PDO or SDO client sized by the description reads the wrong number of bytes, so every value after it in the frame is shifted.";
    CHK_UNREADABLE = "CHK003" Error "(`edsgen check`) the device refuses to read an entry the description says is readable"
        why "Configuration tools and masters that read the entry to verify a node stop there with an SDO abort.";
    CHK_IDENTITY = "CHK004" Error "(`edsgen check`) the device's identity (1000h, 1018h:1-3) differs from the description"
        why "Masters identify a node by 1000h and 1018h before configuring it; a mismatch makes them refuse the node or load the wrong configuration.";
    CHK_DEFAULT = "CHK005" Warning "(`edsgen check`) a value differs from the description's default or DCF ParameterValue (an error for a constant)"
        why "A master that relies on the documented default (it sends only the entries it changes) runs the device with another value than the one it planned.";
    CHK_SII_IDENTITY = "CHK006" Error "(`edsgen ecat check`) the EtherCAT SubDevice's identity in its SII (vendor, product code, revision, order string) differs from the ESI"
        why "A master compares the SII identity with its ESI configuration and refuses to take the SubDevice to PreOp, or configures it as another product.";
    CHK_SYNC_MANAGER = "CHK007" Error "(`edsgen ecat check`) a SyncManager of the SubDevice's SII (kind, start, length, control byte, enable), or its ESC's SyncManager count, differs from the ESI"
        why "The master programs the SyncManagers from the ESI; a SII that disagrees leaves mailbox or process data at other addresses, and the SubDevice stays in Init or SafeOp.";
    CHK_PDO_ASSIGNMENT = "CHK008" Error "(`edsgen ecat check`) the PDO assignment (1C12h/1C13h) or the mapping of a default PDO, read by SDO, differs from the ESI's default PDOs"
        why "The master sizes the process image from the ESI's default PDOs; a device that maps others exchanges bytes the master reads as other values, or refuses SafeOp with a watchdog or size error.";

    // ---- CIP0xx: ODVA EDS (EtherNet/IP, DeviceNet; CIP). Before EDS0xx: codes sort by text ----
    CIP_SYNTAX = "CIP001" Error "ODVA EDS text: a line that is neither a `[section]`, an entry `Key = ...;` nor a `$` comment, an entry without its `;`, or a string without its closing quote"
        why "The line is lost to every tool: RSLinx and the scanner's EDS wizard refuse the whole file at such a line, so the device cannot be registered.";
    CIP_UNKNOWN = "CIP002" Info "ODVA EDS: a section or key this reader does not interpret (kept as written); the specification's class sections (`[... Class]`, `[ClassN_VendorM]`) are kept without a report"
        why "Nothing generated depends on it, but a key that is a misspelling of a known one means the value the author meant is silently ignored.";
    CIP_DUPLICATE = "CIP003" Error "ODVA EDS: a section or a key written twice; the last entry wins"
        why "Tools differ on which of the two entries they keep, so a scanner and edsgen can configure the device differently.";
    CIP_BAD_FIELD = "CIP004" Error "ODVA EDS: a field that should be a number (or reference) is not one, or an entry with fewer fields than its kind has"
        why "A scanner cannot build the connection or the parameter from a field it cannot read; most EDS installers refuse the file.";
    CIP_IDENTITY = "CIP005" Error "ODVA EDS: `[File]` or `[Device]` missing, or `[Device]` without a key a scanner matches (VendCode, ProdType, ProdCode, MajRev, MinRev, ProdName)"
        why "A scanner matches the device on the network by vendor, type, product code and revision; without them it cannot tell which EDS describes the device.";
    CIP_DATA_TYPE = "CIP010" Error "a parameter whose data type is not a CIP elementary type, or whose data size disagrees with its type"
        why "The parameter's size on the wire is unknown or ambiguous, so a scanner reading or writing it by explicit message sends the wrong number of bytes.";
    CIP_LIMITS = "CIP011" Error "a parameter whose default is outside its limits, whose minimum exceeds its maximum, or a limit outside its data type"
        why "A scanner that writes the default gets an Invalid Attribute Value error, and limits outside the type cannot be enforced by anyone.";
    CIP_ENUM_ORPHAN = "CIP012" Error "an `EnumN` for a parameter `ParamN` the file does not have"
        why "The value names meant for a parameter are attached to none, so the operator sees raw numbers where the author wrote names.";
    CIP_ASSEMBLY_SIZE = "CIP020" Error "an assembly whose members' bits, rounded up to whole bytes, do not add up to its size in bytes"
        why "The originator's connection size comes from the assembly; when members and size disagree one side sends more bytes than the other accepts and the Forward_Open fails.";
    CIP_MISSING_REF = "CIP021" Error "an assembly member or a connection field that names a `ParamN` or `AssemN` the file does not have"
        why "A member or connection that names nothing cannot be sized or laid out, so no scanner can build that connection.";
    CIP_MEMBER_BYTES = "CIP022" Warning "assembly member sizes written in bytes where the EDS specification wants bits: read as bytes, because only that makes the assembly add up to its size"
        why "A tool that reads the sizes as bits, as the specification says, lays the members out eight times too short and decodes every value after the first wrongly.";
    CIP_MEMBER_PARAM = "CIP023" Warning "an assembly member whose size in bits differs from its parameter's data size (a BOOL or bit string may take fewer bits)"
        why "The member and its parameter describe the same bytes with two sizes, so a tool that decodes the assembly through the parameter reads neighbouring bytes into it.";
    CIP_CONNECTION_SIZE = "CIP030" Error "a connection size that disagrees with the size of the assembly it names as its format (or that its path names)"
        why "The scanner opens the connection with the size the EDS states; the adapter answers from its assembly, and a Forward_Open with the wrong size is refused (status 0x01/0x0109).";
    CIP_PATH = "CIP031" Error "a path that does not decode as an EPATH, or names an assembly instance (connection point) the file does not have"
        why "The scanner sends the path in its Forward_Open; a path that does not decode or names no connection point is refused by the adapter.";
    CIP_CONNECTION_WORD = "CIP032" Warning "a connection whose trigger and transport word names no transport class, trigger or application type, or whose parameters word allows neither fixed nor variable size in a direction"
        why "The scanner builds the transport class, trigger and fixed/variable flags of its Forward_Open from this word; nonsense here gives a Forward_Open the adapter refuses.";
    // ---- EDS0xx: text and values (readers) ----
    UNREADABLE = "EDS000" Error "the file cannot be read at all (missing, a directory, no permission); `edsgen validate` exits 2"
        why "Nothing in the file can be checked or generated; a build that depends on it stops here.";
    UNPARSEABLE_LINE = "EDS001" Error "a line that is not blank, a comment, a `[section]` or `key=value`"
        why "Tools skip or refuse such a line differently, so an entry the author meant may be missing in one tool and present in another.";
    NON_ASCII = "EDS002" Warning "bytes outside ASCII (the file was decoded as UTF-8, UTF-16 or Windows-1252; a byte that reads as punctuation between two letters in Windows-1252 and as a letter in DOS code page 437/850 is reported as a guess)"
        why "CiA 306 files are ASCII; tools that read them as ASCII or as another code page show wrong characters in names, and generated identifiers are derived from those names.";
    LONG_LINE = "EDS003" Warning "a line longer than 255 characters (once per file, naming the other lines)"
        why "CiA 306 limits lines to 255 characters; some configuration tools truncate longer lines and lose the end of the value.";
    INLINE_COMMENT = "EDS004" Warning "a comment not in column 1, or an inline `;` comment after a value"
        why "CiA 306 allows comments only in column 1; a tool that does not strip an inline comment reads it as part of the value.";
    DUPLICATE_SECTION = "EDS005" Error "a section appears twice (case-insensitive); the last one wins"
        why "Tools keep the first or the last copy differently, so two tools can describe the device differently from one file.";
    DUPLICATE_KEY = "EDS006" Error "a key appears twice in one section; the last one wins"
        why "Tools keep the first or the last value differently, so a master and edsgen can disagree about the entry.";
    KEY_SPELLING = "EDS007" Warning "whitespace before `=`, around a section name, or a key with characters other than [A-Za-z0-9_]"
        why "Strict readers (python canopen, CANopen Magic) look keys up by their exact name and miss such a key.";
    CASE_ONLY_MATCH = "EDS008" Info "a section or key that matches its canonical name only case-insensitively (warning for `LineN` in [Comments] and `DummyNNNN` in [DummyUsage]: python canopen looks them up case-sensitively and cannot import the file)"
        why "Case-sensitive readers such as python canopen do not find the key, and use a default in its place or cannot import the file.";
    UNKNOWN_ITEM = "EDS009" Info "an unknown section or key (kept, not interpreted)"
        why "Nothing generated depends on it; an unknown key is often a misspelling whose value the author meant to be read.";
    LEADING_ZEROS = "EDS010" Warning "a numbered key or a section name with extra leading zeros"
        why "Readers that match section and key names as text do not find `[01000]` or `Line01`, and lose the entry.";
    BAD_NUMBER = "EDS011" Error "a value that should be a number is not one"
        why "The entry's number is lost, so the object, limit or count it gives cannot be used by any tool.";
    BAD_VALUE = "EDS012" Error "a value cannot be parsed for its data type"
        why "The default cannot be loaded; a master that downloads defaults sends nothing or garbage, and the generated code has no value for it.";
    OUT_OF_RANGE = "EDS013" Error "a value outside the range of its data type (warning for a LowLimit below or a HighLimit above the range, for HighLimit=-1 on an unsigned type, or a hex HighLimit on a signed type that two's complement would put below LowLimit: they restrict nothing and are ignored, once per kind per file naming the other lines)"
        why "A value no variable of the type can hold cannot be downloaded; tools truncate it or refuse the file.";
    TWOS_COMPLEMENT = "EDS014" Info "an unsigned hex literal read as two's complement for a signed type"
        why "Tools that do not read hex as two's complement take the value as a large positive number outside the type.";
    NODEID_FORMULA = "EDS015" Error "a $NODEID formula that is not `$NODEID + number`, or on a non-integer type"
        why "Tools that cannot evaluate the formula leave the value out, so COB-IDs and other node-relative values are wrong on every node.";
    NODEID_DIALECT = "EDS016" Warning "a $NODEID formula in a form the spec does not define (postfix, other case); once per form per file, naming the other lines"
        why "Readers that implement only CiA 306's `$NODEID+n` do not resolve other forms, so the node-relative value is wrong in them.";
    OCTAL_LITERAL = "EDS017" Info "an integer with a leading 0 read as octal, as CiA 306 says"
        why "Tools that read the literal as decimal (most C and Python readers) take another value than CiA 306 says.";
    QUOTED_STRING = "EDS018" Info "a string value wrapped in quotes (kept literally, per the spec)"
        why "Tools that strip the quotes and tools that keep them show different strings, and a length computed from the file differs by two.";
    REAL_BIT_PATTERN = "EDS019" Warning "a REAL value written as a hex integer (read as an IEEE 754 bit pattern when it has the type's full 8 or 16 digits, else as a number)"
        why "A tool reading the hex as a number gets a value far from the one meant, and the device starts with it.";
    FLOAT_ON_INTEGER = "EDS020" Warning "a float literal on an integer type"
        why "Tools truncate or refuse the fraction differently, so the default differs between tools.";
    BAD_BOOLEAN = "EDS021" Warning "a boolean key that is not 0 or 1"
        why "Tools read anything other than 0 or 1 as false, true or an error, so the flag means different things in different tools.";
    EMPTY_FILE = "EDS022" Error "the file is empty (or only whitespace), or holds no sections"
        why "There is nothing to configure the device with; a build that depends on the file would generate nothing.";
    COMMISSIONING_SPELLING = "EDS023" Info "the DCF section is spelled `[DeviceCommissioning]` (two m); read as the spec's `[DeviceComissioning]`"
        why "Readers that know only the spec's spelling miss the node-ID and bit rate of the commissioning section.";
    ORPHAN_SECTION = "EDS024" Warning "a sub-index, name, value, denotation or link section (or entry) for an object or sub-index the file does not describe (kept, not interpreted)"
        why "The entry describes nothing the device has, and the values the author wrote there are used by no tool.";
    C_LITERAL_SUFFIX = "EDS025" Warning "an integer or REAL value with a C literal suffix (`LL`, `U`, `f`; written by CANopenNode/CANopenEditor), read without the suffix; once per type per file, naming the other lines"
        why "Readers that follow CiA 306 refuse the value or read it as 0, so the device's default differs between tools.";
    BYTES_DIALECT = "EDS026" Warning "an OCTET_STRING/DOMAIN value written as a `0x` literal (read as its hex digits in written order, Sevcon dialect) or a DOMAIN value `0` (read as empty, CANopenNode dialect); once per form per file, naming the other lines"
        why "Tools that do not know the dialect read other bytes than the author meant, so the default sent to the device differs.";
    COMMENT_CONTINUATION = "EDS027" Warning "a line without `;` or `=` right after a comment line: read as the comment's continuation (a comment with a line break in it)"
        why "Readers that expect one line per entry report the continuation as a broken line, or lose it.";
    EMPTY_NUMBER = "EDS028" Warning "an empty [DeviceInfo] number or boolean, or [Comments] Lines (`VendorNumber=`): read as absent, as CiA 306 says, but python canopen cannot import the file"
        why "Strict readers such as python canopen cannot import the file at all, and other tools read the empty value as 0.";
    NOT_TEXT = "EDS029" Error "not a text file: a NUL byte in a file that is not UTF-16 (nothing is read, and none of its bytes are shown)"
        why "Nothing is read; a file that is not text is usually the wrong file given for the description.";
    BAD_SUB_INDEX = "EDS030" Error "a sub-index section whose sub-index cannot exist: above FFh (sub-index sections are hex: `[D000sub100]` is 0x100, often a sub-index counted in decimal) or not a hex number (the section is kept, not read); or a `[xxxxName]`/`[xxxxValue]`/`[xxxxDenotation]` key above 255 (not read)"
        why "The sub-index cannot exist on the bus (a sub-index is one byte), so the entry can never be read or written.";


    // ---- EDS1xx: [FileInfo] and [DeviceInfo] (validator) ----
    FILE_INFO_MISSING = "EDS101" Warning "[FileInfo] is missing (mandatory in CiA 306; warning because nothing generated depends on it)"
        why "Tools show no file version or author; a user cannot tell which revision of the description is installed.";
    EDS_VERSION = "EDS102" Warning "EDSVersion is missing (meaning 3.0) or is not of the form x.y"
        why "Readers that switch behaviour on the version (python canopen, vendor tools) treat the file as 3.0, which can differ from what the author wrote it for.";
    FILE_DATE_FORMAT = "EDS103" Info "a FileInfo time or date not in the CiA 306 form hh:mm(AM|PM) / mm-dd-yyyy (info: cosmetic, widespread)"
        why "Purely cosmetic: tools show the date as written or not at all.";
    FILE_INFO_LIMITS = "EDS104" Warning "FileVersion/FileRevision not an UNSIGNED8, or Description/CreatedBy/ModifiedBy longer than CiA 306 allows"
        why "Tools that store these fields with CiA 306's sizes truncate or refuse them.";
    DEVICE_INFO_MISSING = "EDS105" Error "[DeviceInfo] is missing"
        why "Without [DeviceInfo] no tool knows the device's bit rates, PDO counts or identity, and masters cannot configure it.";
    IDENTITY_MISMATCH = "EDS106" Warning "VendorNumber/ProductNumber/RevisionNumber differs from the default of 1018h sub 1/2/3"
        why "A master that checks identity against the [DeviceInfo] numbers and one that checks against 1018h judge the same device differently.";
    BAUD_RATES = "EDS107" Warning "no BaudRate_x=1 at all, or a BaudRate_x key for a bit rate CiA 301 does not define"
        why "A master picks the bit rate from BaudRate_x; without one, or with a rate CiA 301 lacks, no network can be configured for the device.";
    GRANULARITY_RANGE = "EDS108" Error "Granularity is above 64"
        why "A Granularity above 64 bits cannot be mapped into a CAN frame; mapping tools refuse or misbehave.";
    GRANULARITY_ZERO_WRITABLE = "EDS109" Warning "Granularity is 0 (mapping not modifiable) but a PDO mapping sub-object is writable"
        why "A tool that trusts Granularity 0 never remaps, while one that trusts the writable mapping does and may get an abort.";
    PDO_COUNT_MISMATCH = "EDS110" Warning "NrOfRXPDO/NrOfTXPDO differs from the number of PDO communication objects"
        why "Masters size their PDO configuration from NrOfRXPDO/NrOfTXPDO and ignore or miss the extra PDOs.";
    PDO_COUNT_LIMIT = "EDS111" Error "NrOfRXPDO or NrOfTXPDO is above 512"
        why "CiA 301 allows at most 512 PDOs per direction; tools that allocate by these counts fail.";
    COMPACT_PDO_BITS = "EDS112" Warning "CompactPDO has bits set above 0x3F"
        why "The reserved bits have no meaning, and a tool that interprets them as flags configures a compact PDO the device does not have.";
    LSS_IDENTITY = "EDS113" Warning "LSS_Supported=1 but 1018h sub 1..4 (the LSS address) are not all present"
        why "An LSS master identifies the node by 1018h sub 1 to 4; without them the node cannot be addressed or configured by LSS.";
    DYNAMIC_CHANNELS_FLAG = "EDS114" Warning "DynamicChannelsSupported is non-zero without [DynamicChannels], or the reverse"
        why "Tools that enable dynamic channels from one and not the other configure channels the device does not have, or miss those it has.";

    // ---- EDS2xx: object lists (validator) ----
    MANDATORY_LIST_MISSING = "EDS201" Error "[MandatoryObjects] is missing"
        why "Readers that start from [MandatoryObjects] (Lely, vendor tools) find no objects at all.";
    OBJECT_LIST_MISSING = "EDS202" Warning "[OptionalObjects] or [ManufacturerObjects] is missing although objects of its range exist"
        why "Readers that take the objects from the lists (Lely) miss every object of that range.";
    SUPPORTED_OBJECTS_COUNT = "EDS203" Warning "SupportedObjects is missing or differs from the numbered entries, or the entries are not 1..N (warning: edsgen uses the union of lists and sections)"
        why "Readers that count entries by SupportedObjects (Lely) ignore the entries beyond it, and those tools lose objects.";
    LISTED_WITHOUT_SECTION = "EDS204" Error "an object list names an index that has no [xxxx] section (warning for an entry numbered beyond SupportedObjects, which Lely ignores)"
        why "A master that trusts the list expects an object the file does not describe, and has no type or access for it.";
    UNLISTED_OBJECT = "EDS205" Warning "[xxxx] sections that no object list names, once per list (Lely ignores them, python uses them)"
        why "Lely ignores objects that no list names, python canopen uses them: the two tools describe different devices.";
    WRONG_OBJECT_LIST = "EDS206" Warning "indices in the wrong object list for their range, once per list"
        why "Readers that derive an object's class from its list treat the object as mandatory, optional or vendor-specific wrongly.";
    LISTED_TWICE = "EDS207" Warning "an index listed twice in the object lists (warning: harmless to edsgen, which uses the union)"
        why "Harmless here; some tools duplicate the object or refuse the second listing.";
    REQUIRED_OBJECT_MISSING = "EDS208" Error "1000h (device type), 1001h (error register) or 1018h (identity) is missing"
        why "Every CANopen master reads 1000h, 1001h and 1018h to identify and supervise a node; without them it refuses the device.";
    ERROR_CONTROL_MISSING = "EDS209" Warning "neither 1017h (heartbeat producer) nor 100Ch/100Dh (node guarding) is present"
        why "Without heartbeat or node guarding, a master cannot detect that the node has stopped.";

    // ---- EDS3xx: objects and sub-objects (validator) ----
    MISSING_NAME = "EDS301" Error "an object or sub-object has no ParameterName (once per object for its subs; warning for ARRAY elements, which are indexed)"
        why "Tools show an unnamed entry, and code generation has no name to derive the field from.";
    LONG_NAME = "EDS302" Warning "a ParameterName longer than 241 characters"
        why "CiA 306 limits names to 241 characters; tools truncate longer ones, and names differ between tools.";
    MISSING_KEY = "EDS303" Error "a key the CiA 306 object table makes mandatory is missing (DataType or AccessType of an entry; SubNumber of an ARRAY/RECORD)"
        why "Without its data type or access, no tool can read or write the entry safely.";
    KEY_NOT_ALLOWED = "EDS304" Warning "a key the CiA 306 object table does not allow: SubNumber on a VAR, PDOMapping on a DOMAIN (info, once per file: VAR keys on ARRAY/RECORD mains, a common dialect)"
        why "Tools that follow the object table strictly refuse the key or the file.";
    SUBNUMBER_AND_COMPACT = "EDS305" Error "both SubNumber and CompactSubObj are non-zero"
        why "The two keys describe the sub-objects in two ways at once; tools pick one and disagree on what exists.";
    SUBNUMBER_MISMATCH = "EDS306" Warning "SubNumber differs from the number of sub-objects described (warning: edsgen uses the sections; Lely loads only SubNumber of them)"
        why "Lely loads only SubNumber sub-objects, python canopen all of them: the tools see different devices.";
    SUB_INDEX_RESERVED = "EDS307" Error "a sub-object at sub-index FFh, which is reserved for the structure description"
        why "Sub-index FFh is the structure description in CiA 301; a value there collides with it on the bus.";
    SUB0_MISSING = "EDS308" Error "an ARRAY has no sub-index 0 or a sub-index 0 that is not UNSIGNED8 (warning for a RECORD, whose sub 0 some vendors use as a value)"
        why "Clients read sub-index 0 as the number of entries; without it, or in another type, they cannot walk the array.";
    SUB0_ACCESS = "EDS309" Warning "sub-index 0 of an ARRAY/RECORD is writable (except 1003h and the PDO mapping objects)"
        why "A master that writes sub 0 of a record changes its structure, which CiA 301 reserves for PDO mappings and error history.";
    SUB0_VALUE = "EDS310" Warning "the default of sub-index 0 differs from the highest sub-index present"
        why "Clients walk the array to sub 0's value; a different default makes them miss entries or read ones that do not exist.";
    ARRAY_MIXED_TYPES = "EDS311" Error "the elements of an ARRAY have different data types"
        why "Tools and generated code address ARRAY elements with one type; a different type makes an element read with the wrong size.";
    ARRAY_MIXED_ACCESS = "EDS312" Warning "the elements of an ARRAY have different AccessType or PDOMapping"
        why "Tools treat an ARRAY's elements alike, so an element's own access or mapping is ignored somewhere.";
    SUB_INDEX_GAPS = "EDS313" Info "gaps in the sub-indices of a RECORD (info) or of an ARRAY (warning: a client indexing the array 1..N meets a refused sub-index)"
        why "A client indexing an array 1..N meets a refused sub-index in a gap and stops there.";
    UNKNOWN_DATA_TYPE = "EDS314" Error "a DataType that is neither a basic type nor a DEFTYPE/DEFSTRUCT of the file"
        why "The entry's size and encoding are unknown, so no tool can read or write it.";
    DOMAIN_DATA_TYPE = "EDS315" Error "a DOMAIN object whose DataType is not 000Fh"
        why "CiA 306 fixes DOMAIN to type 000Fh; another type makes tools read the domain with a fixed size.";
    LIMITS_INVERTED = "EDS316" Error "LowLimit is greater than HighLimit (warning when a hex limit on a signed type causes it: read as two's complement, or a narrower two's-complement pattern such as 0xEC78 on INTEGER32)"
        why "No value satisfies the limits, so every write is refused by a tool that checks them.";
    VALUE_OUTSIDE_LIMITS = "EDS317" Warning "DefaultValue or ParameterValue outside [LowLimit, HighLimit] (for node-IDs 1..127 if $NODEID-relative)"
        why "A master that downloads the default gets a write refused by a device that checks its limits.";
    LIMITS_ON_NON_NUMERIC = "EDS318" Warning "LowLimit/HighLimit on a string, OCTET_STRING or DOMAIN entry"
        why "Limits on strings or domains have no meaning; tools that apply them refuse valid values.";
    NODEID_OVERFLOW = "EDS319" Warning "a $NODEID value that leaves the range of its type for some node-IDs 1..127 (error if for all of them)"
        why "On some nodes the value does not fit its type, so the COB-ID or value wraps and collides with another node's.";
    DEFAULT_COB_ID = "EDS320" Warning "the default COB-ID of 1014h, 1200h, 1400h..1403h or 1800h..1803h is not $NODEID plus the predefined-connection-set base (not checked for masters)"
        why "Masters expect the predefined connection set; another default COB-ID puts the PDO or SDO where the master does not listen.";
    OBJ_FLAGS_RESERVED = "EDS321" Warning "ObjFlags with reserved bits 2..31 set, once per file (warning: vendor tools store other flags there; nothing generated depends on them)"
        why "Tools that interpret the reserved bits change how they treat the entry.";
    COMPACT_SUB_OBJ_MISUSE = "EDS322" Error "CompactSubObj on a VAR or DOMAIN, or above 254"
        why "CompactSubObj on a VAR is meaningless, and above 254 the sub-indices run into FFh; tools build objects that cannot exist.";

    // ---- EDS4xx: PDOs (validator) ----
    PDO_PAIR = "EDS401" Error "a PDO communication object without its mapping object, or the reverse"
        why "A PDO without its other half cannot be configured: the master has a COB-ID without a mapping, or a mapping it cannot send.";
    PDO_COMM_SUB_TYPE = "EDS402" Error "a PDO communication sub-object with the wrong data type (COB-ID U32, type U8, inhibit U16, event timer U16, SYNC start U8)"
        why "The master writes the communication parameter with the wrong size and the device aborts the SDO.";
    PDO_COMM_SUB4 = "EDS403" Info "a PDO communication record implements sub-index 4 (reserved, a compatibility entry)"
        why "Sub-index 4 is reserved; a master that writes it gets an abort.";
    RPDO_TPDO_ONLY_SUB = "EDS404" Info "an RPDO communication record implements inhibit time (sub 3) or SYNC start (sub 6), which only TPDOs use"
        why "RPDOs have no inhibit time or SYNC start; a master that configures them gets an abort or expects a behaviour that does not exist.";
    COB_ID_RESTRICTED = "EDS405" Warning "a PDO COB-ID in a CAN-ID range CiA 301 restricts (NMT, SYNC/EMCY, TIME, SDO, LSS, heartbeat)"
        why "A PDO on a restricted CAN-ID collides with NMT, SYNC, EMCY, SDO or heartbeat frames and disturbs the network.";
    TRANSMISSION_TYPE_RESERVED = "EDS406" Warning "a reserved PDO transmission type (241..251 for a TPDO, 241..253 for an RPDO)"
        why "A reserved transmission type makes the device behave in a way no master expects, or refuse the configuration.";
    MAPPING_COUNT = "EDS407" Error "the number of mapped objects (mapping sub 0) is above 64 or above the mapping entries present (FEh and FFh are the MPDO modes, not counts)"
        why "A master mapping more entries than exist, or than 64, gets an abort, and the PDO stays disabled.";
    MAPPING_TARGET_MISSING = "EDS408" Error "a PDO mapping entry points to an entry that does not exist (warning for empty entries within the count, once per mapping; and with modules)"
        why "The mapping names an entry the device lacks, so the device refuses the mapping and the PDO carries nothing.";
    MAPPING_NOT_MAPPABLE = "EDS409" Error "a PDO mapping entry points to an entry with PDOMapping=0"
        why "The device refuses to map an entry that is not mappable: the PDO stays disabled.";
    MAPPING_DIRECTION = "EDS410" Error "a PDO mapping entry whose access does not fit the direction (RPDO to ro/const/rwr, TPDO to wo/rww)"
        why "An RPDO writing a read-only entry, or a TPDO reading a write-only one, is refused by the device.";
    DUMMY_NOT_ENABLED = "EDS411" Error "a dummy mapping entry for a data type that [DummyUsage] does not enable"
        why "A dummy entry for a type not enabled is refused by the device when the mapping is written.";
    MAPPING_LENGTH = "EDS412" Error "a PDO mapping length that differs from the bit width of the mapped entry (warning for a part of the entry that a Granularity below 8 allows)"
        why "The PDO's bytes are laid out with a width other than the entry's, so every value after it is shifted.";
    MAPPING_TOO_LONG = "EDS413" Error "a PDO maps more than 64 bits"
        why "A CAN frame carries at most 64 bits; the device refuses a longer mapping.";
    MAPPING_GRANULARITY = "EDS414" Warning "a PDO mapping length that is not a multiple of Granularity, or more than 8 entries with Granularity 8"
        why "The device refuses a mapping finer than its Granularity allows.";
    DUPLICATE_PDO_COB_ID = "EDS415" Warning "two enabled TPDOs, or two enabled RPDOs, have the same default COB-ID"
        why "Two PDOs on one COB-ID collide on the bus, or one is never received.";
    DUMMY_USAGE_KEY = "EDS416" Info "[DummyUsage] keys outside Dummy0001..Dummy0007 (info: Lely writes Dummy0000..Dummy001F)"
        why "Readers that know only Dummy0001..Dummy0007 ignore the others.";
    DUMMY_USAGE_MISSING = "EDS417" Warning "[DummyUsage] without one of Dummy0001..Dummy0007 (CiA 306 lists all seven; python canopen cannot import the file)"
        why "Strict readers such as python canopen cannot import the file, and other tools treat the missing dummies as unsupported.";

    // ---- EDS5xx: DCF, commissioning, modules, comments, object links, dynamic channels (validator) ----
    DCF_NODE_ID = "EDS501" Error "the DCF NodeID is outside 1..127 (warning for 255: unconfigured, assigned by LSS; and for 0: not commissioned, as CANopenEditor writes it)"
        why "The DCF configures a node-ID the network cannot use; the node does not answer where the master expects it.";
    DCF_BAUDRATE = "EDS502" Error "the DCF Baudrate is not a CiA 301 bit rate, or not one [DeviceInfo] enables (warning for 0: not commissioned, as CANopenEditor writes it)"
        why "The DCF configures a bit rate the device does not support, and the node is silent on the network.";
    LSS_SERIAL_MISMATCH = "EDS503" Warning "LSS_SerialNumber differs from the value of 1018h sub 4"
        why "LSS identifies the node by its serial number; a mismatch makes LSS find no node or the wrong one.";
    COMMISSIONING_NAME_LENGTH = "EDS504" Warning "NodeName longer than 246 or NetworkName longer than 243 characters"
        why "Tools that store names with CiA 306's sizes truncate longer ones.";
    DCF_ITEM_IN_EDS = "EDS505" Warning "a DCF-only item (ParameterValue, Denotation, [DeviceComissioning]) in an .eds file"
        why "An EDS describes a device type, not a commissioned node; tools that read an EDS ignore DCF-only items.";
    DCF_WITHOUT_COMMISSIONING = "EDS506" Warning "a .dcf file without [DeviceComissioning] (warning: vendors ship EDS files renamed to .dcf)"
        why "A DCF without commissioning data has no node-ID or bit rate, so it configures nothing beyond the EDS.";
    DOMAIN_FILE_KEYS = "EDS507" Warning "UploadFile/DownloadFile on a non-DOMAIN, with an access that cannot upload/download, or a name too long"
        why "The tool tries to upload or download a file through an entry that cannot carry one.";
    PARAMETER_VALUE_READ_ONLY = "EDS508" Warning "ParameterValue differs from DefaultValue on a ro/const entry, which a download cannot write"
        why "A master downloads the DCF's value to an entry it cannot write and gets an abort.";
    MODULES = "EDS509" Warning "module sections that do not fit together (ConnectedModules, SupportedModules, Mx sections, Count, NrOfEntries)"
        why "A tool building a modular device cannot tell which modules fit or how many entries they add.";
    COMMENTS_LINES = "EDS510" Warning "[Comments] Lines differs from the LineN keys, or a comment line is longer than 249 characters"
        why "Tools that read comments by count lose lines or read past them.";
    OBJECT_LINK_MISSING = "EDS511" Warning "an [xxxxObjectLinks] entry names an object that does not exist"
        why "A tool following the link finds nothing, and the grouping the author meant is lost.";
    DYNAMIC_CHANNELS_SECTION = "EDS512" Warning "[DynamicChannels] NrOfSeg differs from its segments, or a TypeN/DirN/RangeN is malformed"
        why "Tools cannot tell which objects the dynamic channels cover, so they configure other objects.";
    DYNAMIC_CHANNEL_OBJECTS = "EDS513" Info "objects described in the EDS inside a range [DynamicChannels] covers"
        why "Objects inside a dynamic-channel range are created at run time; describing them statically can conflict with what the device creates.";

    // ---- EDS6xx: XML (XDD/XDC) ----
    XML_MALFORMED = "EDS601" Error "the file is not well-formed XML; nothing could be read"
        why "Nothing can be read from a file that is not XML; the device cannot be configured from it.";
    XML_NO_OBJECT_LIST = "EDS602" Error "an XML description without a CANopenObjectList"
        why "Without a CANopenObjectList there is no dictionary, so there is nothing to configure or generate.";
    XML_MISSING_ATTRIBUTE = "EDS603" Error "a required attribute is missing (CANopenObject@index, CANopenSubObject@subIndex, @name, @objectType)"
        why "An object without index, sub-index, name or type cannot be addressed or generated.";
    XML_BAD_ATTRIBUTE = "EDS604" Error "an attribute or element value that cannot be read (hexBinary, number, boolean, enumeration)"
        why "The value cannot be used; tools that validate against the XDD schema refuse the file.";
    XML_UNRESOLVED_REF = "EDS605" Error "a uniqueIDRef that names no parameter (or a dataTypeIDRef that names no data type)"
        why "The entry has no parameter or type, so tools cannot tell its size, access or default.";
    XML_DUPLICATE = "EDS606" Error "an index, sub-index or uniqueID described twice; the last one wins"
        why "Tools keep the first or the last copy differently, so they disagree about the entry.";
    XML_SUBS_ON_VAR = "EDS607" Error "CANopenSubObject elements inside a VAR or DOMAIN object (ignored)"
        why "Sub-objects of a VAR cannot exist on the bus; tools ignore them or refuse the file.";
    XML_TYPE_CONFLICT = "EDS608" Warning "the parameter disagrees with the object: data type (the parameter wins) or access direction vs PDOmapping (PDOmapping wins)"
        why "Tools that read the object and tools that read the parameter see different types or access.";
    XML_UNKNOWN_TYPE = "EDS609" Warning "a parameter data type with no CANopen equivalent (variableRef, struct, array on a VAR)"
        why "No CANopen data type holds the value, so the entry cannot be read, written or mapped.";

    // ---- EDS7xx: code generation ----
    NAME_COLLISION = "EDS701" Info "a generated Rust name collided with an earlier one and was made unique"
        why "A field name differs from the file's name, which a user searching the generated code for that name should know.";
    UNREPRESENTABLE_TYPE = "EDS702" Error "an entry's data type cannot be represented in generated code"
        why "The generated code cannot hold the entry's values, so it cannot be read or written through it.";
    UNREPRESENTABLE_VALUE = "EDS703" Error "a default or parameter value does not fit its entry's Rust type"
        why "The generated default would not compile or would differ from the file's.";
    UNTYPED_PDO = "EDS704" Warning "a default PDO mapping cannot be typed; no PDO struct is generated for it"
        why "No PDO struct is generated, so the application must decode that PDO by hand.";
    NO_DEFAULT = "EDS705" Info "an entry without a default value; its generated field starts at zero or empty"
        why "The entry starts at zero or empty, which may not be what the device does.";
    UNUSABLE_LIMIT = "EDS706" Warning "a LowLimit or HighLimit the generated write cannot check (not a constant of the entry's type)"
        why "The generated setter cannot enforce the limit, so the application must check it.";
    CAPACITY_TOO_LARGE = "EDS707" Error "a string, octet string or domain longer than 65535 bytes, or a device whose values need more than 65535 bytes in all"
        why "The generated storage has 16-bit capacities; a longer value would not fit.";
    OVERLAY = "EDS708" Error "an overlay (NAME.toml beside the description) that cannot be applied: not TOML, an unknown table, a key that names no entry (or, in [numbering], no ARRAY), a capacity on an entry that is not a string or domain, or below its value, a name without a letter or digit"
        why "The overlay's changes do not reach the generated code, so the device is built without them.";
    NO_DEFAULT_PDOS = "EDS709" Info "the description maps no default PDO, so no PDO struct is generated (the overlay's [pdo_mapping] can declare mappings)"
        why "No PDO struct is generated, so process data must be built by hand unless the overlay declares mappings.";

    // ---- EDS8xx: EtherCAT (ESI files) ----
    ESI_NO_DEVICE = "EDS801" Error "an ESI file with no Device to read (a module description, or no device matches the `--device` choice)"
        why "There is no device to generate or simulate; the wrong file or a wrong `--device` choice.";
    ESI_MODULES = "EDS802" Info "a modular device: its Slots and the file's Modules are read; a module's PDOs join the process image when the overlay's [modules] plugs it (a file of modules without a device is not read)"
        why "A modular device's I/O depends on its modules; without a choice of modules the images hold the device's own PDOs only.";
    ESI_IDENTITY = "EDS803" Error "a Vendor Id, ProductCode or RevisionNo that is missing or not a number"
        why "The master identifies the SubDevice by vendor, product code and revision; without them it cannot match the ESI to the device.";
    ESI_PROFILE = "EDS804" Warning "a device with a CoE dictionary but no Profile/ProfileNo"
        why "Masters take the CoE profile (e.g. 5001, 402) from the ESI to decide what to configure; without it profile objects are not used.";
    ESI_UNKNOWN_TYPE = "EDS805" Error "a Type that is neither an IEC 61131 type, STRING(n), ARRAY [..] OF .., nor a DataType of the Dictionary (the entry has no data type)"
        why "The entry's size is unknown, so PDOs mapping it cannot be laid out and SDO access has no type.";
    ESI_DUPLICATE_OBJECT = "EDS806" Error "an object index, or a DataType name, described twice in the Dictionary; the last one wins"
        why "Tools keep the first or last copy differently, so master and SubDevice can disagree.";
    ESI_PDO_ENTRY_MISSING = "EDS807" Error "a PDO Entry names an object or sub-index the Dictionary does not have, and no module of the file defines (at its index, or moved by a slot's SlotIndexIncrement)"
        why "The master maps an object the SubDevice does not have; the SubDevice refuses SafeOp.";
    ESI_PDO_ENTRY_LENGTH = "EDS808" Error "a PDO Entry's BitLen differs from the bit size of the object it maps"
        why "The PDO's bits are laid out with another width than the object's, so every value after it is shifted.";
    ESI_PDO_ALIGNMENT = "EDS809" Warning "a PDO Entry of 8 bits or more that does not start on a byte boundary of its PDO (ethercrab's wire types need byte alignment)"
        why "Masters that use byte-aligned types (ethercrab) cannot read the entry in place.";
    ESI_SM_OVERFLOW = "EDS810" Error "the PDOs assigned to a SyncManager by default hold more bytes than its DefaultSize"
        why "The SyncManager is too short for the PDOs assigned to it; the master cannot configure it and the SubDevice stays in PreOp.";
    ESI_EXCLUDE_MISSING = "EDS811" Warning "a PDO's Exclude names a PDO the device does not have"
        why "The exclusion names nothing, so a configuration tool cannot apply it as the author meant.";
    ESI_EXCLUDE_CONFLICT = "EDS812" Error "two PDOs that exclude each other are both assigned by default (both have Sm)"
        why "The device refuses a configuration with both PDOs, yet that is its default: the master cannot reach SafeOp without changing it.";
    ESI_DUPLICATE_PDO = "EDS813" Error "two RxPdo/TxPdo elements with the same Index"
        why "The master cannot tell the two PDOs apart, and maps or assigns the wrong one.";
    ESI_PDO_WITHOUT_SM = "EDS814" Info "PDOs without `Sm`: not assigned by default (once per device, naming them)"
        why "A master that uses the default assignment does not exchange these PDOs; their data is not in the process image unless assigned.";
    ESI_ALT_PDO_MISSING = "EDS815" Error "an AlternativeSmMapping assigns a PDO the device does not have"
        why "The master assigns a PDO the device does not have, and the SubDevice refuses SafeOp.";
    ESI_ALT_SM_OVERFLOW = "EDS816" Error "the PDOs an AlternativeSmMapping assigns to a SyncManager hold more bytes than its DefaultSize"
        why "The alternative mapping overflows its SyncManager, so selecting it fails.";
    ESI_ALT_EXCLUDE_CONFLICT = "EDS817" Error "an AlternativeSmMapping assigns two PDOs that exclude each other"
        why "Selecting the alternative mapping makes the device refuse the configuration.";
    SII_IMAGE = "EDS818" Error "an SII (EEPROM) image `.bin`/`.sii` that is shorter than its header, whose configuration-area CRC does not match, or whose categories run past its end or have no end marker"
        why "A SubDevice with a broken SII cannot be identified by its master, and its CRC error stops it at Init.";
    ESI_PDO_SWAPPED = "EDS819" Error "an RxPdo whose Index is a TxPDO mapping object (1A00h-1BFFh), or a TxPdo whose Index is an RxPDO one (1600h-17FFh): the directions are swapped"
        why "The master configures the PDOs in the wrong direction: outputs arrive where the device sends inputs, and the SubDevice cannot reach Op.";
    ESI_ASSIGN_DEFAULT = "EDS820" Warning "a default PDO assignment in the dictionary (1C12h, 1C13h: 1C10h + SyncManager) that lists other PDOs than those whose `Sm` names that SyncManager"
        why "A master that reads 1C12h/1C13h and one that follows the ESI's `Sm` assign different PDOs, so their process images disagree.";

    // ---- GSD0xx: PROFIBUS-DP GSD files (reader and validator) ----
    GSD_NOT_GSD = "GSD001" Error "no `#Profibus_DP` line: not a GSD file (read as one all the same)"
        why "A configuration tool cannot recognise the file as a GSD and refuses to import it.";
    GSD_UNPARSEABLE = "GSD002" Error "a line that is neither `Keyword = value`, a block's line nor a comment"
        why "Configuration tools refuse the line or the file, so the device cannot be added to a project.";
    GSD_UTF8 = "GSD003" Warning "the file is UTF-8 where the GSD specification says ISO 8859-1 (read as UTF-8; a Latin-1 tool shows its non-ASCII characters as two each)"
        why "Tools that read ISO 8859-1 show names and texts with broken characters, and master configurations carry them.";
    GSD_DUPLICATE = "GSD004" Error "a keyword appears twice (case-insensitive); the last one wins"
        why "Tools keep the first or last value differently, so masters can configure the slave differently.";
    GSD_UNKNOWN = "GSD005" Info "an unknown keyword (kept, not interpreted)"
        why "Nothing generated depends on it; an unknown keyword is often a misspelling whose value the author meant to be read.";
    GSD_BAD_VALUE = "GSD006" Error "a value that cannot be read for its keyword (a number, a quoted string, a byte list, a type, a range)"
        why "The keyword's value is lost; a master configured without it parameterises the slave wrongly or not at all.";
    GSD_BLOCK = "GSD007" Error "a block (Module, PrmText, ExtUserPrmData, SlotDefinition, Unit_Diag_Area) without its end, or an end without its block"
        why "Tools cannot tell where the block ends, so modules or parameter texts are lost or merged.";
    GSD_CFG_BYTES = "GSD010" Error "a module's configuration bytes cannot be decoded: an identifier says more bytes follow than there are"
        why "The master sends the configuration bytes in Chk_Cfg; bytes that do not decode make the slave refuse them with a configuration fault.";
    GSD_IO_LENGTH = "GSD011" Error "a module's input, output or total bytes beyond Max_Input_Len, Max_Output_Len or Max_Data_Len (a compact station's one module, or any one module of a modular station)"
        why "The slave refuses a configuration whose I/O exceeds its maximum lengths, so the master gets a Chk_Cfg fault.";
    GSD_PRM_REF = "GSD012" Error "an Ext_User_Prm_Data_Ref to an ExtUserPrmData, or a Prm_Text_Ref to a PrmText, the file does not define"
        why "The master builds Set_Prm from the referenced data; a missing reference leaves the parameter bytes wrong and the slave refuses them.";
    GSD_PRM_LENGTH = "GSD013" Error "an Ext_User_Prm_Data_Ref or _Const beyond User_Prm_Data_Len (or Max_User_Prm_Data_Len), or User_Prm_Data longer than User_Prm_Data_Len"
        why "The master sends Set_Prm longer than the slave accepts, so the slave reports a parameter fault and never enters data exchange.";
    GSD_PRM_DEFAULT = "GSD014" Error "an ExtUserPrmData default outside its allowed values, or allowed values outside its type"
        why "The master sends a default the slave does not allow, so Set_Prm is refused with a parameter fault.";
    GSD_IDENT = "GSD015" Error "Ident_Number is missing: a master cannot parameterise the slave"
        why "The master sends the Ident_Number in Set_Prm; without it the slave refuses the parameterisation.";
    GSD_TSDR = "GSD016" Warning "a supported baud rate without MaxTsdr (a MaxTsdr for a rate not supported is harmless, and not reported)"
        why "A master running at that baud rate cannot compute its bus timing for the slave and uses a guess, which can give timeouts.";
    GSD_NO_MODULE = "GSD017" Warning "no module: a master has no configuration to send in Chk_Cfg"
        why "Without a module a master has no configuration to send in Chk_Cfg, so it cannot start data exchange.";
    // ---- PN0xx: PROFINET (GSDML files) ----
    PN_IDENTITY = "PN001" Error "a GSDML file without DeviceIdentity, or whose VendorID or DeviceID is missing or not a 16-bit number"
        why "The controller identifies the device by VendorID and DeviceID in DCP; without them the GSDML cannot be matched to any device.";
    PN_NO_ACCESS_POINT = "PN002" Error "a GSDML file without a DeviceAccessPointItem (nothing to connect to)"
        why "Without an access point there is nothing for a controller to connect to.";
    PN_UNKNOWN_TYPE = "PN003" Error "a DataType GSDML does not define, or a string type without Length (the item's size is unknown)"
        why "The item's size is unknown, so the IO data or record cannot be laid out.";
    PN_IO_LIMIT = "PN004" Error "IO data beyond the access point's IOConfigData: a submodule's (or the fixed modules') inputs or outputs longer than MaxInputLength/MaxOutputLength"
        why "The device refuses a connection whose IO data exceeds its IOConfigData limits.";
    PN_NO_SLOT = "PN005" Warning "a module allowed in no slot: a ModuleItemRef whose slots are none of the access point's PhysicalSlots, or a ModuleItem no access point can use"
        why "A module no slot accepts cannot be configured; the engineering tool offers it but cannot place it.";
    PN_MISSING_MODULE = "PN006" Error "a ModuleItemRef whose ModuleItemTarget names no ModuleItem"
        why "The reference names nothing, so the slot it offers has no module to plug.";
    PN_MISSING_TEXT = "PN007" Warning "a TextId that no ExternalTextList text has (once per file, naming the other lines)"
        why "Engineering tools show the TextId or nothing in place of the name.";
    PN_MISSING_VALUE_LIST = "PN008" Error "a record field whose ValueItemTarget names no ValueItem"
        why "The record field has no value list, so the engineering tool cannot offer its values by name.";
    PN_RECORD_OVERLAP = "PN009" Error "two fields (Ref or Const) of one parameter record that share bytes or bits"
        why "Two fields write the same bits, so a controller's record changes one field when the user sets the other.";
    PN_RECORD_OVERRUN = "PN010" Error "a parameter record field (Ref or Const) that ends beyond the record's Length"
        why "The controller writes a record longer than the device expects, and the device refuses it.";
    PN_DUPLICATE_IDENT = "PN011" Error "two submodules of one module in one subslot, or two items with one ID (warning for two modules with one ModuleIdentNumber and different IO data; variants of a module with the same IO data may share one, as may access points, being alternatives, may share one)"
        why "The controller identifies modules and submodules by their ident numbers; two with one number cannot be told apart when plugged.";
    PN_DEFAULT_NOT_ALLOWED = "PN012" Error "a record field whose DefaultValue is not a number, or is outside its AllowedValues or its data type"
        why "The controller writes the default at start-up, and the device refuses the record.";
    PN_BIT_OUTSIDE = "PN013" Error "a BitDataItem whose BitOffset lies beyond its DataItem, or a Bit/BitArea field wider than a byte's bits allow"
        why "A bit outside its item reads or writes another field's bits.";
    PN_DUPLICATE_RECORD = "PN014" Error "two parameter records of one submodule with one Index"
        why "The controller writes both records to one index; the device keeps only one.";
    PN_DUPLICATE_EXT_DIAG = "PN015" Error "two ExtChannelDiagItems of one ChannelDiagItem with one ErrorType (an alarm's ExtChannelErrorType would have two meanings)"
        why "One ExtChannelErrorType with two meanings makes the controller show the wrong diagnosis.";
    PN_EXT_ADD_VALUE_SIZE = "PN016" Error "ExtChannelAddValue DataItems longer than the 4 bytes of an alarm's ExtChannelAddValue (Unsigned32)"
        why "An alarm's ExtChannelAddValue holds 4 bytes; the rest cannot be sent.";
    PN_DUPLICATE_SUBSLOT_LABEL = "PN017" Warning "two SubslotItems of one module or access point with one SubslotNumber (the subslot gets two labels)"
        why "The engineering tool shows two labels for one subslot.";
    PN_STATION_NAME = "PN018" Warning "an access point's DNS_CompatibleName (its default name of station) that PROFINET's name rules forbid in any case: DNS labels of letters, digits and `-`, at most 240 characters (capitals pass: controllers lowercase the name)"
        why "A controller assigns the device that name by DCP; a device refuses a name that breaks the rules, and the controller cannot connect.";
    PN_MISSPELT = "PN019" Warning "an attribute or child element that GSDML's schema does not allow on the element, a letter or two from one it does (with that name as help; a name far from every allowed one is left to schema validation)"
        why "The value is ignored by every tool, so the default, limit or slot the author wrote is lost, and engineering tools that validate against the schema refuse the file.";
}
