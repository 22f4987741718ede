//! `edsgen simulate [FILE[@ID]...] [--node-id N]... [--card NAME[@ID]]... [--bus HOST:PORT |
//! --socketcan IFACE] [--trace]`: devices built at run time from description files, each a
//! runtime `Node` serving a [`RuntimeDictionary`], and the bundled cards with their drives'
//! behaviour ([`edsgen_sim::drives`]); all of them on one driver thread and one bus connection, as
//! one [`Segment`] (they hear one another in the process, the bus hears each frame once), until
//! the process is stopped or the bus goes away.
//!
//! Each FILE's node-ID is the `@ID` after it, else the `--node-id` in the same position, else a
//! DCF's `[DeviceComissioning]` NodeID. A FILE's overlay (`NAME.toml` beside it) applies, as in
//! `edsgen generate`: its strings and domains hold what the generated `Od` would. A card's
//! node-ID is its `@ID`, else its default (ms300 1, cp301 2, goodrive350 3, rd11 4, hd1e 5: the
//! demo's CP301 and Goodrive350 are `--card cp301 --card goodrive350`).
//! `@255` starts a device unconfigured, for an LSS master (CiA 305) to give it a node-ID; only
//! files that say `LSS_Supported=1` (none of the bundled cards does). Several unconfigured
//! devices of one identity get consecutive serial numbers (1018h:04), printed at start.
//! `--trace` prints every frame on the bus decoded
//! ([`edsgen_decode`]), as a further listening connection sees it. With python `canopen` as the
//! master (some lines left out):
//!
//! ```text
//! $ edsgen bus &
//! $ edsgen simulate eds/cp301.eds@3 eds/ms300.eds@4 --trace
//! simulating node 3 (eds/cp301.eds) on 127.0.0.1:29536
//! simulating node 4 (eds/ms300.eds) on 127.0.0.1:29536
//! 1795532924.966401  703  HEARTBEAT  node 3 boot-up
//! 1795532924.966816  704  HEARTBEAT  node 4 boot-up
//! 1795532925.494510  000  NMT        start, all nodes
//! 1795532925.494695  184  TPDO1      node 4 (nothing mapped)
//! 1795532925.495354  583  SDO        node 3 write 6040:00 Controlword = 15
//! 1795532925.521437  583  SDO        node 3 read 6041:00 Statusword = 0
//! 1795532925.521883  080  SYNC
//! ```

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, SystemTime};

use edsgen_host::driver::{Driver, MonotonicClock};
use edsgen_host::segment::Segment;
use edsgen_host::socketcand::SocketcandClient;
use edsgen_host::trace::epoch_micros;
use edsgen_host::vbus::BusDevice;
use edsgen_host::Transport;
use edsgen_runtime::od::ObjectDictionary;
use edsgen_runtime::wire::lss::UNCONFIGURED_NODE_ID;
use edsgen_runtime::{CanFrame, Node};

use super::lss;
use crate::cmd::simulate::Args;
use crate::cmd::{fail, parse_node_id, signals, DEFAULT_BUS};
use edsgen_decode::Decoder;
use edsgen_model::lint::Policy;
use edsgen_model::model::Device;
use edsgen_sim::canopen::{commissioned_node_id, DictionaryHooks, RuntimeDictionary};
use edsgen_sim::drives::{Card, CARDS};

/// How many receive and transmit PDOs a simulated node serves (1400h–140Fh, 1800h–180Fh).
pub const PDOS: usize = 16;

/// A simulated node.
pub type SimulatedNode = Node<RuntimeDictionary, DictionaryHooks, PDOS, PDOS>;

/// How long connecting to the bus (each step of the socketcand handshake) may take.
const CONNECT_TIMEOUT: Duration = Duration::from_secs(3);

/// One device to simulate: where it comes from, its node-ID and its model.
struct Planned {
    path: PathBuf,
    node_id: u8,
    /// What the node serves: a file's description, or a bundled card's simulated drive (whose
    /// description is parsed only to decode a trace).
    source: Source,
}

enum Source {
    File(Box<Device>),
    Card(&'static Card),
}

/// Runs `edsgen simulate` on a CAN bus.
pub fn run(args: Args, allow: &Policy) -> ExitCode {
    let planned = match plan(&args, allow) {
        Ok(planned) => planned,
        Err(message) => return fail(message),
    };
    let bus = match &args.socketcan {
        Some(iface) => Bus::SocketCan(iface),
        None => Bus::Hub(args.bus.as_deref().unwrap_or(DEFAULT_BUS)),
    };
    if let Err(message) = signals::install() {
        return fail(message);
    }
    if let Err(message) = no_one_answers_as(&bus, &planned) {
        return fail(message);
    }
    let mut decoder = Decoder::new();
    let mut members: Vec<Box<dyn BusDevice + Send>> = Vec::new();
    // The tracing connection first, so that it sees the boot-up messages.
    let mut listener = None;
    if args.trace {
        match bus.join() {
            Ok(transport) => listener = Some(transport),
            Err(message) => return fail(message),
        }
    }
    let mut identities: Vec<[u32; 4]> = Vec::new();
    let clock = MonotonicClock::new();
    let mut started = Vec::new();
    for p in &planned {
        let device = match &p.source {
            Source::Card(card) => (card.power_up)(p.node_id, clock.now()),
            Source::File(description) => {
                let mut od = RuntimeDictionary::new(description, p.node_id);
                if p.node_id == UNCONFIGURED_NODE_ID {
                    match own_serial(&mut od, &mut identities) {
                        Ok(identity) => started.push(format!(
                            "unconfigured node (LSS address {}): {}",
                            lss::show_identity(&identity),
                            p.path.display()
                        )),
                        Err(message) => return fail(format!("{}: {message}", p.path.display())),
                    }
                }
                for (index, name) in od.left_out() {
                    eprintln!(
                        "warning: {}: {index:04X}h `{name}` is left out (`edsgen generate` says why)",
                        p.path.display()
                    );
                }
                SimulatedNode::with_capacity(od, DictionaryHooks::default(), p.node_id, clock.now())
                    .map(|node| Box::new(node) as Box<dyn BusDevice + Send>)
            }
        };
        let node = match device {
            Ok(device) => device,
            Err(e) => return fail(format!("bad node-ID {}", e.0)),
        };
        // Only a trace decodes frames: a node's description is not kept otherwise.
        if args.trace && p.node_id != UNCONFIGURED_NODE_ID {
            match &p.source {
                Source::File(description) => decoder.describe(p.node_id, description),
                Source::Card(card) => decoder.describe(p.node_id, &card.model()),
            }
        }
        members.push(node);
        let what = match &p.source {
            Source::Card(card) => format!("card {}", card.name),
            Source::File(_) => p.path.display().to_string(),
        };
        let who = match p.node_id {
            UNCONFIGURED_NODE_ID => "unconfigured node".to_owned(),
            id => format!("node {id}"),
        };
        started.push(format!(
            "simulating {who} ({what}) on {}",
            match bus {
                Bus::Hub(addr) | Bus::SocketCan(addr) => addr,
            }
        ));
    }
    // The parsed descriptions are not needed any more: each node has its dictionary.
    drop(planned);
    // One connection and one driver thread for all the nodes (a segment: they hear one
    // another in this process), however many there are.
    let transport = match bus.join() {
        Ok(transport) => transport,
        Err(message) => return fail(message),
    };
    let count = members.len();
    let driver = match Driver::with_clock(transport, Segment::new(members), clock).spawn() {
        Ok(driver) => driver,
        Err(e) => return fail(format!("cannot start the nodes' thread: {e}")),
    };
    // Said once the nodes are on the bus, so that whoever waits for these lines can talk to them.
    for line in started {
        eprintln!("{line}");
    }
    loop {
        if signals::requested() {
            let _ = driver.stop();
            eprintln!("edsgen simulate: stopped {count} node(s)");
            return ExitCode::SUCCESS;
        }
        if driver.is_finished() {
            let (result, _, _) = driver.stop();
            let why = result.err().map_or("closed".to_owned(), |e| e.to_string());
            return fail(format!("{bus} went away: {why}"));
        }
        let Some(client) = listener.as_mut() else {
            signals::wait(Duration::from_millis(100));
            continue;
        };
        let frame = match client.recv_timeout(Duration::from_millis(100)) {
            Ok(Some(frame)) => frame,
            Ok(None) => continue,
            Err(e) => return fail(format!("{bus} went away: {e}")),
        };
        let now = Duration::from_micros(epoch_micros(SystemTime::now()));
        let mut out = std::io::stdout().lock();
        for line in decoder.decode(now, &frame) {
            if writeln!(out, "{line}").is_err() {
                // Nobody reads the trace any more (`| head`): the devices carry on without it.
                listener = None;
                break;
            }
        }
    }
}

/// How long a node-ID already on the bus has to answer before the simulated one joins.
const DUPLICATE_WAIT: Duration = Duration::from_millis(300);

/// Refuses to join nodes whose node-ID already answers on `bus`: an SDO upload of 1000h to
/// each planned node-ID (as `edsgen scan` asks), any answer on its 580h + node-ID within
/// [`DUPLICATE_WAIT`] a clash. Two nodes with one node-ID garble each other's answers.
fn no_one_answers_as(bus: &Bus<'_>, planned: &[Planned]) -> Result<(), String> {
    let mut probe = bus.join()?;
    let gone = |e: std::io::Error| format!("{bus} went away: {e}");
    for p in planned.iter().filter(|p| p.node_id != UNCONFIGURED_NODE_ID) {
        let request = [0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0];
        if let Some(frame) = CanFrame::new(0x600 + u16::from(p.node_id), &request) {
            probe.send(&frame).map_err(gone)?;
        }
    }
    let end = std::time::Instant::now() + DUPLICATE_WAIT;
    let mut taken = Vec::new();
    while let Some(left) = end.checked_duration_since(std::time::Instant::now()) {
        let Some(frame) = probe.recv_timeout(left).map_err(gone)? else {
            break;
        };
        let answer = frame.std_id().and_then(|id| id.checked_sub(0x580));
        if let Some(p) = planned
            .iter()
            .find(|p| answer == Some(u16::from(p.node_id)) && !taken.contains(&p.node_id))
        {
            taken.push(p.node_id);
        }
    }
    if taken.is_empty() {
        return Ok(());
    }
    taken.sort_unstable();
    let taken: Vec<String> = taken.iter().map(u8::to_string).collect();
    Err(format!(
        "duplicate node-ID: node {} already answers on {bus}; give the simulated device \
         another one (FILE@ID, --card NAME@ID)",
        taken.join(", ")
    ))
}

/// The bus the devices join, each through a connection of its own.
#[derive(Debug, Clone, Copy)]
enum Bus<'a> {
    /// A socketcand server at this address.
    Hub(&'a str),
    /// A Linux SocketCAN interface.
    SocketCan(&'a str),
}

impl Bus<'_> {
    /// A new connection to the bus, or the message saying why not.
    fn join(self) -> Result<Box<dyn Transport + Send>, String> {
        match self {
            Bus::Hub(addr) => match SocketcandClient::connect(addr, "can0", CONNECT_TIMEOUT) {
                Ok(client) => Ok(Box::new(client)),
                Err(e) => Err(format!("cannot reach the bus at {addr}: {e}")),
            },
            #[cfg(feature = "socketcan")]
            Bus::SocketCan(iface) => {
                match edsgen_host::socketcan::SocketCan::open(iface) {
                    Ok(socket) => Ok(Box::new(socket)),
                    Err(e) => Err(e.to_string()),
                }
            }
            #[cfg(not(feature = "socketcan"))]
            Bus::SocketCan(iface) => Err(format!(
                "cannot open SocketCAN interface `{iface}`: this edsgen is built without the `socketcan` feature; join a socketcand hub with --bus"
            )),
        }
    }
}

impl std::fmt::Display for Bus<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Bus::Hub(addr) => write!(f, "the bus at {addr}"),
            Bus::SocketCan(iface) => write!(f, "CAN interface {iface}"),
        }
    }
}

/// The devices of the command line with their node-IDs, or what is wrong.
fn plan(args: &Args, allow: &Policy) -> Result<Vec<Planned>, String> {
    if args.node_id.len() > args.files.len() {
        return Err(format!(
            "{} --node-id for {} file(s)",
            args.node_id.len(),
            args.files.len()
        ));
    }
    let mut planned: Vec<Planned> = Vec::new();
    for (i, arg) in args.files.iter().enumerate() {
        let (path, given) = match arg.rsplit_once('@') {
            Some((path, id)) => (
                path,
                Some(parse_sim_node_id(id).map_err(|e| format!("{arg}: {e}"))?),
            ),
            None => (arg.as_str(), args.node_id.get(i).copied()),
        };
        let path = PathBuf::from(path);
        let device = crate::cmd::simulate::load_servable(&path, None, allow)?.device;
        let node_id = match (given, commissioned_node_id(&device)) {
            (Some(id), _) => id,
            (None, Some(id)) => u8::try_from(id)
                .ok()
                .filter(|id| (1..=127).contains(id))
                .ok_or_else(|| {
                    format!(
                        "{}: the DCF's NodeID {id} is not in 1..=127; give --node-id",
                        path.display()
                    )
                })?,
            (None, None) => {
                return Err(format!(
                    "no node-ID for `{}`: give --node-id N or write {}@N",
                    path.display(),
                    path.display()
                ))
            }
        };
        if node_id == UNCONFIGURED_NODE_ID && !device.device_info.lss_supported {
            return Err(no_lss(&path));
        }
        if let Some(other) = planned.iter().find(|p| p.node_id == node_id) {
            if node_id != UNCONFIGURED_NODE_ID {
                return Err(format!(
                    "node-ID {node_id} is given to both `{}` and `{}`",
                    other.path.display(),
                    path.display()
                ));
            }
        }
        planned.push(Planned {
            path,
            node_id,
            source: Source::File(Box::new(device)),
        });
    }
    for arg in &args.cards {
        let (name, id) = match arg.rsplit_once('@') {
            Some((name, id)) => (
                name,
                Some(parse_sim_node_id(id).map_err(|e| format!("{arg}: {e}"))?),
            ),
            None => (arg.as_str(), None),
        };
        let card = Card::named(name).ok_or_else(|| {
            let names: Vec<&str> = CARDS.iter().map(|card| card.name).collect();
            format!(
                "no card `{name}`: the bundled cards are {}",
                names.join(", ")
            )
        })?;
        let node_id = id.unwrap_or(card.default_node_id);
        let path = PathBuf::from(card.eds_path);
        if node_id == UNCONFIGURED_NODE_ID {
            // Every bundled card's EDS says LSS_Supported=0, as its manual does.
            return Err(format!("--card {name}@255: {}", no_lss(&path)));
        }
        if let Some(other) = planned.iter().find(|p| p.node_id == node_id) {
            return Err(format!(
                "node-ID {node_id} is given to both `{}` and `{}`",
                other.path.display(),
                path.display()
            ));
        }
        planned.push(Planned {
            path,
            node_id,
            source: Source::Card(card),
        });
    }
    Ok(planned)
}

/// A node-ID of a simulated device: 1..=127, or 255 for an unconfigured one (LSS).
fn parse_sim_node_id(text: &str) -> Result<u8, String> {
    match text {
        "255" | "0xFF" | "0xff" => Ok(UNCONFIGURED_NODE_ID),
        _ => parse_node_id(text).map_err(|e| format!("{e} (or 255: unconfigured, for LSS)")),
    }
}

/// Why a device cannot start unconfigured.
fn no_lss(path: &std::path::Path) -> String {
    format!(
        "{} says LSS_Supported=0: the device cannot be configured by LSS (CiA 305), so it \
         cannot start unconfigured (@255); give it a node-ID 1..=127",
        path.display()
    )
}

/// Gives an unconfigured device a serial number (1018h:04) no other unconfigured device of its
/// kind has (the next free one from its own), so that LSS can tell them apart; returns its LSS
/// address and records it in `taken`.
fn own_serial(od: &mut RuntimeDictionary, taken: &mut Vec<[u32; 4]>) -> Result<[u32; 4], String> {
    let mut identity = [0u32; 4];
    for (sub, value) in (1..).zip(&mut identity) {
        let mut bytes = [0u8; 4];
        od.read(0x1018, sub, 0, &mut bytes)
            .map_err(|_| format!("1018h:{sub:02X}h is missing: LSS needs the whole identity"))?;
        *value = u32::from_le_bytes(bytes);
    }
    while taken.contains(&identity) {
        identity[3] = identity[3].wrapping_add(1);
    }
    od.set_initial(0x1018, 4, u64::from(identity[3]));
    taken.push(identity);
    Ok(identity)
}
