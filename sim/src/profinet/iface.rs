//! The IPv4 addresses of a network interface (Linux `getifaddrs`), in the kernel's order: what
//! a simulated device reports when no address is given, and what a controller derives a
//! device's address from.

use std::io;

/// An IPv4 address and its netmask.
pub type Ipv4WithMask = ([u8; 4], [u8; 4]);

/// The IPv4 addresses of `iface`, first the primary one.
pub fn ipv4_addresses(iface: &str) -> io::Result<Vec<Ipv4WithMask>> {
    let v4 = |a: Option<&nix::sys::socket::SockaddrStorage>| {
        a.and_then(|a| a.as_sockaddr_in()).map(|s| s.ip().octets())
    };
    Ok(nix::ifaddrs::getifaddrs()
        .map_err(io::Error::from)?
        .filter(|entry| entry.interface_name == iface)
        .filter_map(|entry| {
            let address = v4(entry.address.as_ref())?;
            Some((address, v4(entry.netmask.as_ref()).unwrap_or([0; 4])))
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_loopback_interface_has_127_0_0_1_slash_8() {
        let found = ipv4_addresses("lo").expect("getifaddrs");
        assert_eq!(found.first(), Some(&([127, 0, 0, 1], [255, 0, 0, 0])));
    }

    #[test]
    fn an_unknown_interface_has_no_address() {
        assert_eq!(ipv4_addresses("no-such-if0").expect("getifaddrs"), vec![]);
    }
}
