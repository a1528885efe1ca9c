//! The roadside's part of a scenario file: the lane map (`[road]`), the work zones and
//! where their geometry comes from (`[[zones]]`), and the radio faults of its broadcast
//! (`[faults]`). The bench's scenario (`hil_sim::scenario`) holds these next to the drive
//! and the expectations and hands them to the roadside as a [`Site`]. Paths are relative
//! to the folder of the file ([`Site::dir`]).

use crate::geojson::InputError;
use crate::road::Road;
use geodesy::LatLon;
use serde::Deserialize;
use std::fmt;
use std::io;
use std::path::{Path, PathBuf};

/// Why a site's lane map could not be built.
#[derive(Debug)]
#[non_exhaustive]
pub enum SiteError {
    /// A built-in road's reference point is not a position.
    Reference {
        /// The reference point as given, `[lat, lon]` degrees.
        reference: [f64; 2],
    },
    /// The GeoJSON lane map could not be read.
    Io {
        /// The file.
        path: PathBuf,
        /// The file system's error.
        source: io::Error,
    },
    /// The GeoJSON lane map is not a lane map.
    LaneMap {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        source: InputError,
    },
}

impl fmt::Display for SiteError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Reference { reference } => {
                write!(f, "reference {reference:?} is not a position")
            }
            Self::Io { path, source } => write!(f, "{}: {source}", path.display()),
            Self::LaneMap { path, source } => write!(f, "{}: {source}", path.display()),
        }
    }
}

impl std::error::Error for SiteError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Reference { .. } => None,
            Self::Io { source, .. } => Some(source),
            Self::LaneMap { source, .. } => Some(source),
        }
    }
}

/// A roadside installation: its lane map, work zones and radio.
#[derive(Debug, Clone)]
pub struct Site {
    /// The lane map.
    pub road: RoadSpec,
    /// Work zones broadcast by the roadside.
    pub zones: Vec<ZoneSpec>,
    /// Radio and timing faults.
    pub faults: RadioFaults,
    /// The folder paths are relative to.
    pub dir: PathBuf,
}

impl Site {
    /// A path of the site, resolved against its folder.
    pub fn path(&self, p: &Path) -> PathBuf {
        self.dir.join(p)
    }

    /// Builds the lane map.
    ///
    /// # Errors
    ///
    /// As [`RoadSpec::build`].
    pub fn road(&self) -> Result<Road, SiteError> {
        self.road.build(&self.dir)
    }
}

/// The lane map: built in or from a GeoJSON file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields, tag = "kind", rename_all = "snake_case")]
pub enum RoadSpec {
    /// [`Road::straight`].
    Straight {
        /// Reference point [lat, lon] in degrees.
        reference: [f64; 2],
        /// Direction of the forward lanes, degrees.
        bearing_deg: f64,
        /// Length, metres.
        length_m: f64,
        /// Lanes in the bearing's direction.
        lanes_forward: u8,
        /// Lanes the other way.
        #[serde(default)]
        lanes_backward: u8,
        /// Lane width, metres.
        #[serde(default = "default_width")]
        width_m: f64,
        /// Speed limit, km/h.
        speed_limit_kmh: f64,
    },
    /// [`Road::arc`].
    Arc {
        /// Reference point [lat, lon] in degrees.
        reference: [f64; 2],
        /// Initial direction, degrees.
        bearing_deg: f64,
        /// Turn radius, metres (positive: right).
        radius_m: f64,
        /// Length, metres.
        length_m: f64,
        /// Lanes in the direction of travel.
        lanes_forward: u8,
        /// Lanes the other way.
        #[serde(default)]
        lanes_backward: u8,
        /// Lane width, metres.
        #[serde(default = "default_width")]
        width_m: f64,
        /// Speed limit, km/h.
        speed_limit_kmh: f64,
    },
    /// A GeoJSON lane map ([`crate::geojson::load_lane_map`]).
    Geojson {
        /// The file.
        file: PathBuf,
    },
}

fn default_width() -> f64 {
    3.6
}

impl RoadSpec {
    /// Builds the lane map; a GeoJSON file is read relative to `dir`.
    ///
    /// # Errors
    ///
    /// [`SiteError`]: a reference that is not a position, or a GeoJSON file that cannot be
    /// read or is not a lane map.
    pub fn build(&self, dir: &Path) -> Result<Road, SiteError> {
        let at = |reference: [f64; 2]| {
            LatLon::from_degrees(reference[0], reference[1])
                .ok_or(SiteError::Reference { reference })
        };
        Ok(match self {
            RoadSpec::Straight {
                reference,
                bearing_deg,
                length_m,
                lanes_forward,
                lanes_backward,
                width_m,
                speed_limit_kmh,
            } => Road::straight(
                at(*reference)?,
                *bearing_deg,
                *length_m,
                (*lanes_forward, *lanes_backward),
                *width_m,
                *speed_limit_kmh,
            ),
            RoadSpec::Arc {
                reference,
                bearing_deg,
                radius_m,
                length_m,
                lanes_forward,
                lanes_backward,
                width_m,
                speed_limit_kmh,
            } => Road::arc(
                at(*reference)?,
                *bearing_deg,
                *radius_m,
                *length_m,
                25.0,
                (*lanes_forward, *lanes_backward),
                *width_m,
                *speed_limit_kmh,
            ),
            RoadSpec::Geojson { file } => {
                let path = dir.join(file);
                let text = match std::fs::read_to_string(&path) {
                    Ok(text) => text,
                    Err(source) => return Err(SiteError::Io { path, source }),
                };
                crate::geojson::load_lane_map(&text)
                    .map_err(|source| SiteError::LaneMap { path, source })?
            }
        })
    }
}

/// One work zone and its source (unknown keys are refused by the source's variant).
#[derive(Debug, Clone, Deserialize)]
pub struct ZoneSpec {
    /// Where the closed lanes come from.
    #[serde(flatten)]
    pub source: ZoneSource,
    /// Reduced speed limit, km/h.
    pub limit_kmh: Option<u16>,
    /// Reduced speed limit, mph (instead of km/h).
    pub limit_mph: Option<u16>,
    /// The roadside stops the zone (cones removed: TIM cancelled) this many seconds into
    /// the drive.
    pub removed_at_s: Option<f64>,
    /// The zone shrinks to end at this station this many seconds into the drive
    /// (`[seconds, end_m]`: cones removed from the far end).
    pub shrink_at: Option<(f64, f64)>,
    /// The TIM's own validity window (`startTime` + `durationTime`) ends at the first
    /// minute boundary at least this many seconds after the zones are built (just before
    /// the drive); the roadside keeps broadcasting the same TIM unchanged after it.
    pub ends_after_s: Option<f64>,
}

/// Where a zone's geometry comes from.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields, tag = "source", rename_all = "snake_case")]
pub enum ZoneSource {
    /// Given directly: lanes and stations along the first one.
    Lanes {
        /// Closed lanes.
        closed_lanes: Vec<u8>,
        /// Start station, metres.
        start_m: f64,
        /// End station, metres.
        end_m: f64,
    },
    /// A list of cone positions ([`crate::geojson::load_cones`]).
    Cones {
        /// JSON or CSV file of lat/lon.
        file: PathBuf,
    },
    /// A WZDx 4.2 road event file ([`crate::geojson::work_zones_from_wzdx`]).
    Wzdx {
        /// The file.
        file: PathBuf,
    },
    /// Cones localised by a calibrated camera: the calibration, and either detections of
    /// real frames or those of the bench's synthetic camera that sees given ground-truth
    /// cones (`hil-sim synth-camera`).
    Camera {
        /// Calibration correspondences (JSON).
        calibration: PathBuf,
        /// Detections per frame (JSON boxes).
        detections: PathBuf,
    },
}

/// Radio and timing faults of the roadside's broadcast (a scenario's `[faults]`).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RadioFaults {
    /// Fraction of V2X datagrams lost.
    #[serde(default)]
    pub loss_rate: f64,
    /// Mean length of loss bursts, datagrams (1: independent losses).
    #[serde(default)]
    pub loss_burst: f64,
    /// Fraction of V2X datagrams with one bit flipped.
    #[serde(default)]
    pub corrupt_rate: f64,
    /// No TIM before this many seconds into the drive.
    #[serde(default)]
    pub tim_delay_s: f64,
    /// The MAP's revision changes (lanes shifted by `map_shift_m` to the left) at this time.
    pub map_revision_at_s: Option<f64>,
    /// Lateral shift of the lanes in the new MAP revision, metres.
    #[serde(default)]
    pub map_shift_m: f64,
    /// Seed of the fault models.
    #[serde(default)]
    pub seed: u64,
}
