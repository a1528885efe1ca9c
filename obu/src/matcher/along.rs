//! Along-track filter: the car's station on its lane and its speed (Kalman), predicted with
//! the receiver's (or the vehicle's) speed, updated with each fix's station weighted by its
//! accuracy; an innovation gate rejects fixes that jump along the road (multipath) as the
//! lane filter's gate does across it.

use super::kalman;
use crate::lane::{LaneId, MapId};
use crate::time::Instant;

/// Variance of a speed not measured, (m/s)²: 40 m/s at one sigma.
const UNKNOWN_SPEED_VAR: f32 = 1600.0;

/// The filter's state on one lane.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct AlongTrack {
    /// The lane the station is on.
    key: Option<(MapId, LaneId)>,
    /// Station, metres, and speed along the lane, m/s.
    s: f32,
    v: f32,
    /// Covariance (pss, psv, pvv).
    p: [f32; 3],
    last: Option<Instant>,
    in_row: u8,
}

/// What one fix says along the road.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct AlongFix {
    /// The lane of the fix and its station on it.
    pub key: (MapId, LaneId),
    pub station: f32,
    /// The station on the filter's previous lane for this same fix, when that lane is
    /// still near (a lane change carries the filtered offset over).
    pub station_on_previous: Option<f32>,
    /// Ground speed, m/s.
    pub speed: Option<f32>,
    /// The fix's error (1 sigma), metres.
    pub sigma: f32,
}

/// Settings (from [`super::FilterConfig`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct AlongConfig {
    pub accel_mps2: f32,
    pub speed_sigma_mps: f32,
    pub gate_sigma: f32,
    pub restart_after: u8,
    pub max_gap_ms: u32,
    /// The smallest fix error assumed, metres.
    pub min_sigma_m: f32,
}

impl AlongTrack {
    /// No track yet.
    pub const fn new() -> Self {
        AlongTrack {
            key: None,
            s: 0.0,
            v: 0.0,
            p: [0.0; 3],
            last: None,
            in_row: 0,
        }
    }

    /// The lane the track is on.
    pub fn key(&self) -> Option<(MapId, LaneId)> {
        self.key
    }

    /// Forgets the track.
    pub fn reset(&mut self) {
        *self = AlongTrack::new();
    }

    /// One fix: the filtered station, or `None` when the fix jumped along the road (an
    /// outlier; the caller keeps the track's prediction).
    pub fn update(&mut self, now: Instant, f: &AlongFix, cfg: &AlongConfig) -> Option<f32> {
        let gap = self.last.map(|t| now.saturating_since(t).millis());
        self.last = Some(now);
        let sigma = f.sigma.max(cfg.min_sigma_m);
        let r = sigma * sigma;
        let carried = match (self.key, f.station_on_previous) {
            (Some(k), _) if k == f.key => true,
            (Some(_), Some(prev)) => {
                // Same place on the new lane: keep the filtered offset from the fix.
                self.s += f.station - prev;
                self.key = Some(f.key);
                true
            }
            _ => false,
        };
        let finite = self.s.is_finite() && self.v.is_finite() && self.p[0].is_finite();
        let fresh = !carried || !finite || gap.is_none_or(|g| g > u64::from(cfg.max_gap_ms));
        if fresh {
            self.start(f, r);
            return Some(self.s);
        }
        let dt = gap.unwrap_or(0) as f32 / 1000.0;
        kalman::predict(&mut self.s, &mut self.v, &mut self.p, dt, cfg.accel_mps2);
        if let Some(v) = f.speed {
            let var = cfg.speed_sigma_mps * cfg.speed_sigma_mps;
            kalman::update(&mut self.s, &mut self.v, &mut self.p, 1, v, var);
        }
        let nu = f.station - self.s;
        if nu * nu > cfg.gate_sigma * cfg.gate_sigma * (self.p[0] + r) {
            self.in_row = self.in_row.saturating_add(1);
            if self.in_row < cfg.restart_after {
                return None;
            }
            self.start(f, r);
            return Some(self.s);
        }
        self.in_row = 0;
        kalman::update(&mut self.s, &mut self.v, &mut self.p, 0, f.station, r);
        Some(self.s)
    }

    fn start(&mut self, f: &AlongFix, r: f32) {
        // Without a measured speed the first stations must teach it: any road speed.
        let pvv = if f.speed.is_some() {
            4.0
        } else {
            UNKNOWN_SPEED_VAR
        };
        *self = AlongTrack {
            key: Some(f.key),
            s: f.station,
            v: f.speed.unwrap_or(0.0),
            p: [r, 0.0, pvv],
            last: self.last,
            in_row: 0,
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const CFG: AlongConfig = AlongConfig {
        accel_mps2: 2.0,
        speed_sigma_mps: 0.2,
        gate_sigma: 4.0,
        restart_after: 10,
        max_gap_ms: 2_000,
        min_sigma_m: 0.25,
    };

    fn fix(lane: u8, station: f32, previous: Option<f32>) -> AlongFix {
        AlongFix {
            key: (MapId(1), LaneId(lane)),
            station,
            station_on_previous: previous,
            speed: Some(20.0),
            sigma: 0.5,
        }
    }

    #[test]
    fn a_jump_along_the_road_is_rejected_and_a_lane_change_keeps_the_offset() {
        let mut a = AlongTrack::new();
        for k in 0..20u64 {
            let s = a.update(
                Instant::from_millis(k * 100),
                &fix(2, 2.0 * k as f32, None),
                &CFG,
            );
            assert!(
                s.is_some_and(|s| (s - 2.0 * k as f32).abs() < 0.2),
                "{k}: {s:?}"
            );
        }
        // 8 m ahead of where the car can be: an outlier.
        assert_eq!(
            a.update(Instant::from_millis(2_000), &fix(2, 48.0, None), &CFG),
            None
        );
        // Back on track; then onto lane 3, whose stations run 5 m ahead of lane 2's.
        let s = a.update(Instant::from_millis(2_100), &fix(2, 42.0, None), &CFG);
        assert!(s.is_some_and(|s| (s - 42.0).abs() < 0.3), "{s:?}");
        let s = a.update(Instant::from_millis(2_200), &fix(3, 49.0, Some(44.0)), &CFG);
        assert!(s.is_some_and(|s| (s - 49.0).abs() < 0.3), "{s:?}");
        assert_eq!(a.key(), Some((MapId(1), LaneId(3))));
    }
}
