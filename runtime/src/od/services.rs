//! Which of the node's optional services a dictionary has the objects of: a service that cannot
//! run without its objects is left out of a node whose dictionary lacks them, as CANopenNode's
//! object counts leave out its code. Generated dictionaries say it from the file they come from.

/// The optional communication objects a dictionary holds, each the one a service of the node
/// cannot run without. A node over a dictionary without one of them never runs that service
/// (it would read the object as absent, as 0, and stay off), so it builds no code for it; what
/// the dictionary has works as before.
/// [`ObjectDictionary::services`](super::ObjectDictionary::services) reports them:
/// [`Services::ALL`] by default; a generated dictionary, the objects of the file it was
/// generated from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Services {
    /// 1003h, the pre-defined error field: the error history the EMCY producer records.
    pub error_history: bool,
    /// 1006h, the communication cycle period: the SYNC producer and the SYNC consumer's
    /// monitoring (EMCY 8100h after 1.5 periods without SYNC).
    pub sync_period: bool,
    /// 1007h, the synchronous window length: synchronous TPDOs not sent after the window.
    pub sync_window: bool,
    /// 1019h, the synchronous counter overflow value: the SYNC counter and the TPDOs' SYNC
    /// start value.
    pub sync_counter: bool,
    /// 1015h, the inhibit time of EMCY: emergencies held back until it has passed.
    pub emcy_inhibit: bool,
    /// 100Ch and 100Dh, the guard time and life time factor: life guarding (the answers to
    /// node-guarding requests need neither).
    pub life_guarding: bool,
    /// 1201h, the second SDO server's parameters: its channel.
    pub second_sdo: bool,
    /// A writable entry whose data type does not fix its size (a string, octet string or
    /// domain): downloads the SDO server streams into the dictionary
    /// ([`begin_write`](super::ObjectDictionary::begin_write), `write_part`, `commit_write`).
    /// Without one the server collects every download and writes it whole, and has no
    /// streaming code.
    pub streamed_writes: bool,
}

impl Services {
    /// Every service: what a dictionary whose objects may change at run time reports.
    pub const ALL: Services = Services {
        error_history: true,
        sync_period: true,
        sync_window: true,
        sync_counter: true,
        emcy_inhibit: true,
        life_guarding: true,
        second_sdo: true,
        streamed_writes: true,
    };
}
