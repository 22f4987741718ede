//! How many PROFINET IO devices one interface serves at a 4 ms cycle (issue 31): `edsgen
//! simulate --profinet` serving N Goodrive350 cards (`--card goodrive350-pn@dev-K`, each with
//! its own MAC and IP) on one end of a veth pair, in a private network namespace; in a second
//! namespace on the other end, this program as the IO controller, with the project's
//! controller core (`edsgen_sim::profinet::controller`): N ARs connected one after the other
//! (Connect, PrmEnd, ApplicationReady answered), then held for SECONDS at SendClockFactor 32,
//! ReductionRatio 4 (4 ms), DataHoldFactor 3 (the device's watchdog: 12 ms without outputs;
//! `--hold=H` for another), then released. Per N: the controller's ticks that started over
//! 1 ms late, the input frames received of those due, the gaps between one device's input
//! frames as the controller's reading thread saw them (p50, p99, worst), the ARs the devices
//! aborted (their watchdog expired: "AR aborted" on the simulator's output) and the ARs still
//! there to release, and the simulator's resident memory; then the largest N of those tried
//! with no watchdog expiry. Prints the load average first and last: on a shared machine the
//! figures are as quiet as it was. Needs root; release builds:
//!
//! ```sh
//! cargo build --release --bin edsgen --example profinet_scale
//! sudo target/release/examples/profinet_scale [SECONDS (10)] [--hold=H (3)] [N...] (1 8 16 32 64 128)
//! ```
//!
//! The namespaces, the veth pair and the simulator are removed at the end, also on failure.

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{mpsc, Arc};
use std::time::{Duration, Instant};

use edsgen_demo::netns::{is_root, End, Network};
use edsgen_runtime::profinet::wire::rt::{RtFrame, DATA_STATUS_GOOD};
use edsgen_runtime::profinet::wire::{Ethernet, Mac};
use edsgen_sim::profinet::ar::config::DeviceConfig;
use edsgen_sim::profinet::controller::{connected, response, Controller, CrLayout};
use edsgen_sim::profinet::driver::{RawSocket, RpcSocket};
use edsgen_sim::profinet::wire::append;
use edsgen_sim::profinet::wire::rpc::{Uuid, RPC_PORT};

/// The variable carrying the devices (`MAC,IP` each, space-separated) to this program run as
/// the controller.
const ROLE: &str = "EDSGEN_PN_SCALE_DEVICES";
/// SendClockFactor × ReductionRatio × 31.25 µs: 4 ms.
const SEND_CLOCK: u16 = 32;
const REDUCTION: u16 = 4;
const PERIOD: Duration = Duration::from_millis(4);
/// DataHoldFactor by default: the device's watchdog is 3 cycles without outputs.
const HOLD: u16 = 3;
/// The variable carrying the DataHoldFactor to the controller.
const HOLD_VAR: &str = "EDSGEN_PN_SCALE_HOLD";
/// A controller tick this late is counted.
const LATE: Duration = Duration::from_millis(1);

fn main() {
    let mut args = std::env::args().skip(1);
    let seconds: u64 = args.next().and_then(|s| s.parse().ok()).unwrap_or(10);
    if let Ok(devices) = std::env::var(ROLE) {
        let iface = args.next().unwrap_or_default();
        let hold = std::env::var(HOLD_VAR).ok().and_then(|h| h.parse().ok());
        match controller(&iface, &devices, seconds, hold.unwrap_or(HOLD)) {
            Ok(line) => println!("{line}"),
            Err(e) => {
                eprintln!("{e}");
                std::process::exit(1);
            }
        }
        return;
    }
    if !is_root() {
        eprintln!("profinet_scale needs root (network namespaces, raw sockets)");
        std::process::exit(2);
    }
    let rest: Vec<String> = args.collect();
    let hold = rest
        .iter()
        .find_map(|a| a.strip_prefix("--hold=")?.parse::<u16>().ok())
        .unwrap_or(HOLD);
    let mut counts: Vec<usize> = rest.iter().filter_map(|a| a.parse().ok()).collect();
    if counts.is_empty() {
        counts = vec![1, 8, 16, 32, 64, 128];
    }
    let edsgen = std::env::current_exe()
        .ok()
        .and_then(|me| Some(me.parent()?.parent()?.join("edsgen")))
        .filter(|p| p.is_file());
    let Some(edsgen) = edsgen else {
        eprintln!("no edsgen beside the example: cargo build --release --bin edsgen");
        std::process::exit(2);
    };
    println!("load average {}", load_average());
    println!(
        "{seconds} s per N at 4 ms, DataHoldFactor {hold} (the devices' watchdog: {} ms)",
        4 * hold
    );
    let mut largest = None;
    for n in counts {
        match run(&edsgen, n, seconds, hold) {
            Ok((line, aborted)) => {
                println!("N {n}: {line}");
                if aborted == 0 {
                    largest = Some(n);
                }
            }
            Err(e) => println!("N {n}: {e}"),
        }
    }
    match largest {
        Some(n) => println!("largest N with no watchdog expiry: {n}"),
        None => println!("every N tried had a watchdog expiry"),
    }
    println!("load average {}", load_average());
}

/// N cards served and driven for `seconds`: the controller's line and the ARs aborted.
fn run(
    edsgen: &std::path::Path,
    n: usize,
    seconds: u64,
    hold: u16,
) -> Result<(String, usize), String> {
    let mut net = Network::create("pnscale", 2)?;
    let (device_if, controller_if) = net.veth(End::Namespace(0), End::Namespace(1))?;
    net.address(1, &controller_if, "10.90.0.1/16")?;
    let ips: Vec<String> = (0..n)
        .map(|i| format!("10.90.{}.{}", 1 + i / 250, 1 + i % 250))
        .collect();
    for ip in &ips {
        net.address(0, &device_if, &format!("{ip}/16"))?;
    }
    let mut command = net.command(0, edsgen)?;
    command.args(["simulate", "--profinet", &device_if]);
    for (i, ip) in ips.iter().enumerate() {
        command.args(["--card", &format!("goodrive350-pn@dev-{}", i + 1)]);
        command.args(["--ip", &format!("{ip}/16")]);
    }
    let mut sim = Killed(
        command
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .map_err(|e| format!("edsgen: {e}"))?,
    );
    let stdout = sim.0.stdout.take().ok_or("the simulator's output")?;
    let aborted = Arc::new(AtomicUsize::new(0));
    let (macs_tx, macs) = mpsc::channel();
    let counted = Arc::clone(&aborted);
    std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines().map_while(Result::ok) {
            if let Some((_, mac)) = line.split_once(", MAC ") {
                let _ = macs_tx.send(mac.to_owned());
            }
            if line.ends_with("AR aborted") {
                counted.fetch_add(1, Ordering::Relaxed);
            }
        }
    });
    let mut devices = Vec::new();
    for ip in &ips {
        let mac = macs
            .recv_timeout(Duration::from_secs(20))
            .map_err(|_| "the simulator did not announce every device".to_owned())?;
        devices.push(format!("{mac},{ip}"));
    }
    // `ip netns exec` runs the program in its own place: the child is the simulator.
    let pid = sim.0.id();
    let me = std::env::current_exe().map_err(|e| e.to_string())?;
    let output = net
        .command(1, &me)?
        .args([seconds.to_string(), controller_if.clone()])
        .env(ROLE, devices.join(" "))
        .env(HOLD_VAR, hold.to_string())
        .output()
        .map_err(|e| format!("the controller: {e}"))?;
    let rss = resident_kib(pid).map_or("?".to_owned(), |k| k.to_string());
    let aborted = aborted.load(Ordering::Relaxed);
    let said = String::from_utf8_lossy(&output.stdout);
    let line = said.lines().last().unwrap_or_default();
    if !output.status.success() {
        let why = String::from_utf8_lossy(&output.stderr);
        return Ok((format!("controller failed: {}", why.trim()), aborted.max(1)));
    }
    Ok((
        format!("{line}, ARs aborted {aborted}, simulator resident {rss} KiB"),
        aborted,
    ))
}

/// One device as the controller holds it.
struct Held {
    mac: Mac,
    ip: [u8; 4],
    ctl: Controller,
    /// The FrameIDs of the input and the output CR.
    frame_ids: (u16, u16),
    last_input: Option<Instant>,
    inputs: usize,
}

/// The controller's side: connect every device, hold the ARs, release them; one line.
fn controller(iface: &str, devices: &str, seconds: u64, hold: u16) -> Result<String, String> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/eds/goodrive350-pn.xml");
    let read = edsgen_model::load::load(std::path::Path::new(path), None)
        .map_err(|e| format!("{path}: {e}"))?;
    let pn = read.device.profinet().ok_or("the card's GSDML")?;
    let config = DeviceConfig::from_gsdml(pn);
    let (input, output) = (CrLayout::of(&config, true), CrLayout::of(&config, false));
    let mut raw = RawSocket::open(iface, Duration::from_micros(200)).map_err(|e| e.to_string())?;
    let rpc = RpcSocket::open(iface).map_err(|e| e.to_string())?;
    let object = Uuid::pnio_object(1, 0x0350, 0x0350);
    let mut held = Vec::new();
    for (n, device) in devices.split_whitespace().enumerate() {
        let (mac, ip) = device.split_once(',').ok_or("MAC,IP")?;
        let mac = parse_mac(mac).ok_or("a MAC")?;
        let ip: std::net::Ipv4Addr = ip.parse().map_err(|_| "an IP")?;
        let ctl = Controller::new(raw.mac(), object, (n % 250) as u8 + 1);
        held.push(Held {
            mac,
            ip: ip.octets(),
            ctl,
            frame_ids: (0, 0),
            last_input: None,
            inputs: 0,
        });
    }
    let started = Instant::now();
    let mut stash = Stash::new();
    for device in &mut held {
        let blocks = device
            .ctl
            .connect_blocks(&config, SEND_CLOCK, REDUCTION, hold);
        let args = call(&rpc, &mut stash, device.ip, &device.ctl.connect(&blocks))?;
        device.frame_ids = connected(&args).ok_or("no IOCRBlockRes")?.frame_ids;
        call(&rpc, &mut stash, device.ip, &device.ctl.prm_end())?;
        ready(&rpc, &mut stash, device)?;
    }
    let connecting = started.elapsed();
    let mut c_sdu = vec![0u8; usize::from(output.length)];
    for &(_, _, offset, len) in &output.data {
        if let Some(iops) = c_sdu.get_mut(usize::from(offset + len)) {
            *iops = 0x80;
        }
    }
    for &(_, _, offset, _) in &output.iocs {
        if let Some(iocs) = c_sdu.get_mut(usize::from(offset)) {
            *iocs = 0x80;
        }
    }
    // A thread blocked in a read wakes when a frame comes; a read timeout goes by the
    // kernel's ticks (4 or 10 ms): the ticks are slept here, the frames read there.
    let mut reader = raw.try_clone().map_err(|e| e.to_string())?;
    let stop = Arc::new(AtomicUsize::new(0));
    let stopped = Arc::clone(&stop);
    let (frames_tx, frames) = mpsc::channel::<(Instant, Vec<u8>)>();
    let rx = std::thread::spawn(move || {
        let mut buf = vec![0u8; 1600];
        while stopped.load(Ordering::Relaxed) == 0 {
            if let Ok(Some(len)) = reader.recv(&mut buf) {
                let _ = frames_tx.send((Instant::now(), buf[..len].to_vec()));
            }
        }
    });
    let mut gaps: Vec<Duration> = Vec::new();
    let (mut ticks, mut late, mut counter) = (0usize, 0usize, 0u16);
    let mut next = Instant::now();
    let end = next + Duration::from_secs(seconds);
    while next < end {
        std::thread::sleep(next.saturating_duration_since(Instant::now()));
        if Instant::now() - next > LATE {
            late += 1;
        }
        ticks += 1;
        counter = counter.wrapping_add(SEND_CLOCK * REDUCTION);
        for device in &held {
            let frame = output_frame(raw.mac(), device, &c_sdu, counter);
            raw.send(&frame).map_err(|e| e.to_string())?;
        }
        next += PERIOD;
        for (at, frame) in frames.try_iter() {
            let Some(eth) = Ethernet::parse(&frame) else {
                continue;
            };
            let Some(device) = held.iter_mut().find(|d| d.mac == eth.src) else {
                continue;
            };
            let rt = frame
                .get(eth.payload..)
                .and_then(|pdu| RtFrame::parse(pdu, usize::from(input.length)));
            if rt.is_none_or(|rt| rt.frame_id != device.frame_ids.0) {
                continue;
            }
            if let Some(last) = device.last_input.replace(at) {
                gaps.push(at - last);
            }
            device.inputs += 1;
        }
    }
    stop.store(1, Ordering::Relaxed);
    let _ = rx.join();
    let due = held.len() * (seconds as usize * 1000 / 4);
    let received: usize = held.iter().map(|d| d.inputs).sum();
    let released = release_all(&rpc, &mut held)?;
    gaps.sort_unstable();
    let at = |q: f64| {
        let i = ((gaps.len() as f64 - 1.0) * q).round() as usize;
        gaps.get(i).map_or(0.0, |d| d.as_secs_f64() * 1000.0)
    };
    Ok(format!(
        "connected in {} ms; {ticks} ticks, {late} late; inputs {received} of {due}; gaps p50 {:.2} ms, p99 {:.2} ms, worst {:.2} ms; released {released} of {}",
        connecting.as_millis(),
        at(0.5),
        at(0.99),
        at(1.0),
        held.len()
    ))
}

/// The output frame of `device`.
fn output_frame(mac: Mac, device: &Held, c_sdu: &[u8], counter: u16) -> Vec<u8> {
    let mut out = Vec::new();
    append(&mut out, |b| Ethernet::emit(device.mac, mac, b));
    let frame = RtFrame {
        frame_id: device.frame_ids.1,
        c_sdu,
        cycle_counter: counter,
        data_status: DATA_STATUS_GOOD,
        transfer_status: 0,
    };
    append(&mut out, |b| frame.emit(b));
    out
}

/// Datagrams that came while waiting for another: the devices' requests (ApplicationReady).
type Stash = Vec<([u8; 4], Vec<u8>)>;

/// Sends `pdu` to the device at `ip` and waits for its answer (up to 2 s, sent up to three
/// times); the answer's blocks when its status is good. Requests that come meanwhile go to
/// `stash`.
fn call(rpc: &RpcSocket, stash: &mut Stash, ip: [u8; 4], pdu: &[u8]) -> Result<Vec<u8>, String> {
    let mut buf = vec![0u8; 4096];
    for _ in 0..3 {
        rpc.send((ip, RPC_PORT), pdu).map_err(|e| e.to_string())?;
        let deadline = Instant::now() + Duration::from_secs(2);
        while Instant::now() < deadline {
            match rpc.recv(&mut buf).map_err(|e| e.to_string())? {
                Some((len, from)) if from.0 == ip => {
                    let Some((status, args)) = response(&buf[..len]) else {
                        stash.push((ip, buf[..len].to_vec()));
                        continue;
                    };
                    return if status.is_ok() {
                        Ok(args)
                    } else {
                        Err(format!("refused: {:02x?}", status.0))
                    };
                }
                Some(_) => {}
                None => std::thread::sleep(Duration::from_micros(200)),
            }
        }
    }
    Err(format!("no answer from {ip:?}"))
}

/// Releases every AR at once (one after the other, each device would see no outputs for the
/// others' round trips, and its watchdog expire): how many the devices confirmed.
fn release_all(rpc: &RpcSocket, held: &mut [Held]) -> Result<usize, String> {
    for device in held.iter_mut() {
        let pdu = device.ctl.release();
        rpc.send((device.ip, RPC_PORT), &pdu)
            .map_err(|e| e.to_string())?;
    }
    let mut confirmed: Vec<[u8; 4]> = Vec::new();
    let mut buf = vec![0u8; 4096];
    let deadline = Instant::now() + Duration::from_secs(2);
    while Instant::now() < deadline && confirmed.len() < held.len() {
        match rpc.recv(&mut buf).map_err(|e| e.to_string())? {
            Some((len, from)) => {
                let ok = response(&buf[..len]).is_some_and(|(status, _)| status.is_ok());
                if ok && !confirmed.contains(&from.0) {
                    confirmed.push(from.0);
                }
            }
            None => std::thread::sleep(Duration::from_micros(200)),
        }
    }
    Ok(confirmed.len())
}

/// Waits for the device's ApplicationReady (perhaps in `stash` already) and answers it.
fn ready(rpc: &RpcSocket, stash: &mut Stash, device: &Held) -> Result<(), String> {
    let to = (device.ip, RPC_PORT);
    for (_, pdu) in stash.drain(..).filter(|(ip, _)| *ip == device.ip) {
        if let Some(done) = device.ctl.answer_ready(&pdu) {
            return rpc.send(to, &done).map_err(|e| e.to_string());
        }
    }
    let mut buf = vec![0u8; 4096];
    let deadline = Instant::now() + Duration::from_secs(5);
    while Instant::now() < deadline {
        match rpc.recv(&mut buf).map_err(|e| e.to_string())? {
            Some((len, from)) if from.0 == device.ip => {
                if let Some(done) = device.ctl.answer_ready(&buf[..len]) {
                    return rpc.send(from, &done).map_err(|e| e.to_string());
                }
            }
            Some(_) => {}
            None => std::thread::sleep(Duration::from_micros(200)),
        }
    }
    Err(format!("no ApplicationReady from {:?}", device.ip))
}

fn parse_mac(text: &str) -> Option<Mac> {
    let bytes: Vec<u8> = text
        .split(':')
        .map(|b| u8::from_str_radix(b, 16).ok())
        .collect::<Option<_>>()?;
    bytes.try_into().ok()
}

/// A child killed and waited for when dropped.
struct Killed(Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = Command::new("kill")
            .args(["-TERM", &self.0.id().to_string()])
            .status();
        let _ = self.0.wait();
    }
}

/// A process's resident memory (VmRSS), in KiB.
fn resident_kib(pid: u32) -> Option<u64> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// The first three fields of /proc/loadavg.
fn load_average() -> String {
    let text = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    let fields: Vec<&str> = text.split_whitespace().take(3).collect();
    fields.join(" ")
}
