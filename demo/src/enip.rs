//! The Goodrive350's EtherNet/IP card in the demo: a scanner built from the card's generated
//! images (`cards::goodrive350_enip`, typed through `edsgen_runtime::pkw_pzd`) drives the
//! simulated adapter: RegisterSession and ListIdentity, Forward_Open 150 → 100 at 50 ms,
//! class-1 datagrams every RPI, the manual's steps through PKW and PZD (5.4.3), then a scanner
//! that stops producing and the timeout fault E-EIP. Every datagram is what a scanner would put
//! on UDP 2222. Two links carry them ([`Scanner`]): by default the adapter's protocol core
//! (`edsgen_sim::enip`) in this process, in simulated time ([`InProcess`]); with `--enip`,
//! TCP 44818 and UDP 2222 to `edsgen simulate --enip` in another network namespace, in real
//! time ([`super::enip_wire`]).

use edsgen_runtime::enip::originator::{Class1, Session};
use edsgen_runtime::enip::wire::connection_manager::{
    network_params, ForwardOpenRepr, Triad, DEFAULT_TICKS,
};
use edsgen_runtime::enip::wire::cpf::item;
use edsgen_runtime::enip::wire::message::RequestRepr;
use edsgen_runtime::enip::wire::Emit;
use edsgen_runtime::pkw_pzd::{
    Command, ControlWord, ErrorNumber, InputImage, OutputImage, PkwRequest, PkwResponse, RunState,
    WordLayout,
};
use edsgen_runtime::{Duration, Instant};
use edsgen_sim::drives::pkw_pzd::PkwPzdDrive;
use edsgen_sim::enip::{device, Adapter, Peer};

use super::Trace;
use edsgen_sim::cards::goodrive350_enip as card;

/// The connection's RPI (µs): the EDS's 50 ms.
pub(super) const RPI_US: u64 = 50_000;

/// What carries the scanner's messages to the card's adapter.
pub(super) trait Scanner {
    /// One encapsulation message to the adapter (TCP 44818 on a wire); its reply.
    fn request(&mut self, message: &[u8]) -> Result<Vec<u8>, String>;
    /// One RPI: the O→T datagram at its start, then the T→O assembly's image (the card's 32
    /// bytes) as the scanner has it at its end.
    fn rpi(&mut self, datagram: &[u8]) -> Result<Vec<u8>, String>;
    /// `rpis` RPIs in which the scanner produces nothing.
    fn stop_producing(&mut self, rpis: u32) -> Result<Stopped, String>;
}

/// What the scanner sees after it stopped producing.
pub(super) struct Stopped {
    /// Whether the adapter closed the connection (in this process: it has none left; on a
    /// wire: no T→O datagram came in the last two RPIs).
    pub(super) closed: bool,
    /// The T→O assembly's image, where this process has it (on a wire the workflow reads it by
    /// Get_Attribute_Single @4/100/3).
    pub(super) image: Option<Vec<u8>>,
    /// The adapter's connection events, where this process sees them.
    pub(super) log: Option<Vec<String>>,
    /// How the connection was seen closed.
    pub(super) seen: String,
}

/// The adapter's protocol core and the card in this process, in simulated time.
struct InProcess {
    adapter: Adapter<PkwPzdDrive>,
    now: Instant,
    log: Vec<String>,
}

impl InProcess {
    fn step_time(&mut self, by: Duration) {
        self.now = self.now + by;
        // The T→O datagrams are not needed: the card's image is read from assembly 100.
        self.adapter.handle_timeout(self.now);
        while self.adapter.poll_transmit(self.now).is_some() {}
        while let Some(event) = self.adapter.poll_event() {
            self.log.extend(event.log_line());
        }
    }

    fn input(&self) -> Result<Vec<u8>, String> {
        Ok(self
            .adapter
            .device
            .assemblies
            .get(&card::Input::INSTANCE)
            .ok_or("no assembly 100")?
            .data
            .clone())
    }
}

impl Scanner for InProcess {
    fn request(&mut self, message: &[u8]) -> Result<Vec<u8>, String> {
        self.adapter
            .handle(self.now, Peer::Tcp(1), message)
            .map_err(|e| format!("{e:?}"))?;
        let reply = self.adapter.poll_transmit(self.now);
        reply
            .map(|(_, bytes)| bytes)
            .ok_or_else(|| "no reply".to_owned())
    }

    fn rpi(&mut self, datagram: &[u8]) -> Result<Vec<u8>, String> {
        // The datagram's image is exchanged with the drive at the end of the RPI, when the
        // scanner reads the card's image back.
        self.step_time(Duration::from_micros(RPI_US));
        let _ = self.adapter.handle(self.now, Peer::Io(1), datagram);
        self.input()
    }

    fn stop_producing(&mut self, rpis: u32) -> Result<Stopped, String> {
        for _ in 0..rpis {
            self.step_time(Duration::from_micros(RPI_US));
        }
        Ok(Stopped {
            closed: self.adapter.connections().is_empty(),
            image: Some(self.input()?),
            log: Some(self.log.clone()),
            seen: String::new(),
        })
    }
}

/// The scanner's side of the session and the connection (the runtime's originator core).
struct Bench<'a> {
    link: &'a mut dyn Scanner,
    session: Session,
    connection: Class1,
}

/// The T→O connection ID the scanner chooses.
const T_O_ID: u32 = 0x0000_0064;

impl Bench<'_> {
    /// RegisterSession: the session handle.
    fn register(&mut self) -> Result<u32, String> {
        let mut message = [0; 28];
        let len = self
            .session
            .register(&mut message)
            .map_err(|e| format!("{e:?}"))?;
        let reply = self.link.request(&message[..len])?;
        self.session
            .registered(&reply)
            .map_err(|e| format!("RegisterSession: {e:?}"))
    }

    /// A Message Router request over SendRRData; its response.
    fn explicit(&mut self, request: &[u8]) -> Result<Vec<u8>, String> {
        let request = RequestRepr::parse(request).map_err(|e| format!("{e:?}"))?;
        let mut message = vec![0; 40 + request.buffer_len()];
        let len = self
            .session
            .send_rr_data(&request, &[], &mut message)
            .map_err(|e| format!("{e:?}"))?;
        let reply = self.link.request(&message[..len])?;
        let reply = self
            .session
            .rr_data_reply(&reply)
            .map_err(|e| format!("{e:?}"))?;
        let response = reply.items.find(item::UNCONNECTED_DATA);
        Ok(response.ok_or("no response item")?.to_vec())
    }

    /// One RPI: the scanner's image out, the card's image back.
    fn cycle(&mut self, output: &OutputImage) -> Result<InputImage, String> {
        let image = card::Output::from_pkw_pzd(output).to_bytes();
        let mut datagram = vec![0; 24 + image.len()];
        let len = self
            .connection
            .produce(true, &image, &mut datagram)
            .map_err(|e| format!("{e:?}"))?;
        let input = self.link.rpi(&datagram[..len])?;
        let input = card::Input::from_slice(&input)
            .ok()
            .ok_or("assembly 100 is not 32 bytes")?;
        input.pkw_pzd().map_err(|e| format!("{e:?}"))
    }

    /// A PKW request held until the card answers it (at most ten RPIs).
    fn pkw(&mut self, request: PkwRequest, write: bool) -> Result<PkwResponse, String> {
        let output = OutputImage {
            pkw: request,
            control: ControlWord(0).with(1 << 8, write),
            pzd: [0; 11],
        };
        for _ in 0..10 {
            let input = self.cycle(&output)?;
            if input.pkw != PkwResponse::None {
                self.cycle(&OutputImage::default())?;
                return Ok(input.pkw);
            }
        }
        Err("no PKW response in ten RPIs".into())
    }
}

/// The card's section of the demo, in this process.
pub(super) fn run(trace: &mut Trace) {
    trace.heading("Goodrive350 EtherNet/IP card: a class-1 scanner from the generated images");
    let adapter = device::goodrive350([10, 0, 0, 1], Instant::from_micros(0));
    let mut link = InProcess {
        adapter,
        now: Instant::from_micros(0),
        log: Vec::new(),
    };
    if let Err(problem) = workflow(trace, &mut link) {
        trace.step("Goodrive350 EtherNet/IP workflow", Err(problem));
    }
}

pub(super) fn not_run(trace: &mut Trace) {
    trace.heading("Goodrive350 EtherNet/IP card");
    trace.step(
        "EtherNet/IP card workflow",
        Ok(
            "not run: a socketcand bus has no EtherNet/IP network (run edsgen demo without --bus)"
                .into(),
        ),
    );
}

fn check(ok: bool, seen: String) -> Result<String, String> {
    if ok {
        Ok(seen)
    } else {
        Err(seen)
    }
}

/// The steps, on either link.
pub(super) fn workflow(trace: &mut Trace, link: &mut dyn Scanner) -> Result<(), String> {
    let mut bench = Bench {
        link,
        session: Session::new(*b"edsgen  "),
        connection: Class1::new(0, T_O_ID, true, false),
    };
    let session = bench.register()?;
    let identity = bench.explicit(&[0x0E, 3, 0x20, 0x01, 0x24, 0x01, 0x30, 0x03])?;
    trace.step(
        "RegisterSession, Identity product code (@1/1/3)",
        check(
            identity == [0x8E, 0, 0, 0, 0x5E, 0x01],
            format!("session {session}, product code {}", card::PRODUCT_CODE),
        ),
    );
    // Forward_Open 150 -> 100 at 50 ms, sizes 32 + 6 and 32 + 2, the EDS's connection path.
    // Point-to-point, high priority, variable size; timeout multiplier ×4.
    let conn = card::EXCLUSIVE_OWNER;
    let params = |size: u16| network_params(false, 2, 1, true, size);
    let open = ForwardOpenRepr {
        large: false,
        ticks: DEFAULT_TICKS,
        o_t_id: 0,
        t_o_id: T_O_ID,
        triad: Triad {
            serial: 1,
            vendor: 1,
            originator_serial: 1,
        },
        multiplier: 0,
        o_t_rpi: conn.rpi_us,
        o_t_params: params(conn.o_t_size + 6),
        t_o_rpi: conn.rpi_us,
        t_o_params: params(conn.t_o_size + 2),
        transport: 0x01,
        path: conn.path,
    };
    let reply = bench.explicit(&open.to_vec().map_err(|e| format!("{e:?}"))?)?;
    let opened = reply.len() >= 8 && reply[2] == 0;
    if opened {
        let o_t_id = u32::from_le_bytes([reply[4], reply[5], reply[6], reply[7]]);
        bench.connection = Class1::new(o_t_id, T_O_ID, true, false);
    }
    trace.step(
        "Forward_Open 150 -> 100 at 50 ms (EXCLUSIVE_OWNER)",
        check(
            opened,
            format!("reply {:02X?}", &reply[..reply.len().min(8)]),
        ),
    );
    if !opened {
        return Err("no connection".into());
    }
    for (name, address) in [
        ("P16.32 = 1 (received PZD2: set frequency)", 0x1020),
        ("P16.43 = 1 (transmitted PZD2: running frequency)", 0x102B),
    ] {
        let response = bench.pkw(
            PkwRequest {
                task: edsgen_runtime::pkw_pzd::Task::WriteEeprom,
                address,
                value: 1,
            },
            true,
        )?;
        trace.step(
            &format!("PKW write {name}"),
            check(
                response == PkwResponse::Word { address, value: 1 },
                format!("{response:?}"),
            ),
        );
    }
    let response = bench.pkw(PkwRequest::read(10), false)?;
    trace.step(
        "PKW read P00.10 (keypad frequency)",
        check(
            response
                == PkwResponse::Word {
                    address: 10,
                    value: 5000,
                },
            format!("{response:?}: 50.00 Hz"),
        ),
    );
    let response = bench.pkw(
        PkwRequest {
            task: edsgen_runtime::pkw_pzd::Task::WriteEeprom,
            address: 0x071B,
            value: 1,
        },
        true,
    )?;
    trace.step(
        "PKW write P07.27 refused (read only, error 7)",
        check(
            response
                == PkwResponse::Refused {
                    address: 0x071B,
                    error: ErrorNumber::ReadOnly,
                },
            format!("{response:?}"),
        ),
    );
    let run = OutputImage {
        pkw: PkwRequest::from_words([0; 4]),
        control: ControlWord::new(Command::RunForward, WordLayout::ByByte),
        pzd: [2500, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
    };
    let first = bench.cycle(&run)?;
    let mut last = first;
    for _ in 0..40 {
        last = bench.cycle(&run)?;
    }
    trace.step(
        "run forward at 25.00 Hz (CW 0x0001, PZD2 2500)",
        check(
            last.status.state(WordLayout::ByByte) == Some(RunState::Forward)
                && last.pzd[0] > first.pzd[0]
                && last.pzd[0] <= 2500,
            format!(
                "SW {:#06X}, transmitted PZD2 {} -> {} (0.01 Hz)",
                last.status.0, first.pzd[0], last.pzd[0]
            ),
        ),
    );
    // The scanner stops producing: after 4 x RPI the connection times out and the drive trips.
    let stopped = bench.link.stop_producing(6)?;
    let image = match stopped.image {
        Some(image) => image,
        None => {
            // Get_Attribute_Single of assembly 100's data: the reply's data after 4 bytes.
            let path = [0x20, 0x04, 0x24, card::Input::INSTANCE as u8, 0x30, 0x03];
            let mut request = vec![0x0E, (path.len() / 2) as u8];
            request.extend_from_slice(&path);
            let reply = bench.explicit(&request)?;
            match reply.get(2) {
                Some(0) => reply.get(4..).unwrap_or_default().to_vec(),
                _ => return Err(format!("@4/100/3: reply {reply:02X?}")),
            }
        }
    };
    let state = card::Input::from_slice(&image)
        .ok()
        .and_then(|f| f.pkw_pzd().ok())
        .and_then(|i| i.status.state(WordLayout::ByByte));
    let (tripped, seen) = match &stopped.log {
        Some(log) => (log.iter().any(|l| l == "drive fault E-EIP"), log.join(", ")),
        // On a wire the adapter's log is not here: the state the card reports is the evidence.
        None => (true, stopped.seen),
    };
    trace.step(
        "scanner stops producing: timeout after 4 x RPI, fault E-EIP",
        check(
            stopped.closed && tripped && state == Some(RunState::Fault),
            format!("{seen}; SW state {state:?}"),
        ),
    );
    Ok(())
}
