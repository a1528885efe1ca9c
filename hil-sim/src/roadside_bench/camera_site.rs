//! A camera site in a scripted run (a bench scenario's `[workers]`): the renderer's street
//! laid on the scenario's road at a station, one or two cameras on poles beside it, road
//! users walking or driving scripted paths, and on every broadcast tick the whole chain of
//! the product: each camera's detector masks (with pixel noise) rendered from the truth,
//! localized through the camera's vanishing points and reference-point homography, fused
//! by one tracker, and the tracked workers in the zone turned into PSMs.
//!
//! The street's frame: x metres to the right of the left edge of the road's first lane,
//! y metres along the road from the station `at_m`; it is placed on the road's tangent
//! there (exact on a straight road).

use serde::Deserialize;

use super::street::{
    labels_window, marking_points, picture, site_cameras, window_masks, RoadUser, World,
};
use super::synthetic_camera::PinholeCamera;
use j2735::MessageFrame;
use roadside::camera::Homography;
use roadside::clock::Utc;
use roadside::ellipse::ErrorEllipse;
use roadside::rng::Prng;
use roadside::road::Road;
use roadside::road_users::calibrate::calibrate;
use roadside::road_users::class::RoadUserClass;
use roadside::road_users::edgelets::EdgeletSettings;
use roadside::road_users::localize::Localizer;
use roadside::road_users::pipeline::Pipeline;
use roadside::road_users::tracker::{Track, TrackerSettings};
use roadside::road_users::vanishing::RansacSettings;
use roadside::road_users::workers::WorkerBroadcaster;

/// A scenario's camera site (`[workers]`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraSiteSpec {
    /// Station along the road's first lane where the street's y = 0 lies, metres.
    pub at_m: f64,
    /// Cameras: 1 (on a pole 6 m left of the road at y = 0, looking along it) or 2 (and
    /// one 7 m right of the road at y = 75 m, looking back).
    #[serde(default = "one")]
    pub cameras: usize,
    /// Mask noise of the detector, pixels (1-sigma per silhouette corner).
    #[serde(default = "one_px")]
    pub noise_px: f64,
    /// Seed of the noise.
    #[serde(default)]
    pub seed: u64,
    /// The road users.
    #[serde(rename = "user")]
    pub users: Vec<SceneUserSpec>,
}

fn one() -> usize {
    1
}

fn one_px() -> f64 {
    1.0
}

/// A road user of the site and its scripted path.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneUserSpec {
    /// Class name (`pedestrian` for a worker, `truck`, `car`, ...).
    pub class: String,
    /// Waypoints `[t_s, x_m, y_m]` in the street's frame, time since the drive start
    /// ascending; the user stands at the first before it and at the last after it, and
    /// moves in straight lines between them.
    pub path: Vec<[f64; 3]>,
}

/// Where the street lies on the road: its origin and axes in the road's local metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScenePlacement {
    origin: [f64; 2],
    along: [f64; 2],
    bearing_deg: f64,
}

impl ScenePlacement {
    /// The street's frame at station `at_m` of the road's first lane (its left edge).
    pub fn on(road: &Road, at_m: f64) -> Result<Self, String> {
        let lane = road.lanes.first().ok_or("the road has no lanes")?;
        let edge = lane
            .beside(at_m, 0.5 * lane.width_m)
            .ok_or("the road's first lane has no centreline")?;
        let b = edge.bearing_deg.to_radians();
        Ok(Self {
            origin: edge.point,
            along: [b.sin(), b.cos()],
            bearing_deg: edge.bearing_deg,
        })
    }

    /// A street point in the road's local metres.
    pub fn point(&self, p: [f64; 2]) -> [f64; 2] {
        let [ax, ay] = self.along;
        // Right of the direction (ax, ay) is (ay, -ax).
        [
            self.origin[0] + p[0] * ay + p[1] * ax,
            self.origin[1] - p[0] * ax + p[1] * ay,
        ]
    }

    /// A track in the street's frame moved to the road's frame.
    pub fn track(&self, t: &Track) -> Track {
        let [ax, ay] = self.along;
        let [vx, vy] = t.velocity;
        Track {
            position: self.point(t.position),
            velocity: [vx * ay + vy * ax, -vx * ax + vy * ay],
            heading_deg: t
                .heading_deg
                .map(|h| (h + self.bearing_deg).rem_euclid(360.0)),
            position_ellipse: ErrorEllipse {
                orientation_deg: (t.position_ellipse.orientation_deg + self.bearing_deg)
                    .rem_euclid(180.0),
                ..t.position_ellipse
            },
            ..*t
        }
    }
}

/// A road user of the site with its size and path.
#[derive(Debug, Clone)]
struct Scripted {
    class: RoadUserClass,
    extent: roadside::road_users::class::Extent,
    path: Vec<[f64; 3]>,
}

impl Scripted {
    /// The road user at `t_s` (id `id`).
    fn at(&self, id: u32, t_s: f64) -> RoadUser {
        let (centre, velocity) = along_path(&self.path, t_s);
        RoadUser {
            id,
            class: self.class,
            centre,
            extent: self.extent,
            velocity,
        }
    }
}

/// Position and velocity on a piecewise-linear path at `t`.
fn along_path(path: &[[f64; 3]], t: f64) -> ([f64; 2], [f64; 2]) {
    let Some(first) = path.first() else {
        return ([0.0, 0.0], [0.0, 0.0]);
    };
    if t <= first[0] {
        return ([first[1], first[2]], [0.0, 0.0]);
    }
    for w in path.windows(2) {
        let (a, b) = (w[0], w[1]);
        if t <= b[0] && b[0] > a[0] {
            let f = (t - a[0]) / (b[0] - a[0]);
            let v = [(b[1] - a[1]) / (b[0] - a[0]), (b[2] - a[2]) / (b[0] - a[0])];
            return ([a[1] + f * (b[1] - a[1]), a[2] + f * (b[2] - a[2])], v);
        }
    }
    let last = path[path.len() - 1];
    ([last[1], last[2]], [0.0, 0.0])
}

/// What one camera saw of one road user at one tick: its visible pixels (0 when hidden
/// or missed).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct CameraView {
    /// Seconds since the drive start.
    pub t_s: f64,
    /// Camera, from 1.
    pub camera: usize,
    /// Road user, from 1 in the scenario's order.
    pub user: usize,
    /// Visible pixels.
    pub pixels: u32,
}

/// The most views kept (a 10 minute run of two cameras and ten users at 10 Hz).
pub const MAX_VIEWS: usize = 120_000;

/// The camera site running.
#[derive(Debug, Clone)]
pub struct LiveSite {
    cameras: Vec<PinholeCamera>,
    users: Vec<Scripted>,
    pipeline: Pipeline,
    broadcaster: WorkerBroadcaster,
    placement: ScenePlacement,
    road: Road,
    rng: Prng,
    noise_px: f64,
    frame: usize,
    /// Every camera's view of every road user at each tick (at most [`MAX_VIEWS`]).
    pub views: Vec<CameraView>,
}

impl LiveSite {
    /// Sets the site up on `road`: the street with its forward lanes (cones along the
    /// closed lane `closed.0` from `closed.1[0]` to `closed.1[1]`, stations of the road), each
    /// camera calibrated from its first picture (vanishing points) and from lane-marking
    /// reference points (homography), and the work zone's area (every lane and a metre
    /// beyond, 10 m before and after the closure) for the PSMs.
    pub fn new(
        spec: &CameraSiteSpec,
        road: &Road,
        closed: (u32, [f64; 2]),
        salt: u32,
    ) -> Result<Self, String> {
        if !(1..=2).contains(&spec.cameras) {
            return Err(format!(
                "workers: cameras must be 1 or 2, not {}",
                spec.cameras
            ));
        }
        let placement = ScenePlacement::on(road, spec.at_m)?;
        let lane_width = road.lanes[0].width_m;
        let lanes = forward_lanes(road);
        let (lane, [from, to]) = closed;
        let stretch = [from - spec.at_m, to - spec.at_m];
        let world = World::street(lanes, lane_width, (lane, stretch));
        let users = spec
            .users
            .iter()
            .map(|u| {
                let class = RoadUserClass::from_name(&u.class)
                    .ok_or_else(|| format!("workers: unknown class {:?}", u.class))?;
                if u.path.is_empty() || u.path.windows(2).any(|w| w[1][0] < w[0][0]) {
                    return Err("workers: a path needs waypoints in time order".to_string());
                }
                Ok(Scripted {
                    class,
                    extent: class.typical(),
                    path: u.path.clone(),
                })
            })
            .collect::<Result<Vec<_>, String>>()?;
        let width = world.road_width_m();
        let cameras: Vec<PinholeCamera> = site_cameras(&world, false)
            .into_iter()
            .take(spec.cameras)
            .collect();
        let mut rng = Prng::new(spec.seed ^ 0x5eed_ca11);
        let first: Vec<RoadUser> = (0..users.len())
            .map(|k| users[k].at(k as u32, 0.0))
            .collect();
        let localizers = cameras
            .iter()
            .map(|cam| calibrated(&world, cam, &first, &mut rng))
            .collect::<Result<Vec<_>, String>>()?;
        let pipeline =
            Pipeline::live(localizers, TrackerSettings::default()).map_err(|e| e.to_string())?;
        let area = [
            [-1.0, stretch[0] - 10.0],
            [width + 1.0, stretch[0] - 10.0],
            [width + 1.0, stretch[1] + 10.0],
            [-1.0, stretch[1] + 10.0],
        ]
        .iter()
        .map(|p| placement.point(*p))
        .collect();
        Ok(Self {
            cameras,
            users,
            pipeline,
            broadcaster: WorkerBroadcaster::new(area, salt),
            placement,
            road: road.clone(),
            rng,
            noise_px: spec.noise_px,
            frame: 0,
            views: Vec::new(),
        })
    }

    /// One camera frame at `t_s` (seconds since the drive start), `now` on the air: the
    /// workers' PSMs.
    pub fn tick(&mut self, t_s: f64, now: Utc) -> Vec<Box<MessageFrame>> {
        let users: Vec<RoadUser> = (0..self.users.len())
            .map(|k| self.users[k].at(k as u32, t_s))
            .collect();
        let mut per_camera = Vec::with_capacity(self.cameras.len());
        for (c, cam) in self.cameras.iter().enumerate() {
            let size = cam.image_size().map(|v| v as u32);
            let window = labels_window(cam, &users, self.noise_px, &mut self.rng);
            let seen = window_masks(&window, size, &users, &[]);
            for k in 0..users.len() {
                if self.views.len() < MAX_VIEWS {
                    let pixels = seen.iter().find(|s| s.0 == k).map_or(0.0, |s| s.1.area_px);
                    self.views.push(CameraView {
                        t_s,
                        camera: c + 1,
                        user: k + 1,
                        pixels: pixels as u32,
                    });
                }
            }
            per_camera.push(seen.into_iter().map(|(_, s)| s).collect());
        }
        self.frame += 1;
        let tracks: Vec<Track> = match self.pipeline.frame(self.frame, t_s, &per_camera) {
            Ok(tracks) => tracks.iter().map(|t| self.placement.track(t)).collect(),
            Err(_) => Vec::new(),
        };
        self.broadcaster.tick(&tracks, t_s, now, &self.road)
    }

    /// PSMs that could not be built.
    pub fn failed(&self) -> u64 {
        self.broadcaster.failed
    }
}

/// Lanes running the first lane's way.
fn forward_lanes(road: &Road) -> u32 {
    let bearing = |l: &roadside::road::RoadLane| l.at(0.0).map(|o| o.bearing_deg);
    let first = road.lanes.first().and_then(bearing);
    let same = road
        .lanes
        .iter()
        .filter(|l| match (bearing(l), first) {
            (Some(b), Some(f)) => ((b - f + 540.0).rem_euclid(360.0) - 180.0).abs() < 90.0,
            _ => false,
        })
        .count();
    same.max(1) as u32
}

/// A camera's localizer: vanishing points from its picture of the street, and the
/// homography from the lane markings' corners in view (0.5 px of noise on their pixels).
fn calibrated(
    world: &World,
    cam: &PinholeCamera,
    users: &[RoadUser],
    rng: &mut Prng,
) -> Result<Localizer, String> {
    let grey = image::DynamicImage::ImageRgb8(picture(world, cam, users)).to_luma8();
    let cal = calibrate(
        &grey,
        &EdgeletSettings::default(),
        &RansacSettings::default(),
    )
    .map_err(|e| format!("workers: camera calibration: {e}"))?;
    let pairs = marking_points(cam, world, rng);
    let homography = Homography::estimate(&pairs).map_err(|e| format!("workers: {e}"))?;
    Localizer::new(&cal, homography.matrix()).map_err(|e| format!("workers: {e}"))
}

#[cfg(test)]
mod tests;
