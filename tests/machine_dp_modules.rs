//! Two modular DP slaves from one GSD on one line, each plugged with its own modules by a
//! machine file (`modules = [...]`), brought up by `edsgen simulate --machine` on a
//! pseudo-terminal pair (`scripts/pty_pair.py`); `edsgen dp io` exchanges data with each by its
//! modules' names, exact bytes. Then SIGTERM stops the machine. Without the venv the test is
//! skipped (`process_support`); under `CI=true` it fails.

mod process_support;

use std::process::Command;
use std::time::Duration;

use process_support::{python, root, Process};

const WAIT: Duration = Duration::from_secs(30);

#[test]
fn a_machine_file_plugs_each_modular_slave_with_its_own_modules() {
    let Some(python) = python() else { return };
    let dir = std::env::temp_dir().join(format!("edsgen-machine-dp-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a directory");
    std::fs::copy(
        root().join("model/src/model/modules/modular.gsd"),
        dir.join("modular.gsd"),
    )
    .expect("the fixture");
    let pair = Process::python(&python, "scripts/pty_pair.py", &[]);
    let line = pair.stdout_line(|l| l.starts_with("PTY "), WAIT);
    let ends: Vec<&str> = line.split(' ').skip(1).collect();
    let machine = dir.join("machine.toml");
    std::fs::write(
        &machine,
        format!(
            "[[profibus]]\ntty = \"{}\"\ndevices = [\n\
             {{ device = \"modular.gsd@5\", modules = [\"0 PKW, 2 PZD (PPO 3)\", \"3=16 words out\"] }},\n\
             {{ device = \"modular.gsd@6\", modules = [\"4 PKW, 2 PZD (PPO 1)\"] }},\n]\n",
            ends[1]
        ),
    )
    .expect("the machine file");
    let running = Process::edsgen(&["simulate", "--machine", &machine.to_string_lossy()]);
    running.stderr_line(|l| l.contains("simulating DP slave 6"), WAIT);
    let gsd = dir.join("modular.gsd").to_string_lossy().into_owned();
    let io = |address: &str, extra: &[&str]| {
        let mut args = vec![
            "dp",
            "io",
            ends[0],
            "--gsd",
            &gsd,
            "--address",
            address,
            "--cycles",
            "5",
        ];
        args.extend_from_slice(extra);
        Process::edsgen(&args).finish(WAIT)
    };
    // Station 5: PPO 3, 8 DI (slot 2's default), 16 words out; its inputs (PPO 3's 4 bytes,
    // 8 DI's 1) echo the outputs (PPO 3's 4 bytes, then slot 3's 32).
    let five = io(
        "5",
        &[
            "--module",
            "0 PKW, 2 PZD (PPO 3)",
            "--module",
            "3=16 words out",
            "slot1.w1=0x0102",
            "slot3.w0=0xA0B0",
        ],
    );
    assert_eq!(five.code, Some(0), "{five:?}");
    assert_eq!(
        five.stdout.lines().collect::<Vec<_>>(),
        [
            "slot1.w0 = 0 (0x0000)",
            "slot1.w1 = 258 (0x0102)",
            "slot2.b0 = 160 (0xA0)"
        ]
    );
    // Station 6 is plugged with PPO 1 alone: PPO 3 is refused there (Cfg_Fault) ...
    let refused = io("6", &["--module", "0 PKW, 2 PZD (PPO 3)"]);
    assert_eq!(refused.code, Some(1), "{refused:?}");
    assert_eq!(
        refused.stderr,
        "station 6: configuration fault: it refused the Chk_Cfg bytes of the modules chosen\n"
    );
    // ... and PPO 1 exchanged: its 6 words echo.
    let six = io(
        "6",
        &["--module", "4 PKW, 2 PZD (PPO 1)", "w0=0x1234", "w5=0xBEEF"],
    );
    assert_eq!(six.code, Some(0), "{six:?}");
    assert_eq!(
        six.stdout.lines().collect::<Vec<_>>(),
        [
            "w0 = 4660 (0x1234)",
            "w1 = 0 (0x0000)",
            "w2 = 0 (0x0000)",
            "w3 = 0 (0x0000)",
            "w4 = 0 (0x0000)",
            "w5 = 48879 (0xBEEF)"
        ]
    );
    let pid = running.id().to_string();
    assert!(Command::new("kill")
        .args(["-TERM", &pid])
        .status()
        .is_ok_and(|s| s.success()));
    let stopped = running.finish(WAIT);
    let _ = std::fs::remove_dir_all(&dir);
    assert!(stopped.stderr.contains("stopped: machine"), "{stopped:?}");
}
