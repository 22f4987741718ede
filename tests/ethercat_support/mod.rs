//! What the EtherCAT wire tests share: a private network namespace with a veth pair, the
//! simulator and this test binary (as the MainDevice, by role) started in it, and the ESI corpus
//! files the simulator can serve to Op.

// Each test binary takes the parts it needs.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

use edsgen_runtime::ObjectDictionary;
use edsgen_sim::ethercat::{Application, EsiDevice};

use crate::process_support::{Process, EDSGEN, START_TIMEOUT};

/// The variable naming the role this test binary plays when run as the MainDevice.
pub const ROLE: &str = "EDSGEN_ECAT_ROLE";
/// The variable naming the MainDevice's interface.
pub const IFACE: &str = "EDSGEN_ECAT_IFACE";

/// A private network namespace with a veth pair `ecm` (MainDevice) / `ecs` (SubDevice), deleted
/// when dropped.
pub struct Namespace {
    name: String,
}

impl Namespace {
    pub fn new() -> Self {
        let name = format!("edsgen-ethercat-{}", std::process::id());
        let ns = Namespace { name };
        ns.ip(&["netns", "add", &ns.name]);
        for args in [
            &["link", "add", "ecm", "type", "veth", "peer", "name", "ecs"][..],
            &["link", "set", "ecm", "up"],
            &["link", "set", "ecs", "up"],
        ] {
            ns.ip(&[&["-n", &ns.name][..], args].concat());
        }
        ns
    }

    pub fn ip(&self, args: &[&str]) {
        let status = Command::new("ip").args(args).status().expect("ip");
        assert!(status.success(), "ip {args:?} failed");
    }

    /// `ip netns exec NS PROGRAM ARGS`.
    pub fn exec(&self, program: &str, args: &[&str]) -> Command {
        let mut command = Command::new("ip");
        command
            .args(["netns", "exec", &self.name, program])
            .args(args);
        command
    }

    pub fn simulator(&self, args: &[&str]) -> Process {
        let mut command = self.exec(
            EDSGEN,
            &[&["simulate", "--ethercat", "ecs"][..], args].concat(),
        );
        let sim = Process::start(&mut command);
        sim.stderr_line(|l| l.starts_with("serving "), START_TIMEOUT);
        sim
    }

    pub fn master(&self, role: &str) -> Process {
        let me = std::env::current_exe().expect("this test");
        let mut command = self.exec(me.to_str().expect("a path"), &[]);
        command.env(ROLE, role).env(IFACE, "ecm");
        Process::start(&mut command)
    }
}

impl Drop for Namespace {
    fn drop(&mut self) {
        let _ = Command::new("ip")
            .args(["netns", "del", &self.name])
            .status();
    }
}

/// The image sizes of a device the simulator can serve to Op: an ESI device (not modular) with a
/// CoE mailbox
/// (both mailbox SyncManagers), 1C12h/1C13h for its process-data SyncManagers, process data in
/// at least one direction, and every mapped object in the dictionary with the mapped size.
pub fn complete_enough(model: &edsgen_model::model::Device) -> Option<(usize, usize)> {
    use edsgen_model::model::SmKind;
    let ec = model.ethercat()?;
    ec.coe.as_ref()?;
    // A modular device's process data depends on the modules plugged in.
    if !ec.slots.is_empty() {
        return None;
    }
    let has = |kind: SmKind| ec.sync_managers.iter().position(|sm| sm.kind == kind);
    // Mailbox SyncManagers the ESI leaves disabled (`Enable="0"`) cannot carry CoE.
    for kind in [SmKind::MailboxOut, SmKind::MailboxIn] {
        if !ec.sync_managers[has(kind)?].enable {
            return None;
        }
    }
    let device = EsiDevice::new(model, None).ok()?;
    let od = device.dictionary();
    for (kind, outputs) in [(SmKind::Outputs, true), (SmKind::Inputs, false)] {
        if let Some(n) = has(kind) {
            od.find(0x1C10 + n as u16, 0).ok()?;
            for (index, sub, bits) in device.image(outputs) {
                if index == 0 {
                    continue;
                }
                let len = od.value_len(index, sub).ok()?;
                if !(len * 8 == usize::from(bits) || (bits < 8 && len == 1)) {
                    return None;
                }
            }
        }
    }
    let sizes = device.image_sizes();
    (sizes != (0, 0)).then_some(sizes)
}

/// The ESI files under `dir`, recursively.
pub fn collect(dir: &Path, files: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("the corpus").flatten() {
        let path = entry.path();
        if path.is_dir() {
            collect(&path, files);
        } else if path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("xml") || e.eq_ignore_ascii_case("esi"))
        {
            files.push(path);
        }
    }
}
