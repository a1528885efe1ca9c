//! Why a camera folder, a truth file or an area file cannot be used: [`FileError`].

use crate::camera::{CalibrationError, ModelError};
use crate::road_users::calibrate::{CalibrationFault, GroundCameraFault};
use crate::road_users::detections::MaskError;
use image::ImageError;
use std::fmt;
use std::io;
use std::path::PathBuf;

/// Why a camera folder, a truth file or a work zone's area file cannot be used, or a
/// drawing not written.
#[derive(Debug)]
#[non_exhaustive]
pub enum FileError {
    /// A file cannot be read.
    Io {
        /// The file.
        path: PathBuf,
        /// The file system's error.
        source: io::Error,
    },
    /// A camera's `calibration.json` cannot be read or is not a calibration.
    Calibration(CalibrationError),
    /// A camera's `calibration.json` has no reference points.
    NoCalibrationPoints,
    /// A camera's reference points give no homography.
    Homography {
        /// The camera folder.
        dir: PathBuf,
        /// Why there is none.
        source: ModelError,
    },
    /// A camera's `detections.json` is not a COCO file of masks.
    Masks {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        source: MaskError,
    },
    /// A camera's `detections.json` names no image file.
    NoImageName {
        /// The file.
        path: PathBuf,
    },
    /// An image cannot be read or written.
    Image {
        /// The image file.
        path: PathBuf,
        /// The image library's error.
        source: ImageError,
    },
    /// A camera's first frame gives no vanishing points.
    VanishingPoints {
        /// The frame's file.
        path: PathBuf,
        /// Why it does not calibrate the camera.
        source: CalibrationFault,
    },
    /// A camera's calibration gives no localizer.
    Localizer(GroundCameraFault),
    /// A file is not JSON.
    Json {
        /// The file.
        path: PathBuf,
        /// The parser's error.
        source: serde_json::Error,
    },
    /// A truth file has no `frames` array.
    NoTruthFrames,
    /// A truth file's frame has no `users` array.
    TruthFrameWithoutUsers,
    /// A truth file's road user lacks a known class or a valid lat/lon.
    TruthUser,
    /// An area file has no `area` array.
    NoArea {
        /// The file.
        path: PathBuf,
    },
    /// An area's corner lacks a valid lat or lon.
    BadCorner {
        /// The file.
        path: PathBuf,
    },
    /// An area of fewer than three corners.
    TooFewCorners {
        /// The file.
        path: PathBuf,
        /// Corners given.
        corners: usize,
    },
}

impl fmt::Display for FileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io { path, source } => write!(f, "{}: {source}", path.display()),
            Self::Calibration(e) => e.fmt(f),
            Self::NoCalibrationPoints => f.write_str("calibration.json has no points"),
            Self::Homography { dir, source } => write!(f, "{}: {source}", dir.display()),
            Self::Masks { path, source } => write!(f, "{}: {source}", path.display()),
            Self::NoImageName { path } => {
                write!(f, "{}: no image with a file name", path.display())
            }
            Self::Image { path, source } => write!(f, "{}: {source}", path.display()),
            Self::VanishingPoints { path, source } => write!(f, "{}: {source}", path.display()),
            Self::Localizer(e) => e.fmt(f),
            Self::Json { path, source } => write!(f, "{}: {source}", path.display()),
            Self::NoTruthFrames => f.write_str("truth: no \"frames\" array"),
            Self::TruthFrameWithoutUsers => f.write_str("truth: a frame has no \"users\""),
            Self::TruthUser => f.write_str("truth: a user needs a class and a lat/lon"),
            Self::NoArea { path } => write!(f, "{}: no \"area\" array", path.display()),
            Self::BadCorner { path } => {
                write!(f, "{}: a corner needs a valid lat and lon", path.display())
            }
            Self::TooFewCorners { path, .. } => write!(
                f,
                "{}: the area needs at least three corners",
                path.display()
            ),
        }
    }
}

impl std::error::Error for FileError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Io { source, .. } => Some(source),
            Self::Calibration(e) => Some(e),
            Self::Homography { source, .. } => Some(source),
            Self::Masks { source, .. } => Some(source),
            Self::Image { source, .. } => Some(source),
            Self::VanishingPoints { source, .. } => Some(source),
            Self::Localizer(e) => Some(e),
            Self::Json { source, .. } => Some(source),
            Self::NoCalibrationPoints
            | Self::NoImageName { .. }
            | Self::NoTruthFrames
            | Self::TruthFrameWithoutUsers
            | Self::TruthUser
            | Self::NoArea { .. }
            | Self::BadCorner { .. }
            | Self::TooFewCorners { .. } => None,
        }
    }
}

impl From<CalibrationError> for FileError {
    fn from(e: CalibrationError) -> Self {
        Self::Calibration(e)
    }
}
