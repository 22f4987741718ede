//! Two pseudo-terminals joined by a relay, as `socat pty,raw,echo=0 pty,raw,echo=0` makes them:
//! the PROFIBUS line of `demo --machine`, the machine's DP slave on one end and the demo's DP
//! master on the other. Both ends are raw (no echo, no line editing: a telegram's bytes pass
//! as they are).

use std::fs::File;
use std::io::{Read, Write};
use std::path::PathBuf;

use nix::pty::openpty;
use nix::sys::termios::{self, SetArg};

/// The two ends' device paths (`/dev/pts/N`). The relay stops when the line is dropped.
pub(crate) struct Line {
    pub(crate) ends: [PathBuf; 2],
    /// The ends' own descriptors, held open: a pseudo-terminal's master reads an error, instead
    /// of waiting for bytes, while no one holds its other side.
    _held: [File; 2],
}

/// Opens two raw pseudo-terminals and relays bytes between them from two threads.
pub(crate) fn line() -> Result<Line, String> {
    let problem = |e: nix::Error| format!("a pseudo-terminal: {e}");
    let mut ends = Vec::new();
    let mut masters = Vec::new();
    let mut held = Vec::new();
    for _ in 0..2 {
        let pty = openpty(None, None).map_err(problem)?;
        let mut settings = termios::tcgetattr(&pty.slave).map_err(problem)?;
        termios::cfmakeraw(&mut settings);
        termios::tcsetattr(&pty.slave, SetArg::TCSANOW, &settings).map_err(problem)?;
        let fd = std::os::fd::AsRawFd::as_raw_fd(&pty.slave);
        let path = std::fs::read_link(format!("/proc/self/fd/{fd}"))
            .map_err(|e| format!("a pseudo-terminal's name: {e}"))?;
        ends.push(path);
        masters.push(File::from(pty.master));
        held.push(File::from(pty.slave));
    }
    let [a, b]: [File; 2] = masters.try_into().map_err(|_| "two pseudo-terminals")?;
    let (a2, b2) = (
        a.try_clone().map_err(|e| e.to_string())?,
        b.try_clone().map_err(|e| e.to_string())?,
    );
    relay(a, b2);
    relay(b, a2);
    Ok(Line {
        ends: ends.try_into().map_err(|_| "two names")?,
        _held: held.try_into().map_err(|_| "two pseudo-terminals")?,
    })
}

/// Copies what `from` reads to `to`, until either fails.
fn relay(mut from: File, mut to: File) {
    std::thread::spawn(move || {
        let mut buf = [0u8; 4096];
        while let Ok(n) = from.read(&mut buf) {
            if n == 0 || to.write_all(&buf[..n]).is_err() {
                return;
            }
        }
    });
}
