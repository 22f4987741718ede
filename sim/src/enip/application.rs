//! What sits behind a simulated EtherNet/IP adapter ([`EnipApplication`]): what the assemblies'
//! bytes mean and what the device does when its connections come and go. "An application trait
//! per bus" (#30): DP has `DpApplication` (runtime), PROFINET `IoApplication`, EtherNet/IP this
//! one; ONE PKW/PZD card application ([`PkwPzdDrive`]) serves the DP, PROFINET and EtherNet/IP
//! cores. A device from any other EDS has none (`()`): its assemblies keep what was written.

use edsgen_runtime::pkw_pzd::{ByteOrder, Command, ControlWord, OutputImage, IMAGE_BYTES};
use edsgen_runtime::Instant;

use super::state::DeviceState;
use crate::cards::goodrive350_enip as card;
use crate::drives::pkw_pzd::PkwPzdDrive;

/// How a class-1 connection ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ending {
    /// Forward_Close: an orderly end.
    Closed,
    /// No O→T data for the connection's timeout.
    TimedOut,
}

/// What the application did when a connection ended (for the driver's log).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reaction {
    /// The drive decelerates to a stop.
    DeceleratesToStop,
    /// The drive tripped with this fault (its keypad name).
    Fault(&'static str),
}

impl std::fmt::Display for Reaction {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Reaction::DeceleratesToStop => write!(f, "drive decelerates to stop"),
            Reaction::Fault(name) => write!(f, "drive fault {name}"),
        }
    }
}

/// The application of an adapter (see the module comment). The adapter calls it as things
/// happen; each call may read and write the device's assemblies.
pub trait EnipApplication {
    /// An originator wrote assembly `instance` at `now` (class-1 O→T data or
    /// Set_Attribute_Single): its bytes are in `device.assemblies`.
    fn consumed(&mut self, now: Instant, instance: u32, device: &mut DeviceState);
    /// A connection ended at `now` (`device.connections` no longer has it); what the
    /// application did about it.
    fn connection_ended(
        &mut self,
        now: Instant,
        ending: Ending,
        device: &mut DeviceState,
    ) -> Option<Reaction>;
    /// When the application next wants [`EnipApplication::handle_timeout`].
    fn poll_timeout(&self) -> Option<Instant>;
    /// Time passed to `now`.
    fn handle_timeout(&mut self, now: Instant, device: &mut DeviceState);
}

/// No application: the assemblies keep what was written.
impl EnipApplication for () {
    fn consumed(&mut self, _: Instant, _: u32, _: &mut DeviceState) {}

    fn connection_ended(&mut self, _: Instant, _: Ending, _: &mut DeviceState) -> Option<Reaction> {
        None
    }

    fn poll_timeout(&self) -> Option<Instant> {
        None
    }

    fn handle_timeout(&mut self, _: Instant, _: &mut DeviceState) {}
}

/// The Goodrive350 EtherNet/IP card (chapter 5): the scanner's image in assembly 150, the
/// drive's in 100, both 32 bytes little-endian. Every O→T image is exchanged with the drive and
/// its answer becomes the T→O image; without a connection the drive's ramps still move and
/// assembly 100 shows the drive as it stands. The card's communication-loss actions: a
/// connection that times out trips the drive with E-EIP (it coasts to a stop, faulted until a
/// fault reset); one that Forward_Close ends decelerates it to a stop.
impl EnipApplication for PkwPzdDrive {
    fn consumed(&mut self, now: Instant, instance: u32, device: &mut DeviceState) {
        if instance != card::Output::INSTANCE {
            return;
        }
        let Some(output) = image(device, card::Output::INSTANCE) else {
            return;
        };
        let input = self.exchange_bytes(now, &output, ByteOrder::LittleEndian);
        set_image(device, card::Input::INSTANCE, &input);
    }

    fn connection_ended(
        &mut self,
        now: Instant,
        ending: Ending,
        device: &mut DeviceState,
    ) -> Option<Reaction> {
        if device.written_by_connection(card::Output::INSTANCE) {
            return None;
        }
        match ending {
            // The last settings kept, no PKW task: explicit reads show it stopping and the next
            // connection's run command starts it from rest.
            Ending::Closed => {
                let mut output = image(device, card::Output::INSTANCE)
                    .map(|bytes| OutputImage::parse(&bytes, ByteOrder::LittleEndian))
                    .unwrap_or_default();
                output.pkw = OutputImage::default().pkw;
                output.control = ControlWord::new(Command::DecelerateToStop, self.layout());
                self.exchange(now, &output);
                Some(Reaction::DeceleratesToStop)
            }
            // E-EIP (fault 70, P07.27): the next connection finds it faulted until its control
            // word resets the fault (command 7).
            Ending::TimedOut if self.vfd().fault().is_none() => {
                self.communication_lost(now);
                Some(Reaction::Fault(self.bus().fault_name()))
            }
            Ending::TimedOut => None,
        }
    }

    fn poll_timeout(&self) -> Option<Instant> {
        PkwPzdDrive::poll_timeout(self)
    }

    fn handle_timeout(&mut self, now: Instant, device: &mut DeviceState) {
        // The drive runs on (its ramps, its own timeout P16.54) with or without a connection.
        PkwPzdDrive::handle_timeout(self, now);
        if device.connections.is_empty() {
            let input = self.inputs().emit(ByteOrder::LittleEndian);
            set_image(device, card::Input::INSTANCE, &input);
        }
    }
}

/// Assembly `instance`'s bytes as a card image, when it is one.
fn image(device: &DeviceState, instance: u32) -> Option<[u8; IMAGE_BYTES]> {
    let assembly = device.assemblies.get(&instance)?;
    assembly.data.as_slice().try_into().ok()
}

fn set_image(device: &mut DeviceState, instance: u32, bytes: &[u8; IMAGE_BYTES]) {
    if let Some(assembly) = device.assemblies.get_mut(&instance) {
        assembly.data = bytes.to_vec();
    }
}
