//! Alert engine: zone states, alert reasons and arbitration, and the HMI output.
//!
//! For each active work zone that concerns the vehicle, the distance to its start
//! ([`crate::distance`]) gives a [`ZoneState`]: approaching, warning, in zone, leaving.
//! The warning distance is `max(warn_distance_m, speed x lead_time_s)` and the
//! approach distance `approach_factor` times that. A state starts at the last fix before
//! its threshold would be passed: the distance is judged as it will be one fix period
//! plus the display latency later ([`AlertConfig::lookahead_m`]), so the warning is never
//! a fix late.
//!
//! Each zone yields alerts (reduced speed, lane closed, overspeed), each with an
//! [`AlertStage`]: information ahead, warning at the warning distance, urgent only when the
//! driver does not comply (still in the closed lane where a lane change no longer fits,
//! or a needed deceleration above the comfortable one). Data problems add stale-data
//! alerts. Road workers (PSMs) in the own lane's path ahead raise the first of all alerts,
//! workers near the road ahead an information. Only one alert is primary (highest stage, then [`AlertKind`] order, then
//! distance); the others are listed. All thresholds live in [`AlertConfig`].

mod engine;
mod hmi;
pub mod settings;

pub use crate::clock::TimeStatus;
pub(crate) use engine::arbitrate;
pub use engine::{decel_needed, zone_alerts, zone_state, Motion, ZoneView, URGENT_RELEASE};
pub use hmi::{Alert, Counters, HmiState, LaneAdvice, LaneInfo, WorkerView};

use core::fmt;

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

use crate::matcher::MatcherConfig;
use crate::time::Duration;

/// Every threshold of the core.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct AlertConfig {
    /// Minimum warning distance, metres ([`settings::WARNING_DISTANCE_M`]).
    pub warn_distance_m: f32,
    /// Lead time: the warning distance grows to speed x this, seconds
    /// ([`settings::LEAD_TIME_S`]).
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
    /// Time from a fix to the driver seeing its state (serial link, Wi-Fi, rendering),
    /// seconds: part of the look-ahead of every threshold.
    pub display_latency_s: f32,
    /// Deceleration a driver finds comfortable, m/s²: needing more to reach the zone limit
    /// by the zone start makes the alert urgent and the speed red.
    pub comfortable_decel_mps2: f32,
    /// Time a lane change takes, seconds: in a closed lane closer to the zone than this
    /// at the current speed (and [`AlertConfig::min_lane_change_m`]), the alert is urgent.
    pub lane_change_time_s: f32,
    /// Least distance a lane change takes, metres.
    pub min_lane_change_m: f32,
    /// During a GNSS outage the position is dead-reckoned along the matched lane for this
    /// long; after it, "position lost".
    pub dead_reckoning: Duration,
    /// A vehicle speed (CAN) older than this is stale.
    pub speed_timeout: Duration,
    /// GNSS time farther than this from the reference clock is unverified.
    pub max_clock_offset: Duration,
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
        warn_distance_m: settings::WARNING_DISTANCE_M.default,
        lead_time_s: settings::LEAD_TIME_S.default,
        approach_factor: 3.0,
        leaving_distance_m: 50.0,
        overspeed_tolerance_mps: 5.0 / 3.6,
        gnss_timeout: Duration::from_millis(1000),
        map_timeout: Duration::from_secs(60),
        zone_timeout: Duration::from_secs(30),
        zone_reach_m: 4.0,
        display_latency_s: 0.1,
        comfortable_decel_mps2: 2.5,
        lane_change_time_s: 5.0,
        min_lane_change_m: 30.0,
        dead_reckoning: Duration::from_secs(5),
        speed_timeout: Duration::from_millis(1000),
        max_clock_offset: Duration::from_secs(10),
        matcher: MatcherConfig::DEFAULT,
    };

    /// Warning distance at `speed_mps` (unknown speed: the configured minimum).
    pub fn warning_distance(&self, speed_mps: Option<f32>) -> f32 {
        let by_time = speed_mps.unwrap_or(0.0) * self.lead_time_s;
        crate::math::finite_or(by_time.max(self.warn_distance_m), self.warn_distance_m)
    }

    /// How far the vehicle travels at `speed_mps` before the next state reaches the driver:
    /// one fix period plus the display latency, metres (0 for an unknown speed).
    pub fn lookahead_m(&self, speed_mps: Option<f32>, fix_period_s: f32) -> f32 {
        let t = fix_period_s.clamp(0.0, 2.0) + self.display_latency_s.clamp(0.0, 1.0);
        crate::math::finite_or(speed_mps.unwrap_or(0.0) * t, 0.0).max(0.0)
    }

    /// Distance a lane change needs at `speed_mps`, metres.
    pub fn lane_change_m(&self, speed_mps: Option<f32>) -> f32 {
        let by_time = speed_mps.unwrap_or(0.0) * self.lane_change_time_s;
        crate::math::finite_or(by_time.max(self.min_lane_change_m), self.min_lane_change_m)
    }
}

/// How strongly an alert calls for the driver: one primary stage drives the colour and
/// the tone of the display.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub enum AlertStage {
    /// Nothing to tell.
    #[default]
    None,
    /// Something lies ahead (amber, no tone).
    Information,
    /// Act now: at the warning distance or lead time (red, one tone).
    Warning,
    /// The driver is not complying (red, the tone repeats until they do).
    Urgent,
}

impl AlertStage {
    /// Every stage, lowest first (the order of `Ord`).
    pub const ALL: [AlertStage; 4] = [
        AlertStage::None,
        AlertStage::Information,
        AlertStage::Warning,
        AlertStage::Urgent,
    ];

    /// The name in the HMI state's JSON (`"stage"`).
    pub const fn as_str(self) -> &'static str {
        match self {
            AlertStage::None => "None",
            AlertStage::Information => "Information",
            AlertStage::Warning => "Warning",
            AlertStage::Urgent => "Urgent",
        }
    }
}

/// Where the position shown comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub enum PositionSource {
    /// A fresh GNSS fix.
    Live,
    /// Dead-reckoned along the matched lane during a GNSS outage.
    Estimated,
    /// No fix, or the outage outlasted the dead-reckoning horizon.
    #[default]
    Lost,
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
    /// A road worker (PSM) stands in the own lane's path ahead: within half the lane width
    /// plus [`crate::worker::IN_PATH_MARGIN_M`] of its centreline, within the approach
    /// distance. First of all: a person in the path is the gravest risk there is.
    WorkerInLane,
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
    /// Road workers ahead near the road (within [`crate::worker::NEAR_ROAD_M`] of a
    /// vehicle lane) but not in the own lane's path (information).
    WorkersNearRoad,
    /// No GNSS fix for longer than the timeout.
    GnssStale,
    /// Work zones are known but no lane map.
    MapMissing,
    /// Neither MAP nor TIM received.
    NoRoadsideData,
}

impl AlertKind {
    /// Every kind, highest priority first (the order of `Ord`, which arbitration uses).
    pub const ALL: [AlertKind; 10] = [
        AlertKind::WorkerInLane,
        AlertKind::LaneClosedOwn,
        AlertKind::Overspeed,
        AlertKind::ReducedSpeedAhead,
        AlertKind::LaneClosedOther,
        AlertKind::WorkZoneAhead,
        AlertKind::WorkersNearRoad,
        AlertKind::GnssStale,
        AlertKind::MapMissing,
        AlertKind::NoRoadsideData,
    ];

    /// The name in the HMI state's JSON (`"kind"`).
    pub const fn as_str(self) -> &'static str {
        match self {
            AlertKind::WorkerInLane => "WorkerInLane",
            AlertKind::LaneClosedOwn => "LaneClosedOwn",
            AlertKind::Overspeed => "Overspeed",
            AlertKind::ReducedSpeedAhead => "ReducedSpeedAhead",
            AlertKind::LaneClosedOther => "LaneClosedOther",
            AlertKind::WorkZoneAhead => "WorkZoneAhead",
            AlertKind::WorkersNearRoad => "WorkersNearRoad",
            AlertKind::GnssStale => "GnssStale",
            AlertKind::MapMissing => "MapMissing",
            AlertKind::NoRoadsideData => "NoRoadsideData",
        }
    }
}

impl fmt::Display for AlertKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            AlertKind::WorkerInLane => "worker in lane ahead",
            AlertKind::WorkersNearRoad => "workers near the road",
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
    fn kinds_and_stages_are_listed_in_their_order() {
        assert!(AlertKind::ALL.windows(2).all(|w| w[0] < w[1]));
        assert!(AlertStage::ALL.windows(2).all(|w| w[0] < w[1]));
    }

    #[cfg(feature = "serde")]
    #[test]
    fn kinds_and_stages_have_their_json_names() {
        for k in AlertKind::ALL {
            assert_eq!(
                serde_json::to_string(&k).unwrap(),
                std::format!("\"{}\"", k.as_str())
            );
        }
        for s in AlertStage::ALL {
            assert_eq!(
                serde_json::to_string(&s).unwrap(),
                std::format!("\"{}\"", s.as_str())
            );
        }
    }

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
