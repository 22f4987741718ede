//! The LSS master (CiA 305), sans-IO: one service at a time ([`LssService`]), its requests out
//! on 7E5h, the slaves' answers in from 7E4h, a timeout per awaited answer, and the result
//! ([`LssOutcome`]). Fastscan runs the CiA 305 bit search over the four parts of the LSS
//! address and leaves the slave it finds in the configuration state; run it again (after giving
//! that slave an ID) to find the next. Frame layouts come from [`crate::wire::lss`].
//!
//! CiA 305 leaves the time a master waits for an answer to the application; python `canopen`
//! waits 0.5 s. [`DEFAULT_TIMEOUT`] is used for confirmed services, [`FASTSCAN_TIMEOUT`] for each
//! fastscan and identify probe, where silence is an answer too.

use crate::frame::CanFrame;
use crate::time::{Duration, Instant};
use crate::wire::lss::{
    cs, Fastscan, IdentifyField, LssAddress, LssError, LssMode, LssPart, LssRequest, LssResponse,
    FASTSCAN_RESET, LSS_REQUEST_COB_ID, LSS_RESPONSE_COB_ID,
};

/// How long a confirmed service waits for the slave's answer.
pub const DEFAULT_TIMEOUT: Duration = Duration::from_millis(500);
/// How long a fastscan or identify probe waits before it takes silence for "no".
pub const FASTSCAN_TIMEOUT: Duration = Duration::from_millis(100);
/// How long the master waits after a probe's first answer before its next request: several
/// slaves answer a probe at once (one frame on a real bus, several on a virtual one), and the
/// late copies must not be taken for answers to the next probe. python `canopen` waits 10 ms.
pub const PROBE_SETTLE: Duration = Duration::from_millis(10);

/// An LSS service to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LssService {
    /// Switch state global: every slave to waiting or configuration (no answer).
    SwitchGlobal(LssMode),
    /// Switch state selective: the slave with this address to configuration.
    SwitchSelective(LssAddress),
    /// Configure node-ID (1..=127, or 255 for unconfigured).
    ConfigureNodeId(u8),
    /// Configure bit timing: table selector and entry.
    ConfigureBitTiming {
        /// Table selector (0 the CiA 301 table).
        table: u8,
        /// Entry of the table.
        index: u8,
    },
    /// Activate bit timing with the switch delay in milliseconds (no answer).
    ActivateBitTiming(u16),
    /// Store configuration.
    Store,
    /// Inquire the LSS address of the slave in configuration.
    InquireAddress,
    /// Inquire the node-ID of the slave in configuration.
    InquireNodeId,
    /// Identify remote slave: whether a slave of this vendor and product with revision and
    /// serial number within the bounds (inclusive) answers.
    IdentifyRemote {
        /// Vendor-ID.
        vendor: u32,
        /// Product code.
        product: u32,
        /// Revision number bounds.
        revision: (u32, u32),
        /// Serial number bounds.
        serial: (u32, u32),
    },
    /// Identify non-configured remote slave: whether any slave without a node-ID answers.
    IdentifyNonConfigured,
    /// Fastscan: the address of one non-configured slave in waiting state, which it leaves in
    /// configuration; `None` if none answers.
    Fastscan,
}

/// What a service found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LssOutcome {
    /// Done (switches, configure, store, activate).
    Done,
    /// The inquired address.
    Address(LssAddress),
    /// The inquired node-ID.
    NodeId(u8),
    /// Whether some slave answered an identify request.
    Identified(bool),
    /// The address fastscan found, if any slave took part.
    Scanned(Option<LssAddress>),
}

/// Why a service failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LssMasterError {
    /// No answer in time (no slave in configuration, or the addressed one absent).
    NoAnswer,
    /// The slave refused: its error code.
    Refused(LssError),
    /// A fastscan lost its slave halfway (it answered one probe, not the next).
    ScanLost,
    /// Another service is running.
    Busy,
}

impl core::fmt::Display for LssMasterError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            LssMasterError::NoAnswer => write!(f, "no LSS answer"),
            LssMasterError::Refused(LssError::OutOfRange) => {
                write!(
                    f,
                    "refused: node-ID out of range or bit timing not supported (1)"
                )
            }
            LssMasterError::Refused(LssError::StoreNotSupported) => {
                write!(f, "refused: store configuration not supported (1)")
            }
            LssMasterError::Refused(LssError::StorageAccess) => {
                write!(f, "refused: storage media access error (2)")
            }
            LssMasterError::Refused(LssError::Reserved(code)) => {
                write!(f, "refused with reserved error code {code}")
            }
            LssMasterError::Refused(LssError::Specific(code)) => {
                write!(f, "refused: implementation-specific error (255, {code})")
            }
            LssMasterError::ScanLost => write!(f, "fastscan lost the slave"),
            LssMasterError::Busy => write!(f, "another LSS service is running"),
        }
    }
}

/// What the master waits for after a request.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Expect {
    /// Nothing: the next request follows at once.
    Nothing,
    /// An answer with this specifier, required.
    Answer(u8),
    /// An answer with this specifier, or silence (a "no").
    Probe(u8),
}

/// Where a fastscan is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum ScanPhase {
    Reset,
    Bit(u8),
    Confirm,
}

/// A running service and its progress.
#[derive(Debug, Clone, Copy)]
struct Job {
    service: LssService,
    step: u8,
    address: LssAddress,
    phase: ScanPhase,
}

type Finished = Option<Result<LssOutcome, LssMasterError>>;

impl Job {
    fn new(service: LssService) -> Self {
        Job {
            service,
            step: 0,
            address: [0; 4],
            phase: ScanPhase::Reset,
        }
    }

    /// The next request and what to wait for.
    fn request(&self) -> (LssRequest, Expect) {
        let part = LssPart::from_index(self.step & 3).unwrap_or(LssPart::Vendor);
        match self.service {
            LssService::SwitchGlobal(mode) => (LssRequest::SwitchGlobal(mode), Expect::Nothing),
            LssService::SwitchSelective(address) => {
                let expect = if self.step == 3 {
                    Expect::Answer(cs::SWITCH_SELECTIVE_ANSWER)
                } else {
                    Expect::Nothing
                };
                let value = address[usize::from(part.index())];
                (LssRequest::SwitchSelective(part, value), expect)
            }
            LssService::ConfigureNodeId(id) => (
                LssRequest::ConfigureNodeId(id),
                Expect::Answer(cs::CONFIGURE_NODE_ID),
            ),
            LssService::ConfigureBitTiming { table, index } => (
                LssRequest::ConfigureBitTiming { table, index },
                Expect::Answer(cs::CONFIGURE_BIT_TIMING),
            ),
            LssService::ActivateBitTiming(delay) => {
                (LssRequest::ActivateBitTiming(delay), Expect::Nothing)
            }
            LssService::Store => (
                LssRequest::StoreConfiguration,
                Expect::Answer(cs::STORE_CONFIGURATION),
            ),
            LssService::InquireAddress => (
                LssRequest::Inquire(part),
                Expect::Answer(cs::INQUIRE_VENDOR + part.index()),
            ),
            LssService::InquireNodeId => (
                LssRequest::InquireNodeId,
                Expect::Answer(cs::INQUIRE_NODE_ID),
            ),
            LssService::IdentifyRemote {
                vendor,
                product,
                revision,
                serial,
            } => {
                let (field, value) = match self.step {
                    0 => (IdentifyField::Vendor, vendor),
                    1 => (IdentifyField::Product, product),
                    2 => (IdentifyField::RevisionLow, revision.0),
                    3 => (IdentifyField::RevisionHigh, revision.1),
                    4 => (IdentifyField::SerialLow, serial.0),
                    _ => (IdentifyField::SerialHigh, serial.1),
                };
                let expect = if self.step == 5 {
                    Expect::Probe(cs::IDENTIFY_SLAVE)
                } else {
                    Expect::Nothing
                };
                (LssRequest::IdentifyRemote(field, value), expect)
            }
            LssService::IdentifyNonConfigured => (
                LssRequest::IdentifyNonConfigured,
                Expect::Probe(cs::NON_CONFIGURED_SLAVE),
            ),
            LssService::Fastscan => {
                let sub = self.step;
                let id_number = self.address[usize::from(sub & 3)];
                let scan = match self.phase {
                    ScanPhase::Reset => Fastscan {
                        id_number: 0,
                        bit_checked: FASTSCAN_RESET,
                        lss_sub: 0,
                        lss_next: 0,
                    },
                    ScanPhase::Bit(bit) => Fastscan {
                        id_number,
                        bit_checked: bit,
                        lss_sub: sub,
                        lss_next: sub,
                    },
                    ScanPhase::Confirm => Fastscan {
                        id_number,
                        bit_checked: 0,
                        lss_sub: sub,
                        lss_next: (sub + 1) & 3,
                    },
                };
                (
                    LssRequest::Fastscan(scan),
                    Expect::Probe(cs::IDENTIFY_SLAVE),
                )
            }
        }
    }

    /// Takes the answer to the last request (`None`: silence, or no answer was awaited);
    /// `Some` when the service is over.
    fn feed(&mut self, answer: Option<LssResponse>) -> Finished {
        let done = Some(Ok(LssOutcome::Done));
        match self.service {
            LssService::SwitchGlobal(_) | LssService::ActivateBitTiming(_) => done,
            LssService::SwitchSelective(_) => {
                self.step += 1;
                (self.step == 4).then_some(Ok(LssOutcome::Done))
            }
            LssService::ConfigureNodeId(_)
            | LssService::ConfigureBitTiming { .. }
            | LssService::Store => match answer {
                Some(LssResponse::Result {
                    cs,
                    error,
                    specific,
                }) => match LssError::from_codes(cs, error, specific) {
                    None => done,
                    Some(error) => Some(Err(LssMasterError::Refused(error))),
                },
                _ => Some(Err(LssMasterError::NoAnswer)),
            },
            LssService::InquireAddress => {
                if let Some(LssResponse::Identity(part, value)) = answer {
                    self.address[usize::from(part.index())] = value;
                }
                self.step += 1;
                (self.step == 4).then_some(Ok(LssOutcome::Address(self.address)))
            }
            LssService::InquireNodeId => match answer {
                Some(LssResponse::NodeId(id)) => Some(Ok(LssOutcome::NodeId(id))),
                _ => Some(Err(LssMasterError::NoAnswer)),
            },
            LssService::IdentifyRemote { .. } => {
                self.step += 1;
                (self.step == 6).then_some(Ok(LssOutcome::Identified(answer.is_some())))
            }
            LssService::IdentifyNonConfigured => Some(Ok(LssOutcome::Identified(answer.is_some()))),
            LssService::Fastscan => self.feed_scan(answer.is_some()),
        }
    }

    fn feed_scan(&mut self, answered: bool) -> Finished {
        let sub = usize::from(self.step & 3);
        match self.phase {
            ScanPhase::Reset if !answered => return Some(Ok(LssOutcome::Scanned(None))),
            ScanPhase::Reset => self.phase = ScanPhase::Bit(31),
            ScanPhase::Bit(bit) => {
                if !answered {
                    self.address[sub] |= 1 << bit;
                }
                self.phase = match bit {
                    0 => ScanPhase::Confirm,
                    _ => ScanPhase::Bit(bit - 1),
                };
            }
            ScanPhase::Confirm if !answered => return Some(Err(LssMasterError::ScanLost)),
            ScanPhase::Confirm => {
                self.step += 1;
                if self.step == 4 {
                    return Some(Ok(LssOutcome::Scanned(Some(self.address))));
                }
                self.phase = ScanPhase::Bit(31);
            }
        }
        None
    }
}

/// The LSS master: one service at a time.
#[derive(Debug, Clone)]
pub struct LssMaster {
    timeout: Duration,
    probe_timeout: Duration,
    job: Option<Job>,
    /// The request to send next and what it waits for.
    next: Option<(LssRequest, Expect)>,
    /// The answer awaited, until when.
    waiting: Option<(Expect, Instant)>,
    /// After a probe's answer: the next request waits until then ([`PROBE_SETTLE`]).
    settle_until: Option<Instant>,
    result: Finished,
}

impl Default for LssMaster {
    fn default() -> Self {
        LssMaster::new()
    }
}

impl LssMaster {
    /// A master with [`DEFAULT_TIMEOUT`] and [`FASTSCAN_TIMEOUT`].
    pub const fn new() -> Self {
        LssMaster {
            timeout: DEFAULT_TIMEOUT,
            probe_timeout: FASTSCAN_TIMEOUT,
            job: None,
            next: None,
            waiting: None,
            settle_until: None,
            result: None,
        }
    }

    /// Sets the time a confirmed service waits for its answer, and a probe (fastscan,
    /// identify) for silence.
    pub fn set_timeouts(&mut self, answer: Duration, probe: Duration) {
        self.timeout = answer;
        self.probe_timeout = probe;
    }

    /// Starts a service. [`LssMasterError::Busy`] while another runs.
    pub fn start(&mut self, service: LssService) -> Result<(), LssMasterError> {
        if self.job.is_some() {
            return Err(LssMasterError::Busy);
        }
        let job = Job::new(service);
        self.next = Some(job.request());
        self.job = Some(job);
        self.result = None;
        Ok(())
    }

    /// Whether a service runs.
    pub fn is_busy(&self) -> bool {
        self.job.is_some()
    }

    /// The next request to send.
    pub fn poll_transmit(&mut self, now: Instant) -> Option<CanFrame> {
        if self.settle_until.is_some_and(|until| now < until) {
            return None;
        }
        self.settle_until = None;
        let (request, expect) = self.next.take()?;
        let frame = CanFrame::from_parts(LSS_REQUEST_COB_ID, request.emit(), 8);
        match expect {
            Expect::Nothing => self.advance(None),
            Expect::Answer(_) => self.waiting = Some((expect, now + self.timeout)),
            Expect::Probe(_) => self.waiting = Some((expect, now + self.probe_timeout)),
        }
        Some(frame)
    }

    /// Takes a received frame (answers on 7E4h; others are ignored).
    pub fn handle_frame(&mut self, now: Instant, frame: &CanFrame) {
        if frame.std_id() != Some(LSS_RESPONSE_COB_ID) || frame.is_remote() {
            return;
        }
        let Some(response) = LssResponse::parse(frame.data()) else {
            return;
        };
        let Some((expect, _)) = self.waiting else {
            return;
        };
        let (Expect::Answer(cs) | Expect::Probe(cs)) = expect else {
            return;
        };
        if response.emit()[0] == cs {
            self.waiting = None;
            if matches!(expect, Expect::Probe(_)) {
                self.settle_until = Some(now + PROBE_SETTLE);
            }
            self.advance(Some(response));
        }
    }

    /// When the awaited answer times out.
    pub fn poll_timeout(&self) -> Option<Instant> {
        match (self.waiting, self.settle_until) {
            (Some((_, at)), _) => Some(at),
            (None, settle) => settle.filter(|_| self.next.is_some()),
        }
    }

    /// Runs the timeout, if due: a required answer missing ends the service with
    /// [`LssMasterError::NoAnswer`], a probe's silence is its "no".
    pub fn handle_timeout(&mut self, now: Instant) {
        let Some((expect, at)) = self.waiting else {
            if self.settle_until.is_some_and(|until| until <= now) {
                self.settle_until = None;
            }
            return;
        };
        if now < at {
            return;
        }
        self.waiting = None;
        match expect {
            Expect::Answer(_) => self.finish(Err(LssMasterError::NoAnswer)),
            _ => self.advance(None),
        }
    }

    /// The result of the service that ended.
    pub fn poll_result(&mut self) -> Option<Result<LssOutcome, LssMasterError>> {
        self.result.take()
    }

    fn advance(&mut self, answer: Option<LssResponse>) {
        let Some(job) = self.job.as_mut() else {
            return;
        };
        match job.feed(answer) {
            Some(result) => self.finish(result),
            None => self.next = Some(job.request()),
        }
    }

    fn finish(&mut self, result: Result<LssOutcome, LssMasterError>) {
        self.job = None;
        self.next = None;
        self.waiting = None;
        self.settle_until = None;
        self.result = Some(result);
    }
}
