//! The camera model of either form, and why one cannot be estimated.

use std::fmt;

use geodesy::LatLon;

use super::{Correspondence, Homography, TopDown, TwoStep};
use crate::road::Road;

/// Which point set of the correspondences an error is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PointSet {
    /// The source points (image pixels).
    Image,
    /// The target points (road plane, or the top-down image).
    Ground,
}

/// Why a camera model cannot be estimated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum ModelError {
    /// Too few correspondences.
    TooFewPoints {
        /// Points given.
        got: usize,
        /// Points needed.
        need: usize,
    },
    /// Correspondence `index` has a non-finite coordinate.
    NonFinite {
        /// Index of the correspondence.
        index: usize,
    },
    /// All points (or three of a minimal set of four) are (nearly) on one line.
    Collinear {
        /// The point set that is collinear.
        set: PointSet,
    },
    /// The points do not fix a unique mapping (e.g. all but one on a line).
    Degenerate,
    /// The estimated homography is singular.
    Singular,
    /// The control points lie on both sides of the horizon: no camera sees them so.
    Horizon,
    /// The top-down view is invalid (scale not positive, bearing not finite, bad quad).
    BadTopDown,
}

impl fmt::Display for ModelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::TooFewPoints { got, need } => {
                write!(f, "{got} correspondences, at least {need} needed")
            }
            Self::NonFinite { index } => write!(f, "correspondence {index} is not finite"),
            Self::Collinear { set } => write!(f, "{set:?} points are (nearly) collinear"),
            Self::Degenerate => f.write_str("the points do not fix a unique mapping"),
            Self::Singular => f.write_str("the estimated homography is singular"),
            Self::Horizon => f.write_str("control points lie on both sides of the horizon"),
            Self::BadTopDown => f.write_str("invalid top-down view"),
        }
    }
}

impl std::error::Error for ModelError {}

/// A camera model of either form.
#[derive(Debug, Clone, PartialEq)]
pub enum CameraModel {
    /// One homography, image -> local metres.
    Homography(Homography),
    /// Perspective to a top-down image, then affine to local metres.
    TwoStep(TwoStep),
}

impl CameraModel {
    /// The one-homography form from control points.
    pub fn homography(road: &Road, points: &[Correspondence]) -> Result<Self, ModelError> {
        Homography::from_correspondences(road, points).map(Self::Homography)
    }

    /// The two-step form from control points.
    pub fn two_step(
        road: &Road,
        points: &[Correspondence],
        view: TopDown,
    ) -> Result<Self, ModelError> {
        TwoStep::from_correspondences(road, points, view).map(Self::TwoStep)
    }

    /// Local metres (east, north) of a pixel; `None` at or beyond the horizon.
    pub fn to_local(&self, px: [f64; 2]) -> Option<[f64; 2]> {
        match self {
            Self::Homography(h) => h.apply(px),
            Self::TwoStep(t) => t.to_local(px),
        }
    }

    /// WGS84 position of a pixel.
    pub fn to_wgs84(&self, road: &Road, px: [f64; 2]) -> Option<LatLon> {
        road.to_wgs84(self.to_local(px)?)
    }

    /// Root-mean-square error over the control points, metres.
    pub fn rmse_m(&self) -> f64 {
        match self {
            Self::Homography(h) => h.rmse(),
            Self::TwoStep(t) => t.rmse_m(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::{close, map, points, road, truth, PROBES};
    use super::*;

    #[test]
    fn control_points_through_the_road_frame() {
        let road = road();
        let pts = points(&road, 8);
        let model = CameraModel::homography(&road, &pts).unwrap();
        assert!(model.rmse_m() < 1e-6);
        for p in PROBES {
            assert!(close(model.to_local(p), map(&truth(), p), 1e-6), "at {p:?}");
        }
        let ll = model.to_wgs84(&road, pts[3].pixel).unwrap();
        assert_eq!(ll, pts[3].ground);
    }
}
