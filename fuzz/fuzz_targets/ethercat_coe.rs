//! Fuzz CoE SDO on the runtime's SDO server (`edsgen_runtime::ethercat::sdo`) with the CP301
//! card's generated dictionary: the input is cut into requests (each prefixed by a length byte,
//! its low 6 bits the answer's room above 8 bytes) given in turn to one server, so that
//! transfers (normal, segmented, complete access) run across requests.
//!
//! Properties: nothing panics; an answer fits its room and is at least 8 bytes; an abort names
//! the request's index and sub-index (its bytes 1 to 3, zeros where the request is shorter),
//! or for a segment (whose bytes 1 to 3 are data) the transfer's: the last other request's,
//! or zeros when no transfer runs (CiA 301 §7.2.4.3.17).
#![no_main]

use edsgen_runtime::ethercat::sdo::CoeSdoServer;
use edsgen_runtime::SdoAbort;
use libfuzzer_sys::fuzz_target;

edsgen_runtime::include_device!("cp301");

fuzz_target!(|input: &[u8]| {
    let mut od = cp301::Od::new(3);
    let mut server = CoeSdoServer::new();
    let allow = |index: u16, _: u8, _: &[u8]| {
        if index == 0x2000 {
            Err(SdoAbort::DeviceState)
        } else {
            Ok(())
        }
    };
    let mut rest = input;
    // The index and sub-index of the last request that was not a segment.
    let mut entry = [0u8; 3];
    while let Some((&head, tail)) = rest.split_first() {
        let len = usize::from(head >> 2).min(tail.len());
        let (request, next) = tail.split_at(len);
        rest = next;
        let room = 8 + usize::from(head & 0x3F);
        let mut answer = vec![0u8; room];
        let mut mux = [0u8; 3];
        for (m, r) in mux.iter_mut().zip(request.iter().skip(1)) {
            *m = *r;
        }
        // Download segment (ccs 0) and upload segment (ccs 3).
        let segment = request.first().is_some_and(|c| matches!(c >> 5, 0 | 3));
        if !segment && !request.is_empty() {
            entry = mux;
        }
        let Some(n) = server.request(&mut od, &allow, request, &mut answer) else {
            continue;
        };
        assert!((8..=room).contains(&n));
        if answer[0] == 0x80 {
            if segment {
                assert!(
                    answer[1..4] == entry || answer[1..4] == [0; 3],
                    "{:?}",
                    &answer[..4]
                );
            } else {
                assert_eq!(answer[1..4], mux);
            }
        }
    }
});
