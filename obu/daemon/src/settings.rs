//! The driver's settings (`GET/PUT /api/settings`): validated, and saved atomically (written
//! to a temporary file beside the target, flushed, then renamed over it) so that a crash or a
//! power cut never leaves half a file and a restart keeps them.

use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::{Path, PathBuf};

pub use obu::alert::settings::{DisplayUnits as Units, OutOfRange, Theme};
use obu::alert::settings::{LEAD_TIME_S, SOUND_DEFAULT, WARNING_DISTANCE_M};

/// What the driver can set on the tablet: the ranges, defaults and units are the core's
/// ([`obu::alert::settings`]), which the tablet reads from `contract.json`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Settings {
    /// Minimum warning distance, metres ([`WARNING_DISTANCE_M`]).
    pub warning_distance_m: f32,
    /// Warning lead time at the current speed, seconds ([`LEAD_TIME_S`]).
    pub lead_time_s: f32,
    /// Audible alerts on.
    pub sound: bool,
    /// Units.
    pub units: Units,
    /// Theme.
    pub theme: Theme,
}

impl Settings {
    /// Settings from the configured alert defaults.
    pub fn defaults(warning_distance_m: f32, lead_time_s: f32) -> Self {
        Self {
            warning_distance_m,
            lead_time_s,
            sound: SOUND_DEFAULT,
            units: Units::default(),
            theme: Theme::default(),
        }
    }

    /// Checks the ranges; the error names the field.
    pub fn validate(&self) -> Result<(), OutOfRange> {
        WARNING_DISTANCE_M.check(self.warning_distance_m)?;
        LEAD_TIME_S.check(self.lead_time_s)?;
        Ok(())
    }
}

/// The settings file.
#[derive(Clone, Debug)]
pub struct SettingsFile {
    path: PathBuf,
}

impl SettingsFile {
    /// The file at `path`.
    pub fn new(path: impl Into<PathBuf>) -> Self {
        Self { path: path.into() }
    }

    /// The saved settings, or `fallback` when there is no (valid) file; a corrupt file is
    /// reported in the error and left in place for inspection.
    pub fn load(&self, fallback: Settings) -> (Settings, Option<String>) {
        match std::fs::read_to_string(&self.path) {
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => (fallback, None),
            Err(e) => (
                fallback,
                Some(format!("cannot read {}: {e}", self.path.display())),
            ),
            Ok(text) => match serde_json::from_str::<Settings>(&text) {
                Ok(s) if s.validate().is_ok() => (s, None),
                Ok(_) | Err(_) => (
                    fallback,
                    Some(format!("ignoring invalid {}", self.path.display())),
                ),
            },
        }
    }

    /// Saves atomically.
    pub fn save(&self, settings: &Settings) -> std::io::Result<()> {
        let tmp = temp_beside(&self.path);
        {
            let mut f = std::fs::File::create(&tmp)?;
            f.write_all(serde_json::to_string_pretty(settings)?.as_bytes())?;
            f.write_all(b"\n")?;
            f.sync_all()?;
        }
        std::fs::rename(&tmp, &self.path)
    }
}

/// `path` with `.tmp` added to its name: where an atomic save writes before the rename.
pub(crate) fn temp_beside(path: &Path) -> PathBuf {
    let mut name = path
        .file_name()
        .map(|n| n.to_os_string())
        .unwrap_or_default();
    name.push(".tmp");
    path.with_file_name(name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_are_checked() {
        let ok = Settings::defaults(100.0, 9.0);
        assert!(ok.validate().is_ok());
        let e = Settings {
            warning_distance_m: 5.0,
            ..ok
        }
        .validate()
        .unwrap_err();
        assert_eq!(e.setting.name, "warning_distance_m");
        let e = Settings {
            lead_time_s: f32::NAN,
            ..ok
        }
        .validate()
        .unwrap_err();
        assert_eq!(e.setting.name, "lead_time_s");
    }

    #[test]
    fn saved_settings_survive_a_restart() {
        let dir = std::env::temp_dir().join(format!("obu-settings-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = SettingsFile::new(dir.join("s.json"));
        let fallback = Settings::defaults(100.0, 9.0);
        assert_eq!(file.load(fallback), (fallback, None));
        let mine = Settings {
            units: Units::Mph,
            warning_distance_m: 300.0,
            ..fallback
        };
        file.save(&mine).unwrap();
        assert_eq!(
            SettingsFile::new(dir.join("s.json")).load(fallback),
            (mine, None)
        );
        std::fs::write(dir.join("s.json"), "{not json").unwrap();
        let (s, warning) = file.load(fallback);
        assert_eq!(s, fallback);
        assert!(warning.unwrap().contains("invalid"));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn json_names_match_the_tablet() {
        let text = serde_json::to_string(&Settings::defaults(100.0, 9.0)).unwrap();
        assert_eq!(
            text,
            r#"{"warning_distance_m":100.0,"lead_time_s":9.0,"sound":true,"units":"kmh","theme":"auto"}"#
        );
    }
}
