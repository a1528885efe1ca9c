//! The state a driver display shows, one per fix.

use heapless::Vec;

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

use super::{AlertKind, AlertStage, PositionSource, TimeStatus, ZoneState};
use crate::capacity::{MAX_ALERTS, MAX_HMI_LANES, MAX_HMI_WORKERS};

/// One alert.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct Alert {
    /// Reason.
    pub kind: AlertKind,
    /// How strongly it calls for the driver.
    pub stage: AlertStage,
    /// Distance to the zone start, metres (negative inside), when zone related; to the
    /// nearest worker concerned along the own lane for the worker alerts.
    pub distance_m: Option<f32>,
    /// Zone speed limit, m/s, when known.
    pub limit_mps: Option<f32>,
}

/// Which way to change lane.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub enum LaneAdvice {
    /// No change needed (or not known).
    #[default]
    None,
    /// Move to the lane on the left.
    MoveLeft,
    /// Move to the lane on the right.
    MoveRight,
}

impl core::fmt::Display for LaneAdvice {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            LaneAdvice::None => "none",
            LaneAdvice::MoveLeft => "move left",
            LaneAdvice::MoveRight => "move right",
        })
    }
}

/// The matched lane as shown (only when the confidence is high enough).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct LaneInfo {
    /// Lane model id.
    pub map: u32,
    /// Lane id.
    pub lane: u8,
}

/// A road worker to draw, placed on the own lane (see [`crate::worker::place`]).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct WorkerView {
    /// The PSM's temporary id, big-endian.
    pub id: u32,
    /// Metres along the own lane from the vehicle to the worker, in the direction of
    /// travel (negative behind).
    pub distance_m: f32,
    /// Metres from the own lane's centreline, positive to the right in the direction of
    /// travel (as [`HmiState::road_lanes`] runs left to right).
    pub lateral_m: f32,
    /// In the own lane's path: within half its width plus
    /// [`crate::worker::IN_PATH_MARGIN_M`] of its centreline (ahead or behind).
    pub in_own_lane_path: bool,
    /// Speed, m/s, when the PSM gave it.
    pub speed_mps: Option<f32>,
    /// Heading, degrees clockwise from north, when the PSM gave it.
    pub heading_deg: Option<f32>,
    /// Milliseconds since the worker's last PSM.
    pub age_ms: u16,
    /// The PSM came with a verified signature.
    pub verified: bool,
}

/// Counters for the HMI's diagnostics page.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct Counters {
    /// Fixes processed.
    pub fixes: u32,
    /// Fixes that matched no lane.
    pub off_map: u32,
    /// Lane switches of the matcher.
    pub lane_switches: u32,
    /// Fixes the lane filter rejected as outliers (innovation gate: multipath jumps).
    pub lane_outliers: u32,
    /// Lane models stored or replaced.
    pub maps_updated: u32,
    /// Lane models that failed to convert.
    pub maps_rejected: u32,
    /// Work zones stored or replaced.
    pub zones_updated: u32,
    /// Work zones that failed to convert.
    pub zones_rejected: u32,
    /// Work zones cancelled by their sender.
    pub zones_cancelled: u32,
    /// Lane models and work zones dropped for age or end of validity.
    pub expired: u32,
    /// Messages other than MAP and TIM handed to [`crate::Obu::on_frame`].
    pub other_messages: u32,
    /// Fixes whose date was corrected for the GNSS week rollover.
    pub rollover_fixes: u32,
    /// Fixes whose time disagreed with the reference clock.
    pub unverified_time_fixes: u32,
}

impl Counters {
    /// All zero.
    pub const ZERO: Counters = Counters {
        fixes: 0,
        off_map: 0,
        lane_switches: 0,
        lane_outliers: 0,
        maps_updated: 0,
        maps_rejected: 0,
        zones_updated: 0,
        zones_rejected: 0,
        zones_cancelled: 0,
        expired: 0,
        other_messages: 0,
        rollover_fixes: 0,
        unverified_time_fixes: 0,
    };
}

/// Everything the driver display shows.
#[derive(Debug, Clone, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct HmiState {
    /// Time of this state on the caller's clock, milliseconds.
    pub time_ms: u64,
    /// Vehicle speed, m/s: `None` when its source is stale (no fresh fix or CAN speed).
    pub speed_mps: Option<f32>,
    /// Speed limit in force where the vehicle is, m/s.
    pub speed_limit_mps: Option<f32>,
    /// True when the limit in force is a work-zone reduction.
    pub reduced_limit: bool,
    /// A lower work-zone limit ahead, m/s (shown with [`HmiState::limit_ahead_m`]).
    pub limit_ahead_mps: Option<f32>,
    /// Metres to where that limit starts.
    pub limit_ahead_m: Option<f32>,
    /// Deceleration needed to reach the limit ahead by where it starts, m/s² (when above it).
    pub decel_needed_mps2: Option<f32>,
    /// The speed calls for the driver (show it red, unless another element already is):
    /// over the limit in force plus the tolerance, or a needed deceleration above the
    /// comfortable one.
    pub speed_alarm: bool,
    /// Stage of the primary alert: the display's colour and tone follow it.
    pub stage: AlertStage,
    /// State relative to the nearest concerning zone.
    pub zone_state: ZoneState,
    /// Distance to that zone's start, metres (negative inside).
    pub distance_m: Option<f32>,
    /// The alert to show.
    pub primary: Option<Alert>,
    /// Further alerts, by priority.
    pub others: Vec<Alert, MAX_ALERTS>,
    /// The matched lane, when known with enough confidence.
    pub lane: Option<LaneInfo>,
    /// Confidence of the lane match, percent (0 off-map).
    pub lane_confidence: u8,
    /// Closed lanes of the nearest closure on the current map.
    pub closed_lanes: Vec<u8, MAX_HMI_LANES>,
    /// The road at the vehicle: ids of the matched lane and of the vehicle lanes beside it
    /// running the same way, left to right in the direction of travel (empty off map).
    pub road_lanes: Vec<u8, MAX_HMI_LANES>,
    /// Lane change advice.
    pub advice: LaneAdvice,
    /// True while fixes arrive in time.
    pub gnss_ok: bool,
    /// Where the position (distance, lane, zone state) comes from: a fix, dead reckoning
    /// during an outage, or nowhere.
    pub position: PositionSource,
    /// Whether the time zones are judged on can be believed.
    pub time_status: TimeStatus,
    /// Where the accuracy of the fix in use comes from (GST, UBX hAcc, HDOP, none: the
    /// lane filter's default).
    #[cfg_attr(feature = "serde", serde(default))]
    pub accuracy_source: crate::fix::AccuracySource,
    /// True when a MAP or TIM is stored.
    pub roadside_data: bool,
    /// Lane models stored.
    pub maps: u8,
    /// Work zones stored.
    pub zones: u8,
    /// Lane models and work zones stored that came without a verified signature (possible
    /// only when signatures are not required): the display marks them "unverified". Zero
    /// with `zones > 0` means every zone shown was verified.
    pub unverified: u8,
    /// Counters.
    pub counters: Counters,
    /// Road workers on the matched lane's map, nearest first (at most
    /// [`MAX_HMI_WORKERS`]); empty without a lane match.
    pub workers: Vec<WorkerView, MAX_HMI_WORKERS>,
}
