//! A segment of SubDevices in line, sans-IO: a frame from the MainDevice passes through each
//! SubDevice in the order they are wired, each one's ESC processing every datagram as it goes by
//! (counting ADP up, adding to working counters, reading and writing its memory), and it returns
//! to the MainDevice from the last one, as on the wire (ETG.1000.4 §5.4).

use edsgen_runtime::Instant;

use super::{Application, SubDevice};

/// SubDevices in segment order: the first is the one the MainDevice's port reaches.
#[derive(Debug)]
pub struct Segment<A> {
    devices: Vec<SubDevice<A>>,
}

impl<A: Application> Segment<A> {
    /// The segment of `devices` in wiring order: each but the last has its port 1 connected to
    /// the next (as the DL status register shows it).
    pub fn new(mut devices: Vec<SubDevice<A>>) -> Self {
        let last = devices.len().saturating_sub(1);
        for (position, device) in devices.iter_mut().enumerate() {
            device.esc_mut().connect_port1(position < last);
        }
        Segment { devices }
    }

    /// The SubDevices, in segment order.
    pub fn devices(&self) -> &[SubDevice<A>] {
        &self.devices
    }

    /// The SubDevice at `position` (0 first), to act on it as its firmware would.
    pub fn device_mut(&mut self, position: usize) -> Option<&mut SubDevice<A>> {
        self.devices.get_mut(position)
    }

    /// How many SubDevices the segment has.
    pub fn len(&self) -> usize {
        self.devices.len()
    }

    /// Whether the segment has no SubDevice.
    pub fn is_empty(&self) -> bool {
        self.devices.is_empty()
    }

    /// Processes the Ethernet frame `frame` in place at `now` through every SubDevice in turn.
    /// Returns whether it comes back to the MainDevice: `false` for a frame that is not
    /// EtherCAT, and on an empty segment (nothing to answer).
    pub fn process_frame(&mut self, now: Instant, frame: &mut [u8]) -> bool {
        let mut answered = false;
        for device in &mut self.devices {
            if !device.process_frame(now, frame) {
                return false;
            }
            answered = true;
        }
        answered
    }

    /// Lets time pass for every SubDevice: their outputs watchdogs.
    pub fn poll(&mut self, now: Instant) {
        for device in &mut self.devices {
            device.poll(now);
        }
    }
}
