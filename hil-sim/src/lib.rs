//! `hil-sim`: the hardware-in-the-loop bench. It drives the real OBU (the `obu` daemon, or
//! the firmware in QEMU behind the daemon in bridge mode) with the [`roadside`] crate's
//! MAP and TIM, a simulated GNSS receiver and CAN bus, and checks what the driver sees.
//!
//! Modules in the order the data flows:
//!
//! - [`scenario`]: a scenario file: the roadside's site (lane map, zones, radio faults),
//!   the drive, the driver's settings and the expectations.
//! - [`drive`]: the simulated drive (true pose every 100 ms, GNSS errors, CAN speed).
//! - [`nmea`]: the NMEA 0183 sentences (GGA, RMC, GST) of the simulated GNSS receiver.
//! - [`bench_pki`]: the bench's IEEE 1609.2 trust anchors and roadside signer.
//! - [`roadside_bench`]: the bench's own roadside: the scripted roadside of a run (the
//!   scenario's timeline through its radio faults), the attacker beside it, the camera site,
//!   and the synthetic camera and rendered street with known truth.
//! - [`deployment`]: a scenario's roadside as deployed: a changing WZDx feed, the
//!   `roadside` service, SNMPv3 into a test RSU that broadcasts to the device.
//! - [`daemon`]: the real `obu` daemon as a child process.
//! - [`rig`]: the processes behind a daemon in bridge mode (QEMU, relays).
//! - [`firmware`]: the OBU firmware in QEMU as the device under test.
//! - [`radio`]: the radio chip in front of the firmware: its receive buffers.
//! - [`test_rsu`]: a test RSU (net-snmp's snmpd with our NTCIP 1218 / RSU 4.1 agent) that
//!   the roadside programs over SNMPv3 and that broadcasts what it was given.
//! - [`sse`]: a Server-Sent Events client that follows the daemon's `/events`.
//! - [`attack`]: a scenario's attacker beside the roadside, and the device's counters of
//!   what it dropped.
//! - [`runner`]: `hil-sim run`: roadside, GNSS and CAN into the device, states recorded.
//! - [`expect`]: the scenario's expectations checked on the recorded states.
//! - [`timeline`]: two runs of a scenario (firmware against daemon) compared state by state.
//! - [`plot`] and [`report_plots`]: the report's figures of a run.
//! - [`hmi_bench`]: the bench of the tablet app's browser tests (scenes fed to the daemon).
//! - [`perf`]: the daemon's latency and load test against the real process.
//! - [`fleet_bench`]: one roadside fleet programming many test RSUs over SNMPv3 (time to
//!   converge, requests of an idle poll, memory).
//! - [`soak`]: the daemon for hours under the whole load and hostile traffic, sampled for
//!   growth (RSS, descriptors, latency, counters).
//!
//! The roadside side (lane map, work-zone inputs, MAP/TIM, broadcaster, RSU files, the
//! camera's road-user pipeline) is the [`roadside`] crate; the bench uses it and never the
//! other way round. Code only a bench run or a test needs is in [`roadside_bench`].
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod attack;
pub mod bench_pki;
pub mod daemon;
pub mod deployment;
pub mod drive;
pub mod expect;
pub mod firmware;
pub mod fleet_bench;
pub mod hmi_bench;
pub mod nmea;
pub mod perf;
pub mod plot;
pub mod radio;
pub mod receiver;
pub mod report_plots;
pub mod rig;
pub mod roadside_bench;
pub mod runner;
pub mod scenario;
pub mod soak;
pub mod sse;
pub mod test_rsu;
pub mod timeline;
