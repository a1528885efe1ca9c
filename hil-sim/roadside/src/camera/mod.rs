//! The roadside camera's model: image pixels to the road plane (local east/north metres of a
//! [`Road`](crate::road::Road), and on to latitude/longitude).
//!
//! Two forms, both estimated from ground control points ([`Correspondence`]: a pixel and the
//! surveyed position of the same road point), both behind [`CameraModel`]:
//!
//! - [`Homography`]: one 3x3 plane-to-plane map, estimated by the normalised direct linear
//!   transformation (Hartley normalisation of both point sets, SVD of the 2n x 9 system, least
//!   squares with more than four points).
//! - [`TwoStep`]: the camera paper's form, a perspective homography from the image to a
//!   top-down (bird's-eye) image ([`TopDown`]), then a least-squares affine map from that image
//!   to local metres.
//!
//! Degenerate point sets are refused with a [`ModelError`]; a pixel at or above the horizon
//! maps to `None`. No function here panics on its input.

mod calibration;
mod fit;
mod homography;
mod model;
#[cfg(test)]
mod test_support;
mod two_step;

pub use calibration::{load_calibration, parse_calibration, CalibrationError, Correspondence};
pub use homography::Homography;
pub use model::{CameraModel, ModelError, PointSet};
pub use two_step::{TopDown, TwoStep};
