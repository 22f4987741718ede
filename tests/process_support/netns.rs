//! Two private network namespaces joined by a veth pair, for the tests against third-party
//! PROFINET peers over raw sockets (root): unique names from a tag and the test's pid, both
//! namespaces deleted on drop (and with them the pair), also when the test fails.

use std::process::Command;

/// Runs `ip` with `args`; the test fails if it does.
pub fn ip(args: &[&str]) {
    let status = Command::new("ip").args(args).status().expect("ip runs");
    assert!(status.success(), "ip {args:?} failed");
}

/// `true` when the test runs as root.
pub fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
}

/// The two namespaces, and the names of the veth ends in them.
pub struct Link {
    /// The device's namespace.
    pub device_ns: String,
    /// The controller's namespace.
    pub controller_ns: String,
    /// The veth end in the device's namespace.
    pub device_if: String,
    /// The veth end in the controller's namespace.
    pub controller_if: String,
}

impl Link {
    /// The namespaces `{tag}-dev-PID` and `{tag}-ctl-PID`, the pair `{tag}dPID`/`{tag}cPID`
    /// up, and the addresses given (`ADDR/PREFIX`) on each end.
    pub fn new(tag: &str, controller_addr: &str, device_addr: Option<&str>) -> Link {
        let pid = std::process::id();
        let link = Link {
            device_ns: format!("{tag}-dev-{pid}"),
            controller_ns: format!("{tag}-ctl-{pid}"),
            device_if: format!("{tag}d{pid}"),
            controller_if: format!("{tag}c{pid}"),
        };
        ip(&["netns", "add", &link.device_ns]);
        ip(&["netns", "add", &link.controller_ns]);
        let (dev, ctl) = (&link.device_if, &link.controller_if);
        ip(&["link", "add", dev, "type", "veth", "peer", "name", ctl]);
        ip(&["link", "set", dev, "netns", &link.device_ns]);
        ip(&["link", "set", ctl, "netns", &link.controller_ns]);
        ip(&["-n", &link.device_ns, "link", "set", dev, "up"]);
        ip(&["-n", &link.controller_ns, "link", "set", ctl, "up"]);
        ip(&[
            "-n",
            &link.controller_ns,
            "addr",
            "add",
            controller_addr,
            "dev",
            ctl,
        ]);
        if let Some(addr) = device_addr {
            ip(&["-n", &link.device_ns, "addr", "add", addr, "dev", dev]);
        }
        link
    }
}

impl Drop for Link {
    fn drop(&mut self) {
        // Deleting a namespace deletes the veth end inside it, and so the pair.
        for ns in [&self.device_ns, &self.controller_ns] {
            let _ = Command::new("ip").args(["netns", "del", ns]).status();
        }
    }
}
