//! `edsgen bus`: a socketcand hub on TCP that python-can, `edsgen simulate` and the runtime's
//! socketcand client join as one CAN bus, until Ctrl-C; optionally logging every frame in the
//! `candump -L` format. Frames dropped for a client that reads too slowly are reported on
//! standard error.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::mpsc;

use edsgen_host::hub::{Hub, HubOptions};

/// The arguments of `edsgen bus`.
#[derive(clap::Args)]
pub struct BusArgs {
    /// The address to listen on (port 0 picks a free one).
    #[arg(long, default_value = "127.0.0.1:29536")]
    listen: String,
    /// The channel the hub serves (`< open CHANNEL >`); clients asking for another are refused.
    #[arg(long, default_value = "can0")]
    channel: String,
    /// How many frames may wait for one client; when a client reads too slowly, its oldest
    /// waiting frames are dropped (counted, reported on standard error and signalled to it as an error
    /// frame), it is never disconnected.
    #[arg(long, value_name = "FRAMES", default_value_t = 65_536,
          value_parser = clap::value_parser!(u32).range(1..))]
    queue_limit: u32,
    /// Write every relayed frame to this file as `candump -L` lines.
    #[arg(long)]
    log: Option<PathBuf>,
}

/// Runs the hub until Ctrl-C. Exit code 2 if it cannot listen, or cannot open or write the log.
pub fn run(args: &BusArgs) -> ExitCode {
    match serve(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::from(2)
        }
    }
}

fn serve(args: &BusArgs) -> Result<(), String> {
    let log = match &args.log {
        Some(path) => {
            let file = File::create(path)
                .map_err(|e| format!("cannot create the log {}: {e}", path.display()))?;
            Some(Box::new(BufWriter::new(file)) as Box<dyn Write + Send>)
        }
        None => None,
    };
    let (stop, stopped) = mpsc::channel();
    ctrlc::set_handler(move || {
        let _ = stop.send(());
    })
    .map_err(|e| format!("cannot catch Ctrl-C: {e}"))?;
    let options = HubOptions {
        log,
        channel: args.channel.clone(),
        queue_limit: args.queue_limit as usize,
        // A closed standard error must not stop the hub either.
        notices: Some(Box::new(|text| {
            let _ = writeln!(io::stderr(), "edsgen bus: {text}");
        })),
        ..HubOptions::default()
    };
    let hub = Hub::start(args.listen.as_str(), options).map_err(|e| {
        let reason = match e.kind() {
            io::ErrorKind::AddrInUse => "the address is in use (another hub?)".to_owned(),
            _ => e.to_string(),
        };
        format!("cannot listen on {}: {reason}", args.listen)
    })?;
    let addr = hub.local_addr();
    // A closed standard output (`edsgen bus | head -1`) must not stop the hub: errors ignored.
    let mut out = io::stdout();
    let _ = writeln!(
        out,
        "edsgen bus: socketcand hub listening on {addr}, channel {}; Ctrl-C stops it",
        args.channel
    );
    let _ = writeln!(
        out,
        "  python-can: can.Bus(interface=\"socketcand\", host=\"{}\", port={}, channel=\"{}\")",
        addr.ip(),
        addr.port(),
        args.channel
    );
    let _ = out.flush();
    let _ = stopped.recv();
    let relayed = hub.frames_relayed();
    let dropped = hub.frames_dropped();
    let log_error = hub.log_error();
    hub.stop();
    let _ = writeln!(out, "edsgen bus: stopped after relaying {relayed} frame(s)");
    if dropped > 0 {
        let _ = writeln!(
            io::stderr(),
            "edsgen bus: {dropped} frame(s) were dropped for clients that read too slowly"
        );
    }
    match log_error {
        Some(e) => Err(format!("the log stopped early: {e}")),
        None => Ok(()),
    }
}
