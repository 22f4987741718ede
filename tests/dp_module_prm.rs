//! Module parameters in Set_Prm (`Ext_Module_Prm_Data_Len`) with a corpus GSD that has them
//! (DPV10008: AI16 with two temperature limits, DI8, DO8 with two control bits): the exact
//! User_Prm_Data the model gives for its modules; pyprofibus, which appends each module's
//! parameters, and `edsgen dp io` bringing a slave plugged with those modules
//! (`simulate --profibus ... --module`) to data exchange. Without the venv or the corpus the
//! tests are skipped (`process_support`); under `CI=true` they fail.

mod process_support;

use std::time::Duration;

use edsgen_model::model::modules::{choose_dp, parse_choices};
use process_support::{gsd_corpus_dir, python, Process};

const WAIT: Duration = Duration::from_secs(20);
const GSD: &str = "zhaoxuji__profibus_DP_PA_soft/DPV10008.gsd";
const MODULES: [&str; 3] = [
    "AI16 (temperature)",
    "DI8 (enable-status)",
    "DO8 (enable-ctr)",
];

/// One line at a time: each test runs a relay, a slave and a master in real time.
static ONE_LINE: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn one_line() -> std::sync::MutexGuard<'static, ()> {
    ONE_LINE
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

#[test]
fn set_prm_carries_the_slaves_bytes_then_each_modules() {
    let Some(dir) = gsd_corpus_dir() else { return };
    let loaded = edsgen_model::load::load(&dir.join(GSD), None).expect("the GSD reads");
    let dp = loaded.device.dp().expect("a GSD");
    let plugged = choose_dp(dp, &parse_choices(&MODULES).expect("names")).expect("allowed");
    // Its own Ext_User_Prm_Data_Const(0) (3 bytes); AI16's 4: the limits' defaults 1F40h and
    // F060h big-endian; DI8 none; DO8's 1: 03h with "hot" (bit 0) and "cool" (bit 1) at their
    // defaults, 0.
    assert_eq!(
        plugged.user_prm_data(dp),
        [0x00, 0x00, 0x00, 0x1F, 0x40, 0xF0, 0x60, 0x00]
    );
    // The default configuration, AI16 alone.
    assert_eq!(
        dp.configuration().user_prm_data(dp),
        [0x00, 0x00, 0x00, 0x1F, 0x40, 0xF0, 0x60]
    );
}

#[test]
fn pyprofibus_sends_the_modules_parameters_and_the_plugged_slave_takes_them() {
    let _line = one_line();
    let (Some(python), Some(dir)) = (python(), gsd_corpus_dir()) else {
        return;
    };
    // pyprofibus's reader refuses the file's `0X60` (a capital X, which edsgen reads): it gets
    // a copy with that one spelling mended.
    let text = std::fs::read_to_string(dir.join(GSD)).expect("the GSD");
    let copy = std::env::temp_dir().join(format!("edsgen-dpv1-{}.gsd", std::process::id()));
    std::fs::write(&copy, text.replace("0X60", "0x60")).expect("a copy");
    let gsd = copy.to_string_lossy().into_owned();
    // Inputs: AI16's word and DI8's byte; outputs: DO8's byte. A Set_Prm without the modules'
    // 5 bytes would be a Prm_Fault, and no data exchange.
    let mut master_args = vec![gsd.as_str(), "6", "3", "1"];
    master_args.extend(MODULES);
    let master = Process::python(&python, "scripts/dp_master_modules.py", &master_args);
    let pty = master.stdout_line(|l| l.starts_with("PTY "), WAIT);
    let pty = pty.trim_start_matches("PTY ").to_owned();
    let served = format!("{gsd}@6");
    let mut args = vec!["simulate", "--profibus", pty.as_str(), served.as_str()];
    for module in MODULES {
        args.extend(["--module", module]);
    }
    let slave = Process::edsgen(&args);
    slave.stderr_line(|l| l == "data exchange", WAIT);
    let lines = [
        master.stdout_line(|l| l.starts_with("DATA_EXCHANGE"), WAIT),
        master.stdout_line(|l| l.starts_with("ECHO"), WAIT),
    ];
    let exited = master.finish(WAIT);
    let _ = std::fs::remove_file(&copy);
    assert_eq!(exited.code, Some(0), "{exited:?}");
    // The inputs echo the one output byte.
    assert_eq!(lines, ["DATA_EXCHANGE", "ECHO 010000"]);
}

#[test]
fn dp_io_sends_the_modules_parameters_to_a_plugged_slave() {
    let _line = one_line();
    let (Some(python), Some(dir)) = (python(), gsd_corpus_dir()) else {
        return;
    };
    let gsd = dir.join(GSD).to_string_lossy().into_owned();
    let pair = Process::python(&python, "scripts/pty_pair.py", &[]);
    let line = pair.stdout_line(|l| l.starts_with("PTY "), WAIT);
    let ends: Vec<&str> = line.split(' ').skip(1).collect();
    let served = format!("{gsd}@6");
    let mut args = vec!["simulate", "--profibus", ends[1], served.as_str()];
    for module in MODULES {
        args.extend(["--module", module]);
    }
    let slave = Process::edsgen(&args);
    slave.stderr_line(|l| l.starts_with("simulating DP slave 6"), WAIT);
    let mut io_args = vec![
        "dp",
        "io",
        ends[0],
        "--gsd",
        &gsd,
        "--address",
        "6",
        "--cycles",
        "5",
    ];
    for module in MODULES {
        io_args.extend(["--module", module]);
    }
    io_args.push("slot3.b0=0xA5");
    let io = Process::edsgen(&io_args).finish(WAIT);
    assert_eq!(io.code, Some(0), "{io:?}");
    // The slave echoes DO8's byte into AI16's first input byte.
    assert_eq!(
        io.stdout.lines().collect::<Vec<_>>(),
        ["slot1.w0 = 42240 (0xA500)", "slot2.b0 = 0 (0x00)"]
    );
}
