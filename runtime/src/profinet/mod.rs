//! PROFINET IO (feature `profinet`), no_std and allocation-free: the wire formats a device and
//! a controller share, as views over the caller's bytes ([`wire`]: Ethernet, DCP, RT frames,
//! DCE/RPC, the PNIO blocks of the Connect, record access and control, the AlarmCR's frames),
//! and the AlarmCR's acyclic transport both ends keep for each priority ([`rta`]: sequence
//! numbers, the DATA PDU awaiting its ACK and its retransmission, what a received DATA PDU is).
//!
//! The device and controller cores are not here yet; they live in the simulator
//! (`edsgen_sim::profinet`, whose module comment says what remains std there and why).

pub mod rta;
pub mod wire;
