//! The master's SDO client typed by the generated bindings against a device node serving the
//! generated cp301 card on the virtual bus: `cp301::od::STATUSWORD` reads as a `u16`,
//! `VL_TARGET_VELOCITY` writes an `i16`, and the boot-up identity entries read as `u32`.

use edsgen_host::vbus::VirtualBus;
use edsgen_runtime::master::SdoClient;
use edsgen_runtime::node::Node;
use edsgen_runtime::od::access::Readable;
use edsgen_runtime::{Entry, Instant, OdValue};
use edsgen_sim::cards::cp301::{self, od};

fn ms(millis: u64) -> Instant {
    Instant::from_millis(millis)
}

/// Reads `entry` of node 3 through `client`, typed.
fn read<T: OdValue, D, A: Readable>(
    bus: &mut VirtualBus,
    client: &mut SdoClient,
    node: &mut Node<cp301::Od>,
    entry: Entry<T, D, A>,
) -> T {
    client.read(bus.now(), entry).unwrap();
    let until = bus.now() + edsgen_runtime::Duration::from_millis(1);
    bus.run_until(until, &mut [client, node]);
    client.poll_result().unwrap().unwrap();
    client.take_value(&entry).unwrap()
}

#[test]
fn reads_and_writes_are_typed_by_the_generated_addresses() {
    let mut node = Node::new(cp301::Od::new(3), 3, ms(0)).unwrap();
    let mut client: SdoClient = SdoClient::new(3);
    let mut bus = VirtualBus::new(ms(0));
    client.write(ms(0), od::VL_TARGET_VELOCITY, &-1500).unwrap();
    bus.run_until(ms(1), &mut [&mut client, &mut node]);
    assert!(client.poll_result().unwrap().is_ok());
    let velocity: i16 = read(&mut bus, &mut client, &mut node, od::VL_TARGET_VELOCITY);
    assert_eq!(velocity, -1500);
    let status: u16 = read(&mut bus, &mut client, &mut node, od::STATUSWORD);
    assert_eq!(status, node.od().get(od::STATUSWORD));
    let vendor: u32 = read(
        &mut bus,
        &mut client,
        &mut node,
        od::identity_object::VENDOR_ID,
    );
    assert_eq!(vendor, cp301::VENDOR_ID);
    assert_eq!(node.od().get(od::VL_TARGET_VELOCITY), -1500);
}
