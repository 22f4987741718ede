//! The Message Router dispatches through its registry: an object an application registers is
//! reached by its class ID, one registered with a standard class ID replaces that object, and a
//! class no object has is "path destination unknown" (0x05).

use std::collections::BTreeMap;

use edsgen_runtime::Instant;

use super::state::DeviceState;
use super::{Adapter, Assembly, CipObject, Identity};

/// An object of the class ID it is given whose attribute 1 of instance 1 is the vendor ID's low byte.
#[derive(Debug)]
struct Vendor(u32);

impl CipObject for Vendor {
    fn class_id(&self) -> u32 {
        self.0
    }

    fn attribute(&self, device: &DeviceState, _instance: u32, attribute: u32) -> Option<Vec<u8>> {
        (attribute == 1).then(|| vec![device.identity.vendor as u8])
    }
}

fn adapter() -> Adapter {
    let identity = Identity {
        vendor: 0x01AB,
        device_type: 12,
        product_code: 350,
        revision: (1, 10),
        serial: 7,
        name: "GD350".to_owned(),
    };
    let mut assemblies = BTreeMap::new();
    assemblies.insert(
        100,
        Assembly {
            data: vec![0; 4],
            consumed: false,
        },
    );
    Adapter::new(identity, assemblies, [192, 168, 0, 1])
}

const T0: Instant = Instant::from_micros(0);

#[test]
fn the_router_reaches_registered_objects_by_class() {
    let mut a = adapter();
    // Get_Attribute_Single 0x64/1/1: no object has class 0x64 yet.
    let get = [0x0E, 3, 0x20, 0x64, 0x24, 0x01, 0x30, 0x01];
    assert_eq!(a.route(7, &get, T0), [0x8E, 0, 0x05, 0]);
    a.registry.register(&Vendor(0x64));
    assert_eq!(a.route(7, &get, T0), [0x8E, 0, 0, 0, 0xAB]);
    // Its attribute 2 is unsupported (0x14), Set_Attribute_Single not settable (0x0E), another
    // instance does not exist (0x16), Get_Attributes_All not a service it has (0x08).
    assert_eq!(
        a.route(7, &[0x0E, 3, 0x20, 0x64, 0x24, 0x01, 0x30, 0x02], T0),
        [0x8E, 0, 0x14, 0]
    );
    assert_eq!(
        a.route(7, &[0x10, 3, 0x20, 0x64, 0x24, 0x01, 0x30, 0x01, 9], T0),
        [0x90, 0, 0x0E, 0]
    );
    assert_eq!(
        a.route(7, &[0x0E, 3, 0x20, 0x64, 0x24, 0x02, 0x30, 0x01], T0),
        [0x8E, 0, 0x16, 0]
    );
    assert_eq!(
        a.route(7, &[0x01, 2, 0x20, 0x64, 0x24, 0x01], T0),
        [0x81, 0, 0x08, 0]
    );
}

#[test]
fn a_registered_class_replaces_the_standard_object() {
    let mut a = adapter();
    // Identity attribute 1, the vendor ID, as the standard object gives it.
    let get = [0x0E, 3, 0x20, 0x01, 0x24, 0x01, 0x30, 0x01];
    assert_eq!(a.route(7, &get, T0), [0x8E, 0, 0, 0, 0xAB, 0x01]);
    a.registry.register(&Vendor(1));
    assert_eq!(a.route(7, &get, T0), [0x8E, 0, 0, 0, 0xAB]);
    assert_eq!(a.registry.find(1).map(|o| o.class_id()), Some(1));
    assert!(a.registry.find(0x64).is_none());
}
