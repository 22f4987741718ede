//! One simulated EtherCAT SubDevice, sans-IO: Ethernet frames and the time in, the same frames
//! out with every datagram processed by the emulated ESC (what a chip does in hardware), and
//! between datagrams the runtime's SubDevice core
//! ([`edsgen_runtime::ethercat::subdevice`]) over that ESC, as a device's firmware runs it.

use std::ops::Range;

use edsgen_runtime::ethercat::subdevice;
use edsgen_runtime::ethercat::wire::datagram::{Command, Datagram, DatagramRepr};
use edsgen_runtime::ethercat::wire::frame::Frame;
use edsgen_runtime::Instant;

pub use edsgen_runtime::ethercat::subdevice::{Application, Layout};

use super::esc::EmulatedEsc;
use super::AlState;

/// The simulated devices' buffers: the longest mailbox and process image they take.
pub const BUFFER: usize = 4096;

/// A simulated SubDevice: the emulated ESC and the core with the application behind it.
#[derive(Debug)]
pub struct SubDevice<A> {
    core: Box<subdevice::SubDevice<EmulatedEsc, A, BUFFER>>,
}

impl<A: Application> SubDevice<A> {
    /// A SubDevice in Init with the SII image `sii`, which the core reads its layout from.
    pub fn new(sii: Vec<u8>, app: A) -> Self {
        let esc = EmulatedEsc::new(sii);
        SubDevice {
            core: Box::new(subdevice::SubDevice::new(esc, app)),
        }
    }

    /// The AL state.
    pub fn state(&self) -> AlState {
        self.core.state()
    }

    /// The ESC, to look at its registers.
    pub fn esc(&self) -> &EmulatedEsc {
        self.core.esc()
    }

    /// The ESC as the device's PDI reaches it, to act as its firmware would.
    pub fn esc_mut(&mut self) -> &mut EmulatedEsc {
        self.core.esc_mut()
    }

    /// The application.
    pub fn app(&self) -> &A {
        self.core.app()
    }

    /// The application, to change it.
    pub fn app_mut(&mut self) -> &mut A {
        self.core.app_mut()
    }

    /// Processes the Ethernet frame `frame` in place at `now`. Returns whether it is to be sent
    /// back: `false` for a frame that is not EtherCAT (ignored, unchanged). Datagrams after a
    /// malformed one are left as they came (their working counters unchanged).
    ///
    /// The device puts its inputs into the ESC before the frame's datagrams (as they are at
    /// `now`) only when one of them reads the inputs SyncManager's memory
    /// ([`EmulatedEsc::reads`]): a frame that passes by (another SubDevice's images, a mailbox
    /// exchange) costs the application nothing. Outputs reach it only when a datagram writes
    /// the outputs buffer's last byte, as the ESC reports it.
    pub fn process_frame(&mut self, now: Instant, frame: &mut [u8]) -> bool {
        let Ok(mut frame) = Frame::new_checked(frame) else {
            return false;
        };
        self.core.handle_timeout(now);
        let inputs = self.inputs_memory();
        let mut fresh = false;
        if let Some(memory) = &inputs {
            let mut datagrams = frame.datagrams();
            while let Some(Ok(place)) = datagrams.next(frame.as_bytes()) {
                let datagram = Datagram::new_unchecked(&frame.as_bytes()[place]);
                if self
                    .core
                    .esc()
                    .reads(&DatagramRepr::parse(&datagram), memory)
                {
                    self.core.update_inputs(now);
                    fresh = true;
                    break;
                }
            }
        }
        let mut remapped = false;
        let mut datagrams = frame.datagrams();
        while let Some(Ok(place)) = datagrams.next(frame.as_bytes()) {
            let Some(mut datagram) = frame.datagram_mut(place) else {
                break;
            };
            let (header, data) = datagram.split_mut();
            // An earlier datagram of this frame may have just mapped the inputs (an FMMU or
            // SyncManager written): they are put in before the first read of them.
            if !fresh && remapped {
                if let Some(memory) = self.inputs_memory() {
                    if self.core.esc().reads(&header, &memory) {
                        self.core.update_inputs(now);
                        fresh = true;
                    }
                }
            }
            remapped |= writes_mapping(&header);
            let (gain, adp) = self.core.esc_mut().datagram(&header, data);
            datagram.set_adp(adp);
            datagram.set_wkc(datagram.wkc().wrapping_add(gain));
            self.core.handle_events(now);
        }
        // As an ESC does on the way back: the source address's locally-administered bit.
        let mut source = frame.source();
        source[0] |= 0x02;
        frame.set_source(source);
        true
    }

    /// The inputs SyncManager's memory, while the device shows inputs (Safe-Op and Op).
    fn inputs_memory(&self) -> Option<Range<u32>> {
        if self.core.state() < AlState::SafeOp {
            return None;
        }
        let sm = self.core.esc().sm(self.core.layout().inputs?);
        (sm.len > 0).then(|| sm.range())
    }

    /// Lets time pass: the outputs watchdog.
    pub fn poll(&mut self, now: Instant) {
        self.core.handle_timeout(now);
    }
}

/// Whether the datagram `header` may write the FMMU or SyncManager registers (0x0600-0x08FF),
/// which map the inputs: a physical write over them, whoever it addresses.
fn writes_mapping(header: &DatagramRepr) -> bool {
    use edsgen_runtime::ethercat::wire::datagram::Command::*;
    let physical_write = matches!(
        Command::from_code(header.command),
        Some(Apwr | Aprw | Fpwr | Fprw | Bwr | Brw | Armw | Frmw)
    );
    let (start, end) = (
        u32::from(header.ado),
        u32::from(header.ado) + u32::from(header.len),
    );
    physical_write && start < 0x0900 && 0x0600 < end
}
