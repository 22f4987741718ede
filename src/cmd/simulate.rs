//! `edsgen simulate`: simulated devices built from description files or bundled cards, on the
//! bus its flag names: a CAN bus by default ([`super::canopen::simulate`]), `--ethercat`
//! ([`super::ethercat::simulate`]), `--enip` ([`super::enip::simulate`]), `--profinet`
//! ([`super::profinet::simulate`]) or `--profibus` ([`super::dp::simulate`]).

use std::path::Path;
use std::process::ExitCode;

use edsgen_model::lint::Policy;
use edsgen_model::load::Loaded;

use super::{fail, parse_node_id, rule_named};

/// The arguments of `edsgen simulate`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Description files, each optionally followed by `@ID` (a node-ID, 255 for an unconfigured
    /// LSS node; a station address with --profibus): EDS, DCF, XDD or XDC on a CAN bus, an ODVA
    /// EDS with --enip, a GSDML with --profinet, a GSD with --profibus, an ESI with --ethercat.
    #[arg(value_name = "FILE[@ID]", required_unless_present_any = ["cards", "machine"])]
    pub files: Vec<String>,
    /// A bundled card with its drive's behaviour (cp301, ms300, goodrive350, rd11, hd1e),
    /// optionally followed by `@ID`; repeatable.
    #[arg(long = "card", value_name = "NAME[@ID]")]
    pub cards: Vec<String>,
    /// Node-IDs (1 to 127), one per FILE in the same order, for files without `@ID`.
    #[arg(long = "node-id", value_name = "N", value_parser = parse_node_id)]
    pub node_id: Vec<u8>,
    /// The socketcand server (`edsgen bus`) to join.
    #[arg(long, value_name = "HOST:PORT", conflicts_with = "socketcan")]
    pub bus: Option<String>,
    /// A Linux SocketCAN interface to join instead (edsgen built with the `socketcan` feature).
    #[arg(long, value_name = "IFACE")]
    pub socketcan: Option<String>,
    /// Print every frame on the bus, decoded.
    #[arg(long)]
    pub trace: bool,
    /// Serve one ODVA EDS FILE (or `--card goodrive350-enip`) as an EtherNet/IP adapter on each
    /// address instead of joining a CAN bus (`IP` or `IP:PORT`; several as `A,B,...`, one
    /// adapter each).
    #[arg(long, value_name = "ADDR[,ADDR...]", conflicts_with_all = ["bus", "socketcan", "trace"])]
    pub enip: Option<String>,
    /// Simulate PROFINET IO devices on this network interface (GSDML FILEs and `--card
    /// goodrive350-pn`, each `@NAME` for its name of station, each with a MAC of its own;
    /// root or CAP_NET_RAW).
    #[arg(long, value_name = "IFACE", conflicts_with_all = ["bus", "socketcan"])]
    pub profinet: Option<String>,
    /// With --profinet: a device's IP address, and prefix (`10.0.0.2/24`; without one, the
    /// interface's prefix for it), as DCP reports it: one of the interface's addresses, for the
    /// RPC endpoint (UDP 34964) to be reached. Repeated, one per device in the devices' order
    /// (the cards, then the files), `-` for a device without one until a DCP Set gives it
    /// one. Default: the interface's IPv4 addresses in order, the first device the first; a
    /// device past them has none until a DCP Set gives it one.
    #[arg(long, value_name = "ADDR[/PREFIX]", requires = "profinet")]
    pub ip: Vec<String>,
    /// Serve PROFIBUS-DP slaves on this serial line instead, each at its own address
    /// (`--card goodrive350-dp[@ADDR]` and FILE.gsd[@ADDR], repeatable; 2 without `@ADDR`).
    #[arg(long, value_name = "TTY", conflicts_with_all = ["bus", "socketcan", "trace"])]
    pub profibus: Option<String>,
    /// With --profibus and one FILE.gsd: the module plugged in a slot (`SLOT=NAME`, or `NAME`
    /// for the slot after the previous one; repeatable, docs/modules.md). The slave then
    /// accepts only these; without, any combination of its modules the GSD allows. With
    /// --ethercat and one modular FILE.xml: the module instances in its `Slots/Slot`s (`SLOT`
    /// counts them from 1); without, the overlay's `[modules]`, else each slot's default.
    #[arg(long = "module", value_name = "[SLOT=]NAME")]
    pub modules: Vec<String>,
    /// Serve an EtherCAT segment on this network interface instead (root or CAP_NET_RAW): ESI
    /// FILEs and `--card ec-tx508`, repeated and mixed, as SubDevices in the order given (the
    /// first nearest the MainDevice), each with its own ESC, SII, station address, AL state
    /// machine, mailbox and process data.
    #[arg(long, value_name = "IFACE", conflicts_with_all = ["bus", "socketcan", "trace", "node_id"])]
    pub ethercat: Option<String>,
    /// With --ethercat: the device of an ESI file with several (type name or `#x` product
    /// code), given after the FILE it chooses in; repeatable, one per FILE.
    #[arg(long = "device", value_name = "NAME|#xCODE", requires = "ethercat")]
    pub devices: Vec<String>,
    /// With --ethercat --card ec-tx508 or --profinet --card goodrive350-pn: read `fault` and
    /// `clear` lines on standard input, which raise a drive fault and remove its cause (to try a
    /// MainDevice's fault handling, as `edsgen demo --ethercat` does, or a PROFINET
    /// controller's diagnosis alarms). In an EtherCAT segment, `fault N` and `clear N` switch
    /// the EC-TX508 at position N (0 first), `fault` and `clear` every one.
    #[arg(long)]
    pub faults_on_stdin: bool,
    /// Bring up a whole machine from a machine file (docs/machine.md): every bus table served,
    /// each device printed with its address, `fault NAME`/`clear NAME` on standard input.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["files", "cards", "node_id", "bus", "socketcan", "trace", "enip", "profinet", "ip", "profibus", "modules", "ethercat", "devices", "faults_on_stdin"])]
    pub machine: Option<std::path::PathBuf>,
    /// Serve a FILE despite its errors of this rule (repeatable): without it, a description
    /// with errors is refused, its errors shown as `edsgen validate` shows them.
    #[arg(long, value_name = "CODE")]
    pub allow: Vec<String>,
}

/// Runs `edsgen simulate`.
pub fn run(args: Args) -> ExitCode {
    if args.faults_on_stdin && args.ethercat.is_none() && args.profinet.is_none() {
        return fail("--faults-on-stdin goes with --ethercat or --profinet");
    }
    let allow = match allowed(&args.allow) {
        Ok(allow) => allow,
        Err(message) => return fail(message),
    };
    if let Some(machine) = &args.machine {
        return super::machine::run(machine, &args.allow, &allow);
    }
    if let Some(addr) = &args.enip {
        return super::enip::simulate::run(addr, &args.files, &args.cards, &allow);
    }
    if let Some(iface) = &args.profinet {
        return super::profinet::simulate::run(
            iface,
            &args.files,
            &args.cards,
            &args.ip,
            args.faults_on_stdin,
            &allow,
        );
    }
    if let Some(tty) = &args.profibus {
        return super::dp::simulate::run(tty, &args.files, &args.cards, &args.modules, &allow);
    }
    if let Some(iface) = &args.ethercat {
        if !args.modules.is_empty() && args.files.len() != 1 {
            return fail("--module plugs the modules of one ESI FILE: give exactly one");
        }
        let modules: Vec<Vec<String>> = args.files.iter().map(|_| args.modules.clone()).collect();
        return super::ethercat::simulate::run(
            iface,
            &args.files,
            &args.cards,
            &args.devices,
            &modules,
            args.faults_on_stdin,
            &allow,
        );
    }
    if !args.modules.is_empty() {
        return fail("--module goes with --profibus or --ethercat");
    }
    super::canopen::simulate::run(args, &allow)
}

/// The policy of `--allow CODE...`.
fn allowed(codes: &[String]) -> Result<Policy, String> {
    let mut policy = Policy::new();
    for code in codes {
        policy.allow(rule_named("--allow", code)?);
    }
    Ok(policy)
}

/// Loads a FILE for a simulator (one device of an ESI file when `device` names it) under the
/// one rule of every simulator ([`Loaded::servable`]): a description with errors that `allow`
/// does not name is refused, its errors printed on standard error rustc-style; the error is
/// then the last line to print.
pub fn load_servable(path: &Path, device: Option<&str>, allow: &Policy) -> Result<Loaded, String> {
    if !path.is_file() {
        return Err(format!("cannot read `{}`: not a file", path.display()));
    }
    let loaded = super::load(path, device)?;
    servable(&loaded, &path.display().to_string(), allow)?;
    Ok(loaded)
}

/// [`Loaded::servable`] for a description already loaded from `name`: the refusing errors
/// printed on standard error, the error the last line to print.
pub fn servable(loaded: &Loaded, name: &str, allow: &Policy) -> Result<(), String> {
    loaded.servable(name, allow).map_err(|refusal| {
        eprint!("{}", refusal.rendered);
        refusal.summary
    })
}
