//! The LSS slave (CiA 305, feature `lss`): the waiting and configuration states, switch global
//! and selective, configure and store node-ID and bit timing, inquiries, identify remote and
//! non-configured slave, and fastscan with its LSS-ID sub-state. [`LssSlave`] owns that state
//! and answers; the node applies what it asks for (a new node-ID at reset communication, the
//! store hook, the bit-rate event) and keeps an unconfigured node (ID 255) silent but for LSS.

use crate::frame::CanFrame;
use crate::od::ObjectDictionary;
use crate::time::{Duration, Instant};
use crate::wire::lss::{
    cs, IdentifyField, LssAddress, LssError, LssMode, LssRequest, LssResponse, FASTSCAN_RESET,
    LSS_RESPONSE_COB_ID, UNCONFIGURED_NODE_ID,
};
use crate::wire::nmt::NmtCommand;

use super::{read_uint_or, Event, Node, NodeHooks};

/// A bit timing: the table selector (0 the CiA 301 table, 128..=255 the manufacturer's) and the
/// entry of that table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct BitTiming {
    /// The table selector.
    pub table: u8,
    /// The entry.
    pub index: u8,
}

impl BitTiming {
    /// The bit rate in kbit/s of an entry of table 0 (CiA 301 table 1): 1000, 800, 500, 250,
    /// 125, (5 reserved), 50, 20, 10. `None` for other entries and tables (9, automatic bit
    /// rate detection, is not offered).
    pub const fn table0_kbit(self) -> Option<u16> {
        if self.table != 0 {
            return None;
        }
        match self.index {
            0 => Some(1000),
            1 => Some(800),
            2 => Some(500),
            3 => Some(250),
            4 => Some(125),
            6 => Some(50),
            7 => Some(20),
            8 => Some(10),
            _ => None,
        }
    }

    /// The table 0 entry of a bit rate in kbit/s.
    pub fn from_kbit(kbit: u16) -> Option<Self> {
        (0..=8)
            .map(|index| BitTiming { table: 0, index })
            .find(|timing| timing.table0_kbit() == Some(kbit))
    }
}

/// What the node must do after a request: the slave's own answer, if any, is queued already.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum LssAction {
    None,
    /// Store the pending node-ID and bit timing (answer with the hook's result).
    Store,
    /// Activate the pending bit timing after the switch delay.
    Activate(u16),
    /// An unconfigured node was given an ID and left the configuration state: reset
    /// communication, which takes the pending node-ID.
    TakePendingId,
}

/// The LSS slave's state.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LssSlave {
    /// The LSS address, 1018h:01..04, read at reset communication.
    address: LssAddress,
    configuration: bool,
    /// How many switch state selective frames matched in a row (0..=3).
    selective: u8,
    /// How many identify remote slave frames matched in a row (0..=5).
    identify: u8,
    /// The fastscan LSS-ID sub-state: the part under test, `None` until a fastscan reset.
    fastscan_sub: Option<u8>,
    /// The node-ID the next reset communication takes.
    pub pending_node_id: u8,
    /// The node-ID a power-on or reset node starts with (the stored one).
    pub stored_node_id: u8,
    pending_bit_timing: Option<BitTiming>,
    answer: Option<LssResponse>,
    /// While a bit timing is activated: no frame goes out before this (twice the switch delay).
    pub silent_until: Option<Instant>,
    /// The node needs the slave in [`Node::poll_transmit`]: an answer is due, the node is
    /// silent, or it is unconfigured. One flag, so that a configured node pays one test.
    pub attention: bool,
}

impl LssSlave {
    pub const fn new(node_id: u8) -> Self {
        LssSlave {
            address: [0; 4],
            configuration: false,
            selective: 0,
            identify: 0,
            fastscan_sub: None,
            pending_node_id: node_id,
            stored_node_id: node_id,
            pending_bit_timing: None,
            answer: None,
            silent_until: None,
            attention: node_id == UNCONFIGURED_NODE_ID,
        }
    }

    /// Reads the LSS address from the identity object (1018h).
    pub fn load_address<O: ObjectDictionary + ?Sized>(&mut self, od: &O) {
        for (sub, value) in (1..).zip(&mut self.address) {
            *value = read_uint_or(od, 0x1018, sub, 0);
        }
    }

    /// Whether the slave is in the LSS configuration state.
    pub fn in_configuration(&self) -> bool {
        self.configuration
    }

    fn answer(&mut self, response: LssResponse) {
        self.answer = Some(response);
        self.attention = true;
    }

    fn result(&mut self, cs: u8, error: Option<LssError>) {
        let (error, specific) = error.map_or((0, 0), LssError::codes);
        self.answer(LssResponse::Result {
            cs,
            error,
            specific,
        });
    }

    /// Answers a store request with the hook's result.
    pub fn stored(&mut self, result: Result<(), LssError>) {
        if result.is_ok() {
            self.stored_node_id = self.pending_node_id;
        }
        self.result(cs::STORE_CONFIGURATION, result.err());
    }

    /// The bit timing configured (the one activate switches to).
    pub fn pending_bit_timing(&self) -> Option<BitTiming> {
        self.pending_bit_timing
    }

    /// Takes a request. `active` is the node's node-ID; `supported` says whether a bit timing
    /// is offered.
    pub fn handle(
        &mut self,
        request: LssRequest,
        active: u8,
        supported: impl FnOnce(BitTiming) -> bool,
    ) -> LssAction {
        let unconfigured =
            active == UNCONFIGURED_NODE_ID && self.pending_node_id == UNCONFIGURED_NODE_ID;
        if !matches!(request, LssRequest::SwitchSelective(..)) {
            self.selective = 0;
        }
        if !matches!(request, LssRequest::IdentifyRemote(..)) {
            self.identify = 0;
        }
        match request {
            LssRequest::SwitchGlobal(LssMode::Configuration) => self.configuration = true,
            LssRequest::SwitchGlobal(LssMode::Waiting) => {
                let was = core::mem::replace(&mut self.configuration, false);
                if was
                    && active == UNCONFIGURED_NODE_ID
                    && self.pending_node_id != UNCONFIGURED_NODE_ID
                {
                    return LssAction::TakePendingId;
                }
            }
            LssRequest::SwitchSelective(part, value) => {
                let matches = self.address[usize::from(part.index())] == value;
                if matches && part.index() == self.selective {
                    self.selective += 1;
                } else {
                    self.selective = 0;
                }
                if self.selective == 4 {
                    self.selective = 0;
                    self.configuration = true;
                    self.answer(LssResponse::SwitchSelective);
                }
            }
            LssRequest::IdentifyRemote(field, value) => self.identify_remote(field, value),
            LssRequest::IdentifyNonConfigured => {
                if unconfigured {
                    self.answer(LssResponse::NonConfiguredSlave);
                }
            }
            LssRequest::Fastscan(scan) => {
                if self.configuration || !unconfigured {
                    return LssAction::None;
                }
                if scan.bit_checked == FASTSCAN_RESET {
                    self.fastscan_sub = Some(0);
                    self.answer(LssResponse::IdentifySlave);
                    return LssAction::None;
                }
                let Some(sub) = self.fastscan_sub else {
                    return LssAction::None;
                };
                if scan.bit_checked > 31 || scan.lss_sub != sub || sub > 3 {
                    return LssAction::None;
                }
                let mask = u32::MAX << scan.bit_checked;
                if (self.address[usize::from(sub)] ^ scan.id_number) & mask != 0 {
                    return LssAction::None;
                }
                self.answer(LssResponse::IdentifySlave);
                if scan.bit_checked == 0 {
                    if scan.lss_next < sub {
                        self.fastscan_sub = None;
                        self.configuration = true;
                    } else if scan.lss_next <= 3 {
                        self.fastscan_sub = Some(scan.lss_next);
                    }
                }
            }
            // The rest is served in the configuration state only; in waiting it is ignored.
            _ if !self.configuration => {}
            LssRequest::ConfigureNodeId(id) => {
                let valid = matches!(id, 1..=127 | UNCONFIGURED_NODE_ID);
                if valid {
                    self.pending_node_id = id;
                }
                self.result(
                    cs::CONFIGURE_NODE_ID,
                    (!valid).then_some(LssError::OutOfRange),
                );
            }
            LssRequest::ConfigureBitTiming { table, index } => {
                let timing = BitTiming { table, index };
                let valid = supported(timing);
                if valid {
                    self.pending_bit_timing = Some(timing);
                }
                self.result(
                    cs::CONFIGURE_BIT_TIMING,
                    (!valid).then_some(LssError::OutOfRange),
                );
            }
            LssRequest::ActivateBitTiming(delay) => {
                if self.pending_bit_timing.is_some() {
                    return LssAction::Activate(delay);
                }
            }
            LssRequest::StoreConfiguration => return LssAction::Store,
            LssRequest::Inquire(part) => {
                self.answer(LssResponse::Identity(
                    part,
                    self.address[usize::from(part.index())],
                ));
            }
            LssRequest::InquireNodeId => self.answer(LssResponse::NodeId(active)),
        }
        LssAction::None
    }

    /// Identify remote slave: vendor and product must be equal, revision and serial number
    /// within the bounds; the slave answers after the serial number's high bound.
    fn identify_remote(&mut self, field: IdentifyField, value: u32) {
        let [vendor, product, revision, serial] = self.address;
        let (position, matches) = match field {
            IdentifyField::Vendor => (0, vendor == value),
            IdentifyField::Product => (1, product == value),
            IdentifyField::RevisionLow => (2, revision >= value),
            IdentifyField::RevisionHigh => (3, revision <= value),
            IdentifyField::SerialLow => (4, serial >= value),
            IdentifyField::SerialHigh => (5, serial <= value),
        };
        // A vendor frame starts a new sequence.
        if position == 0 {
            self.identify = 0;
        }
        if matches && position == self.identify {
            self.identify += 1;
        } else {
            self.identify = 0;
        }
        if self.identify == 6 {
            self.identify = 0;
            self.answer(LssResponse::IdentifySlave);
        }
    }

    /// The slave's answer, if one is due.
    pub fn poll_transmit(&mut self) -> Option<CanFrame> {
        let answer = self.answer.take()?;
        Some(CanFrame::from_parts(LSS_RESPONSE_COB_ID, answer.emit(), 8))
    }
}

impl<O: ObjectDictionary, H: NodeHooks<O>, const RPDOS: usize, const TPDOS: usize>
    Node<O, H, RPDOS, TPDOS>
{
    /// A frame on 7E5h, or any frame while the node is unconfigured: whether LSS took it (a
    /// request on 7E5h, or a frame an unconfigured node does not serve). Out of line and cold,
    /// so that a configured node's frames pay one comparison for LSS.
    #[cold]
    #[inline(never)]
    pub(super) fn lss_takes_frame(&mut self, id: u16, frame: &CanFrame, now: Instant) -> bool {
        if id == crate::wire::lss::LSS_REQUEST_COB_ID && !frame.is_remote() {
            self.handle_lss(frame.data(), now);
            return true;
        }
        self.is_unconfigured()
    }

    /// What [`Node::poll_transmit`] returns while the LSS slave has something to say or keeps
    /// the node silent, or the node is unconfigured: `Some(frame)` (the answer, or `None` while
    /// silent or unconfigured), else `None` and the node's other services go on. Out of line
    /// and cold, like [`Node::lss_takes_frame`].
    #[cold]
    #[inline(never)]
    pub(super) fn poll_lss(&mut self, now: Instant) -> Option<Option<CanFrame>> {
        if self.lss_silent(now) {
            return Some(None);
        }
        if let Some(frame) = self.lss.poll_transmit() {
            return Some(Some(frame));
        }
        let unconfigured = self.is_unconfigured();
        self.lss.attention = unconfigured || self.lss.silent_until.is_some();
        unconfigured.then_some(None)
    }

    /// A frame on 7E5h.
    fn handle_lss(&mut self, data: &[u8], now: Instant) {
        let Some(request) = LssRequest::parse(data) else {
            return;
        };
        let hooks = &self.hooks;
        let action = self.lss.handle(request, self.node_id, |timing| {
            hooks.bit_timing_supported(timing)
        });
        match action {
            LssAction::None => {}
            LssAction::Store => {
                let timing = self.lss.pending_bit_timing();
                let result = self.hooks.store_lss(self.lss.pending_node_id, timing);
                self.lss.stored(result);
            }
            LssAction::Activate(switch_delay_ms) => {
                let delay = Duration::from_millis(u64::from(switch_delay_ms));
                self.lss.silent_until = Some(now + delay + delay);
                self.lss.attention = true;
                if let Some(timing) = self.lss.pending_bit_timing() {
                    self.events.push(Event::BitTimingActivated {
                        timing,
                        switch_delay_ms,
                    });
                }
            }
            LssAction::TakePendingId => self.handle_nmt(NmtCommand::ResetCommunication, now),
        }
    }

    /// Whether the node has no node-ID (255): it serves LSS only.
    pub fn is_unconfigured(&self) -> bool {
        self.node_id == UNCONFIGURED_NODE_ID
    }

    /// The LSS state: whether the slave is in configuration (else waiting).
    pub fn lss_configuration(&self) -> bool {
        self.lss.in_configuration()
    }

    /// Whether an activated bit timing keeps the node silent at `now` (CiA 305: from the
    /// activate request until twice the switch delay has passed).
    fn lss_silent(&mut self, now: Instant) -> bool {
        if self.lss.silent_until.is_some_and(|until| now < until) {
            return true;
        }
        self.lss.silent_until = None;
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wire::lss::{Fastscan, LssPart};
    use proptest::prelude::*;

    const CP301: LssAddress = [0x0000_04D8, 0x0000_9252, 1, 7];

    fn slave(address: LssAddress) -> LssSlave {
        let mut slave = LssSlave::new(UNCONFIGURED_NODE_ID);
        slave.address = address;
        slave
    }

    /// Feeds request bytes as received on 7E5h; returns the action and the answer's bytes.
    fn feed(slave: &mut LssSlave, bytes: [u8; 8]) -> (LssAction, Option<[u8; 8]>) {
        let request = LssRequest::parse(&bytes).expect("a valid request");
        let action = slave.handle(request, UNCONFIGURED_NODE_ID, |t| t.table0_kbit().is_some());
        let answer = slave.poll_transmit().map(|f| f.data().try_into().unwrap());
        (action, answer)
    }

    #[test]
    fn switch_selective_then_configure_node_id_and_back_to_waiting() {
        let mut s = slave(CP301);
        assert_eq!(feed(&mut s, [0x40, 0xD8, 4, 0, 0, 0, 0, 0]).1, None);
        assert_eq!(feed(&mut s, [0x41, 0x52, 0x92, 0, 0, 0, 0, 0]).1, None);
        assert_eq!(feed(&mut s, [0x42, 1, 0, 0, 0, 0, 0, 0]).1, None);
        assert_eq!(
            feed(&mut s, [0x43, 7, 0, 0, 0, 0, 0, 0]).1,
            Some([0x44, 0, 0, 0, 0, 0, 0, 0])
        );
        assert!(s.in_configuration());
        assert_eq!(
            feed(&mut s, [0x5D, 0, 0, 0, 0, 0, 0, 0]).1,
            Some([0x5D, 7, 0, 0, 0, 0, 0, 0])
        );
        assert_eq!(
            feed(&mut s, [0x5E, 0, 0, 0, 0, 0, 0, 0]).1,
            Some([0x5E, 0xFF, 0, 0, 0, 0, 0, 0])
        );
        assert_eq!(
            feed(&mut s, [0x11, 5, 0, 0, 0, 0, 0, 0]).1,
            Some([0x11, 0, 0, 0, 0, 0, 0, 0])
        );
        assert_eq!(s.pending_node_id, 5);
        assert_eq!(
            feed(&mut s, [0x04, 0, 0, 0, 0, 0, 0, 0]),
            (LssAction::TakePendingId, None)
        );
        assert!(!s.in_configuration());
    }

    #[test]
    fn a_wrong_serial_does_not_switch() {
        let mut s = slave(CP301);
        for bytes in [
            [0x40, 0xD8, 4, 0, 0, 0, 0, 0],
            [0x41, 0x52, 0x92, 0, 0, 0, 0, 0],
            [0x42, 1, 0, 0, 0, 0, 0, 0],
            [0x43, 8, 0, 0, 0, 0, 0, 0],
        ] {
            assert_eq!(feed(&mut s, bytes).1, None);
        }
        assert!(!s.in_configuration());
    }

    #[test]
    fn refusals_as_cia305_says() {
        let mut s = slave(CP301);
        // Waiting state: configure, store and inquiries are ignored.
        assert_eq!(
            feed(&mut s, [0x11, 5, 0, 0, 0, 0, 0, 0]),
            (LssAction::None, None)
        );
        assert_eq!(
            feed(&mut s, [0x17, 0, 0, 0, 0, 0, 0, 0]),
            (LssAction::None, None)
        );
        assert_eq!(
            feed(&mut s, [0x5A, 0, 0, 0, 0, 0, 0, 0]),
            (LssAction::None, None)
        );
        assert_eq!(s.pending_node_id, 0xFF);
        feed(&mut s, [0x04, 1, 0, 0, 0, 0, 0, 0]);
        for id in [0u8, 128, 200, 254] {
            assert_eq!(
                feed(&mut s, [0x11, id, 0, 0, 0, 0, 0, 0]).1,
                Some([0x11, 1, 0, 0, 0, 0, 0, 0]),
                "node-ID {id}"
            );
        }
        assert_eq!(s.pending_node_id, 0xFF);
        // Table 0 entry 5 is reserved, 9 (automatic detection) not offered, table 1 reserved.
        for (table, index) in [(0u8, 5u8), (0, 9), (1, 0), (0x80, 0)] {
            assert_eq!(
                feed(&mut s, [0x13, table, index, 0, 0, 0, 0, 0]).1,
                Some([0x13, 1, 0, 0, 0, 0, 0, 0])
            );
        }
        // Activate without a configured bit timing does nothing.
        assert_eq!(
            feed(&mut s, [0x15, 10, 0, 0, 0, 0, 0, 0]),
            (LssAction::None, None)
        );
        assert_eq!(
            feed(&mut s, [0x13, 0, 3, 0, 0, 0, 0, 0]).1,
            Some([0x13, 0, 0, 0, 0, 0, 0, 0])
        );
        assert_eq!(
            feed(&mut s, [0x15, 0xF4, 1, 0, 0, 0, 0, 0]),
            (LssAction::Activate(500), None)
        );
        assert_eq!(
            feed(&mut s, [0x17, 0, 0, 0, 0, 0, 0, 0]),
            (LssAction::Store, None)
        );
        s.stored(Err(LssError::StoreNotSupported));
        assert_eq!(
            s.poll_transmit().unwrap().data(),
            [0x17, 1, 0, 0, 0, 0, 0, 0]
        );
        s.stored(Err(LssError::Specific(9)));
        assert_eq!(
            s.poll_transmit().unwrap().data(),
            [0x17, 255, 9, 0, 0, 0, 0, 0]
        );
    }

    #[test]
    fn identify_remote_and_non_configured() {
        let mut s = slave(CP301);
        let sequence = |serial_high: u32| {
            [
                [0x46, 0xD8, 4, 0, 0, 0, 0, 0],
                [0x47, 0x52, 0x92, 0, 0, 0, 0, 0],
                [0x48, 0, 0, 0, 0, 0, 0, 0],
                [0x49, 5, 0, 0, 0, 0, 0, 0],
                [0x4A, 7, 0, 0, 0, 0, 0, 0],
                LssRequest::IdentifyRemote(IdentifyField::SerialHigh, serial_high).emit(),
            ]
        };
        let answers: Vec<_> = sequence(9).into_iter().map(|b| feed(&mut s, b).1).collect();
        assert_eq!(answers[..5], [None; 5]);
        assert_eq!(answers[5], Some([0x4F, 0, 0, 0, 0, 0, 0, 0]));
        let answers: Vec<_> = sequence(6).into_iter().map(|b| feed(&mut s, b).1).collect();
        assert_eq!(answers, [None; 6], "serial 7 above the range");
        assert_eq!(
            feed(&mut s, [0x4C, 0, 0, 0, 0, 0, 0, 0]).1,
            Some([0x50, 0, 0, 0, 0, 0, 0, 0])
        );
        s.pending_node_id = 5;
        assert_eq!(feed(&mut s, [0x4C, 0, 0, 0, 0, 0, 0, 0]).1, None);
    }

    /// A master's fastscan as CiA 305 describes it (and python canopen runs it) against
    /// `slaves` on one bus: returns the address found, whose slave is then in configuration.
    fn fastscan(slaves: &mut [LssSlave]) -> Option<LssAddress> {
        let mut ask = |f: Fastscan| {
            let bytes = LssRequest::Fastscan(f).emit();
            let mut any = false;
            for s in slaves.iter_mut() {
                any |= feed(s, bytes).1 == Some([0x4F, 0, 0, 0, 0, 0, 0, 0]);
            }
            any
        };
        let reset = Fastscan {
            id_number: 0,
            bit_checked: FASTSCAN_RESET,
            lss_sub: 0,
            lss_next: 0,
        };
        if !ask(reset) {
            return None;
        }
        let mut id = [0u32; 4];
        let mut next = 0;
        for sub in 0..4u8 {
            for bit in (0..32u8).rev() {
                let probe = Fastscan {
                    id_number: id[usize::from(sub)],
                    bit_checked: bit,
                    lss_sub: sub,
                    lss_next: next,
                };
                if !ask(probe) {
                    id[usize::from(sub)] |= 1 << bit;
                }
            }
            next = (sub + 1) & 3;
            let confirm = Fastscan {
                id_number: id[usize::from(sub)],
                bit_checked: 0,
                lss_sub: sub,
                lss_next: next,
            };
            if !ask(confirm) {
                return None;
            }
        }
        Some(id)
    }

    #[test]
    fn fastscan_finds_each_unconfigured_slave_in_turn() {
        let addresses = [CP301, [0x4D8, 0x9252, 1, 8], [0x0000_0300, 0x350, 0x10, 1]];
        let mut slaves = addresses.map(slave);
        let mut found = Vec::new();
        while let Some(address) = fastscan(&mut slaves) {
            let configured: Vec<_> = slaves.iter().map(|s| s.in_configuration()).collect();
            let k = addresses.iter().position(|a| *a == address).unwrap();
            assert_eq!(configured.iter().filter(|c| **c).count(), 1);
            assert!(configured[k], "the slave found is the one in configuration");
            found.push(address);
            // Give it an ID: it no longer takes part.
            feed(&mut slaves[k], [0x11, 10 + k as u8, 0, 0, 0, 0, 0, 0]);
            feed(&mut slaves[k], [0x04, 0, 0, 0, 0, 0, 0, 0]);
            assert!(found.len() <= 3);
        }
        found.sort();
        let mut expected = addresses.to_vec();
        expected.sort();
        assert_eq!(found, expected);
        assert_eq!(LssPart::ALL.len(), 4);
    }

    proptest! {
        /// No sequence of frames on 7E5h leaves the slave inconsistent: its counters stay in
        /// range, the pending node-ID is valid, and it never answers a request that has none.
        #[test]
        fn no_frame_sequence_leaves_the_slave_inconsistent(
            frames in proptest::collection::vec(
                (prop::sample::select(vec![
                    0x04u8, 0x11, 0x13, 0x15, 0x17, 0x40, 0x41, 0x42, 0x43, 0x46, 0x47, 0x48,
                    0x49, 0x4A, 0x4B, 0x4C, 0x51, 0x5A, 0x5B, 0x5C, 0x5D, 0x5E, 0x00, 0xFF,
                ]), any::<[u8; 7]>()),
                0..64,
            )
        ) {
            let mut s = slave(CP301);
            for (cs, rest) in frames {
                let mut bytes = [cs; 8];
                bytes[1..].copy_from_slice(&rest);
                let Some(request) = LssRequest::parse(&bytes) else { continue };
                s.handle(request, UNCONFIGURED_NODE_ID, |t| t.table0_kbit().is_some());
                prop_assert!(s.selective <= 3 && s.identify <= 5);
                prop_assert!(s.fastscan_sub.is_none_or(|sub| sub <= 3));
                prop_assert!(matches!(s.pending_node_id, 1..=127 | 0xFF));
                if let Some(answer) = s.poll_transmit() {
                    let answer = LssResponse::parse(answer.data());
                    prop_assert!(answer.is_some());
                    prop_assert!(!matches!(
                        request,
                        LssRequest::SwitchGlobal(_) | LssRequest::ActivateBitTiming(_)
                    ));
                }
            }
        }
    }
}
