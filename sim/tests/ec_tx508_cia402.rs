//! CiA 402 over EtherCAT without hardware: the master's cyclic `Controller` against the
//! simulated EC-TX508 (`edsgen_sim::drives::EcTx508`: the runtime's `cia402::Drive` in cyclic
//! synchronous velocity), through the card's generated process images as bytes. Each 1 ms cycle
//! the controller fills `ethercat::Outputs` (controlword, 6060h, 60FFh), which is encoded into
//! the 21-byte image; the device decodes it by the 1600h mapping, runs the drive one cycle, and
//! encodes its statusword, 6061h and actual speed into the 23-byte inputs image (1A00h), which
//! the master decodes next cycle.

use edsgen_runtime::cia402::{mode, State};
use edsgen_runtime::master::cia402::{Controller, Outcome};
use edsgen_runtime::Instant;
use edsgen_sim::cards::ec_tx508::ethercat::{Inputs, Outputs, RxPdo1600, TxPdo1A00};
use edsgen_sim::drives::EcTx508;

/// The master's side of one cycle: what it decided and what it had seen.
#[derive(Debug, Clone, Copy)]
struct Seen {
    controlword: u16,
    outcome: Outcome,
    inputs: TxPdo1A00,
}

/// A master with a controller and the device, joined by the two images as bytes.
struct Link {
    controller: Controller,
    device: EcTx508,
    /// The inputs image the device sent last cycle.
    inputs: [u8; Inputs::SIZE],
    /// The outputs image the master sent last cycle.
    outputs: [u8; Outputs::SIZE],
    /// The speed (rpm) the master asks for once operation is enabled.
    speed: i32,
    ms: u64,
}

impl Link {
    /// The EC-TX508 powered up: 3000 rpm, ramps of 3 rpm per ms, a fault stops it at 30 rpm
    /// per ms; csv offered, vl in effect at power-up.
    fn new(controller: Controller) -> Self {
        let device = EcTx508::new(Instant::from_millis(0));
        Link {
            controller,
            inputs: device.inputs(),
            device,
            outputs: [0; Outputs::SIZE],
            speed: 0,
            ms: 0,
        }
    }

    /// One cycle, master then device.
    fn cycle(&mut self) -> Seen {
        // Master: the inputs of the last cycle in, the outputs out.
        let inputs = Inputs::from_slice(&self.inputs).unwrap().tx_pdo_1a00;
        let cycle = self
            .controller
            .cycle(inputs.status_word, inputs.operation_mode_display);
        let outputs = Outputs {
            rx_pdo_1600: RxPdo1600 {
                control_word: cycle.controlword,
                operation_mode: cycle.mode.unwrap_or(0),
                target_speed: if cycle.outcome == Outcome::Reached {
                    self.speed
                } else {
                    0
                },
                ..RxPdo1600::default()
            },
        };
        self.outputs = outputs.to_bytes();

        // Device: the outputs image by the 1600h mapping, one drive cycle, the inputs image.
        let now = Instant::from_millis(self.ms);
        self.inputs = self.device.cycle(now, &self.outputs).unwrap();
        self.ms += 1;
        Seen {
            controlword: cycle.controlword,
            outcome: cycle.outcome,
            inputs,
        }
    }

    fn run(&mut self, cycles: usize) -> Vec<Seen> {
        (0..cycles).map(|_| self.cycle()).collect()
    }
}

fn controlwords(seen: &[Seen]) -> Vec<u16> {
    seen.iter().map(|s| s.controlword).collect()
}

fn enable_in_csv() -> Controller {
    Controller::new(State::OperationEnabled)
        .with_mode(mode::CYCLIC_VELOCITY)
        .with_limit(50)
}

#[test]
fn csv_drive_is_enabled_by_exact_controlwords_and_follows_the_target_on_its_ramp() {
    let mut link = Link::new(enable_in_csv());
    link.speed = 300;
    let seen = link.run(120);
    // Cycle 0: switch on disabled, vl shown (0x0650, mode 2): shutdown, and 6060h = 9.
    assert_eq!(seen[0].inputs.status_word, 0x0650);
    assert_eq!(seen[0].inputs.operation_mode_display, mode::VELOCITY);
    assert_eq!(controlwords(&seen[..5]), [0x06, 0x07, 0x0F, 0x0F, 0x0F]);
    // The drive confirms csv in cycle 0; the master sees it in cycle 1.
    assert_eq!(seen[1].inputs.operation_mode_display, mode::CYCLIC_VELOCITY);
    // Operation enabled is seen in cycle 3.
    let outcomes: Vec<Outcome> = seen[..4].iter().map(|s| s.outcome).collect();
    assert_eq!(
        outcomes,
        [
            Outcome::Busy,
            Outcome::Busy,
            Outcome::Busy,
            Outcome::Reached
        ]
    );
    assert_eq!(seen[3].inputs.status_word, 0x0637);
    assert!(seen[3..].iter().all(|s| s.outcome == Outcome::Reached));

    // 60FFh = 300 from cycle 3 (ms 3): 3 rpm per ms, seen one cycle later.
    let speed_at = |cycle: usize| seen[cycle].inputs.actual_speed;
    assert_eq!(speed_at(4), 0);
    assert_eq!(speed_at(5), 3);
    assert_eq!(speed_at(54), 150);
    assert_eq!(speed_at(103), 297);
    assert_eq!(speed_at(104), 300);
    assert_eq!(speed_at(119), 300);
    // Target reached (bit 10) once the ramp is there.
    assert_eq!(seen[103].inputs.status_word, 0x0237);
    assert_eq!(seen[104].inputs.status_word, 0x0637);
    // The last outputs image, byte for byte: 6040h 000Fh, 607Ah 0, 60FFh 300, 6071h 0,
    // 6072h 0, 6060h 9, 6081h 0, 60B8h 0.
    assert_eq!(
        link.outputs,
        [0x0F, 0x00, 0, 0, 0, 0, 0x2C, 0x01, 0x00, 0x00, 0, 0, 0, 0, 0x09, 0, 0, 0, 0, 0, 0]
    );
    // And the last inputs: 6041h 0637h, 606Ch 300, 6061h 9.
    let mut expected = [0u8; Inputs::SIZE];
    expected[..2].copy_from_slice(&0x0637u16.to_le_bytes());
    expected[6..10].copy_from_slice(&300i32.to_le_bytes());
    expected[16] = 9;
    assert_eq!(link.inputs, expected);
}

#[test]
fn a_fault_is_reset_by_a_rising_edge_after_bit_7_low_then_the_drive_is_enabled_again() {
    let mut link = Link::new(enable_in_csv());
    link.speed = 300;
    let mut seen = link.run(200);
    assert_eq!(seen[199].inputs.actual_speed, 300);
    // The fault from ms 200: quick-stop ramp (30 rpm per ms) for 10 ms, then fault. Its cause
    // stays until ms 214, so the first reset is refused.
    link.device
        .drive_mut()
        .raise_fault(Instant::from_millis(200));
    seen.extend(link.run(14));
    link.device.drive_mut().clear_fault();
    seen.extend(link.run(16));
    assert_eq!(
        controlwords(&seen[199..220]),
        [
            0x0F, 0x0F, // operation enabled, the fault not seen yet
            0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, // fault reaction
            0x80, // the fault seen, bit 7 was low: rising edge, refused (cause present)
            0x00, 0x80, // low, rising again: still refused
            0x00, 0x80, // the cause gone since ms 214: this edge resets
            0x06, 0x07, 0x0F, 0x0F,
        ]
    );
    let states: Vec<State> = seen[200..220]
        .iter()
        .map(|s| State::from_statusword(s.inputs.status_word).unwrap())
        .collect();
    use State::*;
    let mut expected = vec![OperationEnabled];
    expected.extend([FaultReactionActive; 10]);
    expected.extend([Fault; 5]);
    expected.extend([
        SwitchOnDisabled,
        ReadyToSwitchOn,
        SwitchedOn,
        OperationEnabled,
    ]);
    assert_eq!(states, expected);
    // The quick-stop ramp, 30 rpm per ms from ms 200.
    assert_eq!(seen[201].inputs.actual_speed, 300);
    assert_eq!(seen[202].inputs.actual_speed, 270);
    assert_eq!(seen[206].inputs.actual_speed, 150);
    assert_eq!(seen[211].inputs.actual_speed, 0);
    // Enabled again in cycle 219: 60FFh = 300 again, the ramp from 0.
    assert_eq!(seen[219].outcome, Outcome::Reached);
    assert_eq!(seen[229].inputs.actual_speed, 27);
}

#[test]
fn a_mode_the_drive_does_not_run_is_reported_and_operation_is_never_enabled() {
    let controller = Controller::new(State::OperationEnabled)
        .with_mode(mode::CYCLIC_POSITION)
        .with_limit(5);
    let mut link = Link::new(controller);
    let seen = link.run(8);
    assert_eq!(
        controlwords(&seen),
        [0x06, 0x07, 0x07, 0x07, 0x07, 0x07, 0x07, 0x07]
    );
    let refused = Outcome::ModeNotConfirmed {
        wanted: mode::CYCLIC_POSITION,
        shown: mode::VELOCITY,
    };
    let outcomes: Vec<Outcome> = seen.iter().map(|s| s.outcome).collect();
    assert_eq!(outcomes[..5], [Outcome::Busy; 5]);
    assert_eq!(outcomes[5..], [refused; 3]);
    assert_eq!(link.device.drive().state(), State::SwitchedOn);
    assert_eq!(link.device.drive().mode(), mode::VELOCITY);
}

#[test]
fn an_outputs_image_of_the_wrong_length_is_refused_and_the_drive_left_as_it_was() {
    let mut device = EcTx508::new(Instant::from_millis(0));
    let before = device.inputs();
    let enable = Outputs {
        rx_pdo_1600: RxPdo1600 {
            control_word: 0x06,
            ..RxPdo1600::default()
        },
    }
    .to_bytes();
    assert_eq!(
        device.cycle(Instant::from_millis(1), &enable[..20]),
        Err(edsgen_runtime::PdoError::WrongLength {
            expected: 21,
            actual: 20
        })
    );
    assert_eq!(device.inputs(), before);
    assert_eq!(device.drive().state(), State::SwitchOnDisabled);
    // The whole image is taken: shutdown, ready to switch on.
    let inputs = device.cycle(Instant::from_millis(2), &enable).unwrap();
    assert_eq!(
        State::from_statusword(Inputs::from_slice(&inputs).unwrap().tx_pdo_1a00.status_word),
        Some(State::ReadyToSwitchOn)
    );
}
