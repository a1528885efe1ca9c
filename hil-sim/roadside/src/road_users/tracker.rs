//! Multi-object tracker for road users localized by a roadside camera.
//!
//! Each track is a Kalman filter with state `[x, y, vx, vy]` (metres and m/s in the local
//! road frame, x = east, y = north), constant velocity with discrete white-noise
//! acceleration, and a position measurement with the observation's covariance `R` (a box is
//! known better across the camera's line of sight than along it); a person's track runs a
//! standing model beside the walking one and is their weighted mixture (`modes`). A
//! better view after partial ones restarts the track's position (`views`). Observations are
//! associated to tracks of their own class by Mahalanobis distance of the innovation (gated
//! with a margin for a road user that starts or turns: the observation's worst-direction
//! error in every direction, or for a vehicle along the road only; and never beyond a jump a
//! road user cannot make between frames), greedily by increasing distance, one observation
//! per track; a track not seen for `max_coast_s` ends rather than drift onto a neighbour,
//! one last seen cut by the image border is not reported while unseen (it left the view),
//! and a young one is not reported while unseen (its velocity rests on a few boxes).
//! Reported accuracies come from the filter covariance, never better than the error its
//! observations repeat from frame to frame (the calibration's, the size prior's share, a
//! cut end), as an error ellipse for J2735 PSM accuracy fields. Each track also learns its
//! road user's size from its observations ([`super::size`]) and tells it to the next
//! frame's fits.
use super::class::RoadUserClass;
use super::size::{Lent, SizeBelief, SizeEvidence, SizeHints, FADE_PER_FRAME, MIN_FRAMES};
use crate::ellipse::{
    circle, floored, floored_by, is_covariance, symmetric, variance_along, with_axes, worst_sigma,
    Cov2, ErrorEllipse,
};
use kalman::{position_block, set_position_block, M4};
use modes::Modes;
use std::fmt;
use views::RecentFloors;

/// Class groups: how fast a track's road user may move and turn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Group {
    People,
    TwoWheelers,
    Vehicles,
}

impl Group {
    fn of(class: RoadUserClass) -> Self {
        match class {
            RoadUserClass::Pedestrian => Self::People,
            RoadUserClass::Cyclist | RoadUserClass::Motorcycle => Self::TwoWheelers,
            _ => Self::Vehicles,
        }
    }
    /// Prior 1-sigma of each velocity component for a newborn track (m/s); a vehicle's
    /// along the road where its observation gives the road's direction
    /// ([`NEWBORN_ACROSS_ROAD_MPS`] across it).
    fn prior_speed_sigma(self) -> f64 {
        match self {
            Self::People => 3.0,
            Self::TwoWheelers => 10.0,
            Self::Vehicles => 15.0,
        }
    }
}

/// Tracker settings. `Default` gives values suited to a 10-30 fps camera.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackerSettings {
    /// Gate, as a Mahalanobis distance (dimensionless, in sigmas of the
    /// innovation covariance `S = H P H' + R`), not metres despite the name.
    /// Default 4.0: with 2 degrees of freedom a 3-sigma gate misses 1.1 % of
    /// true pairs (at 10 fps one miss per track every ~9 s, each spawning a
    /// duplicate); 4 sigma misses 0.03 %, while people 1 m apart stay ~8 sigma
    /// apart once tracks have converged.
    /// Must be finite, in (0, 100].
    pub gate_m: f64,
    /// Updates (hits) a track needs before it is reported. Default 3: one or
    /// two spurious detections never reach the broadcast. Must be >= 1.
    pub confirm_hits: u32,
    /// A track not observed for longer than this (seconds) is dropped.
    /// Default 0.5 s: bridges a short occlusion; a road user hidden longer ends its track
    /// (dead-reckoned for longer, a track drifts off its road user and onto a neighbour).
    /// Must be finite, in (0, 60].
    pub max_coast_s: f64,
    /// White-acceleration process noise sigma (m/s^2) for vehicles and
    /// two-wheelers. Default 2.0: ordinary urban accelerating and braking.
    /// Must be finite, in (0, 100].
    pub accel_sigma_mps2: f64,
    /// White-acceleration process noise sigma (m/s^2) for people.
    /// Default 0.6: people walk at nearly constant velocity, and turn. 1.0 lets a 0.1 m
    /// camera noise leak ~0.1 m/s (1 sigma) into the speed of a steady walker; 0.5 lags a
    /// worker turning back at the end of a pace by 10-30 cm while reporting 3-5 cm (the
    /// road-user bench's 95 % circle then holds under 95 % of track positions on its own
    /// install); 0.6 follows the turn and keeps a steady walker's speed within 0.2 m/s.
    /// Must be finite, in (0, 100].
    pub person_accel_sigma_mps2: f64,
    /// A confirmed track is reported only while its position is known this well (1-sigma
    /// along its worst direction, metres). Default 0.4: a track born of partial views, or
    /// coasting, is kept but not reported until its accuracy stands for its position (a
    /// PSM of it would otherwise stand metres from its worker). Must be finite, in (0, 100].
    pub max_report_sigma_m: f64,
    /// A track not seen in the frame is reported only once it has taken this many
    /// observations. Default 10 (a second at 10 fps): a young track's velocity rests on a
    /// few boxes, and one wrong box can make it metres a second off; dead-reckoned on it, the
    /// track leaves its road user within a few frames while its accuracy still looks good.
    /// A settled track bridges a short occlusion. Any value (0: every track coasts).
    pub min_hits_to_coast: u32,
}

impl Default for TrackerSettings {
    fn default() -> Self {
        Self {
            gate_m: 4.0,
            confirm_hits: 3,
            max_coast_s: 0.5,
            accel_sigma_mps2: 2.0,
            person_accel_sigma_mps2: 0.6,
            max_report_sigma_m: 0.4,
            min_hits_to_coast: 10,
        }
    }
}

/// One localized road user in one frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Observation {
    /// Detected class.
    pub class: RoadUserClass,
    /// Position `[east, north]` in metres in the local road frame.
    pub position: [f64; 2],
    /// Covariance of the position (east, north), m².
    pub covariance_m2: Cov2,
    /// The part of the covariance that does not average out over frames, m²: the
    /// calibration's, and a size the view does not measure, taken from the same prior in
    /// every frame alike (a side the image border hides most of all), so the same error
    /// repeats. A track's accuracy is never reported better than its latest observation's
    /// floor along either axis of its ellipse.
    pub floor_m2: Cov2,
    /// What the frame's mask says of the road user's size (none for one cut by the image
    /// border), added to its track's size belief ([`super::size`]).
    pub size: Option<SizeEvidence>,
    /// Cut by the image border: a road user last seen there and then not at all has left
    /// the view, so its track is not reported while unseen (one hidden behind another road
    /// user is).
    pub at_border: bool,
    /// The road's direction at the road user (east/north; its camera's, for a camera
    /// looking along a straight road), when known: a vehicle moves along it, so a newborn
    /// vehicle track's velocity is not believed to reach across it
    /// ([`NEWBORN_ACROSS_ROAD_MPS`]) and a vehicle is gated across it with its box's own
    /// error. A direction that is not finite or has no length counts as unknown.
    pub road_axis: Option<[f64; 2]>,
}

/// A tracked road user as reported.
#[derive(Debug, Clone, PartialEq)]
pub struct Track {
    /// Stable while the track lives; not reused until the u32 counter wraps,
    /// and then ids still in use are skipped.
    pub id: u32,
    /// The class seen most often on this track (ties: earlier in `ALL`).
    pub class: RoadUserClass,
    /// Filtered position `[east, north]`, metres.
    pub position: [f64; 2],
    /// Filtered velocity `[east, north]`, m/s.
    pub velocity: [f64; 2],
    /// Speed, m/s.
    pub speed_mps: f64,
    /// Degrees clockwise from north in [0, 360); `None` while the speed is
    /// below twice its sigma (direction not meaningful).
    pub heading_deg: Option<f64>,
    /// 1-sigma along the worst direction: the semi-major axis of `position_ellipse`.
    pub position_sigma_m: f64,
    /// The position's 1-sigma error ellipse: the filter's covariance, each axis never
    /// better than the latest observation's floor ([`Observation::floor_m2`]) along it.
    pub position_ellipse: ErrorEllipse,
    /// 1-sigma of the speed (first-order propagation; at zero speed the
    /// square root of the larger velocity-covariance eigenvalue).
    pub speed_sigma_mps: f64,
    /// 1-sigma of the heading (first-order propagation), `None` with heading.
    pub heading_sigma_deg: Option<f64>,
    /// Time of the first observation, seconds.
    pub first_seen_s: f64,
    /// Time of the latest observation, seconds.
    pub last_seen_s: f64,
    /// Number of observations taken by this track (saturating).
    pub hits: u32,
}

/// Why the tracker refused settings or a frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TrackerError {
    /// A setting is out of its documented range; names the field.
    BadSettings(&'static str),
    /// Frame time earlier than the previous one; the tracker is unchanged.
    TimeWentBack {
        /// Previous frame time, seconds.
        last_s: f64,
        /// Offending frame time, seconds.
        now_s: f64,
    },
    /// Frame time NaN or infinite; the tracker is unchanged.
    NonFiniteTime,
}

impl Observation {
    /// 1-sigma of the position along its worst direction, metres.
    pub fn sigma_m(&self) -> f64 {
        worst_sigma(&self.covariance_m2)
    }
}

impl fmt::Display for TrackerError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::BadSettings(field) => write!(f, "bad tracker setting: {field}"),
            Self::TimeWentBack { last_s, now_s } => {
                write!(f, "frame time went back from {last_s} s to {now_s} s")
            }
            Self::NonFiniteTime => write!(f, "frame time is not finite"),
        }
    }
}

impl std::error::Error for TrackerError {}

/// Counts of observations the tracker ignored, by reason (saturating).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RejectedCounts {
    /// Position NaN/infinite, a covariance not finite, symmetric and positive definite, or a
    /// floor not finite, symmetric and positive semidefinite.
    pub non_finite: u64,
    /// Position beyond +-1000 km, or a 1-sigma or floor above 1 km (numerically unsafe).
    pub out_of_range: u64,
    /// Would have started a track while `MAX_TRACKS` were alive.
    pub over_capacity: u64,
    /// Beyond `MAX_OBSERVATIONS` in one frame.
    pub over_frame_limit: u64,
}

#[derive(Debug, Clone, PartialEq)]
struct TrackState {
    id: u32,
    group: Group,
    class_counts: [u32; 7],
    x: [f64; 4],
    p: M4,
    first_seen_s: f64,
    last_seen_s: f64,
    hits: u32,
    /// The latest observation's floor (see [`Observation::floor_m2`]).
    floor: Cov2,
    /// Every observation at its latest time was cut by the image border
    /// ([`Observation::at_border`]): it left the view of every camera that saw it.
    at_border: bool,
    /// The size evidence of its observations, older frames faded.
    size: SizeEvidence,
    /// Observations that brought size evidence (saturating).
    size_frames: u32,
    /// The floors of its recent frames: whether a view is a better one.
    views: RecentFloors,
    /// A person's standing and walking models, whose mixture `x` and `p` are; `None` for
    /// other road users (one constant-velocity model).
    modes: Option<Modes>,
}

/// Multi-object road-user tracker (bounded: at most `MAX_TRACKS` tracks).
#[derive(Debug, Clone, PartialEq)]
pub struct RoadUserTracker {
    settings: TrackerSettings,
    tracks: Vec<TrackState>,
    last_time_s: Option<f64>,
    next_id: u32,
    rejected: RejectedCounts,
}

const MAX_ABS_POSITION_M: f64 = 1.0e6;
/// An observation farther than this (plus three sigmas of its position and of the track's
/// predicted one) from a track's prediction never continues it, metres: a road user does
/// not stray that far from its predicted path in a frame, a neighbour may stand that near.
const MAX_JUMP_M: f64 = 1.5;
/// Prior 1-sigma of a newborn vehicle track's velocity across the road, m/s: vehicles
/// drive along the road (a lane change crosses at 1-2 m/s), so a young vehicle track does
/// not reach a neighbour in the next lane, whose box it would otherwise take at the speed
/// its prior allows along the road.
pub const NEWBORN_ACROSS_ROAD_MPS: f64 = 2.0;
const MAX_SIGMA_M: f64 = 1.0e3;
/// Observation sigmas are floored here in every direction to keep `S` well conditioned.
const MIN_SIGMA_M: f64 = 1.0e-3;

impl RoadUserTracker {
    /// New tracks beyond this many live ones are not started (counted).
    pub const MAX_TRACKS: usize = 256;
    /// Observations per frame beyond this many are ignored (counted).
    pub const MAX_OBSERVATIONS: usize = 1024;

    /// Creates a tracker after checking every setting's documented range.
    pub fn new(settings: TrackerSettings) -> Result<Self, TrackerError> {
        let s = &settings;
        let limits = [
            (s.gate_m, 100.0, "gate_m"),
            (s.max_coast_s, 60.0, "max_coast_s"),
            (s.accel_sigma_mps2, 100.0, "accel_sigma_mps2"),
            (s.person_accel_sigma_mps2, 100.0, "person_accel_sigma_mps2"),
            (s.max_report_sigma_m, 100.0, "max_report_sigma_m"),
        ];
        if let Some(&(_, _, name)) = limits
            .iter()
            .find(|(v, hi, _)| !(v.is_finite() && *v > 0.0 && v <= hi))
        {
            return Err(TrackerError::BadSettings(name));
        }
        if settings.confirm_hits == 0 {
            return Err(TrackerError::BadSettings("confirm_hits"));
        }
        Ok(Self {
            settings,
            tracks: Vec::new(),
            last_time_s: None,
            next_id: 1,
            rejected: RejectedCounts::default(),
        })
    }

    /// Advances to `time_s` (frame time, seconds, monotonic; equal to the
    /// previous time is allowed, with dt = 0) and takes the frame's
    /// observations; returns the confirmed tracks that were updated, or are coasting with
    /// at least `min_hits_to_coast` observations and were not last seen at the image border,
    /// and whose position is known within
    /// `max_report_sigma_m`, in creation order. On error the tracker is unchanged.
    pub fn update(
        &mut self,
        time_s: f64,
        observations: &[Observation],
    ) -> Result<Vec<Track>, TrackerError> {
        if !time_s.is_finite() {
            return Err(TrackerError::NonFiniteTime);
        }
        if let Some(last_s) = self.last_time_s.filter(|last| time_s < *last) {
            return Err(TrackerError::TimeWentBack {
                last_s,
                now_s: time_s,
            });
        }
        let dt = self.last_time_s.map_or(0.0, |last| time_s - last);
        self.last_time_s = Some(time_s);
        let max_coast = self.settings.max_coast_s;
        // Survivors were seen within max_coast_s, so dt <= max_coast_s here.
        self.tracks.retain(|t| time_s - t.last_seen_s <= max_coast);
        for t in &mut self.tracks {
            let sigma_a = match t.group {
                Group::People => self.settings.person_accel_sigma_mps2,
                _ => self.settings.accel_sigma_mps2,
            };
            match &mut t.modes {
                Some(m) => (t.x, t.p) = m.predict(dt, sigma_a * sigma_a),
                None => kalman::predict(&mut t.x, &mut t.p, dt, sigma_a * sigma_a),
            }
        }
        let valid = self.screen(observations);
        let gate2 = self.settings.gate_m * self.settings.gate_m;
        let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
        for (ti, t) in self.tracks.iter().enumerate() {
            for (oi, o) in valid.iter().enumerate() {
                // Same class only (a van never continues a car's track), and never farther
                // from the prediction than a road user may stray in a frame plus three
                // sigmas of both positions: a young track (its speed not yet known) reaches
                // as far as its speed prior allows, a settled one only to its neighbourhood.
                if dominant_class(t) != o.class {
                    continue;
                }
                // A better view is weighed against the track as it will take it.
                let anchored;
                let t = match t.views.better_view(&o.floor_m2, time_s) {
                    Some(floor) => {
                        anchored = reanchored(t, &floor);
                        &anchored
                    }
                    None => t,
                };
                let jump = (o.position[0] - t.x[0]).hypot(o.position[1] - t.x[1]);
                if jump > MAX_JUMP_M + 3.0 * (o.sigma_m() + position_sigma(t)) {
                    continue;
                }
                let gating = Observation {
                    covariance_m2: gating_covariance(t.group, o),
                    ..*o
                };
                let r = &gating.covariance_m2;
                let d2 = kalman::innovation(&t.x, &t.p, o.position, r).map(|i| i.d2);
                // A person's box is gated by the nearer of the track and its two models.
                let modes_d2 = t.modes.as_ref().and_then(|m| m.nearest_d2(o.position, r));
                let d2 = [d2, modes_d2].into_iter().flatten().min_by(f64::total_cmp);
                if let Some(d2) = d2.filter(|d2| *d2 <= gate2) {
                    pairs.push((d2, ti, oi));
                }
            }
        }
        // Confirmed tracks choose first, so a fresh tentative track (wide
        // velocity prior, hence small Mahalanobis distances) cannot steal
        // observations from an established one.
        let confirm = self.settings.confirm_hits;
        let tentative = |ti: usize| self.tracks[ti].hits < confirm;
        pairs.sort_by(|a, b| {
            tentative(a.1)
                .cmp(&tentative(b.1))
                .then(a.0.total_cmp(&b.0))
        });
        let mut track_used = vec![false; self.tracks.len()];
        let mut obs_used = vec![false; valid.len()];
        for &(_, ti, oi) in &pairs {
            if !track_used[ti] && !obs_used[oi] {
                track_used[ti] = true;
                obs_used[oi] = true;
                correct(&mut self.tracks[ti], &valid[oi], time_s);
            }
        }
        for (o, _) in valid.iter().zip(&obs_used).filter(|(_, used)| !**used) {
            if self.tracks.len() >= Self::MAX_TRACKS {
                self.rejected.over_capacity = self.rejected.over_capacity.saturating_add(1);
                continue;
            }
            let id = self.allocate_id();
            self.tracks.push(new_track(id, o, time_s));
        }
        let (sharp, settled) = (
            self.settings.max_report_sigma_m,
            self.settings.min_hits_to_coast,
        );
        Ok(self
            .tracks
            .iter()
            .filter(|t| t.hits >= confirm && reported_sigma(t) <= sharp)
            .filter(|t| t.last_seen_s == time_s || (t.hits >= settled && !t.at_border))
            .map(report)
            .collect())
    }

    /// The size belief of the one track of `class` whose position, predicted to `time_s`,
    /// lies near `position` (within half the class's mean length and a metre), with size
    /// evidence from at least [`MIN_FRAMES`] frames; `None` when no track or more than one
    /// is there (tracks the next update ends, unseen for longer than `max_coast_s`, do not
    /// count), or when the belief is not a size of the class.
    pub fn size_near(
        &self,
        class: RoadUserClass,
        position: [f64; 2],
        time_s: f64,
    ) -> Option<SizeBelief> {
        self.size_lent(class, position, time_s).map(|l| l.belief)
    }

    /// [`RoadUserTracker::size_near`] with the id of the track that lends it.
    fn size_lent(&self, class: RoadUserClass, position: [f64; 2], time_s: f64) -> Option<Lent> {
        let dt = self
            .last_time_s
            .map_or(0.0, |last| (time_s - last).max(0.0));
        let within = 0.5 * class.size_prior().mean.length_m + 1.0;
        let max_coast = self.settings.max_coast_s;
        let mut near = self.tracks.iter().filter(|t| {
            let [x, y, vx, vy] = t.x;
            time_s - t.last_seen_s <= max_coast
                && dominant_class(t) == class
                && (x + vx * dt - position[0]).hypot(y + vy * dt - position[1]) <= within
        });
        let one = near.next()?;
        if near.next().is_some() || one.size_frames < MIN_FRAMES {
            return None;
        }
        SizeBelief::with(class, &one.size).map(|belief| Lent {
            lender: one.id,
            belief,
        })
    }

    /// The tracks' sizes at `time_s` as hints for a localizer.
    pub fn sizes_at(&self, time_s: f64) -> TrackSizes<'_> {
        TrackSizes {
            tracker: self,
            time_s,
        }
    }

    /// Counters of ignored observations since creation.
    pub fn rejected(&self) -> RejectedCounts {
        self.rejected
    }

    /// Keeps usable observations (sigma floored), counting the others.
    fn screen(&mut self, observations: &[Observation]) -> Vec<Observation> {
        let r = &mut self.rejected;
        let n = observations.len().min(Self::MAX_OBSERVATIONS);
        let excess = (observations.len() - n) as u64;
        r.over_frame_limit = r.over_frame_limit.saturating_add(excess);
        let mut valid = Vec::with_capacity(n);
        for o in &observations[..n] {
            let [x, y] = o.position;
            let sigma_ok = is_covariance(&o.covariance_m2, true);
            let floor_ok = is_covariance(&o.floor_m2, false);
            let size_ok = o.size.is_none_or(|e| e.is_finite());
            if !(x.is_finite() && y.is_finite() && sigma_ok && floor_ok && size_ok) {
                r.non_finite = r.non_finite.saturating_add(1);
            } else if x.abs() > MAX_ABS_POSITION_M
                || y.abs() > MAX_ABS_POSITION_M
                || o.sigma_m() > MAX_SIGMA_M
                || worst_sigma(&o.floor_m2) > MAX_SIGMA_M
            {
                r.out_of_range = r.out_of_range.saturating_add(1);
            } else {
                valid.push(Observation {
                    covariance_m2: floored(&symmetric(&o.covariance_m2), MIN_SIGMA_M),
                    floor_m2: floored(&symmetric(&o.floor_m2), 0.0),
                    ..*o
                });
            }
        }
        valid
    }

    /// Next id not in use; terminates because at most MAX_TRACKS are in use.
    fn allocate_id(&mut self) -> u32 {
        loop {
            let id = self.next_id;
            self.next_id = self.next_id.wrapping_add(1);
            if !self.tracks.iter().any(|t| t.id == id) {
                return id;
            }
        }
    }
}

/// A tracker's size beliefs at one time, as a localizer's hints.
#[derive(Debug, Clone, Copy)]
pub struct TrackSizes<'a> {
    tracker: &'a RoadUserTracker,
    time_s: f64,
}

impl SizeHints for TrackSizes<'_> {
    fn near(&self, class: RoadUserClass, position: [f64; 2]) -> Option<Lent> {
        self.tracker.size_lent(class, position, self.time_s)
    }
}

/// The covariance an observation is gated with. A road user that starts or stops moves
/// where the constant-velocity model does not foresee, and its box may be known to a few
/// centimetres in that direction (across the line of sight): the box's worst-direction
/// error is the gate's margin. A person or a two-wheeler may start in any direction, so
/// the margin is a circle. A vehicle starts and brakes along the road, so where the road's
/// direction is known the margin lies along it alone: across the road the box's own error
/// gates it, and a young vehicle track does not take the box of a neighbour in the next
/// lane.
fn gating_covariance(group: Group, o: &Observation) -> Cov2 {
    let worst = o.sigma_m();
    match (group, o.road_axis.and_then(unit)) {
        (Group::Vehicles, Some(u)) => {
            let r = &o.covariance_m2;
            let margin = with_axes((worst * worst - variance_along(r, u)).max(0.0), 0.0, u);
            std::array::from_fn(|i| std::array::from_fn(|j| r[i][j] + margin[i][j]))
        }
        _ => circle(worst),
    }
}

/// `v` scaled to unit length; `None` when it is not finite or has no length.
fn unit(v: [f64; 2]) -> Option<[f64; 2]> {
    let n = v[0].hypot(v[1]);
    (n.is_finite() && n > 1e-9).then(|| [v[0] / n, v[1] / n])
}

/// Tentative track at the observation, velocity 0 with the group's prior.
fn new_track(id: u32, o: &Observation, time_s: f64) -> TrackState {
    let group = Group::of(o.class);
    let speed = group.prior_speed_sigma();
    let mut p = [[0.0; 4]; 4];
    for (i, row) in o.covariance_m2.iter().enumerate() {
        p[i][..2].copy_from_slice(row);
    }
    let velocity = match (group, o.road_axis.and_then(unit)) {
        (Group::Vehicles, Some(u)) => with_axes(speed * speed, NEWBORN_ACROSS_ROAD_MPS.powi(2), u),
        _ => circle(speed),
    };
    for (row, v) in p[2..].iter_mut().zip(velocity) {
        row[2..].copy_from_slice(&v);
    }
    let mut class_counts = [0; 7];
    class_counts[o.class as usize] = 1;
    let mut x = [o.position[0], o.position[1], 0.0, 0.0];
    let modes = (group == Group::People).then(|| Modes::new(&x, &p));
    if let Some(m) = &modes {
        (x, p) = m.mixture();
    }
    TrackState {
        id,
        group,
        class_counts,
        x,
        p,
        first_seen_s: time_s,
        last_seen_s: time_s,
        hits: 1,
        floor: o.floor_m2,
        at_border: o.at_border,
        size: o.size.unwrap_or(SizeEvidence::NONE),
        size_frames: u32::from(o.size.is_some()),
        views: RecentFloors::new(&o.floor_m2, time_s),
        modes,
    }
}

/// The class seen most often on a track (ties: earlier in `ALL`).
fn dominant_class(t: &TrackState) -> RoadUserClass {
    RoadUserClass::ALL
        .into_iter()
        .rev()
        .max_by_key(|&c| t.class_counts[c as usize])
        .unwrap_or(RoadUserClass::Car)
}

/// Kalman measurement update (each motion model's, for a person) and bookkeeping. A better
/// view ([`views`]) restarts the track's position instead: the views before it share an
/// error that averaging did not remove, and a blend keeps part of it (and the filter takes
/// its removal over the next frames for motion).
fn correct(t: &mut TrackState, o: &Observation, time_s: f64) {
    let better = t.views.better_view(&o.floor_m2, time_s).is_some();
    t.views.record(&o.floor_m2, time_s, better);
    let (position, r) = (o.position, &o.covariance_m2);
    let updated = match (&mut t.modes, better) {
        (Some(m), true) => {
            m.restart_position(position, r);
            (t.x, t.p) = m.mixture();
            true
        }
        (None, true) => {
            kalman::restart_position(&mut t.x, &mut t.p, position, r);
            true
        }
        (Some(m), false) => m
            .correct(position, r)
            .map(|(x, p)| (t.x, t.p) = (x, p))
            .is_some(),
        (None, false) => kalman::update(&mut t.x, &mut t.p, position, r).is_some(),
    };
    if !updated {
        return;
    }
    let c = &mut t.class_counts[o.class as usize];
    *c = c.saturating_add(1);
    t.hits = t.hits.saturating_add(1);
    // Cut by the border in one camera and seen whole by another at the same time, the road
    // user is still in the site's view: it left only if every view of it was cut.
    let seen_now = t.last_seen_s == time_s;
    t.at_border = o.at_border && (t.at_border || !seen_now);
    t.last_seen_s = time_s;
    t.floor = o.floor_m2;
    if let Some(e) = &o.size {
        t.size = t.size.scaled(FADE_PER_FRAME).plus(e);
        t.size_frames = t.size_frames.saturating_add(1);
    }
}

/// A copy of `t` whose position covariance is raised to `floor` along each axis: the error
/// its recent observations shared, which the filter averaged as if it were independent from
/// frame to frame ([`views`]). A better view is gated against it.
fn reanchored(t: &TrackState, floor: &Cov2) -> TrackState {
    let mut copy = t.clone();
    let block = floored_by(&position_covariance(&copy), floor);
    set_position_block(&mut copy.p, &block);
    copy
}

/// The position block of a track's covariance, m².
fn position_covariance(t: &TrackState) -> Cov2 {
    symmetric(&position_block(&t.p))
}

/// 1-sigma of a track's position along its worst direction, metres (the filter's).
fn position_sigma(t: &TrackState) -> f64 {
    worst_sigma(&position_covariance(t))
}

/// The accuracy a track reports along its worst direction (its ellipse's semi-major axis).
fn reported_sigma(t: &TrackState) -> f64 {
    reported_ellipse(t).semi_major_m
}

/// The error ellipse a track reports: the filter's, each axis never better than the error
/// its latest observation repeats from frame to frame along it.
fn reported_ellipse(t: &TrackState) -> ErrorEllipse {
    ErrorEllipse::of(&floored_by(&position_covariance(t), &t.floor))
}

/// Public view of a track, with accuracies from its covariance.
fn report(t: &TrackState) -> Track {
    let [x, y, vx, vy] = t.x;
    let p = &t.p;
    let speed = vx.hypot(vy);
    let (mut heading_deg, mut heading_sigma_deg) = (None, None);
    let speed_sigma_mps = if speed > 1e-9 {
        let (ux, uy) = (vx / speed, vy / speed);
        let var_s = ux * ux * p[2][2] + 2.0 * ux * uy * p[2][3] + uy * uy * p[3][3];
        let sigma = var_s.max(0.0).sqrt();
        if speed >= 2.0 * sigma {
            // d(atan2(vx, vy))/dv = [vy, -vx] / speed^2.
            let var_h =
                (uy * uy * p[2][2] - 2.0 * ux * uy * p[2][3] + ux * ux * p[3][3]) / (speed * speed);
            let h = vx.atan2(vy).to_degrees().rem_euclid(360.0);
            heading_deg = Some(if h >= 360.0 { 0.0 } else { h });
            heading_sigma_deg = Some(var_h.max(0.0).sqrt().to_degrees().min(180.0));
        }
        sigma
    } else {
        worst_sigma(&[[p[2][2], p[2][3]], [p[3][2], p[3][3]]])
    };
    // max_by_key keeps the last maximum; reversed, that is the earliest in ALL.
    let class = dominant_class(t);
    let ellipse = reported_ellipse(t);
    Track {
        id: t.id,
        class,
        position: [x, y],
        velocity: [vx, vy],
        speed_mps: speed,
        heading_deg,
        position_sigma_m: ellipse.semi_major_m,
        position_ellipse: ellipse,
        speed_sigma_mps,
        heading_sigma_deg,
        first_seen_s: t.first_seen_s,
        last_seen_s: t.last_seen_s,
        hits: t.hits,
    }
}

mod kalman;
mod modes;
#[cfg(test)]
mod tests;
mod views;
