//! The demo over a real wire (root only: a visible skip otherwise, a failure under `CI=true`):
//! the [`edsgen::netns`] guard makes namespaces, veth pairs and addresses, runs programs inside
//! and leaves nothing behind, also when the code using it panics.

mod process_support;

use std::process::{Command, Stdio};
use std::time::Duration;

use edsgen::netns::{is_root, End, Network};
use process_support::skip;

/// The output of `ip ARGS` (empty when `ip` fails).
fn ip(args: &[&str]) -> String {
    Command::new("ip")
        .args(args)
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).into_owned())
        .unwrap_or_default()
}

/// Whether the host has a link of that name.
fn host_link(name: &str) -> bool {
    Command::new("ip")
        .args(["link", "show", name])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

fn namespaces() -> String {
    ip(&["netns", "list"])
}

#[test]
fn a_network_is_made_used_and_removed_without_a_trace() {
    if !is_root() {
        skip::<()>("not root: no network namespaces for the netns guard test");
        return;
    }
    let (names, links, pid);
    {
        let mut net = Network::create("t-netns", 2).expect("two namespaces");
        names = net.namespaces().to_vec();
        assert_eq!(names.len(), 2);
        let me = std::process::id();
        assert!(names[0].starts_with(&format!("edsgen-t-netns-{me}-")));
        let listed = namespaces();
        assert!(
            names.iter().all(|n| listed.contains(n.as_str())),
            "{listed}"
        );
        let (a, b) = net
            .veth(End::Namespace(0), End::Namespace(1))
            .expect("a veth pair between the namespaces");
        let (host, inside) = net
            .veth(End::Host, End::Namespace(0))
            .expect("a veth pair from the host");
        assert!(a.starts_with(&format!("tne{me}a")), "{a}");
        assert!(host_link(&host) && !host_link(&a) && !host_link(&b));
        net.address(0, &a, "10.233.0.1/24").expect("an address");
        net.address(1, &b, "10.233.0.2/24").expect("an address");
        let shown = ip(&["-n", &names[0], "-o", "addr", "show", "dev", &a]);
        assert!(shown.contains("inet 10.233.0.1/24"), "{shown}");
        let shown = ip(&["-n", &names[0], "-o", "link", "show", "dev", &inside]);
        assert!(shown.contains("state UP"), "{shown}");
        // A program inside namespace 1 sees its end and address, not the host's links.
        let mut command = net.command(1, "ip").expect("namespace 1");
        command.args(["-o", "addr", "show"]).stdout(Stdio::piped());
        let id = net.spawn(&mut command).expect("ip inside");
        let stdout = net.child(id).and_then(|c| c.stdout.take()).expect("stdout");
        let status = net.wait(id, Duration::from_secs(10)).expect("ip exits");
        assert!(status.success());
        let text = std::io::read_to_string(stdout).expect("its output");
        assert!(
            text.contains(&format!("{b}    inet 10.233.0.2/24")),
            "{text}"
        );
        assert!(!text.contains(&host), "{text}");
        // A long-running one is stopped on drop.
        let mut command = net.command(0, "sleep").expect("namespace 0");
        command.arg("600");
        let id = net.spawn(&mut command).expect("sleep inside");
        pid = net.child(id).expect("running").id();
        links = vec![host];
    }
    let listed = namespaces();
    assert!(
        names.iter().all(|n| !listed.contains(n.as_str())),
        "{listed}"
    );
    assert!(!host_link(&links[0]));
    assert!(!std::path::Path::new(&format!("/proc/{pid}")).exists());
}

#[test]
fn a_network_is_removed_when_its_user_panics() {
    if !is_root() {
        skip::<()>("not root: no network namespaces for the netns guard test");
        return;
    }
    let made = std::sync::Mutex::new(None);
    let result = std::panic::catch_unwind(|| {
        let mut net = Network::create("t-panic", 1).expect("a namespace");
        let (host, _) = net.veth(End::Host, End::Namespace(0)).expect("a pair");
        *made.lock().expect("not poisoned") = Some((net.namespaces()[0].clone(), host));
        panic!("the user of the network fails");
    });
    assert!(result.is_err());
    let (name, host) = made.into_inner().expect("not poisoned").expect("made");
    assert!(!namespaces().contains(&name));
    assert!(!host_link(&host));
}
