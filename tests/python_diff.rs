//! Differential test: edsgen's model of every EDS/DCF file against python `canopen` 2.4.1's import
//! of the same file (`scripts/canopen_dump.py`, in the venv of `scripts/python-venv.sh`).
//!
//! Compared per object and sub-object: presence, names, object type, data types, access types,
//! PDO mappability and default values. Every disagreement on a corpus file must be listed in
//! [`KNOWN_DIFFERENCES`], exactly (file, index, sub-index, field), with the reason edsgen is right;
//! an unlisted difference, or a listed one that no longer occurs, fails the test. The bundled cards
//! in `eds/` must match python exactly, with one rule instead of a list: in a CompactSubObj array
//! python 2.4.1 invents sub-index 0 and the names (see [`compare`]), so there only types, access,
//! mapping and defaults are compared. The corpus files python cannot import must still read in
//! edsgen, each with a warning at the line that breaks python ([`PYTHON_FAILURES`]).
//!
//! Run with `EDSGEN_PYTHON_DIFF_JSON=FILE` to get every difference as JSON lines for review.

mod process_support;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;

use process_support::{corpus_dir, python, root};

use edsgen_model::diag::Severity;
use edsgen_model::{dump, read, validate};
use serde_json::Value as Json;

/// Which sub-indices a known difference covers.
#[derive(Debug, Clone, Copy)]
enum Subs {
    /// The object itself (object presence, name or type).
    Object,
    /// One sub-index.
    One(u8),
    /// Every sub-index of an inclusive range (each one must differ).
    Range(u8, u8),
}

/// Accepted disagreements between python canopen and edsgen: every (index, sub, field)
/// combination of one file, each of which must differ.
struct Known {
    /// The corpus file, relative to the corpus directory.
    file: &'static str,
    indices: &'static [u16],
    subs: Subs,
    /// Among `presence`, `name`, `object_type`, `data_type`, `access`, `pdo_mapping`, `default`.
    fields: &'static [&'static str],
    /// Why edsgen's reading is the right one.
    reason: &'static str,
}

const fn known(
    file: &'static str,
    indices: &'static [u16],
    subs: Subs,
    fields: &'static [&'static str],
    reason: &'static str,
) -> Known {
    Known {
        file,
        indices,
        subs,
        fields,
        reason,
    }
}

// Why edsgen is right, one reason per kind of disagreement.
const COMPACT_SUB0: &str = "CiA 306 compact storage: sub-index 0 is the entry count (ro, value \
    CompactSubObj); python 2.4.1 names it `Number of entries`, leaves it rw and without a value";
const COMPACT_NAMES: &str = "CiA 306 names compact sub-objects after the object and the \
    sub-index (X1, X2, ...); python names them X, X_2, X_3 (hex)";
const COMPACT_RECORD: &str = "Lely writes RECORDs (PDO mappings) with CompactSubObj; python \
    honours it only on ARRAYs and leaves the record empty, edsgen expands it";
const COMPACT_PDO: &str = "[DeviceInfo] CompactPDO implies the PDO communication and mapping \
    objects (CiA 306); python ignores CompactPDO";
const SIGNED_HEX: &str = "an unsigned hex literal of a signed type's width is its two's \
    complement (EDS014); python keeps the out-of-range unsigned number as the default";
const NODEID_CASE: &str = "`$NodeID + 0x80` is a $NODEID formula (EDS016); python 2.4.1 \
    recognises only upper-case `$NODEID` (python #180) and loses the value";
const NODEID_ALONE: &str = "`$NODEID` alone is `$NODEID+0`; python 2.4.1 cannot evaluate it \
    and loses the value";
const REAL_HEX: &str = "a REAL32 written as a 0x bit pattern (0x437A0000 is 250.0) is read as \
    IEEE 754 (EDS019); python's float() fails and loses the value";
const EMPTY_DEFAULT: &str = "`DefaultValue=` means 'no value' in CiA 306 (the model keeps the \
    empty raw text); python makes it an empty string or empty bytes";
const UNKNOWN_TYPE: &str = "a DataType above 0x1B without an [XXsub1] definition is kept as \
    written; python replaces it by DOMAIN (0x0F)";
const UNKNOWN_TYPE_DEFAULT: &str = "python's substitute DOMAIN cannot read `0x0` as hex bytes; \
    edsgen reads the integer of the file's own type 0x40";
const SHORT_SECTION: &str = "[A0] is a CANfestival type-definition section, index 0x00A0; \
    python reads only 4-digit section names";

const HEX_PREFIX_BYTES: &str = "an OCTET_STRING/DOMAIN written with a 0x prefix is read as \
    its bytes (EDS026); python's bytes.fromhex rejects the prefix and loses the value";
const ZERO_DOMAIN: &str = "a DOMAIN default written `0` means no content and reads as empty \
    (EDS026); python's bytes.fromhex cannot read a single digit";
const C_SUFFIX: &str = "a C literal suffix (`0.0f`, `LL`) is read past, with a warning \
    (EDS025); python's float()/int() fail and lose the value";
/// Every disagreement with python canopen 2.4.1 on the corpus, and why edsgen is right.
const KNOWN_DIFFERENCES: &[Known] = &[
    known("CANopenNode__CANopenDemo/demo__demoDevice.eds", &[0x1008, 0x1009, 0x100A, 0x2122], Subs::One(0), &["default"], EMPTY_DEFAULT),
    known("Daxbot__node-canopen/test__common__test.eds", &[0x200B, 0x200C, 0x200D, 0x2010, 0x201C, 0x201D, 0x201E, 0x201F], Subs::One(0), &["default"], EMPTY_DEFAULT),
    known("Daxbot__node-canopen/test__common__test.eds", &[0x201C, 0x201D, 0x201E, 0x201F], Subs::One(0), &["data_type"], UNKNOWN_TYPE),
    known("KITmedical__kacanopen_old/master__share__eds_library__cia__402.eds", &[0x607B, 0x607D], Subs::One(1), &["default"], SIGNED_HEX),
    known("KITmedical__kacanopen_old/master__share__eds_library__cia__402.eds", &[0x60C2], Subs::One(2), &["default"], SIGNED_HEX),
    known("Laerdal__python-objdictgen/tests__od__legacy-compare__jsontest.eds", &[0x1F20], Subs::Range(1, 2), &["default"], EMPTY_DEFAULT),
    known("Laerdal__python-objdictgen/tests__od__legacy-compare__jsontest.eds", &[0x00A0], Subs::Object, &["presence"], SHORT_SECTION),
    known("NobseVomBerg__CANopen-Bench/canopen_bench__seed__CiA301Base.eds", &[0x1008, 0x1009, 0x100A], Subs::One(0), &["default"], EMPTY_DEFAULT),
    known("Xeryon-Precision__XLA-INTG_prog_examples/eds__xeryon_xla_5_eds.eds", &[0x2013], Subs::One(1), &["default"], REAL_HEX),
    known("Xeryon-Precision__XLA-INTG_prog_examples/eds__xeryon_xla_5_eds.eds", &[0x3001], Subs::One(3), &["default"], REAL_HEX),
    known("amperaufsc__Sevcon/V6.dcf", &[0x2870], Subs::One(3), &["default"], SIGNED_HEX),
    known("brtiberio__Sevcon_gen4/Gen4.eds", &[0x4617], Subs::One(1), &["default"], HEX_PREFIX_BYTES),
    known("brtiberio__Sevcon_gen4/Gen4.eds", &[0x2870], Subs::One(3), &["default"], SIGNED_HEX),
    known("brtiberio__Sevcon_gen4/Gen4.eds", &[0x2870], Subs::One(7), &["default"], SIGNED_HEX),
    known("brtiberio__Sevcon_gen4/documents__2019-06-24-MOTEUR-UK0319-55-110V-300A-S4-GEN4-Config-origine.dcf", &[0x2870], Subs::One(3), &["default"], SIGNED_HEX),
    known("brtiberio__Sevcon_gen4/documents__2019-06-24-MOTEUR-UK0319-55-110V-300A-S4-GEN4-Config-origine.dcf", &[0x2870], Subs::One(7), &["default"], SIGNED_HEX),
    known("canopen-python__canopen/test__sample.eds", &[0x3006], Subs::Range(1, 24), &["name"], COMPACT_NAMES),
    known("canopen-python__canopen/test__sample.eds", &[0x3004, 0x3006], Subs::One(0), &["access", "default", "name"], COMPACT_SUB0),
    known("canopen-python__canopen/test__sample.eds", &[0x2020], Subs::One(0), &["data_type"], UNKNOWN_TYPE),
    known("canopen-python__canopen/test__sample.eds", &[0x2020], Subs::One(0), &["default"], UNKNOWN_TYPE_DEFAULT),
    known("christiansandberg__canopen/cog.eds", &[0x607D], Subs::One(1), &["default"], SIGNED_HEX),
    known("christiansandberg__canopen/test__sensor.eds", &[0x1003], Subs::Range(1, 255), &["name"], COMPACT_NAMES),
    known("christiansandberg__canopen/test__sensor.eds", &[0x3001], Subs::Range(1, 3), &["name"], COMPACT_NAMES),
    known("christiansandberg__canopen/test__sensor.eds", &[0x1003, 0x3001], Subs::One(0), &["access", "default", "name"], COMPACT_SUB0),
    known("delmic__odemis/src__odemis__driver__TMCM-1240_CANopen_V322.dcf", &[0x607D], Subs::One(1), &["default"], SIGNED_HEX),
    known("delmic__odemis/src__odemis__driver__TMCM-1240_CANopen_V322.dcf", &[0x60C2], Subs::One(2), &["default"], SIGNED_HEX),
    known("dianhuaeven__Eyou_Canopen_master/config__master.dcf", &[0x1003, 0x1029], Subs::Range(1, 254), &["name"], COMPACT_NAMES),
    known("dianhuaeven__Eyou_Canopen_master/config__master.dcf", &[0x1016, 0x1028, 0x1F25, 0x1F55, 0x1F81, 0x1F82, 0x1F84, 0x1F85, 0x1F86, 0x1F87, 0x1F88, 0x1F8A], Subs::Range(1, 127), &["name"], COMPACT_NAMES),
    known("dianhuaeven__Eyou_Canopen_master/config__master.dcf", &[0x5A00, 0x5A02, 0x5A04, 0x5A06, 0x5A08, 0x5A0A, 0x5E00, 0x5E03, 0x5E06, 0x5E09, 0x5E0C, 0x5E0E], Subs::Range(1, 3), &["name"], COMPACT_NAMES),
    known("dianhuaeven__Eyou_Canopen_master/config__master.dcf", &[0x5A01, 0x5A03, 0x5A05, 0x5A07, 0x5A09, 0x5A0B], Subs::Range(1, 2), &["name"], COMPACT_NAMES),
    known("dianhuaeven__Eyou_Canopen_master/config__master.dcf", &[0x5E01, 0x5E02, 0x5E04, 0x5E05, 0x5E07, 0x5E08, 0x5E0A, 0x5E0B, 0x5E0D, 0x5E0F], Subs::One(1), &["name"], COMPACT_NAMES),
    known("dianhuaeven__Eyou_Canopen_master/config__master.dcf", &[0x1600, 0x1602, 0x1604, 0x1606, 0x1608, 0x160A, 0x1A00, 0x1A03, 0x1A06, 0x1A09, 0x1A0C, 0x1A0E], Subs::Range(0, 3), &["presence"], COMPACT_RECORD),
    known("dianhuaeven__Eyou_Canopen_master/config__master.dcf", &[0x1601, 0x1603, 0x1605, 0x1607, 0x1609, 0x160B], Subs::Range(0, 2), &["presence"], COMPACT_RECORD),
    known("dianhuaeven__Eyou_Canopen_master/config__master.dcf", &[0x1A01, 0x1A02, 0x1A04, 0x1A05, 0x1A07, 0x1A08, 0x1A0A, 0x1A0B, 0x1A0D, 0x1A0F], Subs::Range(0, 1), &["presence"], COMPACT_RECORD),
    known("dianhuaeven__Eyou_Canopen_master/config__master.dcf", &[0x1003, 0x1016, 0x1028, 0x1029, 0x1F25, 0x1F55, 0x1F81, 0x1F82, 0x1F84, 0x1F85, 0x1F86, 0x1F87, 0x1F88, 0x1F8A, 0x5A00, 0x5A01, 0x5A02, 0x5A03, 0x5A04, 0x5A05, 0x5A06, 0x5A07, 0x5A08, 0x5A09, 0x5A0A, 0x5A0B, 0x5E00, 0x5E01, 0x5E02, 0x5E03, 0x5E04, 0x5E05, 0x5E06, 0x5E07, 0x5E08, 0x5E09, 0x5E0A, 0x5E0B, 0x5E0C, 0x5E0D, 0x5E0E, 0x5E0F], Subs::One(0), &["access", "default", "name"], COMPACT_SUB0),
    known("heig-vd-iai__canopen-stack/example__example.eds", &[0x1009, 0x4040, 0x4041, 0x6503, 0x6505], Subs::One(0), &["default"], EMPTY_DEFAULT),
    known("heig-vd-iai__canopen-stack/example__example.eds", &[0x1F50], Subs::Range(1, 2), &["default"], EMPTY_DEFAULT),
    known("heig-vd-iai__canopen-stack/od.eds", &[0x2003, 0x2004], Subs::One(0), &["default"], C_SUFFIX),
    known("hellantos__trinamic_pd42_can/config__TMCM-1270.eds", &[0x607D], Subs::One(1), &["default"], SIGNED_HEX),
    known("hellantos__trinamic_pd42_can/config__TMCM-1270.eds", &[0x60C2], Subs::One(2), &["default"], SIGNED_HEX),
    known("hellantos__trinamic_pd42_can/config__master.dcf", &[0x1003, 0x1029], Subs::Range(1, 254), &["name"], COMPACT_NAMES),
    known("hellantos__trinamic_pd42_can/config__master.dcf", &[0x1016, 0x1028, 0x1F25, 0x1F55, 0x1F81, 0x1F82, 0x1F84, 0x1F85, 0x1F86, 0x1F87, 0x1F88, 0x1F8A], Subs::Range(1, 127), &["name"], COMPACT_NAMES),
    known("hellantos__trinamic_pd42_can/config__master.dcf", &[0x5A00, 0x5A01, 0x5A02, 0x5E00, 0x5E01, 0x5E02], Subs::Range(1, 2), &["name"], COMPACT_NAMES),
    known("hellantos__trinamic_pd42_can/config__master.dcf", &[0x1600, 0x1601, 0x1602, 0x1A00, 0x1A01, 0x1A02], Subs::Range(0, 2), &["presence"], COMPACT_RECORD),
    known("hellantos__trinamic_pd42_can/config__master.dcf", &[0x1003, 0x1016, 0x1028, 0x1029, 0x1F25, 0x1F55, 0x1F81, 0x1F82, 0x1F84, 0x1F85, 0x1F86, 0x1F87, 0x1F88, 0x1F8A, 0x5A00, 0x5A01, 0x5A02, 0x5E00, 0x5E01, 0x5E02], Subs::One(0), &["access", "default", "name"], COMPACT_SUB0),
    known("husarion__panther_ros/panther_hardware_interfaces__config__master.dcf", &[0x1003, 0x1029], Subs::Range(1, 254), &["name"], COMPACT_NAMES),
    known("husarion__panther_ros/panther_hardware_interfaces__config__master.dcf", &[0x1016, 0x1028, 0x1F25, 0x1F55, 0x1F81, 0x1F82, 0x1F84, 0x1F85, 0x1F86, 0x1F87, 0x1F88, 0x1F8A], Subs::Range(1, 127), &["name"], COMPACT_NAMES),
    known("husarion__panther_ros/panther_hardware_interfaces__config__master.dcf", &[0x5A00, 0x5A04, 0x5E00, 0x5E01, 0x5E02, 0x5E03, 0x5E04, 0x5E05, 0x5E06, 0x5E07], Subs::Range(1, 2), &["name"], COMPACT_NAMES),
    known("husarion__panther_ros/panther_hardware_interfaces__config__master.dcf", &[0x5A01, 0x5A05], Subs::Range(1, 4), &["name"], COMPACT_NAMES),
    known("husarion__panther_ros/panther_hardware_interfaces__config__master.dcf", &[0x5A02, 0x5A03, 0x5A06, 0x5A07], Subs::Range(1, 3), &["name"], COMPACT_NAMES),
    known("husarion__panther_ros/panther_hardware_interfaces__config__master.dcf", &[0x1600, 0x1604, 0x1A00, 0x1A01, 0x1A02, 0x1A03, 0x1A04, 0x1A05, 0x1A06, 0x1A07], Subs::Range(0, 2), &["presence"], COMPACT_RECORD),
    known("husarion__panther_ros/panther_hardware_interfaces__config__master.dcf", &[0x1601, 0x1605], Subs::Range(0, 4), &["presence"], COMPACT_RECORD),
    known("husarion__panther_ros/panther_hardware_interfaces__config__master.dcf", &[0x1602, 0x1603, 0x1606, 0x1607], Subs::Range(0, 3), &["presence"], COMPACT_RECORD),
    known("husarion__panther_ros/panther_hardware_interfaces__config__master.dcf", &[0x1003, 0x1016, 0x1028, 0x1029, 0x1F25, 0x1F55, 0x1F81, 0x1F82, 0x1F84, 0x1F85, 0x1F86, 0x1F87, 0x1F88, 0x1F8A, 0x5A00, 0x5A01, 0x5A02, 0x5A03, 0x5A04, 0x5A05, 0x5A06, 0x5A07, 0x5E00, 0x5E01, 0x5E02, 0x5E03, 0x5E04, 0x5E05, 0x5E06, 0x5E07], Subs::One(0), &["access", "default", "name"], COMPACT_SUB0),
    known("ipa320__cob_robots/cob_hardware_config__common__ElmoSimplIQ.dcf", &[0x100B], Subs::One(0), &["default"], NODEID_ALONE),
    known("ipa320__schunk_robots/schunk_pg70__config__Schunk_0_63.dcf", &[0x1014], Subs::One(0), &["default"], NODEID_CASE),
    known("ipa320__schunk_robots/schunk_pg70__config__Schunk_0_63.dcf", &[0x1200], Subs::Range(1, 2), &["default"], NODEID_CASE),
    known("ipa320__schunk_robots/schunk_pg70__config__Schunk_0_63.dcf", &[0x1400, 0x1401, 0x1800, 0x1801, 0x1802, 0x1803], Subs::One(1), &["default"], NODEID_CASE),
    known("isPointless__Sevcon/Sevcon_DVT__drive_wizard__Installation_DriveWizard__drivewizard__build__0001_alpha__Source__bin__Release__EDS__Gen4_pc0x0701182d_rev0x0001000d.eds", &[0x5810], Subs::One(7), &["default"], ZERO_DOMAIN),
    known("isPointless__Sevcon/Sevcon_DVT__drive_wizard__Installation_DriveWizard__drivewizard__build__0001_alpha__Source__bin__Release__EDS__espAC_pc0x00000000_rev0x00000000.eds", &[0x467E, 0x467F, 0x468E, 0x468F], Subs::One(0), &["default"], EMPTY_DEFAULT),
    known("isPointless__Sevcon/Sevcon_config_files__DCF_files__Sev_001.dcf", &[0x2870], Subs::One(3), &["default"], SIGNED_HEX),
    known("isPointless__Sevcon/Sevcon_config_files__DCF_files__Sev_001.dcf", &[0x2870], Subs::One(7), &["default"], SIGNED_HEX),
    known("isPointless__Sevcon/Sevcon_config_files__DCF_files__Sev_001.dcf", &[0x5810], Subs::One(7), &["default"], ZERO_DOMAIN),
    known("lely-industries__lely-core/test__gw_txt-slave.dcf", &[0x1400, 0x1600, 0x1800, 0x1A00], Subs::Object, &["presence"], COMPACT_PDO),
    known("lely-industries__lely-core/tools__cocatd.dcf", &[0x1003], Subs::Range(1, 254), &["name"], COMPACT_NAMES),
    known("lely-industries__lely-core/tools__cocatd.dcf", &[0x1003], Subs::One(0), &["access", "default", "name"], COMPACT_SUB0),
    known("redpesk-industrial__canopen-binding/conf.d__project__etc__my-cpp-master.eds", &[0x1003, 0x1029], Subs::Range(1, 254), &["name"], COMPACT_NAMES),
    known("redpesk-industrial__canopen-binding/conf.d__project__etc__my-cpp-master.eds", &[0x1016, 0x1028, 0x1F81, 0x1F82, 0x1F84, 0x1F85], Subs::Range(1, 127), &["name"], COMPACT_NAMES),
    known("redpesk-industrial__canopen-binding/conf.d__project__etc__my-cpp-master.eds", &[0x1600, 0x1A00, 0x5A00, 0x5E00], Subs::One(1), &["name"], COMPACT_NAMES),
    known("redpesk-industrial__canopen-binding/conf.d__project__etc__my-cpp-master.eds", &[0x1003, 0x1016, 0x1028, 0x1029, 0x1600, 0x1A00, 0x1F81, 0x1F82, 0x1F84, 0x1F85, 0x5A00, 0x5E00], Subs::One(0), &["access", "default", "name"], COMPACT_SUB0),
    known("redpesk-industrial__canopen-binding/tests__test-kp-M150__canopen-kingpigeonM150-config__master.dcf", &[0x1003, 0x1029], Subs::Range(1, 254), &["name"], COMPACT_NAMES),
    known("redpesk-industrial__canopen-binding/tests__test-kp-M150__canopen-kingpigeonM150-config__master.dcf", &[0x1016, 0x1028, 0x1F25, 0x1F55, 0x1F81, 0x1F82, 0x1F84, 0x1F85, 0x1F86, 0x1F87, 0x1F88, 0x1F8A], Subs::Range(1, 127), &["name"], COMPACT_NAMES),
    known("redpesk-industrial__canopen-binding/tests__test-kp-M150__canopen-kingpigeonM150-config__master.dcf", &[0x5A00, 0x5E00], Subs::Range(1, 2), &["name"], COMPACT_NAMES),
    known("redpesk-industrial__canopen-binding/tests__test-kp-M150__canopen-kingpigeonM150-config__master.dcf", &[0x5A01], Subs::Range(1, 4), &["name"], COMPACT_NAMES),
    known("redpesk-industrial__canopen-binding/tests__test-kp-M150__canopen-kingpigeonM150-config__master.dcf", &[0x1600, 0x1A00], Subs::Range(0, 2), &["presence"], COMPACT_RECORD),
    known("redpesk-industrial__canopen-binding/tests__test-kp-M150__canopen-kingpigeonM150-config__master.dcf", &[0x1601], Subs::Range(0, 4), &["presence"], COMPACT_RECORD),
    known("redpesk-industrial__canopen-binding/tests__test-kp-M150__canopen-kingpigeonM150-config__master.dcf", &[0x1003, 0x1016, 0x1028, 0x1029, 0x1F25, 0x1F55, 0x1F81, 0x1F82, 0x1F84, 0x1F85, 0x1F86, 0x1F87, 0x1F88, 0x1F8A, 0x5A00, 0x5A01, 0x5E00], Subs::One(0), &["access", "default", "name"], COMPACT_SUB0),
    known("redpesk-industrial__canopen-binding/tests__test-kp-M150__canopen-kingpigeonM150-config__slaves_dcf__m150c.dcf", &[0x1014], Subs::One(0), &["default"], NODEID_CASE),
    known("redpesk-industrial__canopen-binding/tests__test-kp-M150__canopen-kingpigeonM150-config__slaves_dcf__m150c.dcf", &[0x1400, 0x1401, 0x1800, 0x1801, 0x1802], Subs::One(1), &["default"], NODEID_CASE),
    known("ros-industrial__ros2_canopen/canopen_core__test__master.dcf", &[0x1003, 0x1029], Subs::Range(1, 254), &["name"], COMPACT_NAMES),
    known("ros-industrial__ros2_canopen/canopen_core__test__master.dcf", &[0x1016, 0x1028, 0x1F25, 0x1F55, 0x1F81, 0x1F82, 0x1F84, 0x1F85, 0x1F86, 0x1F87, 0x1F88, 0x1F8A], Subs::Range(1, 127), &["name"], COMPACT_NAMES),
    known("ros-industrial__ros2_canopen/canopen_core__test__master.dcf", &[0x5A00, 0x5A01, 0x5E00, 0x5E01], Subs::One(1), &["name"], COMPACT_NAMES),
    known("ros-industrial__ros2_canopen/canopen_core__test__master.dcf", &[0x1600, 0x1601, 0x1A00, 0x1A01], Subs::Range(0, 1), &["presence"], COMPACT_RECORD),
    known("ros-industrial__ros2_canopen/canopen_core__test__master.dcf", &[0x1003, 0x1016, 0x1028, 0x1029, 0x1F25, 0x1F55, 0x1F81, 0x1F82, 0x1F84, 0x1F85, 0x1F86, 0x1F87, 0x1F88, 0x1F8A, 0x5A00, 0x5A01, 0x5E00, 0x5E01], Subs::One(0), &["access", "default", "name"], COMPACT_SUB0),
    known("ros-industrial__ros2_canopen/canopen_core__test__simple.eds", &[0x1003], Subs::Range(1, 254), &["name"], COMPACT_NAMES),
    known("ros-industrial__ros2_canopen/canopen_core__test__simple.eds", &[0x1016, 0x1029, 0x1600, 0x1A00], Subs::One(1), &["name"], COMPACT_NAMES),
    known("ros-industrial__ros2_canopen/canopen_core__test__simple.eds", &[0x1003, 0x1016, 0x1029, 0x1600, 0x1A00], Subs::One(0), &["access", "default", "name"], COMPACT_SUB0),
    known("ros-industrial__ros2_canopen/canopen_proxy_driver__config__concurrency_test__master.dcf", &[0x1003, 0x1029], Subs::Range(1, 254), &["name"], COMPACT_NAMES),
    known("ros-industrial__ros2_canopen/canopen_proxy_driver__config__concurrency_test__master.dcf", &[0x1016, 0x1028, 0x1F25, 0x1F55, 0x1F81, 0x1F82, 0x1F84, 0x1F85, 0x1F86, 0x1F87, 0x1F88, 0x1F8A], Subs::Range(1, 127), &["name"], COMPACT_NAMES),
    known("ros-industrial__ros2_canopen/canopen_proxy_driver__config__concurrency_test__master.dcf", &[0x5A00, 0x5A01, 0x5A02, 0x5A03, 0x5A04, 0x5A05, 0x5E00, 0x5E01, 0x5E02, 0x5E03, 0x5E04, 0x5E05], Subs::One(1), &["name"], COMPACT_NAMES),
    known("ros-industrial__ros2_canopen/canopen_proxy_driver__config__concurrency_test__master.dcf", &[0x1600, 0x1601, 0x1602, 0x1603, 0x1604, 0x1605, 0x1A00, 0x1A01, 0x1A02, 0x1A03, 0x1A04, 0x1A05], Subs::Range(0, 1), &["presence"], COMPACT_RECORD),
    known("ros-industrial__ros2_canopen/canopen_proxy_driver__config__concurrency_test__master.dcf", &[0x1003, 0x1016, 0x1028, 0x1029, 0x1F25, 0x1F55, 0x1F81, 0x1F82, 0x1F84, 0x1F85, 0x1F86, 0x1F87, 0x1F88, 0x1F8A, 0x5A00, 0x5A01, 0x5A02, 0x5A03, 0x5A04, 0x5A05, 0x5E00, 0x5E01, 0x5E02, 0x5E03, 0x5E04, 0x5E05], Subs::One(0), &["access", "default", "name"], COMPACT_SUB0),
    known("ros-industrial__ros2_canopen/canopen_tests__config__robot_control__prbt_0_1.dcf", &[0x1014], Subs::One(0), &["default"], NODEID_CASE),
    known("ros-industrial__ros2_canopen/canopen_tests__config__robot_control__prbt_0_1.dcf", &[0x1200], Subs::Range(1, 2), &["default"], NODEID_CASE),
    known("ros-industrial__ros2_canopen/canopen_tests__config__robot_control__prbt_0_1.dcf", &[0x1400, 0x1401, 0x1800, 0x1801, 0x1802, 0x1803], Subs::One(1), &["default"], NODEID_CASE),
    known("ros-industrial__ros_canopen/canopen_402__resources__pilz.dcf", &[0x1003, 0x1029], Subs::Range(1, 254), &["name"], COMPACT_NAMES),
    known("ros-industrial__ros_canopen/canopen_402__resources__pilz.dcf", &[0x1016, 0x1028, 0x1F25, 0x1F55, 0x1F81, 0x1F82, 0x1F84, 0x1F85, 0x1F86, 0x1F87, 0x1F88, 0x1F8A], Subs::Range(1, 127), &["name"], COMPACT_NAMES),
    known("ros-industrial__ros_canopen/canopen_402__resources__pilz.dcf", &[0x5A00, 0x5E00], Subs::Range(1, 3), &["name"], COMPACT_NAMES),
    known("ros-industrial__ros_canopen/canopen_402__resources__pilz.dcf", &[0x5A01, 0x5A02, 0x5E01], Subs::Range(1, 2), &["name"], COMPACT_NAMES),
    known("ros-industrial__ros_canopen/canopen_402__resources__pilz.dcf", &[0x1600, 0x1A00], Subs::Range(0, 3), &["presence"], COMPACT_RECORD),
    known("ros-industrial__ros_canopen/canopen_402__resources__pilz.dcf", &[0x1601, 0x1602, 0x1A01], Subs::Range(0, 2), &["presence"], COMPACT_RECORD),
    known("ros-industrial__ros_canopen/canopen_402__resources__pilz.dcf", &[0x1003, 0x1016, 0x1028, 0x1029, 0x1F25, 0x1F55, 0x1F81, 0x1F82, 0x1F84, 0x1F85, 0x1F86, 0x1F87, 0x1F88, 0x1F8A, 0x5A00, 0x5A01, 0x5A02, 0x5E00, 0x5E01], Subs::One(0), &["access", "default", "name"], COMPACT_SUB0),
    known("ros-industrial__ros_canopen/canopen_402__resources__simple_mc.dcf", &[0x1003, 0x1029], Subs::Range(1, 254), &["name"], COMPACT_NAMES),
    known("ros-industrial__ros_canopen/canopen_402__resources__simple_mc.dcf", &[0x1016, 0x1028, 0x1F25, 0x1F55, 0x1F81, 0x1F82, 0x1F84, 0x1F85, 0x1F86, 0x1F87, 0x1F88, 0x1F8A], Subs::Range(1, 127), &["name"], COMPACT_NAMES),
    known("ros-industrial__ros_canopen/canopen_402__resources__simple_mc.dcf", &[0x5A00, 0x5E00], Subs::Range(1, 3), &["name"], COMPACT_NAMES),
    known("ros-industrial__ros_canopen/canopen_402__resources__simple_mc.dcf", &[0x5A01, 0x5A02, 0x5E01], Subs::Range(1, 2), &["name"], COMPACT_NAMES),
    known("ros-industrial__ros_canopen/canopen_402__resources__simple_mc.dcf", &[0x1600, 0x1A00], Subs::Range(0, 3), &["presence"], COMPACT_RECORD),
    known("ros-industrial__ros_canopen/canopen_402__resources__simple_mc.dcf", &[0x1601, 0x1602, 0x1A01], Subs::Range(0, 2), &["presence"], COMPACT_RECORD),
    known("ros-industrial__ros_canopen/canopen_402__resources__simple_mc.dcf", &[0x1003, 0x1016, 0x1028, 0x1029, 0x1F25, 0x1F55, 0x1F81, 0x1F82, 0x1F84, 0x1F85, 0x1F86, 0x1F87, 0x1F88, 0x1F8A, 0x5A00, 0x5A01, 0x5A02, 0x5E00, 0x5E01], Subs::One(0), &["access", "default", "name"], COMPACT_SUB0),
    known("ros-industrial__ros_canopen/canopen_test_utils__config__Schunk_0_63.dcf", &[0x1014], Subs::One(0), &["default"], NODEID_CASE),
    known("ros-industrial__ros_canopen/canopen_test_utils__config__Schunk_0_63.dcf", &[0x1200], Subs::Range(1, 2), &["default"], NODEID_CASE),
    known("ros-industrial__ros_canopen/canopen_test_utils__config__Schunk_0_63.dcf", &[0x1400, 0x1401, 0x1800, 0x1801, 0x1802, 0x1803], Subs::One(1), &["default"], NODEID_CASE),
    known("ros-industrial__ros_canopen/ipa_canopen_test__config__Schunk.eds", &[0x1003], Subs::Range(1, 254), &["name"], COMPACT_NAMES),
    known("ros-industrial__ros_canopen/ipa_canopen_test__config__Schunk.eds", &[0x1016], Subs::Range(1, 3), &["name"], COMPACT_NAMES),
    known("ros-industrial__ros_canopen/ipa_canopen_test__config__Schunk.eds", &[0x1003, 0x1016], Subs::One(0), &["access", "default", "name"], COMPACT_SUB0),
    known("ros-industrial__ros_canopen/ipa_canopen_test__config__Schunk_0_63.eds", &[0x1014], Subs::One(0), &["default"], NODEID_CASE),
    known("ros-industrial__ros_canopen/ipa_canopen_test__config__Schunk_0_63.eds", &[0x1200], Subs::Range(1, 2), &["default"], NODEID_CASE),
    known("ros-industrial__ros_canopen/ipa_canopen_test__config__Schunk_0_63.eds", &[0x1400, 0x1401, 0x1800, 0x1801, 0x1802, 0x1803], Subs::One(1), &["default"], NODEID_CASE),
    known("ros-industrial__ros_canopen/ressources__technosoft.dcf", &[0x1003, 0x1029], Subs::Range(1, 254), &["name"], COMPACT_NAMES),
    known("ros-industrial__ros_canopen/ressources__technosoft.dcf", &[0x1016, 0x1028, 0x1F25, 0x1F55, 0x1F81, 0x1F82, 0x1F84, 0x1F85, 0x1F86, 0x1F87, 0x1F88, 0x1F8A], Subs::Range(1, 127), &["name"], COMPACT_NAMES),
    known("ros-industrial__ros_canopen/ressources__technosoft.dcf", &[0x5A00, 0x5E00], Subs::One(1), &["name"], COMPACT_NAMES),
    known("ros-industrial__ros_canopen/ressources__technosoft.dcf", &[0x5A01, 0x5E01, 0x5E02, 0x5E03], Subs::Range(1, 2), &["name"], COMPACT_NAMES),
    known("ros-industrial__ros_canopen/ressources__technosoft.dcf", &[0x1600, 0x1A00], Subs::Range(0, 1), &["presence"], COMPACT_RECORD),
    known("ros-industrial__ros_canopen/ressources__technosoft.dcf", &[0x1601, 0x1A01, 0x1A02, 0x1A03], Subs::Range(0, 2), &["presence"], COMPACT_RECORD),
    known("ros-industrial__ros_canopen/ressources__technosoft.dcf", &[0x1003, 0x1016, 0x1028, 0x1029, 0x1F25, 0x1F55, 0x1F81, 0x1F82, 0x1F84, 0x1F85, 0x1F86, 0x1F87, 0x1F88, 0x1F8A, 0x5A00, 0x5A01, 0x5E00, 0x5E01, 0x5E02, 0x5E03], Subs::One(0), &["access", "default", "name"], COMPACT_SUB0),
    known("ros-industrial__ros_canopen/ros2_canopen_core__tests__test_concurrency__concurrency.dcf", &[0x1003, 0x1029], Subs::Range(1, 254), &["name"], COMPACT_NAMES),
    known("ros-industrial__ros_canopen/ros2_canopen_core__tests__test_concurrency__concurrency.dcf", &[0x1016, 0x1028, 0x1F25, 0x1F55, 0x1F81, 0x1F82, 0x1F84, 0x1F85, 0x1F86, 0x1F87, 0x1F88, 0x1F8A], Subs::Range(1, 127), &["name"], COMPACT_NAMES),
    known("ros-industrial__ros_canopen/ros2_canopen_core__tests__test_concurrency__concurrency.dcf", &[0x5A00, 0x5A01, 0x5A02, 0x5A03, 0x5A04, 0x5A05, 0x5A06, 0x5A07, 0x5A08, 0x5A09, 0x5A0A, 0x5A0B, 0x5A0C, 0x5A0D, 0x5A0E, 0x5A0F, 0x5A10, 0x5A11, 0x5A12, 0x5E00, 0x5E01, 0x5E02, 0x5E03, 0x5E04, 0x5E05, 0x5E06, 0x5E07, 0x5E08, 0x5E09, 0x5E0A, 0x5E0B, 0x5E0C, 0x5E0D, 0x5E0E, 0x5E0F, 0x5E10, 0x5E11, 0x5E12], Subs::One(1), &["name"], COMPACT_NAMES),
    known("ros-industrial__ros_canopen/ros2_canopen_core__tests__test_concurrency__concurrency.dcf", &[0x1600, 0x1601, 0x1602, 0x1603, 0x1604, 0x1605, 0x1606, 0x1607, 0x1608, 0x1609, 0x160A, 0x160B, 0x160C, 0x160D, 0x160E, 0x160F, 0x1610, 0x1611, 0x1612, 0x1A00, 0x1A01, 0x1A02, 0x1A03, 0x1A04, 0x1A05, 0x1A06, 0x1A07, 0x1A08, 0x1A09, 0x1A0A, 0x1A0B, 0x1A0C, 0x1A0D, 0x1A0E, 0x1A0F, 0x1A10, 0x1A11, 0x1A12], Subs::Range(0, 1), &["presence"], COMPACT_RECORD),
    known("ros-industrial__ros_canopen/ros2_canopen_core__tests__test_concurrency__concurrency.dcf", &[0x1003, 0x1016, 0x1028, 0x1029, 0x1F25, 0x1F55, 0x1F81, 0x1F82, 0x1F84, 0x1F85, 0x1F86, 0x1F87, 0x1F88, 0x1F8A, 0x5A00, 0x5A01, 0x5A02, 0x5A03, 0x5A04, 0x5A05, 0x5A06, 0x5A07, 0x5A08, 0x5A09, 0x5A0A, 0x5A0B, 0x5A0C, 0x5A0D, 0x5A0E, 0x5A0F, 0x5A10, 0x5A11, 0x5A12, 0x5E00, 0x5E01, 0x5E02, 0x5E03, 0x5E04, 0x5E05, 0x5E06, 0x5E07, 0x5E08, 0x5E09, 0x5E0A, 0x5E0B, 0x5E0C, 0x5E0D, 0x5E0E, 0x5E0F, 0x5E10, 0x5E11, 0x5E12], Subs::One(0), &["access", "default", "name"], COMPACT_SUB0),
    known("samsamfire__gocanopen/pkg__od__base.eds", &[0x200F], Subs::One(0), &["default"], ZERO_DOMAIN),
];

// ---------------------------------------------------------------------------------------------

/// Python's dump of each file, in order.
fn python_dump(python: &Path, files: &[PathBuf]) -> Vec<Json> {
    let out = Command::new(python)
        .arg(root().join("scripts/canopen_dump.py"))
        .args(files)
        .output()
        .expect("run scripts/canopen_dump.py");
    assert!(
        out.status.success(),
        "canopen_dump.py failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let all: Vec<Json> = serde_json::from_slice(&out.stdout).expect("canopen_dump.py JSON");
    assert_eq!(all.len(), files.len());
    all
}

fn edsgen_dump(path: &Path) -> (Json, edsgen_model::model::Device) {
    let read = read::read_file(path).expect("readable file");
    (dump::to_json(&read.device), read.device)
}

/// The corpus files python imports (`ok`) and those it cannot, from the baseline table.
fn baseline(dir: &Path) -> (Vec<String>, Vec<String>) {
    let table = std::fs::read_to_string(dir.join("python_canopen_baseline.tsv")).unwrap();
    let mut ok = Vec::new();
    let mut failing = Vec::new();
    for line in table.lines().skip(1) {
        let mut cols = line.split('\t');
        let (Some(file), Some(result)) = (cols.next(), cols.next()) else {
            continue;
        };
        if result == "ok" {
            ok.push(file.to_owned());
        } else {
            failing.push(file.to_owned());
        }
    }
    (ok, failing)
}

#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
struct Difference {
    file: String,
    index: u16,
    /// `None` for the object itself.
    sub: Option<u8>,
    field: &'static str,
    python: String,
    edsgen: String,
}

fn objects_by_index(dump: &Json) -> BTreeMap<u16, &Json> {
    dump["objects"]
        .as_array()
        .map(|objects| {
            objects
                .iter()
                .filter_map(|o| Some((u16::try_from(o["index"].as_u64()?).ok()?, o)))
                .collect()
        })
        .unwrap_or_default()
}

fn subs_by_index(object: &Json) -> BTreeMap<u8, &Json> {
    object["subs"]
        .as_array()
        .map(|subs| {
            subs.iter()
                .filter_map(|s| Some((u8::try_from(s["sub"].as_u64()?).ok()?, s)))
                .collect()
        })
        .unwrap_or_default()
}

/// Whether two default values agree. Integers compare exactly, reals as f64, strings and hex as
/// text; `{"nodeid_offset": N}` by N.
fn same_value(python: &Json, edsgen: &Json) -> bool {
    match (python, edsgen) {
        (Json::Number(a), Json::Number(b)) => {
            if a.is_f64() || b.is_f64() {
                a.as_f64() == b.as_f64()
            } else {
                a == b
            }
        }
        _ => python == edsgen,
    }
}

/// The entry python's array answers for a sub-index it does not hold (see `canopen_dump.py`).
fn lazy_sub(object: &Json, sub: u8) -> Option<Json> {
    let lazy = object.get("lazy").filter(|l| !l.is_null())?;
    let mut entry = lazy.clone();
    let prefix = lazy["name_prefix"].as_str()?;
    entry["name"] = Json::String(format!("{prefix}_{sub:x}"));
    Some(entry)
}

/// Compares one file. Python turns `DummyNNNN=1` into objects 1-7, which edsgen keeps as dummy
/// usage, not objects: those match edsgen's `dummy_usage`. A sub-index of an array that python
/// does not hold is compared with what python's array makes of it on access (from sub-index 1).
///
/// `compact` lists objects whose CompactSubObj python 2.4.1 cannot name: for those, sub-index 0
/// (python invents `Number of entries`, rw, no value) and the names (python: `X`, `X_2`, ...;
/// CiA 306: `X1`, `X2`, ...) are not compared; types, access, mapping and defaults are.
fn compare(
    file: &str,
    python: &Json,
    edsgen: &Json,
    compact: &BTreeSet<u16>,
    out: &mut Vec<Difference>,
) {
    let mut push = |index: u16, sub: Option<u8>, field: &'static str, p: &Json, e: &Json| {
        out.push(Difference {
            file: file.to_owned(),
            index,
            sub,
            field,
            python: p.to_string(),
            edsgen: e.to_string(),
        });
    };
    let present = Json::String("present".into());
    let absent = Json::String("absent".into());
    let python_objects = objects_by_index(python);
    let edsgen_objects = objects_by_index(edsgen);
    let indices: BTreeSet<u16> = python_objects
        .keys()
        .chain(edsgen_objects.keys())
        .copied()
        .collect();
    for index in indices {
        let (p, e) = match (python_objects.get(&index), edsgen_objects.get(&index)) {
            (Some(p), Some(e)) => (*p, *e),
            (Some(p), None) => {
                let dummy_used = edsgen["dummy_usage"][index.to_string()] == Json::Bool(true);
                if !(p["dummy"] == Json::Bool(true) && dummy_used) {
                    push(index, None, "presence", &present, &absent);
                }
                continue;
            }
            (None, Some(_)) => {
                push(index, None, "presence", &absent, &present);
                continue;
            }
            (None, None) => continue,
        };
        if p["name"] != e["name"] {
            push(index, None, "name", &p["name"], &e["name"]);
        }
        // Python has one class for VAR and DOMAIN objects (7); edsgen says DOMAIN (2).
        let edsgen_type = match e["object_type"].as_u64() {
            Some(2) => Json::from(7),
            _ => e["object_type"].clone(),
        };
        if p["object_type"] != edsgen_type {
            push(
                index,
                None,
                "object_type",
                &p["object_type"],
                &e["object_type"],
            );
        }
        let python_subs = subs_by_index(p);
        let edsgen_subs = subs_by_index(e);
        let subs: BTreeSet<u8> = python_subs
            .keys()
            .chain(edsgen_subs.keys())
            .copied()
            .collect();
        let compact_object = compact.contains(&index);
        for sub in subs {
            if compact_object && sub == 0 {
                continue;
            }
            let lazy;
            let (ps, es) = match (python_subs.get(&sub), edsgen_subs.get(&sub)) {
                (Some(ps), Some(es)) => (*ps, *es),
                (Some(_), None) => {
                    push(index, Some(sub), "presence", &present, &absent);
                    continue;
                }
                (None, Some(es)) => match lazy_sub(p, sub) {
                    Some(entry) => {
                        lazy = entry;
                        (&lazy, *es)
                    }
                    None => {
                        push(index, Some(sub), "presence", &absent, &present);
                        continue;
                    }
                },
                (None, None) => continue,
            };
            for field in ["name", "data_type", "access", "pdo_mapping"] {
                if compact_object && field == "name" {
                    continue;
                }
                if ps[field] != es[field] {
                    push(index, Some(sub), field, &ps[field], &es[field]);
                }
            }
            if !same_value(&ps["default"], &es["default"]) {
                push(index, Some(sub), "default", &ps["default"], &es["default"]);
            }
        }
    }
}

/// The known differences, expanded to one key per (file, index, sub, field).
fn expanded_known() -> BTreeSet<(String, u16, Option<u8>, String)> {
    let mut keys = BTreeSet::new();
    for k in KNOWN_DIFFERENCES {
        assert!(
            !k.reason.trim().is_empty(),
            "{}: a known difference needs its reason",
            k.file
        );
        let subs: Vec<Option<u8>> = match k.subs {
            Subs::Object => vec![None],
            Subs::One(s) => vec![Some(s)],
            Subs::Range(a, b) => (a..=b).map(Some).collect(),
        };
        for &index in k.indices {
            for &sub in &subs {
                for field in k.fields {
                    let key = (k.file.to_owned(), index, sub, (*field).to_owned());
                    assert!(keys.insert(key.clone()), "listed twice: {key:?}");
                }
            }
        }
    }
    keys
}

/// One line per difference: `file 2000h sub 1: name: python "A" / edsgen "A1"`.
fn describe(d: &Difference) -> String {
    let at = match d.sub {
        None => format!("{:04X}h", d.index),
        Some(s) => format!("{:04X}h sub {s}", d.index),
    };
    format!(
        "{} {at}: {}: python {} / edsgen {}",
        d.file, d.field, d.python, d.edsgen
    )
}

/// A difference in the allow-list's syntax, for a reviewer to judge and paste.
fn as_known_entry(d: &Difference) -> String {
    let subs = match d.sub {
        None => "Subs::Object".to_owned(),
        Some(s) => format!("Subs::One({s:#04x})"),
    };
    format!(
        "known(\"{}\", &[{:#06x}], {subs}, &[\"{}\"], \"python {} / edsgen {}\"),",
        d.file, d.index, d.field, d.python, d.edsgen
    )
}

#[test]
fn corpus_agrees_with_python_canopen_except_known_differences() {
    let Some(dir) = corpus_dir() else { return };
    let Some(python) = python() else { return };
    let (ok, _) = baseline(&dir);
    assert_eq!(ok.len(), 93, "python imports 93 corpus files");
    let paths: Vec<PathBuf> = ok.iter().map(|f| dir.join(f)).collect();
    let python_dumps = python_dump(&python, &paths);

    let mut differences = Vec::new();
    for ((file, path), python_dump) in ok.iter().zip(&paths).zip(&python_dumps) {
        assert!(
            python_dump.get("error").is_none(),
            "python no longer imports {file}: {}",
            python_dump["error"]
        );
        let (edsgen, _) = edsgen_dump(path);
        compare(
            file,
            python_dump,
            &edsgen,
            &BTreeSet::new(),
            &mut differences,
        );
    }

    if let Some(out) = std::env::var_os("EDSGEN_PYTHON_DIFF_JSON") {
        // For reviewing the differences: every one, as JSON lines.
        let lines: Vec<String> = differences
            .iter()
            .map(|d| {
                serde_json::json!({"file": d.file, "index": d.index, "sub": d.sub,
                    "field": d.field, "python": d.python, "edsgen": d.edsgen})
                .to_string()
            })
            .collect();
        std::fs::write(out, lines.join("\n")).unwrap();
    }
    let known = expanded_known();
    let found: BTreeSet<(String, u16, Option<u8>, String)> = differences
        .iter()
        .map(|d| (d.file.clone(), d.index, d.sub, d.field.to_owned()))
        .collect();
    let unexpected: Vec<&Difference> = differences
        .iter()
        .filter(|d| !known.contains(&(d.file.clone(), d.index, d.sub, d.field.to_owned())))
        .collect();
    let stale: Vec<_> = known.difference(&found).collect();
    if !unexpected.is_empty() || !stale.is_empty() {
        let mut report = String::new();
        for d in &unexpected {
            report.push_str(&as_known_entry(d));
            report.push('\n');
        }
        panic!(
            "{} difference(s) with python canopen not in KNOWN_DIFFERENCES:\n{report}\n\
             {} listed difference(s) no longer occur:\n{stale:#?}",
            unexpected.len(),
            stale.len()
        );
    }
}

/// The corpus EDS/DCF files python canopen 2.4.1 cannot import, and the warning edsgen gives at
/// the line that breaks python: (file, code, line).
const PYTHON_FAILURES: &[(&str, &str, u32)] = &[
    // `VendorNumber=` (empty): python's `int('', 0)` raises.
    ("CANopenNode__CANopenNode/example__DS301_profile.eds", "EDS028", 17),
    ("CANopenNode__CANopenSocket/examples__basicDevice__basicDevice.eds", "EDS028", 17),
    ("lely-industries__lely-core/test__nmt-master.dcf", "EDS028", 3),
    ("mcbridejc__zencan/integration_tests__eds_files__example1.eds", "EDS028", 17),
    ("mcbridejc__zencan/zencan-eds__src__example.eds", "EDS028", 17),
    // `Lines=5` with `line5=`: python looks `Line5` up case-sensitively.
    ("CANopenNode__CANopenNode/example__IO.eds", "EDS008", 49),
    ("CANopenNode__CANopenNode/stack__S32_SDK__CANopenNode_S32K144__CANopen_Sensor__Sources__ObjDict__CANopen_Sensor_s32k144.eds", "EDS008", 49),
    ("UniMelbHumanRoboticsLab__CANOpenRobotController/src__libs__objDict__CANopenSocket.eds", "EDS008", 49),
    // [DummyUsage] without Dummy0001: python reads Dummy0001..0007 without a fallback.
    ("dborgards__eds-dcf-net/tests__EdsDcfNet.Tests__Fixtures__full_features.dcf", "EDS417", 56),
    ("lely-industries__lely-core/test__coapp-fiber-master.dcf", "EDS417", 17),
    ("lely-industries__lely-core/tools__coctl.dcf", "EDS417", 17),
    ("MartinHolcik__lely-canopen/test__coapp-401-master.dcf", "EDS417", 17),
    ("MartinHolcik__lely-canopen/test__coapp-401-slave.dcf", "EDS417", 17),
    // Windows-1252 bytes (0x94, a closing quote): python decodes UTF-8 only.
    ("KITmedical__kacanopen_old/eds__Faulhaber__605.3150.51-V-EK-3-60.eds", "EDS002", 52),
    ("KITmedical__kacanopen_old/master__share__eds_library__327__3150.1.eds", "EDS002", 52),
    // A comment broken over two lines: python's configparser rejects the second.
    ("isPointless__Sevcon/Sevcon_DVT__drive_wizard__Installation_DriveWizard__drivewizard__build__0001_alpha__Source__bin__Release__EDS__PST__pst_pc0x02011806_rev0x00010000.eds", "EDS027", 726),
];

#[test]
fn corpus_files_python_cannot_import_read_with_a_warning_at_the_cause() {
    let Some(dir) = corpus_dir() else { return };
    let (_, failing) = baseline(&dir);
    let mut eds_or_dcf: Vec<&str> = failing
        .iter()
        .map(String::as_str)
        .filter(|f| {
            let lower = f.to_ascii_lowercase();
            lower.ends_with(".eds") || lower.ends_with(".dcf")
        })
        .collect();
    eds_or_dcf.sort_unstable();
    let mut listed: Vec<&str> = PYTHON_FAILURES.iter().map(|(f, _, _)| *f).collect();
    listed.sort_unstable();
    assert_eq!(eds_or_dcf, listed, "the baseline's failing EDS/DCF files");
    for (file, code, line) in PYTHON_FAILURES {
        let read = read::read_file(&dir.join(file)).unwrap();
        assert!(!read.device.objects.is_empty(), "{file}: no objects");
        let mut diags = read.diagnostics;
        diags.extend(validate::validate(&read.device));
        let found: Vec<(&str, Severity, u32)> = diags
            .iter()
            .map(|d| (d.code(), d.severity, d.span.map_or(0, |s| s.line)))
            .collect();
        assert!(
            found.contains(&(*code, Severity::Warning, *line)),
            "{file}: no {code} warning at line {line}: {found:?}"
        );
    }
}

#[test]
fn bundled_cards_match_python_exactly() {
    let cards: Vec<PathBuf> = match std::fs::read_dir(root().join("eds")) {
        Ok(entries) => entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x.eq_ignore_ascii_case("eds")))
            // The EtherNet/IP card's ODVA EDS is not a CiA 306 file: python canopen has no part in it.
            .filter(|p| {
                std::fs::read(p).is_ok_and(|bytes| {
                    edsgen_model::read::detect_format(p, &bytes) == edsgen_model::model::Format::Eds
                })
            })
            .collect(),
        Err(_) => Vec::new(),
    };
    if cards.is_empty() {
        eprintln!("no eds/*.eds yet: nothing to compare");
        return;
    }
    let Some(python) = python() else { return };
    let mut cards = cards;
    cards.sort();
    let python_dumps = python_dump(&python, &cards);
    let mut differences = Vec::new();
    for (path, python_dump) in cards.iter().zip(&python_dumps) {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        assert!(
            python_dump.get("error").is_none(),
            "python cannot import eds/{name}: {}",
            python_dump["error"]
        );
        let (edsgen, device) = edsgen_dump(path);
        assert!(!device.objects.is_empty(), "eds/{name}: no objects");
        let compact: BTreeSet<u16> = device
            .objects
            .values()
            .filter(|o| o.compact_sub_obj.is_some())
            .map(|o| o.index)
            .collect();
        compare(&name, python_dump, &edsgen, &compact, &mut differences);
    }
    let lines: Vec<String> = differences.iter().map(describe).collect();
    assert!(
        differences.is_empty(),
        "the bundled cards differ from python canopen in {} place(s):\n{}",
        lines.len(),
        lines.join("\n")
    );
}
