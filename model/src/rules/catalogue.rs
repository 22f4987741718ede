//! The catalogue itself: one line per rule, in code order (the table sorts by code).

use super::{Rule, Severity};

macro_rules! rules {
    ($($name:ident = $code:literal $sev:ident $summary:literal;)*) => {
        $(
            #[doc = $summary]
            // Summaries name sections like `[FileInfo]`, which rustdoc would read as links.
            #[allow(rustdoc::broken_intra_doc_links)]
            pub static $name: Rule = Rule { code: $code, severity: Severity::$sev, summary: $summary };
        )*
        /// Every rule, in code order.
        pub static ALL: &[&Rule] = &[$(&$name),*];
    };
}

rules! {
    // ---- CHK0xx: a live device against its description (`edsgen check`) ----
    CHK_MISSING = "CHK001" Error "(`edsgen check`) an object or sub-index of the description is missing on the device";
    CHK_LENGTH = "CHK002" Error "(`edsgen check`) the device's value has a length other than its data type's";
    CHK_UNREADABLE = "CHK003" Error "(`edsgen check`) the device refuses to read an entry the description says is readable";
    CHK_IDENTITY = "CHK004" Error "(`edsgen check`) the device's identity (1000h, 1018h:1-3) differs from the description";
    CHK_DEFAULT = "CHK005" Warning "(`edsgen check`) a value differs from the description's default or DCF ParameterValue (an error for a constant)";
    CHK_SII_IDENTITY = "CHK006" Error "(`edsgen ecat check`) the EtherCAT SubDevice's identity in its SII (vendor, product code, revision, order string) differs from the ESI";
    CHK_SYNC_MANAGER = "CHK007" Error "(`edsgen ecat check`) a SyncManager of the SubDevice's SII (kind, start, length, control byte, enable), or its ESC's SyncManager count, differs from the ESI";
    CHK_PDO_ASSIGNMENT = "CHK008" Error "(`edsgen ecat check`) the PDO assignment (1C12h/1C13h) or the mapping of a default PDO, read by SDO, differs from the ESI's default PDOs";

    // ---- CIP0xx: ODVA EDS (EtherNet/IP, DeviceNet; CIP). Before EDS0xx: codes sort by text ----
    CIP_SYNTAX = "CIP001" Error "ODVA EDS text: a line that is neither a `[section]`, an entry `Key = ...;` nor a `$` comment, an entry without its `;`, or a string without its closing quote";
    CIP_UNKNOWN = "CIP002" Info "ODVA EDS: a section or key this reader does not interpret (kept as written); the specification's class sections (`[... Class]`, `[ClassN_VendorM]`) are kept without a report";
    CIP_DUPLICATE = "CIP003" Error "ODVA EDS: a section or a key written twice; the last entry wins";
    CIP_BAD_FIELD = "CIP004" Error "ODVA EDS: a field that should be a number (or reference) is not one, or an entry with fewer fields than its kind has";
    CIP_IDENTITY = "CIP005" Error "ODVA EDS: `[File]` or `[Device]` missing, or `[Device]` without a key a scanner matches (VendCode, ProdType, ProdCode, MajRev, MinRev, ProdName)";
    CIP_DATA_TYPE = "CIP010" Error "a parameter whose data type is not a CIP elementary type, or whose data size disagrees with its type";
    CIP_LIMITS = "CIP011" Error "a parameter whose default is outside its limits, whose minimum exceeds its maximum, or a limit outside its data type";
    CIP_ENUM_ORPHAN = "CIP012" Error "an `EnumN` for a parameter `ParamN` the file does not have";
    CIP_ASSEMBLY_SIZE = "CIP020" Error "an assembly whose members' bits, rounded up to whole bytes, do not add up to its size in bytes";
    CIP_MISSING_REF = "CIP021" Error "an assembly member or a connection field that names a `ParamN` or `AssemN` the file does not have";
    CIP_MEMBER_BYTES = "CIP022" Warning "assembly member sizes written in bytes where the EDS specification wants bits: read as bytes, because only that makes the assembly add up to its size";
    CIP_MEMBER_PARAM = "CIP023" Warning "an assembly member whose size in bits differs from its parameter's data size (a BOOL or bit string may take fewer bits)";
    CIP_CONNECTION_SIZE = "CIP030" Error "a connection size that disagrees with the size of the assembly it names as its format (or that its path names)";
    CIP_PATH = "CIP031" Error "a path that does not decode as an EPATH, or names an assembly instance (connection point) the file does not have";
    CIP_CONNECTION_WORD = "CIP032" Warning "a connection whose trigger and transport word names no transport class, trigger or application type, or whose parameters word allows neither fixed nor variable size in a direction";
    // ---- EDS0xx: text and values (readers) ----
    UNREADABLE = "EDS000" Error "the file cannot be read at all (missing, a directory, no permission); `edsgen validate` exits 2";
    UNPARSEABLE_LINE = "EDS001" Error "a line that is not blank, a comment, a `[section]` or `key=value`";
    NON_ASCII = "EDS002" Warning "bytes outside ASCII (the file was decoded as UTF-8, UTF-16 or Windows-1252; a byte that reads as punctuation between two letters in Windows-1252 and as a letter in DOS code page 437/850 is reported as a guess)";
    LONG_LINE = "EDS003" Warning "a line longer than 255 characters (once per file, naming the other lines)";
    INLINE_COMMENT = "EDS004" Warning "a comment not in column 1, or an inline `;` comment after a value";
    DUPLICATE_SECTION = "EDS005" Error "a section appears twice (case-insensitive); the last one wins";
    DUPLICATE_KEY = "EDS006" Error "a key appears twice in one section; the last one wins";
    KEY_SPELLING = "EDS007" Warning "whitespace before `=`, around a section name, or a key with characters other than [A-Za-z0-9_]";
    CASE_ONLY_MATCH = "EDS008" Info "a section or key that matches its canonical name only case-insensitively (warning for `LineN` in [Comments] and `DummyNNNN` in [DummyUsage]: python canopen looks them up case-sensitively and cannot import the file)";
    UNKNOWN_ITEM = "EDS009" Info "an unknown section or key (kept, not interpreted)";
    LEADING_ZEROS = "EDS010" Warning "a numbered key or a section name with extra leading zeros";
    BAD_NUMBER = "EDS011" Error "a value that should be a number is not one";
    BAD_VALUE = "EDS012" Error "a value cannot be parsed for its data type";
    OUT_OF_RANGE = "EDS013" Error "a value outside the range of its data type (warning for a LowLimit below or a HighLimit above the range, for HighLimit=-1 on an unsigned type, or a hex HighLimit on a signed type that two's complement would put below LowLimit: they restrict nothing and are ignored, once per kind per file naming the other lines)";
    TWOS_COMPLEMENT = "EDS014" Info "an unsigned hex literal read as two's complement for a signed type";
    NODEID_FORMULA = "EDS015" Error "a $NODEID formula that is not `$NODEID + number`, or on a non-integer type";
    NODEID_DIALECT = "EDS016" Warning "a $NODEID formula in a form the spec does not define (postfix, other case); once per form per file, naming the other lines";
    OCTAL_LITERAL = "EDS017" Info "an integer with a leading 0 read as octal, as CiA 306 says";
    QUOTED_STRING = "EDS018" Info "a string value wrapped in quotes (kept literally, per the spec)";
    REAL_BIT_PATTERN = "EDS019" Warning "a REAL value written as a hex integer (read as an IEEE 754 bit pattern when it has the type's full 8 or 16 digits, else as a number)";
    FLOAT_ON_INTEGER = "EDS020" Warning "a float literal on an integer type";
    BAD_BOOLEAN = "EDS021" Warning "a boolean key that is not 0 or 1";
    EMPTY_FILE = "EDS022" Error "the file is empty (or only whitespace), or holds no sections";
    COMMISSIONING_SPELLING = "EDS023" Info "the DCF section is spelled `[DeviceCommissioning]` (two m); read as the spec's `[DeviceComissioning]`";
    ORPHAN_SECTION = "EDS024" Warning "a sub-index, name, value, denotation or link section (or entry) for an object or sub-index the file does not describe (kept, not interpreted)";
    C_LITERAL_SUFFIX = "EDS025" Warning "an integer or REAL value with a C literal suffix (`LL`, `U`, `f`; written by CANopenNode/CANopenEditor), read without the suffix; once per type per file, naming the other lines";
    BYTES_DIALECT = "EDS026" Warning "an OCTET_STRING/DOMAIN value written as a `0x` literal (read as its hex digits in written order, Sevcon dialect) or a DOMAIN value `0` (read as empty, CANopenNode dialect); once per form per file, naming the other lines";
    COMMENT_CONTINUATION = "EDS027" Warning "a line without `;` or `=` right after a comment line: read as the comment's continuation (a comment with a line break in it)";
    EMPTY_NUMBER = "EDS028" Warning "an empty [DeviceInfo] number or boolean, or [Comments] Lines (`VendorNumber=`): read as absent, as CiA 306 says, but python canopen cannot import the file";
    NOT_TEXT = "EDS029" Error "not a text file: a NUL byte in a file that is not UTF-16 (nothing is read, and none of its bytes are shown)";
    BAD_SUB_INDEX = "EDS030" Error "a sub-index section whose sub-index cannot exist: above FFh (sub-index sections are hex: `[D000sub100]` is 0x100, often a sub-index counted in decimal) or not a hex number (the section is kept, not read); or a `[xxxxName]`/`[xxxxValue]`/`[xxxxDenotation]` key above 255 (not read)";


    // ---- EDS1xx: [FileInfo] and [DeviceInfo] (validator) ----
    FILE_INFO_MISSING = "EDS101" Warning "[FileInfo] is missing (mandatory in CiA 306; warning because nothing generated depends on it)";
    EDS_VERSION = "EDS102" Warning "EDSVersion is missing (meaning 3.0) or is not of the form x.y";
    FILE_DATE_FORMAT = "EDS103" Info "a FileInfo time or date not in the CiA 306 form hh:mm(AM|PM) / mm-dd-yyyy (info: cosmetic, widespread)";
    FILE_INFO_LIMITS = "EDS104" Warning "FileVersion/FileRevision not an UNSIGNED8, or Description/CreatedBy/ModifiedBy longer than CiA 306 allows";
    DEVICE_INFO_MISSING = "EDS105" Error "[DeviceInfo] is missing";
    IDENTITY_MISMATCH = "EDS106" Warning "VendorNumber/ProductNumber/RevisionNumber differs from the default of 1018h sub 1/2/3";
    BAUD_RATES = "EDS107" Warning "no BaudRate_x=1 at all, or a BaudRate_x key for a bit rate CiA 301 does not define";
    GRANULARITY_RANGE = "EDS108" Error "Granularity is above 64";
    GRANULARITY_ZERO_WRITABLE = "EDS109" Warning "Granularity is 0 (mapping not modifiable) but a PDO mapping sub-object is writable";
    PDO_COUNT_MISMATCH = "EDS110" Warning "NrOfRXPDO/NrOfTXPDO differs from the number of PDO communication objects";
    PDO_COUNT_LIMIT = "EDS111" Error "NrOfRXPDO or NrOfTXPDO is above 512";
    COMPACT_PDO_BITS = "EDS112" Warning "CompactPDO has bits set above 0x3F";
    LSS_IDENTITY = "EDS113" Warning "LSS_Supported=1 but 1018h sub 1..4 (the LSS address) are not all present";
    DYNAMIC_CHANNELS_FLAG = "EDS114" Warning "DynamicChannelsSupported is non-zero without [DynamicChannels], or the reverse";

    // ---- EDS2xx: object lists (validator) ----
    MANDATORY_LIST_MISSING = "EDS201" Error "[MandatoryObjects] is missing";
    OBJECT_LIST_MISSING = "EDS202" Warning "[OptionalObjects] or [ManufacturerObjects] is missing although objects of its range exist";
    SUPPORTED_OBJECTS_COUNT = "EDS203" Warning "SupportedObjects is missing or differs from the numbered entries, or the entries are not 1..N (warning: edsgen uses the union of lists and sections)";
    LISTED_WITHOUT_SECTION = "EDS204" Error "an object list names an index that has no [xxxx] section (warning for an entry numbered beyond SupportedObjects, which Lely ignores)";
    UNLISTED_OBJECT = "EDS205" Warning "[xxxx] sections that no object list names, once per list (Lely ignores them, python uses them)";
    WRONG_OBJECT_LIST = "EDS206" Warning "indices in the wrong object list for their range, once per list";
    LISTED_TWICE = "EDS207" Warning "an index listed twice in the object lists (warning: harmless to edsgen, which uses the union)";
    REQUIRED_OBJECT_MISSING = "EDS208" Error "1000h (device type), 1001h (error register) or 1018h (identity) is missing";
    ERROR_CONTROL_MISSING = "EDS209" Warning "neither 1017h (heartbeat producer) nor 100Ch/100Dh (node guarding) is present";

    // ---- EDS3xx: objects and sub-objects (validator) ----
    MISSING_NAME = "EDS301" Error "an object or sub-object has no ParameterName (once per object for its subs; warning for ARRAY elements, which are indexed)";
    LONG_NAME = "EDS302" Warning "a ParameterName longer than 241 characters";
    MISSING_KEY = "EDS303" Error "a key the CiA 306 object table makes mandatory is missing (DataType or AccessType of an entry; SubNumber of an ARRAY/RECORD)";
    KEY_NOT_ALLOWED = "EDS304" Warning "a key the CiA 306 object table does not allow: SubNumber on a VAR, PDOMapping on a DOMAIN (info, once per file: VAR keys on ARRAY/RECORD mains, a common dialect)";
    SUBNUMBER_AND_COMPACT = "EDS305" Error "both SubNumber and CompactSubObj are non-zero";
    SUBNUMBER_MISMATCH = "EDS306" Warning "SubNumber differs from the number of sub-objects described (warning: edsgen uses the sections; Lely loads only SubNumber of them)";
    SUB_INDEX_RESERVED = "EDS307" Error "a sub-object at sub-index FFh, which is reserved for the structure description";
    SUB0_MISSING = "EDS308" Error "an ARRAY has no sub-index 0 or a sub-index 0 that is not UNSIGNED8 (warning for a RECORD, whose sub 0 some vendors use as a value)";
    SUB0_ACCESS = "EDS309" Warning "sub-index 0 of an ARRAY/RECORD is writable (except 1003h and the PDO mapping objects)";
    SUB0_VALUE = "EDS310" Warning "the default of sub-index 0 differs from the highest sub-index present";
    ARRAY_MIXED_TYPES = "EDS311" Error "the elements of an ARRAY have different data types";
    ARRAY_MIXED_ACCESS = "EDS312" Warning "the elements of an ARRAY have different AccessType or PDOMapping";
    SUB_INDEX_GAPS = "EDS313" Info "gaps in the sub-indices of a RECORD (info) or of an ARRAY (warning: a client indexing the array 1..N meets a refused sub-index)";
    UNKNOWN_DATA_TYPE = "EDS314" Error "a DataType that is neither a basic type nor a DEFTYPE/DEFSTRUCT of the file";
    DOMAIN_DATA_TYPE = "EDS315" Error "a DOMAIN object whose DataType is not 000Fh";
    LIMITS_INVERTED = "EDS316" Error "LowLimit is greater than HighLimit (warning when a hex limit on a signed type causes it: read as two's complement, or a narrower two's-complement pattern such as 0xEC78 on INTEGER32)";
    VALUE_OUTSIDE_LIMITS = "EDS317" Warning "DefaultValue or ParameterValue outside [LowLimit, HighLimit] (for node-IDs 1..127 if $NODEID-relative)";
    LIMITS_ON_NON_NUMERIC = "EDS318" Warning "LowLimit/HighLimit on a string, OCTET_STRING or DOMAIN entry";
    NODEID_OVERFLOW = "EDS319" Warning "a $NODEID value that leaves the range of its type for some node-IDs 1..127 (error if for all of them)";
    DEFAULT_COB_ID = "EDS320" Warning "the default COB-ID of 1014h, 1200h, 1400h..1403h or 1800h..1803h is not $NODEID plus the predefined-connection-set base (not checked for masters)";
    OBJ_FLAGS_RESERVED = "EDS321" Warning "ObjFlags with reserved bits 2..31 set, once per file (warning: vendor tools store other flags there; nothing generated depends on them)";
    COMPACT_SUB_OBJ_MISUSE = "EDS322" Error "CompactSubObj on a VAR or DOMAIN, or above 254";

    // ---- EDS4xx: PDOs (validator) ----
    PDO_PAIR = "EDS401" Error "a PDO communication object without its mapping object, or the reverse";
    PDO_COMM_SUB_TYPE = "EDS402" Error "a PDO communication sub-object with the wrong data type (COB-ID U32, type U8, inhibit U16, event timer U16, SYNC start U8)";
    PDO_COMM_SUB4 = "EDS403" Info "a PDO communication record implements sub-index 4 (reserved, a compatibility entry)";
    RPDO_TPDO_ONLY_SUB = "EDS404" Info "an RPDO communication record implements inhibit time (sub 3) or SYNC start (sub 6), which only TPDOs use";
    COB_ID_RESTRICTED = "EDS405" Warning "a PDO COB-ID in a CAN-ID range CiA 301 restricts (NMT, SYNC/EMCY, TIME, SDO, LSS, heartbeat)";
    TRANSMISSION_TYPE_RESERVED = "EDS406" Warning "a reserved PDO transmission type (241..251 for a TPDO, 241..253 for an RPDO)";
    MAPPING_COUNT = "EDS407" Error "the number of mapped objects (mapping sub 0) is above 64 or above the mapping entries present (FEh and FFh are the MPDO modes, not counts)";
    MAPPING_TARGET_MISSING = "EDS408" Error "a PDO mapping entry points to an entry that does not exist (warning for empty entries within the count, once per mapping; and with modules)";
    MAPPING_NOT_MAPPABLE = "EDS409" Error "a PDO mapping entry points to an entry with PDOMapping=0";
    MAPPING_DIRECTION = "EDS410" Error "a PDO mapping entry whose access does not fit the direction (RPDO to ro/const/rwr, TPDO to wo/rww)";
    DUMMY_NOT_ENABLED = "EDS411" Error "a dummy mapping entry for a data type that [DummyUsage] does not enable";
    MAPPING_LENGTH = "EDS412" Error "a PDO mapping length that differs from the bit width of the mapped entry (warning for a part of the entry that a Granularity below 8 allows)";
    MAPPING_TOO_LONG = "EDS413" Error "a PDO maps more than 64 bits";
    MAPPING_GRANULARITY = "EDS414" Warning "a PDO mapping length that is not a multiple of Granularity, or more than 8 entries with Granularity 8";
    DUPLICATE_PDO_COB_ID = "EDS415" Warning "two enabled TPDOs, or two enabled RPDOs, have the same default COB-ID";
    DUMMY_USAGE_KEY = "EDS416" Info "[DummyUsage] keys outside Dummy0001..Dummy0007 (info: Lely writes Dummy0000..Dummy001F)";
    DUMMY_USAGE_MISSING = "EDS417" Warning "[DummyUsage] without one of Dummy0001..Dummy0007 (CiA 306 lists all seven; python canopen cannot import the file)";

    // ---- EDS5xx: DCF, commissioning, modules, comments, object links, dynamic channels (validator) ----
    DCF_NODE_ID = "EDS501" Error "the DCF NodeID is outside 1..127 (warning for 255: unconfigured, assigned by LSS; and for 0: not commissioned, as CANopenEditor writes it)";
    DCF_BAUDRATE = "EDS502" Error "the DCF Baudrate is not a CiA 301 bit rate, or not one [DeviceInfo] enables (warning for 0: not commissioned, as CANopenEditor writes it)";
    LSS_SERIAL_MISMATCH = "EDS503" Warning "LSS_SerialNumber differs from the value of 1018h sub 4";
    COMMISSIONING_NAME_LENGTH = "EDS504" Warning "NodeName longer than 246 or NetworkName longer than 243 characters";
    DCF_ITEM_IN_EDS = "EDS505" Warning "a DCF-only item (ParameterValue, Denotation, [DeviceComissioning]) in an .eds file";
    DCF_WITHOUT_COMMISSIONING = "EDS506" Warning "a .dcf file without [DeviceComissioning] (warning: vendors ship EDS files renamed to .dcf)";
    DOMAIN_FILE_KEYS = "EDS507" Warning "UploadFile/DownloadFile on a non-DOMAIN, with an access that cannot upload/download, or a name too long";
    PARAMETER_VALUE_READ_ONLY = "EDS508" Warning "ParameterValue differs from DefaultValue on a ro/const entry, which a download cannot write";
    MODULES = "EDS509" Warning "module sections that do not fit together (ConnectedModules, SupportedModules, Mx sections, Count, NrOfEntries)";
    COMMENTS_LINES = "EDS510" Warning "[Comments] Lines differs from the LineN keys, or a comment line is longer than 249 characters";
    OBJECT_LINK_MISSING = "EDS511" Warning "an [xxxxObjectLinks] entry names an object that does not exist";
    DYNAMIC_CHANNELS_SECTION = "EDS512" Warning "[DynamicChannels] NrOfSeg differs from its segments, or a TypeN/DirN/RangeN is malformed";
    DYNAMIC_CHANNEL_OBJECTS = "EDS513" Info "objects described in the EDS inside a range [DynamicChannels] covers";

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
    CAPACITY_TOO_LARGE = "EDS707" Error "a string, octet string or domain longer than 65535 bytes, or a device whose values need more than 65535 bytes in all";
    OVERLAY = "EDS708" Error "an overlay (NAME.toml beside the description) that cannot be applied: not TOML, an unknown table, a key that names no entry (or, in [numbering], no ARRAY), a capacity on an entry that is not a string or domain, or below its value, a name without a letter or digit";
    NO_DEFAULT_PDOS = "EDS709" Info "the description maps no default PDO, so no PDO struct is generated (the overlay's [pdo_mapping] can declare mappings)";

    // ---- EDS8xx: EtherCAT (ESI files) ----
    ESI_NO_DEVICE = "EDS801" Error "an ESI file with no Device to read (a module description, or no device matches the `--device` choice)";
    ESI_MODULES = "EDS802" Info "a modular device: its Slots and the file's Modules are read, but no process image is generated for a module (a file of modules without a device is not read)";
    ESI_IDENTITY = "EDS803" Error "a Vendor Id, ProductCode or RevisionNo that is missing or not a number";
    ESI_PROFILE = "EDS804" Warning "a device with a CoE dictionary but no Profile/ProfileNo";
    ESI_UNKNOWN_TYPE = "EDS805" Error "a Type that is neither an IEC 61131 type, STRING(n), ARRAY [..] OF .., nor a DataType of the Dictionary (the entry has no data type)";
    ESI_DUPLICATE_OBJECT = "EDS806" Error "an object index, or a DataType name, described twice in the Dictionary; the last one wins";
    ESI_PDO_ENTRY_MISSING = "EDS807" Error "a PDO Entry names an object or sub-index the Dictionary does not have, and no module of the file defines (at its index, or moved by a slot's SlotIndexIncrement)";
    ESI_PDO_ENTRY_LENGTH = "EDS808" Error "a PDO Entry's BitLen differs from the bit size of the object it maps";
    ESI_PDO_ALIGNMENT = "EDS809" Warning "a PDO Entry of 8 bits or more that does not start on a byte boundary of its PDO (ethercrab's wire types need byte alignment)";
    ESI_SM_OVERFLOW = "EDS810" Error "the PDOs assigned to a SyncManager by default hold more bytes than its DefaultSize";
    ESI_EXCLUDE_MISSING = "EDS811" Warning "a PDO's Exclude names a PDO the device does not have";
    ESI_EXCLUDE_CONFLICT = "EDS812" Error "two PDOs that exclude each other are both assigned by default (both have Sm)";
    ESI_DUPLICATE_PDO = "EDS813" Error "two RxPdo/TxPdo elements with the same Index";
    ESI_PDO_WITHOUT_SM = "EDS814" Info "PDOs without `Sm`: not assigned by default (once per device, naming them)";
    ESI_ALT_PDO_MISSING = "EDS815" Error "an AlternativeSmMapping assigns a PDO the device does not have";
    ESI_ALT_SM_OVERFLOW = "EDS816" Error "the PDOs an AlternativeSmMapping assigns to a SyncManager hold more bytes than its DefaultSize";
    ESI_ALT_EXCLUDE_CONFLICT = "EDS817" Error "an AlternativeSmMapping assigns two PDOs that exclude each other";
    SII_IMAGE = "EDS818" Error "an SII (EEPROM) image `.bin`/`.sii` that is shorter than its header, whose configuration-area CRC does not match, or whose categories run past its end or have no end marker";
    ESI_PDO_SWAPPED = "EDS819" Error "an RxPdo whose Index is a TxPDO mapping object (1A00h-1BFFh), or a TxPdo whose Index is an RxPDO one (1600h-17FFh): the directions are swapped";
    ESI_ASSIGN_DEFAULT = "EDS820" Warning "a default PDO assignment in the dictionary (1C12h, 1C13h: 1C10h + SyncManager) that lists other PDOs than those whose `Sm` names that SyncManager";

    // ---- GSD0xx: PROFIBUS-DP GSD files (reader and validator) ----
    GSD_NOT_GSD = "GSD001" Error "no `#Profibus_DP` line: not a GSD file (read as one all the same)";
    GSD_UNPARSEABLE = "GSD002" Error "a line that is neither `Keyword = value`, a block's line nor a comment";
    GSD_UTF8 = "GSD003" Warning "the file is UTF-8 where the GSD specification says ISO 8859-1 (read as UTF-8; a Latin-1 tool shows its non-ASCII characters as two each)";
    GSD_DUPLICATE = "GSD004" Error "a keyword appears twice (case-insensitive); the last one wins";
    GSD_UNKNOWN = "GSD005" Info "an unknown keyword (kept, not interpreted)";
    GSD_BAD_VALUE = "GSD006" Error "a value that cannot be read for its keyword (a number, a quoted string, a byte list, a type, a range)";
    GSD_BLOCK = "GSD007" Error "a block (Module, PrmText, ExtUserPrmData, SlotDefinition, Unit_Diag_Area) without its end, or an end without its block";
    GSD_CFG_BYTES = "GSD010" Error "a module's configuration bytes cannot be decoded: an identifier says more bytes follow than there are";
    GSD_IO_LENGTH = "GSD011" Error "a module's input, output or total bytes beyond Max_Input_Len, Max_Output_Len or Max_Data_Len (a compact station's one module, or any one module of a modular station)";
    GSD_PRM_REF = "GSD012" Error "an Ext_User_Prm_Data_Ref to an ExtUserPrmData, or a Prm_Text_Ref to a PrmText, the file does not define";
    GSD_PRM_LENGTH = "GSD013" Error "an Ext_User_Prm_Data_Ref or _Const beyond User_Prm_Data_Len (or Max_User_Prm_Data_Len), or User_Prm_Data longer than User_Prm_Data_Len";
    GSD_PRM_DEFAULT = "GSD014" Error "an ExtUserPrmData default outside its allowed values, or allowed values outside its type";
    GSD_IDENT = "GSD015" Error "Ident_Number is missing: a master cannot parameterise the slave";
    GSD_TSDR = "GSD016" Warning "a supported baud rate without MaxTsdr (a MaxTsdr for a rate not supported is harmless, and not reported)";
    GSD_NO_MODULE = "GSD017" Warning "no module: a master has no configuration to send in Chk_Cfg";
    // ---- PN0xx: PROFINET (GSDML files) ----
    PN_IDENTITY = "PN001" Error "a GSDML file without DeviceIdentity, or whose VendorID or DeviceID is missing or not a 16-bit number";
    PN_NO_ACCESS_POINT = "PN002" Error "a GSDML file without a DeviceAccessPointItem (nothing to connect to)";
    PN_UNKNOWN_TYPE = "PN003" Error "a DataType GSDML does not define, or a string type without Length (the item's size is unknown)";
    PN_IO_LIMIT = "PN004" Error "IO data beyond the access point's IOConfigData: a submodule's (or the fixed modules') inputs or outputs longer than MaxInputLength/MaxOutputLength";
    PN_NO_SLOT = "PN005" Warning "a module allowed in no slot: a ModuleItemRef whose slots are none of the access point's PhysicalSlots, or a ModuleItem no access point can use";
    PN_MISSING_MODULE = "PN006" Error "a ModuleItemRef whose ModuleItemTarget names no ModuleItem";
    PN_MISSING_TEXT = "PN007" Warning "a TextId that no ExternalTextList text has (once per file, naming the other lines)";
    PN_MISSING_VALUE_LIST = "PN008" Error "a record field whose ValueItemTarget names no ValueItem";
    PN_RECORD_OVERLAP = "PN009" Error "two fields (Ref or Const) of one parameter record that share bytes or bits";
    PN_RECORD_OVERRUN = "PN010" Error "a parameter record field (Ref or Const) that ends beyond the record's Length";
    PN_DUPLICATE_IDENT = "PN011" Error "two submodules of one module in one subslot, or two items with one ID (warning for two modules with one ModuleIdentNumber and different IO data; variants of a module with the same IO data may share one, as may access points, being alternatives, may share one)";
    PN_DEFAULT_NOT_ALLOWED = "PN012" Error "a record field whose DefaultValue is not a number, or is outside its AllowedValues or its data type";
    PN_BIT_OUTSIDE = "PN013" Error "a BitDataItem whose BitOffset lies beyond its DataItem, or a Bit/BitArea field wider than a byte's bits allow";
    PN_DUPLICATE_RECORD = "PN014" Error "two parameter records of one submodule with one Index";
    PN_DUPLICATE_EXT_DIAG = "PN015" Error "two ExtChannelDiagItems of one ChannelDiagItem with one ErrorType (an alarm's ExtChannelErrorType would have two meanings)";
    PN_EXT_ADD_VALUE_SIZE = "PN016" Error "ExtChannelAddValue DataItems longer than the 4 bytes of an alarm's ExtChannelAddValue (Unsigned32)";
    PN_DUPLICATE_SUBSLOT_LABEL = "PN017" Warning "two SubslotItems of one module or access point with one SubslotNumber (the subslot gets two labels)";
    PN_STATION_NAME = "PN018" Warning "an access point's DNS_CompatibleName (its default name of station) that PROFINET's name rules forbid in any case: DNS labels of letters, digits and `-`, at most 240 characters (capitals pass: controllers lowercase the name)";
}
