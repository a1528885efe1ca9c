//! On-board unit (OBU) core for connected-vehicle work-zone warnings.
//!
//! The crate is `no_std`, allocation-free and deterministic: every input carries
//! the time it happened (`Instant`, milliseconds) and nothing here reads a clock,
//! a file or a socket. The pieces, in data-flow order:
//!
//! * [`geo`]: WGS84 <-> local east/north tangent plane (the `v2x-geodesy` crate, shared
//!   with the roadside).
//! * [`link`]: COBS + CRC-32 frames of the firmware's serial links.
//! * [`v2x`]: the one V2X receive path, received bytes (bare UPER, IEEE 1609.2, RSU text)
//!   to [`v2x::V2xOutcome`] ([`Obu::on_datagram`]), with drop reasons from a closed set
//!   ([`v2x::DropReason`]); the daemon and the firmware both call it.
//! * [`ingest`]: decoded J2735 MAP and TIM values (crate `j2735`) into lane models and
//!   work zones ([`Obu::on_frame`], [`Obu::on_map`], [`Obu::on_tim`]).
//! * [`lane`]: lane model filled from a J2735 MAP, and [`lane::MapStore`].
//! * [`zone`]: work zones filled from a J2735 TIM, and [`zone::ZoneStore`].
//! * [`store`]: the fixed-slot store both of those wrap.
//! * [`worker`]: road workers from J2735 PSMs ([`Obu::on_psm`]), kept for a second and
//!   placed on the lanes.
//! * [`input`]: NMEA 0183 sentences and the CAN speed signal into a [`Fix`].
//! * [`matcher`]: GNSS fix -> lane, station, lateral offset, confidence.
//! * [`distance`]: distance along the lane to the work-zone start.
//! * [`clock`]: GNSS time checked for the week rollover and against a reference clock.
//! * [`alert`]: alert state machine and the [`alert::HmiState`] shown to the driver.
//! * [`onboard`]: [`Obu`], the facade the daemon, the firmware and the simulator drive.
//!
//! Capacities (maps, lanes, nodes, zones, workers) are fixed at compile time in [`capacity`].
//!
//! ## Panic contract
//! No public function panics on any input, including NaN, infinities and
//! out-of-range integers; invalid inputs are rejected or ignored and counted.
//!
//! ## Features
//! * `serde`: `Serialize`/`Deserialize` for the HMI output, configuration and value types.
//! * `std`: `std::error::Error` for the error types.
#![no_std]
#![forbid(unsafe_code)]
#![warn(missing_docs)]

#[cfg(any(feature = "std", test))]
extern crate std;

pub mod alert;
pub mod capacity;
pub mod clock;
pub mod distance;
pub mod fix;
/// WGS84 positions and the local tangent plane: the `v2x-geodesy` crate, shared with the
/// roadside.
pub use geodesy as geo;
pub mod ingest;
pub mod input;
pub mod lane;
pub mod link;
pub mod matcher;
mod math;
pub mod onboard;
pub mod security;
pub mod store;
pub mod time;
pub mod v2x;
pub mod worker;
pub mod zone;

pub use alert::{AlertConfig, HmiState};
pub use fix::Fix;
pub use geo::{LatLon, Point};
pub use onboard::Obu;
pub use time::{Duration, Instant, UtcTime};

#[cfg(test)]
mod testutil;
