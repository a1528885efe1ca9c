//! Road users seen by the roadside camera: the second seed paper's method.
//!
//! 1. [`calibrate`]: the scene's three orthogonal vanishing points by RANSAC directly on
//!    [`edgelets`] ([`vanishing`]), the focal length from them, and the full projection from
//!    them with the reference-point homography, cross-checked against it.
//! 2. [`detections`]: an instance-segmentation detector's output (COCO JSON with polygons or
//!    RLE masks, YOLO-seg text), each mask reduced to the convex hull of its outline
//!    (polygons filled back into pixels first, [`rasterise`]).
//! 3. [`localize`]: the 3D box of each road user fitted to its mask ([`fit`]: position,
//!    length, width and height whose projected box matches the mask's outline, the class's
//!    size prior deciding only what the view does not measure: the class's, or the size
//!    belief of the road user's track, [`size`]), started from the tangents
//!    of the vanishing points to its silhouette ([`boxes`]) where they work; partly hidden
//!    or cut road users are localized from what is seen, with the larger error that leaves,
//!    and refused with a reason when too little is. Each camera learns how noisy its masks
//!    are from its fits ([`noise`]), and the fits weigh the masks by it.
//! 4. [`tracker`]: a constant-velocity Kalman filter per road user, assignment by class and
//!    by distance in road coordinates with the track's uncertainty, for position, speed and
//!    heading with their accuracy.
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
pub mod noise;
pub mod outline;
pub mod pipeline;
pub mod polygon;
pub mod rasterise;
pub mod size;
pub mod tracker;
pub mod vanishing;
pub mod workers;

pub use class::RoadUserClass;
