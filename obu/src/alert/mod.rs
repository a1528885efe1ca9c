//! Alert engine: zone states, alert reasons and arbitration, and the HMI output.
//!
//! For each active work zone that concerns the vehicle, the distance to its start
//! ([`crate::distance`]) gives a [`ZoneState`]: approaching, warning, in zone, leaving.
//! The warning distance is `max(warn_distance_m, speed x lead_time_s)` and the
//! approach distance `approach_factor` times that. Each zone yields alerts (reduced
//! speed, lane closed, overspeed); data problems add stale-data alerts. Only the
//! highest-priority alert is primary ([`AlertKind`] order, then distance); the others
//! are listed. All thresholds live in [`AlertConfig`].

mod engine;
mod hmi;

pub(crate) use engine::arbitrate;
pub use engine::{zone_alerts, zone_state, ZoneView};
pub use hmi::{Alert, Counters, HmiState, LaneAdvice, LaneInfo};

use core::fmt;

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

use crate::matcher::MatcherConfig;
use crate::time::Duration;

/// Every threshold of the core.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct AlertConfig {
    /// Minimum warning distance, metres (100 m: the field test's figure at 40 km/h).
    pub warn_distance_m: f32,
    /// Lead time: the warning distance grows to speed x this, seconds.
    pub lead_time_s: f32,
    /// Approaching starts at this multiple of the warning distance.
    pub approach_factor: f32,
    /// After the zone end the state stays "leaving" for this many metres.
    pub leaving_distance_m: f32,
    /// Overspeed when speed exceeds the zone limit by more than this, m/s.
    pub overspeed_tolerance_mps: f32,
    /// Without a fix for this long the GNSS is stale.
    pub gnss_timeout: Duration,
    /// A MAP not heard for this long is dropped.
    pub map_timeout: Duration,
    /// A TIM not heard for this long is dropped.
    pub zone_timeout: Duration,
    /// Lateral room beyond half the zone width for geometric distance routes, metres.
    pub zone_reach_m: f32,
    /// Lane matcher thresholds.
    pub matcher: MatcherConfig,
}

impl Default for AlertConfig {
    fn default() -> Self {
        AlertConfig::DEFAULT
    }
}

impl AlertConfig {
    /// The documented defaults (100 m, 9 s, 1 s GNSS timeout, ...).
    pub const DEFAULT: AlertConfig = AlertConfig {
        warn_distance_m: 100.0,
        lead_time_s: 9.0,
        approach_factor: 3.0,
        leaving_distance_m: 50.0,
        overspeed_tolerance_mps: 5.0 / 3.6,
        gnss_timeout: Duration::from_millis(1000),
        map_timeout: Duration::from_secs(60),
        zone_timeout: Duration::from_secs(30),
        zone_reach_m: 4.0,
        matcher: MatcherConfig::DEFAULT,
    };

    /// Warning distance at `speed_mps` (unknown speed: the configured minimum).
    pub fn warning_distance(&self, speed_mps: Option<f32>) -> f32 {
        let by_time = speed_mps.unwrap_or(0.0) * self.lead_time_s;
        crate::math::finite_or(by_time.max(self.warn_distance_m), self.warn_distance_m)
    }
}

/// Where the vehicle is relative to the nearest work zone.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub enum ZoneState {
    /// No zone concerns the vehicle.
    #[default]
    None,
    /// A zone lies ahead within the approach distance.
    Approaching,
    /// A zone lies ahead within the warning distance.
    Warning,
    /// Inside a zone.
    InZone,
    /// Just past a zone's end.
    Leaving,
}

impl fmt::Display for ZoneState {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ZoneState::None => "none",
            ZoneState::Approaching => "approaching",
            ZoneState::Warning => "warning",
            ZoneState::InZone => "in zone",
            ZoneState::Leaving => "leaving",
        })
    }
}

/// Alert reasons, highest priority first.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub enum AlertKind {
    /// The vehicle's own lane is closed ahead: change lane. First: cones in the lane
    /// ahead are a collision risk at any speed; the overspeed alert follows in `others`.
    LaneClosedOwn,
    /// Faster than the zone limit plus tolerance (warning or in zone).
    Overspeed,
    /// A reduced speed limit ahead.
    ReducedSpeedAhead,
    /// Another lane of the road is closed ahead.
    LaneClosedOther,
    /// A work zone without limit or closure ahead.
    WorkZoneAhead,
    /// No GNSS fix for longer than the timeout.
    GnssStale,
    /// Work zones are known but no lane map.
    MapMissing,
    /// Neither MAP nor TIM received.
    NoRoadsideData,
}

impl fmt::Display for AlertKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            AlertKind::Overspeed => "overspeed",
            AlertKind::LaneClosedOwn => "lane closed ahead: change lane",
            AlertKind::ReducedSpeedAhead => "reduced speed ahead",
            AlertKind::LaneClosedOther => "lane closed ahead",
            AlertKind::WorkZoneAhead => "work zone ahead",
            AlertKind::GnssStale => "GNSS data stale",
            AlertKind::MapMissing => "lane map missing",
            AlertKind::NoRoadsideData => "no roadside data",
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn warning_distance_scales_with_speed() {
        let c = AlertConfig::default();
        assert_eq!(c.warning_distance(None), 100.0);
        assert!((c.warning_distance(Some(40.0 / 3.6)) - 100.0).abs() < 1e-3);
        assert!((c.warning_distance(Some(30.0)) - 270.0).abs() < 1e-3);
        assert_eq!(c.warning_distance(Some(f32::INFINITY)), 100.0);
        assert!(AlertKind::Overspeed < AlertKind::GnssStale);
        assert_eq!(ZoneState::InZone.to_string_buf().as_str(), "in zone");
    }

    trait ToBuf {
        fn to_string_buf(&self) -> heapless::String<32>;
    }
    impl<T: fmt::Display> ToBuf for T {
        fn to_string_buf(&self) -> heapless::String<32> {
            let mut s = heapless::String::new();
            let _ = fmt::write(&mut s, format_args!("{self}"));
            s
        }
    }
}
