//! The Goodrive350's EtherNet/IP card in the demo: a scanner built from the card's generated
//! images (`cards::goodrive350_enip`, typed through `edsgen_runtime::pkw_pzd`) drives the
//! simulated adapter's protocol core (`edsgen_sim::enip`) in this process, in simulated time:
//! RegisterSession and ListIdentity, Forward_Open 150 → 100 at 50 ms, class-1 datagrams every
//! RPI, the manual's steps through PKW and PZD (5.4.3), then a scanner that stops producing and
//! the timeout fault E-EIP. Every datagram is what a scanner would put on UDP 2222.

use edsgen_runtime::pkw_pzd::{
    Command, ControlWord, ErrorNumber, InputImage, OutputImage, PkwRequest, PkwResponse, RunState,
    WordLayout,
};
use edsgen_runtime::{Duration, Instant};
use edsgen_sim::enip::wire::{emit_items, item, parse_items, Encapsulation};
use edsgen_sim::enip::{device, driver, Adapter};

use super::Trace;
use crate::cards::goodrive350_enip as card;

const RPI_US: u64 = 50_000;

/// The scanner and the card.
struct Bench {
    adapter: Adapter,
    card: driver::Card,
    session: u32,
    o_t_id: u32,
    sequence: u16,
    now: Instant,
    log: Vec<String>,
}

impl Bench {
    fn encapsulated(&mut self, command: u16, data: Vec<u8>) -> Result<Encapsulation, String> {
        let message = Encapsulation {
            command,
            session: self.session,
            status: 0,
            context: *b"edsgen  ",
            options: 0,
            data,
        };
        let (reply, _) = self
            .adapter
            .handle(1, &message.emit(), self.now)
            .map_err(|e| format!("{e:?}"))?;
        let reply = reply.ok_or("no reply")?;
        Ok(Encapsulation::parse(&reply)
            .map_err(|e| format!("{e:?}"))?
            .0)
    }

    /// A Message Router request over SendRRData; its response.
    fn explicit(&mut self, request: &[u8]) -> Result<Vec<u8>, String> {
        let mut data = vec![0; 6];
        data.extend(emit_items(&[
            (item::NULL_ADDRESS, &[]),
            (item::UNCONNECTED_DATA, request),
        ]));
        let reply = self.encapsulated(0x6F, data)?;
        let items = reply
            .data
            .get(6..)
            .and_then(parse_items)
            .ok_or("no items")?;
        Ok(items.get(1).ok_or("no response item")?.1.to_vec())
    }

    /// One RPI: the scanner's image out, the card's image back.
    fn cycle(&mut self, output: &OutputImage) -> Result<InputImage, String> {
        let image = card::Output::from_pkw_pzd(output).encode();
        self.sequence = self.sequence.wrapping_add(1);
        let mut address = self.o_t_id.to_le_bytes().to_vec();
        address.extend_from_slice(&u32::from(self.sequence).to_le_bytes());
        let mut payload = self.sequence.to_le_bytes().to_vec();
        payload.extend_from_slice(&1u32.to_le_bytes()); // run
        payload.extend_from_slice(&image);
        let datagram = emit_items(&[
            (item::SEQUENCED_ADDRESS, &address),
            (item::CONNECTED_DATA, &payload),
        ]);
        self.adapter.receive_io(1, &datagram, self.now);
        self.step_time(Duration::from_micros(RPI_US));
        let input = self
            .adapter
            .assemblies
            .get(&card::Input::INSTANCE)
            .ok_or("no assembly 100")?;
        let input = card::Input::decode(&input.data).ok_or("assembly 100 is short")?;
        input.pkw_pzd().map_err(|e| format!("{e:?}"))
    }

    fn step_time(&mut self, by: Duration) {
        self.now = self.now + by;
        // The T→O datagrams are not needed: the card's image is read from assembly 100.
        self.adapter.poll(self.now);
        let mut log = Vec::new();
        driver::link(
            &mut self.adapter,
            Some(&mut self.card),
            self.now,
            &mut |l| log.push(l),
        );
        self.log.extend(log);
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

pub(super) fn run(trace: &mut Trace) {
    trace.heading("Goodrive350 EtherNet/IP card: a class-1 scanner from the generated images");
    if let Err(problem) = workflow(trace) {
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

fn workflow(trace: &mut Trace) -> Result<(), String> {
    let (adapter, card) = device::goodrive350([10, 0, 0, 1], Instant::from_micros(0));
    let mut bench = Bench {
        adapter,
        card,
        session: 0,
        o_t_id: 0,
        sequence: 0,
        now: Instant::from_micros(0),
        log: Vec::new(),
    };
    let registered = bench.encapsulated(0x65, vec![1, 0, 0, 0])?;
    bench.session = registered.session;
    let identity = bench.explicit(&[0x0E, 3, 0x20, 0x01, 0x24, 0x01, 0x30, 0x03])?;
    trace.step(
        "RegisterSession, Identity product code (@1/1/3)",
        check(
            registered.status == 0 && identity == [0x8E, 0, 0, 0, 0x5E, 0x01],
            format!(
                "session {}, product code {}",
                bench.session,
                card::PRODUCT_CODE
            ),
        ),
    );
    // Forward_Open 150 -> 100 at 50 ms, sizes 32 + 6 and 32 + 2, the EDS's connection path.
    let conn = card::EXCLUSIVE_OWNER;
    let mut open = vec![0x54, 2, 0x20, 0x06, 0x24, 0x01, 0x0A, 0x0E];
    open.extend_from_slice(&0u32.to_le_bytes());
    open.extend_from_slice(&0x0000_0064u32.to_le_bytes());
    open.extend_from_slice(&1u16.to_le_bytes());
    open.extend_from_slice(&0x0001u16.to_le_bytes());
    open.extend_from_slice(&1u32.to_le_bytes());
    open.extend_from_slice(&[0, 0, 0, 0]);
    open.extend_from_slice(&conn.rpi_us.to_le_bytes());
    open.extend_from_slice(&(0x4600 | (conn.o_t_size as u16 + 6)).to_le_bytes());
    open.extend_from_slice(&conn.rpi_us.to_le_bytes());
    open.extend_from_slice(&(0x4600 | (conn.t_o_size as u16 + 2)).to_le_bytes());
    open.push(0x01);
    open.push((conn.path.len() / 2) as u8);
    open.extend_from_slice(conn.path);
    let reply = bench.explicit(&open)?;
    let opened = reply.len() >= 8 && reply[2] == 0;
    if opened {
        bench.o_t_id = u32::from_le_bytes([reply[4], reply[5], reply[6], reply[7]]);
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
    for _ in 0..6 {
        bench.step_time(Duration::from_micros(RPI_US));
    }
    let fault = bench
        .adapter
        .assemblies
        .get(&card::Input::INSTANCE)
        .and_then(|a| card::Input::decode(&a.data));
    let state = fault
        .and_then(|f| f.pkw_pzd().ok())
        .and_then(|i| i.status.state(WordLayout::ByByte));
    let tripped = bench.log.iter().any(|l| l == "drive fault E-EIP");
    trace.step(
        "scanner stops producing: timeout after 4 x RPI, fault E-EIP",
        check(
            bench.adapter.connections().is_empty() && tripped && state == Some(RunState::Fault),
            format!("{}; SW state {state:?}", bench.log.join(", ")),
        ),
    );
    Ok(())
}
