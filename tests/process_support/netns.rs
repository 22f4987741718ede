//! A device's network namespace and its master's joined by a veth pair, with addresses on each
//! end, for the tests that need a wire: a thin layer over [`edsgen_demo::netns::Network`], which
//! names them uniquely and removes them, and what runs inside, when dropped (also on failure).

use std::process::Command;

pub use edsgen_demo::netns::is_root;
use edsgen_demo::netns::{End, Network};

/// Namespace 0 (the devices') and 1 (the master's), joined by a veth pair.
pub struct VethPair {
    /// The namespaces and their link.
    pub net: Network,
    /// The veth end in the devices' namespace.
    pub device_if: String,
    /// The veth end in the master's namespace.
    pub master_if: String,
}

impl VethPair {
    /// Creates both namespaces (`edsgen-TAG-PID-N`), the pair and its ends' addresses
    /// (`ADDR/PREFIX`); panics with what failed.
    pub fn new(tag: &str, device_addrs: &[&str], master_addrs: &[&str]) -> VethPair {
        let mut net = Network::create(tag, 2).expect("two namespaces");
        let (device_if, master_if) = net
            .veth(End::Namespace(0), End::Namespace(1))
            .expect("a veth pair");
        for addr in device_addrs {
            net.address(0, &device_if, addr).expect("an address");
        }
        for addr in master_addrs {
            net.address(1, &master_if, addr).expect("an address");
        }
        VethPair {
            net,
            device_if,
            master_if,
        }
    }

    /// `program` to run in namespace `n` (0 the devices', 1 the master's).
    pub fn inside(&self, n: usize, program: &str) -> Command {
        self.net.command(n, program).expect("a namespace")
    }

    /// The devices' namespace.
    pub fn devices(&self) -> &str {
        self.net.namespace(0).expect("two namespaces")
    }

    /// The master's namespace.
    pub fn master(&self) -> &str {
        self.net.namespace(1).expect("two namespaces")
    }
}
