//! Fuzz the PROFIBUS FDL telegram parser and the simulated DP slave (the Goodrive350 card):
//! any bytes, cut into telegrams where the parser says one ends.
//!
//! Properties: nothing panics; every data telegram that parses re-emits (`emit`) to bytes that
//! parse back to the same telegram (SD1/SD2/SD3 chosen by its data); the slave answers only
//! telegrams that parse, addressed to it and not broadcast, and every answer parses as a
//! response (or is the short acknowledgement) from the slave's address to the requester.
#![no_main]

use edsgen_runtime::Instant;
use edsgen_sim::dp::card::goodrive350;
use edsgen_sim::dp::fdl::{self, Telegram};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(mut slave) = goodrive350(2, Instant::from_millis(0)) else {
        return;
    };
    let mut rest = data;
    let mut now = 0u64;
    while !rest.is_empty() {
        now += 1;
        let (telegram, used) = match fdl::parse(rest) {
            Ok(parsed) => parsed,
            Err(_) => {
                // Not answered; skip a byte, as a receiver resynchronising does.
                assert_eq!(slave.handle(Instant::from_millis(now), &rest[..1]), None);
                rest = &rest[1..];
                continue;
            }
        };
        let bytes = &rest[..used];
        rest = &rest[used..];
        if let Telegram::Data(t) = &telegram {
            if let Some(again) = t.emit() {
                assert_eq!(fdl::parse(&again), Ok((telegram.clone(), again.len())));
            }
        }
        let answer = slave.handle(Instant::from_millis(now), bytes);
        slave.handle_timeout(Instant::from_millis(now));
        let Some(answer) = answer else { continue };
        let Telegram::Data(request) = telegram else {
            panic!("answered a token or short acknowledgement");
        };
        assert_eq!(request.da, 2, "answered a telegram for another station");
        if answer != [fdl::SC] {
            match fdl::parse(&answer) {
                Ok((Telegram::Data(reply), n)) => {
                    assert_eq!(n, answer.len());
                    assert!(!reply.is_request());
                    assert_eq!((reply.da, reply.sa), (request.sa, 2));
                }
                other => panic!("answer {answer:02X?} reads {other:?}"),
            }
        }
    }
});
