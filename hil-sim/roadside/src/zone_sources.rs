//! Zone geometry of a site from its sources: a cone list, a WZDx feed, or cones
//! localised by a calibrated camera from per-frame detections; and the site's zones as
//! the roadside broadcasts them ([`build_zones`]).

use crate::camera::{self, CalibrationError, CameraModel, ModelError};
use crate::clock::Utc;
use crate::cones::{self, ConeTracker, DetectionError, TrackerConfig};
use crate::geojson::InputError;
use crate::messages::{SignSpeed, WorkZone, DURATION_INDEFINITE};
use crate::road::Road;
use crate::site::{Site, ZoneSource};
use std::fmt;
use std::io;
use std::path::{Path, PathBuf};

/// Why a zone's source gives no zone. `file` is the path as the site gives it (relative to
/// its folder); `path` the file as read.
#[derive(Debug)]
#[non_exhaustive]
pub enum ZoneError {
    /// A source file could not be read.
    Io {
        /// The file as read.
        path: PathBuf,
        /// The file system's error.
        source: io::Error,
    },
    /// A WZDx file is not a WZDx feed on this map.
    Wzdx {
        /// The file.
        file: PathBuf,
        /// What is wrong with it.
        source: InputError,
    },
    /// A WZDx file has no work-zone event on this map.
    NoWzdxZone {
        /// The file.
        file: PathBuf,
    },
    /// A WZDx source given where only other sources are taken (a WZDx source goes through
    /// [`zone`]).
    WzdxNotHere {
        /// The file.
        file: PathBuf,
    },
    /// A cone list is not a cone list on this map.
    Cones {
        /// The file.
        file: PathBuf,
        /// What is wrong with it.
        source: InputError,
    },
    /// A camera's calibration file is not a calibration.
    Calibration {
        /// The file.
        file: PathBuf,
        /// What is wrong with it.
        source: CalibrationError,
    },
    /// A camera's calibration points give no camera model.
    CameraModel {
        /// The calibration file.
        file: PathBuf,
        /// Why there is no model.
        source: ModelError,
    },
    /// A camera's detections file is not detections.
    Detections {
        /// The file.
        file: PathBuf,
        /// What is wrong with it.
        source: DetectionError,
    },
    /// The cone tracker's configuration is refused.
    TrackerConfig,
    /// No cone of the source lies on a lane of the map.
    NoConeOnLane,
}

impl fmt::Display for ZoneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io { path, source } => write!(f, "{}: {source}", path.display()),
            Self::Wzdx { file, source } | Self::Cones { file, source } => {
                write!(f, "{}: {source}", file.display())
            }
            Self::NoWzdxZone { file } => {
                write!(f, "{}: no work-zone event on this map", file.display())
            }
            Self::WzdxNotHere { file } => {
                write!(f, "{}: a WZDx feed goes through zone()", file.display())
            }
            Self::Calibration { file, source } => write!(f, "{}: {source}", file.display()),
            Self::CameraModel { file, source } => write!(f, "{}: {source}", file.display()),
            Self::Detections { file, source } => write!(f, "{}: {source}", file.display()),
            Self::TrackerConfig => f.write_str("tracker configuration"),
            Self::NoConeOnLane => f.write_str("no cone lies on a lane of the map"),
        }
    }
}

impl std::error::Error for ZoneError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Io { source, .. } => Some(source),
            Self::Wzdx { source, .. } | Self::Cones { source, .. } => Some(source),
            Self::Calibration { source, .. } => Some(source),
            Self::CameraModel { source, .. } => Some(source),
            Self::Detections { source, .. } => Some(source),
            Self::NoWzdxZone { .. }
            | Self::WzdxNotHere { .. }
            | Self::TrackerConfig
            | Self::NoConeOnLane => None,
        }
    }
}

/// The text of the site's file `file`.
fn read(s: &Site, file: &Path) -> Result<String, ZoneError> {
    let path = s.path(file);
    match std::fs::read_to_string(&path) {
        Ok(text) => Ok(text),
        Err(source) => Err(ZoneError::Io { path, source }),
    }
}

/// What a source says about a zone.
#[derive(Debug, Clone, PartialEq)]
pub struct SourcedZone {
    /// Closed lanes.
    pub closed_lanes: Vec<u8>,
    /// Start station along the first closed lane, metres.
    pub start_m: f64,
    /// End station, metres.
    pub end_m: f64,
    /// The reduced limit the source gives (WZDx), if any.
    pub speed_limit: Option<SignSpeed>,
}

/// The closed lanes, stations and limit of a zone from its source.
///
/// # Errors
///
/// [`ZoneError`]: a source file that cannot be read or is not what its source says, or a
/// source that gives no zone on this map.
pub fn zone(s: &Site, road: &Road, source: &ZoneSource) -> Result<SourcedZone, ZoneError> {
    if let ZoneSource::Wzdx { file } = source {
        let text = read(s, file)?;
        let zones = crate::geojson::work_zones_from_wzdx(road, &text).map_err(|source| {
            ZoneError::Wzdx {
                file: file.clone(),
                source,
            }
        })?;
        let z = zones
            .first()
            .ok_or_else(|| ZoneError::NoWzdxZone { file: file.clone() })?;
        return Ok(SourcedZone {
            closed_lanes: z.closed_lanes.clone(),
            start_m: z.start_m,
            end_m: z.end_m,
            speed_limit: z.speed_limit,
        });
    }
    let (closed_lanes, start_m, end_m) = geometry(s, road, source)?;
    Ok(SourcedZone {
        closed_lanes,
        start_m,
        end_m,
        speed_limit: None,
    })
}

/// Closed lanes and the start/end stations (along the first closed lane) of a zone from a
/// source other than WZDx.
fn geometry(s: &Site, road: &Road, source: &ZoneSource) -> Result<(Vec<u8>, f64, f64), ZoneError> {
    match source {
        ZoneSource::Lanes {
            closed_lanes,
            start_m,
            end_m,
        } => Ok((closed_lanes.clone(), *start_m, *end_m)),
        ZoneSource::Cones { file } => {
            let cones = crate::geojson::load_cones(road, &read(s, file)?).map_err(|source| {
                ZoneError::Cones {
                    file: file.clone(),
                    source,
                }
            })?;
            from_cones(road, &cones)
        }
        ZoneSource::Wzdx { file } => Err(ZoneError::WzdxNotHere { file: file.clone() }),
        ZoneSource::Camera {
            calibration,
            detections,
        } => {
            let points = camera::parse_calibration(&read(s, calibration)?).map_err(|source| {
                ZoneError::Calibration {
                    file: calibration.clone(),
                    source,
                }
            })?;
            let model = CameraModel::homography(road, &points).map_err(|source| {
                ZoneError::CameraModel {
                    file: calibration.clone(),
                    source,
                }
            })?;
            let frames = cones::parse_detections_json(&read(s, detections)?).map_err(|source| {
                ZoneError::Detections {
                    file: detections.clone(),
                    source,
                }
            })?;
            let mut tracker =
                ConeTracker::new(TrackerConfig::default()).ok_or(ZoneError::TrackerConfig)?;
            let mut confirmed = Vec::new();
            for f in &frames {
                let local: Vec<[f64; 2]> = f
                    .detections
                    .iter()
                    .filter_map(|d| model.to_local(d.bbox.bottom_centre()))
                    .collect();
                confirmed = tracker.push_frame(&local);
            }
            from_cones(road, &confirmed)
        }
    }
}

/// A zone from cone positions: the lanes they close and the closure of the first.
fn from_cones(road: &Road, cones: &[[f64; 2]]) -> Result<(Vec<u8>, f64, f64), ZoneError> {
    let closures = cones::closures(road, cones);
    let first = closures.first().ok_or(ZoneError::NoConeOnLane)?;
    Ok((
        closures.iter().map(|c| c.lane).collect(),
        first.start_m,
        first.end_m,
    ))
}

/// The zones of the site as the roadside builds them (stable packet ids), valid from
/// `start` until further notice.
///
/// # Errors
///
/// The first zone whose source gives none ([`zone`]).
pub fn build_zones(s: &Site, road: &Road, start: Utc) -> Result<Vec<WorkZone>, ZoneError> {
    let mut out = Vec::new();
    for (i, z) in s.zones.iter().enumerate() {
        let mut packet_id = *b"HILZONE00";
        packet_id[7] = b'0' + (i / 10) as u8 % 10;
        packet_id[8] = b'0' + (i % 10) as u8;
        let sourced = zone(s, road, &z.source)?;
        let speed_limit = match (z.limit_kmh, z.limit_mph) {
            (_, Some(value)) => Some(SignSpeed { value, mph: true }),
            (Some(value), None) => Some(SignSpeed { value, mph: false }),
            (None, None) => sourced.speed_limit,
        };
        let (closed_lanes, start_m, end_m) = (sourced.closed_lanes, sourced.start_m, sourced.end_m);
        out.push(WorkZone {
            closed_lanes,
            start_m,
            end_m,
            speed_limit,
            packet_id,
            msg_cnt: 1,
            start,
            duration_min: DURATION_INDEFINITE,
        });
    }
    Ok(out)
}
