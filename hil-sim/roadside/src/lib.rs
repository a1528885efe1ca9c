//! `roadside`: the roadside unit of the work-zone product, from the lane map to the air.
//!
//! Modules in the order the data flows:
//!
//! - [`road`]: the lane map (centrelines in a local east/north frame around a reference
//!   point, from the `v2x-geodesy` crate).
//! - [`geojson`]: inputs read from files: a GeoJSON lane map, WZDx 4.2 work zones and cone
//!   lists (JSON or CSV).
//! - [`camera`]: the roadside camera's model (pixels to the road plane) and its
//!   calibration.
//! - [`cones`]: detector boxes, their tracking over frames and the lane closures they make.
//! - [`road_users`]: road users from the camera: vanishing points, 3D boxes from
//!   instance masks, their positions on the road and their tracks.
//! - [`site`]: a roadside installation as a scenario file describes it (lane map, zones and
//!   their sources, radio faults).
//! - [`site_file`]: a deployed installation's site file (lane map, zones, signing, RSUs).
//! - [`wzdx_feed`]: a live WZDx feed polled over HTTP(S) (conditional requests, size cap).
//! - [`zone_sources`]: each zone's closed lanes and stations from its source (lanes, cones,
//!   WZDx, camera), and the site's zones as the roadside broadcasts them.
//! - [`messages`]: the J2735 MAP and TIM for the road and a work zone, UPER-encoded.
//! - [`publisher`]: the zones published over time (msgCnt and MAP revision follow the
//!   content; cancels for zones that ended or left their source).
//! - [`pki`]: IEEE 1609.2 certificates (root, issuing CA, RSU) as files, and the signer of
//!   MAP and TIM.
//! - [`broadcast`]: the broadcaster (UDP, raw or IEEE 1609.2), its fault channel and the
//!   RSU 4.1 text files.
//! - [`rsu`]: a site's messages broadcast and/or written as RSU files (the bench's
//!   `hil-sim roadside`).
//! - [`rsu_snmp`]: RSU management over SNMP (NTCIP 1218 / RSU 4.1 store-and-repeat and
//!   immediate-forward tables, SNMPv3 USM): the site's messages deposited and kept.
//! - [`service`]: `roadside run`: a site's messages deposited and kept on its RSUs.
//!
//! Helpers used along the way: [`clock`] (UTC calendar arithmetic for J2735 times),
//! [`ellipse`] (a position's error ellipse, as the camera measures it and PSMs carry it),
//! [`signer`] (IEEE 1609.2 signing of what goes on the air) and [`rng`] (the seeded
//! pseudo-random generator of the radio faults; the bench reuses it).
//!
//! The `roadside` binary: `roadside run` (the service), `roadside rsu` (RSU management),
//! `roadside pki` (a small IEEE 1609.2 PKI) and `roadside road-users` (road users from
//! camera folders: tracks, localization errors, workers' PSMs).
//!
//! Bench-only code (the scripted roadside of a scenario run, the attacker, the synthetic
//! camera and the rendered street) lives in the `hil-sim` crate, which uses this one; this
//! crate never depends on the bench.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod assign;
pub mod broadcast;
pub mod camera;
pub mod clock;
pub mod cones;
pub mod ellipse;
pub mod geojson;
pub mod messages;
pub mod pki;
pub mod publisher;
pub mod rng;
pub mod road;
pub mod road_users;
pub mod rsu;
pub mod rsu_snmp;
pub mod service;
pub mod signer;
pub mod site;
pub mod site_file;
pub mod wzdx_feed;
pub mod zone_sources;
