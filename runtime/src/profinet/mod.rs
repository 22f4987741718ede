//! PROFINET IO (feature `profinet`): the wire formats a device and a controller share, as
//! views over the caller's bytes ([`wire`]), no_std and allocation-free. The device and
//! controller cores still live in the simulator (`edsgen_sim::profinet`): they keep their
//! application relations, records and connection state in heap collections and run over a
//! UDP socket the runtime does not have.

pub mod rta;
pub mod wire;
