//! `edsgen pn io IFACE NAME --gsdml FILE [SETTING...]`: a PROFINET IO controller at the bench
//! (root, or `CAP_NET_RAW`). It finds the device by its name of station (DCP Identify; a DCP
//! Set of a temporary IP when it has none), connects an IO AR with the IOCRs, AlarmCR and
//! expected submodules of the GSDML's configuration (the overlay's `[modules]`, else
//! `--access-point` and `--module [SLOT=]NAME`, else the first access point and its fixed and
//! used modules), prints the device's ModuleDiffBlock if it sends one, writes the parameter
//! records (not those of the submodules it lists), ends the parametrization, answers the
//! device's ApplicationReady, and exchanges RT_CLASS_1 frames every `--cycle-ms`
//! with the outputs set on the command line (zero elsewhere), printing the inputs by name
//! whenever they change and each alarm (acknowledged); it releases the AR after `--cycles` or
//! on SIGINT/SIGTERM. Exit 0; 1 when the device is not found, refuses a step or is lost; 2 for
//! usage and I/O problems.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use edsgen_host::driver::MonotonicClock;
use edsgen_runtime::profinet::wire::connect::{SlotIdent, MODULE_NO};
use edsgen_runtime::profinet::wire::dcp;
use edsgen_runtime::profinet::wire::rpc::{PnioStatus, Uuid};
use edsgen_runtime::profinet::wire::rt::{RtFrame, DATA_STATUS_GOOD};
use edsgen_runtime::profinet::wire::{Ethernet, Mac};
use edsgen_sim::profinet::ar::config::DeviceConfig;
use edsgen_sim::profinet::controller::{alarm_cr, connected, Controller, CrLayout};
use edsgen_sim::profinet::controller_alarm::ControllerAlarms;
use edsgen_sim::profinet::iface;

use super::io_data::{self, RecordWrite, Setting, SubmoduleData};
use super::io_link::Link;
use super::{request, show_mac};
use crate::cmd::fail;

/// IOPS and IOCS "good".
pub(super) const GOOD: u8 = 0x80;
/// How long a DCP answer and an RPC response may take.
pub(super) const DCP_WAIT: Duration = Duration::from_secs(2);
pub(super) const RPC_WAIT: Duration = Duration::from_secs(5);

/// What `pn io` is asked to do.
#[derive(Debug)]
pub struct IoArgs<'a> {
    /// The interface.
    pub iface: &'a str,
    /// The device's name of station.
    pub name: &'a str,
    /// Its GSDML.
    pub gsdml: &'a PathBuf,
    /// `NAME=VALUE` and `SLOT.SUBSLOT=HEX` settings.
    pub settings: &'a [String],
    /// `[SLOT=]NAME` modules to plug (docs/modules.md).
    pub modules: &'a [String],
    /// The access point (its ID or name).
    pub access_point: Option<&'a str>,
    /// `SLOT.SUBSLOT.INDEX=HEX` record contents.
    pub records: &'a [String],
    /// Cycles of data exchange before the release (until a signal with `None`).
    pub cycles: Option<u64>,
    /// The cycle in ms (a power of two, 1 to 512).
    pub cycle_ms: u16,
}

/// Why a session ended early: a usage or I/O problem (2) or the device (1).
pub(super) enum Stop {
    Usage(String),
    Device(String),
}

/// Runs `pn io`.
pub fn run(args: &IoArgs) -> ExitCode {
    match session(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(Stop::Usage(message)) => fail(message),
        Err(Stop::Device(message)) => {
            eprintln!("{message}");
            ExitCode::from(1)
        }
    }
}

pub(super) fn usage(message: impl Into<String>) -> Stop {
    Stop::Usage(message.into())
}

fn session(args: &IoArgs) -> Result<(), Stop> {
    if !args.cycle_ms.is_power_of_two() || args.cycle_ms > 512 {
        return Err(usage(format!(
            "--cycle-ms {} is not a power of two from 1 to 512",
            args.cycle_ms
        )));
    }
    if args.name.is_empty() {
        return Err(usage("the device's name of station is empty"));
    }
    super::check_name(args.name).map_err(Stop::Usage)?;
    let loaded = super::super::load(args.gsdml, None).map_err(Stop::Usage)?;
    let pn = loaded
        .device
        .profinet()
        .ok_or_else(|| usage(format!("`{}` is not a GSDML file", args.gsdml.display())))?;
    let pn = &super::configured(
        pn,
        &args.gsdml.display().to_string(),
        args.modules,
        args.access_point,
    )
    .map_err(Stop::Usage)?;
    let config = DeviceConfig::from_gsdml(pn);
    let subs = io_data::submodules(pn, &config);
    let output_len = |slot, subslot| config.submodule(slot, subslot).map(|s| s.output_len);
    let settings = args
        .settings
        .iter()
        .map(|s| io_data::parse_setting(s, &subs, output_len))
        .collect::<Result<Vec<_>, _>>()
        .map_err(Stop::Usage)?;
    let records = io_data::records_with(pn, &config, args.records).map_err(Stop::Usage)?;
    crate::cmd::signals::install().map_err(Stop::Usage)?;
    let mut link = Link::open(args.iface)?;
    let (mac, ip, instance, ids) = find(&mut link, args.name)?;
    let ip = match ip {
        Some(ip) => ip,
        None => set_ip(&mut link, args.iface, mac)?,
    };
    let object = Uuid::pnio_object(instance, ids.1, ids.0);
    let mut ctl = Controller::new(link.mac, object, std::process::id() as u8);
    let mut ar = Ar::connect(&mut link, &mut ctl, &config, ip, mac, args.cycle_ms)?;
    ar.outputs(&settings);
    let result = exchange(&mut link, &mut ctl, &mut ar, &records, &subs, args);
    if !matches!(result, Err(Stop::Device(_))) {
        // The device may end its AlarmCR as the AR ends: no reason to stop now.
        ar.releasing = true;
        let cycles = ar.cycles;
        let released = link
            .call(ip, &ctl.release(), &mut ar)
            .map(|(status, _)| status.is_ok());
        match released {
            Ok(true) => println!("released the AR after {cycles} cycles"),
            Ok(false) => println!("the device refused the Release"),
            Err(e) => println!("no answer to the Release: {}", message(&e)),
        }
    }
    result
}

fn message(stop: &Stop) -> &str {
    match stop {
        Stop::Usage(m) | Stop::Device(m) => m,
    }
}

/// What DCP Identify tells of a device: MAC, IP, instance, (VendorID, DeviceID).
type Found = (Mac, Option<[u8; 4]>, u16, (u16, u16));

/// DCP Identify by name: the device's MAC, IP (`None` for 0.0.0.0), instance and
/// (VendorID, DeviceID).
fn find(link: &mut Link, name: &str) -> Result<Found, Stop> {
    let mut filter = vec![0; 4 + name.len() + 1];
    let n = dcp::emit_plain_block(&mut filter, dcp::NAME_OF_STATION, name.as_bytes())
        .map_err(|_| usage("the name does not fit a frame"))?;
    filter.truncate(n);
    let xid = std::process::id();
    let frame = request(
        dcp::MULTICAST_IDENTIFY,
        link.mac,
        dcp::FRAME_IDENTIFY_REQUEST,
        dcp::SERVICE_IDENTIFY,
        xid,
        &filter,
    );
    let (mac, blocks) = link.dcp(&frame, xid)?.ok_or_else(|| {
        Stop::Device(format!("no device named `{name}` answered in {DCP_WAIT:?}"))
    })?;
    let get = |option| blocks.iter().find(|b| b.0 == option).map(|b| b.1.clone());
    let ip = get(dcp::IP_PARAMETER)
        .and_then(|d| <[u8; 4]>::try_from(d.get(..4)?).ok())
        .filter(|ip| *ip != [0; 4]);
    let ids = get(dcp::DEVICE_ID).unwrap_or_default();
    let ids = match ids[..] {
        [a, b, c, d, ..] => (u16::from_be_bytes([a, b]), u16::from_be_bytes([c, d])),
        _ => (0, 0),
    };
    let instance = get(dcp::DEVICE_INSTANCE)
        .and_then(|d| Some(u16::from_be_bytes([*d.first()?, *d.get(1)?])))
        .unwrap_or(1);
    println!(
        "device `{name}` at {}, IP {}, VendorID {:#06x}, DeviceID {:#06x}",
        show_mac(&mac),
        ip.map_or("none".to_owned(), dotted),
        ids.0,
        ids.1
    );
    Ok((mac, ip, instance, ids))
}

fn dotted(ip: [u8; 4]) -> String {
    format!("{}.{}.{}.{}", ip[0], ip[1], ip[2], ip[3])
}

/// Gives the device without an IP the address after this interface's (temporary, DCP Set).
fn set_ip(link: &mut Link, iface: &str, mac: Mac) -> Result<[u8; 4], Stop> {
    let (own, mask) = iface::ipv4_addresses(iface)
        .ok()
        .and_then(|a| a.first().copied())
        .ok_or_else(|| {
            usage(format!(
                "the device has no IP and `{iface}` has none to derive one from"
            ))
        })?;
    let (own32, mask32) = (u32::from_be_bytes(own), u32::from_be_bytes(mask));
    let host = own32 & !mask32;
    let next = if host + 1 < !mask32 {
        host + 1
    } else {
        host - 1
    };
    let ip = ((own32 & mask32) | next).to_be_bytes();
    let mut value = vec![0x00, 0x00];
    value.extend_from_slice(&ip);
    value.extend_from_slice(&mask);
    value.extend_from_slice(&[0; 4]);
    let mut block = vec![0; 4 + value.len()];
    let n = dcp::emit_plain_block(&mut block, dcp::IP_PARAMETER, &value).unwrap_or(0);
    block.truncate(n);
    let xid = std::process::id().wrapping_add(1);
    let frame = request(
        mac,
        link.mac,
        dcp::FRAME_GET_SET,
        dcp::SERVICE_SET,
        xid,
        &block,
    );
    let answer = link.dcp(&frame, xid)?;
    let error = answer
        .as_ref()
        .and_then(|(_, blocks)| blocks.iter().find(|b| b.0 == dcp::CONTROL_RESPONSE))
        .and_then(|b| b.1.first().copied());
    match error {
        Some(0) => {
            println!(
                "set the device's IP to {} mask {} (temporary)",
                dotted(ip),
                dotted(mask)
            );
            Ok(ip)
        }
        Some(code) => Err(Stop::Device(format!(
            "the device refused the IP {} (BlockError {code})",
            dotted(ip)
        ))),
        None => Err(Stop::Device(format!(
            "no answer to the DCP Set of the IP in {DCP_WAIT:?}"
        ))),
    }
}

/// The AR's cyclic side: its frames, layouts, output data and alarms.
pub(super) struct Ar {
    pub(super) device: Mac,
    pub(super) ip: [u8; 4],
    pub(super) frame_ids: (u16, u16),
    pub(super) input: CrLayout,
    pub(super) output: CrLayout,
    /// The output CR's C_SDU.
    pub(super) c_sdu: Vec<u8>,
    pub(super) interval: Duration,
    /// Cycle counter step (31.25 µs units).
    pub(super) step: u16,
    pub(super) counter: u16,
    pub(super) next: Instant,
    /// Whether data exchange runs (after ApplicationReady): cycles count from then.
    pub(super) running: bool,
    pub(super) cycles: u64,
    /// The Release is under way: the end of the AlarmCR is expected.
    pub(super) releasing: bool,
    /// The last input frame's C_SDU, and when it came.
    pub(super) last: Option<(Vec<u8>, Instant)>,
    pub(super) alarms: ControllerAlarms,
    pub(super) clock: MonotonicClock,
    /// The modules of the device's ModuleDiffBlock: their submodules it lists, and every
    /// submodule of a slot it says is empty, are not parametrized.
    differing: Vec<SlotIdent>,
}

impl Ar {
    fn connect(
        link: &mut Link,
        ctl: &mut Controller,
        config: &DeviceConfig,
        ip: [u8; 4],
        device: Mac,
        cycle_ms: u16,
    ) -> Result<Ar, Stop> {
        // Send clock 1 ms (32 × 31.25 µs), the reduction ratio the cycle; a watchdog of 1 s.
        let factor = (1000 / cycle_ms).max(3);
        let blocks = ctl.connect_blocks(config, 32, cycle_ms, factor);
        let (input, output) = (CrLayout::of(config, true), CrLayout::of(config, false));
        let mut ar = Ar {
            device,
            ip,
            frame_ids: (0, 0),
            c_sdu: vec![0; usize::from(output.length)],
            input,
            output,
            interval: Duration::from_millis(u64::from(cycle_ms)),
            step: 32 * cycle_ms,
            counter: 0,
            next: Instant::now(),
            running: false,
            cycles: 0,
            releasing: false,
            last: None,
            alarms: ControllerAlarms::new(&alarm_cr(), 0, link.mac, device),
            clock: MonotonicClock::new(),
            differing: Vec::new(),
        };
        let (status, answer) = link.call(ip, &ctl.connect(&blocks), &mut ar)?;
        refused("Connect", status)?;
        let connected = connected(&answer)
            .ok_or_else(|| Stop::Device("the Connect's answer has no IOCRBlockRes".into()))?;
        if let Some(diff) = &connected.diff {
            println!("the device's modules differ from the configuration (its ModuleDiffBlock):");
            for line in io_data::module_diff_lines(diff) {
                println!("  {line}");
            }
            ar.differing = diff.apis.iter().flat_map(|a| a.modules.clone()).collect();
        }
        ar.frame_ids = connected.frame_ids;
        let device_ref = connected.device_alarm_ref.unwrap_or(0);
        ar.alarms = ControllerAlarms::new(&alarm_cr(), device_ref, link.mac, device);
        println!(
            "connected: input frame {:#06x}, output frame {:#06x}, every {cycle_ms} ms",
            ar.frame_ids.0, ar.frame_ids.1
        );
        Ok(ar)
    }

    /// The output C_SDU: every data IOPS and IOCS good, the settings in place.
    fn outputs(&mut self, settings: &[Setting]) {
        for &(_, _, offset, len) in &self.output.data {
            if let Some(b) = self.c_sdu.get_mut(usize::from(offset) + usize::from(len)) {
                *b = GOOD;
            }
        }
        for &(_, _, offset, _) in &self.output.iocs {
            if let Some(b) = self.c_sdu.get_mut(usize::from(offset)) {
                *b = GOOD;
            }
        }
        for (slot, subslot, at, bytes) in settings {
            let Some(&(_, _, offset, _)) = self
                .output
                .data
                .iter()
                .find(|d| (d.0, d.1) == (*slot, *subslot))
            else {
                continue;
            };
            let start = usize::from(offset) + at;
            if let Some(area) = self.c_sdu.get_mut(start..start + bytes.len()) {
                area.copy_from_slice(bytes);
            }
        }
    }

    /// The output frame, when its time has come.
    pub(super) fn due_frame(&mut self, mac: Mac) -> Option<Vec<u8>> {
        let now = Instant::now();
        if self.frame_ids.1 == 0 || now < self.next {
            return None;
        }
        self.next = (self.next + self.interval).max(now + self.interval / 2);
        self.counter = self.counter.wrapping_add(self.step);
        if self.running {
            self.cycles += 1;
        }
        let rt = RtFrame {
            frame_id: self.frame_ids.1,
            c_sdu: &self.c_sdu,
            cycle_counter: self.counter,
            data_status: DATA_STATUS_GOOD,
            transfer_status: 0,
        };
        let mut frame = vec![0; 14 + rt.buffer_len()];
        let at = Ethernet::emit(self.device, mac, &mut frame).ok()?;
        rt.emit(frame.get_mut(at..)?).ok()?;
        Some(frame)
    }
}

fn refused(step: &str, status: PnioStatus) -> Result<(), Stop> {
    if status.is_ok() {
        return Ok(());
    }
    let s = status.0;
    Err(Stop::Device(format!(
        "the device refused the {step}: PNIOStatus {:02x} {:02x} {:02x} {:02x}",
        s[0], s[1], s[2], s[3]
    )))
}

/// Parameters, PrmEnd, ApplicationReady, then cycles until done, a signal, or the device lost.
fn exchange(
    link: &mut Link,
    ctl: &mut Controller,
    ar: &mut Ar,
    records: &[RecordWrite],
    subs: &[SubmoduleData],
    args: &IoArgs,
) -> Result<(), Stop> {
    let ip = ar.ip;
    for (slot, subslot, index, data) in records {
        let (slot, subslot, index) = (*slot, *subslot, *index);
        let differs = ar
            .differing
            .iter()
            .filter(|m| m.slot == slot)
            .any(|m| m.state == MODULE_NO || m.submodules.iter().any(|s| s.0 == subslot));
        if differs {
            println!("not writing record {index} of slot {slot} subslot {subslot}: the device has another submodule there");
            continue;
        }
        let (status, _) = link.call(ip, &ctl.write(slot, subslot, index, data), ar)?;
        refused(
            &format!("Write of record {index} of slot {slot} subslot {subslot}"),
            status,
        )?;
        println!(
            "wrote record {index} of slot {slot} subslot {subslot} ({} bytes)",
            data.len()
        );
    }
    let (status, _) = link.call(ip, &ctl.prm_end(), ar)?;
    refused("PrmEnd", status)?;
    link.pump(ar, Instant::now() + RPC_WAIT, |l, _| !l.requests.is_empty())?;
    let Some((from, pdu)) = link.requests.pop() else {
        return Err(Stop::Device(format!(
            "no ApplicationReady from the device in {RPC_WAIT:?}"
        )));
    };
    let done = ctl
        .answer_ready(&pdu)
        .ok_or_else(|| Stop::Device("the device's request is not ApplicationReady".into()))?;
    link.rpc
        .send(from, &done)
        .map_err(|e| usage(format!("UDP to the device: {e}")))?;
    println!("application ready: exchanging data");
    ar.running = true;
    let watchdog = Duration::from_secs(1).max(ar.interval * 3);
    let started = Instant::now();
    let mut shown: Vec<String> = Vec::new();
    loop {
        let until = Instant::now() + ar.interval;
        // A late cycle can be followed by the next within one interval: stop at the count.
        let counted = |ar: &Ar| args.cycles.is_some_and(|n| ar.cycles >= n);
        link.pump(ar, until, |_, ar| counted(ar))?;
        if let Some((data, _)) = &ar.last {
            let lines = inputs(ar, subs, data);
            for (n, line) in lines.iter().enumerate() {
                if shown.get(n) != Some(line) {
                    println!("{line}");
                }
            }
            shown = lines;
        }
        let last = ar.last.as_ref().map_or(started, |(_, at)| *at);
        if last.elapsed() > watchdog + Duration::from_secs(2) {
            return Err(Stop::Device(format!(
                "lost: no input frame from the device for {} ms",
                last.elapsed().as_millis()
            )));
        }
        if counted(ar) || crate::cmd::signals::requested() {
            return Ok(());
        }
    }
}

/// The inputs of every submodule that has some, in words, a line each.
fn inputs(ar: &Ar, subs: &[SubmoduleData], c_sdu: &[u8]) -> Vec<String> {
    let mut parts = Vec::new();
    for sub in subs.iter().filter(|s| !s.inputs.is_empty()) {
        let Some(&(_, _, offset, len)) = ar
            .input
            .data
            .iter()
            .find(|d| (d.0, d.1) == (sub.slot, sub.subslot))
        else {
            continue;
        };
        let start = usize::from(offset);
        let data = c_sdu
            .get(start..start + usize::from(len))
            .unwrap_or_default();
        let values: Vec<String> = sub
            .inputs
            .iter()
            .map(|i| format!("{}={}", i.label, io_data::show(i, data)))
            .collect();
        let iops = c_sdu.get(start + usize::from(len)).copied().unwrap_or(0);
        let bad = if iops & GOOD == 0 { " (IOPS bad)" } else { "" };
        parts.push(format!(
            "inputs {}.{}{bad}: {}",
            sub.slot,
            sub.subslot,
            values.join(" ")
        ));
    }
    parts
}
