//! Device-level elements: `ProfileBody` file info, `DeviceIdentity`, dummy usage, baud rates,
//! general and master features, dynamic channels and commissioning.

use roxmltree::Node;

use super::XmlReader;
use crate::diag::{Diagnostic, Severity};
use crate::model::*;
use crate::read::value::parse_integer;
use crate::read::xml::{attribute, children, element_text, local};
use crate::rules;

/// `"250 Kbps"` (any case, with or without the space) as kbit/s; also accepts `"1 Mbps"`.
fn parse_baud_rate(text: &str) -> Option<u32> {
    let lower = text.trim().to_ascii_lowercase();
    if let Some(number) = lower.strip_suffix("kbps") {
        return number.trim().parse().ok();
    }
    if let Some(number) = lower.strip_suffix("mbps") {
        return number.trim().parse::<u32>().ok()?.checked_mul(1000);
    }
    None
}

impl XmlReader<'_, '_> {
    pub(super) fn read_file_info(&mut self, body: Node, info: &mut FileInfo) {
        let get = |name: &str| {
            attribute(body, name)
                .map(|a| a.value().trim().to_owned())
                .filter(|v| !v.is_empty())
        };
        // Both profile bodies usually repeat the same attributes; the first one written wins.
        let fill = |slot: &mut Option<String>, value: Option<String>| {
            if slot.is_none() {
                *slot = value;
            }
        };
        fill(&mut info.file_name, get("fileName"));
        fill(&mut info.file_version, get("fileVersion"));
        fill(&mut info.created_by, get("fileCreator"));
        fill(&mut info.creation_date, get("fileCreationDate"));
        fill(&mut info.creation_time, get("fileCreationTime"));
        fill(&mut info.modified_by, get("fileModifiedBy"));
        fill(&mut info.modification_date, get("fileModificationDate"));
        fill(&mut info.modification_time, get("fileModificationTime"));
        if info.span.is_none() {
            info.span = Some(self.spans.element(body));
        }
    }

    pub(super) fn read_identity(&mut self, identity: Node, device: &mut Device) {
        let span = self.spans.element(identity);
        device.device_info.span.get_or_insert(span);
        let mut extra = Vec::new();
        for item in identity.children().filter(|n| n.is_element()) {
            let item_span = self.spans.element(item);
            let text = element_text(item);
            match local(item) {
                "vendorName" => device.device_info.vendor_name = text,
                "productName" => device.device_info.product_name = text,
                "orderNumber" => device.device_info.order_code = text,
                "vendorID" | "productID" => {
                    let Some(text) = text else { continue };
                    let number = parse_integer(&text).and_then(|n| u32::try_from(n).ok());
                    let Some(number) = number else {
                        self.push(Diagnostic::new(
                            &rules::XML_BAD_ATTRIBUTE,
                            Some(item_span),
                            format!("`{}` is `{text}`, not a 32-bit number", local(item)),
                        ));
                        continue;
                    };
                    let slot = if local(item) == "vendorID" {
                        &mut device.device_info.vendor_number
                    } else {
                        &mut device.device_info.product_number
                    };
                    *slot = Some(Spanned::new(number, item_span));
                }
                other => {
                    let key = match attribute(item, "versionType") {
                        Some(kind) => format!("{other}@{}", kind.value()),
                        None => other.to_owned(),
                    };
                    if let Some(value) = text {
                        extra.push(RawEntry {
                            key,
                            value,
                            span: item_span,
                        });
                    }
                }
            }
        }
        if !extra.is_empty() {
            device.other_sections.push(RawSection {
                name: "DeviceIdentity".to_owned(),
                entries: extra,
                span,
            });
        }
    }

    pub(super) fn read_dummy_usage(&mut self, node: Node, device: &mut Device) {
        device.dummy_usage_span = Some(self.spans.element(node));
        for dummy in children(node, "dummy") {
            let Some(entry) = attribute(dummy, "entry") else {
                continue;
            };
            let span = self.spans.attribute(&entry);
            let parsed = entry.value().split_once('=').and_then(|(key, value)| {
                let key = key.trim();
                let index = key
                    .get(..5)
                    .filter(|p| p.eq_ignore_ascii_case("dummy"))
                    .and_then(|_| u16::from_str_radix(key.get(5..)?, 16).ok())?;
                let used = match value.trim() {
                    "1" => true,
                    "0" => false,
                    _ => return None,
                };
                Some((index, used))
            });
            match parsed {
                Some((index, used)) => {
                    device.dummy_usage.insert(index, used);
                }
                None => self.push(Diagnostic::new(
                    &rules::XML_BAD_ATTRIBUTE,
                    Some(span),
                    format!("dummy entry `{}` is not `DummyXXXX=0|1`", entry.value()),
                )),
            }
        }
    }

    pub(super) fn read_baud_rates(&mut self, node: Node, device: &mut Device) {
        let mut extra = Vec::new();
        if let Some(default) = attribute(node, "defaultValue") {
            extra.push(RawEntry {
                key: "defaultValue".to_owned(),
                value: default.value().to_owned(),
                span: self.spans.attribute(&default),
            });
        }
        for rate in children(node, "supportedBaudRate") {
            let Some(value) = attribute(rate, "value") else {
                continue;
            };
            let span = self.spans.attribute(&value);
            match parse_baud_rate(value.value()) {
                Some(kbit) => device.device_info.baud_rates.push((kbit, true)),
                None if value.value().trim() == "auto-baudRate" => extra.push(RawEntry {
                    key: "supportedBaudRate".to_owned(),
                    value: value.value().to_owned(),
                    span,
                }),
                None => self.push(Diagnostic::new(
                    &rules::XML_BAD_ATTRIBUTE,
                    Some(span),
                    format!(
                        "supported baud rate `{}` is not like `250 Kbps`",
                        value.value()
                    ),
                )),
            }
        }
        if !extra.is_empty() {
            device.other_sections.push(RawSection {
                name: "baudRate".to_owned(),
                entries: extra,
                span: self.spans.element(node),
            });
        }
    }

    /// Attributes of `node` not in `known`, kept as a raw section so nothing is dropped.
    fn keep_other_attributes(&self, node: Node, known: &[&str], device: &mut Device) {
        let entries: Vec<RawEntry> = node
            .attributes()
            .filter(|a| !known.contains(&a.name()))
            .map(|a| RawEntry {
                key: a.name().to_owned(),
                value: a.value().to_owned(),
                span: self.spans.attribute(&a),
            })
            .collect();
        if !entries.is_empty() {
            device.other_sections.push(RawSection {
                name: local(node).to_owned(),
                entries,
                span: self.spans.element(node),
            });
        }
    }

    /// `dynamicChannels/dynamicChannel` (CiA 302/405): kept verbatim, one entry per attribute
    /// (`dynamicChannel1.startIndex`), like the EDS `[DynamicChannels]` section.
    pub(super) fn read_dynamic_channels(&mut self, node: Node, device: &mut Device) {
        let mut entries = Vec::new();
        for (number, channel) in children(node, "dynamicChannel").enumerate() {
            for attr in channel.attributes() {
                entries.push(RawEntry {
                    key: format!("dynamicChannel{}.{}", number + 1, attr.name()),
                    value: attr.value().to_owned(),
                    span: self.spans.attribute(&attr),
                });
            }
        }
        device.other_sections.push(RawSection {
            name: "dynamicChannels".to_owned(),
            entries,
            span: self.spans.element(node),
        });
    }

    pub(super) fn read_general_features(&mut self, node: Node, device: &mut Device) {
        let info = &mut device.device_info;
        info.span.get_or_insert(self.spans.element(node));
        info.granularity = self.optional_number(node, "granularity");
        info.nr_of_rx_pdo = self.optional_number(node, "nrOfRxPDO");
        info.nr_of_tx_pdo = self.optional_number(node, "nrOfTxPDO");
        if let Some(group) = self.optional_bool(node, "groupMessaging") {
            info.group_messaging = group;
        }
        if let Some(channels) = self.optional_number(node, "dynamicChannels") {
            info.dynamic_channels_supported = channels.value;
        }
        if let Some(boot) = self.optional_bool(node, "bootUpSlave") {
            info.simple_boot_up_slave = boot;
        }
        if let Some(lss) = self.optional_bool(node, "layerSettingServiceSlave") {
            info.lss_supported = lss;
        }
        self.keep_other_attributes(
            node,
            &[
                "granularity",
                "nrOfRxPDO",
                "nrOfTxPDO",
                "groupMessaging",
                "dynamicChannels",
                "bootUpSlave",
                "layerSettingServiceSlave",
            ],
            device,
        );
    }

    pub(super) fn read_master_features(&mut self, node: Node, device: &mut Device) {
        if let Some(boot) = self.optional_bool(node, "bootUpMaster") {
            device.device_info.simple_boot_up_master = boot;
        }
        self.keep_other_attributes(node, &["bootUpMaster"], device);
    }

    pub(super) fn read_commissioning(&mut self, node: Node, device: &mut Device) {
        let text = |name: &str| attribute(node, name).map(|a| a.value().to_owned());
        let mut commissioning = Commissioning {
            node_id: self.optional_number(node, "nodeID"),
            node_name: text("nodeName"),
            network_name: text("networkName"),
            net_number: self.optional_number(node, "networkNumber").map(|n| n.value),
            canopen_manager: self.optional_bool(node, "CANopenManager").unwrap_or(false),
            span: self.spans.element(node),
            ..Default::default()
        };
        if let Some(rate) = attribute(node, "actualBaudRate") {
            let span = self.spans.attribute(&rate);
            match parse_baud_rate(rate.value()) {
                Some(kbit) => commissioning.baudrate = Some(Spanned::new(kbit, span)),
                None if !rate.value().trim().is_empty()
                    && rate.value().trim().bytes().all(|b| b.is_ascii_digit()) =>
                {
                    let kbit = rate.value().trim().parse::<u32>().ok();
                    commissioning.baudrate = kbit.map(|k| Spanned::new(k, span));
                    self.push(
                        Diagnostic::new(
                            &rules::XML_BAD_ATTRIBUTE,
                            Some(span),
                            format!(
                                "actualBaudRate `{}` has no unit; read as kbit/s",
                                rate.value()
                            ),
                        )
                        .with_severity(Severity::Info)
                        .with_help("write it as `250 Kbps`"),
                    );
                }
                None => self.push(Diagnostic::new(
                    &rules::XML_BAD_ATTRIBUTE,
                    Some(span),
                    format!("actualBaudRate `{}` is not like `250 Kbps`", rate.value()),
                )),
            }
        }
        device.commissioning = Some(commissioning);
    }
}
