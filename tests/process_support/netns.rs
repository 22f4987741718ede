//! Two network namespaces joined by a veth pair, for the tests that need a wire between a
//! device and its master: each end up with its addresses and its loopback, both deleted when
//! the guard drops (also on failure; deleting a namespace deletes its end of the pair, and with
//! it the pair). Names carry the test's pid, so parallel test binaries do not meet.

use std::process::Command;

/// The two namespaces: `near` (the devices' side) and `far` (the master's).
pub struct VethPair {
    /// The devices' namespace.
    pub near: String,
    /// The master's namespace.
    pub far: String,
}

impl VethPair {
    /// Creates `edsgen-TAG-PID-a` and `-b`, a veth pair between them, and the addresses
    /// (`ADDR/PREFIX`) of each end; panics with the `ip` step that failed. `tag` is at most 4
    /// characters: the veth names (`TAG` + pid + `a`/`b`) must fit the kernel's 15.
    pub fn create(tag: &str, near_addresses: &[&str], far_addresses: &[&str]) -> VethPair {
        let pid = std::process::id();
        let pair = VethPair {
            near: format!("edsgen-{tag}-{pid}-a"),
            far: format!("edsgen-{tag}-{pid}-b"),
        };
        let (near_end, far_end) = (format!("{tag}{pid}a"), format!("{tag}{pid}b"));
        let (near, far) = (pair.near.as_str(), pair.far.as_str());
        let mut steps: Vec<Vec<&str>> = vec![
            vec!["netns", "add", near],
            vec!["netns", "add", far],
            vec![
                "link", "add", &near_end, "type", "veth", "peer", "name", &far_end,
            ],
            vec!["link", "set", &near_end, "netns", near],
            vec!["link", "set", &far_end, "netns", far],
        ];
        for (ns, end, addresses) in [
            (near, &near_end, near_addresses),
            (far, &far_end, far_addresses),
        ] {
            for address in addresses {
                steps.push(vec!["-n", ns, "addr", "add", address, "dev", end]);
            }
            steps.push(vec!["-n", ns, "link", "set", end, "up"]);
            steps.push(vec!["-n", ns, "link", "set", "lo", "up"]);
        }
        for step in &steps {
            assert!(ip(step), "ip {step:?} failed");
        }
        pair
    }
}

impl Drop for VethPair {
    fn drop(&mut self) {
        ip(&["netns", "del", &self.near]);
        ip(&["netns", "del", &self.far]);
    }
}

/// Runs `ip ARGS`: whether it succeeded.
pub fn ip(args: &[&str]) -> bool {
    Command::new("ip")
        .args(args)
        .status()
        .is_ok_and(|s| s.success())
}

/// Whether this process runs as root (namespaces and veth pairs need it).
pub fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
}
