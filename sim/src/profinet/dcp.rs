//! The device's DCP machine (IEC 61158-6-10 DCP; p-net's `pf_dcp`): it answers Identify (all, or
//! filtered by name of station, alias, type, IDs, role, instance, IP), Get, Set (name of station,
//! IP parameter, signal, start/end transaction, reset to factory), and builds Hello requests.
//! Sans-IO: a frame in, a frame (or nothing) out, and events for what a Set changed. Frames of
//! another FrameID, service or destination, and malformed ones, get no answer (the standard's
//! answer to what a device does not understand); no frame panics it.
//!
//! An Identify sent to the multicast address is answered after the device's own share of the
//! request's ResponseDelayFactor ([`Dcp::response_delay`]: the factor's 10 ms steps, one chosen
//! by the MAC address, as the standard asks so that many devices do not answer at once); the
//! device ([`super::device::Device`]) holds the answer that long. Unicast requests are
//! answered at once.

use super::wire::dcp::*;
use super::wire::{append, Ethernet, Mac, ETHERTYPE_PROFINET};

/// What the device says about itself over DCP.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Station {
    /// The interface's MAC address.
    pub mac: Mac,
    /// Name of station (empty until one is set).
    pub name_of_station: String,
    /// IP address, subnet mask and gateway.
    pub ip: [[u8; 4]; 3],
    /// VendorID (the GSDML's).
    pub vendor_id: u16,
    /// DeviceID (the GSDML's).
    pub device_id: u16,
    /// Type of station (the GSDML's vendor and product family).
    pub type_of_station: String,
    /// Device instance (high, low): the access point's `ObjectUUID_LocalIndex`.
    pub instance: (u8, u8),
}

/// What a Set changed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum DcpEvent {
    /// The name of station was set (possibly to empty).
    NameSet(String),
    /// The IP parameter was set.
    IpSet([[u8; 4]; 3]),
    /// The controller asked the device to flash its LED.
    Signal,
    /// Reset to factory: name and IP cleared.
    ResetToFactory,
}

/// The DCP machine of one interface.
#[derive(Debug, Clone)]
pub struct Dcp {
    station: Station,
    events: Vec<DcpEvent>,
    hello_xid: u32,
}

/// The options the device answers to, as its DeviceOptions block lists them.
const OPTIONS: [(u8, u8); 10] = [
    MAC_ADDRESS,
    IP_PARAMETER,
    TYPE_OF_STATION,
    NAME_OF_STATION,
    DEVICE_ID,
    DEVICE_ROLE,
    DEVICE_OPTIONS,
    DEVICE_INSTANCE,
    CONTROL_SIGNAL,
    CONTROL_RESET_TO_FACTORY,
];

impl Dcp {
    /// A DCP machine for `station`.
    pub fn new(station: Station) -> Self {
        Dcp {
            station,
            events: Vec::new(),
            hello_xid: 0,
        }
    }

    /// What the device says about itself now.
    pub fn station(&self) -> &Station {
        &self.station
    }

    /// The next event a Set caused, oldest first.
    pub fn poll_event(&mut self) -> Option<DcpEvent> {
        (!self.events.is_empty()).then(|| self.events.remove(0))
    }

    /// Handles one received Ethernet frame; the answer to send, if any.
    pub fn handle(&mut self, frame: &[u8]) -> Option<Vec<u8>> {
        let eth = Ethernet::parse(frame)?;
        if eth.ethertype != ETHERTYPE_PROFINET {
            return None;
        }
        let (header, blocks) = DcpHeader::parse(frame.get(eth.payload..)?)?;
        if header.service_type != TYPE_REQUEST {
            return None;
        }
        let to_me = eth.dst == self.station.mac;
        match (header.frame_id, header.service_id) {
            (FRAME_IDENTIFY_REQUEST, SERVICE_IDENTIFY)
                if to_me || eth.dst == MULTICAST_IDENTIFY =>
            {
                self.identify(eth.src, &header, blocks)
            }
            (FRAME_GET_SET, SERVICE_GET) if to_me => Some(self.get(eth.src, &header, blocks)),
            (FRAME_GET_SET, SERVICE_SET) if to_me => self.set(eth.src, &header, blocks),
            (FRAME_GET_SET, _) if to_me => {
                // A service the device does not know: "request not supported".
                let mut out = Vec::new();
                let start = self.response_head(eth.src, FRAME_GET_SET, &header, &mut out);
                out[start + 3] = TYPE_NOT_SUPPORTED;
                finish(&mut out, start);
                Some(out)
            }
            _ => None,
        }
    }

    /// How long the answer to `frame` waits: for an Identify to the multicast address with a
    /// ResponseDelayFactor F over 1, a step of 0 to F-1 times 10 ms chosen by the device's MAC
    /// address (FNV-1a of its six bytes, so that devices of one interface spread out and each
    /// always takes the same step); zero for anything else.
    pub fn response_delay(&self, frame: &[u8]) -> edsgen_runtime::Duration {
        let factor = Ethernet::parse(frame)
            .filter(|eth| eth.dst == MULTICAST_IDENTIFY && eth.ethertype == ETHERTYPE_PROFINET)
            .and_then(|eth| DcpHeader::parse(frame.get(eth.payload..)?))
            .filter(|(h, _)| h.frame_id == FRAME_IDENTIFY_REQUEST)
            .map_or(0, |(h, _)| h.response_delay);
        if factor <= 1 {
            return edsgen_runtime::Duration::from_millis(0);
        }
        let hash = self.station.mac.iter().fold(0x811c_9dc5u32, |h, b| {
            (h ^ u32::from(*b)).wrapping_mul(0x0100_0193)
        });
        edsgen_runtime::Duration::from_millis(u64::from(hash % u32::from(factor)) * 10)
    }

    /// A Hello request announcing the device (to 01:0e:cf:00:00:01).
    pub fn hello(&mut self) -> Vec<u8> {
        self.hello_xid = self.hello_xid.wrapping_add(1);
        let mut out = Vec::new();
        append(&mut out, |b| {
            Ethernet::emit(MULTICAST_HELLO, self.station.mac, b)
        });
        let start = out.len();
        let header = DcpHeader {
            frame_id: FRAME_HELLO,
            service_id: SERVICE_HELLO,
            service_type: TYPE_REQUEST,
            xid: self.hello_xid,
            response_delay: 0,
            length: 0,
        };
        append(&mut out, |b| header.emit(b));
        for option in [
            NAME_OF_STATION,
            IP_PARAMETER,
            DEVICE_ID,
            DEVICE_OPTIONS,
            DEVICE_ROLE,
            DEVICE_INSTANCE,
        ] {
            self.emit_option(option, &mut out);
        }
        finish(&mut out, start);
        out
    }

    /// The Ethernet and DCP header of a response to `header`; the PDU's start.
    fn response_head(
        &self,
        to: Mac,
        frame_id: u16,
        header: &DcpHeader,
        out: &mut Vec<u8>,
    ) -> usize {
        append(out, |b| Ethernet::emit(to, self.station.mac, b));
        let start = out.len();
        let response = DcpHeader {
            frame_id,
            service_id: header.service_id,
            service_type: TYPE_RESPONSE,
            xid: header.xid,
            response_delay: 0,
            length: 0,
        };
        append(out, |b| response.emit(b));
        start
    }

    fn identify(&mut self, from: Mac, header: &DcpHeader, blocks: &[u8]) -> Option<Vec<u8>> {
        let mut any = false;
        for block in super::wire::dcp::blocks(blocks) {
            let block = block.ok()?;
            if !self.matches(&block) {
                return None;
            }
            any = true;
        }
        if !any {
            return None;
        }
        let mut out = Vec::new();
        let start = self.response_head(from, FRAME_IDENTIFY_RESPONSE, header, &mut out);
        for option in [
            DEVICE_OPTIONS,
            TYPE_OF_STATION,
            NAME_OF_STATION,
            DEVICE_ID,
            DEVICE_ROLE,
            DEVICE_INSTANCE,
            IP_PARAMETER,
        ] {
            self.emit_option(option, &mut out);
        }
        finish(&mut out, start);
        Some(out)
    }

    /// Whether an Identify filter block selects this device.
    fn matches(&self, block: &Block) -> bool {
        let s = &self.station;
        match block.option {
            ALL_SELECTOR => true,
            NAME_OF_STATION => block.data == s.name_of_station.as_bytes(),
            TYPE_OF_STATION => block.data == s.type_of_station.as_bytes(),
            ALIAS_NAME => block.data == format!("port-001.{}", s.name_of_station).as_bytes(),
            DEVICE_ID => block.data == self.value(DEVICE_ID),
            DEVICE_ROLE => block.data.first() == Some(&1),
            DEVICE_INSTANCE => block.data == [s.instance.0, s.instance.1],
            IP_PARAMETER => block.data.get(..4) == Some(&s.ip[0][..]),
            _ => false,
        }
    }

    /// An option's data as a response carries it (after the BlockInfo).
    fn value(&self, option: (u8, u8)) -> Vec<u8> {
        let s = &self.station;
        match option {
            MAC_ADDRESS => s.mac.to_vec(),
            IP_PARAMETER => s.ip.concat(),
            TYPE_OF_STATION => s.type_of_station.as_bytes().to_vec(),
            NAME_OF_STATION => s.name_of_station.as_bytes().to_vec(),
            DEVICE_ID => [s.vendor_id.to_be_bytes(), s.device_id.to_be_bytes()].concat(),
            // IO device, and a reserved byte.
            DEVICE_ROLE => vec![0x01, 0x00],
            DEVICE_OPTIONS => OPTIONS.iter().flat_map(|(o, so)| [*o, *so]).collect(),
            DEVICE_INSTANCE => vec![s.instance.0, s.instance.1],
            _ => Vec::new(),
        }
    }

    fn emit_option(&self, option: (u8, u8), out: &mut Vec<u8>) {
        // BlockInfo of the IP parameter: bit 0 "IP set".
        let info = u16::from(option == IP_PARAMETER && self.station.ip[0] != [0; 4]);
        let value = self.value(option);
        append(out, |b| emit_block(b, option, info, &value));
    }

    fn get(&self, from: Mac, header: &DcpHeader, data: &[u8]) -> Vec<u8> {
        let mut out = Vec::new();
        let start = self.response_head(from, FRAME_GET_SET, header, &mut out);
        for option in get_options(data) {
            if OPTIONS.contains(&option) && option.0 != 5 {
                self.emit_option(option, &mut out);
            } else {
                let error = if matches!(option.0, 1 | 2 | 5) {
                    ERROR_SUBOPTION
                } else {
                    ERROR_OPTION
                };
                append(&mut out, |b| emit_set_response(b, option, error));
            }
        }
        finish(&mut out, start);
        out
    }

    fn set(&mut self, from: Mac, header: &DcpHeader, data: &[u8]) -> Option<Vec<u8>> {
        let requests: Vec<Block> = super::wire::dcp::blocks(data)
            .collect::<Result<_, TruncatedBlock>>()
            .ok()?;
        let mut out = Vec::new();
        let start = self.response_head(from, FRAME_GET_SET, header, &mut out);
        for block in requests {
            let error = self.set_one(&block);
            append(&mut out, |b| emit_set_response(b, block.option, error));
        }
        finish(&mut out, start);
        Some(out)
    }

    /// Applies one Set block (BlockQualifier, then the value); its BlockError.
    fn set_one(&mut self, block: &Block) -> u8 {
        let Some(value) = block.data.get(2..) else {
            return ERROR_LOCAL;
        };
        match block.option {
            NAME_OF_STATION => match std::str::from_utf8(value) {
                Ok(name) if valid_name(name) => {
                    self.station.name_of_station = name.to_owned();
                    self.events.push(DcpEvent::NameSet(name.to_owned()));
                    ERROR_NONE
                }
                // A name the PROFINET name rules refuse: "not set", as p-net answers.
                _ => ERROR_NOT_SET,
            },
            IP_PARAMETER => match value.get(..12) {
                Some(v) if value.len() == 12 => {
                    let ip = [0, 4, 8].map(|i| [v[i], v[i + 1], v[i + 2], v[i + 3]]);
                    self.station.ip = ip;
                    self.events.push(DcpEvent::IpSet(ip));
                    ERROR_NONE
                }
                _ => ERROR_LOCAL,
            },
            CONTROL_SIGNAL => {
                self.events.push(DcpEvent::Signal);
                ERROR_NONE
            }
            CONTROL_START | CONTROL_END => ERROR_NONE,
            CONTROL_RESET_TO_FACTORY | CONTROL_FACTORY_RESET => {
                self.station.name_of_station.clear();
                self.station.ip = [[0; 4]; 3];
                self.events.push(DcpEvent::ResetToFactory);
                ERROR_NONE
            }
            (1 | 2 | 5, _) => ERROR_SUBOPTION,
            _ => ERROR_OPTION,
        }
    }
}

#[cfg(test)]
mod tests;
