//! `edsgen demo [--bus HOST:PORT] [--ethercat] [--enip] [--profinet] [--machine]`: the bundled cards at work
//! (see the library's `demo` module), on the in-memory bus or against the drives on a socketcand
//! bus, the EC-TX508, the EtherNet/IP and the PROFINET card in this process or over a real wire
//! (root: network namespaces, removed also on Ctrl-C, exit 130); exit 0 only if every step
//! behaved as the manuals say. `edsgen demo-role enip-scanner ADDR` and `edsgen demo-role
//! profinet-controller IFACE ADDR` are the scanner and the controller that `--enip` and
//! `--profinet` run in their namespaces: their report as JSON on stdout.

use std::net::Ipv4Addr;
use std::process::ExitCode;
use std::time::Duration;

use edsgen_host::socketcand::SocketcandClient;

use super::{fail, print_stdout, DEFAULT_BUS};

/// The arguments of `edsgen demo`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Drive the devices on this socketcand bus (`edsgen bus`) instead of simulating them: a
    /// CP301 at node 2 and a Goodrive350 at node 3 (their default node-IDs: `edsgen simulate
    /// --card cp301 --card goodrive350`), in real time. Without HOST:PORT, `edsgen bus`'s
    /// default address. The EC-TX508 and the EtherNet/IP card are then reported as not run
    /// (their simulated devices live in this process); the PROFINET and PROFIBUS-DP cards still
    /// run in this process.
    #[arg(long, value_name = "HOST:PORT", num_args = 0..=1, default_missing_value = DEFAULT_BUS)]
    bus: Option<String>,
    /// Run the EC-TX508 over a real wire: a veth pair to a private network namespace, `edsgen
    /// simulate --ethercat` at its far end, ethercrab driving it from this end (root, and edsgen
    /// built with the `ethercrab` feature; otherwise said on stderr, and run in this process).
    /// Namespace and pair are removed on exit, also on Ctrl-C.
    #[arg(long, conflicts_with = "bus")]
    ethercat: bool,
    /// Run the Goodrive350's EtherNet/IP card over a real wire: two private network namespaces
    /// joined by a veth pair, `edsgen simulate --enip` in one, the demo's scanner in the other,
    /// over TCP 44818 and UDP 2222 (root; otherwise said on stderr, and run in this process).
    /// Namespaces and pair are removed on exit, also on Ctrl-C.
    #[arg(long, conflicts_with = "bus")]
    enip: bool,
    /// Run the Goodrive350's PROFINET card over a real wire: two private network namespaces
    /// joined by a veth pair, `edsgen simulate --profinet` in one, the demo's controller in the
    /// other, with DCP and RT_CLASS_1 frames and RPC on UDP 34964 (root; otherwise said on
    /// stderr, and run in this process). Namespaces and pair are removed on exit, also on
    /// Ctrl-C.
    #[arg(long, conflicts_with = "bus")]
    profinet: bool,
    /// Run the bundled cards as one machine: `edsgen simulate --machine` in a private network
    /// namespace serving the CP301 and the Goodrive350 on CANopen (an `edsgen bus` beside
    /// it), the EC-TX508 on EtherCAT, the EtherNet/IP, PROFINET and DP cards, each bus driven
    /// from the far side of its wire by the demo's master for it (root; the EC-TX508 by
    /// ethercrab, with the `ethercrab` feature; the DP card by profirust on a pseudo-terminal
    /// line). Then SIGTERM stops the machine. Not root: said on stderr, and the demo runs in this process.
    #[arg(long, conflicts_with_all = ["bus", "ethercat", "enip", "profinet"])]
    machine: bool,
}

/// Runs the demo, prints its trace and summary.
pub fn run(args: &Args) -> ExitCode {
    // A bus that is not there is a usage problem (exit 2), not a failed demo.
    if let Some(addr) = &args.bus {
        if let Err(e) = SocketcandClient::connect(addr, "can0", Duration::from_secs(5)) {
            return fail(format!(
                "cannot reach the bus at {addr}: {e} (start `edsgen bus`, then `edsgen simulate \
                 --card cp301 --card goodrive350`)"
            ));
        }
    }
    let wires = edsgen_demo::Wires {
        ethercat: args.ethercat,
        enip: args.enip,
        profinet: args.profinet,
    };
    if args.machine || wires != edsgen_demo::Wires::default() {
        // Ctrl-C must not leave a namespace behind.
        if let Err(message) = edsgen_demo::netns::clean_up_on_signal() {
            return fail(message);
        }
    }
    let report = match &args.bus {
        Some(addr) => edsgen_demo::run_on_bus(addr),
        None if args.machine => edsgen_demo::run_machine(),
        None => edsgen_demo::run_with(wires),
    };
    while edsgen_demo::netns::interrupted() {
        // Ctrl-C: the handler removes the namespaces, then ends the process with 130.
        std::thread::sleep(Duration::from_millis(100));
    }
    let mut text = report.lines.join("\n");
    let failed = report.steps.iter().filter(|s| s.outcome.is_err()).count();
    text.push_str(&format!(
        "\n\n{} step(s): {} as the manuals say, {failed} not\n",
        report.steps.len(),
        report.steps.len() - failed
    ));
    print_stdout(&text);
    if report.passed() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

/// `edsgen demo-role`: one of the demo's client roles, run by `edsgen demo --enip`,
/// `--profinet` or `--machine` inside its own network namespace.
#[derive(Debug, clap::Subcommand)]
pub enum Role {
    /// The CANopen master: both drives' workflows (CP301 at node 2, Goodrive350 at node 3)
    /// on the socketcand bus at this address, in real time.
    CanopenMaster {
        /// The bus's HOST:PORT.
        #[arg(value_name = "HOST:PORT")]
        bus: String,
    },
    /// The EtherNet/IP scanner: the Goodrive350 EtherNet/IP card's steps against the adapter at
    /// this address, over TCP 44818 and UDP 2222.
    EnipScanner {
        /// The adapter's IPv4 address.
        #[arg(value_name = "IPV4")]
        adapter: Ipv4Addr,
    },
    /// The PROFINET controller: the Goodrive350 PROFINET card's steps from this interface
    /// against the card at this address (DCP and RT_CLASS_1 frames, RPC on UDP 34964).
    ProfinetController {
        /// The controller's network interface.
        #[arg(value_name = "IFACE")]
        iface: String,
        /// The card's IPv4 address.
        #[arg(value_name = "IPV4")]
        card: Ipv4Addr,
    },
}

/// Runs one of the demo's client roles and prints its report as JSON.
pub fn run_role(role: &Role) -> ExitCode {
    let report = match role {
        Role::CanopenMaster { bus } => edsgen_demo::canopen_master(bus),
        Role::EnipScanner { adapter } => edsgen_demo::enip_scanner(*adapter),
        Role::ProfinetController { iface, card } => edsgen_demo::profinet_controller(iface, *card),
    };
    print_stdout(&report.to_json());
    ExitCode::SUCCESS
}
