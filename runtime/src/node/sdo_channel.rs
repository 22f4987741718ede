//! One SDO server channel of the node (1200h, 1201h): its COB-IDs, read from the OD, and the
//! SDO server that runs on them. The node hands it the frames on its request COB-ID and takes
//! its responses.

use super::read_uint_or;
use crate::frame::CanFrame;
use crate::od::ObjectDictionary;
use crate::sdo::{SdoEvent, SdoServer};
use crate::time::{Duration, Instant};
use crate::wire::pdo::CobIdEntry;
use crate::wire::sdo::{SDO_REQUEST_BASE, SDO_RESPONSE_BASE};

/// The SDO server's segment timeout.
pub const SDO_TIMEOUT: Duration = Duration::from_millis(1000);

pub(crate) struct SdoChannel {
    server: SdoServer,
    /// The server may have frames to send (it was fed a request or a timeout since it last
    /// said it had none).
    busy: bool,
    enabled: bool,
    rx: u16,
    tx: u16,
}

impl SdoChannel {
    /// The default SDO server (1200h) of node `node_id`. CiA 301 fixes its COB-IDs (1200h is
    /// read-only): 600h/580h + node-ID, whatever the OD stores there (some descriptions hold
    /// 8000 0000h, to be set at run time).
    pub const fn new(node_id: u8) -> Self {
        SdoChannel {
            server: SdoServer::new(SDO_TIMEOUT),
            busy: false,
            enabled: true,
            rx: SDO_REQUEST_BASE + node_id as u16,
            tx: SDO_RESPONSE_BASE + node_id as u16,
        }
    }

    /// Reads the COB-IDs of an additional SDO server (1201h..) from the OD; none if the OD
    /// does not have it.
    pub fn configure<O: ObjectDictionary + ?Sized>(&mut self, od: &O, index: u16) {
        let rx = CobIdEntry(read_uint_or(od, index, 1, CobIdEntry::INVALID));
        let tx = CobIdEntry(read_uint_or(od, index, 2, CobIdEntry::INVALID));
        self.enabled = rx.valid() && tx.valid() && !rx.extended() && !tx.extended();
        self.rx = rx.can_id();
        self.tx = tx.can_id();
    }

    /// Whether a frame on `id` is a request to this channel.
    #[inline]
    pub fn accepts(&self, id: u16) -> bool {
        self.enabled && id == self.rx
    }

    /// Hands a request to the server.
    pub fn handle<O: ObjectDictionary + ?Sized>(
        &mut self,
        now: Instant,
        request: &[u8],
        od: &mut O,
    ) -> Option<SdoEvent> {
        self.busy = true;
        self.server.handle(now, request, od)
    }

    /// Whether the server may have a frame to send.
    #[inline]
    pub fn busy(&self) -> bool {
        self.busy
    }

    /// The server's next response frame. A channel disabled by the write it is answering still
    /// sends that answer.
    #[inline]
    pub fn poll_transmit<O: ObjectDictionary + ?Sized>(
        &mut self,
        now: Instant,
        od: &O,
    ) -> Option<CanFrame> {
        if !self.busy {
            return None;
        }
        // Busy until the server has nothing left: only then is the flag written.
        let Some(response) = self.server.poll_transmit(now, od) else {
            self.busy = false;
            return None;
        };
        Some(CanFrame::from_parts(self.tx, response, 8))
    }

    /// When the transfer in progress times out, if one is.
    #[inline]
    pub fn next_deadline(&self) -> Option<Instant> {
        self.server.poll_timeout()
    }

    /// Aborts the transfer whose timeout ([`SdoChannel::next_deadline`]) passed at `now`.
    pub fn expire<O: ObjectDictionary + ?Sized>(&mut self, now: Instant, od: &mut O) {
        self.server.handle_timeout(now, od);
        self.busy = true;
    }

    /// Drops any transfer in progress (NMT stopped, reset communication); a download leaves
    /// its entry as it was.
    pub fn reset<O: ObjectDictionary + ?Sized>(&mut self, od: &mut O) {
        self.server.reset(od);
    }
}
