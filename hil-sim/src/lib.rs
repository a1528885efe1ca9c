//! `hil-sim`: the roadside side of the product and the hardware-in-the-loop bench.
//!
//! - [`road`]: a lane map (centrelines in a local east/north frame around a reference point).
//! - [`messages`]: the MAP and TIM a roadside unit broadcasts for that map and a work zone,
//!   built as J2735 values and encoded with our codec.
//! - [`nmea`] and [`clock`]: NMEA 0183 sentences (GGA, RMC, GST) of a simulated GNSS receiver
//!   at UTC times.
//! - [`hmi_bench`]: the test bench of the tablet app's browser tests: it runs the real `obu`
//!   daemon and feeds it a consistent road, work zone and drive, scene by scene.
//! - [`perf`]: the daemon's latency (UDP datagram in -> SSE event out) and its load test
//!   (many tablets), both against the real process ([`daemon`], [`sse`]).
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod broadcast;
pub mod camera;
pub mod clock;
pub mod cones;
pub mod daemon;
pub mod drive;
pub mod expect;
pub mod firmware;
pub mod geojson;
pub mod hmi_bench;
pub mod messages;
pub mod nmea;
pub mod perf;
pub mod plot;
pub mod report_plots;
pub mod rng;
pub mod road;
pub mod roadside;
pub mod roadside_cli;
pub mod runner;
pub mod scenario;
pub mod sse;
pub mod timeline;
pub mod zone_sources;
