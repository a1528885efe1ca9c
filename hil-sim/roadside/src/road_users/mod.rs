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
//! [`synthetic`] renders scenes with known truth for the tests and the benchmark. Helpers:
//! [`class`] (the classes and their sizes), [`homog`] (homogeneous image geometry),
//! [`polygon`] (convex hulls and overlaps).

pub mod boxes;
pub mod calibrate;
pub mod class;
pub mod detections;
pub mod draw;
pub mod edgelets;
pub mod files;
pub mod homog;
pub mod live;
pub mod localize;
pub mod outline;
pub mod pipeline;
pub mod polygon;
pub mod synthetic;
pub mod tracker;
pub mod vanishing;
pub mod workers;

pub use class::RoadUserClass;
