//! The roadside unit's broadcast: MAP and TIM frames sent over UDP at a fixed rate, bare or
//! in IEEE 1609.2 unsecured data, with seeded fault injection for the bench, and the
//! RSU 4.1 text records that make a real roadside unit send the same messages.
//!
//! - [`Broadcaster`]: a UDP socket, its destinations, the [`Wrapping`] and the
//!   [`Message`]s; [`Broadcaster::tick`] sends every message once to every destination,
//!   [`Broadcaster::run_for`] / [`Broadcaster::run_until`] tick at the rate (10 Hz by
//!   default) on a fixed time grid, so the rate does not drift. A lost datagram is not
//!   retried; the next tick sends the message again.
//! - [`FaultInjector`]: what a bench does to the air, seeded and counted: packet loss
//!   ([`LossModel`]: independent, or Gilbert-Elliott bursts), bit flips, and holding the
//!   TIM back until a given time. It is sans-IO: a scenario runner that hands frames to an
//!   OBU core directly uses it without sockets.
//! - [`rsu_record`] / [`write_rsu_files`]: `Version=0.7` store-and-repeat or
//!   immediate-forward records written with the codec's RSU text writer.

mod broadcaster;
mod config;
mod faults;
mod loss;
mod message;
mod rsu_files;

#[cfg(test)]
mod tests;

pub use crate::rng::Prng;
pub use broadcaster::{BroadcastStats, Broadcaster};
pub use config::ConfigError;
pub use faults::{DropReason, FaultInjector, Faults, Verdict};
pub use j2735::envelope::rsu_text::{TxChannel, TxMode};
pub use loss::{LossChannel, LossModel};
pub use message::{FrameError, Message, MessageKind, MessageSlot, Wrapping};
pub use rsu_files::{
    rsu_file_name, rsu_record, write_rsu_files, RsuDelivery, RsuFileError, RsuOptions,
};

/// Broadcast rate of MAP and TIM unless set otherwise, Hz.
pub const DEFAULT_RATE_HZ: f64 = 10.0;
/// Highest broadcast rate accepted, Hz.
pub const MAX_RATE_HZ: f64 = 1000.0;
