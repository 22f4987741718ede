//! Fuzz the simulated PROFINET device's DCP machine and its wire parsers: any bytes as a received
//! Ethernet frame must not panic; every answer is a DCP response (Identify response or Get/Set)
//! from the device's MAC address to the frame's sender, and its DCPDataLength counts exactly the
//! bytes after its header.
#![no_main]

use edsgen_sim::profinet::dcp::{Dcp, Station};
use libfuzzer_sys::fuzz_target;

const MAC: [u8; 6] = [0x02, 0, 0, 0, 0x03, 0x50];

fuzz_target!(|data: &[u8]| {
    let mut dcp = Dcp::new(Station {
        mac: MAC,
        name_of_station: "goodrive350-pn".to_owned(),
        ip: [[0; 4]; 3],
        vendor_id: 0x0350,
        device_id: 0x0350,
        type_of_station: "INVT Goodrive350".to_owned(),
        instance: (0, 1),
    });
    if let Some(answer) = dcp.handle(data) {
        assert_eq!(answer[..6], data[6..12]);
        assert_eq!(answer[6..12], MAC);
        assert!(matches!(answer[14..16], [0xFE, 0xFF] | [0xFE, 0xFD]));
        let length = usize::from(u16::from_be_bytes([answer[24], answer[25]]));
        assert_eq!(length, answer.len() - 26);
    }
    while dcp.poll_event().is_some() {}
    let _ = dcp.hello();
});
