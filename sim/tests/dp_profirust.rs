//! profirust's DP master (a third-party master) brings the simulated Goodrive350 DP card to
//! data exchange on profirust's simulated bus, with the identity and configuration read from
//! the card's GSD, answering after Tsdr (the simulator panics on an early answer or a
//! collision); then §2.6's PKW examples and CW/SW commands byte-exact, a wrong Ident_Number
//! (Prm_Fault), a wrong configuration (Cfg_Fault) and the watchdog fault (E-DP) when the
//! master stops.

use std::path::Path;

use edsgen_runtime::pkw_pzd::PkwResponse;
use edsgen_runtime::Instant;
use edsgen_sim::cards::goodrive350_dp::modules::n_4_pkw_12_pzd::{Inputs, Outputs};
use edsgen_sim::dp::card::{goodrive350, read_gsd, Goodrive350Dp, GSD, GSD_PATH};
use edsgen_sim::dp::DpState;
use profirust::dp::{self, DiagnosticFlags};
use profirust::phy::SimulatorPhy;
use profirust::{fdl as pfdl, Baudrate};

const MASTER: u8 = 1;
const SLAVE: u8 = 2;
const BAUD: Baudrate = Baudrate::B19200;

/// The card on the simulated bus.
type SlaveStation = edsgen_sim::dp::simulator_phy::SlaveStation<Goodrive350Dp>;

struct Bus {
    phy: SimulatorPhy,
    station: SlaveStation,
}

fn bus() -> Bus {
    let phy = SimulatorPhy::new(BAUD, "master");
    let slave_phy = phy.duplicate("goodrive350");
    Bus {
        phy,
        station: SlaveStation::new(
            slave_phy,
            BAUD,
            goodrive350(SLAVE, Instant::from_micros(0)).unwrap(),
        ),
    }
}

/// The card's identity, configuration and MaxTsdr at 19.2 kbit/s: the code generated from its
/// GSD (`edsgen_sim::cards::goodrive350_dp`), checked against the GSD's model.
fn gsd() -> (u16, Vec<u8>, u16) {
    use edsgen_sim::cards::goodrive350_dp::{modules::n_4_pkw_12_pzd, BAUD_RATES, IDENT_NUMBER};
    let dp = read_gsd(Path::new(GSD_PATH), GSD).unwrap();
    assert_eq!(dp.ident_number.unwrap().value, IDENT_NUMBER);
    assert_eq!(dp.modules[0].config, n_4_pkw_12_pzd::CONFIG);
    let tsdr = BAUD_RATES
        .iter()
        .find(|(rate, _)| *rate == 19_200)
        .unwrap()
        .1;
    (IDENT_NUMBER, n_4_pkw_12_pzd::CONFIG.to_vec(), tsdr)
}

/// Runs the bus until `done` or 20 s of bus time; the time it took.
fn run(
    bus: &mut Bus,
    fdl: &mut pfdl::FdlActiveStation,
    master: &mut dp::DpMaster,
    mut done: impl FnMut(&mut dp::DpMaster, &mut SlaveStation) -> bool,
) -> bool {
    let end = bus.phy.bus_time() + profirust::time::Duration::from_secs(20);
    while bus.phy.bus_time() < end {
        bus.phy
            .advance_bus_time(profirust::time::Duration::from_micros(100));
        let now = bus.phy.bus_time();
        fdl.poll(now, &mut bus.phy, master);
        bus.station.poll(now);
        if done(master, &mut bus.station) {
            return true;
        }
    }
    false
}

fn fdl_station(master: &dp::DpMaster) -> pfdl::FdlActiveStation {
    let mut fdl = pfdl::FdlActiveStation::new(
        pfdl::ParametersBuilder::new(MASTER, BAUD)
            .slot_bits(300)
            .highest_station_address(4)
            .watchdog_timeout(profirust::time::Duration::from_millis(200))
            .build_verified(master),
    );
    fdl.set_online();
    fdl
}

fn words(pkw: [u16; 4], cw: u16, pzd2: u16) -> [u8; 32] {
    let mut out = [0u8; 32];
    for (n, word) in pkw.into_iter().chain([cw, pzd2]).enumerate() {
        out[2 * n..2 * n + 2].copy_from_slice(&word.to_be_bytes());
    }
    out
}

#[test]
fn profirust_brings_the_card_to_data_exchange() {
    let (ident, config, max_tsdr) = gsd();
    let mut bus = bus();
    let mut inputs = [0u8; 32];
    let mut outputs = [0u8; 32];
    let mut master = dp::DpMaster::new(vec![]);
    let handle = master.add(dp::Peripheral::new(
        SLAVE,
        dp::PeripheralOptions {
            ident_number: ident,
            max_tsdr,
            user_parameters: Some(&edsgen_sim::cards::goodrive350_dp::USER_PRM_DATA),
            config: Some(&config),
            ..Default::default()
        },
        &mut inputs[..],
        &mut outputs[..],
    ));
    let mut fdl = fdl_station(&master);
    master.enter_operate();
    let running = run(&mut bus, &mut fdl, &mut master, |m, _| {
        m.get_mut(handle).is_running()
    });
    assert!(running, "no data exchange");
    assert_eq!(bus.station.slave.state(), DpState::DataExchange);

    // The steps: (outputs, what the inputs' first 12 bytes must become).
    let steps: [([u8; 32], [u8; 12]); 4] = [
        // §2.6 example 1: read P00.10 ("00 01 | 00 10" decimal), 5000 = 13 88h in PKW4.
        (
            words([1, 10, 0, 0], 0, 0),
            [0, 1, 0, 0x0A, 0, 0, 0x13, 0x88, 0x41, 0x03, 0, 0],
        ),
        // §2.6 example 2: write 5000 to P00.10 (task 4), CW bit 8 enables writing.
        (
            words([4, 10, 0, 5000], 0x0100, 0),
            [0, 1, 0, 0x0A, 0, 0, 0x13, 0x88, 0x41, 0x03, 0, 0],
        ),
        // Run forward (CW 1) at 10.00 Hz on PZD2: SW 4101h (forward, ready, communication).
        (
            words([0; 4], 1, 1000),
            [0, 0, 0, 0, 0, 0, 0, 0, 0x41, 0x01, 0x03, 0xE8],
        ),
        // Coast to stop (CW 6): SW 4103h, running frequency 0.
        (
            words([0; 4], 6, 1000),
            [0, 0, 0, 0, 0, 0, 0, 0, 0x41, 0x03, 0, 0],
        ),
    ];
    for (out, expected) in steps {
        // Through the generated image: PKW in identifier 0, CW/PZD in identifier 1.
        let image = Outputs::from_bytes(&out);
        master
            .get_mut(handle)
            .pi_q_mut()
            .copy_from_slice(&image.to_bytes());
        let reached = run(&mut bus, &mut fdl, &mut master, |m, _| {
            m.get_mut(handle).pi_i()[..12] == expected
        });
        let got = master.get_mut(handle).pi_i()[..12].to_vec();
        assert!(reached, "expected {expected:02X?}, inputs {got:02X?}");
        let mut bytes = [0u8; 32];
        bytes.copy_from_slice(master.get_mut(handle).pi_i());
        let inputs = Inputs::from_bytes(&bytes);
        assert_eq!(
            inputs.data_2[0],
            u16::from_be_bytes([expected[8], expected[9]]),
            "SW"
        );
        assert_eq!(
            inputs.data_1[0],
            u16::from_be_bytes([expected[0], expected[1]]),
            "PKW1"
        );
        // The overlay's [pkw_pzd]: the generated image as the runtime's typed PKW/PZD image.
        let typed = inputs.pkw_pzd().unwrap();
        assert_eq!(typed.status.0, inputs.data_2[0]);
        if expected[1] == 1 {
            let value = PkwResponse::Word {
                address: 10,
                value: 5000,
            };
            assert_eq!(typed.pkw, value);
        }
        assert_eq!(Outputs::from_pkw_pzd(&image.pkw_pzd()), image);
    }

    // The master stops: the slave's watchdog (200 ms) trips E-DP (29).
    for _ in 0..5000 {
        bus.phy
            .advance_bus_time(profirust::time::Duration::from_micros(100));
        bus.station.poll(bus.phy.bus_time());
    }
    assert_eq!(bus.station.slave.state(), DpState::WaitPrm);
    assert_eq!(bus.station.slave.app().drive.vfd().fault(), Some(29));
}

/// A master with the wrong Ident_Number or configuration: the slave's diagnosis says which.
#[test]
fn wrong_ident_and_wrong_configuration() {
    let (ident, config, max_tsdr) = gsd();
    for (ident, config, flag) in [
        (ident + 1, config.clone(), DiagnosticFlags::PARAMETER_FAULT),
        (
            ident,
            vec![0xF3, 0xF5],
            DiagnosticFlags::CONFIGURATION_FAULT,
        ),
    ] {
        let mut bus = bus();
        let mut inputs = [0u8; 32];
        let mut outputs = [0u8; 32];
        let mut master = dp::DpMaster::new(vec![]);
        let handle = master.add(dp::Peripheral::new(
            SLAVE,
            dp::PeripheralOptions {
                ident_number: ident,
                max_tsdr,
                user_parameters: Some(&[]),
                config: Some(&config),
                ..Default::default()
            },
            &mut inputs[..],
            &mut outputs[..],
        ));
        let mut fdl = fdl_station(&master);
        master.enter_operate();
        let seen = run(&mut bus, &mut fdl, &mut master, |m, _| {
            m.get_mut(handle)
                .last_diagnostics()
                .is_some_and(|d| d.flags.contains(flag))
        });
        assert!(seen, "no {flag:?}");
        assert!(!master.get_mut(handle).is_running());
        assert_ne!(bus.station.slave.state(), DpState::DataExchange);
    }
}
