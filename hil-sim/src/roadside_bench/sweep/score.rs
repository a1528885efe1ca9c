//! The road-user pipeline on a sweep install, scored against the truth: per class the
//! per-frame box errors and the track errors, track positions more than 1 m from every road
//! user of their class (and the workers' PSMs among them), how often the reported 95 %
//! error ellipse holds the truth, coverage of the road users within 40 m with at least half their
//! silhouette visible, and the refusals by reason.

use super::super::street::{
    labels_window, marking_points, picture, range_m, silhouette, users_at, window_masks, Mover,
    RoadUser, World,
};
use super::super::synthetic_camera::PinholeCamera;
use super::bound::{ideal_error, position_bound, position_bound_size_known};
use roadside::assign::cheapest_first;
use roadside::camera::Homography;
use roadside::ellipse::{mahalanobis2, Cov2};
use roadside::rng::Prng;
use roadside::road_users::calibrate::calibrate;
use roadside::road_users::detections::Silhouette;
use roadside::road_users::edgelets::EdgeletSettings;
use roadside::road_users::localize::{Localized, Localizer, Rejections};
use roadside::road_users::pipeline::Pipeline;
use roadside::road_users::polygon::{in_front, near_or_overlapping, signed_area};
use roadside::road_users::tracker::{Observation, RoadUserTracker, Track, TrackerSettings};
use roadside::road_users::vanishing::RansacSettings;
use roadside::road_users::RoadUserClass;

/// Road users farther than this from the camera's foot are not counted, metres.
pub const RANGE_M: f64 = 40.0;
/// Share of its silhouette a road user must show to count for coverage.
pub const MIN_VISIBLE: f64 = 0.5;
/// A track position farther than this from every road user of its class is off, metres.
pub const OFF_M: f64 = 1.0;
/// The 95 % ellipse's size in 1-sigma units (chi-square, two degrees of freedom).
pub const ELLIPSE_95: f64 = 2.4477;

/// How a run is made.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunSettings {
    /// Frames (at 10 per second).
    pub frames: usize,
    /// Mask noise, pixels (each silhouette corner).
    pub noise_px: f64,
    /// Traffic seed.
    pub seed: u64,
}

/// The scores of one run (one camera, or a pair fused).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Score {
    /// Per class (in [`RoadUserClass::ALL`] order), per-frame box errors, cm.
    pub boxes: [Vec<f64>; 7],
    /// Per class, per-frame box errors of road users seen whole (in the image, no nearer
    /// road user covering any of it), cm: the paper's case.
    pub whole_boxes: [Vec<f64>; 7],
    /// Per class, for the same boxes, the errors of an ideal estimator at the Cramér-Rao
    /// bound of the mask's information and the size prior ([`super::bound`]), cm.
    pub ideal_boxes: [Vec<f64>; 7],
    /// Per class, for the same boxes, the errors of an ideal estimator that knows each road
    /// user's size exactly ([`position_bound_size_known`]), cm.
    pub size_known_boxes: [Vec<f64>; 7],
    /// Per class, track position errors (to each track's road user: tracks and road users of
    /// a class paired one to one within [`OFF_M`], wherever the track is, counted when the
    /// road user is within range; the tracks left over within range are counted in
    /// `tracks_off`), cm.
    pub tracks: [Vec<f64>; 7],
    /// Per class, the track position errors of road users seen whole in that frame (as
    /// [`Score::whole_boxes`]): the position the product broadcasts, in the paper's case, cm.
    pub whole_tracks: [Vec<f64>; 7],
    /// Every track position paired with a road user within range: (frame, the road user's
    /// id, error in cm), so that two runs can be compared on the road users both track.
    pub matched: Vec<(usize, u32, f64)>,
    /// Track positions within range with no road user of their own (more than [`OFF_M`]
    /// from every road user of their class, or a second track of one).
    pub tracks_off: usize,
    /// Of those, workers' (people in the closed lane): PSMs that would be off.
    pub psms_off: usize,
    /// Boxes, and those whose 95 % ellipse holds the truth.
    pub boxes_in_ellipse: (usize, usize),
    /// Track positions, and those whose 95 % ellipse holds the truth.
    pub tracks_in_ellipse: (usize, usize),
    /// Per class: road users within range showing enough (per frame), and how many of them
    /// were localized.
    pub coverage: [(usize, usize); 7],
    /// Per class: the same road users, and how many had a track of their own (paired one to
    /// one, within [`OFF_M`]).
    pub track_coverage: [(usize, usize); 7],
    /// Per class: road users within range seen whole (per frame), and how many had a track
    /// of their own.
    pub whole_tracked: [(usize, usize); 7],
    /// Refusals.
    pub rejected: Rejections,
    /// Detections.
    pub detections: usize,
    /// The mask noise each camera learnt by the end of its run, pixels
    /// ([`Localizer::learn`]).
    pub learnt_noise_px: Vec<f64>,
}

impl Score {
    /// Adds another run's scores.
    pub fn merge(&mut self, o: &Score) {
        for k in 0..7 {
            self.boxes[k].extend_from_slice(&o.boxes[k]);
            self.whole_boxes[k].extend_from_slice(&o.whole_boxes[k]);
            self.ideal_boxes[k].extend_from_slice(&o.ideal_boxes[k]);
            self.size_known_boxes[k].extend_from_slice(&o.size_known_boxes[k]);
            self.tracks[k].extend_from_slice(&o.tracks[k]);
            self.whole_tracks[k].extend_from_slice(&o.whole_tracks[k]);
            self.coverage[k].0 += o.coverage[k].0;
            self.coverage[k].1 += o.coverage[k].1;
            self.track_coverage[k].0 += o.track_coverage[k].0;
            self.track_coverage[k].1 += o.track_coverage[k].1;
            self.whole_tracked[k].0 += o.whole_tracked[k].0;
            self.whole_tracked[k].1 += o.whole_tracked[k].1;
        }
        self.matched.extend_from_slice(&o.matched);
        self.tracks_off += o.tracks_off;
        self.psms_off += o.psms_off;
        self.boxes_in_ellipse.0 += o.boxes_in_ellipse.0;
        self.boxes_in_ellipse.1 += o.boxes_in_ellipse.1;
        self.tracks_in_ellipse.0 += o.tracks_in_ellipse.0;
        self.tracks_in_ellipse.1 += o.tracks_in_ellipse.1;
        self.rejected.add(&o.rejected);
        self.detections += o.detections;
        self.learnt_noise_px.extend_from_slice(&o.learnt_noise_px);
    }
}

/// A class's index in [`RoadUserClass::ALL`] (the per-class arrays' order).
pub fn slot(class: RoadUserClass) -> usize {
    RoadUserClass::ALL
        .iter()
        .position(|c| *c == class)
        .unwrap_or(0)
}

/// A camera's localizer as a site would set it up: vanishing points from a picture of the
/// empty street, the homography from the surveyed lane-marking corners it sees.
pub fn localizer(world: &World, cam: &PinholeCamera, seed: u64) -> Result<Localizer, String> {
    let grey = image::DynamicImage::ImageRgb8(picture(world, cam, &[])).to_luma8();
    let cal = calibrate(
        &grey,
        &EdgeletSettings::default(),
        &RansacSettings::default(),
    )
    .map_err(|e| format!("calibration: {e}"))?;
    let pairs = marking_points(cam, world, &mut Prng::new(seed));
    let h = Homography::estimate(&pairs).map_err(|e| format!("homography: {e}"))?;
    Localizer::new(&cal, h.matrix()).map_err(|e| format!("ground camera: {e}"))
}

/// One camera's view of a frame: the masks, each with its road user's index.
struct View {
    masks: Vec<(usize, Silhouette)>,
    /// Per road user: within range and showing enough to count.
    counts: Vec<bool>,
    /// Per road user: within range.
    near: Vec<bool>,
    /// Per road user: seen whole (in the image, no nearer road user covering it).
    whole: Vec<bool>,
}

fn view(cam: &PinholeCamera, users: &[RoadUser], noise_px: f64, rng: &mut Prng) -> View {
    let size = cam.image_size().map(|v| v as u32);
    let window = labels_window(cam, users, noise_px, rng);
    let masks = window_masks(&window, size, users, &[]);
    let near: Vec<bool> = users
        .iter()
        .map(|u| range_m(cam, u.centre) <= RANGE_M)
        .collect();
    let mut exact = Prng::new(0);
    let outlines: Vec<Option<Vec<[f64; 2]>>> = users
        .iter()
        .map(|u| silhouette(cam, &u.solid(), 0.0, &mut exact))
        .collect();
    let c = cam.centre();
    let eye = [c[0], c[1]];
    let footprint = |u: &RoadUser| {
        let s = u.solid();
        [
            [s.min[0], s.min[1]],
            [s.max[0], s.min[1]],
            [s.max[0], s.max[1]],
            [s.min[0], s.max[1]],
        ]
    };
    // Hidden: a road user standing in front of it covers part of its silhouette.
    let hidden = |k: usize| {
        let Some(sk) = &outlines[k] else { return true };
        users.iter().enumerate().any(|(j, u)| {
            j != k
                && outlines[j]
                    .as_ref()
                    .is_some_and(|sj| near_or_overlapping(sk, sj, 0.0))
                && in_front(&footprint(u), &footprint(&users[k]), eye) != Some(false)
        })
    };
    let mut counts = vec![false; users.len()];
    let mut whole = vec![false; users.len()];
    for (k, m) in &masks {
        let full = outlines[*k].as_ref().map_or(0.0, |h| signed_area(h).abs());
        counts[*k] = near[*k] && m.area_px >= MIN_VISIBLE * full;
        whole[*k] = !m.touches_border && !hidden(*k);
    }
    View {
        masks,
        counts,
        near,
        whole,
    }
}

impl Score {
    fn add_boxes(&mut self, found: &[Localized], v: &View, users: &[RoadUser]) {
        let mut localized = vec![false; users.len()];
        for b in found {
            let k = v.masks[b.index].0;
            let u = &users[k];
            localized[k] = true;
            if !v.near[k] {
                continue;
            }
            let e = dist(b.position, u.centre);
            self.boxes[slot(u.class)].push(e * 100.0);
            if v.whole[k] {
                self.whole_boxes[slot(u.class)].push(e * 100.0);
            }
            self.boxes_in_ellipse.0 += 1;
            if holds(&b.covariance_m2, b.position, u.centre) {
                self.boxes_in_ellipse.1 += 1;
            }
        }
        for (k, u) in users.iter().enumerate().filter(|(k, _)| v.counts[*k]) {
            let c = &mut self.coverage[slot(u.class)];
            c.0 += 1;
            c.1 += usize::from(localized[k]);
        }
    }

    /// For each box of a road user seen whole, the errors of the ideal estimators
    /// ([`super::bound`]): the one knowing sizes through the class's prior (drawn from
    /// `rngs[0]`), and the one knowing them exactly (from `rngs[1]`).
    fn add_ideal(
        &mut self,
        found: &[Localized],
        v: &View,
        users: &[RoadUser],
        cam: &PinholeCamera,
        noise_px: f64,
        rngs: [&mut Prng; 2],
    ) {
        let [rng, known_rng] = rngs;
        for b in found {
            let k = v.masks[b.index].0;
            if !(v.near[k] && v.whole[k]) {
                continue;
            }
            // Exact corners pin the box down: the ideal makes no error.
            let error = if noise_px > 0.0 {
                position_bound(cam, &users[k], noise_px).map(|cov| ideal_error(cov, rng))
            } else {
                Some(0.0)
            };
            if let Some(e) = error {
                self.ideal_boxes[slot(users[k].class)].push(e * 100.0);
            }
            let known = if noise_px > 0.0 {
                position_bound_size_known(cam, &users[k], noise_px)
                    .map(|cov| ideal_error(cov, known_rng))
            } else {
                Some(0.0)
            };
            if let Some(e) = known {
                self.size_known_boxes[slot(users[k].class)].push(e * 100.0);
            }
        }
    }

    fn add_tracks(
        &mut self,
        frame: usize,
        tracks: &[Track],
        users: &[RoadUser],
        seen: Seen<'_>,
        world: &World,
        near: &dyn Fn([f64; 2]) -> bool,
    ) {
        let Seen { counts, whole } = seen;
        // Every track is paired, wherever it is; a pair is scored when its road user is in
        // range, a track without one when the track is (a track just past the range for a
        // road user just inside it is scored, not dropped).
        let tracks: Vec<&Track> = tracks.iter().collect();
        let matches = one_to_one(&tracks, users);
        let mut tracked = vec![false; users.len()];
        for (t, m) in tracks.iter().zip(&matches) {
            if !m.map_or(near(t.position), |(k, _)| near(users[k].centre)) {
                continue;
            }
            let Some((k, error_m)) = *m else {
                // Off by more than any reported ellipse reaches (or a second track of a
                // road user that has one): a miss for the ellipse too.
                self.tracks_in_ellipse.0 += 1;
                self.tracks_off += 1;
                if t.class.is_person() && in_closed_lane(world, t.position) {
                    self.psms_off += 1;
                }
                continue;
            };
            let u = &users[k];
            tracked[k] = true;
            self.tracks[slot(t.class)].push(error_m * 100.0);
            if whole[k] {
                self.whole_tracks[slot(t.class)].push(error_m * 100.0);
            }
            self.matched.push((frame, u.id, error_m * 100.0));
            self.tracks_in_ellipse.0 += 1;
            if holds(&t.position_ellipse.covariance(), t.position, u.centre) {
                self.tracks_in_ellipse.1 += 1;
            }
        }
        for (k, u) in users.iter().enumerate() {
            if counts[k] {
                let c = &mut self.track_coverage[slot(u.class)];
                c.0 += 1;
                c.1 += usize::from(tracked[k]);
            }
            if whole[k] && near(u.centre) {
                let c = &mut self.whole_tracked[slot(u.class)];
                c.0 += 1;
                c.1 += usize::from(tracked[k]);
            }
        }
    }
}

/// Each track's road user: tracks and road users of a class paired one to one, nearest
/// pairs first, none farther apart than [`OFF_M`]; per track, the road user's index and the
/// distance, metres. A second track near a road user that has one is left unpaired.
fn one_to_one(tracks: &[&Track], users: &[RoadUser]) -> Vec<Option<(usize, f64)>> {
    let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
    for (ti, t) in tracks.iter().enumerate() {
        for (k, u) in users.iter().enumerate().filter(|(_, u)| u.class == t.class) {
            let d = dist(u.centre, t.position);
            if d <= OFF_M {
                pairs.push((d, ti, k));
            }
        }
    }
    cheapest_first(pairs, tracks.len(), users.len())
}

/// Per road user of a frame: does it count for coverage, is it seen whole.
#[derive(Clone, Copy)]
struct Seen<'a> {
    counts: &'a [bool],
    whole: &'a [bool],
}

fn in_closed_lane(world: &World, p: [f64; 2]) -> bool {
    let x0 = world.lane_width_m * f64::from(world.closed.0 - 1);
    let [y0, y1] = world.closed.1;
    (x0 - 0.5..=x0 + world.lane_width_m + 0.5).contains(&p[0]) && (y0..=y1).contains(&p[1])
}

/// Does the 95 % ellipse of `covariance` around `estimate` hold `truth`?
fn holds(covariance: &Cov2, estimate: [f64; 2], truth: [f64; 2]) -> bool {
    let d = [truth[0] - estimate[0], truth[1] - estimate[1]];
    mahalanobis2(covariance, d) <= ELLIPSE_95 * ELLIPSE_95
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// The mean track error of `a` and of `b` over the positions both have (the same road user
/// in the same frame), cm, and how many there are: two runs compared on the same road users.
pub fn common_means(a: &Score, b: &Score) -> (f64, f64, usize) {
    let of_b: std::collections::HashMap<(usize, u32), f64> =
        b.matched.iter().map(|&(f, id, e)| ((f, id), e)).collect();
    let of_a: std::collections::HashMap<(usize, u32), f64> =
        a.matched.iter().map(|&(f, id, e)| ((f, id), e)).collect();
    let (mut sa, mut sb, mut n) = (0.0, 0.0, 0usize);
    for (key, ea) in &of_a {
        if let Some(eb) = of_b.get(key) {
            (sa, sb, n) = (sa + ea, sb + eb, n + 1);
        }
    }
    let mean = |s: f64| if n == 0 { 0.0 } else { s / n as f64 };
    (mean(sa), mean(sb), n)
}

/// Runs one camera over the traffic: boxes per frame, and one tracker.
pub fn run_camera(
    world: &World,
    cam: &PinholeCamera,
    loc: &Localizer,
    movers: &[Mover],
    settings: RunSettings,
) -> Score {
    // The camera learns its masks' noise over the run, as on site.
    let mut loc = loc.clone();
    let mut rng = Prng::new(settings.seed ^ 0x5eed);
    let mut ideal_rng = Prng::new(settings.seed ^ 0xb0d);
    let mut known_rng = Prng::new(settings.seed ^ 0x517e);
    let mut tracker = RoadUserTracker::new(TrackerSettings::default()).expect("default settings");
    let mut score = Score::default();
    for f in 0..settings.frames {
        let t = f as f64 * 0.1;
        let users = users_at(movers, t);
        let v = view(cam, &users, settings.noise_px, &mut rng);
        let sil: Vec<Silhouette> = v.masks.iter().map(|(_, s)| s.clone()).collect();
        score.detections += sil.len();
        let (found, rejected) = loc.frame_with(&sil, &tracker.sizes_at(t));
        loc.learn(&found);
        score.rejected.add(&rejected);
        score.add_boxes(&found, &v, &users);
        let rngs = [&mut ideal_rng, &mut known_rng];
        score.add_ideal(&found, &v, &users, cam, settings.noise_px, rngs);
        let obs: Vec<Observation> = found.iter().map(Localized::observation).collect();
        let tracks = tracker.update(t, &obs).expect("frame times go forward");
        let near = |p: [f64; 2]| range_m(cam, p) <= RANGE_M;
        let seen = Seen {
            counts: &v.counts,
            whole: &v.whole,
        };
        score.add_tracks(f, &tracks, &users, seen, world, &near);
    }
    score.learnt_noise_px.push(loc.mask_noise().sigma_px());
    score
}

/// Runs a pair of cameras through one pipeline, both fused or (`only`) one of them alone;
/// the track coverage counts the road users either camera counts, so that one camera and
/// the pair are scored on the same road users.
pub fn run_pair(
    world: &World,
    cams: [&PinholeCamera; 2],
    locs: [&Localizer; 2],
    only: Option<usize>,
    movers: &[Mover],
    settings: RunSettings,
) -> Score {
    let fed: Vec<usize> = only.map_or(vec![0, 1], |k| vec![k]);
    let mut rng = Prng::new(settings.seed ^ 0xfade);
    let cameras = fed.iter().map(|&k| locs[k].clone()).collect();
    let mut pipeline =
        Pipeline::live(cameras, TrackerSettings::default()).expect("default settings");
    let mut score = Score::default();
    for f in 0..settings.frames {
        let t = f as f64 * 0.1;
        let users = users_at(movers, t);
        let views = cams.map(|c| view(c, &users, settings.noise_px, &mut rng));
        let per_camera: Vec<Vec<Silhouette>> = fed
            .iter()
            .map(|&k| views[k].masks.iter().map(|(_, s)| s.clone()).collect())
            .collect();
        let tracks = pipeline
            .frame(f, t, &per_camera)
            .expect("frame times go forward")
            .to_vec();
        let either: Vec<bool> = (0..users.len())
            .map(|k| views[0].counts[k] || views[1].counts[k])
            .collect();
        let whole: Vec<bool> = (0..users.len())
            .map(|k| fed.iter().any(|&c| views[c].whole[k]))
            .collect();
        let near = |p: [f64; 2]| cams.iter().any(|c| range_m(c, p) <= RANGE_M);
        let seen = Seen {
            counts: &either,
            whole: &whole,
        };
        score.add_tracks(f, &tracks, &users, seen, world, &near);
    }
    let learnt = pipeline.cameras().iter().map(|l| l.mask_noise().sigma_px());
    score.learnt_noise_px.extend(learnt);
    score
}
