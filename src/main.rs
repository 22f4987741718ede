//! The `edsgen` command line: validate, dump, generate, list and explain the rules, and the bus
//! commands. The commands themselves live in `cmd/`; this file parses the arguments.
//!
//! Exit codes: 0 clean, 1 the input has errors (or warnings under `--deny
//! warnings`), 2 usage or I/O problems.

mod cmd;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};
use edsgen_model::diag::Severity;

use cmd::EXIT_USAGE;

/// mimalloc, not the system's malloc: `validate` builds a model of tens of thousands of small
/// strings per file and drops it whole, a pattern glibc's malloc serves with about 180
/// instructions per allocation and a page fault for each page it takes back and gives again;
/// mimalloc took 9 % of the instructions and 94 % of the page faults off reading the corpus.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

#[derive(Parser)]
#[command(
    name = "edsgen",
    version,
    about = "Typed Rust from fieldbus device descriptions (CANopen EDS, DCF, XDD, XDC; EtherNet/IP EDS; PROFIBUS GSD; PROFINET GSDML; EtherCAT ESI)"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Check description files (EDS, DCF, XDD, XDC, ESI, ODVA EDS, GSD, GSDML) against their
    /// standards and print diagnostics.
    Validate {
        /// Output format.
        #[arg(long, value_enum, default_value_t = OutputFormat::Human)]
        format: OutputFormat,
        /// Make warnings errors (`--deny warnings`), or the warnings and infos of one rule
        /// (`--deny EDS013`); repeatable.
        #[arg(long, value_name = "warnings|CODE")]
        deny: Vec<String>,
        /// Silence the warnings and infos of one rule (errors stay); repeatable.
        #[arg(long, value_name = "CODE")]
        allow: Vec<String>,
        /// Show only diagnostics of this severity or above (all are still counted).
        #[arg(long, value_enum, default_value_t = MinSeverity::Info)]
        min_severity: MinSeverity,
        /// Hide infos (`--min-severity warning`).
        #[arg(short, long, conflicts_with = "min_severity")]
        quiet: bool,
        /// For an ESI file with several devices: the one to read, by type name or product code
        /// (`#x00009252`); the first by default.
        #[arg(long, value_name = "NAME|#xCODE")]
        device: Option<String>,
        /// Description files (.eds, .dcf, .xdd, .xdc, .xml/.esi for ESI).
        #[arg(required = true)]
        files: Vec<PathBuf>,
    },
    /// Print the resolved model of one file as JSON.
    Dump {
        /// Output format (only JSON).
        #[arg(long, value_enum, default_value_t = DumpFormat::Json)]
        format: DumpFormat,
        /// For an ESI file with several devices: the one to read, by type name or product code
        /// (`#x00009252`); the first by default.
        #[arg(long, value_name = "NAME|#xCODE")]
        device: Option<String>,
        /// The description file.
        file: PathBuf,
    },
    /// List the devices of an ESI file, one line each: type name, product code, revision,
    /// profiles, bits mapped by default to outputs and inputs, name.
    Devices {
        /// The ESI file.
        file: PathBuf,
    },
    /// Write the SII (EEPROM) image of an ESI device (ETG.2010), as `simulate --ethercat` serves it.
    Sii {
        /// The ESI file.
        file: PathBuf,
        /// The device of a file with several: its type name or `#x` product code.
        #[arg(long, value_name = "NAME|#xCODE")]
        device: Option<String>,
        /// Where to write the image.
        #[arg(short = 'o', long = "output")]
        output: PathBuf,
    },
    /// Generate the Rust module build.rs would produce for one device.
    Generate {
        /// The description file.
        file: PathBuf,
        /// Write to this file instead of standard output.
        #[arg(short = 'o', long = "output")]
        output: Option<PathBuf>,
        /// The module name (default: from the file name).
        #[arg(long)]
        module: Option<String>,
        /// For an ESI file with several devices: the one to read, by type name or product code
        /// (`#x00009252`); the first by default.
        #[arg(long, value_name = "NAME|#xCODE")]
        device: Option<String>,
    },
    /// List every validation rule: code, severity and meaning.
    Rules {
        /// Output format.
        #[arg(long, value_enum, default_value_t = OutputFormat::Human)]
        format: OutputFormat,
    },
    /// Explain one rule: what it checks and what its severity does.
    Explain {
        /// The rule code, e.g. EDS317.
        code: String,
    },
    /// Read or write an entry of a node on a live bus (SDO).
    Sdo {
        #[command(subcommand)]
        command: cmd::canopen::sdo::SdoCommand,
    },
    /// Send an NMT command to a node or to all nodes, and report the state each then reports
    /// (its next heartbeat or boot-up within --timeout, else a guarding answer); exit 1 when
    /// none answers or one reports another state.
    Nmt {
        #[command(flatten)]
        bus: cmd::BusArgs,
        /// The command.
        #[arg(value_enum)]
        verb: cmd::canopen::nmt::NmtVerb,
        /// The node-ID, or `all`.
        node: String,
    },
    /// LSS (CiA 305): find nodes without a node-ID (fastscan), inquire, give a node-ID or a
    /// bit rate by identity; exit 1 when no node answers or one refuses.
    Lss {
        #[command(subcommand)]
        command: cmd::canopen::lss::LssCommand,
    },
    /// Find the nodes on a bus: node-ID, NMT state and identity.
    Scan {
        #[command(flatten)]
        bus: cmd::BusArgs,
    },
    /// Compare a live device with its description (every readable entry, and its identity).
    Check(cmd::canopen::check::CheckArgs),
    /// Run a CAN bus on TCP (a socketcand hub for python-can and edsgen) until Ctrl-C.
    Bus(cmd::canopen::bus::BusArgs),
    /// Simulate devices from description files on their bus: CAN by default, or EtherCAT,
    /// EtherNet/IP, PROFINET, PROFIBUS-DP.
    Simulate(cmd::simulate::Args),
    /// An EtherNet/IP scanner at the bench: list identities, read and write attributes and
    /// parameters, send any service, run a class-1 connection (io).
    #[command(subcommand)]
    Enip(cmd::enip::Args),
    /// PROFINET at the bench: list the devices on an interface (DCP), set a name of station,
    /// connect to a device as its IO controller and exchange its IO data (io).
    Pn {
        #[command(subcommand)]
        command: cmd::profinet::PnCommand,
    },
    /// A PROFIBUS-DP master at the bench (profirust): scan a serial line, exchange data (io).
    #[command(subcommand)]
    Dp(cmd::dp::Command),
    /// EtherCAT bench side over ethercrab: `ecat scan --iface IFACE [--esi FILE...]`.
    #[cfg(feature = "ethercrab")]
    Ecat(cmd::ethercat::ecat::Args),
    /// EtherCAT bench side: not in this build (it needs the `ethercrab` feature).
    #[cfg(not(feature = "ethercrab"))]
    #[command(disable_help_flag = true)]
    Ecat {
        /// Whatever was given: the command says how to get a build that has it.
        #[arg(trailing_var_arg = true, allow_hyphen_values = true, hide = true)]
        args: Vec<String>,
    },
    /// Decode a CAN log (candump, Vector ASC, PCAN TRC; or standard input) into CANopen messages.
    Decode(cmd::decode::Args),
    /// The bundled cards at work: validate them, drive a CP301 and a Goodrive350 (simulated, or
    /// on a bus) through their manuals' workflows, every frame decoded, then the EC-TX508 over
    /// EtherCAT in cyclic synchronous velocity and the Goodrive350's EtherNet/IP, PROFINET and
    /// PROFIBUS-DP cards, in this process, or with --ethercat, --enip and --profinet over a
    /// real wire.
    Demo(cmd::demo::Args),
    /// The demo's client roles that `demo --enip` and `demo --profinet` run inside a network
    /// namespace (a process enters one only by being started in it): the card's steps against
    /// the device at the address, the report as JSON on standard output.
    #[command(subcommand)]
    DemoRole(cmd::demo::Role),
}

#[derive(Clone, Copy, ValueEnum)]
enum OutputFormat {
    Human,
    Json,
}

#[derive(Clone, Copy, ValueEnum)]
enum DumpFormat {
    Json,
}

#[derive(Clone, Copy, ValueEnum)]
enum MinSeverity {
    Info,
    Warning,
    Error,
}

impl From<MinSeverity> for Severity {
    fn from(min: MinSeverity) -> Self {
        match min {
            MinSeverity::Info => Severity::Info,
            MinSeverity::Warning => Severity::Warning,
            MinSeverity::Error => Severity::Error,
        }
    }
}

/// Parses the command line; `simulate`'s `--module`s then go to the FILE before each.
fn parse<I, T>(argv: I) -> Result<Cli, clap::Error>
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    use clap::{CommandFactory, FromArgMatches};
    let mut command = Cli::command();
    let matches = command.try_get_matches_from_mut(argv)?;
    let mut cli = Cli::from_arg_matches(&matches)?;
    if let (Command::Simulate(args), Some(simulate)) =
        (&mut cli.command, matches.subcommand_matches("simulate"))
    {
        if let Err(message) = args.place_modules(simulate) {
            let kind = clap::error::ErrorKind::ArgumentConflict;
            let simulate = command.find_subcommand_mut("simulate");
            return Err(match simulate {
                Some(simulate) => simulate.error(kind, message),
                None => command.error(kind, message),
            });
        }
    }
    Ok(cli)
}

fn main() -> ExitCode {
    cmd::signals::follow_parent();
    let cli = match parse(std::env::args_os()) {
        Ok(cli) => cli,
        Err(err) => {
            let _ = err.print();
            return match err.kind() {
                clap::error::ErrorKind::DisplayHelp | clap::error::ErrorKind::DisplayVersion => {
                    ExitCode::SUCCESS
                }
                _ => ExitCode::from(EXIT_USAGE),
            };
        }
    };
    match cli.command {
        Command::Validate {
            format,
            deny,
            allow,
            min_severity,
            quiet,
            device,
            files,
        } => {
            let min = if quiet {
                Severity::Warning
            } else {
                min_severity.into()
            };
            match cmd::validate::policy_or_exit(&allow, &deny, min) {
                Ok(policy) => cmd::validate::run(
                    matches!(format, OutputFormat::Json),
                    &policy,
                    &files,
                    device.as_deref(),
                ),
                Err(code) => code,
            }
        }
        Command::Dump {
            format: _,
            device,
            file,
        } => cmd::dump::run(&file, device.as_deref()),
        Command::Devices { file } => cmd::devices::run(&file),
        Command::Generate {
            file,
            output,
            module,
            device,
        } => cmd::generate::run(
            &file,
            output.as_deref(),
            module.as_deref(),
            device.as_deref(),
        ),
        Command::Sii {
            file,
            device,
            output,
        } => cmd::ethercat::sii::run(&file, device.as_deref(), &output),
        Command::Rules { format } => cmd::rules::list(matches!(format, OutputFormat::Json)),
        Command::Explain { code } => cmd::rules::explain(&code),
        Command::Sdo { command } => cmd::canopen::sdo::run(&command),
        Command::Nmt { bus, verb, node } => cmd::canopen::nmt::run(&bus, verb, &node),
        Command::Lss { command } => cmd::canopen::lss::run(&command),
        Command::Scan { bus } => cmd::canopen::scan::run(&bus),
        Command::Check(args) => cmd::canopen::check::run(&args),
        Command::Bus(args) => cmd::canopen::bus::run(&args),
        #[cfg(feature = "ethercrab")]
        Command::Ecat(args) => cmd::ethercat::ecat::run(args),
        #[cfg(not(feature = "ethercrab"))]
        Command::Ecat { .. } => {
            eprintln!("{}", cmd::ethercat::NOT_BUILT);
            ExitCode::from(EXIT_USAGE)
        }
        Command::Simulate(args) => cmd::simulate::run(args),
        Command::Enip(args) => cmd::enip::run(args),
        Command::Pn { command } => cmd::profinet::run(&command),
        Command::Dp(command) => cmd::dp::run(command),
        Command::Decode(args) => cmd::decode::run(args),
        Command::Demo(args) => cmd::demo::run(&args),
        Command::DemoRole(role) => cmd::demo::run_role(&role),
    }
}
