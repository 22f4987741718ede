//! The CANopen master on an operating system: [`blocking::Master`] runs the runtime's sans-IO
//! master cores (SDO clients, node monitor, EMCY consumer) on a [`Transport`](crate::Transport)
//! one call at a time; [`concurrent::AsyncMaster`] runs them on a driver thread, all nodes at once.

pub mod blocking;
pub mod concurrent;
mod drive;
