//! A site file: one roadside installation as deployed (lane map, work zones, signing, a
//! direct UDP broadcast, and the RSUs to program over SNMP). It has no simulator sections:
//! the bench's scenario files hold those.
//!
//! ```toml
//! [site]
//! name = "I-70 EB MP 120"
//! state_dir = "/var/lib/roadside"          # owned rows, status.json
//!
//! [road]                                   # as a scenario's [road]
//! kind = "geojson"
//! file = "lanes.geojson"
//!
//! [[zones]]                                # as a scenario's [[zones]]
//! source = "wzdx"
//! file = "wzdx.geojson"
//!
//! [wzdx_feed]                              # zones from a live feed (and/or [[zones]])
//! url = "https://dot.example/wzdx/feed.geojson"
//! poll_s = 60
//!
//! [signing]
//! pki = "pki"                              # rsu.oer + rsu.key
//! deposit = "roadside"                     # roadside | rsu | none
//!
//! [rsus]
//! credentials = "/etc/roadside/rsu-credentials.toml"   # mode 0600
//! poll_s = 30
//!
//! [[rsu]]
//! name = "rsu-mp120"
//! address = "10.20.0.11:161"
//! mib = "ntcip1218"                        # or "rsu4.1"
//! credentials = "field"                    # entry of the credentials file
//! ```

mod error;

pub use error::{SiteFileError, SiteProblem};

use crate::rsu_snmp::credentials::CredentialsFile;
use crate::rsu_snmp::deposit::{DepositSettings, DepositSigning};
use crate::rsu_snmp::fleet::{FleetTiming, RsuSpec};
use crate::rsu_snmp::mib::RsuMib;
use crate::rsu_snmp::table::TableRules;
use crate::site::{RadioFaults, RoadSpec, Site, ZoneSpec};
use serde::Deserialize;
use std::net::{SocketAddr, ToSocketAddrs};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// A site file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SiteFile {
    /// `[site]`.
    pub site: SiteInfo,
    /// `[road]`: the lane map.
    pub road: RoadSpec,
    /// `[[zones]]`: the work zones.
    #[serde(default)]
    pub zones: Vec<ZoneSpec>,
    /// `[wzdx_feed]`: work zones from a live WZDx feed (besides any `[[zones]]`).
    pub wzdx_feed: Option<crate::wzdx_feed::FeedConfig>,
    /// `[signing]`.
    pub signing: Option<Signing>,
    /// `[broadcast]`: UDP straight from the roadside (besides or instead of RSUs).
    pub broadcast: Option<BroadcastSection>,
    /// `[rsus]`: settings of every RSU.
    pub rsus: Option<RsusSection>,
    /// `[[rsu]]`: the RSUs.
    #[serde(default)]
    pub rsu: Vec<RsuEntry>,
    /// The folder the file is in (paths are relative to it).
    #[serde(skip)]
    pub dir: PathBuf,
}

/// `[site]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SiteInfo {
    /// A name for logs.
    pub name: String,
    /// Where the roadside keeps the rows it owns and its status (`status.json`).
    #[serde(default = "default_state_dir")]
    pub state_dir: PathBuf,
}

fn default_state_dir() -> PathBuf {
    PathBuf::from("roadside-state")
}

/// `[signing]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Signing {
    /// The roadside's PKI folder (`rsu.oer`, `rsu.key`).
    pub pki: Option<PathBuf>,
    /// Who signs deposited messages.
    #[serde(default)]
    pub deposit: DepositSigning,
}

/// `[broadcast]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BroadcastSection {
    /// UDP destinations.
    pub to: Vec<SocketAddr>,
    /// Rate, Hz.
    #[serde(default = "default_rate")]
    pub rate_hz: f64,
}

fn default_rate() -> f64 {
    10.0
}

/// `[rsus]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RsusSection {
    /// The credentials file (mode 0600).
    pub credentials: PathBuf,
    /// Seconds between reads of a converged RSU.
    #[serde(default = "default_poll")]
    pub poll_s: f64,
    /// Answer timeout, ms.
    #[serde(default = "default_timeout")]
    pub timeout_ms: u64,
    /// Retries of a read.
    #[serde(default = "default_retries")]
    pub retries: u32,
    /// Worker threads.
    #[serde(default = "default_workers")]
    pub workers: usize,
    /// Radio channel (172-184; 183 for C-V2X).
    #[serde(default = "default_channel")]
    pub channel: u8,
    /// Repeat interval, ms.
    #[serde(default = "default_interval")]
    pub interval_ms: u32,
    /// NTCIP 1218 priority.
    #[serde(default = "default_priority")]
    pub priority: u8,
    /// How long a deposit lasts when its zone gives no end, hours.
    #[serde(default = "default_window")]
    pub window_hours: u32,
}

fn default_poll() -> f64 {
    30.0
}
fn default_timeout() -> u64 {
    1000
}
fn default_retries() -> u32 {
    1
}
fn default_workers() -> usize {
    8
}
fn default_channel() -> u8 {
    183
}
fn default_interval() -> u32 {
    100
}
fn default_priority() -> u8 {
    6
}
fn default_window() -> u32 {
    24
}

/// `[[rsu]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RsuEntry {
    /// Its name.
    pub name: String,
    /// `host:port` (port 161 when left out).
    pub address: String,
    /// The MIB it speaks (`roadside rsu probe` tells).
    pub mib: RsuMib,
    /// Its entry in the credentials file.
    pub credentials: String,
    /// Rows the roadside may use (default: what the RSU says, 100 on RSU 4.1).
    pub max_rows: Option<u32>,
    /// The roadside owns the whole table: rows it did not place are destroyed.
    #[serde(default)]
    pub manage_all_rows: bool,
    /// Radio channel (default: `[rsus]`'s).
    pub channel: Option<u8>,
    /// Repeat interval, ms (default: `[rsus]`'s).
    pub interval_ms: Option<u32>,
}

impl SiteFile {
    /// Reads a site file.
    ///
    /// # Errors
    ///
    /// [`SiteFileError`]: unreadable, not TOML of this shape (unknown keys refused), or
    /// inconsistent ([`SiteFileError::Invalid`]).
    pub fn load(path: &Path) -> Result<Self, SiteFileError> {
        let text = std::fs::read_to_string(path).map_err(|source| SiteFileError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let mut f: Self = toml::from_str(&text).map_err(|source| SiteFileError::Toml {
            path: path.to_path_buf(),
            source,
        })?;
        f.dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
        f.check().map_err(|problem| SiteFileError::Invalid {
            path: path.to_path_buf(),
            problem,
        })?;
        Ok(f)
    }

    /// Something to do, every number in its range, names unique, a signer where one is
    /// needed.
    fn check(&self) -> Result<(), SiteProblem> {
        if !self.rsu.is_empty() && self.rsus.is_none() {
            return Err(SiteProblem::RsuWithoutCredentials);
        }
        if self.rsu.is_empty() && self.broadcast.is_none() {
            return Err(SiteProblem::NothingToDo);
        }
        let within = |section: &str, key: &'static str, value: f64, min: f64, max: f64| {
            if value.is_finite() && (min..=max).contains(&value) {
                Ok(())
            } else {
                Err(SiteProblem::OutOfRange {
                    section: section.to_string(),
                    key,
                    value,
                    min,
                    max,
                })
            }
        };
        if let Some(r) = &self.rsus {
            let within = |key, value, min, max| within("[rsus]", key, value, min, max);
            within("poll_s", r.poll_s, 0.1, 86_400.0)?;
            within("timeout_ms", r.timeout_ms as f64, 10.0, 60_000.0)?;
            within("retries", f64::from(r.retries), 0.0, 10.0)?;
            within("workers", r.workers as f64, 1.0, 256.0)?;
            within("channel", f64::from(r.channel), 172.0, 184.0)?;
            within("interval_ms", f64::from(r.interval_ms), 1.0, 3_600_000.0)?;
            within("priority", f64::from(r.priority), 0.0, 63.0)?;
            within("window_hours", f64::from(r.window_hours), 1.0, 8_760.0)?;
        }
        if let Some(f) = &self.wzdx_feed {
            let within = |key, value, min, max| within("[wzdx_feed]", key, value, min, max);
            within("poll_s", f.poll_s, 0.1, 86_400.0)?;
            within("timeout_s", f.timeout_s, 0.1, 600.0)?;
            within("cancel_for_s", f.cancel_for_s, 0.0, 86_400.0)?;
            within("max_bytes", f.max_bytes as f64, 1.0, 1e9)?;
        }
        let mut names = std::collections::BTreeSet::new();
        for e in &self.rsu {
            if !names.insert(&e.name) {
                return Err(SiteProblem::DuplicateRsu {
                    name: e.name.clone(),
                });
            }
            let section = format!("[[rsu]] {}", e.name);
            if let Some(c) = e.channel {
                within(&section, "channel", f64::from(c), 172.0, 184.0)?;
            }
            if let Some(i) = e.interval_ms {
                within(&section, "interval_ms", f64::from(i), 1.0, 3_600_000.0)?;
            }
        }
        let deposit = self.signing.as_ref().map(|s| s.deposit).unwrap_or_default();
        let pki = self.signing.as_ref().and_then(|s| s.pki.as_ref());
        if !self.rsu.is_empty() && deposit == DepositSigning::Roadside && pki.is_none() {
            return Err(SiteProblem::SigningWithoutPki);
        }
        Ok(())
    }

    /// A path of the site, resolved against its folder.
    pub fn path(&self, p: &Path) -> PathBuf {
        self.dir.join(p)
    }

    /// The site's lane map and zones as the message builder takes them.
    pub fn site(&self) -> Site {
        Site {
            road: self.road.clone(),
            zones: self.zones.clone(),
            faults: RadioFaults::default(),
            dir: self.dir.clone(),
        }
    }

    /// The state folder.
    pub fn state_dir(&self) -> PathBuf {
        self.path(&self.site.state_dir)
    }

    /// The fleet's timing.
    pub fn timing(&self) -> FleetTiming {
        let r = self.rsus.clone().unwrap_or_else(|| RsusSection {
            credentials: PathBuf::new(),
            poll_s: default_poll(),
            timeout_ms: default_timeout(),
            retries: default_retries(),
            workers: default_workers(),
            channel: default_channel(),
            interval_ms: default_interval(),
            priority: default_priority(),
            window_hours: default_window(),
        });
        FleetTiming {
            poll: Duration::from_secs_f64(r.poll_s.max(0.1)),
            timeout: Duration::from_millis(r.timeout_ms.max(10)),
            retries: r.retries,
            backoff: Duration::from_secs(1),
            workers: r.workers.max(1),
        }
    }

    /// The RSUs with their credentials (from the 0600 file).
    ///
    /// # Errors
    ///
    /// [`SiteFileError::Credentials`]: the credentials file or an unknown entry;
    /// [`SiteFileError::Address`]: an address that does not resolve.
    pub fn rsu_specs(&self) -> Result<Vec<RsuSpec>, SiteFileError> {
        let Some(r) = &self.rsus else {
            return Ok(Vec::new());
        };
        let creds = CredentialsFile::load(&self.path(&r.credentials))?;
        let signing = self.signing.as_ref().map(|s| s.deposit).unwrap_or_default();
        self.rsu
            .iter()
            .map(|e| {
                let address = resolve(&e.address).map_err(|source| SiteFileError::Address {
                    rsu: e.name.clone(),
                    address: e.address.clone(),
                    source,
                })?;
                Ok(RsuSpec {
                    name: e.name.clone(),
                    address,
                    credentials: creds.get(&e.credentials)?.clone(),
                    rules: TableRules {
                        mib: e.mib,
                        max_rows: e.max_rows,
                        manage_all: e.manage_all_rows,
                    },
                    deposit: DepositSettings {
                        channel: e.channel.unwrap_or(r.channel),
                        interval_ms: e.interval_ms.unwrap_or(r.interval_ms),
                        priority: r.priority,
                        signing,
                    },
                })
            })
            .collect()
    }
}

/// `host:port`, or `host` on port 161; the error is the resolver's (`None`: no address).
fn resolve(address: &str) -> Result<SocketAddr, Option<std::io::Error>> {
    let with_port = if address.parse::<SocketAddr>().is_ok() || address.contains(':') {
        address.to_string()
    } else {
        format!("{address}:161")
    };
    with_port
        .to_socket_addrs()
        .map_err(Some)?
        .next()
        .ok_or(None)
}

#[cfg(test)]
mod tests {
    use super::*;

    const ROAD: &str = r#"
[site]
name = "test"

[road]
kind = "straight"
reference = [39.7392, -104.9903]
bearing_deg = 90.0
length_m = 600.0
lanes_forward = 2
speed_limit_kmh = 40.0
"#;

    /// Loads `text` as a site file in a folder of its own.
    fn load(name: &str, text: &str) -> (PathBuf, Result<SiteFile, SiteFileError>) {
        let dir = std::env::temp_dir().join(format!("site-file-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("site.toml");
        std::fs::write(&path, text).unwrap();
        let loaded = SiteFile::load(&path);
        let _ = std::fs::remove_dir_all(&dir);
        (path, loaded)
    }

    #[test]
    fn a_value_out_of_range_is_named_by_its_section_and_key() {
        let text = format!(
            "{ROAD}\n[broadcast]\nto = [\"127.0.0.1:1516\"]\n\n[rsus]\ncredentials = \"c.toml\"\nchannel = 200\n"
        );
        let (path, loaded) = load("range", &text);
        let err = loaded.unwrap_err();
        assert_eq!(
            err.to_string(),
            format!("{}: [rsus] channel = 200: from 172 to 184", path.display())
        );
        match err {
            SiteFileError::Invalid {
                path: at,
                problem:
                    SiteProblem::OutOfRange {
                        section,
                        key: "channel",
                        value,
                        ..
                    },
            } => assert_eq!((at, section.as_str(), value), (path, "[rsus]", 200.0)),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn a_site_with_nothing_to_do_or_an_unknown_key_is_refused() {
        let (_, loaded) = load("idle", ROAD);
        assert!(matches!(
            loaded,
            Err(SiteFileError::Invalid {
                problem: SiteProblem::NothingToDo,
                ..
            })
        ));
        let (_, loaded) = load("unknown", &format!("{ROAD}\ncolour = \"red\"\n"));
        assert!(matches!(loaded, Err(SiteFileError::Toml { .. })));
        let (_, ok) = load(
            "ok",
            &format!("{ROAD}\n[broadcast]\nto = [\"127.0.0.1:1516\"]\n"),
        );
        assert_eq!(ok.unwrap().site.name, "test");
    }
}
