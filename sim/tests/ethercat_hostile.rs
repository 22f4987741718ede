//! Hostile frames at the simulated EC-TX508, in process: thousands of frames mutated from a
//! recorded good start-up (bytes flipped, cut short, random), with a deterministic seed; after
//! each batch a master's start-up (reset to Init, SyncManagers and FMMUs cleared, the SII
//! offered, mailboxes, Pre-Op, an SDO read of 1018h:01, process data, Safe-Op, Op, one LRW)
//! must work again, as a restarted master's would.

mod hostile_support;

use edsgen_runtime::Instant;
use edsgen_sim::ethercat::AlState;
use std::path::Path;

use edsgen_sim::ethercat::{EsiDevice, SubDevice};
use hostile_support::{mutate, recorded_start_up, Rng, StartUp};

fn ec_tx508() -> SubDevice<EsiDevice> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../eds/ec-tx508.xml");
    let model = edsgen_model::read::read_file(&path).unwrap().device;
    EsiDevice::subdevice(&model, None).unwrap()
}

#[test]
fn a_master_starts_up_again_after_thousands_of_mutated_frames() {
    let good = recorded_start_up(ec_tx508());
    let mut device = ec_tx508();
    let mut now = 0;
    let mut rng = Rng(0x5EED_EC47);
    for batch in 0..50 {
        for _ in 0..100 {
            let mut frame = mutate(&mut rng, &good);
            now += 1_000;
            device.process_frame(Instant(now), &mut frame);
        }
        let mut again = StartUp {
            device: &mut device,
            now: &mut now,
            frames: Vec::new(),
        };
        let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| again.run()));
        assert!(
            result.is_ok(),
            "batch {batch}: the master's start-up failed; SII {:02X?}, 0x0500 {:02X?}",
            &device.esc().sii()[..0x20],
            device.esc().memory(0x0500, 16)
        );
        assert_eq!(device.state(), AlState::Op);
    }
}
