//! PDO state: the mapping a PDO packs or unpacks, the receive and transmit PDOs' configuration as
//! read from 1400h–1BFFh, and the checks a mapping entry must pass (CiA 301 §7.4.7).
//!
//! Mappings are byte-granular: each mapped object takes its whole size in whole bytes (a mapping
//! length that is not a multiple of 8 is refused with 0604 0041). At most [`MAX_MAPPED`] objects
//! per PDO.

use crate::frame::CanFrame;
use crate::od::{DataType, ObjectDictionary, SdoAbort};
use crate::time::{Duration, Instant};
use crate::wire::pdo::{CobIdEntry, MappingEntry};

/// The most objects one PDO can map.
pub const MAX_MAPPED: usize = 8;

/// One mapped object, checked: where its bytes go in the payload.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) struct MappedObject {
    pub index: u16,
    pub sub: u8,
    pub len: u8,
    /// Its position in the OD's table (found when the mapping was checked), so that packing and
    /// unpacking do not search; [`BY_ADDRESS`] for a dummy or a table too long for 16 bits.
    pub position: u16,
}

/// [`MappedObject::position`] of an object read and written by (index, sub).
const BY_ADDRESS: u16 = u16::MAX;

impl MappedObject {
    /// Reads the object's value into `slot`.
    #[inline]
    fn read<O: ObjectDictionary + ?Sized>(
        self,
        od: &O,
        slot: &mut [u8],
    ) -> Result<usize, SdoAbort> {
        match self.position {
            BY_ADDRESS => od.read(self.index, self.sub, 0, slot),
            position => od.read_at(usize::from(position), 0, slot),
        }
    }

    /// Writes `bytes` into the object.
    #[inline]
    fn write<O: ObjectDictionary + ?Sized>(self, od: &mut O, bytes: &[u8]) -> Result<(), SdoAbort> {
        match self.position {
            BY_ADDRESS => od.write(self.index, self.sub, bytes),
            position => od.write_at(usize::from(position), bytes),
        }
    }

    #[inline]
    fn is_dummy(self) -> bool {
        MappingEntry {
            index: self.index,
            sub: self.sub,
            bits: 0,
        }
        .is_dummy()
    }
}

/// The checked mapping of one PDO.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Mapping {
    pub objects: [MappedObject; MAX_MAPPED],
    pub count: u8,
    /// Payload length in bytes.
    pub len: u8,
}

/// By an array repeat at run time rather than derived or [`Mapping::EMPTY`]: both clear the
/// array with the byte-wise `__aeabi_memclr` (the array is only 2-byte aligned), which nothing
/// else on the device needs (about 200 B of flash).
impl Default for Mapping {
    fn default() -> Mapping {
        Mapping {
            objects: [MappedObject::default(); MAX_MAPPED],
            count: 0,
            len: 0,
        }
    }
}

impl Mapping {
    /// No objects, for [`Rpdo::OFF`] and [`Tpdo::OFF`].
    pub const EMPTY: Mapping = Mapping {
        objects: [MappedObject {
            index: 0,
            sub: 0,
            len: 0,
            position: 0,
        }; MAX_MAPPED],
        count: 0,
        len: 0,
    };

    #[inline]
    pub fn objects(&self) -> &[MappedObject] {
        &self.objects[..self.count as usize]
    }

    #[inline]
    pub fn contains(&self, index: u16, sub: u8) -> bool {
        self.objects()
            .iter()
            .any(|o| o.index == index && o.sub == sub)
    }

    /// Reads the mapped objects into a payload (dummies give zeros).
    #[inline]
    pub fn pack<O: ObjectDictionary + ?Sized>(&self, od: &O) -> [u8; 8] {
        let mut data = [0u8; 8];
        let mut offset = 0usize;
        for object in self.objects() {
            let end = offset + object.len as usize;
            if object.is_dummy() {
                offset = end;
                continue;
            }
            if let Some(slot) = data.get_mut(offset..end) {
                // A failed read leaves zeros: the mapping was checked, so this only happens
                // when the OD refuses its own entry.
                let _ = object.read(od, slot);
            }
            offset = end;
        }
        data
    }

    /// Writes a payload's bytes into the mapped objects, all or none: if the OD refuses a value
    /// (a limit), the objects written before it get their previous values back and the refusal
    /// is returned. A single object needs no copy: the OD leaves a refused value unchanged.
    #[inline]
    pub fn unpack<O: ObjectDictionary + ?Sized>(
        &self,
        od: &mut O,
        data: &[u8],
    ) -> Result<(), SdoAbort> {
        if self.count <= 1 {
            return self
                .write_objects(od, data, MAX_MAPPED)
                .map_err(|(_, abort)| abort);
        }
        let previous = self.pack(od);
        self.write_objects(od, data, MAX_MAPPED)
            .map_err(|(written, abort)| {
                // The previous values were accepted once; they are again.
                let _ = self.write_objects(od, &previous, written);
                abort
            })
    }

    /// Writes the payload's bytes into the first `count` mapped objects (dummies skipped); on a
    /// refusal, how many objects come before the refused one, and why.
    fn write_objects<O: ObjectDictionary + ?Sized>(
        &self,
        od: &mut O,
        data: &[u8],
        count: usize,
    ) -> Result<(), (usize, SdoAbort)> {
        let mut offset = 0usize;
        for (n, object) in self.objects().iter().take(count).enumerate() {
            let end = offset + object.len as usize;
            if !object.is_dummy() {
                if let Some(bytes) = data.get(offset..end) {
                    object.write(od, bytes).map_err(|abort| (n, abort))?;
                }
            }
            offset = end;
        }
        Ok(())
    }
}

/// Direction of a PDO, for the mapping checks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Direction {
    Receive,
    Transmit,
}

/// Size in bits of a dummy-mapping data type (0002h–0007h); BOOLEAN (0001h) is bit-sized and
/// not supported.
fn dummy_bits(index: u16) -> Option<u8> {
    match index {
        0x0002 | 0x0005 => Some(8),
        0x0003 | 0x0006 => Some(16),
        0x0004 | 0x0007 => Some(32),
        _ => None,
    }
}

/// Checks one mapping entry against the OD: 0604 0041 if the object is absent, not mappable in
/// this direction, or its length does not match. Dummy entries (0002h–0007h with their type's
/// length) are accepted in both directions.
pub(crate) fn check_entry<O: ObjectDictionary + ?Sized>(
    od: &O,
    entry: MappingEntry,
    direction: Direction,
) -> Result<MappedObject, SdoAbort> {
    if entry.bits == 0 || entry.bits % 8 != 0 {
        return Err(SdoAbort::NotMappable);
    }
    let len = entry.bits / 8;
    if entry.is_dummy() {
        // CiA 301 defines dummies for RPDOs (bytes to skip); vendor EDS files also pad TPDOs
        // with them (the Goodrive350 card's TPDO1), which then carry zeros there.
        return match dummy_bits(entry.index) {
            Some(bits) if bits == entry.bits => Ok(MappedObject {
                index: entry.index,
                sub: entry.sub,
                len,
                position: BY_ADDRESS,
            }),
            _ => Err(SdoAbort::NotMappable),
        };
    }
    let position = od
        .locate(entry.index, entry.sub)
        .map_err(|_| SdoAbort::NotMappable)?;
    let descriptor = od.entries().get(position).ok_or(SdoAbort::NotMappable)?;
    let allowed = match direction {
        Direction::Receive => descriptor.access.writable(),
        Direction::Transmit => descriptor.access.readable(),
    };
    let size = descriptor.data_type.fixed_size();
    if !descriptor.pdo_mappable
        || !allowed
        || size != Some(len as usize)
        || descriptor.data_type == DataType::Domain
    {
        return Err(SdoAbort::NotMappable);
    }
    Ok(MappedObject {
        index: entry.index,
        sub: entry.sub,
        len,
        position: u16::try_from(position).unwrap_or(BY_ADDRESS),
    })
}

/// Reads and checks the mapping record at `index` (1600h+n or 1A00h+n) into `mapping`, which
/// is empty (see [`check_mapping`]).
pub(crate) fn load_mapping<O: ObjectDictionary + ?Sized>(
    od: &O,
    index: u16,
    direction: Direction,
    mapping: &mut Mapping,
) -> Result<(), SdoAbort> {
    let count = super::read_uint(od, index, 0).ok_or(SdoAbort::NoObject)?;
    check_mapping(od, index, count, direction, mapping)
}

/// Checks that the first `count` entries of the mapping record at `index` form a valid mapping:
/// 0604 0042 if there are too many or they exceed 8 bytes, 0604 0041 if one cannot be mapped.
///
/// The mapping is written into `mapping`, which must be empty: its objects as they are checked,
/// its count and length once all passed, so that a refused mapping leaves it empty. In place
/// rather than returned, which would move the 50-byte mapping twice on its way into a PDO.
pub(crate) fn check_mapping<O: ObjectDictionary + ?Sized>(
    od: &O,
    index: u16,
    count: u32,
    direction: Direction,
    mapping: &mut Mapping,
) -> Result<(), SdoAbort> {
    if count as usize > MAX_MAPPED {
        return Err(SdoAbort::PdoTooLong);
    }
    let mut total = 0usize;
    // Half-open ranges here and in the node's other sub-index loops (1003h, 1016h): an
    // inclusive one carries an exhausted flag and steps through `RangeInclusive::next`, some
    // 240 B more flash over the four loops.
    for (slot, sub) in mapping.objects.iter_mut().zip(1..count as u8 + 1) {
        let raw = super::read_uint(od, index, sub).ok_or(SdoAbort::NotMappable)?;
        *slot = check_entry(od, MappingEntry::from_u32(raw), direction)?;
        total += slot.len as usize;
        if total > 8 {
            return Err(SdoAbort::PdoTooLong);
        }
    }
    mapping.count = count as u8;
    mapping.len = total as u8;
    Ok(())
}

/// A receive PDO.
/// Word-aligned (its widest field has 2 bytes) so that [`Rpdo::load`]'s clear is a word-wise
/// memclr: a byte-wise one would bring 208 B of `__aeabi_memclr` into a firmware image (see
/// [`Mapping`]'s `Default`).
#[derive(Debug, Clone, Copy)]
#[repr(align(4))]
pub(crate) struct Rpdo {
    /// Whether the PDO exists and is valid.
    enabled: bool,
    cob_id: u16,
    transmission: u8,
    mapping: Mapping,
    /// Data received for a synchronous RPDO, applied at the next SYNC.
    buffered: Option<[u8; 8]>,
    /// Some TPDO maps an object this PDO writes (change-of-state detection must look).
    feeds_tpdo: bool,
    /// The last frame was shorter / longer than the mapping.
    too_short: bool,
    too_long: bool,
    /// The last frame was not applied: the OD refused one of its values (EMCY 8200h).
    refused: bool,
    /// Deadline monitoring (1400h+n sub 05h, ms; 0 = off): the PDO must arrive again within
    /// this time of its last reception.
    event_timer_ms: u16,
    /// The deadline passed and the PDO has not arrived since (EMCY 8250h is active for it).
    timed_out: bool,
}

impl Rpdo {
    /// A PDO that does not exist (yet): nothing configured, nothing received. A constant of
    /// zeros and `None`s rather than a (derived) `Default`, so that power-on and [`Rpdo::load`]
    /// clear it with one word-aligned memset instead of building a copy to move.
    pub const OFF: Rpdo = Rpdo {
        enabled: false,
        cob_id: 0,
        transmission: 0,
        mapping: Mapping::EMPTY,
        buffered: None,
        feeds_tpdo: false,
        too_short: false,
        too_long: false,
        refused: false,
        event_timer_ms: 0,
        timed_out: false,
    };

    /// Reads the configuration of RPDO `n` (1400h + n, 1600h + n) into this PDO, in place, and
    /// forgets its running state. Returns why the mapping was refused if the COB-ID is valid
    /// (the PDO is then not served).
    pub fn load<O: ObjectDictionary + ?Sized>(&mut self, od: &O, n: u16) -> Option<SdoAbort> {
        *self = Rpdo::OFF;
        let comm = 0x1400 + n;
        let cob = CobIdEntry(super::read_uint(od, comm, 1)?);
        self.cob_id = cob.can_id();
        self.transmission = super::read_uint_or(od, comm, 2, 255) as u8;
        self.event_timer_ms = super::read_uint_or(od, comm, 5, 0) as u16;
        match load_mapping(od, 0x1600 + n, Direction::Receive, &mut self.mapping) {
            Ok(()) => {
                self.enabled = cob.valid() && !cob.extended();
                None
            }
            Err(reason) => cob.valid().then_some(reason),
        }
    }

    #[inline]
    fn synchronous(&self) -> bool {
        self.transmission <= 240
    }

    /// Whether a frame on `id` is this PDO.
    #[inline]
    pub fn accepts(&self, id: u16) -> bool {
        self.enabled && id == self.cob_id
    }

    /// The checked mapping.
    #[inline]
    pub fn mapping(&self) -> &Mapping {
        &self.mapping
    }

    /// Whether a TPDO maps an object this PDO writes (so that a reception looks for changes
    /// of state).
    #[inline]
    pub fn feeds_tpdo(&self) -> bool {
        self.feeds_tpdo
    }

    /// Notes whether a TPDO maps an object this PDO writes.
    #[inline]
    pub fn set_feeds_tpdo(&mut self, feeds: bool) {
        self.feeds_tpdo = feeds;
    }

    /// The last frame was shorter / longer than the mapping (EMCY 8210h / 8220h).
    #[inline]
    pub fn length_errors(&self) -> (bool, bool) {
        (self.too_short, self.too_long)
    }

    /// The deadline passed and the PDO has not arrived since (EMCY 8250h).
    #[inline]
    pub fn timed_out(&self) -> bool {
        self.timed_out
    }

    /// The last frame was not applied: the OD refused one of its values (EMCY 8200h).
    #[inline]
    pub fn refused(&self) -> bool {
        self.refused
    }

    /// A frame received at `now`. A frame shorter than the mapping is not processed (and is no
    /// reception for the deadline monitoring); a synchronous PDO's data waits for the next
    /// SYNC; an event-driven one is handed back to be applied. Also returns whether a timeout
    /// of the PDO ended. `deadline` is the PDO's slot in the node's timer table.
    #[inline]
    pub fn receive<'d>(
        &mut self,
        now: Instant,
        data: &'d [u8],
        deadline: &mut Option<Instant>,
    ) -> (Option<&'d [u8]>, bool) {
        let expected = usize::from(self.mapping.len);
        self.too_short = data.len() < expected;
        self.too_long = data.len() > expected;
        if self.too_short {
            return (None, false);
        }
        // CiA 301, 1400h+n sub 05h: a non-zero event timer of an RPDO is its deadline; the
        // monitoring is activated with the next reception of the RPDO (after entering
        // operational or configuring the event timer) and restarts with each one.
        let timer = Duration::from_millis(u64::from(self.event_timer_ms));
        *deadline = (self.event_timer_ms != 0).then(|| now + timer);
        let recovered = core::mem::take(&mut self.timed_out);
        if self.synchronous() {
            let mut buffer = [0u8; 8];
            buffer[..expected].copy_from_slice(&data[..expected]);
            self.buffered = Some(buffer);
            (None, recovered)
        } else {
            (Some(data), recovered)
        }
    }

    /// The data of a synchronous PDO received before this SYNC, to apply now.
    #[inline]
    pub fn take_buffered(&mut self) -> Option<[u8; 8]> {
        self.buffered.take()
    }

    /// Writes received data into the OD, all or none ([`Mapping::unpack`]), and notes whether
    /// it was refused. `Ok(true)` when it was applied after a refusal.
    pub fn apply<O: ObjectDictionary + ?Sized>(
        &mut self,
        od: &mut O,
        data: &[u8],
    ) -> Result<bool, SdoAbort> {
        match self.mapping.unpack(od, data) {
            Ok(()) => Ok(core::mem::take(&mut self.refused)),
            Err(abort) => {
                self.refused = true;
                Err(abort)
            }
        }
    }

    /// Leaving operational: buffered data is dropped (the node stops the deadline).
    pub fn stop(&mut self) {
        self.buffered = None;
    }

    /// Re-reads RPDO `n` after an SDO write to its parameters. A valid PDO keeps its deadline
    /// monitoring across other changes (its transmission type); a new event timer
    /// (`event_timer_written`) stops it, as does disabling the PDO: CiA 301 activates the
    /// monitoring with the next reception after the event timer is configured. `deadline` is
    /// the PDO's slot in the node's timer table. Returns whether a timeout ended.
    pub fn reload<O: ObjectDictionary + ?Sized>(
        &mut self,
        od: &O,
        n: u16,
        event_timer_written: bool,
        deadline: &mut Option<Instant>,
    ) -> bool {
        let timed_out = self.timed_out;
        self.load(od, n);
        if self.enabled && !event_timer_written {
            self.timed_out = timed_out;
        } else {
            *deadline = None;
        }
        timed_out && !self.timed_out
    }

    /// The deadline passed: the PDO is timed out until it arrives again.
    pub fn expire(&mut self) {
        self.timed_out = true;
    }
}

/// A transmit PDO.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Tpdo {
    enabled: bool,
    cob_id: u16,
    rtr_allowed: bool,
    transmission: u8,
    /// The inhibit time (1800h+n sub 03h, in 100 µs) and event timer (sub 05h, ms) as read:
    /// 32 bits each rather than 64-bit `Duration`s.
    inhibit_100us: u32,
    event_timer_ms: u32,
    sync_start: u8,
    mapping: Mapping,
    /// A frame is waiting to be sent; `data` holds it if it was sampled already (synchronous,
    /// `sampled`). A flag beside a plain array rather than an `Option`, which keeps the array
    /// word-aligned (it is copied into a frame as whole words).
    pending: bool,
    sampled: bool,
    data: [u8; 8],
    /// For synchronous PDOs: the latest sample (252) and the window deadline.
    sync_deadline: Option<Instant>,
    /// Type 0: an event occurred since the last SYNC.
    acyclic_request: bool,
    /// SYNCs left until the next cyclic transmission; `None` before the first SYNC, `Some(0)`
    /// while waiting for the SYNC start value.
    sync_countdown: Option<u8>,
    /// Type 252: the data sampled at the last SYNC, sent on a remote request.
    rtr_sample: Option<[u8; 8]>,
    /// The payload last sent (change-of-state detection).
    last_data: [u8; 8],
    last_sent: Option<Instant>,
    /// A mapped object may have changed: compare before the next transmission decision.
    check_change: bool,
}

impl Tpdo {
    /// A PDO that does not exist (yet): nothing configured, nothing running. A constant, like
    /// [`Rpdo::OFF`].
    pub const OFF: Tpdo = Tpdo {
        enabled: false,
        cob_id: 0,
        rtr_allowed: false,
        transmission: 0,
        inhibit_100us: 0,
        event_timer_ms: 0,
        sync_start: 0,
        mapping: Mapping::EMPTY,
        pending: false,
        sampled: false,
        data: [0; 8],
        sync_deadline: None,
        acyclic_request: false,
        sync_countdown: None,
        rtr_sample: None,
        last_data: [0; 8],
        last_sent: None,
        check_change: false,
    };

    /// Reads the configuration of TPDO `n` (1800h + n, 1A00h + n) into this PDO, in place, and
    /// forgets its running state. Returns why the mapping was refused if the COB-ID is valid
    /// (the PDO is then not served).
    pub fn load<O: ObjectDictionary + ?Sized>(&mut self, od: &O, n: u16) -> Option<SdoAbort> {
        *self = Tpdo::OFF;
        let comm = 0x1800 + n;
        let cob = CobIdEntry(super::read_uint(od, comm, 1)?);
        self.cob_id = cob.can_id();
        self.rtr_allowed = !cob.bit30();
        self.transmission = super::read_uint_or(od, comm, 2, 255) as u8;
        self.inhibit_100us = super::read_uint_or(od, comm, 3, 0);
        self.event_timer_ms = super::read_uint_or(od, comm, 5, 0);
        self.sync_start = super::read_uint_or(od, comm, 6, 0) as u8;
        match load_mapping(od, 0x1A00 + n, Direction::Transmit, &mut self.mapping) {
            Ok(()) => {
                self.enabled = cob.valid() && !cob.extended();
                None
            }
            Err(reason) => cob.valid().then_some(reason),
        }
    }

    #[inline]
    pub fn event_driven(&self) -> bool {
        self.transmission >= 254
    }

    /// Forgets everything a running PDO accumulated (leaving operational, reconfiguring).
    pub fn stop(&mut self) {
        self.pending = false;
        self.sampled = false;
        self.rtr_sample = None;
        self.sync_deadline = None;
        self.acyclic_request = false;
        self.sync_countdown = None;
        self.check_change = false;
    }

    /// The inhibit time.
    pub fn inhibit(&self) -> Duration {
        Duration::from_micros(u64::from(self.inhibit_100us) * 100)
    }

    /// The event timer (zero: off).
    pub fn event_timer(&self) -> Duration {
        Duration::from_millis(u64::from(self.event_timer_ms))
    }

    /// Whether its mapping holds (index, sub).
    #[inline]
    pub fn maps(&self, index: u16, sub: u8) -> bool {
        self.mapping.contains(index, sub)
    }

    /// A mapped object may have changed: compare before the next transmission decision.
    #[inline]
    pub fn mark_changed(&mut self) {
        self.check_change = true;
    }

    /// Re-reads TPDO `n` after an SDO write to its parameters, keeping the timing history
    /// (last transmission, last data) of a running PDO across a change of its event timer or
    /// transmission type. In operational, an event-driven PDO restarts its event timer (its
    /// slot `event_timer` in the node's timer table; a new configuration stops it otherwise)
    /// and, if it has just become valid, is sent. Returns whether it is now waiting to be sent.
    pub fn reload<O: ObjectDictionary + ?Sized>(
        &mut self,
        od: &O,
        n: u16,
        now: Instant,
        operational: bool,
        event_timer: &mut Option<Instant>,
    ) -> bool {
        let (last_sent, last_data, was_enabled) = (self.last_sent, self.last_data, self.enabled);
        self.load(od, n);
        self.last_sent = last_sent;
        self.last_data = last_data;
        *event_timer = None;
        if operational && self.enabled && self.event_driven() {
            *event_timer = self.event_timer_from(now);
            if !was_enabled {
                self.pending = true;
            }
        }
        self.pending
    }

    /// Entering operational: an event-driven PDO is sent once. Returns whether it is waiting.
    pub fn start(&mut self) -> bool {
        if self.enabled && self.event_driven() {
            self.pending = true;
        }
        self.pending
    }

    /// An application event (`Node::trigger_tpdo`): an event-driven PDO is sent as soon as its
    /// inhibit time allows, an acyclic synchronous one at the next SYNC. `false` if the PDO is
    /// not valid or has another transmission type.
    pub fn trigger(&mut self) -> bool {
        if !self.enabled {
            return false;
        }
        match self.transmission {
            0 => self.acyclic_request = true,
            254 | 255 => self.pending = true,
            _ => return false,
        }
        true
    }

    /// A remote request on `id`: a PDO of type 252 sends its sample of the last SYNC, one of
    /// 253 (or event-driven) a fresh one. Returns whether it was for this PDO.
    pub fn remote_request(&mut self, id: u16) -> bool {
        if !(self.enabled && self.rtr_allowed && self.cob_id == id) {
            return false;
        }
        match self.transmission {
            252 => {
                if let Some(sample) = self.rtr_sample {
                    self.data = sample;
                    self.sampled = true;
                    self.pending = true;
                }
            }
            _ => {
                self.sampled = false;
                self.pending = true;
            }
        }
        true
    }

    /// A SYNC with `counter` (`use_start`: 1019h is set, so the SYNC start value applies),
    /// whose synchronous window ends at `window_end`. Returns whether the PDO is now waiting
    /// to be sent.
    pub fn on_sync<O: ObjectDictionary + ?Sized>(
        &mut self,
        od: &O,
        counter: Option<u8>,
        use_start: bool,
        window_end: Option<Instant>,
    ) -> bool {
        if !self.enabled {
            return false;
        }
        let send = match self.transmission {
            0 => {
                if self.check_change {
                    let data = self.mapping.pack(od);
                    self.check_change = false;
                    if data != self.last_data {
                        self.acyclic_request = true;
                    }
                }
                core::mem::take(&mut self.acyclic_request)
            }
            every @ 1..=240 => {
                let start = if use_start { self.sync_start } else { 0 };
                // SYNCs left until the next transmission, counting this one.
                let left = match self.sync_countdown {
                    Some(left) => Some(left),
                    None if start != 0 => (counter == Some(start)).then_some(1),
                    None => Some(every),
                };
                match left {
                    Some(left) if left <= 1 => {
                        self.sync_countdown = Some(every);
                        true
                    }
                    Some(left) => {
                        self.sync_countdown = Some(left - 1);
                        false
                    }
                    None => false,
                }
            }
            252 => {
                self.rtr_sample = Some(self.mapping.pack(od));
                false
            }
            _ => false,
        };
        if send {
            self.data = self.mapping.pack(od);
            self.sampled = true;
            self.pending = true;
            self.sync_deadline = window_end;
        }
        send
    }

    /// The frame to send at `now`, if the PDO is waiting and may go: an event-driven PDO
    /// whose mapped values changed is sent (change of state), within its inhibit time; a
    /// synchronous one only within its SYNC's window (else that SYNC's PDO is dropped). A PDO
    /// sent restarts its event timer (its slot `event_timer` in the node's timer table).
    pub fn poll_transmit<O: ObjectDictionary + ?Sized>(
        &mut self,
        od: &O,
        now: Instant,
        event_timer: &mut Option<Instant>,
    ) -> Option<CanFrame> {
        if !self.enabled {
            return None;
        }
        if self.event_driven() && core::mem::take(&mut self.check_change) {
            let data = self.mapping.pack(od);
            if data != self.last_data {
                self.pending = true;
            }
        }
        if !self.pending {
            return None;
        }
        if let Some(deadline) = self.sync_deadline {
            if now > deadline {
                // Outside the synchronous window (1007h): this SYNC's PDO is dropped.
                self.pending = false;
                self.sampled = false;
                self.sync_deadline = None;
                return None;
            }
        }
        if self.event_driven() && !self.inhibit_passed(now) {
            return None;
        }
        let data = if core::mem::take(&mut self.sampled) {
            self.data
        } else {
            self.mapping.pack(od)
        };
        self.pending = false;
        self.sync_deadline = None;
        self.last_data = data;
        self.last_sent = Some(now);
        if self.event_driven() {
            *event_timer = self.event_timer_from(now);
        }
        Some(CanFrame::from_parts(self.cob_id, data, self.mapping.len))
    }

    /// Whether a frame is waiting (perhaps for its inhibit time).
    #[inline]
    pub fn pending(&self) -> bool {
        self.pending
    }

    /// When an event timer started at `now` runs out (1800h+n sub 05h), if it is not 0.
    fn event_timer_from(&self, now: Instant) -> Option<Instant> {
        (self.event_timer_ms != 0).then(|| now + self.event_timer())
    }

    /// When the inhibit time of an event-driven PDO's waiting frame ends (it may go out
    /// through [`Tpdo::poll_transmit`] then), if one is waiting.
    #[inline]
    pub fn inhibit_end(&self) -> Option<Instant> {
        if !(self.event_driven() && self.pending) {
            return None;
        }
        self.last_sent.map(|sent| sent + self.inhibit())
    }

    /// The event timer ran out: the PDO is waiting to be sent.
    pub fn expire_event(&mut self) {
        self.pending = true;
    }

    /// Whether the inhibit time since the last transmission has passed.
    #[inline]
    pub fn inhibit_passed(&self, now: Instant) -> bool {
        match self.last_sent {
            Some(sent) => now >= sent + self.inhibit(),
            None => true,
        }
    }
}
