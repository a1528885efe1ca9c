//! A site's cameras over a video: each frame's masks to positions (per camera), and one
//! tracker fed by every camera, so that two views of the same zone fuse by track association
//! in road coordinates: a road user hidden from one camera keeps its track from the other.
//!
//! Frames of all cameras are taken as simultaneous (same index, same time); each camera's
//! observations update the tracker in turn at that time.

use super::detections::Silhouette;
use super::localize::{Localized, Localizer, Rejections};
use super::tracker::{Observation, RoadUserTracker, Track, TrackerError, TrackerSettings};
use super::RoadUserClass;

/// One localized road user of one camera in one frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sighting {
    /// Frame index.
    pub frame: usize,
    /// Camera index.
    pub camera: usize,
    /// Class.
    pub class: RoadUserClass,
    /// Position, local metres.
    pub position: [f64; 2],
    /// 1-sigma error, metres.
    pub sigma_m: f64,
}

/// The tracks after one frame.
#[derive(Debug, Clone, PartialEq)]
pub struct TrackedFrame {
    /// Frame index.
    pub frame: usize,
    /// Its time, seconds.
    pub time_s: f64,
    /// Confirmed tracks.
    pub tracks: Vec<Track>,
}

/// What a run of the pipeline gives.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Run {
    /// Every localized road user.
    pub sightings: Vec<Sighting>,
    /// The tracks, frame by frame.
    pub tracked: Vec<TrackedFrame>,
    /// Detections per camera.
    pub detections: Vec<usize>,
    /// Refusals per camera.
    pub rejected: Vec<Rejections>,
}

/// The pipeline of a site: its cameras' localizers and one tracker.
#[derive(Debug, Clone)]
pub struct Pipeline {
    cameras: Vec<Localizer>,
    tracker: RoadUserTracker,
    run: Run,
    /// Keep every sighting and tracked frame ([`Pipeline::new`]) or only the counts and the
    /// last frame ([`Pipeline::live`]).
    record: bool,
}

impl Pipeline {
    /// A pipeline of these cameras (all in one local frame).
    pub fn new(cameras: Vec<Localizer>, settings: TrackerSettings) -> Result<Self, TrackerError> {
        let n = cameras.len();
        Ok(Self {
            cameras,
            tracker: RoadUserTracker::new(settings)?,
            run: Run {
                detections: vec![0; n],
                rejected: vec![Rejections::default(); n],
                ..Run::default()
            },
            record: true,
        })
    }

    /// A pipeline for a camera site that runs for as long as it is on: its [`Run`] keeps
    /// the counts and only the last tracked frame (no sightings), so memory stays bounded.
    pub fn live(cameras: Vec<Localizer>, settings: TrackerSettings) -> Result<Self, TrackerError> {
        Ok(Self {
            record: false,
            ..Self::new(cameras, settings)?
        })
    }

    /// Takes frame `frame` at `time_s`: `per_camera[c]` is camera `c`'s masks (missing
    /// cameras saw nothing). Returns the confirmed tracks.
    pub fn frame(
        &mut self,
        frame: usize,
        time_s: f64,
        per_camera: &[Vec<Silhouette>],
    ) -> Result<&[Track], TrackerError> {
        let mut tracks = Vec::new();
        for (c, loc) in self.cameras.iter_mut().enumerate() {
            let masks = per_camera.get(c).map_or(&[][..], Vec::as_slice);
            let (found, rejected) = loc.frame_with(masks, &self.tracker.sizes_at(time_s));
            loc.learn(&found);
            self.run.detections[c] += masks.len();
            self.run.rejected[c].add(&rejected);
            let obs: Vec<Observation> = found.iter().map(Localized::observation).collect();
            tracks = self.tracker.update(time_s, &obs)?;
            if !self.record {
                continue;
            }
            self.run.sightings.extend(found.iter().map(|l| Sighting {
                frame,
                camera: c,
                class: l.road_user.class,
                position: l.position,
                sigma_m: l.sigma_m,
            }));
        }
        if self.cameras.is_empty() {
            tracks = self.tracker.update(time_s, &[])?;
        }
        if !self.record {
            self.run.tracked.clear();
        }
        self.run.tracked.push(TrackedFrame {
            frame,
            time_s,
            tracks,
        });
        Ok(&self.run.tracked[self.run.tracked.len() - 1].tracks)
    }

    /// Its cameras' localizers, with what each learnt of its masks' noise.
    pub fn cameras(&self) -> &[Localizer] {
        &self.cameras
    }

    /// What the run gave so far.
    pub fn run(&self) -> &Run {
        &self.run
    }

    /// The run, ending the pipeline.
    pub fn finish(self) -> Run {
        self.run
    }
}

/// The paper's field table (1920x1080, camera 6 m up a pole, UAV truth): mean and max
/// localization error per class, centimetres.
pub const PAPER_ERRORS_CM: [(RoadUserClass, f64, f64); 5] = [
    (RoadUserClass::Car, 12.3, 20.5),
    (RoadUserClass::Van, 17.2, 26.8),
    (RoadUserClass::Bus, 20.8, 30.7),
    (RoadUserClass::Truck, 23.7, 35.4),
    (RoadUserClass::Pedestrian, 8.0, 19.8),
];

/// "mean / max" of the paper's table for a class, "-" for a class it does not have.
pub fn paper_text(class: RoadUserClass) -> String {
    PAPER_ERRORS_CM
        .iter()
        .find(|p| p.0 == class)
        .map_or(String::from("-"), |p| format!("{:.1} / {:.1}", p.1, p.2))
}

/// Localization errors per class, centimetres.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ErrorTable {
    /// Per class (in [`RoadUserClass::ALL`] order), the errors found.
    pub errors: [Vec<f64>; 7],
    /// Sightings (or tracks) with no truth of their class within the match distance.
    pub unmatched: usize,
}

/// A truth: a road user's class and position (local metres) in a frame.
pub type Truth = (RoadUserClass, [f64; 2]);

/// Sightings (or track positions) matched to the truth of their frame: each to the nearest
/// truth of its class within `within_m`.
pub fn error_table<'a>(
    found: impl Iterator<Item = (usize, RoadUserClass, [f64; 2])>,
    truth: impl Fn(usize) -> &'a [Truth],
    within_m: f64,
) -> ErrorTable {
    let mut table = ErrorTable::default();
    for (frame, class, p) in found {
        let nearest = truth(frame)
            .iter()
            .filter(|t| t.0 == class)
            .map(|t| (t.1[0] - p[0]).hypot(t.1[1] - p[1]))
            .fold(f64::INFINITY, f64::min);
        match RoadUserClass::ALL.iter().position(|c| *c == class) {
            Some(k) if nearest <= within_m => table.errors[k].push(nearest * 100.0),
            _ => table.unmatched += 1,
        }
    }
    table
}

/// Mean, standard deviation and maximum of a list (zeros when empty).
pub fn stats(v: &[f64]) -> (f64, f64, f64) {
    if v.is_empty() {
        return (0.0, 0.0, 0.0);
    }
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n;
    (mean, var.sqrt(), v.iter().copied().fold(0.0, f64::max))
}
