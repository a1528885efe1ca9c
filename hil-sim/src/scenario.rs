//! Scenario files (TOML): the lane map, the work zones and where they come from, the
//! drive, the faults, the driver's settings and the expectations. Paths inside a scenario
//! are relative to its file.

use crate::drive::DriveSpec;
use crate::expect::Expectation;
use crate::road::Road;
use obu::LatLon;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// A whole scenario.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Short name (report titles).
    pub name: String,
    /// What it shows.
    #[serde(default)]
    pub description: String,
    /// The lane map.
    pub road: RoadSpec,
    /// Work zones broadcast by the roadside.
    #[serde(default)]
    pub zones: Vec<ZoneSpec>,
    /// The drive.
    pub drive: DriveSpec,
    /// Radio and timing faults.
    #[serde(default)]
    pub faults: Faults,
    /// Driver settings of the OBU.
    #[serde(default)]
    pub settings: Settings,
    /// Vehicle speed from CAN (a candump replay) instead of GNSS.
    #[serde(default)]
    pub can_speed: bool,
    /// What must hold.
    #[serde(default, rename = "expect")]
    pub expectations: Vec<Expectation>,
    /// The folder of the scenario file (paths are relative to it).
    #[serde(skip)]
    pub dir: PathBuf,
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
    /// real frames or a synthetic camera that sees given ground-truth cones.
    Camera {
        /// Calibration correspondences (JSON).
        calibration: PathBuf,
        /// Detections per frame (JSON boxes).
        detections: PathBuf,
    },
}

/// Radio and timing faults.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Faults {
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

/// Driver settings of the OBU.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Settings {
    /// Configured warning distance, metres.
    pub warning_distance_m: f64,
    /// Lead time, seconds.
    pub lead_time_s: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            warning_distance_m: 100.0,
            lead_time_s: 9.0,
        }
    }
}

impl Scenario {
    /// Reads a scenario file.
    pub fn load(path: &Path) -> Result<Self, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let mut s = Self::parse(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        s.dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Ok(s)
    }

    /// Parses scenario text (paths relative to the current directory).
    pub fn parse(text: &str) -> Result<Self, String> {
        toml::from_str(text).map_err(|e| e.to_string())
    }

    /// A path of the scenario, resolved against its folder.
    pub fn path(&self, p: &Path) -> PathBuf {
        self.dir.join(p)
    }

    /// Builds the lane map.
    pub fn road(&self) -> Result<Road, String> {
        let at = |r: [f64; 2]| {
            LatLon::from_degrees(r[0], r[1]).ok_or(format!("reference {r:?} is not a position"))
        };
        Ok(match &self.road {
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
                let path = self.path(file);
                let text = std::fs::read_to_string(&path)
                    .map_err(|e| format!("{}: {e}", path.display()))?;
                crate::geojson::load_lane_map(&text)
                    .map_err(|e| format!("{}: {e}", path.display()))?
            }
        })
    }
}
