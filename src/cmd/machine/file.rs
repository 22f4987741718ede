//! The machine file (`docs/machine.md`): a TOML file with one array of tables per bus, read
//! into [`Machine`] and checked as a whole before anything starts: every problem is reported
//! with its line and column (unknown tables and keys, cards that do not exist, files that are
//! not there, a bus table without its interface, the same address twice on one bus).

use std::collections::BTreeMap;
use std::ops::Range;
use std::path::Path;

use toml::de::{DeArray, DeTable, DeValue};
use toml::Spanned;

use super::model::{Address, Bus, Machine, Place, Planned, Section, Source};
use crate::cmd::did_you_mean;

/// A problem in a machine file, at a line and column (1-based).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Problem {
    /// The line.
    pub line: usize,
    /// The column.
    pub column: usize,
    /// What is wrong.
    pub message: String,
}

/// Reads the machine file `path`; every problem found, when there is one.
pub fn read(path: &Path) -> Result<Machine, Vec<Problem>> {
    let text = std::fs::read_to_string(path).map_err(|e| {
        vec![Problem {
            line: 0,
            column: 0,
            message: format!("cannot read the machine file: {e}"),
        }]
    })?;
    parse(&text, path.parent().unwrap_or(Path::new(".")))
}

/// Reads a machine file's `text`; relative paths in it are relative to `base`.
pub fn parse(text: &str, base: &Path) -> Result<Machine, Vec<Problem>> {
    let mut reader = Reader {
        text,
        base,
        problems: Vec::new(),
    };
    let root = match DeTable::parse(text) {
        Ok(root) => root.into_inner(),
        Err(err) => {
            let at = err.span().map_or(0, |r| r.start);
            reader.problem(at, format!("not TOML: {}", err.message().trim()));
            return Err(reader.problems);
        }
    };
    let mut sections = Vec::new();
    for (key, value) in &root {
        let name = key.get_ref().as_ref();
        let Some(bus) = Bus::ALL.into_iter().find(|b| b.table() == name) else {
            let tables: Vec<(String, &str)> = Bus::ALL
                .iter()
                .map(|b| (b.table().to_owned(), b.table()))
                .collect();
            let near = did_you_mean::closest(name, tables, true);
            let hint = near
                .first()
                .map_or(String::new(), |t| format!(" (did you mean `[[{t}]]`?)"));
            reader.problem(
                key.span().start,
                format!("unknown table `{name}`{hint}: a machine file has [[canopen]], [[ethercat]], [[profibus]], [[profinet]] and [[enip]]"),
            );
            continue;
        };
        match value.get_ref() {
            DeValue::Array(tables) => {
                for table in tables.iter() {
                    match table.get_ref() {
                        DeValue::Table(t) => {
                            if let Some(section) = reader.section(bus, t, table.span()) {
                                sections.push(section);
                            }
                        }
                        _ => reader.problem(
                            table.span().start,
                            format!("`{name}` is an array of tables: write `[[{name}]]`"),
                        ),
                    }
                }
            }
            _ => reader.problem(
                key.span().start,
                format!("`{name}` is an array of tables: write `[[{name}]]`"),
            ),
        }
    }
    reader.duplicates(&sections);
    if reader.problems.is_empty() {
        Ok(Machine { sections })
    } else {
        reader.problems.sort_by_key(|p| (p.line, p.column));
        Err(reader.problems)
    }
}

pub(super) struct Reader<'a> {
    text: &'a str,
    base: &'a Path,
    problems: Vec<Problem>,
}

impl Reader<'_> {
    pub(super) fn problem(&mut self, at: usize, message: String) {
        let before = &self.text[..at.min(self.text.len())];
        let line = before.matches('\n').count() + 1;
        let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        self.problems.push(Problem {
            line,
            column,
            message,
        });
    }

    /// One `[[bus]]` table.
    fn section(&mut self, bus: Bus, table: &DeTable<'_>, span: Range<usize>) -> Option<Section> {
        let name = bus.table();
        let mut place = None;
        let mut devices = None;
        for (key, value) in table {
            let k = key.get_ref().as_ref();
            if k == "devices" {
                devices = Some(value);
            } else if bus.place_keys().contains(&k) {
                let Some(s) = self.string(value, k) else {
                    continue;
                };
                let here = match k {
                    "bus" => Place::CanBus(s),
                    "socketcan" => Place::SocketCan(s),
                    "interface" => Place::Interface(s),
                    _ => Place::Tty(s),
                };
                if place.replace(here).is_some() {
                    self.problem(
                        key.span().start,
                        "a [[canopen]] table joins one bus: `bus` or `socketcan`, not both".into(),
                    );
                }
            } else {
                let mut keys = bus.place_keys().to_vec();
                keys.push("devices");
                let list = keys
                    .iter()
                    .map(|k| format!("`{k}`"))
                    .collect::<Vec<_>>()
                    .join(", ");
                self.problem(
                    key.span().start,
                    format!("unknown key `{k}` in [[{name}]] (it takes {list})"),
                );
            }
        }
        let place = match (bus, place) {
            (Bus::Enip, _) => Place::Host,
            (_, Some(place)) => place,
            (_, None) => {
                let keys = bus.place_keys();
                let what = match keys {
                    [one] => format!("`{one}`"),
                    _ => "`bus` or `socketcan`".to_owned(),
                };
                self.problem(span.start, format!("[[{name}]] without its {what}"));
                return None;
            }
        };
        let Some(devices) = devices else {
            self.problem(span.start, format!("[[{name}]] without `devices`"));
            return None;
        };
        let DeValue::Array(list) = devices.get_ref() else {
            self.problem(
                devices.span().start,
                "`devices` is a list: `devices = [...]`".into(),
            );
            return None;
        };
        let planned = self.devices(bus, list);
        if planned.len() > bus.capacity() {
            self.problem(
                devices.span().start,
                format!(
                    "[[{name}]] lists {} devices; this build serves {} per {name} table",
                    planned.len(),
                    bus.capacity()
                ),
            );
        }
        Some(Section {
            bus,
            place,
            devices: planned,
        })
    }

    fn string(&mut self, value: &Spanned<DeValue<'_>>, key: &str) -> Option<String> {
        match value.get_ref() {
            DeValue::String(s) => Some(s.to_string()),
            _ => {
                self.problem(value.span().start, format!("`{key}` is a string"));
                None
            }
        }
    }

    /// A list of strings (`modules = ["1=8 DI", ...]`).
    fn strings(&mut self, value: &Spanned<DeValue<'_>>, key: &str) -> Option<Vec<String>> {
        let words = match value.get_ref() {
            DeValue::Array(list) => list
                .iter()
                .map(|item| match item.get_ref() {
                    DeValue::String(s) => Some(s.to_string()),
                    _ => None,
                })
                .collect(),
            _ => None,
        };
        if words.is_none() {
            self.problem(
                value.span().start,
                format!("`{key}` is a list of strings: `{key} = [\"1=NAME\", ...]`"),
            );
        }
        words
    }

    fn devices(&mut self, bus: Bus, list: &DeArray<'_>) -> Vec<Planned> {
        let mut planned = Vec::new();
        for (position, item) in list.iter().enumerate() {
            let at = item.span().start;
            let fields = match item.get_ref() {
                DeValue::String(s) => Some(Fields {
                    device: s.to_string(),
                    ..Fields::default()
                }),
                DeValue::Table(t) => self.fields(bus, t, at),
                _ => {
                    self.problem(
                        at,
                        "a device is a string (\"card@ID\", \"FILE@ID\") or an inline table".into(),
                    );
                    None
                }
            };
            if let Some(mut fields) = fields {
                // The same EtherCAT device written twice in a segment (two EC-TX508s) is
                // named by its position too, so that faults can name each.
                if bus == Bus::EtherCat && fields.name.is_none() {
                    let written =
                        |v: &DeValue<'_>| matches!(v, DeValue::String(s) if *s == fields.device);
                    if list.iter().filter(|v| written(v.get_ref())).count() > 1 {
                        fields.name = Some(format!("{}@{position}", fields.device));
                    }
                }
                if let Some(device) = self.device(bus, fields, position, at) {
                    planned.push(device);
                }
            }
        }
        planned
    }

    /// An inline table's keys.
    fn fields(&mut self, bus: Bus, table: &DeTable<'_>, at: usize) -> Option<Fields> {
        let mut values: BTreeMap<&str, (String, usize)> = BTreeMap::new();
        let allowed: &[&str] = match bus {
            Bus::Profinet => &["device", "name", "ip", "modules", "access_point"],
            Bus::Enip => &["device", "address", "name"],
            Bus::CanOpen => &["device", "name"],
            Bus::EtherCat | Bus::Profibus => &["device", "name", "modules"],
        };
        let mut modules = None;
        for (key, value) in table {
            let k = key.get_ref().as_ref();
            if k == "modules" || k == "access_point" {
                if !allowed.contains(&k) {
                    self.problem(
                        key.span().start,
                        format!(
                            "`{k}` is for a modular device in [[profibus]], [[profinet]] or [[ethercat]]: a [[{}]] device takes none",
                            bus.table()
                        ),
                    );
                    continue;
                }
                if k == "modules" {
                    modules = self.strings(value, k).map(|list| (list, key.span().start));
                    continue;
                }
            }
            let Some(known) = allowed.iter().find(|a| **a == k) else {
                let list = allowed
                    .iter()
                    .map(|k| format!("`{k}`"))
                    .collect::<Vec<_>>()
                    .join(", ");
                self.problem(
                    key.span().start,
                    format!(
                        "unknown key `{k}` in a {} device (it takes {list})",
                        bus.table()
                    ),
                );
                continue;
            };
            if let Some(s) = self.string(value, k) {
                values.insert(known, (s, value.span().start));
            }
        }
        let take = |k: &str, values: &mut BTreeMap<&str, (String, usize)>| {
            values.remove(k).map(|(s, _)| s)
        };
        let Some(device) = take("device", &mut values) else {
            self.problem(
                at,
                "a device table names its card or file: `device = \"...\"`".into(),
            );
            return None;
        };
        let access_point = values.remove("access_point");
        Some(Fields {
            device,
            name: take("name", &mut values),
            ip: take("ip", &mut values),
            address: take("address", &mut values),
            modules,
            access_point,
        })
    }

    /// One device: its card or file, and its address.
    fn device(&mut self, bus: Bus, f: Fields, position: usize, at: usize) -> Option<Planned> {
        let (what, suffix) = split_suffix(bus, &f.device);
        let source = self.source(bus, what, at)?;
        let address = match bus {
            Bus::CanOpen | Bus::Profibus => {
                let default = match &source {
                    Source::Card(card) if bus == Bus::CanOpen => {
                        edsgen_sim::drives::Card::named(card).map(|c| c.default_node_id)
                    }
                    Source::Card(_) => Some(edsgen_sim::dp::card::DEFAULT_ADDRESS),
                    Source::File(..) => None,
                };
                let (low, high, what) = match bus {
                    Bus::CanOpen => (1, 127, "node-ID"),
                    _ => (0, 125, "station address"),
                };
                let value = match (suffix, default) {
                    (Some(s), _) => match s.parse::<u8>() {
                        Ok(v) if (low..=high).contains(&v) => v,
                        _ => {
                            self.problem(
                                at,
                                format!("bad {what} `{s}` in `{}` ({low} to {high})", f.device),
                            );
                            return None;
                        }
                    },
                    (None, Some(d)) => d,
                    (None, None) => {
                        self.problem(
                            at,
                            format!("`{}` needs its {what}: `{}@ID`", f.device, f.device),
                        );
                        return None;
                    }
                };
                if bus == Bus::CanOpen {
                    Address::NodeId(value)
                } else {
                    Address::Station(value)
                }
            }
            Bus::EtherCat => Address::Position(position),
            Bus::Profinet => Address::Pn {
                name: f.name.clone().or(suffix.map(str::to_owned)),
                ip: f.ip.clone(),
            },
            Bus::Enip => match f.address.clone() {
                Some(ip) => Address::Ip(ip),
                None => {
                    self.problem(
                        at,
                        format!(
                            "an EtherNet/IP device names its address: {{ device = \"{}\", address = \"10.0.0.21\" }}",
                            f.device
                        ),
                    );
                    return None;
                }
            },
        };
        if let Address::Pn { name: Some(n), .. } = &address {
            if let Some(problem) = edsgen_runtime::profinet::wire::dcp::name_problem(n) {
                self.problem(
                    at,
                    format!("`{n}` is not a PROFINET name of station: {problem}"),
                );
                return None;
            }
        }
        let source = match (source, bus, suffix) {
            (Source::File(path, _), Bus::EtherCat, Some(pick)) => {
                Source::File(path, Some(pick.to_owned()))
            }
            (source, _, _) => source,
        };
        let (modules, access_point) = self.modules(bus, &source, &f)?;
        Some(Planned {
            name: f.name.unwrap_or(f.device),
            source,
            address,
            modules,
            access_point,
            at,
        })
    }

    /// A bundled card of `bus` by name, or a file that exists.
    fn source(&mut self, bus: Bus, what: &str, at: usize) -> Option<Source> {
        let cards = bus.cards();
        if let Some(card) = cards.iter().find(|c| **c == what) {
            return Some(Source::Card(card));
        }
        let looks_like_file = what.contains('/') || what.contains('.');
        if !looks_like_file {
            let near = did_you_mean::closest(what, cards.iter().map(|c| (c.to_string(), *c)), true);
            let hint = near
                .first()
                .map_or(String::new(), |c| format!(" (did you mean `{c}`?)"));
            self.problem(
                at,
                format!(
                    "no {} card `{what}`{hint}: the bundled ones are {}; a file is a path (`vendor/drive.eds`)",
                    bus.table(),
                    cards.join(", ")
                ),
            );
            return None;
        }
        let path = self.base.join(what);
        if !path.is_file() {
            self.problem(
                at,
                format!(
                    "no file `{}` (relative to the machine file)",
                    path.display()
                ),
            );
            return None;
        }
        Some(Source::File(path, None))
    }

    /// The same address twice on one bus, the same name or IP address twice in the machine.
    fn duplicates(&mut self, sections: &[Section]) {
        let mut names: Vec<&str> = Vec::new();
        let mut ips: Vec<String> = Vec::new();
        for section in sections {
            let mut seen: Vec<&Address> = Vec::new();
            for device in &section.devices {
                if names.contains(&device.name.as_str()) {
                    self.problem(
                        device.at,
                        format!(
                            "a second device named `{}`: faults on standard input name one device; give each its own `name`",
                            device.name
                        ),
                    );
                }
                names.push(&device.name);
                let clash = match &device.address {
                    Address::NodeId(_) | Address::Station(_) => seen.contains(&&device.address),
                    Address::Pn { name: Some(n), .. } => seen
                        .iter()
                        .any(|a| matches!(a, Address::Pn { name: Some(m), .. } if m == n)),
                    _ => false,
                };
                if clash {
                    self.problem(
                        device.at,
                        format!(
                            "{} on {} is taken by an earlier device",
                            device.address, section.place
                        ),
                    );
                }
                let ip = match &device.address {
                    Address::Ip(ip) => Some(ip.as_str()),
                    Address::Pn { ip: Some(ip), .. } => ip.split('/').next(),
                    _ => None,
                };
                if let Some(ip) = ip {
                    if ips.iter().any(|seen| seen == ip) {
                        self.problem(
                            device.at,
                            format!("IP address {ip} is taken by an earlier device"),
                        );
                    }
                    ips.push(ip.to_owned());
                }
                seen.push(&device.address);
            }
        }
    }
}

/// A device entry's keys.
#[derive(Default)]
pub(super) struct Fields {
    pub(super) device: String,
    pub(super) name: Option<String>,
    pub(super) ip: Option<String>,
    pub(super) address: Option<String>,
    /// `modules = [...]` and where its key is.
    pub(super) modules: Option<(Vec<String>, usize)>,
    /// `access_point = "..."` and where its value is.
    pub(super) access_point: Option<(String, usize)>,
}

/// `card@ID` / `FILE@ID` (`@NAME` for PROFINET), `FILE#PICK` for EtherCAT.
fn split_suffix(bus: Bus, device: &str) -> (&str, Option<&str>) {
    let mark = match bus {
        Bus::EtherCat => '#',
        _ => '@',
    };
    match device.rsplit_once(mark) {
        Some((what, suffix)) => (what, Some(suffix)),
        None => (device, None),
    }
}
