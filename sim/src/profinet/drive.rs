//! The Goodrive350 behind the simulated PROFINET card: each output frame's 16 words go to the
//! PKW/PZD drive ([`PkwPzdDrive`] on `Bus::Profinet`, big-endian as PROFINET carries them) and
//! its 16 words come back in the input frames; the cyclic watchdog trips the drive's E-PN fault.
//! The drive's other faults are its diagnosis: [`CardCycle::poll_diagnosis`] tells when one
//! appears or disappears, [`fault_alarm`] makes the Diagnosis alarm of the card's GSDML
//! (ChannelDiagItem 0x0101, the fault type as ExtChannelAddValue). Sans-IO, as [`Cyclic`] is.

use edsgen_runtime::pkw_pzd::IMAGE_BYTES;
use edsgen_runtime::{Duration, Instant};

use super::application::IoApplication;
use super::cyclic::{CrLayout, Cyclic, DataObject};
use super::wire::alarm::{
    AlarmNotification, AlarmSource, ChannelDiagnosis, ALARM_DIAGNOSIS, ALARM_DIAGNOSIS_DISAPPEARS,
    CHANNEL_APPEARS, CHANNEL_DISAPPEARS, CHANNEL_SUBMODULE, SPEC_AR_DIAGNOSIS,
    SPEC_CHANNEL_DIAGNOSIS, SPEC_SUBMODULE_DIAGNOSIS,
};
use super::wire::Mac;
pub use crate::drives::pkw_pzd::FaultChange;
use crate::drives::pkw_pzd::PkwPzdDrive;

/// Where the card's module with the drive's 16 words sits: slot 1, subslot 1.
pub const DRIVE_SLOT: (u16, u16) = (1, 1);

/// The cyclic layout of the card's one module (slot 1, subslot 1) alone: in each CR its 32 bytes
/// of data and its IOPS, then the IOCS of the other direction. `interval` and `factor` as the
/// Connect's IOCR blocks give them.
pub fn card_layout(controller: Mac, device: Mac, interval: Duration, factor: u16) -> CrLayout {
    CrLayout {
        controller,
        device,
        output_frame_id: 0xC000,
        output_len: IMAGE_BYTES + 2,
        outputs: vec![DataObject {
            slot: 1,
            subslot: 1,
            offset: 0,
            len: IMAGE_BYTES,
        }],
        input_frame_id: 0xC001,
        input_len: IMAGE_BYTES + 2,
        inputs: vec![DataObject {
            slot: 1,
            subslot: 1,
            offset: 0,
            len: IMAGE_BYTES,
        }],
        input_iocs: vec![IMAGE_BYTES + 1],
        interval,
        watchdog_factor: factor,
    }
}

/// The card's GSDML's ChannelDiagItem of the drive's faults (other than E-PN).
pub const DRIVE_FAULT_ERROR_TYPE: u16 = 0x0101;
/// Its ExtChannelDiagItem: the fault type (P07.27) as ExtChannelAddValue.
pub const DRIVE_FAULT_EXT_ERROR_TYPE: u16 = 1;

/// The Diagnosis alarm (low priority) of `change` on the drive's submodule, whose module and
/// submodule have the ident numbers `idents`: ExtChannelDiagnosis of the whole submodule with
/// the card's error type 0x0101 and the fault type. After "appears" the submodule has a
/// diagnosis; after "disappears" none is left (the drive has one fault at a time).
pub fn fault_alarm(change: FaultChange, idents: (u32, u32)) -> AlarmNotification {
    let (alarm_type, specifier, properties, fault) = match change {
        FaultChange::Appears(f) => (
            ALARM_DIAGNOSIS,
            SPEC_CHANNEL_DIAGNOSIS | SPEC_SUBMODULE_DIAGNOSIS | SPEC_AR_DIAGNOSIS,
            CHANNEL_APPEARS,
            f,
        ),
        FaultChange::Disappears(f) => (
            ALARM_DIAGNOSIS_DISAPPEARS,
            SPEC_CHANNEL_DIAGNOSIS,
            CHANNEL_DISAPPEARS,
            f,
        ),
    };
    let diagnosis = ChannelDiagnosis {
        channel: CHANNEL_SUBMODULE,
        properties,
        error_type: DRIVE_FAULT_ERROR_TYPE,
        ext: Some((DRIVE_FAULT_EXT_ERROR_TYPE, u32::from(fault))),
    };
    let mut data = Vec::new();
    super::wire::append(&mut data, |b| diagnosis.emit(b));
    AlarmNotification {
        high: false,
        source: AlarmSource {
            alarm_type,
            api: 0,
            slot: DRIVE_SLOT.0,
            subslot: DRIVE_SLOT.1,
            specifier,
        },
        module_ident: idents.0,
        submodule_ident: idents.1,
        payload: Some((diagnosis.usi(), data)),
    }
}

/// The card's cyclic exchange and the application (the drive) behind it.
#[derive(Debug, Clone)]
pub struct CardCycle<A = PkwPzdDrive> {
    cyclic: Cyclic,
    drive: A,
    inputs: [u8; IMAGE_BYTES],
    next_send: Instant,
}

impl<A: IoApplication> CardCycle<A> {
    /// The exchange of `layout` with `drive` from `now`.
    pub fn new(layout: CrLayout, mut drive: A, now: Instant) -> Self {
        let inputs = drive.inputs();
        drive.forget_reported_fault();
        CardCycle {
            cyclic: Cyclic::new(layout),
            drive,
            inputs,
            next_send: now,
        }
    }

    /// The next change of the drive's diagnosis since the exchange started
    /// ([`IoApplication::poll_fault_change`]): E-PN ends the AR, so it is not one.
    pub fn poll_diagnosis(&mut self) -> Option<FaultChange> {
        self.drive.poll_fault_change()
    }

    /// The drive.
    pub fn drive(&self) -> &A {
        &self.drive
    }

    /// A received frame at `now`: an output frame of the CR is one exchange with the drive.
    pub fn handle(&mut self, now: Instant, frame: &[u8]) {
        if !self.cyclic.handle(now, frame) {
            return;
        }
        let Some((data, iops)) = self
            .cyclic
            .output_index(DRIVE_SLOT.0, DRIVE_SLOT.1)
            .and_then(|n| self.cyclic.output(n))
        else {
            return;
        };
        // Outputs with a bad IOPS carry nothing to act on.
        let Ok(words) = <[u8; IMAGE_BYTES]>::try_from(data) else {
            return;
        };
        if iops & 0x80 != 0 {
            self.inputs = self.drive.exchange(now, &words);
        }
    }

    /// The input frame when one is due at `now` (one per send interval).
    pub fn poll_transmit(&mut self, now: Instant) -> Option<Vec<u8>> {
        if now < self.next_send {
            return None;
        }
        self.next_send = now + self.cyclic.layout().interval;
        let inputs = self.inputs;
        let data: Vec<&[u8]> = self
            .cyclic
            .layout()
            .inputs
            .iter()
            .map(|o| {
                if (o.slot, o.subslot) == DRIVE_SLOT {
                    &inputs[..]
                } else {
                    &[][..]
                }
            })
            .collect();
        Some(self.cyclic.produce(now, &data))
    }

    /// The next time something is due: a send, the watchdog, or the drive's ramps.
    pub fn poll_timeout(&self) -> Instant {
        [
            Some(self.next_send),
            self.cyclic.poll_timeout(),
            self.drive.poll_timeout(),
        ]
        .into_iter()
        .flatten()
        .min()
        .unwrap_or(self.next_send)
    }

    /// Time passed to `now`: the watchdog trips the drive's bus fault (E-PN); `true` when it
    /// expired now (the AR is then over).
    pub fn handle_timeout(&mut self, now: Instant) -> bool {
        let expired = self.cyclic.handle_timeout(now);
        if expired {
            self.drive.communication_lost(now);
        } else {
            self.drive.handle_timeout(now);
        }
        self.inputs = self.drive.inputs();
        expired
    }

    /// The drive, when the AR ends (it serves the next one).
    pub fn into_drive(self) -> A {
        self.drive
    }

    /// Data exchange starts at `now`: the first output frame must come within `first`.
    pub fn arm(&mut self, now: Instant, first: Duration) {
        self.cyclic.arm(now, first);
    }

    /// The drive, to change its parameters (a record write).
    pub fn drive_mut(&mut self) -> &mut A {
        &mut self.drive
    }
}

#[cfg(test)]
mod tests;
