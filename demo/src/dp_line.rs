//! The DP card's steps on a real serial line (`demo --machine`): profirust's master in this
//! process over a pseudo-terminal ([`edsgen_host::dp_line::TtyPhy`]), in real time, against the
//! machine's simulated Goodrive350 DP card at the line's other end: data exchange, the manual's
//! PKW examples and CW/SW commands as in bus time ([`super::dp`]), then the master falls silent
//! and the card's watchdog ends data exchange, seen in its Slave_Diag.

use std::fs::OpenOptions;
use std::path::Path;
use std::time::{Duration, Instant};

use edsgen_host::dp_line::TtyPhy;
use profirust::{dp, Baudrate};

use super::dp::{check_gsd, hex, inputs_seen, master, pkw_steps, SLAVE};
use super::Trace;

/// How long one step may take in real time.
const STEP_TIME: Duration = Duration::from_secs(10);
/// How long the master falls silent: beyond the 200 ms watchdog.
const SILENCE: Duration = Duration::from_millis(500);

/// Runs the card's steps with the master on `tty`.
pub(super) fn run(trace: &mut Trace, tty: &Path) {
    trace.heading(&format!(
        "Goodrive350 DP card (station 2) on the machine's PROFIBUS line: profirust's master on \
         {}, in real time",
        tty.display()
    ));
    check_gsd(trace);
    let port = match OpenOptions::new().read(true).write(true).open(tty) {
        Ok(port) => port,
        Err(e) => return trace.step("open the line", Err(format!("{}: {e}", tty.display()))),
    };
    let mut phy = match TtyPhy::new(port, Baudrate::B19200) {
        Ok(phy) => phy,
        Err(e) => return trace.step("open the line", Err(format!("{}: {e}", tty.display()))),
    };
    let mut inputs = [0u8; 32];
    let mut out = [0u8; 32];
    let (mut master, handle, mut fdl) = master(&mut inputs, &mut out);
    let start = Instant::now();
    let mut until = |master: &mut dp::DpMaster, done: &dyn Fn(&[u8], bool) -> bool| {
        let end = Instant::now() + STEP_TIME;
        while Instant::now() < end {
            fdl.poll(profirust::time::Instant::now(), &mut phy, master);
            let peripheral = master.get_mut(handle);
            if done(peripheral.pi_i(), peripheral.is_running()) {
                return Some(start.elapsed().as_millis());
            }
            std::thread::sleep(Duration::from_micros(200));
        }
        None
    };
    let reached = until(&mut master, &|_, running| running);
    trace.step(
        "Set_Prm, Chk_Cfg, data exchange",
        match reached {
            Some(ms) => Ok(format!("data exchange after {ms} ms, 19.2 kbit/s")),
            None => Err(format!("no data exchange in {STEP_TIME:?}")),
        },
    );
    if reached.is_none() {
        return;
    }
    for (name, image, expected) in pkw_steps() {
        master.get_mut(handle).pi_q_mut().copy_from_slice(&image);
        let seen = until(&mut master, &|inputs, _| inputs[..12] == expected);
        let got = master.get_mut(handle).pi_i()[..12].to_vec();
        trace.step(name, inputs_seen(seen.is_some(), &got, &expected));
    }
    // The master falls silent; then one Slave_Diag from it.
    std::thread::sleep(SILENCE);
    let diag = (0..3).find_map(|_| phy.slave_diag(1, SLAVE, Duration::from_millis(200)));
    trace.step(
        "the master falls silent: the card's DP watchdog (200 ms) ends data exchange, Slave_Diag \
         says station not ready and asks for parameters (Prm_Req)",
        match diag {
            Some(d) if d[0] & 0x02 != 0 && d[1] & 0x01 != 0 => Ok(format!("diagnosis {}", hex(&d))),
            Some(d) => Err(format!("diagnosis {}", hex(&d))),
            None => Err("no Slave_Diag answer".into()),
        },
    );
}
