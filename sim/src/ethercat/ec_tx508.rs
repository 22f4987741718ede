//! The EC-TX508 card as a SubDevice [`Behaviour`]: each cycle its default process images
//! (RxPDO 1600h in, TxPDO 1A00h out, as the ESI assigns them) are taken from and put back into
//! the dictionary's mapped objects around one cycle of the card's CiA 402 drive
//! ([`crate::drives::ec_tx508::EcTx508`]). A master that reassigns PDOs still reaches
//! the same objects; the drive sees them as the default images lay them out.

use edsgen_model::model::Device;
use edsgen_runtime::Instant;

use super::device::{Behaviour, Mapped};
use super::image::{image_len, pack, place, unpack, Placed};
use crate::canopen::RuntimeDictionary;
use crate::drives::ec_tx508::EcTx508;

/// The card's drive behind its dictionary.
#[derive(Debug)]
pub struct EcTx508Behaviour {
    card: EcTx508,
    outputs: Vec<Mapped>,
    inputs: Vec<Mapped>,
    /// `outputs` and `inputs` placed in the dictionary, at the first cycle (its entries never
    /// move), and the outputs image they are packed into.
    placed: Option<(Vec<Placed>, Vec<Placed>, Vec<u8>)>,
}

impl EcTx508Behaviour {
    /// The card powered up at `now`, its images laid out by `device`'s (the EC-TX508's ESI)
    /// default PDO assignment.
    pub fn new(device: &Device, now: Instant) -> Self {
        let default = |pdos: &[edsgen_model::model::EcPdo]| -> Vec<Mapped> {
            pdos.iter()
                .filter(|p| p.sm.is_some())
                .flat_map(|p| p.entries.iter().map(|e| (e.index, e.sub, e.bit_len)))
                .collect()
        };
        let (outputs, inputs) = device
            .ethercat()
            .map(|ec| (default(&ec.rx_pdos), default(&ec.tx_pdos)))
            .unwrap_or_default();
        EcTx508Behaviour {
            card: EcTx508::new(now),
            outputs,
            inputs,
            placed: None,
        }
    }

    /// The card, to look at its drive.
    pub fn card(&self) -> &EcTx508 {
        &self.card
    }

    /// The card, to raise and clear its drive's faults as the application would.
    pub fn card_mut(&mut self) -> &mut EcTx508 {
        &mut self.card
    }
}

impl Behaviour for EcTx508Behaviour {
    fn cycle(&mut self, now: Instant, od: &mut RuntimeDictionary) {
        let (outputs, inputs, image) = self.placed.get_or_insert_with(|| {
            let outputs = place(od, &self.outputs);
            let image = vec![0; image_len(&outputs)];
            (outputs, place(od, &self.inputs), image)
        });
        pack(od, outputs, image);
        if let Ok(values) = self.card.cycle(now, image) {
            unpack(od, inputs, &values);
        }
    }
}
