//! The lane filter's settings and what it takes of each candidate lane: shared by the
//! filter and its belief.

use crate::lane::LaneId;

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

/// Lane filter settings.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct FilterConfig {
    /// Probability (percent) the most probable lane needs before it is shown.
    pub show_percent: u8,
    /// Lateral acceleration the track allows (process noise), m/s².
    pub lateral_accel_mps2: f32,
    /// Error of the receiver's course, degrees (1 sigma): the lateral rate it implies.
    pub course_sigma_deg: f32,
    /// Weight of one fix's evidence (0..1): fixes' errors are correlated over seconds.
    pub evidence_weight: f32,
    /// Probability per second of a lane change with no lateral motion seen.
    pub change_per_s: f32,
    /// Innovation gate, sigmas: a fix farther from the track is an outlier.
    pub gate_sigma: f32,
    /// This many outliers in a row restart the track at the fix.
    pub restart_after: u8,
    /// Transition rate per lateral speed towards a neighbour: lane widths per second of
    /// lateral motion, times this, is the rate of moving belief there.
    pub rate_gain: f32,
    /// Probability per second of leaving the mapped road.
    pub leave_per_s: f32,
    /// Probability per second of coming back onto it.
    pub return_per_s: f32,
    /// Width over which an off-road position is spread, metres (its density is 1/width).
    pub off_road_width_m: f32,
    /// A gap between fixes longer than this starts the filter over, milliseconds.
    pub max_gap_ms: u32,
    /// A fix this far beyond the edge of its nearest lane, or nearer, keeps the road even
    /// when the belief leans off it, metres.
    pub keep_road_m: f32,
    /// Along the road: acceleration the station track allows (process noise), m/s².
    pub along_accel_mps2: f32,
    /// Along the road: error of the speed (Doppler or CAN), m/s (1 sigma).
    pub speed_sigma_mps: f32,
    /// Time constant of the receiver's wandering bias (first-order Gauss-Markov), seconds:
    /// how slowly the correlated part of the fix error forgets where it was.
    pub bias_time_s: f32,
    /// How far a car keeping its lane strays from the centre, metres (1 sigma).
    pub lane_keep_m: f32,
}

impl FilterConfig {
    /// The defaults, tuned on the drive table (`cargo bench -p obu --bench drive_table`).
    pub const DEFAULT: FilterConfig = FilterConfig {
        show_percent: 80,
        lateral_accel_mps2: 1.0,
        course_sigma_deg: 3.0,
        evidence_weight: 0.5,
        change_per_s: 0.002,
        gate_sigma: 4.0,
        restart_after: 10,
        rate_gain: 2.0,
        leave_per_s: 0.02,
        return_per_s: 1.0,
        off_road_width_m: 12.0,
        max_gap_ms: 2_000,
        keep_road_m: 5.0,
        along_accel_mps2: 2.0,
        speed_sigma_mps: 0.2,
        bias_time_s: 60.0,
        lane_keep_m: 0.3,
    };
}

impl Default for FilterConfig {
    fn default() -> Self {
        FilterConfig::DEFAULT
    }
}

/// One candidate lane of a fix, as the filter needs it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Candidate {
    /// The lane.
    pub lane: LaneId,
    /// The fix's offset from the lane's centreline, metres, positive to the left.
    pub lateral: f32,
    /// Lane width there, metres.
    pub width: f32,
    /// Bearing of the lane there in its direction of travel, degrees.
    pub bearing_deg: f32,
}
