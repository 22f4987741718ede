//! `edsgen enip io ADDR --eds FILE [NAME=VALUE...]`: a class-1 connection opened as the ODVA
//! EDS's `[Connection Manager]` describes it (the first Exclusive Owner unless `--connection`
//! names another): Forward_Open (Large_Forward_Open when a size needs more than 9 bits) with its
//! O→T/T→O sizes, RPI, real-time formats and path; then the output assembly, its members at
//! their parameters' defaults or the `NAME=VALUE`s given (typed and range-checked, see
//! `cip_value`), sent every RPI with the 32-bit run/idle header saying run; each new T→O
//! datagram printed as one line `N: name=value, ...` until Ctrl-C or `--cycles N` (producing
//! for at least one RPI, so the device has the outputs); then Forward_Close. Exit 0 ok, 1 a refusal or a connection that stops producing, 2 bad usage or
//! I/O.
//!
//! T→O data is received on UDP 2222 of the local address when that port is free, else on a port
//! of the system's choosing, asked for with a T→O sockaddr info item in the Forward_Open (as
//! OpENer and the simulated adapter honour it). O→T data goes to UDP 2222 of the device, or where
//! its Forward_Open reply's O→T sockaddr item says.

use std::net::{IpAddr, SocketAddr, UdpSocket};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use edsgen_model::model::{path_bytes, Cip, CipAssembly, CipConnection, CipNumber, FieldRef};
use edsgen_runtime::enip::originator::Class1;
use edsgen_runtime::enip::wire::connection_manager::{
    network_params, ForwardCloseRepr, ForwardOpenReply, ForwardOpenRepr, Triad, DEFAULT_TICKS,
};
use edsgen_runtime::enip::wire::cpf::{item, Item, Sockaddr};

use super::cip_value::{self, Member, Typed};
use super::link::{Link, LinkError};
use crate::cmd::signals;

/// The class-1 UDP port.
const IO_PORT: u16 = 2222;
/// The timeout multiplier code: ×16 the RPI (generous for a loaded host).
const MULTIPLIER: u8 = 2;

/// `edsgen enip io`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The device (`IP` or `IP:PORT`, 44818 by default).
    pub addr: String,
    /// The device's ODVA EDS: its connection, assemblies and parameters.
    #[arg(long)]
    pub eds: PathBuf,
    /// Output members to set: `NAME=VALUE` (the parameter's name as the EDS writes it, any case,
    /// or with `_` for spaces; the value in its units, an enumeration text, or raw `0x` hex).
    pub values: Vec<String>,
    /// The connection: its name in `[Connection Manager]`, or N of `ConnectionN` (default: the
    /// first Exclusive Owner).
    #[arg(long)]
    pub connection: Option<String>,
    /// The RPI in milliseconds (default: the EDS's).
    #[arg(long, value_name = "MS")]
    pub rpi: Option<f64>,
    /// Stop after this many input lines (default: until Ctrl-C).
    #[arg(long, value_name = "N")]
    pub cycles: Option<u64>,
}

fn usage(message: String) -> ExitCode {
    eprintln!("error: {message}");
    ExitCode::from(2)
}

fn refusal(message: String) -> ExitCode {
    eprintln!("error: {message}");
    ExitCode::from(1)
}

/// A connection as the EDS describes it, resolved for a Forward_Open.
struct Plan<'a> {
    name: String,
    output: Option<(&'a CipAssembly, Vec<Member<'a>>)>,
    input: Option<(&'a CipAssembly, Vec<Member<'a>>)>,
    o_t_size: usize,
    t_o_size: usize,
    o_t_header: bool,
    t_o_header: bool,
    rpi_us: u32,
    o_t_params: u32,
    t_o_params: u32,
    large: bool,
    path: Vec<u8>,
}

/// Runs `edsgen enip io`.
pub fn run(args: Args) -> ExitCode {
    let shown = args.eds.display().to_string();
    let cip = match super::read_cip(&args.eds) {
        Ok(cip) => cip,
        Err(m) => return usage(m),
    };
    let cip = &cip;
    let plan = match plan(cip, &shown, &args) {
        Ok(p) => p,
        Err(m) => return usage(m),
    };
    let output = match output_image(cip, &plan, &args.values) {
        Ok(image) => image,
        Err(m) => return usage(m),
    };
    let target = match super::address(&args.addr) {
        Ok(a) => a,
        Err(m) => return usage(m),
    };
    if let Err(m) = signals::install() {
        return usage(m);
    }
    match exchange(cip, &plan, &output, target, args.cycles) {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Usage(m)) => usage(m),
        Err(Failure::Refused(m)) => refusal(m),
    }
}

fn connection<'a>(
    cip: &'a Cip,
    file: &str,
    wanted: Option<&str>,
) -> Result<&'a CipConnection, String> {
    if cip.connections.is_empty() {
        return Err(format!(
            "`{file}` has no connection in [Connection Manager]"
        ));
    }
    let names = || {
        cip.connections
            .values()
            .map(|c| format!("Connection{} `{}`", c.number, c.name))
            .collect::<Vec<_>>()
            .join(", ")
    };
    match wanted {
        Some(w) => {
            let by_number = w.parse::<u32>().ok().and_then(|n| cip.connections.get(&n));
            by_number
                .or_else(|| {
                    cip.connections
                        .values()
                        .find(|c| c.name.trim().eq_ignore_ascii_case(w.trim()))
                })
                .ok_or_else(|| format!("`{file}` has no connection `{w}`: it has {}", names()))
        }
        None => cip
            .connections
            .values()
            .find(|c| {
                c.trigger_transport.as_ref().is_some_and(|t| {
                    t.value.application_types().contains(&"exclusive-owner")
                        && t.value.classes().contains(&1)
                })
            })
            .ok_or_else(|| {
                format!(
                    "`{file}` has no class-1 Exclusive Owner connection: name one with \
                     --connection ({})",
                    names()
                )
            }),
    }
}

fn param_default(cip: &Cip, n: u32) -> Option<u64> {
    match cip.params.get(&n)?.default.as_ref()?.value {
        CipNumber::Int(v) => u64::try_from(v).ok(),
        CipNumber::Real(_) => None,
    }
}

fn plan<'a>(cip: &'a Cip, file: &str, args: &Args) -> Result<Plan<'a>, String> {
    let c = connection(cip, file, args.connection.as_deref())?;
    let label = format!("Connection{} `{}`", c.number, c.name);
    let tt = c.trigger_transport.as_ref().map(|t| t.value);
    if !tt.is_some_and(|t| t.classes().contains(&1)) {
        return Err(format!("{label} is not a class-1 connection"));
    }
    let params = c
        .params
        .as_ref()
        .map(|p| p.value)
        .ok_or_else(|| format!("{label} has no connection parameters word"))?;
    let assembly = |r: &FieldRef| match r {
        FieldRef::Assem(n) => cip
            .assemblies
            .get(n)
            .map(|a| (a, cip_value::members(cip, a))),
        _ => None,
    };
    // Sized as the simulated adapter sizes it (one model function).
    let size = |d: &edsgen_model::model::ConnectionData| cip.connection_size(d).unwrap_or(0);
    let (o_t_size, t_o_size) = (size(&c.o_t), size(&c.t_o));
    let header = |format: u8, direction: &str| match format {
        0 | 1 => Ok(false),
        4 => Ok(true),
        other => Err(format!(
            "{label}: the {direction} real-time format `{}` is not one `enip io` sends",
            edsgen_model::model::real_time_format_name(other)
        )),
    };
    let o_t_header = header(params.o_t_format(), "O→T")?;
    let t_o_header = header(params.t_o_format(), "T→O")?;
    let rpi_us = match args.rpi {
        Some(ms) if ms.is_finite() && ms > 0.0 && ms * 1000.0 <= f64::from(u32::MAX) => {
            (ms * 1000.0).round() as u32
        }
        Some(ms) => return Err(format!("--rpi {ms}: not a time in milliseconds")),
        None => match &c.o_t.rpi.value {
            FieldRef::Number(n) => u32::try_from(*n).unwrap_or(0),
            FieldRef::Param(n) => param_default(cip, *n)
                .and_then(|v| u32::try_from(v).ok())
                .unwrap_or(0),
            _ => 0,
        },
    };
    if rpi_us == 0 {
        return Err(format!("{label} gives no RPI: give one with --rpi MS"));
    }
    if let (Some(_), FieldRef::Param(n)) = (args.rpi, &c.o_t.rpi.value) {
        if let Some(p) = cip.params.get(n) {
            let v = f64::from(rpi_us);
            let low = p.min.as_ref().map(|m| m.value.as_f64());
            let high = p.max.as_ref().map(|m| m.value.as_f64());
            if low.is_some_and(|l| v < l) || high.is_some_and(|h| v > h) {
                return Err(format!(
                    "--rpi: {rpi_us} µs is outside {}..{} µs (Param{n} `{}`)",
                    low.unwrap_or(0.0),
                    high.unwrap_or(f64::INFINITY),
                    p.name
                ));
            }
        }
    }
    let path: Vec<u8> = c
        .path
        .as_ref()
        .and_then(|p| path_bytes(&p.value).ok())
        .filter(|p: &Vec<u8>| !p.is_empty() && p.len().is_multiple_of(2))
        .ok_or_else(|| format!("{label}: its path is not plain hex bytes of whole words"))?;
    // Class 1: the 16-bit sequence count both ways, the run/idle header where the format says.
    let o_t_wire = o_t_size + 2 + if o_t_header { 4 } else { 0 };
    let t_o_wire = t_o_size + 2 + if t_o_header { 4 } else { 0 };
    if o_t_wire > 0xFFFF || t_o_wire > 0xFFFF {
        return Err(format!("{label}: a size above 65535 bytes"));
    }
    let large = o_t_wire > 0x01FF || t_o_wire > 0x01FF;
    // Point-to-point both ways (T→O multicast would need a group to join); the highest
    // priority the file allows; fixed sizes where it allows them.
    let priority = |list: Vec<&str>| {
        if list.contains(&"scheduled") {
            2
        } else if list.contains(&"high") {
            1
        } else {
            0
        }
    };
    if !params.t_o_types().is_empty() && !params.t_o_types().contains(&"point-to-point") {
        return Err(format!(
            "{label}: T→O is multicast only, which `enip io` does not join"
        ));
    }
    let o_t_params = network_params(
        large,
        2,
        priority(params.o_t_priorities()),
        !params.o_t_fixed() && params.o_t_variable(),
        o_t_wire as u16,
    );
    let t_o_params = network_params(
        large,
        2,
        priority(params.t_o_priorities()),
        !params.t_o_fixed() && params.t_o_variable(),
        t_o_wire as u16,
    );
    Ok(Plan {
        name: label,
        output: assembly(&c.o_t.format.value),
        input: assembly(&c.t_o.format.value),
        o_t_size: o_t_size as usize,
        t_o_size: t_o_size as usize,
        o_t_header,
        t_o_header,
        rpi_us,
        o_t_params,
        t_o_params,
        large,
        path,
    })
}

/// The O→T image: defaults, then the `NAME=VALUE`s.
fn output_image(cip: &Cip, plan: &Plan<'_>, values: &[String]) -> Result<Vec<u8>, String> {
    let empty = Vec::new();
    let members = plan.output.as_ref().map_or(&empty, |(_, m)| m);
    let mut image = cip_value::defaults(cip, members, plan.o_t_size);
    for pair in values {
        let Some((name, value)) = pair.split_once('=') else {
            return Err(format!("`{pair}` is not NAME=VALUE"));
        };
        let wanted = cip_value::fold(name);
        let Some(member) = members.iter().find(|m| m.is_named(&wanted)) else {
            let input = plan
                .input
                .as_ref()
                .is_some_and(|(_, m)| m.iter().any(|m| m.is_named(&wanted)));
            if input {
                return Err(format!(
                    "`{name}` is an input (T→O) of {}, not an output",
                    plan.name
                ));
            }
            return Err(format!(
                "`{name}` is no output member of {}{}",
                plan.name,
                suggestions(&wanted, members)
            ));
        };
        let raw = Typed::member(cip, member)
            .parse(value)
            .map_err(|m| format!("`{}={}`: {m}", member.name, value.trim()))?;
        cip_value::put_bits(&mut image, member.bit, member.bits, raw);
    }
    Ok(image)
}

/// `; did you mean ...?` with the five output names closest to `wanted` (ties by name).
fn suggestions(wanted: &str, members: &[Member<'_>]) -> String {
    if members.is_empty() {
        return ": it has no output assembly members".to_owned();
    }
    let mut names: Vec<&str> = members.iter().map(|m| m.name.as_str()).collect();
    names.sort();
    let keyed = names.into_iter().map(|n| (cip_value::fold(n), n));
    let names: Vec<String> = crate::cmd::did_you_mean::closest(wanted, keyed, false)
        .into_iter()
        .take(5)
        .map(|n| format!("`{n}`"))
        .collect();
    format!("; did you mean {}?", names.join(", "))
}

enum Failure {
    Usage(String),
    Refused(String),
}

impl From<LinkError> for Failure {
    fn from(error: LinkError) -> Failure {
        match error {
            LinkError::Io(m) => Failure::Usage(m),
            LinkError::Refused(m) => Failure::Refused(m),
        }
    }
}

/// Opens the connection, exchanges data, closes it.
fn exchange(
    cip: &Cip,
    plan: &Plan<'_>,
    output: &[u8],
    target: SocketAddr,
    cycles: Option<u64>,
) -> Result<(), Failure> {
    let mut link = Link::open(target)?;
    let local = link.local()?.ip();
    let io = |e: std::io::Error| Failure::Usage(e.to_string());
    let udp = UdpSocket::bind(SocketAddr::new(local, IO_PORT))
        .or_else(|_| UdpSocket::bind(SocketAddr::new(local, 0)))
        .map_err(|e| Failure::Usage(format!("cannot open a UDP socket on {local}: {e}")))?;
    let t_o_port = udp.local_addr().map_err(io)?.port();
    let pid = std::process::id();
    let open = ForwardOpenRepr {
        large: plan.large,
        ticks: DEFAULT_TICKS,
        o_t_id: 0,
        t_o_id: 0x4544_0000 | (pid & 0xFFFF),
        triad: Triad {
            serial: (pid as u16) ^ 0x5A5A,
            vendor: 0,
            originator_serial: pid,
        },
        multiplier: MULTIPLIER,
        o_t_rpi: plan.rpi_us,
        o_t_params: plan.o_t_params,
        t_o_rpi: plan.rpi_us,
        t_o_params: plan.t_o_params,
        transport: 0x01,
        path: &plan.path,
    };
    let sockaddr = Sockaddr {
        port: t_o_port,
        address: [0; 4],
    }
    .to_bytes();
    let extra: &[Item<'_>] = if t_o_port == IO_PORT {
        &[]
    } else {
        &[Item::new(item::SOCKADDR_T_O, &sockaddr)]
    };
    let service = if plan.large {
        "Large_Forward_Open"
    } else {
        "Forward_Open"
    };
    let reply = link.request(&open, extra)?;
    if let Some(text) = reply.refusal(&format!("{service} of {}", plan.name)) {
        return Err(Failure::Refused(text));
    }
    let opened = ForwardOpenReply::parse(&reply.data)
        .map_err(|_| Failure::Usage(format!("a short {service} reply")))?;
    let o_t_to = reply
        .o_t_sockaddr
        .map(|s| {
            let ip = if s.address == [0; 4] {
                target.ip()
            } else {
                IpAddr::from(s.address)
            };
            SocketAddr::new(ip, s.port)
        })
        .unwrap_or(SocketAddr::new(target.ip(), IO_PORT));
    let connection = Class1::new(opened.o_t_id, open.t_o_id, plan.o_t_header, plan.t_o_header);
    let result = run_io(
        cip,
        plan,
        output,
        &udp,
        o_t_to,
        connection,
        (opened.o_t_api.max(1000), opened.t_o_api.max(1000)),
        cycles,
    );
    let close = ForwardCloseRepr {
        ticks: DEFAULT_TICKS,
        triad: open.triad,
        path: &plan.path,
    };
    let closed = link.request(&close, &[]);
    link.close();
    result?;
    match closed?.refusal("Forward_Close") {
        Some(text) => Err(Failure::Refused(text)),
        None => Ok(()),
    }
}

/// The class-1 exchange: O→T every RPI, a line per new T→O datagram.
#[allow(clippy::too_many_arguments)]
fn run_io(
    cip: &Cip,
    plan: &Plan<'_>,
    output: &[u8],
    udp: &UdpSocket,
    o_t_to: SocketAddr,
    mut connection: Class1,
    (o_t_api, t_o_api): (u32, u32),
    cycles: Option<u64>,
) -> Result<(), Failure> {
    let rpi = Duration::from_micros(u64::from(o_t_api));
    let timeout = Duration::from_micros(u64::from(t_o_api) * (4 << MULTIPLIER));
    let started = Instant::now();
    let mut next_send = started;
    let mut last_heard = started;
    let mut printed = 0u64;
    let mut buf = [0u8; 65_536];
    let mut datagram = vec![0u8; 18 + 6 + output.len()];
    let empty = Vec::new();
    let inputs = plan.input.as_ref().map_or(&empty, |(_, m)| m);
    let wanted = cycles.unwrap_or(u64::MAX);
    // After the last line, produce on until one RPI has passed since the first O→T datagram:
    // the device has had the outputs before the Forward_Close.
    while (printed < wanted || Instant::now() < started + rpi) && !signals::requested() {
        let now = Instant::now();
        if now >= next_send {
            let len = connection
                .produce(true, output, &mut datagram)
                .map_err(|e| Failure::Usage(format!("an O→T datagram: {e:?}")))?;
            udp.send_to(&datagram[..len], o_t_to)
                .map_err(|e| Failure::Usage(format!("cannot send to {o_t_to}: {e}")))?;
            next_send += rpi;
            if next_send < now {
                next_send = now + rpi;
            }
        }
        if now.duration_since(last_heard) > timeout {
            return Err(Failure::Refused(format!(
                "no T→O data for {} ms: the connection timed out",
                timeout.as_millis()
            )));
        }
        let wait = next_send
            .saturating_duration_since(Instant::now())
            .max(Duration::from_millis(1));
        // poll(2), not the socket's read timeout: that one counts in scheduler ticks and would
        // stretch every RPI shorter than a few ticks.
        if !edsgen_host::wait::readable(&udp, wait.min(Duration::from_millis(20))).unwrap_or(false)
        {
            continue;
        }
        let Ok((n, _)) = udp.recv_from(&mut buf) else {
            continue;
        };
        if printed == wanted {
            continue;
        }
        let Some(image) = connection.consume(&buf[..n]) else {
            continue;
        };
        last_heard = Instant::now();
        printed += 1;
        let values: Vec<String> = inputs
            .iter()
            .map(|m| format!("{}={}", m.name, cip_value::show(cip, m, image)))
            .collect();
        let line = if values.is_empty() {
            format!("{printed}: {} bytes", image.len().min(plan.t_o_size))
        } else {
            format!("{printed}: {}", values.join(", "))
        };
        crate::cmd::print_stdout(&format!("{line}\n"));
    }
    Ok(())
}
