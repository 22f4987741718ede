//! The cyclic exchange of one application relation (p-net's `pf_cpm` consumer and `pf_ppm`
//! provider): the output CR's frames consumed, with the watchdog, and the input CR's frames
//! produced. Sans-IO: frames and time in, frames out.
//!
//! The layout (where each submodule's data, IOPS and IOCS sit in the C_SDU, the FrameIDs, the
//! send interval and the watchdog factor) is what a Connect's IOCR blocks give; here it is a
//! value the caller sets ([`CrLayout`]), so that connection management can fill it in.

use edsgen_runtime::{Duration, Instant};

use super::wire::rt::{RtFrame, DATA_STATUS_GOOD, DATA_VALID};
use super::wire::{append, Ethernet, Mac, ETHERTYPE_PROFINET};

/// Where one submodule's IO data sits in a C_SDU: its data at `offset`, `len` bytes, and its
/// IOPS right after.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DataObject {
    /// The submodule's slot.
    pub slot: u16,
    /// The submodule's subslot.
    pub subslot: u16,
    /// Offset of the data in the C_SDU.
    pub offset: usize,
    /// Bytes of data.
    pub len: usize,
}

/// One application relation's cyclic layout.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CrLayout {
    /// The controller's MAC address (the input CR's destination, the output CR's source).
    pub controller: Mac,
    /// The device's MAC address.
    pub device: Mac,
    /// FrameID of the output CR (controller to device).
    pub output_frame_id: u16,
    /// C_SDU length of the output CR.
    pub output_len: usize,
    /// The output submodules' data objects in the output CR, in the order of the submodules.
    pub outputs: Vec<DataObject>,
    /// FrameID of the input CR (device to controller).
    pub input_frame_id: u16,
    /// C_SDU length of the input CR.
    pub input_len: usize,
    /// The input submodules' data objects in the input CR, in the order of the submodules.
    pub inputs: Vec<DataObject>,
    /// Where the device puts its IOCS for each output submodule, in the input CR.
    pub input_iocs: Vec<usize>,
    /// The send interval (SendClockFactor × ReductionRatio × 31.25 µs).
    pub interval: Duration,
    /// DataHoldFactor: frames that may be missed before the watchdog expires.
    pub watchdog_factor: u16,
}

/// The consumer and provider of one application relation.
#[derive(Debug, Clone)]
pub struct Cyclic {
    layout: CrLayout,
    outputs: Vec<(Vec<u8>, u8)>,
    last_received: Option<Instant>,
    first_deadline: Option<Instant>,
    cycle: u16,
    expired: bool,
}

impl Cyclic {
    /// The exchange of `layout`; no output has come yet (outputs read as zero, IOPS bad).
    pub fn new(layout: CrLayout) -> Self {
        let outputs = layout.outputs.iter().map(|o| (vec![0; o.len], 0)).collect();
        Cyclic {
            layout,
            outputs,
            last_received: None,
            first_deadline: None,
            cycle: 0,
            expired: false,
        }
    }

    /// Data exchange starts at `now`: the first output frame must come within `first`, or the
    /// watchdog expires (a controller that never sends one is noticed too).
    pub fn arm(&mut self, now: Instant, first: Duration) {
        self.first_deadline = Some(now + first);
        self.expired = false;
    }

    /// The layout.
    pub fn layout(&self) -> &CrLayout {
        &self.layout
    }

    /// Takes a received frame at `now`: `true` when it was the output CR's, with valid data,
    /// and the outputs were updated. Other frames (another FrameID or sender, too short, data
    /// not valid) are ignored.
    pub fn handle(&mut self, now: Instant, frame: &[u8]) -> bool {
        let Some(eth) = Ethernet::parse(frame) else {
            return false;
        };
        if eth.ethertype != ETHERTYPE_PROFINET
            || eth.src != self.layout.controller
            || eth.dst != self.layout.device
        {
            return false;
        }
        let Some(rt) = frame
            .get(eth.payload..)
            .and_then(|pdu| RtFrame::parse(pdu, self.layout.output_len))
        else {
            return false;
        };
        if rt.frame_id != self.layout.output_frame_id || rt.data_status & DATA_VALID == 0 {
            return false;
        }
        for (object, (data, iops)) in self.layout.outputs.iter().zip(&mut self.outputs) {
            if let Some(bytes) = rt.c_sdu.get(object.offset..object.offset + object.len) {
                data.copy_from_slice(bytes);
                *iops = rt
                    .c_sdu
                    .get(object.offset + object.len)
                    .copied()
                    .unwrap_or(0);
            }
        }
        self.last_received = Some(now);
        self.expired = false;
        true
    }

    /// The index of the output submodule in `slot`, `subslot`.
    pub fn output_index(&self, slot: u16, subslot: u16) -> Option<usize> {
        self.layout
            .outputs
            .iter()
            .position(|o| (o.slot, o.subslot) == (slot, subslot))
    }

    /// Output submodule `n`'s last data and its IOPS.
    pub fn output(&self, n: usize) -> Option<(&[u8], u8)> {
        self.outputs.get(n).map(|(d, iops)| (d.as_slice(), *iops))
    }

    /// A loopback's input data, as a test rack wired output to input: the bytes of the output
    /// data (submodule after submodule, in the layout's order) poured into the input data
    /// objects in their order, zero past the outputs' end.
    pub fn looped_back(&self) -> Vec<Vec<u8>> {
        let mut bytes = self
            .outputs
            .iter()
            .flat_map(|(data, _)| data.iter().copied());
        self.layout
            .inputs
            .iter()
            .map(|input| (0..input.len).map(|_| bytes.next().unwrap_or(0)).collect())
            .collect()
    }

    /// The input CR's frame at `now`: each input submodule's data (from `inputs`, in order;
    /// missing ones zero) with IOPS good, the IOCS good, the cycle counter of `now`.
    pub fn produce(&mut self, now: Instant, inputs: &[&[u8]]) -> Vec<u8> {
        let mut c_sdu = vec![0u8; self.layout.input_len];
        for (n, object) in self.layout.inputs.iter().enumerate() {
            if let Some(area) = c_sdu.get_mut(object.offset..object.offset + object.len) {
                if let Some(data) = inputs.get(n).filter(|d| d.len() == object.len) {
                    area.copy_from_slice(data);
                }
            }
            if let Some(iops) = c_sdu.get_mut(object.offset + object.len) {
                *iops = 0x80;
            }
        }
        for &at in &self.layout.input_iocs {
            if let Some(iocs) = c_sdu.get_mut(at) {
                *iocs = 0x80;
            }
        }
        // The cycle counter counts 31.25 µs units.
        self.cycle = (now.as_micros() * 32 / 1000) as u16;
        let mut out = Vec::new();
        append(&mut out, |b| {
            Ethernet::emit(self.layout.controller, self.layout.device, b)
        });
        let frame = RtFrame {
            frame_id: self.layout.input_frame_id,
            c_sdu: &c_sdu,
            cycle_counter: self.cycle,
            data_status: DATA_STATUS_GOOD,
            transfer_status: 0,
        };
        append(&mut out, |b| frame.emit(b));
        out
    }

    /// When the watchdog expires if no output frame comes first.
    pub fn poll_timeout(&self) -> Option<Instant> {
        if self.expired {
            return None;
        }
        let Some(last) = self.last_received else {
            return self.first_deadline;
        };
        let micros = self.layout.interval.as_micros() * u64::from(self.layout.watchdog_factor);
        Some(last + Duration::from_micros(micros))
    }

    /// `true` (once) when the watchdog has expired at `now`: the controller stopped sending.
    pub fn handle_timeout(&mut self, now: Instant) -> bool {
        if self.poll_timeout().is_some_and(|at| at <= now) {
            self.expired = true;
            return true;
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_armed_watchdog_expires_without_a_first_frame_and_a_running_one_after_the_factor() {
        let layout = crate::profinet::drive::card_layout(
            [2, 0, 0, 0, 0, 1],
            [2, 0, 0, 0, 3, 0x50],
            Duration::from_millis(8),
            3,
        );
        let mut c = Cyclic::new(layout);
        assert_eq!(c.poll_timeout(), None);
        c.arm(Instant::from_millis(100), Duration::from_millis(10_000));
        assert_eq!(c.poll_timeout(), Some(Instant::from_millis(10_100)));
        assert!(!c.handle_timeout(Instant::from_millis(10_099)));
        assert!(c.handle_timeout(Instant::from_millis(10_100)));
        assert_eq!(c.poll_timeout(), None);
        assert!(!c.handle_timeout(Instant::from_millis(20_000)));
    }

    #[test]
    fn a_loopback_pours_the_output_bytes_into_the_inputs_in_order() {
        let object = |slot, offset, len| DataObject {
            slot,
            subslot: 1,
            offset,
            len,
        };
        let mut layout = crate::profinet::drive::card_layout(
            [2, 0, 0, 0, 0, 1],
            [2, 0, 0, 0, 3, 0x50],
            Duration::from_millis(4),
            3,
        );
        layout.outputs = vec![object(1, 0, 2), object(2, 3, 1)];
        layout.inputs = vec![object(3, 0, 1), object(4, 2, 3)];
        let mut c = Cyclic::new(layout);
        assert_eq!(c.looped_back(), [vec![0], vec![0, 0, 0]]);
        c.outputs = vec![(vec![0x11, 0x22], 0x80), (vec![0x33], 0x80)];
        assert_eq!(c.looped_back(), [vec![0x11], vec![0x22, 0x33, 0]]);
    }
}
