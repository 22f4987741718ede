//! A slave simulated from a modular GSD: Chk_Cfg accepts any combination of modules the GSD
//! allows (and then exchanges that combination's images), refuses others with Cfg_Fault, and
//! with modules chosen accepts only those.

use std::path::Path;

use edsgen_model::model::modules::parse_choices;
use edsgen_runtime::dp::fdl::{self, DataRepr, Repr, MAX_TELEGRAM_LEN};
use edsgen_runtime::dp::slave::sap;
use edsgen_runtime::dp::{DpSlave, DpState};
use edsgen_runtime::Instant;

use super::{loopback, read_gsd, CardError, Loopback};

/// Slot 1 takes a PPO module, slots 2 and 3 the I/O modules (the model's fixture, as its
/// tests use it).
const GSD: &str = include_str!("../../../../model/src/model/modules/modular.gsd");

const MASTER: u8 = 1;
const SLAVE: u8 = 7;

struct Bench {
    slave: DpSlave<Loopback>,
    fcb: bool,
    now: u64,
}

impl Bench {
    fn new(modules: &[&str]) -> Self {
        Self::of(GSD, modules)
    }

    /// A slave of the GSD `text`, plugged with `modules` (none: the master picks them).
    fn of(text: &str, modules: &[&str]) -> Self {
        let dp = read_gsd(Path::new("modular.gsd"), text.as_bytes()).unwrap();
        let modules = parse_choices(modules).unwrap();
        let slave = loopback(&dp, &modules, SLAVE, Instant::from_millis(0)).unwrap();
        Bench {
            slave,
            fcb: false,
            now: 0,
        }
    }

    /// The data of the slave's answer to a request to `dsap` (`None`: Data_Exchange); `None`
    /// for a short acknowledgement or silence.
    fn send(&mut self, dsap: Option<u8>, data: &[u8]) -> Option<Vec<u8>> {
        self.fcb = !self.fcb;
        self.now += 1;
        let mut buf = [0; MAX_TELEGRAM_LEN];
        let request = DataRepr {
            da: SLAVE,
            sa: MASTER,
            dsap,
            ssap: dsap.map(|_| 62),
            fc: 0x40 | 0x10 | if self.fcb { 0x20 } else { 0 } | fdl::request::SRD_LOW,
            data,
        };
        let n = request.emit(&mut buf).unwrap();
        let now = Instant::from_millis(self.now);
        self.slave.handle(now, &buf[..n]);
        let n = self.slave.poll_transmit(now, &mut buf)?;
        match fdl::parse(&buf[..n]).unwrap().0 {
            Repr::Data(t) => Some(t.data.to_vec()),
            _ => None,
        }
    }

    /// Set_Prm (no watchdog, Ident_Number 1234h) then Chk_Cfg with `config`; the diagnosis.
    fn configure(&mut self, config: &[u8]) -> Vec<u8> {
        self.send(Some(sap::SET_PRM), &[0x00, 0, 0, 11, 0x12, 0x34, 0]);
        self.send(Some(sap::CHK_CFG), config);
        self.send(Some(sap::SLAVE_DIAG), &[]).unwrap()
    }
}

#[test]
fn any_allowed_combination_is_accepted_and_exchanged() {
    let mut bench = Bench::new(&[]);
    // The default configuration is the first module.
    assert_eq!(bench.send(Some(sap::GET_CFG), &[]), Some(vec![0xF3, 0xF1]));
    // PPO 3, 8 DI, 16 words out: 4 + 1 input bytes, 4 + 32 output bytes.
    let diag = bench.configure(&[0xF1, 0x10, 0x6F]);
    assert_eq!(diag, [0x00, 0x04, 0x00, MASTER, 0x12, 0x34]);
    assert_eq!(bench.slave.state(), DpState::DataExchange);
    assert_eq!(
        bench.send(Some(sap::GET_CFG), &[]),
        Some(vec![0xF1, 0x10, 0x6F])
    );
    let outputs: Vec<u8> = (1..=36).collect();
    // The inputs echo the outputs, cut to the 5 input bytes.
    assert_eq!(bench.send(None, &outputs), Some(vec![1, 2, 3, 4, 5]));
    // Outputs of the old length are not this configuration's.
    assert_eq!(bench.send(None, &outputs[..12]), None);
}

#[test]
fn a_combination_the_gsd_does_not_allow_is_a_cfg_fault() {
    let mut bench = Bench::new(&[]);
    // 8 DI in slot 1 (the drive's slot): Cfg_Fault, station not ready, back to Wait_Prm
    // (Prm_Req), as a real slave reports it.
    let diag = bench.configure(&[0x10]);
    assert_eq!(diag, [0x06, 0x05, 0x00, MASTER, 0x12, 0x34]);
    assert_eq!(bench.slave.state(), DpState::WaitPrm);
    // Unknown bytes, and four modules where Max_Module is 3.
    assert_eq!(bench.configure(&[0xF1, 0x77])[0], 0x06);
    assert_eq!(bench.configure(&[0xF1, 0x10, 0x10, 0x10])[0], 0x06);
    // Then an allowed one.
    assert_eq!(bench.configure(&[0xF3, 0xF1])[0], 0x00);
}

#[test]
fn chosen_modules_are_plugged_and_only_they_are_accepted() {
    let mut bench = Bench::new(&["0 PKW, 2 PZD (PPO 3)", "3=16 words out"]);
    // Slot 2 takes its SlotDefinition default, 8 DI.
    assert_eq!(
        bench.send(Some(sap::GET_CFG), &[]),
        Some(vec![0xF1, 0x10, 0x6F])
    );
    assert_eq!(bench.configure(&[0xF3, 0xF1])[0], 0x06);
    assert_eq!(bench.configure(&[0xF1, 0x10, 0x6F])[0], 0x00);
    let dp = read_gsd(Path::new("modular.gsd"), GSD.as_bytes()).unwrap();
    let bad = parse_choices(&["8 DI"]).unwrap();
    assert_eq!(
        loopback(&dp, &bad, SLAVE, Instant::from_millis(0)).err(),
        Some(CardError::Modules(vec![
            "slot 1 (\"Drive\") does not take module \"8 DI\"".to_owned()
        ]))
    );
}

/// A modular slave with module parameters (the model's fixture): its own 3 bytes, AI16's 4,
/// DO8's 1 (Ident_Number 0008h).
const PRM_GSD: &str = include_str!("../../../../model/src/model/modules/module_prm.gsd");

/// Set_Prm (no watchdog, Ident_Number 0008h) with `user_prm` after the seven standard bytes,
/// then Chk_Cfg with `config`; the diagnosis.
fn parameterise(bench: &mut Bench, user_prm: &[u8], config: &[u8]) -> Vec<u8> {
    let mut prm = vec![0x00, 0, 0, 11, 0x00, 0x08, 0];
    prm.extend_from_slice(user_prm);
    bench.send(Some(sap::SET_PRM), &prm);
    bench.send(Some(sap::CHK_CFG), config);
    bench.send(Some(sap::SLAVE_DIAG), &[]).unwrap()
}

#[test]
fn a_plugged_slave_takes_its_modules_parameters_and_refuses_other_lengths_with_prm_fault() {
    let mut bench = Bench::of(PRM_GSD, &["DO8", "DI8", "AI16"]);
    // Its own 3 bytes, DO8's 1, AI16's 4: data exchange.
    let user_prm = [0, 0, 0, 0x06, 0x1F, 0x40, 0xF0, 0x60];
    let diag = parameterise(&mut bench, &user_prm, &[0x20, 0x10, 0x50]);
    assert_eq!(diag, [0x00, 0x04, 0x00, MASTER, 0x00, 0x08]);
    assert_eq!(bench.slave.state(), DpState::DataExchange);
    // Without AI16's 4 bytes: Prm_Fault and Station_Not_Ready, Prm_Req (the master it had
    // stays in byte 4).
    let diag = parameterise(&mut bench, &user_prm[..4], &[0x20, 0x10, 0x50]);
    assert_eq!(diag, [0x42, 0x05, 0x00, MASTER, 0x00, 0x08]);
    assert_eq!(bench.slave.state(), DpState::WaitPrm);
}

#[test]
fn a_slave_whose_master_picks_the_modules_takes_their_parameters_then_checks_them_in_chk_cfg() {
    let mut bench = Bench::of(PRM_GSD, &[]);
    // AI16 alone with its 4 bytes.
    let diag = parameterise(&mut bench, &[0, 0, 0, 0x1F, 0x40, 0xF0, 0x60], &[0x50]);
    assert_eq!(diag, [0x00, 0x04, 0x00, MASTER, 0x00, 0x08]);
    // DO8 and DI8 sent with AI16's 4 bytes: the modules named do not take them, Cfg_Fault.
    let diag = parameterise(
        &mut bench,
        &[0, 0, 0, 0x1F, 0x40, 0xF0, 0x60],
        &[0x20, 0x10],
    );
    assert_eq!(diag, [0x06, 0x05, 0x00, MASTER, 0x00, 0x08]);
    // Fewer than its own 3 bytes: Prm_Fault.
    let diag = parameterise(&mut bench, &[0, 0], &[0x50]);
    assert_eq!(diag[0], 0x42);
}
