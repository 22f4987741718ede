//! Shared by the tests that start processes or need what the workspace does not hold: the
//! venv's python and the corpus (or a skip), and child processes (`edsgen bus`, `edsgen
//! simulate`, python scripts) read line by line with bounded waits and killed when their guard
//! drops.
//!
//! One rule for what a test needs and cannot find (python, its venv, the corpus, a target):
//! [`skip`] (`tests/skip_support`, shared with the codegen and runtime tests), a skip with a
//! message and a line in the skip log, except under `CI=true`, where it is a failure.
// Each test crate uses only some of these helpers.
#![allow(dead_code, unused_imports)]

use std::io::{BufRead, BufReader, Read, Write};
use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::process::{ChildStdin, Command, Stdio};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

pub mod netns;
#[path = "../skip_support/mod.rs"]
mod skip_support;
pub use skip_support::{ci, corpus, skip, target_dir};

/// The `edsgen` binary of this build.
pub const EDSGEN: &str = env!("CARGO_BIN_EXE_edsgen");

/// How long a child may take to say it is ready (`edsgen bus`, `edsgen simulate`, a script).
pub const START_TIMEOUT: Duration = Duration::from_secs(20);

/// The workspace root.
pub fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The venv's python, with the pinned `canopen` and `python-can`: `scripts/python-venv.sh`
/// creates the venv or installs what is missing, once per test process. `None` (a
/// [`skip`]) where that fails.
pub fn python() -> Option<PathBuf> {
    static PYTHON: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    let found = PYTHON.get_or_init(|| {
        let out = Command::new(root().join("scripts/python-venv.sh"))
            .stdin(Stdio::null())
            .output()
            .map_err(|e| format!("no python venv: cannot run scripts/python-venv.sh: {e}"))?;
        if !out.status.success() {
            return Err(format!(
                "no python venv: scripts/python-venv.sh failed:\n{}",
                String::from_utf8_lossy(&out.stderr)
            ));
        }
        Ok(PathBuf::from(String::from_utf8_lossy(&out.stdout).trim()))
    });
    match found {
        Ok(python) => Some(python.clone()),
        Err(why) => skip(why),
    }
}

/// The third-party corpus (`EDSGEN_CORPUS`, else `../shared/eds-corpus` beside the workspace,
/// present where its `MANIFEST.tsv` is), or a [`skip`].
pub fn corpus_dir() -> Option<PathBuf> {
    skip_support::eds_corpus()
}

/// The third-party ESI corpus (`EDSGEN_ESI_CORPUS`, else `../shared/esi-corpus`), or a
/// [`skip`].
pub fn esi_corpus_dir() -> Option<PathBuf> {
    skip_support::esi_corpus()
}

/// The ODVA EDS corpus (`EDSGEN_ODVA_CORPUS`, else `../shared/odva-eds-corpus`), or a [`skip`].
pub fn odva_corpus_dir() -> Option<PathBuf> {
    skip_support::corpus("EDSGEN_ODVA_CORPUS", "odva-eds-corpus")
}

/// The third-party GSDML corpus (`EDSGEN_GSDML_CORPUS`, else `../shared/gsdml-corpus`), or a
/// [`skip`].
pub fn gsdml_corpus_dir() -> Option<PathBuf> {
    skip_support::corpus("EDSGEN_GSDML_CORPUS", "gsdml-corpus")
}

/// The third-party GSD corpus (`EDSGEN_GSD_CORPUS`, else `../shared/gsd-corpus`), or a
/// [`skip`].
pub fn gsd_corpus_dir() -> Option<PathBuf> {
    skip_support::corpus("EDSGEN_GSD_CORPUS", "gsd-corpus")
}

/// A file of the third-party corpus, or a [`skip`].
pub fn corpus_file(relative: &str) -> Option<PathBuf> {
    let path = corpus_dir()?.join(relative);
    if path.exists() {
        Some(path)
    } else {
        skip(format!("{} not found (set EDSGEN_CORPUS)", path.display()))
    }
}

/// A running child process, killed and reaped when dropped. Its standard output and error are
/// read line by line on threads of their own, so a chatty child never blocks.
pub struct Process {
    child: std::process::Child,
    stdin: Option<ChildStdin>,
    stdout: Receiver<String>,
    stderr: Receiver<String>,
    /// What was started, for messages.
    what: String,
}

/// A child that has exited: its code (`None` if killed by a signal) and the output it had not
/// been asked for.
#[derive(Debug)]
pub struct Exited {
    /// The exit code.
    pub code: Option<i32>,
    /// The standard output's remaining lines.
    pub stdout: String,
    /// The standard error's remaining lines.
    pub stderr: String,
}

fn lines_of(reader: impl Read + Send + 'static) -> Receiver<String> {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(reader).lines().map_while(Result::ok) {
            if tx.send(line).is_err() {
                return;
            }
        }
    });
    rx
}

impl Drop for Process {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Process {
    /// Starts `command` with its standard input, output and error piped.
    pub fn start(command: &mut Command) -> Process {
        Process::spawn(command, true)
    }

    /// [`start`](Self::start), with the child's standard output closed at once: its writes there
    /// fail, as when whoever read its output went away.
    pub fn start_without_stdout(command: &mut Command) -> Process {
        Process::spawn(command, false)
    }

    fn spawn(command: &mut Command, read_stdout: bool) -> Process {
        let what = format!("{command:?}");
        let mut child = command
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap_or_else(|e| panic!("cannot start {what}: {e}"));
        let stdout = child.stdout.take().unwrap();
        Process {
            stdin: child.stdin.take(),
            stdout: if read_stdout {
                lines_of(stdout)
            } else {
                mpsc::channel().1
            },
            stderr: lines_of(child.stderr.take().unwrap()),
            child,
            what,
        }
    }

    /// `edsgen ARGS`, in the workspace root.
    pub fn edsgen(args: &[&str]) -> Process {
        Process::start(Command::new(EDSGEN).args(args).current_dir(root()))
    }

    /// `python SCRIPT ARGS`, the script named from the workspace root (`scripts/...`).
    pub fn python(python: &Path, script: &str, args: &[&str]) -> Process {
        Process::start(Command::new(python).arg(root().join(script)).args(args))
    }

    /// The child's process ID (for signals).
    pub fn id(&self) -> u32 {
        self.child.id()
    }

    /// The next line of standard output, if one comes within `timeout`.
    pub fn next_line(&self, timeout: Duration) -> Option<String> {
        self.stdout.recv_timeout(timeout).ok()
    }

    /// Waits at most `timeout` for a line of standard output for which `wanted` holds, skipping
    /// the others; panics with what came (and the standard error so far) if none does.
    pub fn stdout_line(&self, wanted: impl Fn(&str) -> bool, timeout: Duration) -> String {
        self.line_from(&self.stdout, "standard output", wanted, timeout)
    }

    /// [`stdout_line`](Self::stdout_line) for standard error.
    pub fn stderr_line(&self, wanted: impl Fn(&str) -> bool, timeout: Duration) -> String {
        self.line_from(&self.stderr, "standard error", wanted, timeout)
    }

    fn line_from(
        &self,
        lines: &Receiver<String>,
        stream: &str,
        wanted: impl Fn(&str) -> bool,
        timeout: Duration,
    ) -> String {
        let deadline = Instant::now() + timeout;
        let mut seen = Vec::new();
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match lines.recv_timeout(left) {
                Ok(line) if wanted(&line) => return line,
                Ok(line) => seen.push(line),
                Err(why) => {
                    let why = match why {
                        RecvTimeoutError::Timeout => format!("nothing within {timeout:?}"),
                        RecvTimeoutError::Disconnected => "the stream closed".to_owned(),
                    };
                    let other: Vec<String> = if stream == "standard error" {
                        self.stdout.try_iter().collect()
                    } else {
                        self.stderr.try_iter().collect()
                    };
                    panic!(
                        "{}: no such line on its {stream} ({why}); it said {seen:#?}\nand elsewhere {other:#?}",
                        self.what
                    );
                }
            }
        }
    }

    /// Writes one line to the child's standard input.
    pub fn send_line(&mut self, line: &str) {
        let stdin = self.stdin.as_mut().expect("standard input is open");
        writeln!(stdin, "{line}").expect("the child reads its standard input");
        stdin.flush().expect("the child reads its standard input");
    }

    /// Closes the child's standard input.
    pub fn close_stdin(&mut self) {
        self.stdin = None;
    }

    /// Waits at most `timeout` for the child to exit (killing it and failing the test if it
    /// does not), then collects the output nobody asked for.
    pub fn finish(mut self, timeout: Duration) -> Exited {
        self.stdin = None;
        let deadline = Instant::now() + timeout;
        let status = loop {
            if let Some(status) = self.child.try_wait().expect("wait for the child") {
                break status;
            }
            if Instant::now() >= deadline {
                let _ = self.child.kill();
                let stderr: Vec<String> = self.stderr.try_iter().collect();
                panic!(
                    "{} did not exit within {timeout:?}; its standard error: {stderr:#?}",
                    self.what
                );
            }
            std::thread::sleep(Duration::from_millis(10));
        };
        // The readers end at the end of the pipes; a grandchild could keep them open.
        let rest = |lines: &Receiver<String>| {
            let mut text = String::new();
            while let Ok(line) = lines.recv_timeout(Duration::from_secs(2)) {
                text.push_str(&line);
                text.push('\n');
            }
            text
        };
        Exited {
            code: status.code(),
            stdout: rest(&self.stdout),
            stderr: rest(&self.stderr),
        }
    }
}

/// `edsgen bus --listen 127.0.0.1:0 ARGS`, and the address it says it listens on.
pub fn edsgen_bus(args: &[&str]) -> (Process, SocketAddr) {
    let bus = Process::edsgen(&[&["bus", "--listen", "127.0.0.1:0"], args].concat());
    let first = bus.stdout_line(|_| true, START_TIMEOUT);
    let addr = first
        .split_whitespace()
        .find_map(|word| word.trim_end_matches(',').parse::<SocketAddr>().ok())
        .unwrap_or_else(|| panic!("no address in {first:?}"));
    (bus, addr)
}

/// `edsgen simulate ARGS`, once it has announced `nodes` simulated nodes (on standard error),
/// and those announcements.
pub fn edsgen_simulate(args: &[&str], nodes: usize) -> (Process, Vec<String>) {
    let sim = Process::edsgen(&[&["simulate"], args].concat());
    let announced = (0..nodes)
        .map(|_| sim.stderr_line(|line| line.starts_with("simulating node"), START_TIMEOUT))
        .collect();
    (sim, announced)
}
