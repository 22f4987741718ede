//! "Did you mean" for GSDML names (PN019): the attributes and child elements GSDML's closed
//! schema allows on the elements this reader interprets. A name of neither that is a letter or
//! two from an allowed one is a misspelling whose value is lost; a name far from all is left to
//! schema validation, so that a newer schema's additions raise nothing here.

use roxmltree::Node;

use super::{local, Spans};
use crate::diag::Diagnostic;
use crate::rules;

/// An element of the schema: its attributes and its child elements.
struct Allowed {
    element: &'static str,
    attributes: &'static [&'static str],
    children: &'static [&'static str],
}

const ALLOWED: &[Allowed] = &[
    Allowed {
        element: "DeviceIdentity",
        attributes: &["VendorID", "DeviceID"],
        children: &["InfoText", "VendorName"],
    },
    Allowed {
        element: "DeviceAccessPointItem",
        attributes: &[
            "ID",
            "PhysicalSlots",
            "ModuleIdentNumber",
            "MinDeviceInterval",
            "ImplementationType",
            "DNS_CompatibleName",
            "ExtendedAddressAssignmentSupported",
            "AllowedInSlots",
            "FixedInSlots",
            "ObjectUUID_LocalIndex",
            "RequiredSchemaVersion",
            "MultipleWriteSupported",
            "IOXS_Required",
            "PhysicalSubslots",
            "RemoteApplicationTimeout",
            "MaxSupportedRecordSize",
            "PowerOnToCommReady",
            "ParameterizationSpeedupSupported",
            "NameOfStationNotTransferable",
            "SharedDeviceSupported",
            "SharedInputSupported",
            "DeviceAccessSupported",
            "NumberOfDeviceAccessAR",
            "CheckDeviceID_Allowed",
            "WebServer",
            "AddressAssignment",
            "LLDP_NoD_Supported",
            "ResetToFactoryModes",
            "PrmBeginPrmEndSequenceSupported",
            "PROFIenergyASE_Supported",
            "AdaptsRealIdentification",
            "PNIO_Version",
            "AutoConfigurationSupported",
            "CIR_Supported",
            "NumberOfSubmodules",
            "SFPDiagnosisSupported",
            "Writeable_IM_Records",
        ],
        children: &[
            "ModuleInfo",
            "CertificationInfo",
            "SubslotList",
            "IOConfigData",
            "UseableModules",
            "VirtualSubmoduleList",
            "SystemDefinedSubmoduleList",
            "Graphics",
            "AssetManagement",
            "ApplicationRelations",
            "UseableSubmodules",
            "SlotList",
            "SlotGroups",
            "FieldbusIntegrationSlots",
        ],
    },
    Allowed {
        element: "ModuleItem",
        attributes: &[
            "ID",
            "ModuleIdentNumber",
            "PhysicalSubslots",
            "RequiredSchemaVersion",
        ],
        children: &[
            "ModuleInfo",
            "SubslotList",
            "VirtualSubmoduleList",
            "SystemDefinedSubmoduleList",
            "UseableSubmodules",
            "Graphics",
        ],
    },
    Allowed {
        element: "VirtualSubmoduleItem",
        attributes: &[
            "ID",
            "SubmoduleIdentNumber",
            "API",
            "FixedInSubslots",
            "AllowedInSubslots",
            "UsedInSubslots",
            "MayIssueProcessAlarm",
            "PROFIsafeSupported",
            "Writeable_IM_Records",
            "Max_iParameterSize",
            "SubsysModuleDirInfo",
            "RequiredSchemaVersion",
        ],
        children: &[
            "IOData",
            "RecordDataList",
            "ModuleInfo",
            "Graphics",
            "IsochroneMode",
            "PROFIenergy",
            "ReportingSystem",
        ],
    },
    Allowed {
        element: "IOConfigData",
        attributes: &[
            "MaxInputLength",
            "MaxOutputLength",
            "MaxDataLength",
            "ApplicationLengthIncludesIOxS",
        ],
        children: &[],
    },
    Allowed {
        element: "IOData",
        attributes: &[
            "IOPS_Length",
            "IOCS_Length",
            "F_IO_StructureDescVersion",
            "F_IO_StructureDescCRC",
        ],
        children: &["Input", "Output"],
    },
    Allowed {
        element: "DataItem",
        attributes: &[
            "DataType",
            "Length",
            "TextId",
            "UseAsBits",
            "Id",
            "Subordinate",
        ],
        children: &["BitDataItem"],
    },
    Allowed {
        element: "BitDataItem",
        attributes: &["BitOffset", "TextId"],
        children: &[],
    },
    Allowed {
        element: "ParameterRecordDataItem",
        attributes: &["Index", "Length", "TransferSequence", "API", "Access"],
        children: &["Name", "Const", "Ref", "MenuList"],
    },
    Allowed {
        element: "Ref",
        attributes: &[
            "ValueItemTarget",
            "ByteOffset",
            "BitOffset",
            "BitLength",
            "DataType",
            "DefaultValue",
            "AllowedValues",
            "Changeable",
            "Visible",
            "TextId",
            "Length",
            "ID",
        ],
        children: &[],
    },
    Allowed {
        element: "Const",
        attributes: &["ByteOffset", "Data"],
        children: &[],
    },
    Allowed {
        element: "ModuleItemRef",
        attributes: &[
            "ModuleItemTarget",
            "AllowedInSlots",
            "UsedInSlots",
            "FixedInSlots",
        ],
        children: &[],
    },
    Allowed {
        element: "SubslotItem",
        attributes: &["SubslotNumber", "TextId"],
        children: &[],
    },
    Allowed {
        element: "ValueItem",
        attributes: &["ID"],
        children: &["Help", "Assignments"],
    },
    Allowed {
        element: "Assign",
        attributes: &["Content", "TextId"],
        children: &[],
    },
    Allowed {
        element: "ExtChannelDiagItem",
        attributes: &["ErrorType", "API", "MaintenanceAlarmState"],
        children: &["Name", "Help", "ExtChannelAddValue"],
    },
];

/// PN019 for every attribute or child element of an element of [`ALLOWED`] that the schema does
/// not allow there and that is a letter or two from one it does.
pub(super) fn check(root: Node, spans: &Spans, diags: &mut Vec<Diagnostic>) {
    for node in root.descendants().filter(|n| n.is_element()) {
        let Some(allowed) = ALLOWED.iter().find(|a| a.element == local(node)) else {
            continue;
        };
        for attr in node.attributes() {
            if attr.namespace().is_none() && !allowed.attributes.contains(&attr.name()) {
                if let Some(meant) = misspelt(attr.name(), allowed.attributes) {
                    diags.push(misspelling(
                        "attribute",
                        attr.name(),
                        allowed.element,
                        meant,
                        spans.attribute(&attr),
                    ));
                }
            }
        }
        for child in node.children().filter(|c| c.is_element()) {
            if !allowed.children.contains(&local(child)) {
                if let Some(meant) = misspelt(local(child), allowed.children) {
                    let span = spans.element(child);
                    diags.push(misspelling(
                        "element",
                        local(child),
                        allowed.element,
                        meant,
                        span,
                    ));
                }
            }
        }
    }
}

fn misspelt(name: &str, allowed: &[&'static str]) -> Option<&'static str> {
    let candidates = allowed.iter().map(|a| ((*a).to_owned(), *a));
    crate::did_you_mean::misspelt(name, candidates)
}

fn misspelling(
    kind: &str,
    name: &str,
    element: &str,
    meant: &str,
    span: crate::model::Span,
) -> Diagnostic {
    Diagnostic::new(
        &rules::PN_MISSPELT,
        Some(span),
        format!("the {kind} `{name}` is not one GSDML allows on `{element}` (ignored)"),
    )
    .with_label(format!("not a {element} {kind}"))
    .with_help(format!("did you mean `{meant}`?"))
}
