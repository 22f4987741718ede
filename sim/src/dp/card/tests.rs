//! The slave against hand-built master telegrams: start-up to data exchange, the faults, the
//! §2.6 PKW examples through Data_Exchange, FCB repetitions, bad telegrams, Global_Control and
//! the watchdog.

use edsgen_runtime::dp::fdl::{self, DataRepr, Repr, MAX_TELEGRAM_LEN};
use edsgen_runtime::dp::slave::sap;
use edsgen_runtime::dp::{DpSlave, DpState};
use edsgen_runtime::Instant;

use super::{goodrive350, Goodrive350Dp};

const MASTER: u8 = 1;
const SLAVE: u8 = 2;

fn ms(n: u64) -> Instant {
    Instant::from_millis(n)
}

/// A telegram's bytes.
fn emit(t: DataRepr<'_>) -> Vec<u8> {
    let mut buf = [0; MAX_TELEGRAM_LEN];
    let n = t.emit(&mut buf).unwrap();
    buf[..n].to_vec()
}

/// The slave's answer to `bytes` at `now`, if any.
fn handle(slave: &mut DpSlave<Goodrive350Dp>, now: Instant, bytes: &[u8]) -> Option<Vec<u8>> {
    slave.handle(now, bytes);
    let mut buf = [0; MAX_TELEGRAM_LEN];
    let n = slave.poll_transmit(now, &mut buf)?;
    Some(buf[..n].to_vec())
}

/// A master request: SRD low with FCV and the given FCB, SAPs as given.
fn request(dsap: Option<u8>, fcb: bool, data: &[u8]) -> Vec<u8> {
    emit(DataRepr {
        da: SLAVE,
        sa: MASTER,
        dsap,
        ssap: dsap.map(|_| 62),
        fc: 0x40 | 0x10 | if fcb { 0x20 } else { 0 } | fdl::request::SRD_LOW,
        data,
    })
}

/// The data of a slave's answer.
fn data(answer: &[u8]) -> Vec<u8> {
    match fdl::parse(answer).unwrap().0 {
        Repr::Data(t) => t.data.to_vec(),
        other => panic!("{other:?}"),
    }
}

/// Set_Prm: watchdog on (10 ms × 10 × 10 = 1 s), Ident_Number 0350h, no user parameters.
fn set_prm(ident: u16) -> Vec<u8> {
    let [hi, lo] = ident.to_be_bytes();
    vec![0x08, 10, 10, 11, hi, lo, 0]
}

struct Master {
    fcb: bool,
}

impl Master {
    fn send(
        &mut self,
        slave: &mut DpSlave<Goodrive350Dp>,
        now: Instant,
        dsap: Option<u8>,
        data: &[u8],
    ) -> Option<Vec<u8>> {
        self.fcb = !self.fcb;
        handle(slave, now, &request(dsap, self.fcb, data))
    }
}

fn started() -> (DpSlave<Goodrive350Dp>, Master) {
    let mut slave = goodrive350(SLAVE, ms(0)).unwrap();
    let mut master = Master { fcb: false };
    let diag = master
        .send(&mut slave, ms(1), Some(sap::SLAVE_DIAG), &[])
        .unwrap();
    // Station not ready, Prm_Req, no master, Ident_Number 0350h.
    assert_eq!(data(&diag), [0x02, 0x05, 0x00, 0xFF, 0x03, 0x50]);
    assert_eq!(
        master.send(&mut slave, ms(2), Some(sap::SET_PRM), &set_prm(0x0350)),
        Some(vec![0xE5])
    );
    assert_eq!(slave.state(), DpState::WaitCfg);
    assert_eq!(
        master.send(&mut slave, ms(3), Some(sap::CHK_CFG), &[0xF3, 0xFB]),
        Some(vec![0xE5])
    );
    let diag = master
        .send(&mut slave, ms(4), Some(sap::SLAVE_DIAG), &[])
        .unwrap();
    assert_eq!(data(&diag), [0x00, 0x0C, 0x00, MASTER, 0x03, 0x50]);
    assert_eq!(slave.state(), DpState::DataExchange);
    (slave, master)
}

/// 32 output bytes: PKW1–PKW4, the CW and PZD2, big-endian.
fn outputs(pkw: [u16; 4], cw: u16, pzd2: u16) -> Vec<u8> {
    let mut out = Vec::new();
    for word in pkw.into_iter().chain([cw, pzd2]) {
        out.extend(word.to_be_bytes());
    }
    out.resize(32, 0);
    out
}

#[test]
fn pkw_examples_through_data_exchange() {
    let (mut slave, mut master) = started();
    // §2.6 example 1: read address 10, answered with 5000 (the manual's "50 00").
    let answer = master
        .send(&mut slave, ms(10), None, &outputs([1, 10, 0, 0], 0, 0))
        .unwrap();
    let inputs = data(&answer);
    assert_eq!(inputs.len(), 32);
    assert_eq!(
        inputs[..10],
        [0x00, 0x01, 0x00, 0x0A, 0x00, 0x00, 0x13, 0x88, 0x41, 0x03]
    );
    // §2.6 example 2: write 5000 to address 10 (RAM and EEPROM), CW bit 8 set.
    let answer = master
        .send(
            &mut slave,
            ms(20),
            None,
            &outputs([4, 10, 0, 5000], 0x0100, 0),
        )
        .unwrap();
    assert_eq!(
        data(&answer)[..8],
        [0x00, 0x01, 0x00, 0x0A, 0x00, 0x00, 0x13, 0x88]
    );
    // Run forward at 25.00 Hz: SW 4101h, PZD2 (running frequency) 2.50 Hz after 0.5 s.
    master.send(&mut slave, ms(30), None, &outputs([0; 4], 1, 2500));
    let answer = master
        .send(&mut slave, ms(530), None, &outputs([0; 4], 1, 2500))
        .unwrap();
    assert_eq!(data(&answer)[8..12], [0x41, 0x01, 0x00, 0xFA]);
    // A refused write: P07.27 is read-only, error 7.
    let answer = master
        .send(
            &mut slave,
            ms(1040),
            None,
            &outputs([4, 0x071B, 0, 1], 0x0101, 2500),
        )
        .unwrap();
    assert_eq!(data(&answer)[..8], [0, 3, 0x07, 0x1B, 0, 7, 0, 0]);
}

#[test]
fn wrong_ident_number_is_a_prm_fault() {
    let mut slave = goodrive350(SLAVE, ms(0)).unwrap();
    let mut master = Master { fcb: false };
    assert_eq!(
        master.send(&mut slave, ms(1), Some(sap::SET_PRM), &set_prm(0x0351)),
        Some(vec![0xE5])
    );
    let diag = master
        .send(&mut slave, ms(2), Some(sap::SLAVE_DIAG), &[])
        .unwrap();
    assert_eq!(data(&diag), [0x42, 0x05, 0x00, 0xFF, 0x03, 0x50]);
    assert_eq!(slave.state(), DpState::WaitPrm);
    // User parameters the GSD does not declare: a Prm_Fault too.
    let mut long = set_prm(0x0350);
    long.push(0);
    master.send(&mut slave, ms(3), Some(sap::SET_PRM), &long);
    let diag = master
        .send(&mut slave, ms(4), Some(sap::SLAVE_DIAG), &[])
        .unwrap();
    assert_eq!(data(&diag)[0], 0x42);
}

#[test]
fn wrong_configuration_is_a_cfg_fault() {
    let mut slave = goodrive350(SLAVE, ms(0)).unwrap();
    let mut master = Master { fcb: false };
    master.send(&mut slave, ms(1), Some(sap::SET_PRM), &set_prm(0x0350));
    // PPO 2 (F3 F5) instead of 4 PKW + 12 PZD.
    master.send(&mut slave, ms(2), Some(sap::CHK_CFG), &[0xF3, 0xF5]);
    let diag = master
        .send(&mut slave, ms(3), Some(sap::SLAVE_DIAG), &[])
        .unwrap();
    assert_eq!(data(&diag), [0x06, 0x05, 0x00, MASTER, 0x03, 0x50]);
    assert_eq!(slave.state(), DpState::WaitPrm);
    // Data_Exchange is refused (RS) until the slave is configured.
    let answer = master
        .send(&mut slave, ms(4), None, &outputs([0; 4], 0, 0))
        .unwrap();
    assert_eq!(answer, [0x10, MASTER, SLAVE, 0x03, 0x06, 0x16]);
    // Get_Cfg answers the GSD's configuration.
    let cfg = master
        .send(&mut slave, ms(5), Some(sap::GET_CFG), &[])
        .unwrap();
    assert_eq!(data(&cfg), [0xF3, 0xFB]);
}

#[test]
fn a_repeated_fcb_repeats_the_answer_without_executing_twice() {
    let (mut slave, mut master) = started();
    master.fcb = !master.fcb;
    let write = request(None, master.fcb, &outputs([4, 10, 0, 3000], 0x0100, 0));
    let first = handle(&mut slave, ms(10), &write).unwrap();
    slave.app_mut().drive.set_parameter(10, 1234).unwrap();
    let again = handle(&mut slave, ms(20), &write).unwrap();
    assert_eq!(first, again);
    assert_eq!(slave.app().drive.parameter(10), Some(1234));
}

#[test]
fn bad_telegrams_are_not_answered() {
    let (mut slave, mut master) = started();
    let mut bytes = request(None, !master.fcb, &outputs([1, 10, 0, 0], 0, 0));
    let n = bytes.len();
    bytes[n - 2] ^= 1; // FCS
    assert_eq!(handle(&mut slave, ms(10), &bytes), None);
    bytes[n - 2] ^= 1;
    bytes[n - 1] = 0x17; // end delimiter
    assert_eq!(handle(&mut slave, ms(10), &bytes), None);
    // A SAP DP does not have; another station; a short output image.
    assert_eq!(master.send(&mut slave, ms(11), Some(20), &[]), None);
    let other = emit(DataRepr {
        da: 9,
        sa: MASTER,
        dsap: None,
        ssap: None,
        fc: 0x7C,
        data: &[0; 32],
    });
    assert_eq!(handle(&mut slave, ms(12), &other), None);
    assert_eq!(master.send(&mut slave, ms(13), None, &[0; 4]), None);
    assert_eq!(slave.state(), DpState::DataExchange);
}

/// Issue 34: telegrams that check but are no valid request to this slave get silence (each of
/// these was answered before).
#[test]
fn requests_that_are_not_valid_get_no_answer() {
    let (mut slave, _) = started();
    // FDL status from master 1, and Slave_Diag with both SAPs (60 from 62): answered.
    let status = [0x10, 0x02, 0x01, 0x49, 0x4C, 0x16];
    let answer = [0x10, 0x01, 0x02, 0x00, 0x03, 0x16];
    assert_eq!(handle(&mut slave, ms(10), &status), Some(answer.to_vec()));
    let diag = [
        0x68, 0x05, 0x05, 0x68, 0x82, 0x81, 0x5D, 0x3C, 0x3E, 0xDA, 0x16,
    ];
    assert!(handle(&mut slave, ms(10), &diag).is_some());
    for bytes in [
        // From 127 (the broadcast address) and from the slave's own address 2.
        &[0x10, 0x02, 0x7F, 0x49, 0xCA, 0x16][..],
        &[0x10, 0x02, 0x02, 0x49, 0x4D, 0x16],
        // FC bit 7 set (reserved); FDL status with FCV.
        &[0x10, 0x02, 0x01, 0xC9, 0xCC, 0x16],
        &[0x10, 0x02, 0x01, 0x59, 0x5C, 0x16],
        // Slave_Diag with a DSAP and no SSAP; with DSAP 7Ch (60 with the extension bit); with
        // SSAP FEh.
        &[0x68, 0x04, 0x04, 0x68, 0x82, 0x01, 0x5D, 0x3C, 0x1C, 0x16],
        &[
            0x68, 0x05, 0x05, 0x68, 0x82, 0x81, 0x5D, 0x7C, 0x3E, 0x1A, 0x16,
        ],
        &[
            0x68, 0x05, 0x05, 0x68, 0x82, 0x81, 0x5D, 0x3C, 0xFE, 0x9A, 0x16,
        ],
    ] {
        assert_eq!(handle(&mut slave, ms(11), bytes), None, "{bytes:02X?}");
    }
    assert_eq!(slave.state(), DpState::DataExchange);
}

#[test]
fn the_watchdog_leaves_data_exchange_with_e_dp() {
    let (mut slave, mut master) = started();
    master.send(&mut slave, ms(10), None, &outputs([0; 4], 1, 2500));
    assert_eq!(slave.poll_timeout(), Some(ms(1010)));
    slave.handle_timeout(ms(1009));
    assert_eq!(slave.state(), DpState::DataExchange);
    slave.handle_timeout(ms(1010));
    assert_eq!(slave.state(), DpState::WaitPrm);
    assert_eq!(slave.app().drive.vfd().fault(), Some(29));
    let diag = master
        .send(&mut slave, ms(1100), Some(sap::SLAVE_DIAG), &[])
        .unwrap();
    assert_eq!(data(&diag), [0x02, 0x05, 0x00, 0xFF, 0x03, 0x50]);
}

#[test]
fn sync_and_freeze() {
    let (mut slave, mut master) = started();
    let global = |control: u8| {
        emit(DataRepr {
            da: fdl::BROADCAST,
            sa: MASTER,
            dsap: Some(sap::GLOBAL_CONTROL),
            ssap: Some(62),
            fc: 0x46,
            data: &[control, 0],
        })
    };
    // Freeze: the inputs stay those of the Freeze while the drive runs.
    master.send(&mut slave, ms(10), None, &outputs([0; 4], 1, 2500));
    assert_eq!(handle(&mut slave, ms(500), &global(0x08)), None);
    let frozen = data(
        &master
            .send(&mut slave, ms(1000), None, &outputs([0; 4], 1, 2500))
            .unwrap(),
    );
    let later = data(
        &master
            .send(&mut slave, ms(1500), None, &outputs([0; 4], 1, 2500))
            .unwrap(),
    );
    assert_eq!(frozen, later);
    assert_eq!(
        data(
            &master
                .send(&mut slave, ms(1500), Some(sap::SLAVE_DIAG), &[])
                .unwrap()
        )[1],
        0x1C
    );
    handle(&mut slave, ms(1500), &global(0x04)); // Unfreeze
    let fresh = data(
        &master
            .send(&mut slave, ms(2000), None, &outputs([0; 4], 1, 2500))
            .unwrap(),
    );
    assert_ne!(fresh[10..12], later[10..12]);
    // Sync: a coast command waits for the next Sync.
    handle(&mut slave, ms(2000), &global(0x20));
    master.send(&mut slave, ms(2010), None, &outputs([0; 4], 6, 2500));
    assert!(slave.app().drive.vfd().output_frequency() > 0);
    handle(&mut slave, ms(2020), &global(0x20));
    assert_eq!(slave.app().drive.vfd().output_frequency(), 0);
}

#[test]
fn events_tell_the_state_changes_and_the_watchdog() {
    use edsgen_runtime::dp::Event;
    let (mut slave, mut master) = started();
    let changes: Vec<Event> = std::iter::from_fn(|| slave.poll_event()).collect();
    assert_eq!(
        changes,
        [
            Event::StateChanged {
                from: DpState::WaitPrm,
                to: DpState::WaitCfg
            },
            Event::StateChanged {
                from: DpState::WaitCfg,
                to: DpState::DataExchange
            },
        ]
    );
    master.send(&mut slave, ms(10), None, &outputs([0; 4], 0, 0));
    assert_eq!(slave.poll_event(), None);
    slave.handle_timeout(ms(1010));
    assert_eq!(slave.poll_event(), Some(Event::WatchdogExpired));
    assert_eq!((slave.poll_event(), slave.events_lost()), (None, 0));
}
