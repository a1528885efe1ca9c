//! Road users seen by the roadside camera: the second seed paper's method.
//!
//! 1. [`calibrate`]: the scene's three orthogonal vanishing points by RANSAC directly on
//!    [`edgelets`] ([`vanishing`]), the focal length from them, and the full projection from
//!    them with the reference-point homography, cross-checked against it.
//! 2. [`detections`]: an instance-segmentation detector's output (COCO JSON with polygons or
//!    RLE masks, YOLO-seg text), each mask reduced to its convex hull.
//! 3. [`boxes`]: the 3D box of each road user from the tangents of the vanishing points to
//!    its silhouette (B1-B4 on the road, B5-B8 above), its footprint's centre in local
//!    metres; [`localize`] does it for a frame and refuses cut, occluded or degenerate masks
//!    with a reason.
//! 4. [`tracker`]: a constant-velocity Kalman filter per road user, assignment by distance,
//!    for position, speed and heading with their accuracy.
//!
//! Around them: [`pipeline`] (every camera's frames through localization and one tracker),
//! [`workers`] (the tracked workers in a work zone as PSMs), [`files`] (a camera's folder
//! read, the tracks written as JSON) and [`draw`] (boxes drawn on a frame). Helpers:
//! [`class`] (the classes and their sizes), [`homog`] (homogeneous image geometry),
//! [`outline`] (a mask's outline), [`polygon`] (convex hulls and overlaps).
//!
//! The scenes with known truth that the tests and the benchmark render are the bench's
//! (`hil-sim`'s `roadside_bench::street`).

pub mod boxes;
pub mod calibrate;
pub mod class;
pub mod detections;
pub mod draw;
pub mod edgelets;
pub mod files;
pub mod fit;
pub mod homog;
pub mod localize;
pub mod outline;
pub mod pipeline;
pub mod polygon;
pub mod tracker;
pub mod vanishing;
pub mod workers;

pub use class::RoadUserClass;
