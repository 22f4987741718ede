//! The subcommands that run on a bus, one module each (`bus`, `sdo`, `nmt`, `scan`, `check`),
//! and what the master's commands share: how they reach the bus, parse node-IDs and addresses,
//! and read values as an EDS types them.

pub mod bus;
pub mod check;
pub mod nmt;
pub mod scan;
pub mod sdo;
pub mod value;

use std::process::ExitCode;
use std::time::Duration;

use clap::Args;
use edsgen_runtime::master::blocking::Master;
use edsgen_runtime::transport::socketcand::SocketcandClient;
use edsgen_runtime::transport::Transport;
use edsgen_runtime::wire::sdo::Multiplexer;

/// Exit code for usage and I/O problems.
pub const EXIT_USAGE: u8 = 2;

/// How to reach the bus.
#[derive(Args, Debug, Clone)]
pub struct BusArgs {
    /// A socketcand server (`edsgen bus`, socketcand on a Linux box) as HOST:PORT.
    #[arg(long, value_name = "HOST:PORT")]
    pub bus: Option<String>,
    /// A Linux SocketCAN interface (can0, vcan0).
    #[cfg(feature = "socketcan")]
    #[arg(long, value_name = "IFACE", conflicts_with = "bus")]
    pub socketcan: Option<String>,
    /// The CAN channel to open on the socketcand server.
    #[arg(long, default_value = "can0")]
    pub channel: String,
    /// How long to wait for each SDO answer, in milliseconds.
    #[arg(long, value_name = "MS", default_value_t = 1000)]
    pub timeout: u64,
}

impl BusArgs {
    /// A master on the bus, or the reason there is none.
    pub fn connect(&self) -> Result<Master<Box<dyn Transport + Send>>, String> {
        let transport: Box<dyn Transport + Send> = match self.target()? {
            Target::Socketcand(addr) => Box::new(
                SocketcandClient::connect(addr, &self.channel, Duration::from_secs(5))
                    .map_err(|e| format!("cannot reach the bus at {addr}: {e}"))?,
            ),
            #[cfg(feature = "socketcan")]
            Target::SocketCan(iface) => Box::new(
                edsgen_runtime::transport::socketcan::SocketCan::open(iface)
                    .map_err(|e| format!("cannot open {iface}: {e}"))?,
            ),
        };
        let mut master = Master::new(transport);
        master.set_default_timeout(Duration::from_millis(self.timeout));
        Ok(master)
    }
}

/// Where the bus is.
enum Target<'a> {
    Socketcand(&'a str),
    #[cfg(feature = "socketcan")]
    SocketCan(&'a str),
}

impl BusArgs {
    fn target(&self) -> Result<Target<'_>, String> {
        #[cfg(feature = "socketcan")]
        if let Some(iface) = &self.socketcan {
            return Ok(Target::SocketCan(iface));
        }
        match &self.bus {
            Some(addr) => Ok(Target::Socketcand(addr)),
            None if cfg!(feature = "socketcan") => {
                Err("give the bus: --bus HOST:PORT or --socketcan IFACE".into())
            }
            None => Err("give the bus: --bus HOST:PORT".into()),
        }
    }
}

/// A usage or I/O problem: the message on standard error, exit 2.
pub fn usage_error(message: impl std::fmt::Display) -> ExitCode {
    eprintln!("error: {message}");
    ExitCode::from(EXIT_USAGE)
}

/// A node-ID, decimal or `0x` hex, 1..=127.
pub fn parse_node_id(text: &str) -> Result<u8, String> {
    let value = parse_number(text).ok_or_else(|| format!("`{text}` is not a node-ID"))?;
    match u8::try_from(value) {
        Ok(id @ 1..=127) => Ok(id),
        _ => Err(format!("node-ID {text} is not 1..=127")),
    }
}

/// `INDEX:SUB`, both hexadecimal (`6041:0`, `0x1018:0x02`, `1018h:2`).
pub fn parse_address(text: &str) -> Result<Multiplexer, String> {
    let bad = || format!("`{text}` is not INDEX:SUB in hex (such as 6041:0)");
    let (index, sub) = text.split_once(':').ok_or_else(bad)?;
    let hex = |part: &str| {
        let part = part.trim();
        let part = part
            .strip_prefix("0x")
            .or_else(|| part.strip_prefix("0X"))
            .unwrap_or(part);
        let part = part.strip_suffix(['h', 'H']).unwrap_or(part);
        u32::from_str_radix(part, 16).ok()
    };
    let index = hex(index)
        .and_then(|i| u16::try_from(i).ok())
        .ok_or_else(bad)?;
    let sub = hex(sub)
        .and_then(|s| u8::try_from(s).ok())
        .ok_or_else(bad)?;
    Ok(Multiplexer::new(index, sub))
}

/// A decimal or `0x` hex number.
fn parse_number(text: &str) -> Option<u64> {
    match text.strip_prefix("0x").or_else(|| text.strip_prefix("0X")) {
        Some(hex) => u64::from_str_radix(hex, 16).ok(),
        None => text.parse().ok(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn addresses_and_node_ids_parse_in_the_usual_spellings() {
        assert_eq!(parse_address("6041:0"), Ok(Multiplexer::new(0x6041, 0)));
        assert_eq!(
            parse_address("0x1018:0x02"),
            Ok(Multiplexer::new(0x1018, 2))
        );
        assert_eq!(parse_address("1018h:1"), Ok(Multiplexer::new(0x1018, 1)));
        assert!(parse_address("6041").is_err());
        assert!(parse_address("10000:0").is_err());
        assert_eq!(parse_node_id("5"), Ok(5));
        assert_eq!(parse_node_id("0x7F"), Ok(127));
        assert!(parse_node_id("0").is_err());
        assert!(parse_node_id("128").is_err());
    }
}
