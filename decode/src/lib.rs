//! edsgen-decode, the bus decoder: CAN frames with their timestamps in, one line of text per
//! CANopen message out, naming entries and typing values from the devices' descriptions.
//! `edsgen decode` feeds it a log ([`log`]), `edsgen simulate --trace` the live bus.
//!
//! Each line is the time (seconds, as candump prints it), the CAN identifier, the service and
//! what the message says. An SDO transfer is one line when it finishes, whatever its frames
//! (expedited, segmented or block), with the whole value (an SDO channel of 1201h+ is followed
//! too, marked `(SDO channel 2)`); PDOs are decoded with the mapping the device has at that
//! moment (its description's, changed by the SDO writes seen on the bus); NMT resets bring the
//! description's values back; what cannot be attributed is printed raw. A session of python `canopen` with a simulated node
//! 9 (the device of `tests/sim_support`), decoded (some lines left out):
//!
//! ```text
//! 1764000000.000100  000  NMT        reset node 9
//! 1764000000.000800  709  HEARTBEAT  node 9 boot-up
//! 1764000000.002000  589  SDO        node 9 write 1017:00 Producer heartbeat time = 50
//! 1764000000.003100  589  SDO        node 9 read 1000:00 Device type = 131474 (0x00020192)
//! 1764000000.006300  589  SDO        node 9 write 2000:00 Device label = "edsgen simulate 2026" (segmented, 20 bytes)
//! 1764000000.012900  609  SDO        node 9 read 2000:00 Device label = "6202 etalumis negsde" (block, 20 bytes, CRC 6CDEh)
//! 1764000000.013600  589  SDO        node 9 read 5FFF:00 (not in the description): abort 0602 0000 object does not exist in the object dictionary
//! 1764000000.021000  589  SDO        node 9 write 1A00:01 TPDO1 mapping parameter: Mapped object 1 = 537067536 (0x20030010)
//! 1764000000.030000  000  NMT        start node 9
//! 1764000000.080000  080  SYNC
//! 1764000000.080400  189  TPDO1      node 9 Actual speed = -2
//! 1764000000.081000  209  RPDO1      node 9 Target speed = 102
//! 1764000000.090000  209  RPDO1      node 9 (empty) (the mapping needs 16 bits, the PDO has 0)
//! 1764000000.090300  089  EMCY       node 9 8210 PDO not processed due to length error; register 10h (communication); manufacturer 00 00 00 00 00
//! 1764000000.100000  7E5  LSS        switch state global: configuration
//! 1764000000.100400  7E5  LSS        inquire vendor-ID
//! 1764000000.100900  7E4  LSS        vendor-ID = 0x00000123
//! ```
//!
//! A value of more than 64 bytes is summarised: its first 16 bytes (or 64 characters), its
//! size and, for a block transfer, the CRC its end message gave (checked against the data);
//! [`Decoder::show_full_values`] (`edsgen decode --full`) prints it whole.
#![forbid(unsafe_code)]

pub mod image;
pub mod log;
pub mod lss;
pub mod sdo;
pub mod text;

use std::collections::{BTreeMap, BTreeSet};
use std::time::Duration;

use edsgen_model::model::Device;
use edsgen_runtime::wire::emcy::EmcyRepr;
use edsgen_runtime::wire::heartbeat::{ErrorControlRepr, NmtState};
use edsgen_runtime::wire::nmt::{NmtCommand, NmtRepr};
use edsgen_runtime::{CanFrame, CanId, ObjectDictionary, ResetKind};

use edsgen_sim::canopen::RuntimeDictionary;
use sdo::{Channel, Kind, Outcome, Transfer};

/// A described node: the names and types of its entries, and a copy of its dictionary kept up
/// to date with the SDO writes seen, for its PDOs' COB-IDs and mappings.
struct Described {
    device: Device,
    mirror: RuntimeDictionary,
}

/// The decoder's state between frames.
#[derive(Default)]
pub struct Decoder {
    described: BTreeMap<u8, Described>,
    /// SDO channels by node and number (0: the default one on 600h/580h + node-ID, 1 and up
    /// those of 1201h+ of a described node).
    sdo: BTreeMap<(u8, u8), Channel>,
    /// Nodes sent a node-guarding request whose answer has not come yet.
    guarded: BTreeSet<u8>,
    /// Print long SDO values whole rather than summarised.
    full: bool,
}

/// SDO values longer than this many bytes are summarised (unless [`Decoder::show_full_values`]).
pub const SUMMARY_AFTER: usize = 64;

impl Decoder {
    /// A decoder that knows no device: every message is decoded, without names or types.
    pub fn new() -> Self {
        Decoder::default()
    }

    /// Prints long SDO values whole: by default a value of more than [`SUMMARY_AFTER`] bytes
    /// shows its first bytes (or characters) only, beside its size and the CRC of a block
    /// transfer.
    pub fn show_full_values(&mut self) {
        self.full = true;
    }

    /// Describes node `node_id` by `device` (its values as the device starts: a DCF's
    /// ParameterValues, `$NODEID` resolved for `node_id`).
    pub fn describe(&mut self, node_id: u8, device: &Device) {
        let mirror = RuntimeDictionary::new(device, node_id);
        self.described.insert(
            node_id,
            Described {
                device: device.clone(),
                mirror,
            },
        );
    }

    /// The lines for one frame received at `at` (since the Unix epoch, as candump logs it):
    /// none for a step of an unfinished SDO transfer, else one.
    pub fn decode(&mut self, at: Duration, frame: &CanFrame) -> Vec<String> {
        let id = match frame.id() {
            CanId::Standard(id) => id,
            CanId::Extended(id) => {
                return vec![line(at, &format!("{id:08X}"), "RAW", &raw(frame))];
            }
        };
        let cob = format!("{id:03X}");
        let node = (id & 0x7F) as u8;
        let text = if frame.is_remote() {
            self.remote(id, node, frame)
        } else if let Some((node, channel, client)) = self.sdo_channel(id) {
            self.sdo(node, channel, client, frame.data())
        } else if let Some(text) = self.pdo(id, frame.data()) {
            Some(text)
        } else if matches!(id, 0x7E4 | 0x7E5) {
            Some(("LSS", lss::describe(id == 0x7E5, frame.data())))
        } else {
            match (id & !0x7F, node) {
                (0x000, 0) => Some(self.nmt(frame.data())),
                (0x080, 0) => Some(sync(frame.data())),
                (0x080, _) => Some(emergency(node, frame.data())),
                (0x100, 0) => Some((
                    "TIME",
                    text::time_of_day(frame.data()).unwrap_or_else(|| raw(frame)),
                )),
                (0x580, 1..) => self.sdo(node, 0, false, frame.data()),
                (0x600, 1..) => self.sdo(node, 0, true, frame.data()),
                (0x700, 1..) => Some(self.error_control(node, frame.data())),
                (base @ 0x180..=0x500, 1..) => Some(predefined_pdo(base, node, frame.data())),
                _ => Some(("RAW", raw(frame))),
            }
        };
        text.map(|(kind, text)| line(at, &cob, kind, &text))
            .into_iter()
            .collect()
    }

    /// Lines for the SDO transfers still unfinished (at the end of a log).
    pub fn finish(&mut self, at: Duration) -> Vec<String> {
        let mut lines = Vec::new();
        for (&(node, number), channel) in &mut self.sdo {
            if let Some(transfer) = channel.unfinished() {
                let described = self.described.get(&node);
                let text = describe_transfer(described, node, number, &transfer, false, self.full);
                lines.push(line(at, "---", "SDO", &format!("{text} (unfinished)")));
            }
        }
        lines
    }

    fn remote(&mut self, id: u16, node: u8, frame: &CanFrame) -> Option<(&'static str, String)> {
        if id & !0x7F == 0x700 && node != 0 {
            self.guarded.insert(node);
            return Some(("GUARD", format!("node {node} request")));
        }
        Some(("RAW", format!("remote request, DLC {}", frame.dlc())))
    }

    fn nmt(&mut self, data: &[u8]) -> (&'static str, String) {
        let Some(NmtRepr { command, node_id }) = NmtRepr::parse(data) else {
            return (
                "NMT",
                format!("not an NMT command: {}", text::hex_bytes(data)),
            );
        };
        // `reset node 3`, but `reset node, all nodes`.
        let (what, short) = match command {
            NmtCommand::Start => ("start", "start"),
            NmtCommand::Stop => ("stop", "stop"),
            NmtCommand::EnterPreOperational => ("enter pre-operational", "enter pre-operational"),
            NmtCommand::ResetNode => ("reset node", "reset"),
            NmtCommand::ResetCommunication => ("reset communication", "reset communication"),
        };
        let reset = match command {
            NmtCommand::ResetNode => Some(ResetKind::Node),
            NmtCommand::ResetCommunication => Some(ResetKind::Communication),
            _ => None,
        };
        for (&node, described) in &mut self.described {
            if let Some(kind) = reset.filter(|_| node_id == 0 || node_id == node) {
                described.mirror.reset(kind);
            }
        }
        if node_id == 0 {
            ("NMT", format!("{what}, all nodes"))
        } else {
            ("NMT", format!("{short} node {node_id}"))
        }
    }

    fn error_control(&mut self, node: u8, data: &[u8]) -> (&'static str, String) {
        let guarded = self.guarded.remove(&node);
        let Some(ErrorControlRepr { state, toggle }) = ErrorControlRepr::parse(data) else {
            return (
                "HEARTBEAT",
                format!("node {node} {}", text::hex_bytes(data)),
            );
        };
        let state = match state {
            NmtState::Initialising => "boot-up",
            NmtState::Stopped => "stopped",
            NmtState::Operational => "operational",
            NmtState::PreOperational => "pre-operational",
        };
        if guarded {
            (
                "GUARD",
                format!("node {node} {state}, toggle {}", u8::from(toggle)),
            )
        } else {
            ("HEARTBEAT", format!("node {node} {state}"))
        }
    }

    /// The node, channel number and direction (client to server or not) of an SDO channel a
    /// described node has beside the default one (1201h+: sub 1 client to server, sub 2 server
    /// to client).
    fn sdo_channel(&self, id: u16) -> Option<(u8, u8, bool)> {
        for (&node, described) in &self.described {
            let od = &described.mirror;
            for (position, entry) in od.entries().iter().enumerate() {
                if !(0x1201..=0x127F).contains(&entry.index()) || !matches!(entry.sub(), 1 | 2) {
                    continue;
                }
                let cob = od.value_at(position).map_or(0, u32_of);
                if cob & 0x8000_0000 == 0 && cob & 0x1FFF_FFFF == u32::from(id) {
                    return Some((node, (entry.index() - 0x1200) as u8, entry.sub() == 1));
                }
            }
        }
        None
    }

    fn sdo(
        &mut self,
        node: u8,
        number: u8,
        client: bool,
        data: &[u8],
    ) -> Option<(&'static str, String)> {
        let channel = self.sdo.entry((node, number)).or_default();
        let outcome = if client {
            channel.client(data)
        } else {
            channel.server(data)
        };
        match outcome {
            Outcome::Pending => None,
            Outcome::Abandoned(old) => {
                let described = self.described.get(&node);
                let text = describe_transfer(described, node, number, &old, false, self.full);
                Some(("SDO", format!("{text} (abandoned for a new request)")))
            }
            Outcome::Unattributed(why) => Some((
                "SDO",
                format!("node {node} {}: {why}", text::hex_bytes(data)),
            )),
            Outcome::Done(transfer) => {
                let described = self.described.get_mut(&node);
                let text = describe_transfer(
                    described.as_deref(),
                    node,
                    number,
                    &transfer,
                    true,
                    self.full,
                );
                if let Some(described) = described {
                    if transfer.write && transfer.abort.is_none() {
                        // What the device accepted; the mirror checks only lengths and limits.
                        let _ = described.mirror.write(
                            transfer.mux.index,
                            transfer.mux.sub,
                            &transfer.data,
                        );
                    }
                }
                Some(("SDO", text))
            }
        }
    }

    /// A PDO of a described node, by the COB-IDs and mappings its dictionary has now. Not on
    /// an identifier CiA 301 restricts (NMT, SYNC, TIME, SDO, error control, LSS): a PDO
    /// COB-ID there is a description's mistake (a missing default reads as 0).
    fn pdo(&self, id: u16, data: &[u8]) -> Option<(&'static str, String)> {
        let restricted = matches!(
            id,
            0x000..=0x080 | 0x100..=0x180 | 0x581..=0x5FF | 0x601..=0x67F | 0x6E0..=0x6FF | 0x701..
        );
        if restricted {
            return None;
        }
        for (&node, described) in &self.described {
            let od = &described.mirror;
            for (position, entry) in od.entries().iter().enumerate() {
                let transmit = match entry.index() {
                    0x1400..=0x15FF => false,
                    0x1800..=0x19FF => true,
                    _ => continue,
                };
                let cob = od.value_at(position).map_or(0, u32_of);
                if entry.sub() != 1 || cob & 0x8000_0000 != 0 || cob & 0x1FFF_FFFF != u32::from(id)
                {
                    continue;
                }
                let n = entry.index() & 0x1FF;
                let fields = described.pdo_fields(entry.index() + 0x200, data);
                return Some((pdo_kind(transmit, n), format!("node {node} {fields}")));
            }
        }
        None
    }
}

impl Described {
    /// The mapped fields of a PDO whose mapping is at `map_index`, decoded from `data`.
    fn pdo_fields(&self, map_index: u16, data: &[u8]) -> String {
        let od = &self.mirror;
        let count = od
            .locate(map_index, 0)
            .ok()
            .and_then(|p| od.value_at(p))
            .map_or(0, |v| v.first().copied().unwrap_or(0));
        let mut fields = Vec::new();
        let mut offset = 0usize;
        for sub in 1..=count {
            let Some(entry) = od
                .locate(map_index, sub)
                .ok()
                .and_then(|p| od.value_at(p))
                .map(u32_of)
            else {
                break;
            };
            let (index, mapped_sub, bits) = ((entry >> 16) as u16, (entry >> 8) as u8, entry as u8);
            let bits = usize::from(bits);
            if offset + bits > 8 * data.len() {
                return format!(
                    "{} (the mapping needs {} bits, the PDO has {})",
                    text::hex_bytes(data),
                    offset + bits,
                    8 * data.len()
                );
            }
            if index >= 0x1000 && bits % 8 == 0 && offset.is_multiple_of(8) {
                let bytes = &data[offset / 8..(offset + bits) / 8];
                let data_type = od.find(index, mapped_sub).ok().map(|e| e.data_type());
                fields.push(format!(
                    "{} = {}",
                    self.name(index, mapped_sub),
                    text::value(data_type, bytes)
                ));
            } else if index >= 0x1000 {
                let value = edsgen_runtime::od::typed::get_bits(data, offset, bits as u32);
                fields.push(format!("{} = {value}", self.name(index, mapped_sub)));
            }
            offset += bits;
        }
        match (fields.is_empty(), count, data.is_empty()) {
            (true, 0, true) => return "(nothing mapped)".into(),
            (true, 0, false) => return format!("(nothing mapped) {}", text::hex_bytes(data)),
            (true, _, _) => return text::hex_bytes(data),
            _ => {}
        }
        fields.join(", ")
    }

    /// `Object: Sub` for an entry of a record or array, else the object's name; `?` if absent.
    fn name(&self, index: u16, sub: u8) -> String {
        let Some(object) = self.device.objects.get(&index) else {
            return "(not in the description)".into();
        };
        match object.subs.get(&sub) {
            Some(entry) if object.object_type.has_subs() => {
                format!("{}: {}", object.name, entry.name)
            }
            Some(_) => object.name.clone(),
            None => format!("{}: (no sub-index {sub})", object.name),
        }
    }
}

fn u32_of(bytes: &[u8]) -> u32 {
    let mut word = [0u8; 4];
    let n = bytes.len().min(4);
    word[..n].copy_from_slice(&bytes[..n]);
    u32::from_le_bytes(word)
}

/// `TPDO1` for transmit PDO n = 0.
fn pdo_kind(transmit: bool, n: u16) -> &'static str {
    const TPDO: [&str; 8] = [
        "TPDO1", "TPDO2", "TPDO3", "TPDO4", "TPDO5", "TPDO6", "TPDO7", "TPDO8",
    ];
    const RPDO: [&str; 8] = [
        "RPDO1", "RPDO2", "RPDO3", "RPDO4", "RPDO5", "RPDO6", "RPDO7", "RPDO8",
    ];
    let list = if transmit { &TPDO } else { &RPDO };
    list.get(usize::from(n))
        .copied()
        .unwrap_or(if transmit { "TPDO" } else { "RPDO" })
}

/// A PDO of the pre-defined connection set whose mapping is not known.
fn predefined_pdo(base: u16, node: u8, data: &[u8]) -> (&'static str, String) {
    let n = (base - 0x180) / 0x100;
    let kind = pdo_kind(base & 0x80 != 0, n);
    (kind, format!("node {node} {}", text::hex_bytes(data)))
}

fn sync(data: &[u8]) -> (&'static str, String) {
    match data {
        [] => ("SYNC", String::new()),
        [counter] => ("SYNC", format!("counter {counter}")),
        _ => (
            "SYNC",
            format!("unexpected length: {}", text::hex_bytes(data)),
        ),
    }
}

fn emergency(node: u8, data: &[u8]) -> (&'static str, String) {
    let Some(EmcyRepr {
        code,
        register,
        manufacturer,
    }) = EmcyRepr::parse(data)
    else {
        return ("EMCY", format!("node {node} {}", text::hex_bytes(data)));
    };
    let text = format!(
        "node {node} {code:04X} {}; register {register:02X}h ({}); manufacturer {}",
        edsgen_runtime::wire::emcy::meaning(code),
        text::error_register(register),
        text::hex_bytes(&manufacturer)
    );
    ("EMCY", text)
}

/// The text of an SDO transfer; the value is shown when it is complete (a transfer that
/// `finished` without an abort, or an aborted expedited write, whose value was all sent),
/// summarised when long unless `full`.
fn describe_transfer(
    described: Option<&Described>,
    node: u8,
    number: u8,
    t: &Transfer,
    finished: bool,
    full: bool,
) -> String {
    let (index, sub) = (t.mux.index, t.mux.sub);
    let name = described.map_or(String::new(), |d| format!(" {}", d.name(index, sub)));
    let what = if t.write { "write" } else { "read" };
    let channel = match number {
        0 => String::new(),
        n => format!(" (SDO channel {})", n + 1),
    };
    let mut text = format!("node {node}{channel} {what} {index:04X}:{sub:02X}{name}");
    let complete = match t.abort {
        None => finished,
        Some(_) => t.write && t.kind == Kind::Expedited,
    };
    if complete {
        let data_type = described
            .and_then(|d| d.mirror.find(index, sub).ok())
            .map(|e| e.data_type());
        let summarised = !full && t.data.len() > SUMMARY_AFTER;
        let value = if summarised {
            text::summary(data_type, &t.data)
        } else {
            text::value(data_type, &t.data)
        };
        text.push_str(&format!(" = {value}"));
        let crc = match t.crc {
            Some(crc) if crc != 0 => {
                let actual = edsgen_runtime::sdo::crc::crc16(&t.data);
                if actual == crc {
                    format!(", CRC {crc:04X}h")
                } else {
                    format!(", CRC {crc:04X}h but the data's is {actual:04X}h")
                }
            }
            _ => String::new(),
        };
        let more = if summarised { "; --full shows all" } else { "" };
        match t.kind {
            Kind::Expedited => {}
            Kind::Segmented => {
                text.push_str(&format!(" (segmented, {} bytes{more})", t.data.len()))
            }
            Kind::Block => text.push_str(&format!(" (block, {} bytes{crc}{more})", t.data.len())),
        }
    }
    if let Some((code, by_server)) = t.abort {
        let by = if by_server { "" } else { " by the client" };
        text.push_str(&format!(": abort{by} {}", text::abort(code)));
    }
    text
}

fn raw(frame: &CanFrame) -> String {
    text::hex_bytes(frame.data())
}

/// One output line: time, COB-ID, service, text.
fn line(at: Duration, cob: &str, kind: &str, text: &str) -> String {
    let line = format!(
        "{}.{:06}  {cob}  {kind:<9}  {text}",
        at.as_secs(),
        at.subsec_micros()
    );
    line.trim_end().to_owned()
}
