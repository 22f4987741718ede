//! The subcommands that run on a bus, one module each.

pub mod bus;
