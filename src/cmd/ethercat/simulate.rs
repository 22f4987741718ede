//! `edsgen simulate --ethercat IFACE FILE.xml [--device NAME|#xCODE]` and `edsgen simulate
//! --ethercat IFACE --card ec-tx508`: one EtherCAT SubDevice served from an ESI file (or the
//! bundled EC-TX508 with its CiA 402 drive) on a network interface, through a raw socket (root
//! or CAP_NET_RAW), until SIGINT or SIGTERM. With `--faults-on-stdin` the EC-TX508's drive
//! takes `fault` and `clear` lines on standard input ([`FaultSwitch`]).

use std::io::BufRead;
use std::path::Path;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use edsgen_model::lint::Policy;
use edsgen_model::model::Device;
use edsgen_model::read;
use edsgen_runtime::Instant;
use edsgen_sim::canopen::RuntimeDictionary;
use edsgen_sim::drives::ec_tx508;
use edsgen_sim::ethercat::ec_tx508::EcTx508Behaviour;
use edsgen_sim::ethercat::raw_socket::RawSocket;
use edsgen_sim::ethercat::serve::serve;
use edsgen_sim::ethercat::{Behaviour, EsiDevice};

use crate::cmd::fail;

/// Runs the EtherCAT simulator: exactly one of one ESI `files` entry or `--card ec-tx508`; with
/// `faults_on_stdin` (the card only), its drive's faults switched by standard input.
pub fn run(
    iface: &str,
    files: &[String],
    cards: &[String],
    device: Option<&str>,
    faults_on_stdin: bool,
    allow: &Policy,
) -> ExitCode {
    if faults_on_stdin && cards.is_empty() {
        return fail("--faults-on-stdin switches the faults of --card ec-tx508's drive");
    }
    let (model, behaviour): (Device, Option<Box<dyn Behaviour>>) = match (files, cards) {
        ([file], []) => {
            let path = Path::new(file);
            let read = match crate::cmd::simulate::load_servable(path, device, allow) {
                Ok(read) => read,
                Err(err) => return fail(err),
            };
            if read.nothing_read || read.device.ethercat().is_none() {
                return fail(format!(
                    "{file}: not an ESI device (`edsgen validate {file}` says why)"
                ));
            }
            (read.device, None)
        }
        ([], [card]) if card == "ec-tx508" => {
            let model = read::read_bytes(Path::new(ec_tx508::ESI_PATH), ec_tx508::ESI).device;
            let behaviour = EcTx508Behaviour::new(&model, Instant(0));
            let behaviour: Box<dyn Behaviour> = if faults_on_stdin {
                Box::new(FaultSwitch::reading_stdin(behaviour))
            } else {
                Box::new(behaviour)
            };
            (model, Some(behaviour))
        }
        ([], [card]) => return fail(format!("--ethercat serves the card ec-tx508, not `{card}`")),
        _ => return fail("--ethercat serves one device: one ESI file, or --card ec-tx508"),
    };
    let mut subdevice = match EsiDevice::subdevice(&model, behaviour) {
        Ok(subdevice) => subdevice,
        Err(message) => return fail(message),
    };
    let mut socket = match RawSocket::open(iface, Duration::from_millis(100)) {
        Ok(socket) => socket,
        Err(err) => return fail(edsgen_sim::ethercat::raw_socket::open_error(iface, &err)),
    };
    let stop = Arc::new(AtomicBool::new(false));
    let flag = Arc::clone(&stop);
    if let Err(err) = ctrlc::set_handler(move || flag.store(true, Ordering::Relaxed)) {
        return fail(format!("cannot handle signals: {err}"));
    }
    let info = &model.device_info;
    let number = |n: &Option<edsgen_model::model::Spanned<u32>>| n.as_ref().map_or(0, |n| n.value);
    eprintln!(
        "serving {} (vendor {:#010X}, product {:#010X}, revision {:#010X}) as an EtherCAT SubDevice on {iface}; Ctrl-C stops",
        info.product_name.as_deref().unwrap_or("?"),
        number(&info.vendor_number),
        number(&info.product_number),
        number(&info.revision_number),
    );
    match serve(&mut socket, &mut subdevice, &stop) {
        Ok(served) => {
            eprintln!(
                "stopped: {} frames answered, {} ignored",
                served.frames, served.ignored
            );
            ExitCode::SUCCESS
        }
        Err(err) => fail(format!("{iface}: {err}")),
    }
}

/// The EC-TX508's drive with its faults switched from outside: a thread reads standard input,
/// `fault` raises a drive fault and `clear` removes its cause (the drive then takes a fault
/// reset), each applied at the next cycle and said on standard error; other lines are
/// reported and ignored.
#[derive(Debug)]
struct FaultSwitch {
    card: EcTx508Behaviour,
    /// What standard input last asked for: a fault present or not.
    wanted: Arc<AtomicBool>,
    /// What the drive was last told.
    present: bool,
}

impl FaultSwitch {
    fn reading_stdin(card: EcTx508Behaviour) -> Self {
        let wanted = Arc::new(AtomicBool::new(false));
        let flag = Arc::clone(&wanted);
        std::thread::spawn(move || {
            for line in std::io::stdin().lock().lines() {
                let Ok(line) = line else { break };
                match line.trim() {
                    "fault" => flag.store(true, Ordering::SeqCst),
                    "clear" => flag.store(false, Ordering::SeqCst),
                    other => eprintln!("ignored on standard input: `{other}` (fault or clear)"),
                }
            }
        });
        FaultSwitch {
            card,
            wanted,
            present: false,
        }
    }
}

impl Behaviour for FaultSwitch {
    fn cycle(&mut self, now: Instant, od: &mut RuntimeDictionary) {
        let wanted = self.wanted.load(Ordering::SeqCst);
        if wanted != self.present {
            let drive = self.card.card_mut().drive_mut();
            if wanted {
                drive.raise_fault(now);
                eprintln!("drive fault raised at {} ms", now.as_micros() / 1000);
            } else {
                drive.clear_fault();
                eprintln!("drive fault cause removed at {} ms", now.as_micros() / 1000);
            }
            self.present = wanted;
        }
        self.card.cycle(now, od);
    }
}
