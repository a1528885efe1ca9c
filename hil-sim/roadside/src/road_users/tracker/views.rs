//! Which views a track rests on: the error its recent frames' observations repeat (their
//! floors), so that a better view of the road user re-anchors the track.
//!
//! A road user seen in part (hidden behind another, cut by the border) is placed from what
//! is visible with the class's size prior, and every such frame shares the prior's error:
//! the observation's floor says how much. The filter takes each frame as independent, so
//! after a run of partial views it holds their average as if the shared error had averaged
//! out, and a whole view that follows moves it only part of the way. A view whose floor is
//! under [`BETTER_VIEW_SHARE`] of every recent frame's best floor is a better view: the
//! track's position restarts from it (its velocity kept). A blend, with the track's
//! position covariance raised to the partial views' floor, would keep part of their error,
//! and that error is not drawn afresh from view to view (the same neighbour hides the same
//! side); the filter would then take the rest of the correction over the next frames for
//! motion. The raised covariance gates the better view: it belongs to the track if it lies
//! within the partial views' error.

use crate::ellipse::{worst_sigma, Cov2};

/// An observation whose floor (worst direction) is under this share of the best floor of
/// each of the track's last [`RECENT_FRAMES`] frames is a better view. On the road-user
/// bench any share from 0.3 to 0.7 gives the same tracks: the floors of a partial and a
/// whole view differ by five times or more.
pub(super) const BETTER_VIEW_SHARE: f64 = 0.5;
/// Frames (with observations) a run of worse views must last to re-anchor the track: one
/// partial frame between whole ones barely moves a track, and re-anchoring would throw away
/// what the whole ones built up.
pub(super) const RECENT_FRAMES: usize = 3;

/// The best floor of each of a track's recent frames.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct RecentFloors {
    /// The best floor of each earlier frame, newest first.
    earlier: [Cov2; RECENT_FRAMES],
    /// The best floor of the frame at `now_s` so far.
    now: Cov2,
    now_s: f64,
    /// When the track was last re-anchored: at most once a frame (a second camera's whole
    /// view of the same frame is taken as usual).
    reanchored_s: f64,
}

impl RecentFloors {
    /// A track's first observation, at `time_s`, with `floor`.
    pub(super) fn new(floor: &Cov2, time_s: f64) -> Self {
        Self {
            earlier: [*floor; RECENT_FRAMES],
            now: *floor,
            now_s: time_s,
            reanchored_s: f64::NEG_INFINITY,
        }
    }

    /// Whether an observation with `floor` at `time_s` is a better view: the best floor of
    /// the recent frames (the error the track's position shares with them, which gates the
    /// view) if it is; the track unchanged.
    pub(super) fn better_view(&self, floor: &Cov2, time_s: f64) -> Option<Cov2> {
        if self.reanchored_s == time_s {
            return None;
        }
        let earlier = self.rolled(time_s);
        let best = earlier
            .iter()
            .min_by(|a, b| worst_sigma(a).total_cmp(&worst_sigma(b)))?;
        (worst_sigma(floor) < BETTER_VIEW_SHARE * worst_sigma(best)).then_some(*best)
    }

    /// Records an observation with `floor` at `time_s` (not before the latest), and whether
    /// the track was re-anchored for it.
    pub(super) fn record(&mut self, floor: &Cov2, time_s: f64, reanchored: bool) {
        if time_s > self.now_s {
            self.earlier = self.rolled(time_s);
            self.now = *floor;
            self.now_s = time_s;
        } else if worst_sigma(floor) < worst_sigma(&self.now) {
            self.now = *floor;
        }
        if reanchored {
            self.reanchored_s = time_s;
        }
    }

    /// The earlier frames' floors as seen from `time_s`: the current frame's joins them once
    /// time has moved on.
    fn rolled(&self, time_s: f64) -> [Cov2; RECENT_FRAMES] {
        if time_s <= self.now_s {
            return self.earlier;
        }
        let mut e = self.earlier;
        e.rotate_right(1);
        e[0] = self.now;
        e
    }
}
