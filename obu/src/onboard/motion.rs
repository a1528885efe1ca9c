//! The vehicle's motion between fixes: dead reckoning through a GNSS outage, the speed
//! shown, and where the position comes from.

use super::Obu;
use crate::alert::PositionSource;
use crate::time::Instant;

/// Distance travelled since the last fix, integrated piecewise over the speeds known
/// (the fix's, then each CAN speed as it comes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Travel {
    /// Up to when `metres` counts.
    at: Instant,
    /// Speed since then, m/s.
    speed_mps: f32,
    /// Metres from the last fix to `at`.
    metres: f32,
}

impl Travel {
    /// Nothing travelled, no speed.
    pub(super) const ZERO: Travel = Travel {
        at: Instant::ZERO,
        speed_mps: 0.0,
        metres: 0.0,
    };

    /// From a fix at `now` moving at `speed_mps` (unknown: standing).
    pub(super) fn start(now: Instant, speed_mps: Option<f32>) -> Self {
        Travel {
            at: now,
            speed_mps: speed_mps.unwrap_or(0.0),
            metres: 0.0,
        }
    }

    /// A new speed from `now` on.
    pub(super) fn set_speed(&mut self, now: Instant, speed_mps: f32) {
        self.metres = self.metres_at(now);
        self.at = self.at.max(now);
        self.speed_mps = speed_mps;
    }

    /// Metres from the last fix to `now`.
    pub(super) fn metres_at(&self, now: Instant) -> f32 {
        let dt = now.saturating_since(self.at).millis() as f32 / 1000.0;
        self.metres + self.speed_mps * dt
    }

    /// The speed integrated, m/s.
    pub(super) fn speed(&self) -> f32 {
        self.speed_mps
    }
}

impl Obu {
    /// True when the last fix is younger than the GNSS timeout.
    pub(super) fn gnss_fresh(&self, now: Instant) -> bool {
        self.last_fix
            .is_some_and(|(t, _)| now.saturating_since(t) <= self.config.gnss_timeout)
    }

    /// When dead reckoning from the last fix ends.
    fn horizon(&self) -> Option<Instant> {
        let (t, _) = self.last_fix?;
        Some(t + self.config.gnss_timeout + self.config.dead_reckoning)
    }

    /// Where the position at `now` comes from.
    pub(super) fn position_source(&self, now: Instant) -> PositionSource {
        if self.gnss_fresh(now) {
            PositionSource::Live
        } else if self.horizon().is_some_and(|h| now <= h) {
            PositionSource::Estimated
        } else {
            PositionSource::Lost
        }
    }

    /// Metres travelled along the lane since the last fix, up to `now` or the
    /// dead-reckoning horizon, whichever comes first.
    pub(super) fn travelled_m(&self, now: Instant) -> f32 {
        let until = self.horizon().map_or(now, |h| now.min(h));
        let m = self.travel.metres_at(until);
        if m.is_finite() {
            m.max(0.0)
        } else {
            0.0
        }
    }

    /// The CAN speed while fresh.
    pub(super) fn fresh_vehicle_speed(&self, now: Instant) -> Option<f32> {
        let (t, v) = self.vehicle_speed?;
        (now.saturating_since(t) <= self.config.speed_timeout).then_some(v)
    }

    /// The speed shown at `now`: the fix's while GNSS is live (a fresh CAN speed already
    /// replaced it), else the CAN speed while fresh; `None` when its source is stale.
    pub(super) fn shown_speed(&self, now: Instant, position: PositionSource) -> Option<f32> {
        match position {
            PositionSource::Live => self.last_fix.and_then(|(_, f)| f.speed()),
            _ => self.fresh_vehicle_speed(now),
        }
    }

    /// The speed the thresholds use: the shown one, else (dead reckoning on the last GNSS
    /// speed) the speed being integrated.
    pub(super) fn threshold_speed(&self, now: Instant, position: PositionSource) -> Option<f32> {
        self.shown_speed(now, position).or(match position {
            PositionSource::Live => None,
            _ => self.last_fix.map(|_| self.travel.speed()),
        })
    }
}
