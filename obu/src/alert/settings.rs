//! The driver's alert settings and the tablet's contract, defined once.
//!
//! The warning distance and lead time a driver may set (range, default, unit, step) are
//! [`WARNING_DISTANCE_M`] and [`LEAD_TIME_S`]; [`super::AlertConfig::DEFAULT`] takes its
//! defaults from them, the daemon validates its configuration and `PUT /api/settings` with
//! [`SettingRange::check`], and the tablet reads them from the contract
//! [`write_contract_json`] writes (served as `contract.json`), together with the alert kinds
//! in priority order ([`AlertKind::ALL`]), the stages ([`AlertStage::ALL`]) and the display
//! choices ([`DisplayUnits`], [`Theme`]).

use core::fmt;

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

use super::{AlertKind, AlertStage};

/// A numeric setting: its name (the JSON key), range, default, unit and the step the form
/// offers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SettingRange {
    /// The setting's key in `/api/settings`, the configuration's `[alerts]` table and the
    /// contract.
    pub name: &'static str,
    /// Least value allowed.
    pub min: f32,
    /// Greatest value allowed.
    pub max: f32,
    /// The default.
    pub default: f32,
    /// The unit of the stored value (SI: `m`, `s`).
    pub unit: &'static str,
    /// The step the tablet's form offers.
    pub step: f32,
}

/// A value outside its [`SettingRange`] (or not a finite number).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutOfRange {
    /// The setting.
    pub setting: SettingRange,
    /// The value refused.
    pub value: f32,
}

impl fmt::Display for OutOfRange {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = &self.setting;
        write!(f, "{} must be between {} and {}", s.name, s.min, s.max)
    }
}

impl core::error::Error for OutOfRange {}

impl SettingRange {
    /// `value` when it is a finite number within the range.
    pub fn check(&self, value: f32) -> Result<f32, OutOfRange> {
        if value.is_finite() && (self.min..=self.max).contains(&value) {
            Ok(value)
        } else {
            Err(OutOfRange {
                setting: *self,
                value,
            })
        }
    }
}

/// Minimum warning distance, metres: the warning starts at `max(this, speed x lead time)`.
/// 100 m is the field test's figure at 40 km/h.
pub const WARNING_DISTANCE_M: SettingRange = SettingRange {
    name: "warning_distance_m",
    min: 20.0,
    max: 2000.0,
    default: 100.0,
    unit: "m",
    step: 1.0,
};

/// Warning lead time at the current speed, seconds.
pub const LEAD_TIME_S: SettingRange = SettingRange {
    name: "lead_time_s",
    min: 2.0,
    max: 30.0,
    default: 9.0,
    unit: "s",
    step: 0.5,
};

/// Every numeric setting, in the form's order.
pub const NUMERIC_SETTINGS: [SettingRange; 2] = [WARNING_DISTANCE_M, LEAD_TIME_S];

/// Whether the tablet sounds its tones by default.
pub const SOUND_DEFAULT: bool = true;

/// Speed and distance units of the display.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum DisplayUnits {
    /// km/h and metres.
    #[default]
    Kmh,
    /// mph and feet.
    Mph,
}

impl DisplayUnits {
    /// Every choice, in the form's order.
    pub const ALL: [DisplayUnits; 2] = [DisplayUnits::Kmh, DisplayUnits::Mph];

    /// The JSON name.
    pub const fn as_str(self) -> &'static str {
        match self {
            DisplayUnits::Kmh => "kmh",
            DisplayUnits::Mph => "mph",
        }
    }
}

/// Display theme.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum Theme {
    /// Light.
    Day,
    /// Dark, low glare.
    Night,
    /// Follows the device.
    #[default]
    Auto,
}

impl Theme {
    /// Every choice, in the form's order.
    pub const ALL: [Theme; 3] = [Theme::Day, Theme::Night, Theme::Auto];

    /// The JSON name.
    pub const fn as_str(self) -> &'static str {
        match self {
            Theme::Day => "day",
            Theme::Night => "night",
            Theme::Auto => "auto",
        }
    }
}

/// Writes the tablet's contract as JSON: the alert kinds highest priority first, the stages
/// lowest first, and every setting with its range or choices, default and unit. The daemon
/// serves it as `contract.json`; `hmi-web/contract.json` is this text (a test compares them).
pub fn write_contract_json(out: &mut impl fmt::Write) -> fmt::Result {
    out.write_str("{\n  \"alert_kinds\": [")?;
    write_names(out, AlertKind::ALL.iter().map(|k| k.as_str()))?;
    out.write_str("],\n  \"stages\": [")?;
    write_names(out, AlertStage::ALL.iter().map(|s| s.as_str()))?;
    out.write_str("],\n  \"settings\": {\n")?;
    for s in NUMERIC_SETTINGS {
        writeln!(
            out,
            "    \"{}\": {{ \"min\": {}, \"max\": {}, \"default\": {}, \"unit\": \"{}\", \"step\": {} }},",
            s.name, s.min, s.max, s.default, s.unit, s.step
        )?;
    }
    writeln!(out, "    \"sound\": {{ \"default\": {SOUND_DEFAULT} }},")?;
    out.write_str("    \"units\": { \"choices\": [")?;
    write_names(out, DisplayUnits::ALL.iter().map(|u| u.as_str()))?;
    let units = DisplayUnits::default().as_str();
    writeln!(out, "], \"default\": \"{units}\" }},")?;
    out.write_str("    \"theme\": { \"choices\": [")?;
    write_names(out, Theme::ALL.iter().map(|t| t.as_str()))?;
    let theme = Theme::default().as_str();
    write!(out, "], \"default\": \"{theme}\" }}\n  }}\n}}\n")
}

fn write_names<'a>(out: &mut impl fmt::Write, names: impl Iterator<Item = &'a str>) -> fmt::Result {
    for (i, name) in names.enumerate() {
        if i > 0 {
            out.write_str(", ")?;
        }
        write!(out, "\"{name}\"")?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_refuse_what_lies_outside_and_non_numbers() {
        assert_eq!(WARNING_DISTANCE_M.check(20.0), Ok(20.0));
        assert_eq!(WARNING_DISTANCE_M.check(2000.0), Ok(2000.0));
        for bad in [19.9, 2000.5, f32::NAN, f32::INFINITY, -100.0] {
            let e = WARNING_DISTANCE_M.check(bad).unwrap_err();
            assert_eq!(
                std::format!("{e}"),
                "warning_distance_m must be between 20 and 2000"
            );
        }
        assert!(LEAD_TIME_S.check(1.5).is_err());
        assert!(LEAD_TIME_S.check(30.0).is_ok());
    }

    #[test]
    fn defaults_lie_within_their_ranges_and_feed_the_core() {
        for s in NUMERIC_SETTINGS {
            assert!(s.check(s.default).is_ok(), "{}", s.name);
        }
        assert_eq!(
            super::super::AlertConfig::DEFAULT.warn_distance_m,
            WARNING_DISTANCE_M.default
        );
        assert_eq!(
            super::super::AlertConfig::DEFAULT.lead_time_s,
            LEAD_TIME_S.default
        );
    }

    #[test]
    fn contract_is_json_with_the_kinds_in_priority_order() {
        let mut text = std::string::String::new();
        write_contract_json(&mut text).unwrap();
        let v: serde_json::Value = serde_json::from_str(&text).expect(&text);
        let kinds: std::vec::Vec<&str> = v["alert_kinds"]
            .as_array()
            .unwrap()
            .iter()
            .map(|k| k.as_str().unwrap())
            .collect();
        assert_eq!(kinds.first(), Some(&"WorkerInLane"));
        assert_eq!(kinds.get(1), Some(&"LaneClosedOwn"));
        assert_eq!(kinds.len(), 10);
        assert_eq!(v["stages"][3], "Urgent");
        let d = &v["settings"]["warning_distance_m"];
        assert_eq!(
            (d["min"].as_f64(), d["max"].as_f64()),
            (Some(20.0), Some(2000.0))
        );
        assert_eq!(d["default"].as_f64(), Some(100.0));
        assert_eq!(v["settings"]["lead_time_s"]["step"].as_f64(), Some(0.5));
        assert_eq!(v["settings"]["units"]["choices"][1], "mph");
        assert_eq!(v["settings"]["theme"]["default"], "auto");
        assert_eq!(v["settings"]["sound"]["default"], true);
    }
}
