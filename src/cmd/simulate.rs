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
    /// With --profibus, --ethercat or --profinet: a module plugged in a slot of the FILE before
    /// it (`SLOT=NAME`, or `NAME` for the next slot; repeatable, docs/modules.md). A FILE with
    /// modules is plugged with them, and a GSD slave then accepts only these (without, any
    /// combination of its modules the GSD allows).
    #[arg(long = "module", value_name = "[SLOT=]NAME")]
    pub module_args: Vec<String>,
    /// With --profinet: the access point (DeviceAccessPointItem's ID or name) of the GSDML FILE
    /// before it; without, the first.
    #[arg(long = "access-point", value_name = "NAME", requires = "profinet")]
    pub access_point_args: Vec<String>,
    /// The modules of each FILE, in the order of `files` (`--module` after it): set by
    /// [`Args::place_modules`].
    #[arg(skip)]
    pub modules: Vec<Vec<String>>,
    /// The access point of each FILE, in the order of `files`: set by [`Args::place_modules`].
    #[arg(skip)]
    pub access_points: Vec<Option<String>>,
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
    #[arg(long, value_name = "FILE", conflicts_with_all = ["files", "cards", "node_id", "bus", "socketcan", "trace", "enip", "profinet", "ip", "profibus", "module_args", "access_point_args", "ethercat", "devices", "faults_on_stdin"])]
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
    let modular = args.profibus.is_some() || args.ethercat.is_some() || args.profinet.is_some();
    if !args.module_args.is_empty() && !modular {
        return fail("--module goes with --profibus, --ethercat or --profinet");
    }
    if let Some(addr) = &args.enip {
        return super::enip::simulate::run(addr, &args.files, &args.cards, &allow);
    }
    if let Some(iface) = &args.profinet {
        return super::profinet::simulate::run(
            iface,
            &args.files,
            &args.cards,
            (&args.modules, &args.access_points),
            &args.ip,
            args.faults_on_stdin,
            &allow,
        );
    }
    if let Some(tty) = &args.profibus {
        return super::dp::simulate::run(tty, &args.files, &args.cards, &args.modules, &allow);
    }
    if let Some(iface) = &args.ethercat {
        return super::ethercat::simulate::run(
            iface,
            &args.files,
            &args.cards,
            &args.devices,
            &args.modules,
            args.faults_on_stdin,
            &allow,
        );
    }
    super::canopen::simulate::run(args, &allow)
}

impl Args {
    /// Sets [`Args::modules`] and [`Args::access_points`] from where each `--module` and
    /// `--access-point` stood on the command line (`matches`, this subcommand's): each goes to
    /// the FILE before it. One before any FILE, or after a `--card`, is a usage error.
    pub fn place_modules(&mut self, matches: &clap::ArgMatches) -> Result<(), String> {
        let at = |id: &str| -> Vec<usize> {
            matches
                .indices_of(id)
                .map(|i| i.collect())
                .unwrap_or_default()
        };
        let placed = place(
            &Places {
                files: at("files"),
                cards: at("cards"),
                modules: at("module_args"),
                access_points: at("access_point_args"),
            },
            &self.module_args,
            &self.access_point_args,
        )?;
        (self.modules, self.access_points) = placed;
        Ok(())
    }
}

/// Where each FILE, `--card`, `--module` and `--access-point` stood (clap's indices).
#[derive(Debug, Default)]
struct Places {
    files: Vec<usize>,
    cards: Vec<usize>,
    modules: Vec<usize>,
    access_points: Vec<usize>,
}

/// Each FILE's modules and its access point, in the order of the files.
type Placed = (Vec<Vec<String>>, Vec<Option<String>>);

/// Each FILE's modules and access point, in the order of the files: every `--module` and
/// `--access-point` goes to the FILE before it.
fn place(places: &Places, modules: &[String], access_points: &[String]) -> Result<Placed, String> {
    /// What stands at an index.
    enum Word {
        File(usize),
        Card,
        Module(usize),
        AccessPoint(usize),
    }
    let mut words: Vec<(usize, Word)> = Vec::new();
    words.extend(
        places
            .files
            .iter()
            .enumerate()
            .map(|(n, &i)| (i, Word::File(n))),
    );
    words.extend(places.cards.iter().map(|&i| (i, Word::Card)));
    words.extend(
        places
            .modules
            .iter()
            .enumerate()
            .map(|(n, &i)| (i, Word::Module(n))),
    );
    words.extend(
        places
            .access_points
            .iter()
            .enumerate()
            .map(|(n, &i)| (i, Word::AccessPoint(n))),
    );
    words.sort_by_key(|(i, _)| *i);
    let mut per_file = vec![Vec::new(); places.files.len()];
    let mut points = vec![None; places.files.len()];
    // The FILE the words go to: `None` before any, `Some(None)` after a --card.
    let mut owner: Option<Option<usize>> = None;
    for (_, word) in words {
        let (flag, value) = match word {
            Word::File(n) => {
                owner = Some(Some(n));
                continue;
            }
            Word::Card => {
                owner = Some(None);
                continue;
            }
            Word::Module(n) => ("--module", modules.get(n)),
            Word::AccessPoint(n) => ("--access-point", access_points.get(n)),
        };
        let value = value.cloned().unwrap_or_default();
        let file = match owner {
            Some(Some(file)) => file,
            Some(None) => {
                return Err(format!(
                    "{flag} `{value}` follows a --card: a card's modules are its own; put {flag} after the FILE it plugs"
                ))
            }
            None => {
                return Err(format!(
                    "{flag} `{value}` comes before any FILE: put it after the FILE it plugs"
                ))
            }
        };
        if flag == "--module" {
            per_file[file].push(value);
        } else if points[file].replace(value).is_some() {
            return Err(
                "two --access-point for one FILE: a device has one access point".to_owned(),
            );
        }
    }
    Ok((per_file, points))
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

#[cfg(test)]
mod tests {
    use super::Args;

    /// `edsgen simulate ARGV...` parsed as `main` parses it.
    fn parsed(argv: &[&str]) -> Result<Args, String> {
        let mut words = vec!["edsgen", "simulate"];
        words.extend(argv);
        match crate::parse(words) {
            Ok(cli) => match cli.command {
                crate::Command::Simulate(args) => Ok(args),
                _ => Err("not simulate".to_owned()),
            },
            Err(e) => Err(e.to_string()),
        }
    }

    fn strings(words: &[&str]) -> Vec<String> {
        words.iter().map(|w| (*w).to_owned()).collect()
    }

    #[test]
    fn each_module_goes_to_the_file_before_it() {
        let args = parsed(&[
            "--profibus",
            "/dev/ttyS1",
            "a.gsd@5",
            "--module",
            "PPO 3",
            "--card",
            "goodrive350-dp@3",
            "b.gsd@6",
            "c.gsd@7",
            "--module",
            "2=8 DI",
            "--module",
            "4 PKW, 2 PZD (PPO 1)",
        ])
        .expect("parsed");
        assert_eq!(args.files, strings(&["a.gsd@5", "b.gsd@6", "c.gsd@7"]));
        assert_eq!(
            args.modules,
            vec![
                strings(&["PPO 3"]),
                Vec::new(),
                strings(&["2=8 DI", "4 PKW, 2 PZD (PPO 1)"])
            ]
        );
        assert_eq!(args.access_points, vec![None, None, None]);
    }

    #[test]
    fn an_access_point_goes_to_the_gsdml_before_it() {
        let args = parsed(&[
            "--profinet",
            "veth0",
            "a.xml@dev-a",
            "b.xml@dev-b",
            "--access-point",
            "DAP 2",
            "--module",
            "1=MOD_8DI",
        ])
        .expect("parsed");
        assert_eq!(args.modules, vec![Vec::new(), strings(&["1=MOD_8DI"])]);
        assert_eq!(args.access_points, vec![None, Some("DAP 2".to_owned())]);
    }

    #[test]
    fn a_module_before_any_file_or_after_a_card_is_refused() {
        let before = parsed(&["--profibus", "/dev/ttyS1", "--module", "PPO 3", "a.gsd@5"])
            .expect_err("refused");
        assert!(
            before.starts_with(
                "error: --module `PPO 3` comes before any FILE: put it after the FILE it plugs"
            ),
            "{before}"
        );
        let after_card = parsed(&[
            "--ethercat",
            "veth1",
            "a.xml",
            "--card",
            "ec-tx508",
            "--module",
            "EL1008",
        ])
        .expect_err("refused");
        assert!(
            after_card.starts_with(
                "error: --module `EL1008` follows a --card: a card's modules are its own; put --module after the FILE it plugs"
            ),
            "{after_card}"
        );
        let two = parsed(&[
            "--profinet",
            "veth0",
            "a.xml",
            "--access-point",
            "DAP 1",
            "--access-point",
            "DAP 2",
        ])
        .expect_err("refused");
        assert!(
            two.starts_with("error: two --access-point for one FILE"),
            "{two}"
        );
    }
}
