//! Class-3 connected explicit messaging against exact bytes: the Forward_Open of a class-3
//! connection, SendUnitData with its sequence count and retransmissions, the connection's
//! timeout and its end with its session, and the refusals.

use edsgen_runtime::enip::wire::cpf::item;
use edsgen_runtime::{Duration, Instant};

use super::tests::{
    adapter, class3_open, encap, explicit, forward_open, reply, session, ROUTER, T0,
};
use super::tests_support::{emit_items, events, produce, Encapsulation};
use super::{Adapter, Event};

/// SendUnitData on connection `id` with sequence count `sequence` at `now`: the encapsulation
/// status and data of the reply.
fn unit_data<A: super::EnipApplication>(
    a: &mut Adapter<A>,
    session: u32,
    id: u32,
    sequence: u16,
    request: &[u8],
    now: Instant,
) -> (u32, Vec<u8>) {
    let mut payload = sequence.to_le_bytes().to_vec();
    payload.extend_from_slice(request);
    let mut data = vec![0; 6];
    data.extend(emit_items(&[
        (item::CONNECTED_ADDRESS, &id.to_le_bytes()),
        (item::CONNECTED_DATA, &payload),
    ]));
    let (out, _) = a
        .request(7, &encap(0x70, session, &data), now)
        .expect("complete");
    let r = Encapsulation::parse(&out.expect("a reply"))
        .expect("parses")
        .0;
    assert_eq!(
        (r.command, r.session, &r.context),
        (0x70, session, b"ctx12345")
    );
    (r.status, r.data)
}

/// The reply SendUnitData should carry: T→O ID 0x3000_0007, the count, the response.
fn connected(sequence: u16, response: &[u8]) -> Vec<u8> {
    let mut payload = sequence.to_le_bytes().to_vec();
    payload.extend_from_slice(response);
    let mut data = vec![0; 6];
    data.extend(emit_items(&[
        (item::CONNECTED_ADDRESS, &0x3000_0007u32.to_le_bytes()),
        (item::CONNECTED_DATA, &payload),
    ]));
    data
}

#[test]
fn class3_forward_open_send_unit_data_and_forward_close() {
    let mut a = adapter();
    let s = session(&mut a);
    let ok = explicit(&mut a, s, &class3_open(0x54, 5, 2_000_000, 0xA3, &ROUTER));
    let mut expected = vec![0xD4, 0, 0, 0];
    expected.extend_from_slice(&0x1000_0001u32.to_le_bytes());
    expected.extend_from_slice(&0x3000_0007u32.to_le_bytes());
    expected.extend_from_slice(&[5, 0, 1, 0, 0xFE, 0xCA, 0xAD, 0x0B]);
    expected.extend_from_slice(&2_000_000u32.to_le_bytes());
    expected.extend_from_slice(&2_000_000u32.to_le_bytes());
    expected.extend_from_slice(&[0, 0]);
    assert_eq!(ok, expected);
    let id = 0x1000_0001;
    assert_eq!(events(&mut a), vec![Event::Opened(id)]);
    assert_eq!(
        a.explicit_connections()[0].timeout,
        Duration::from_micros(8_000_000)
    );
    // Get_Attribute_Single @1/1/3 on the connection: product code 350, count echoed.
    let get = [0x0E, 3, 0x20, 0x01, 0x24, 0x01, 0x30, 0x03];
    assert_eq!(
        unit_data(&mut a, s, id, 1, &get, T0),
        (0, connected(1, &[0x8E, 0, 0, 0, 0x5E, 0x01]))
    );
    // A write, then the same count again: the same reply, not executed twice.
    let mut set = vec![0x10, 3, 0x20, 0x04, 0x24, 0x96, 0x30, 0x03];
    set.extend([0xAA; 32]);
    assert_eq!(
        unit_data(&mut a, s, id, 2, &set, T0),
        (0, connected(2, &[0x90, 0, 0, 0]))
    );
    assert_eq!(events(&mut a), vec![Event::Consumed(150)]);
    a.device.assemblies.get_mut(&150).expect("150").data = vec![0; 32];
    assert_eq!(
        unit_data(&mut a, s, id, 2, &set, T0),
        (0, connected(2, &[0x90, 0, 0, 0]))
    );
    assert_eq!(events(&mut a), vec![]);
    assert_eq!(a.device.assemblies[&150].data, vec![0; 32]);
    // The next count executes again; a refusal travels as the CIP response.
    assert_eq!(
        unit_data(
            &mut a,
            s,
            id,
            3,
            &[0x0E, 3, 0x20, 0x01, 0x24, 0x01, 0x30, 0x63],
            T0
        ),
        (0, connected(3, &[0x8E, 0, 0x14, 0]))
    );
    // An unknown connection ID, or the connection from another session: incorrect data.
    assert_eq!(unit_data(&mut a, s, 0x0666, 4, &get, T0), (0x03, vec![]));
    let other = session(&mut a);
    assert_eq!(unit_data(&mut a, other, id, 4, &get, T0), (0x03, vec![]));
    // No connected address item: incorrect data.
    let mut data = vec![0; 6];
    data.extend(emit_items(&[(item::CONNECTED_DATA, &[1, 0, 0x0E, 0])]));
    assert_eq!(reply(&mut a, &encap(0x70, s, &data)).status, 0x03);
    // Not owned by class 3: the identity status stays 0.
    assert_eq!(
        unit_data(
            &mut a,
            s,
            id,
            5,
            &[0x0E, 3, 0x20, 0x01, 0x24, 0x01, 0x30, 0x05],
            T0
        ),
        (0, connected(5, &[0x8E, 0, 0, 0, 0, 0]))
    );
    // Forward_Close with the triad; the connection is gone.
    let mut close = vec![0x4E, 2, 0x20, 0x06, 0x24, 0x01, 0x0A, 0x0E];
    close.extend_from_slice(&5u16.to_le_bytes());
    close.extend_from_slice(&1u16.to_le_bytes());
    close.extend_from_slice(&0x0BAD_CAFEu32.to_le_bytes());
    close.extend_from_slice(&[2, 0, 0x20, 0x02, 0x24, 0x01]);
    assert_eq!(
        explicit(&mut a, s, &close),
        vec![0xCE, 0, 0, 0, 5, 0, 1, 0, 0xFE, 0xCA, 0xAD, 0x0B, 0, 0]
    );
    assert_eq!(events(&mut a), vec![Event::Closed(id)]);
    assert!(a.explicit_connections().is_empty());
    assert_eq!(unit_data(&mut a, s, id, 6, &get, T0), (0x03, vec![]));
}

#[test]
fn class3_connections_close_on_timeout_and_with_their_session() {
    let mut a = adapter();
    let s = session(&mut a);
    // RPI 100 ms, multiplier 0: 400 ms without a request closes it.
    let ok = explicit(&mut a, s, &class3_open(0x54, 1, 100_000, 0xA3, &ROUTER));
    let id = u32::from_le_bytes([ok[4], ok[5], ok[6], ok[7]]);
    events(&mut a);
    assert_eq!(a.poll_timeout(), Some(T0 + Duration::from_micros(400_000)));
    let t1 = T0 + Duration::from_micros(300_000);
    let get = [0x0E, 3, 0x20, 0x01, 0x24, 0x01, 0x30, 0x01];
    assert_eq!(unit_data(&mut a, s, id, 1, &get, t1).0, 0);
    produce(&mut a, t1 + Duration::from_micros(399_000));
    assert_eq!(a.explicit_connections().len(), 1);
    produce(&mut a, t1 + Duration::from_micros(400_000));
    assert!(a.explicit_connections().is_empty());
    assert_eq!(events(&mut a), vec![Event::Expired(id)]);
    // A Large_Forward_Open; the session ends (UnRegisterSession) and takes it along.
    let ok = explicit(&mut a, s, &class3_open(0x5B, 2, 100_000, 0xA3, &ROUTER));
    assert_eq!(&ok[..4], &[0xDB, 0, 0, 0]);
    let id = u32::from_le_bytes([ok[4], ok[5], ok[6], ok[7]]);
    assert_eq!(a.explicit_connections()[0].t_o_size, 510);
    events(&mut a);
    assert_eq!(
        a.request(7, &encap(0x66, s, &[]), T0).expect("complete").0,
        None
    );
    assert!(a.explicit_connections().is_empty());
    assert_eq!(events(&mut a), vec![Event::Expired(id)]);
    // A client that goes away takes its sessions' connections along.
    let s = session(&mut a);
    explicit(&mut a, s, &class3_open(0x54, 3, 100_000, 0xA3, &ROUTER));
    a.client_gone(T0, 7);
    assert!(a.explicit_connections().is_empty());
}

#[test]
fn class3_refusals() {
    let mut a = adapter();
    let s = session(&mut a);
    // Class 3 to an assembly, not the Message Router: invalid segment.
    assert_eq!(
        &explicit(
            &mut a,
            s,
            &class3_open(0x54, 1, 100_000, 0xA3, &[0x20, 0x04, 0x24, 0x64])
        )[..6],
        &[0xD4, 0, 0x01, 1, 0x15, 0x03]
    );
    // Class 3 as a client (direction bit clear): transport not supported.
    assert_eq!(
        &explicit(&mut a, s, &class3_open(0x54, 1, 100_000, 0x23, &ROUTER))[..6],
        &[0xD4, 0, 0x01, 1, 0x03, 0x01]
    );
    // Port segment before the router (cpppo's default 1/0/@2/1) is accepted.
    let ok = explicit(
        &mut a,
        s,
        &class3_open(
            0x54,
            1,
            100_000,
            0xA3,
            &[0x01, 0x00, 0x20, 0x02, 0x24, 0x01],
        ),
    );
    assert_eq!(&ok[..4], &[0xD4, 0, 0, 0]);
    // The same triad again, as class 1: in use.
    assert_eq!(
        &explicit(&mut a, s, &forward_open(1, 50_000, 38, 34))[..6],
        &[0xD4, 0, 0x01, 1, 0x00, 0x01]
    );
    // A reply larger than the T→O size: reply data too large.
    let mut small = class3_open(0x54, 2, 100_000, 0xA3, &ROUTER);
    small[38..40].copy_from_slice(&0x4208u16.to_le_bytes());
    let ok = explicit(&mut a, s, &small);
    let id = u32::from_le_bytes([ok[4], ok[5], ok[6], ok[7]]);
    let name = [0x0E, 3, 0x20, 0x01, 0x24, 0x01, 0x30, 0x07];
    assert_eq!(
        unit_data(&mut a, s, id, 1, &name, T0),
        (0, connected(1, &[0x8E, 0, 0x11, 0]))
    );
    // A request longer than the O→T size (8 bytes with the count): too much data, and not
    // executed (the assembly keeps its bytes).
    let mut narrow = class3_open(0x54, 3, 100_000, 0xA3, &ROUTER);
    narrow[32..34].copy_from_slice(&0x4208u16.to_le_bytes());
    let ok = explicit(&mut a, s, &narrow);
    let id = u32::from_le_bytes([ok[4], ok[5], ok[6], ok[7]]);
    let write = [0x10, 3, 0x20, 0x04, 0x24, 0x96, 0x30, 0x03, 0xFF];
    assert_eq!(
        unit_data(&mut a, s, id, 1, &write, T0),
        (0, connected(1, &[0x90, 0, 0x15, 0]))
    );
    assert_eq!(a.device.assemblies[&150].data, [0; 32]);
    // Six bytes with the count fit: executed.
    let vendor = [0x0E, 2, 0x20, 0x01, 0x24, 0x01];
    assert_eq!(
        unit_data(&mut a, s, id, 2, &vendor, T0),
        (0, connected(2, &[0x8E, 0, 0x14, 0]))
    );
}
