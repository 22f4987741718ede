//! The demo's PROFIBUS-DP section: profirust's DP master (a third-party master) on its
//! simulated bus, in bus time, brings the simulated Goodrive350 DP card (`edsgen_sim::dp`) to
//! data exchange with the identity and configuration generated from `eds/goodrive350-dp.gsd`,
//! then walks the manual's §2.6 PKW examples and CW/SW commands through the card's images, and
//! stops to see the card's watchdog trip E-DP. The slave answers 11 bit times after a request
//! ends (the simulator refuses an earlier answer).

use std::path::Path;

use edsgen_runtime::Instant;
use edsgen_sim::cards::goodrive350_dp::{self as card, modules::n_4_pkw_12_pzd as module};
use edsgen_sim::dp::card::{goodrive350, Goodrive350Dp, GSD, GSD_PATH};
use edsgen_sim::dp::simulator_phy::SlaveStation;
use edsgen_sim::dp::DpState;
use profirust::phy::SimulatorPhy;
use profirust::time::Duration;
use profirust::{dp, fdl as pfdl, Baudrate};

use super::Trace;

const MASTER: u8 = 1;
pub(super) const SLAVE: u8 = 2;
const BAUD: Baudrate = Baudrate::B19200;
/// The bus time one step may take.
const STEP_TIME: Duration = Duration::from_secs(20);

/// The card on the simulated bus.
type Station = SlaveStation<Goodrive350Dp>;

/// The 32 output bytes of PKW1–PKW4, the CW and PZD2, through the generated image.
fn outputs(pkw: [u16; 4], cw: u16, pzd2: u16) -> [u8; 32] {
    let mut image = module::Outputs::ZERO;
    image.data_1 = pkw;
    image.data_2[0] = cw;
    image.data_2[1] = pzd2;
    image.to_bytes()
}

/// The card's GSD, loaded as `edsgen validate eds/goodrive350-dp.gsd` loads it (with the
/// overlay beside it): no errors.
pub(super) fn check_gsd(trace: &mut Trace) {
    // Loaded as `edsgen validate eds/goodrive350-dp.gsd` loads it: with the overlay beside it.
    let loaded = edsgen_model::load::load_bundled(
        Path::new(GSD_PATH),
        GSD,
        Some(include_str!("../../eds/goodrive350-dp.toml")),
    );
    let errors = loaded
        .diagnostics
        .iter()
        .chain(loaded.overlay_diagnostics())
        .filter(|d| d.severity == edsgen_model::diag::Severity::Error)
        .count();
    trace.step(
        "the card's GSD reads and validates",
        if errors == 0 {
            Ok(format!(
                "Ident_Number {:04X}h, Chk_Cfg {:02X?}",
                card::IDENT_NUMBER,
                module::CONFIG
            ))
        } else {
            Err(format!("{errors} error(s)"))
        },
    );
}

/// profirust's DP master (station 1) with the card at station 2 as its one peripheral: the
/// GSD's identity, Tsdr at 19.2 kbit/s, parameters and configuration, a 200 ms watchdog; online
/// and operating.
pub(super) fn master<'a>(
    inputs: &'a mut [u8; 32],
    out: &'a mut [u8; 32],
) -> (
    dp::DpMaster<'a>,
    dp::PeripheralHandle,
    pfdl::FdlActiveStation,
) {
    let tsdr = card::BAUD_RATES
        .iter()
        .find(|(rate, _)| *rate == 19_200)
        .map_or(60, |(_, tsdr)| *tsdr);
    let mut master = dp::DpMaster::new(vec![]);
    let handle = master.add(dp::Peripheral::new(
        SLAVE,
        dp::PeripheralOptions {
            ident_number: card::IDENT_NUMBER,
            max_tsdr: tsdr,
            user_parameters: Some(&card::USER_PRM_DATA),
            config: Some(&module::CONFIG),
            ..Default::default()
        },
        &mut inputs[..],
        &mut out[..],
    ));
    let mut fdl = pfdl::FdlActiveStation::new(
        pfdl::ParametersBuilder::new(MASTER, BAUD)
            .slot_bits(300)
            .highest_station_address(4)
            .watchdog_timeout(Duration::from_millis(200))
            .build_verified(&master),
    );
    fdl.set_online();
    master.enter_operate();
    (master, handle, fdl)
}

/// Runs the DP section into `trace`.
pub(super) fn run(trace: &mut Trace) {
    trace.heading(
        "Goodrive350 DP card (station 2): PROFIBUS-DP with profirust's master, manual chapter 2",
    );
    check_gsd(trace);
    let phy = SimulatorPhy::new(BAUD, "master");
    let slave = match goodrive350(SLAVE, Instant::from_micros(0)) {
        Ok(slave) => slave,
        Err(e) => return trace.step("power up the card", Err(e.to_string())),
    };
    let mut station = SlaveStation::new(phy.duplicate("goodrive350-dp"), BAUD, slave);
    let mut phy = phy;
    let mut inputs = [0u8; 32];
    let mut out = [0u8; 32];
    let (mut master, handle, mut fdl) = master(&mut inputs, &mut out);
    let mut until =
        |master: &mut dp::DpMaster, station: &mut Station, done: &dyn Fn(&[u8], bool) -> bool| {
            let end = phy.bus_time() + STEP_TIME;
            while phy.bus_time() < end {
                phy.advance_bus_time(Duration::from_micros(100));
                let now = phy.bus_time();
                fdl.poll(now, &mut phy, master);
                station.poll(now);
                let peripheral = master.get_mut(handle);
                if done(peripheral.pi_i(), peripheral.is_running()) {
                    return Some(now.total_micros() / 1000);
                }
            }
            None
        };
    let reached = until(&mut master, &mut station, &|_, running| running);
    trace.step(
        "Set_Prm, Chk_Cfg, data exchange",
        match reached {
            Some(ms) => Ok(format!("data exchange at {ms} ms bus time, 19.2 kbit/s")),
            None => Err(format!(
                "no data exchange; the card is in {:?}",
                station.slave.state()
            )),
        },
    );
    if reached.is_none() {
        return;
    }
    for (name, image, expected) in pkw_steps() {
        master.get_mut(handle).pi_q_mut().copy_from_slice(&image);
        let seen = until(&mut master, &mut station, &|inputs, _| {
            inputs[..12] == expected
        });
        let got = master.get_mut(handle).pi_i()[..12].to_vec();
        trace.step(name, inputs_seen(seen.is_some(), &got, &expected));
    }
    // The master stops: 0.5 s of bus time with only the card polled.
    for _ in 0..5000 {
        phy.advance_bus_time(Duration::from_micros(100));
        station.poll(phy.bus_time());
    }
    let fault = station.slave.app().drive.vfd().fault();
    trace.step(
        "the master stops: the DP watchdog (200 ms) trips E-DP",
        if station.slave.state() == DpState::WaitPrm && fault == Some(29) {
            Ok("Wait_Prm, P07.27 = 29 (E-DP)".to_owned())
        } else {
            Err(format!("{:?}, fault {fault:?}", station.slave.state()))
        },
    );
}

/// The manual's §2.6 PKW examples and two CW/SW commands: each step's name, the 32 output bytes,
/// and the first 12 input bytes the card answers with.
pub(super) fn pkw_steps() -> [(&'static str, [u8; 32], [u8; 12]); 4] {
    [
        (
            "§2.6 example 1: read P00.10 (task 1, address 10)",
            outputs([1, 10, 0, 0], 0, 0),
            [0, 1, 0, 0x0A, 0, 0, 0x13, 0x88, 0x41, 0x03, 0, 0],
        ),
        (
            "§2.6 example 2: write 50.00 Hz to P00.10 (task 4, CW bit 8)",
            outputs([4, 10, 0, 5000], 0x0100, 0),
            [0, 1, 0, 0x0A, 0, 0, 0x13, 0x88, 0x41, 0x03, 0, 0],
        ),
        (
            "CW 1 (run forward) at 10.00 Hz on PZD2",
            outputs([0; 4], 1, 1000),
            [0, 0, 0, 0, 0, 0, 0, 0, 0x41, 0x01, 0x03, 0xE8],
        ),
        (
            "CW 6 (coast to stop)",
            outputs([0; 4], 6, 1000),
            [0, 0, 0, 0, 0, 0, 0, 0, 0x41, 0x03, 0, 0],
        ),
    ]
}

/// A PKW step's outcome: the first 12 input bytes, as expected or not.
pub(super) fn inputs_seen(
    as_expected: bool,
    got: &[u8],
    expected: &[u8],
) -> Result<String, String> {
    if as_expected {
        Ok(format!("inputs {}", hex(got)))
    } else {
        Err(format!("inputs {}, expected {}", hex(got), hex(expected)))
    }
}

pub(super) fn hex(bytes: &[u8]) -> String {
    bytes
        .iter()
        .map(|b| format!("{b:02X}"))
        .collect::<Vec<_>>()
        .join(" ")
}
