//! Private network namespaces for runs over a real wire (root only): a [`Network`] guard creates
//! uniquely named namespaces (`edsgen-TAG-PID-N`), veth pairs between them (or between one and
//! the host's namespace), addresses inside them, and runs programs inside them (`ip netns exec`);
//! when dropped it stops those programs and removes every namespace and link it made. Networks
//! alive when SIGINT, SIGTERM or SIGHUP comes are removed too ([`clean_up_on_signal`]).
//!
//! Everything goes through iproute2's `ip` and `kill` commands, so that this crate keeps no
//! `unsafe`: setting a namespace is `ip netns exec`'s job.

use std::ffi::OsStr;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Mutex, OnceLock};
use std::time::{Duration, Instant};

/// Whether this process runs as root (effective user ID 0), which namespaces and veth pairs
/// need.
pub fn is_root() -> bool {
    std::fs::read_to_string("/proc/self/status")
        .is_ok_and(|status| effective_uid(&status) == Some(0))
}

/// The effective user ID from `/proc/self/status` text (its `Uid:` line: real, effective, ...).
fn effective_uid(status: &str) -> Option<u32> {
    let line = status.lines().find(|l| l.starts_with("Uid:"))?;
    line.split_whitespace().nth(2)?.parse().ok()
}

/// What to say when `what` cannot run over a wire because this process is not root.
pub fn not_root(what: &str) -> String {
    format!("{what} needs root (for network namespaces and a veth pair)")
}

/// One end of a veth pair: in the host's namespace (where this process runs), or in one of the
/// network's namespaces (by its number, from 0).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum End {
    /// The namespace this process runs in.
    Host,
    /// The network's namespace number N.
    Namespace(usize),
}

/// A program started inside the network, kept by it (see [`Network::spawn`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ChildId(usize);

/// Namespaces, veth pairs and the programs running in them, removed when dropped (see the module
/// comment).
#[derive(Debug)]
pub struct Network {
    /// The key of this network in [`LIVE`].
    key: usize,
    tag: String,
    namespaces: Vec<String>,
    /// Links made in the host's namespace (the host ends of veth pairs).
    host_links: Vec<String>,
    children: Vec<Option<Child>>,
}

/// What a signal handler must remove: per live network, its namespaces, host links and programs.
#[derive(Debug, Default)]
struct Live {
    key: usize,
    namespaces: Vec<String>,
    host_links: Vec<String>,
    pids: Vec<u32>,
}

static LIVE: Mutex<Vec<Live>> = Mutex::new(Vec::new());
/// Numbers namespaces and links across the process, so that two networks never share a name.
static NEXT: AtomicUsize = AtomicUsize::new(0);
static HANDLER: OnceLock<Result<(), String>> = OnceLock::new();
/// Set by the signal handler before it removes the networks and ends the process.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// The longest interface name Linux takes (IFNAMSIZ less its terminating zero).
const IFNAME_MAX: usize = 15;

/// Runs `ip ARGS`; the error quotes the command and what `ip` said.
fn ip(args: &[&str]) -> Result<(), String> {
    let output = Command::new("ip")
        .args(args)
        .stdin(Stdio::null())
        .output()
        .map_err(|e| format!("cannot run `ip` (iproute2): {e}"))?;
    if output.status.success() {
        Ok(())
    } else {
        Err(format!(
            "`ip {}` failed: {}",
            args.join(" "),
            String::from_utf8_lossy(&output.stderr).trim()
        ))
    }
}

/// Sends SIGTERM to `pid` (a program this module started).
fn terminate(pid: u32) {
    let _ = Command::new("kill")
        .args(["-TERM", &pid.to_string()])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status();
}

fn update_live(key: usize, change: impl FnOnce(&mut Live)) {
    let mut live = LIVE.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    if let Some(entry) = live.iter_mut().find(|l| l.key == key) {
        change(entry);
    }
}

impl Network {
    /// `count` namespaces named `edsgen-TAG-PID-N`, each with its loopback up. `tag` says what
    /// the network is for (letters, digits and `-`, at most 12), and its first three characters
    /// start the names of the veth ends. Fails (having removed what it made) when not root or
    /// when `ip` refuses.
    pub fn create(tag: &str, count: usize) -> Result<Network, String> {
        if tag.is_empty()
            || tag.len() > 12
            || !tag.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'-')
        {
            return Err(format!(
                "`{tag}` is not a network tag (1 to 12 letters, digits or `-`)"
            ));
        }
        if !is_root() {
            return Err(not_root("a network namespace"));
        }
        let key = NEXT.fetch_add(1, Ordering::Relaxed);
        LIVE.lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
            .push(Live {
                key,
                ..Live::default()
            });
        let mut network = Network {
            key,
            tag: tag.to_owned(),
            namespaces: Vec::new(),
            host_links: Vec::new(),
            children: Vec::new(),
        };
        let pid = std::process::id();
        for _ in 0..count {
            let name = format!(
                "edsgen-{tag}-{pid}-{}",
                NEXT.fetch_add(1, Ordering::Relaxed)
            );
            ip(&["netns", "add", &name])?;
            network.namespaces.push(name.clone());
            update_live(key, |live| live.namespaces.push(name.clone()));
            ip(&["-n", &name, "link", "set", "lo", "up"])?;
        }
        Ok(network)
    }

    /// The name of namespace `n` (for `ip netns exec`, or to show).
    pub fn namespace(&self, n: usize) -> Option<&str> {
        self.namespaces.get(n).map(String::as_str)
    }

    /// The names of every namespace, in order.
    pub fn namespaces(&self) -> &[String] {
        &self.namespaces
    }

    fn checked(&self, end: End) -> Result<Option<&str>, String> {
        match end {
            End::Host => Ok(None),
            End::Namespace(n) => self.namespace(n).map(Some).ok_or_else(|| {
                format!("no namespace {n} in a network of {}", self.namespaces.len())
            }),
        }
    }

    /// A veth pair from `a` to `b`, both ends up: their interface names, `a`'s first. The names
    /// are unique in the process and the host (the tag's first three characters, the process
    /// ID, a number). A host end is removed on drop like the namespaces.
    pub fn veth(&mut self, a: End, b: End) -> Result<(String, String), String> {
        let (ns_a, ns_b) = (self.checked(a)?, self.checked(b)?);
        let (ns_a, ns_b) = (ns_a.map(str::to_owned), ns_b.map(str::to_owned));
        let short: String = self.tag.chars().filter(|c| *c != '-').take(3).collect();
        let pid = std::process::id();
        let n = NEXT.fetch_add(1, Ordering::Relaxed);
        let name_a = format!("{short}{pid}a{n}");
        let name_b = format!("{short}{pid}b{n}");
        if name_a.len() > IFNAME_MAX {
            return Err(format!("interface name `{name_a}` is too long"));
        }
        // Made in the host's namespace, then moved: until moved, both ends are host links.
        ip(&[
            "link", "add", &name_a, "type", "veth", "peer", "name", &name_b,
        ])?;
        self.host_links.push(name_a.clone());
        update_live(self.key, |live| live.host_links.push(name_a.clone()));
        for (name, ns) in [(&name_a, &ns_a), (&name_b, &ns_b)] {
            match ns {
                Some(ns) => {
                    ip(&["link", "set", name, "netns", ns])?;
                    ip(&["-n", ns, "link", "set", name, "up"])?;
                }
                None => ip(&["link", "set", name, "up"])?,
            }
        }
        if ns_a.is_some() {
            // The pair's host link is now `b` (if any): deleting either end deletes the pair.
            self.host_links.retain(|l| *l != name_a);
            update_live(self.key, |live| live.host_links.retain(|l| *l != name_a));
            if ns_b.is_none() {
                self.host_links.push(name_b.clone());
                update_live(self.key, |live| live.host_links.push(name_b.clone()));
            }
        }
        Ok((name_a, name_b))
    }

    /// Gives `iface` in namespace `n` the address `cidr` (such as `10.231.0.1/24`). Addresses
    /// go only inside the network's namespaces, never on the host.
    pub fn address(&self, n: usize, iface: &str, cidr: &str) -> Result<(), String> {
        let ns = self.checked(End::Namespace(n))?.unwrap_or_default();
        ip(&["-n", ns, "addr", "add", cidr, "dev", iface])
    }

    /// `program` to run inside namespace `n` (`ip netns exec NS PROGRAM`), to be given its
    /// arguments and standard streams, then started by [`Network::spawn`].
    pub fn command(&self, n: usize, program: impl AsRef<OsStr>) -> Result<Command, String> {
        let ns = self.checked(End::Namespace(n))?.unwrap_or_default();
        let mut command = Command::new("ip");
        command.args(["netns", "exec", ns]).arg(program);
        Ok(command)
    }

    /// Starts `command` (from [`Network::command`]); the network keeps the child and stops it
    /// when dropped (SIGTERM, then SIGKILL after two seconds).
    pub fn spawn(&mut self, command: &mut Command) -> Result<ChildId, String> {
        let child = command
            .spawn()
            .map_err(|e| format!("cannot start {command:?}: {e}"))?;
        let pid = child.id();
        update_live(self.key, |live| live.pids.push(pid));
        self.children.push(Some(child));
        Ok(ChildId(self.children.len() - 1))
    }

    /// The child, to take its standard streams or ask whether it is still running; `None` once
    /// it was waited for.
    pub fn child(&mut self, id: ChildId) -> Option<&mut Child> {
        self.children.get_mut(id.0).and_then(Option::as_mut)
    }

    /// Waits up to `timeout` for the child to exit by itself; `None` if it is still running
    /// then (it is left running), or was already waited for.
    pub fn wait(&mut self, id: ChildId, timeout: Duration) -> Option<ExitStatus> {
        let end = Instant::now() + timeout;
        loop {
            let child = self.child(id)?;
            match child.try_wait() {
                Ok(Some(status)) => {
                    self.forget(id);
                    return Some(status);
                }
                Ok(None) if Instant::now() < end => std::thread::sleep(Duration::from_millis(10)),
                Ok(None) | Err(_) => return None,
            }
        }
    }

    /// Stops the child: SIGTERM, then SIGKILL if it has not exited after `grace`. Its exit
    /// status (`None` if it was already waited for).
    pub fn stop(&mut self, id: ChildId, grace: Duration) -> Option<ExitStatus> {
        let pid = self.child(id)?.id();
        terminate(pid);
        if let Some(status) = self.wait(id, grace) {
            return Some(status);
        }
        let child = self.child(id)?;
        let _ = child.kill();
        let status = child.wait().ok();
        self.forget(id);
        status
    }

    fn forget(&mut self, id: ChildId) {
        if let Some(child) = self.children.get_mut(id.0).and_then(Option::take) {
            let pid = child.id();
            update_live(self.key, |live| live.pids.retain(|p| *p != pid));
        }
    }
}

impl Drop for Network {
    fn drop(&mut self) {
        for n in 0..self.children.len() {
            self.stop(ChildId(n), Duration::from_secs(2));
        }
        // A namespace's links go with it; a veth pair goes with either end.
        for link in &self.host_links {
            let _ = ip(&["link", "del", link]);
        }
        for ns in &self.namespaces {
            let _ = ip(&["netns", "del", ns]);
        }
        let mut live = LIVE.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        live.retain(|l| l.key != self.key);
    }
}

/// Removes every live network now (its programs sent SIGTERM, then its links and namespaces):
/// what a signal handler does before the process exits.
pub fn clean_up_all() {
    let live = std::mem::take(&mut *LIVE.lock().unwrap_or_else(|poisoned| poisoned.into_inner()));
    for network in &live {
        for pid in &network.pids {
            terminate(*pid);
        }
    }
    // Give the programs a moment to close their sockets, then remove the namespaces anyway: a
    // namespace whose last program has not exited yet goes when that program does.
    if live.iter().any(|l| !l.pids.is_empty()) {
        std::thread::sleep(Duration::from_millis(200));
    }
    for network in &live {
        for link in &network.host_links {
            let _ = ip(&["link", "del", link]);
        }
        for ns in &network.namespaces {
            let _ = ip(&["netns", "del", ns]);
        }
    }
}

/// From now on, SIGINT (Ctrl-C), SIGTERM and SIGHUP remove every live network
/// ([`clean_up_all`]) and exit with 130. For a command that uses networks and has no handler
/// of its own (one per process); installed once, the error says why it cannot be.
pub fn clean_up_on_signal() -> Result<(), String> {
    HANDLER
        .get_or_init(|| {
            ctrlc::set_handler(|| {
                INTERRUPTED.store(true, Ordering::SeqCst);
                clean_up_all();
                eprintln!("interrupted: network namespaces removed");
                std::process::exit(130);
            })
            .map_err(|e| format!("cannot catch SIGINT/SIGTERM: {e}"))
        })
        .clone()
}

/// Whether a signal came and its handler ([`clean_up_on_signal`]) is removing the networks,
/// after which it ends the process: what the programs in them said since is not to be reported
/// as a failure.
pub fn interrupted() -> bool {
    INTERRUPTED.load(Ordering::SeqCst)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_effective_uid_is_the_second_number_of_the_uid_line() {
        let status =
            "Name:\tedsgen\nUmask:\t0022\nUid:\t1000\t0\t0\t0\nGid:\t1000\t1000\t1000\t1000\n";
        assert_eq!(effective_uid(status), Some(0));
        let status = "Uid:\t0\t1000\t1000\t1000\n";
        assert_eq!(effective_uid(status), Some(1000));
        assert_eq!(effective_uid("Name:\tedsgen\n"), None);
    }

    #[test]
    fn a_tag_that_would_make_bad_names_is_refused() {
        for tag in ["", "has space", "a/b", "thirteen-long"] {
            let err = Network::create(tag, 1).expect_err(tag);
            assert!(err.contains("is not a network tag"), "{err}");
        }
    }
}
