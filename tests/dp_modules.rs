//! Modular DP slaves end to end: `edsgen simulate --profibus` serving a corpus MICROMASTER GSD
//! (SIEM8046, "PPO 1" or "PPO 3" in its one slot) accepts whichever PPO pyprofibus plugs
//! (`scripts/dp_master_modules.py`), and, plugged with `--module`, refuses the other with
//! Cfg_Fault as `edsgen dp io` names it; `dp io --module` sends a configuration of several
//! modules and sets and prints each module's data by name. Without the venv or the corpus the
//! tests are skipped (`process_support`); under `CI=true` they fail.

mod process_support;

use std::time::Duration;

use process_support::{gsd_corpus_dir, python, Process};

const WAIT: Duration = Duration::from_secs(20);
const MICROMASTER: &str = "ivangre4__PLC_Programms/SIEM8046.gse";
const PPO1: &str = "PPO 1:   4 PKW / 2 PZD";
const PPO3: &str = "PPO 3:   0 PKW / 2 PZD";

/// pyprofibus plugs `modules` (inputs and outputs of `sizes`) into the slave that
/// `simulate --profibus PTY slave_args` serves; its step lines.
fn exchange(
    slave_args: &[&str],
    gsd: &str,
    sizes: (usize, usize),
    modules: &[&str],
) -> Vec<String> {
    let python = python().expect("checked by the caller");
    let (input_size, output_size) = (sizes.0.to_string(), sizes.1.to_string());
    let mut master_args = vec![gsd, "6", &input_size, &output_size];
    master_args.extend_from_slice(modules);
    let master = Process::python(&python, "scripts/dp_master_modules.py", &master_args);
    let pty = master.stdout_line(|l| l.starts_with("PTY "), WAIT);
    let pty = pty.trim_start_matches("PTY ").to_owned();
    let mut args = vec!["simulate", "--profibus", pty.as_str()];
    args.extend_from_slice(slave_args);
    let slave = Process::edsgen(&args);
    slave.stderr_line(|l| l == "data exchange", WAIT);
    let lines = vec![
        master.stdout_line(|l| l.starts_with("DATA_EXCHANGE"), WAIT),
        master.stdout_line(|l| l.starts_with("ECHO"), WAIT),
    ];
    let exited = master.finish(WAIT);
    assert_eq!(exited.code, Some(0), "{exited:?}");
    lines
}

/// One line at a time: each test runs a relay, a slave and a master in real time at 19.2 kbit/s,
/// and three at once on two loaded cores miss the master's slot time.
static ONE_LINE: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn one_line() -> std::sync::MutexGuard<'static, ()> {
    ONE_LINE
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

#[test]
fn pyprofibus_plugs_either_ppo_and_the_slave_accepts_it() {
    let _line = one_line();
    let (Some(_), Some(dir)) = (python(), gsd_corpus_dir()) else {
        return;
    };
    let gsd = dir.join(MICROMASTER).to_string_lossy().into_owned();
    let served = format!("{gsd}@6");
    // PPO 3 (00h F1h): 2 words each way.
    assert_eq!(
        exchange(&[&served], &gsd, (4, 4), &[PPO3]),
        ["DATA_EXCHANGE", "ECHO 01020304"]
    );
    // PPO 1 (F3h F1h): 6 words each way, from the same slave's file.
    assert_eq!(
        exchange(&[&served], &gsd, (12, 12), &[PPO1]),
        ["DATA_EXCHANGE", "ECHO 0102030405060708090a0b0c"]
    );
}

/// Two pseudo-terminals joined (`scripts/pty_pair.py`): the slave's end and the master's.
fn pty_pair(python: &std::path::Path) -> (Process, String, String) {
    let pair = Process::python(python, "scripts/pty_pair.py", &[]);
    let line = pair.stdout_line(|l| l.starts_with("PTY "), WAIT);
    let ends: Vec<&str> = line.split(' ').skip(1).collect();
    let (a, b) = (ends[0].to_owned(), ends[1].to_owned());
    (pair, a, b)
}

#[test]
fn a_slave_plugged_with_modules_refuses_others_as_dp_io_names_it() {
    let _line = one_line();
    let (Some(python), Some(dir)) = (python(), gsd_corpus_dir()) else {
        return;
    };
    let gsd = dir.join(MICROMASTER).to_string_lossy().into_owned();
    let (_pair, a, b) = pty_pair(&python);
    let served = format!("{gsd}@6");
    let slave = Process::edsgen(&["simulate", "--profibus", &b, &served, "--module", PPO3]);
    slave.stderr_line(|l| l.starts_with("simulating DP slave 6"), WAIT);
    let io = |extra: &[&str]| {
        let mut args = vec![
            "dp",
            "io",
            &a,
            "--gsd",
            &gsd,
            "--address",
            "6",
            "--cycles",
            "5",
        ];
        args.extend_from_slice(extra);
        Process::edsgen(&args).finish(WAIT)
    };
    let plugged = io(&["--module", PPO3, "w0=0x1234", "w1=7"]);
    assert_eq!(plugged.code, Some(0), "{plugged:?}");
    assert_eq!(
        plugged.stdout.lines().collect::<Vec<_>>(),
        ["w0 = 4660 (0x1234)", "w1 = 7 (0x0007)"]
    );
    // Without --module, dp io sends the GSD's first module, PPO 1: a real slave plugged with
    // PPO 3 sets Cfg_Fault.
    let other = io(&[]);
    assert_eq!(other.code, Some(1), "{other:?}");
    assert_eq!(
        other.stderr,
        "station 6: configuration fault: it refused the Chk_Cfg bytes of the modules chosen\n"
    );
    let unknown = io(&["--module", "PPO 9"]);
    assert_eq!(unknown.code, Some(2));
    assert_eq!(
        unknown.stderr,
        format!(
            "error: {gsd}: --module: slot 1: no module \"PPO 9\"; did you mean:\n  \"{}\"\n  \"{}\"\n",
            "PPO 1:   4 PKW / 2 PZD        ".trim(),
            "PPO 3:   0 PKW / 2 PZD        ".trim()
        )
    );
}

/// A station of three slots (the model's test GSD): a PPO, 8 inputs, 16 output words.
const MODULAR: &str = "#Profibus_DP
GSD_Revision = 3
Vendor_Name = \"Test\"
Model_Name = \"Modular\"
Ident_Number = 0x1234
Protocol_Ident = 0
Station_Type = 0
19.2_supp = 1
MaxTsdr_19.2 = 60
Modular_Station = 1
Max_Module = 3
Max_Input_Len = 40
Max_Output_Len = 48
Max_Data_Len = 70
Module = \"4 PKW, 2 PZD (PPO 1)\" 0xF3, 0xF1
1
EndModule
Module = \"0 PKW, 2 PZD (PPO 3)\" 0xF1
2
EndModule
Module = \"8 DI\" 0x10
3
EndModule
Module = \"16 words out\" 0x6F
4
EndModule
SlotDefinition
Slot(1) = \"Drive\" 1 1-2
Slot(2) = \"IO\" 3 3-4
Slot(3) = \"IO\" 3 3-4
EndSlotDefinition
";

#[test]
fn dp_io_sets_and_prints_every_modules_data_by_slot() {
    let _line = one_line();
    let Some(python) = python() else { return };
    let gsd = std::env::temp_dir().join(format!("edsgen-dp-modules-{}.gsd", std::process::id()));
    std::fs::write(&gsd, MODULAR).expect("a temporary GSD");
    let gsd = gsd.to_string_lossy().into_owned();
    let (_pair, a, b) = pty_pair(&python);
    // The simulated slave starts with PPO 1 alone and accepts any allowed combination.
    let slave = Process::edsgen(&["simulate", "--profibus", &b, &format!("{gsd}@6")]);
    slave.stderr_line(|l| l.starts_with("simulating DP slave 6"), WAIT);
    let io = Process::edsgen(&[
        "dp",
        "io",
        &a,
        "--gsd",
        &gsd,
        "--address",
        "6",
        "--cycles",
        "5",
        "--module",
        "0 PKW, 2 PZD (PPO 3)",
        "--module",
        "3=16 words out",
        "slot1.w1=0x0102",
        "slot3.w0=0xA0B0",
    ])
    .finish(WAIT);
    let _ = std::fs::remove_file(&gsd);
    assert_eq!(io.code, Some(0), "{io:?}");
    // Slot 2 took its default (8 DI); the inputs (PPO 3's 4 bytes, 8 DI's 1) echo the outputs
    // (PPO 3's 4 bytes, then the 32 of slot 3).
    assert_eq!(
        io.stdout.lines().collect::<Vec<_>>(),
        [
            "slot1.w0 = 0 (0x0000)",
            "slot1.w1 = 258 (0x0102)",
            "slot2.b0 = 160 (0xA0)"
        ]
    );
}
