//! The bench's own roadside: what only a bench run or a test needs, beside the product in the
//! [`roadside`] crate (which never depends on it).
//!
//! - [`scripted`]: the roadside of a scenario run: the MAP and TIMs following the scenario's
//!   timeline (revisions, shrinking and removed zones) through its radio faults, with the
//!   camera site's PSMs.
//! - [`attacker`]: a forged or replayed MAP/TIM sender beside the scripted roadside (the
//!   spoofing scenarios).
//! - [`camera_site`]: a scenario's camera site (`[workers]`): the rendered street on the
//!   scenario's road, road users on scripted paths, and the product's road-user pipeline on
//!   every frame.
//! - [`synthetic_camera`]: a pinhole camera with known truth: control points and cone
//!   detections with seeded noise (`hil-sim synth-camera`, the localisation tests).
//! - [`street`]: the rendered street (lanes, markings, cones, road users as boxes): pictures,
//!   detector masks and COCO files with known truth (the road-user tests and benchmark).
//! - [`sweep`]: the camera sweep: the street from many installs, with dense two-way traffic,
//!   and the road-user pipeline scored against the truth (the road-users benchmark).
//! - [`synthetic_site`]: a rendered site written as camera folders (`hil-sim road-users
//!   --synthesize`), for `roadside road-users` to run on.

pub mod attacker;
pub mod camera_site;
pub mod scripted;
pub mod street;
pub mod sweep;
pub mod synthetic_camera;
pub mod synthetic_site;
