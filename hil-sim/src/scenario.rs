//! Scenario files (TOML): the lane map, the work zones and where they come from, the
//! faults (the roadside's [`Site`]), an attacker beside the roadside (`[attacker]`), a
//! camera site whose tracked workers go out as PSMs (`[workers]`), the
//! drive, the driver's settings and the expectations. Paths inside a scenario are relative to its file.

use crate::drive::DriveSpec;
use crate::expect::Expectation;
pub use crate::roadside_bench::attacker::{AttackKind, AttackerSpec};
pub use crate::roadside_bench::camera_site::{CameraSiteSpec, SceneUserSpec};
use obu::alert::settings::{LEAD_TIME_S, WARNING_DISTANCE_M};
use roadside::road::Road;
pub use roadside::site::{RadioFaults, RoadSpec, Site, ZoneSource, ZoneSpec};
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
    pub faults: RadioFaults,
    /// Driver settings of the OBU.
    #[serde(default)]
    pub settings: Settings,
    /// A forged or replayed MAP/TIM sender beside the roadside.
    #[serde(default)]
    pub attacker: Option<AttackerSpec>,
    /// A roadside camera site whose tracked workers go out as PSMs (`[workers]`).
    #[serde(default)]
    pub workers: Option<CameraSiteSpec>,
    /// Vehicle speed from CAN (a candump replay) instead of GNSS.
    #[serde(default)]
    pub can_speed: bool,
    /// How the bench roadside signs (default: each transmission anew, 60 s expiry, the
    /// certificate in every message).
    #[serde(default)]
    pub signing: SigningSpec,
    /// The roadside as deployed: a WZDx feed, the `roadside` service and a test RSU over
    /// SNMP instead of the bench's scripted broadcaster (`[rsu_deployment]`).
    #[serde(default)]
    pub rsu_deployment: Option<crate::deployment::DeploymentSpec>,
    /// What must hold.
    #[serde(default, rename = "expect")]
    pub expectations: Vec<Expectation>,
    /// The folder of the scenario file (paths are relative to it).
    #[serde(skip)]
    pub dir: PathBuf,
}

/// `[signing]`: how the bench roadside signs what it broadcasts.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SigningSpec {
    /// `per_transmission` (V2X-Hub's way) or `once` (signed once and repeated until its
    /// expiry time, as jpo-ode deposits TIMs).
    #[serde(default)]
    pub pattern: SigningKind,
    /// `once`: how long before the drive the messages were signed, seconds.
    #[serde(default)]
    pub signed_ago_s: u64,
    /// Generation to expiry, seconds.
    #[serde(default = "sixty")]
    pub lifetime_s: u64,
    /// Send the certificate whole at most this often, milliseconds, and a `digest` signer
    /// in between (per transmission); absent: the certificate in every message.
    #[serde(default)]
    pub certificate_every_ms: Option<u64>,
}

fn sixty() -> u64 {
    60
}

impl Default for SigningSpec {
    fn default() -> Self {
        Self {
            pattern: SigningKind::PerTransmission,
            signed_ago_s: 0,
            lifetime_s: sixty(),
            certificate_every_ms: None,
        }
    }
}

/// [`SigningSpec::pattern`].
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SigningKind {
    /// Each transmission signed anew.
    #[default]
    PerTransmission,
    /// Signed once, repeated until its expiry time.
    Once,
}

impl SigningSpec {
    /// The pattern, the lifetime (ms) and how often the certificate goes whole (ms), as
    /// `roadside::rsu::RoadsideOptions::signing` takes them.
    pub fn settings(&self) -> (roadside::signer::SigningPattern, u64, Option<u64>) {
        use roadside::signer::SigningPattern;
        let pattern = match self.pattern {
            SigningKind::PerTransmission => SigningPattern::PerTransmission,
            SigningKind::Once => SigningPattern::Once {
                signed_ago_ms: self.signed_ago_s.saturating_mul(1000),
            },
        };
        (
            pattern,
            self.lifetime_s.saturating_mul(1000),
            self.certificate_every_ms,
        )
    }

    /// `signer` signing this way.
    pub fn apply(&self, signer: &roadside::signer::RsuSigner) -> roadside::signer::RsuSigner {
        let (pattern, lifetime_ms, every) = self.settings();
        signer.clone().signing(pattern, lifetime_ms, every)
    }
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
            warning_distance_m: f64::from(WARNING_DISTANCE_M.default),
            lead_time_s: f64::from(LEAD_TIME_S.default),
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
        self.road.build(&self.dir).map_err(|e| e.to_string())
    }

    /// The roadside's part: lane map, zones and radio faults, with the folder of the file.
    pub fn site(&self) -> Site {
        Site {
            road: self.road.clone(),
            zones: self.zones.clone(),
            faults: self.faults.clone(),
            dir: self.dir.clone(),
        }
    }
}
