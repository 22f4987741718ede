//! Stopping long-running commands cleanly (`simulate`, `bus`, ...): SIGINT (Ctrl-C), SIGTERM and
//! SIGHUP set one flag, which the command polls between its steps to shut down its threads and
//! exit 0, instead of dying half-way. One handler per process (ctrlc allows only one), installed
//! by the first [`install`].

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

static REQUESTED: AtomicBool = AtomicBool::new(false);
static INSTALLED: OnceLock<Result<(), String>> = OnceLock::new();

/// Catches SIGINT, SIGTERM and SIGHUP from now on; the error says why it cannot.
pub fn install() -> Result<(), String> {
    INSTALLED
        .get_or_init(|| {
            ctrlc::set_handler(|| REQUESTED.store(true, Ordering::SeqCst))
                .map_err(|e| format!("cannot catch SIGINT/SIGTERM: {e}"))
        })
        .clone()
}

/// The variable a machine (`simulate --machine`) sets for the buses it starts: its process ID.
pub const PARENT_VARIABLE: &str = "EDSGEN_STOP_WITH_PARENT";

/// When this process was started by a machine ([`PARENT_VARIABLE`]): a SIGTERM when the
/// machine ends, however it ends (killed included), so that no bus outlives it; a machine
/// already gone asks for the stop at once.
pub fn follow_parent() {
    let Some(parent) = std::env::var(PARENT_VARIABLE)
        .ok()
        .and_then(|v| v.parse::<i32>().ok())
    else {
        return;
    };
    let _ = nix::sys::prctl::set_pdeathsig(nix::sys::signal::Signal::SIGTERM);
    if nix::unistd::getppid().as_raw() != parent {
        REQUESTED.store(true, Ordering::SeqCst);
    }
}

/// Whether a stop was asked for.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::SeqCst)
}

/// The flag a stop sets, for a loop that polls an `AtomicBool` of its own (the EtherNet/IP
/// adapter's driver).
pub fn flag() -> &'static AtomicBool {
    &REQUESTED
}

/// Sleeps up to `timeout`, waking early when a stop is asked for; returns [`requested`].
pub fn wait(timeout: Duration) -> bool {
    let end = Instant::now() + timeout;
    while !requested() {
        let left = end.saturating_duration_since(Instant::now());
        if left.is_zero() {
            break;
        }
        std::thread::sleep(left.min(Duration::from_millis(20)));
    }
    requested()
}
