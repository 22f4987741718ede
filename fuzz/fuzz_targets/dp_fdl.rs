//! Fuzz the PROFIBUS FDL telegram views and the DP slave core (`edsgen_runtime::dp`) with the
//! simulated Goodrive350 card behind it: any bytes, cut into telegrams where the parser says one
//! ends.
//!
//! Properties: nothing panics; every data telegram that parses re-emits (`emit`) to bytes that
//! parse back to the same telegram (SD1/SD2/SD3 chosen by its data); the slave answers only
//! telegrams that parse, addressed to it and not broadcast, and every answer parses as a
//! response (or is the short acknowledgement) from the slave's address to the requester.
#![no_main]

use edsgen_runtime::dp::fdl::{self, Repr, MAX_TELEGRAM_LEN};
use edsgen_runtime::Instant;
use edsgen_sim::dp::card::goodrive350;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(mut slave) = goodrive350(2, Instant::from_millis(0)) else {
        return;
    };
    let mut rest = data;
    let mut now = 0u64;
    let mut answer = [0u8; MAX_TELEGRAM_LEN];
    let mut again = [0u8; MAX_TELEGRAM_LEN];
    while !rest.is_empty() {
        now += 1;
        let at = Instant::from_millis(now);
        let (telegram, used) = match fdl::parse(rest) {
            Ok(parsed) => parsed,
            Err(_) => {
                // Not answered; skip a byte, as a receiver resynchronising does.
                slave.handle(at, &rest[..1]);
                assert_eq!(slave.poll_transmit(at, &mut answer), None);
                rest = &rest[1..];
                continue;
            }
        };
        let bytes = &rest[..used];
        rest = &rest[used..];
        if let Repr::Data(t) = &telegram {
            if let Ok(n) = t.emit(&mut again) {
                assert_eq!(fdl::parse(&again[..n]), Ok((telegram, n)));
            }
        }
        slave.handle(at, bytes);
        let sent = slave.poll_transmit(at, &mut answer);
        slave.handle_timeout(at);
        let Some(n) = sent else { continue };
        let answer = &answer[..n];
        let Repr::Data(request) = telegram else {
            panic!("answered a token or short acknowledgement");
        };
        assert_eq!(request.da, 2, "answered a telegram for another station");
        if answer != [fdl::SC] {
            match fdl::parse(answer) {
                Ok((Repr::Data(reply), used)) => {
                    assert_eq!(used, answer.len());
                    assert!(!reply.is_request());
                    assert_eq!((reply.da, reply.sa), (request.sa, 2));
                }
                other => panic!("answer {answer:02X?} reads {other:?}"),
            }
        }
    }
});
