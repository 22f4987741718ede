//! `edsgen simulate --ethercat IFACE [FILE.xml [--device NAME|#xCODE] | --card ec-tx508]...`: an
//! EtherCAT segment of SubDevices served on a network interface, in the order the command line
//! names them: ESI devices and bundled EC-TX508s (each with its CiA 402 drive), mixed, each with
//! its own ESC, SII, station address, AL state machine, mailbox and process data. Through a raw
//! socket (root or CAP_NET_RAW), until SIGINT or SIGTERM. With `--faults-on-stdin` the
//! EC-TX508s' drives take `fault [POSITION]` and `clear [POSITION]` lines on standard input
//! ([`FaultSwitch`]). A modular ESI device is served with its modules plugged (`--module`, the
//! overlay's `[modules]`, else each slot's default): their PDOs, objects and SII categories.

use std::io::BufRead;
use std::path::Path;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use edsgen_model::lint::Policy;
use edsgen_model::model::modules::{choose_ec, parse_choices};
use edsgen_model::model::Device;
use edsgen_model::read;
use edsgen_runtime::Instant;
use edsgen_sim::canopen::RuntimeDictionary;
use edsgen_sim::drives::ec_tx508;
use edsgen_sim::ethercat::ec_tx508::EcTx508Behaviour;
use edsgen_sim::ethercat::raw_socket::RawSocket;
use edsgen_sim::ethercat::serve::serve;
use edsgen_sim::ethercat::{Behaviour, EsiDevice, Segment};

use crate::cmd::fail;

/// One SubDevice of the segment as the command line names it.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Member {
    /// An ESI file and the device chosen in it (`--device` after it).
    File {
        path: String,
        device: Option<String>,
    },
    /// A bundled card (`--card`).
    Card(String),
}

/// Where each FILE, `--card` and `--device` stood on the command line (clap's indices).
#[derive(Debug, Default)]
struct Places {
    files: Vec<usize>,
    cards: Vec<usize>,
    devices: Vec<usize>,
}

/// Runs the EtherCAT simulator: the segment of `files` (ESI) and `cards` (`ec-tx508`) in the
/// order given, `devices` choosing the device of the FILE each follows, `modules` the module
/// instances of each FILE in turn (`[SLOT=]NAME`; an empty list, or none, for a FILE: the
/// overlay's `[modules]`, else each slot's default); with `faults_on_stdin`, the EC-TX508s'
/// drives' faults switched by standard input.
pub fn run(
    iface: &str,
    files: &[String],
    cards: &[String],
    devices: &[String],
    modules: &[Vec<String>],
    faults_on_stdin: bool,
    allow: &Policy,
) -> ExitCode {
    let members = match members(files, cards, devices, &places()) {
        Ok(members) => members,
        Err(message) => return fail(message),
    };
    let drives: Vec<usize> = (0..members.len())
        .filter(|&n| matches!(members[n], Member::Card(_)))
        .collect();
    if faults_on_stdin && drives.is_empty() {
        return fail("--faults-on-stdin switches the faults of --card ec-tx508's drive");
    }
    let faults = faults_on_stdin.then(|| FaultLines::reading_stdin(&drives));
    let mut subdevices = Vec::new();
    let mut shown = Vec::new();
    let mut files_seen = 0;
    for (position, member) in members.iter().enumerate() {
        let chosen: &[String] = match member {
            Member::File { .. } => {
                files_seen += 1;
                modules.get(files_seen - 1).map_or(&[], Vec::as_slice)
            }
            Member::Card(_) => &[],
        };
        let (model, behaviour) = match load(member, chosen, allow) {
            Ok(loaded) => loaded,
            Err(message) => return fail(message),
        };
        let behaviour = match (behaviour, &faults) {
            (Some(card), Some(faults)) => {
                let switch = FaultSwitch {
                    card,
                    position: (members.len() > 1).then_some(position),
                    wanted: faults.flag(position),
                    present: false,
                };
                Some(Box::new(switch) as Box<dyn Behaviour>)
            }
            (card, _) => card.map(|card| Box::new(card) as Box<dyn Behaviour>),
        };
        let model = edsgen_sim::ethercat::modules::plugged(&model);
        match EsiDevice::subdevice(&model, behaviour) {
            Ok(subdevice) => subdevices.push(subdevice),
            Err(message) => return fail(format!("SubDevice {position}: {message}")),
        }
        shown.push(identity(&model));
    }
    let mut segment = Segment::new(subdevices);
    let mut socket = match RawSocket::open(iface, Duration::from_millis(100)) {
        Ok(socket) => socket,
        Err(err) => return fail(edsgen_sim::ethercat::raw_socket::open_error(iface, &err)),
    };
    let stop = Arc::new(AtomicBool::new(false));
    let flag = Arc::clone(&stop);
    if let Err(err) = ctrlc::set_handler(move || flag.store(true, Ordering::Relaxed)) {
        return fail(format!("cannot handle signals: {err}"));
    }
    if let [one] = &shown[..] {
        eprintln!("serving {one} as an EtherCAT SubDevice on {iface}; Ctrl-C stops");
    } else {
        for (position, device) in shown.iter().enumerate() {
            eprintln!("SubDevice {position}: {device}");
        }
        eprintln!(
            "serving a segment of {} SubDevices on {iface}; Ctrl-C stops",
            shown.len()
        );
    }
    match serve(&mut socket, &mut segment, &stop) {
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

/// `NAME (vendor .., product .., revision ..)` of a device's description, and `, modules SLOT=TYPE,
/// ...` (its `Slots/Slot`s counted from 1) when modules are plugged.
fn identity(model: &Device) -> String {
    let info = &model.device_info;
    let number = |n: &Option<edsgen_model::model::Spanned<u32>>| n.as_ref().map_or(0, |n| n.value);
    let mut line = format!(
        "{} (vendor {:#010X}, product {:#010X}, revision {:#010X})",
        info.product_name.as_deref().unwrap_or("?"),
        number(&info.vendor_number),
        number(&info.product_number),
        number(&info.revision_number),
    );
    let ec = model.ethercat();
    let plugged = ec.and_then(|ec| Some((ec, ec.chosen.as_ref()?)));
    if let Some((ec, chosen)) = plugged.filter(|(_, c)| !c.slots.is_empty()) {
        let names: Vec<String> = chosen
            .slots
            .iter()
            .map(|p| format!("{}={}", p.slot + 1, ec.modules[p.module].type_name))
            .collect();
        line.push_str(&format!(", modules {}", names.join(", ")));
    }
    line
}

/// Plugs `device`'s modules: the overlay's `[modules]` if it chose (a `--module` as well is
/// refused, as `--profinet` refuses it: the two would contradict), else `chosen` (`[SLOT=]NAME`), else each slot's default
/// where that makes a configuration the device allows (otherwise the device as described).
/// A `--module` choice the device does not allow is refused with EDS708's sentences.
fn plug(device: &mut Device, path: &str, chosen: &[String]) -> Result<(), String> {
    let Some(ec) = device.ethercat_mut() else {
        return Ok(());
    };
    if ec.chosen.is_some() {
        if !chosen.is_empty() {
            return Err(format!(
                "`{path}`: its overlay's [modules] already chooses the configuration; --module would contradict it"
            ));
        }
        return Ok(());
    }
    if chosen.is_empty() {
        ec.chosen = choose_ec(ec, &[]).ok();
        return Ok(());
    }
    let configuration = parse_choices(chosen)
        .map_err(|e| vec![e])
        .and_then(|choices| choose_ec(ec, &choices))
        .map_err(|problems| format!("{path}: --module (EDS708): {}", problems.join("; ")))?;
    ec.chosen = Some(configuration);
    Ok(())
}

/// A member's description, its modules plugged (`chosen`, [`plug`]), and the EC-TX508's drive
/// for the card.
fn load(
    member: &Member,
    chosen: &[String],
    allow: &Policy,
) -> Result<(Device, Option<EcTx508Behaviour>), String> {
    match member {
        Member::File { path, device } => {
            let read =
                crate::cmd::simulate::load_servable(Path::new(path), device.as_deref(), allow)?;
            if read.nothing_read || read.device.ethercat().is_none() {
                return Err(format!(
                    "{path}: not an ESI device (`edsgen validate {path}` says why)"
                ));
            }
            let mut model = read.device;
            plug(&mut model, path, chosen)?;
            Ok((model, None))
        }
        Member::Card(card) if card == "ec-tx508" => {
            let model = read::read_bytes(Path::new(ec_tx508::ESI_PATH), ec_tx508::ESI).device;
            let behaviour = EcTx508Behaviour::new(&model, Instant(0));
            Ok((model, Some(behaviour)))
        }
        Member::Card(card) => Err(format!("--ethercat serves the card ec-tx508, not `{card}`")),
    }
}

/// Where FILEs, `--card`s and `--device`s stood on this process's command line, as clap parses
/// it (its derived arguments keep no order between two of them). Empty if it does not parse,
/// as when `run` is not called from `edsgen simulate`.
fn places() -> Places {
    use clap::CommandFactory;
    let Ok(matches) = crate::Cli::command().try_get_matches_from(std::env::args_os()) else {
        return Places::default();
    };
    let Some(simulate) = matches.subcommand_matches("simulate") else {
        return Places::default();
    };
    let at = |id: &str| -> Vec<usize> {
        simulate
            .indices_of(id)
            .map(|i| i.collect())
            .unwrap_or_default()
    };
    Places {
        files: at("files"),
        cards: at("cards"),
        devices: at("devices"),
    }
}

/// The segment in command-line order: FILEs and `--card`s as `places` puts them (files first
/// when it does not know), each `--device` choosing in the FILE before it (with one FILE, in it
/// wherever it stands).
fn members(
    files: &[String],
    cards: &[String],
    devices: &[String],
    places: &Places,
) -> Result<Vec<Member>, String> {
    if files.is_empty() && cards.is_empty() {
        return Err("--ethercat serves ESI files and --card ec-tx508 (one or more)".to_owned());
    }
    let known = places.files.len() == files.len()
        && places.cards.len() == cards.len()
        && places.devices.len() == devices.len();
    let (file_at, card_at, device_at) = if known {
        (
            places.files.clone(),
            places.cards.clone(),
            places.devices.clone(),
        )
    } else {
        // Files first, each `--device` following the FILE of the same rank.
        let files_at: Vec<usize> = (0..files.len()).map(|n| 2 * n).collect();
        let cards_at = (0..cards.len()).map(|n| 2 * files.len() + n).collect();
        let devices_at = (0..devices.len()).map(|n| 2 * n + 1).collect();
        (files_at, cards_at, devices_at)
    };
    let mut chosen: Vec<Option<String>> = vec![None; files.len()];
    for (device, &at) in devices.iter().zip(&device_at) {
        let file = match files.len() {
            0 => return Err("--device chooses the device of an ESI FILE; none is given".to_owned()),
            1 => 0,
            _ => match file_at.iter().rposition(|&f| f < at) {
                Some(file) => file,
                None => {
                    return Err(format!(
                        "--device {device}: with several FILEs, each --device follows the FILE \
                         it chooses in"
                    ))
                }
            },
        };
        if let Some(first) = chosen[file].replace(device.clone()) {
            return Err(format!(
                "{}: two --device choices ({first}, {device}); one SubDevice per FILE given",
                files[file]
            ));
        }
    }
    let mut ordered: Vec<(usize, Member)> = files
        .iter()
        .zip(chosen)
        .zip(file_at)
        .map(|((path, device), at)| {
            let path = path.clone();
            (at, Member::File { path, device })
        })
        .chain(
            cards
                .iter()
                .zip(card_at)
                .map(|(card, at)| (at, Member::Card(card.clone()))),
        )
        .collect();
    ordered.sort_by_key(|(at, _)| *at);
    Ok(ordered.into_iter().map(|(_, member)| member).collect())
}

/// The `fault` and `clear` lines of standard input, read by a thread of their own, as flags
/// per EC-TX508: `fault`/`clear` for every one, `fault N`/`clear N` for the one at position N.
#[derive(Debug)]
struct FaultLines {
    flags: Vec<(usize, Arc<AtomicBool>)>,
}

impl FaultLines {
    fn reading_stdin(drives: &[usize]) -> Self {
        let flags: Vec<(usize, Arc<AtomicBool>)> = drives
            .iter()
            .map(|&n| (n, Arc::new(AtomicBool::new(false))))
            .collect();
        let reader = flags.clone();
        std::thread::spawn(move || {
            for line in std::io::stdin().lock().lines() {
                let Ok(line) = line else { break };
                if let Err(message) = apply_fault_line(&reader, line.trim()) {
                    eprintln!("ignored on standard input: `{}` ({message})", line.trim());
                }
            }
        });
        FaultLines { flags }
    }

    /// The flag of the drive at `position`.
    fn flag(&self, position: usize) -> Arc<AtomicBool> {
        self.flags
            .iter()
            .find(|(n, _)| *n == position)
            .map(|(_, f)| Arc::clone(f))
            .unwrap_or_default()
    }
}

/// Sets the flags a `fault [N]` or `clear [N]` line names; otherwise says what is taken.
fn apply_fault_line(flags: &[(usize, Arc<AtomicBool>)], line: &str) -> Result<(), String> {
    let mut words = line.split_whitespace();
    let wanted = match words.next() {
        Some("fault") => true,
        Some("clear") => false,
        _ => return Err("fault or clear, then optionally the EC-TX508's position".to_owned()),
    };
    let position = match (words.next(), words.next()) {
        (None, _) => None,
        (Some(n), None) => Some(
            n.parse::<usize>()
                .map_err(|_| format!("`{n}` is no position"))?,
        ),
        _ => return Err("one position at most".to_owned()),
    };
    let named: Vec<&Arc<AtomicBool>> = flags
        .iter()
        .filter(|(n, _)| position.is_none_or(|p| p == *n))
        .map(|(_, flag)| flag)
        .collect();
    if named.is_empty() {
        let positions: Vec<String> = flags.iter().map(|(n, _)| n.to_string()).collect();
        return Err(format!(
            "the EC-TX508s are at positions {}",
            positions.join(", ")
        ));
    }
    for flag in named {
        flag.store(wanted, Ordering::SeqCst);
    }
    Ok(())
}

/// The EC-TX508's drive with its faults switched from outside ([`FaultLines`]): a fault raised
/// or its cause removed (the drive then takes a fault reset) at the next cycle, and said on
/// standard error, with the SubDevice's position in a segment of several.
#[derive(Debug)]
struct FaultSwitch {
    card: EcTx508Behaviour,
    position: Option<usize>,
    /// What standard input last asked for: a fault present or not.
    wanted: Arc<AtomicBool>,
    /// What the drive was last told.
    present: bool,
}

impl Behaviour for FaultSwitch {
    fn cycle(&mut self, now: Instant, od: &mut RuntimeDictionary) {
        let wanted = self.wanted.load(Ordering::SeqCst);
        if wanted != self.present {
            let drive = self.card.card_mut().drive_mut();
            let what = if wanted {
                drive.raise_fault(now);
                "drive fault raised"
            } else {
                drive.clear_fault();
                "drive fault cause removed"
            };
            let at = now.as_micros() / 1000;
            match self.position {
                Some(n) => eprintln!("{what} at {at} ms (SubDevice {n})"),
                None => eprintln!("{what} at {at} ms"),
            }
            self.present = wanted;
        }
        self.card.cycle(now, od);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(path: &str, device: Option<&str>) -> Member {
        Member::File {
            path: path.to_owned(),
            device: device.map(str::to_owned),
        }
    }

    fn strings(list: &[&str]) -> Vec<String> {
        list.iter().map(|s| (*s).to_owned()).collect()
    }

    #[test]
    fn members_keep_the_command_line_order_and_their_device_choices() {
        // simulate --ethercat ecs --card ec-tx508 a.xml --device #x12 --card ec-tx508 b.xml
        let places = Places {
            files: vec![5, 10],
            cards: vec![4, 9],
            devices: vec![7],
        };
        let got = members(
            &strings(&["a.xml", "b.xml"]),
            &strings(&["ec-tx508", "ec-tx508"]),
            &strings(&["#x12"]),
            &places,
        );
        assert_eq!(
            got,
            Ok(vec![
                Member::Card("ec-tx508".to_owned()),
                file("a.xml", Some("#x12")),
                Member::Card("ec-tx508".to_owned()),
                file("b.xml", None),
            ])
        );
    }

    #[test]
    fn one_file_takes_its_device_wherever_it_stands() {
        let places = Places {
            files: vec![6],
            cards: vec![],
            devices: vec![4],
        };
        let got = members(&strings(&["a.xml"]), &[], &strings(&["X"]), &places);
        assert_eq!(got, Ok(vec![file("a.xml", Some("X"))]));
    }

    #[test]
    fn device_choices_that_name_no_file_or_two_are_refused() {
        let places = Places {
            files: vec![6, 8],
            cards: vec![],
            devices: vec![4],
        };
        let files = strings(&["a.xml", "b.xml"]);
        assert_eq!(
            members(&files, &[], &strings(&["X"]), &places),
            Err(
                "--device X: with several FILEs, each --device follows the FILE it chooses in"
                    .to_owned()
            )
        );
        let places = Places {
            files: vec![4, 10],
            cards: vec![],
            devices: vec![6, 8],
        };
        assert_eq!(
            members(&files, &[], &strings(&["X", "Y"]), &places),
            Err("a.xml: two --device choices (X, Y); one SubDevice per FILE given".to_owned())
        );
        assert_eq!(
            members(
                &[],
                &strings(&["ec-tx508"]),
                &strings(&["X"]),
                &Places::default()
            ),
            Err("--device chooses the device of an ESI FILE; none is given".to_owned())
        );
        assert_eq!(
            members(&[], &[], &[], &Places::default()),
            Err("--ethercat serves ESI files and --card ec-tx508 (one or more)".to_owned())
        );
    }

    #[test]
    fn without_places_files_come_first_each_with_its_device() {
        let got = members(
            &strings(&["a.xml", "b.xml"]),
            &strings(&["ec-tx508"]),
            &strings(&["X", "Y"]),
            &Places::default(),
        );
        assert_eq!(
            got,
            Ok(vec![
                file("a.xml", Some("X")),
                file("b.xml", Some("Y")),
                Member::Card("ec-tx508".to_owned()),
            ])
        );
    }

    #[test]
    fn fault_lines_name_every_drive_or_one_position() {
        let flags: Vec<(usize, Arc<AtomicBool>)> = [0, 2]
            .into_iter()
            .map(|n| (n, Arc::new(AtomicBool::new(false))))
            .collect();
        let states = || -> Vec<bool> {
            flags
                .iter()
                .map(|(_, f)| f.load(Ordering::SeqCst))
                .collect()
        };
        assert_eq!(apply_fault_line(&flags, "fault 2"), Ok(()));
        assert_eq!(states(), [false, true]);
        assert_eq!(apply_fault_line(&flags, "fault"), Ok(()));
        assert_eq!(states(), [true, true]);
        assert_eq!(apply_fault_line(&flags, "clear 0"), Ok(()));
        assert_eq!(states(), [false, true]);
        assert_eq!(
            apply_fault_line(&flags, "fault 1"),
            Err("the EC-TX508s are at positions 0, 2".to_owned())
        );
        assert_eq!(
            apply_fault_line(&flags, "fault one"),
            Err("`one` is no position".to_owned())
        );
        assert_eq!(
            apply_fault_line(&flags, "reset"),
            Err("fault or clear, then optionally the EC-TX508's position".to_owned())
        );
        assert_eq!(states(), [false, true]);
    }
}
