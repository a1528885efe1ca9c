//! A work zone seen by a synthetic camera: cones along the closed lanes as a crew would set
//! them, and a camera on a pole beside the road, before the zone, framing it.

use super::{PinholeCamera, SyntheticError};
use roadside::road::{bearing, dist, Road, RoadLane};

/// Cones stand this far inside a closed lane's edges, metres (so that they lie on it).
const EDGE_INSET_M: f64 = 0.5;
/// Control points this far beyond the zone's ends, metres (at most half the camera's
/// distance before the zone).
const CONTROL_MARGIN_M: f64 = 10.0;
/// Share of the image (each axis) the zone and the control points fill.
const FILL: f64 = 0.9;
/// Range of the focal length chosen, pixels.
const FOCAL_RANGE_PX: (f64, f64) = (500.0, 8000.0);

/// Where the camera goes and how the cones are set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// Height of the camera above the road, metres.
    pub height_m: f64,
    /// Distance of the camera before the zone start, along the first closed lane, metres.
    pub before_m: f64,
    /// Distance of the camera beyond the outer (right) edge of the carriageway, metres.
    pub outside_m: f64,
    /// Largest distance between cones along a lane, metres.
    pub spacing_m: f64,
    /// Image size, `[width, height]` pixels.
    pub image_size: [f64; 2],
}

impl Default for Placement {
    /// 8 m up, 40 m before the zone, 3 m beyond the edge, a cone every 8 m, 1920x1080.
    fn default() -> Self {
        Self {
            height_m: 8.0,
            before_m: 40.0,
            outside_m: 3.0,
            spacing_m: 8.0,
            image_size: PinholeCamera::DEFAULT_SIZE,
        }
    }
}

/// The ground truth of a synthetic camera view of a work zone (local metres).
#[derive(Debug, Clone, PartialEq)]
pub struct ZoneScene {
    /// The camera, aimed and zoomed so that all cones and control points are in view.
    pub camera: PinholeCamera,
    /// The cones.
    pub cones: Vec<[f64; 2]>,
    /// Surveyed road points for the calibration: across the carriageway at four stations
    /// from just before the zone to just after it.
    pub control: Vec<[f64; 2]>,
}

/// The scene of a zone closing `closed_lanes` from `start_m` to `end_m` (stations along the
/// first of them, as in a scenario): on each closed lane a cone at its centre and at both
/// edges where the zone starts (the taper), then cones along both edges about every
/// `spacing_m` to the end; the camera on the right of the carriageway, `before_m` before the
/// zone, pitched and zoomed so that the cones and the control points fill the image.
pub fn zone_scene(
    road: &Road,
    closed_lanes: &[u8],
    start_m: f64,
    end_m: f64,
    placement: &Placement,
) -> Result<ZoneScene, SyntheticError> {
    if !(start_m.is_finite() && end_m.is_finite() && end_m > start_m) {
        return Err(SyntheticError::BadZone);
    }
    let lane = |id: u8| road.lane(id).ok_or(SyntheticError::UnknownLane(id));
    let first = lane(*closed_lanes.first().ok_or(SyntheticError::BadZone)?)?;
    let mut cones = Vec::new();
    for &id in closed_lanes {
        let closed = lane(id)?;
        let stations = [start_m, end_m].map(|s| station_on(first, closed, s));
        let [Some(from), Some(to)] = stations else {
            return Err(SyntheticError::BadZone);
        };
        cones.extend(lane_cones(closed, from, to, placement.spacing_m));
    }
    let before = placement.before_m.max(0.0);
    let (right, left) = carriageway(road, first, start_m - before);
    let foot = first
        .beside(start_m - before, right - placement.outside_m)
        .ok_or(SyntheticError::BadZone)?;
    let margin = CONTROL_MARGIN_M.min(0.5 * before);
    let control = control_points(first, start_m - margin, end_m + margin, right, left);
    let centre = [foot.point[0], foot.point[1], placement.height_m];
    let seen: Vec<[f64; 2]> = cones.iter().chain(&control).copied().collect();
    let camera = frame(centre, &seen, placement.image_size).ok_or(SyntheticError::NoView)?;
    Ok(ZoneScene {
        camera,
        cones,
        control,
    })
}

/// The station on `lane` level with station `s` of `first`.
fn station_on(first: &RoadLane, lane: &RoadLane, s: f64) -> Option<f64> {
    if lane.id == first.id {
        return Some(s);
    }
    lane.project(first.at(s)?.point).map(|(station, _)| station)
}

/// Cones on one lane from station `from` to `to`: the taper across the lane at `from`, then
/// both edges every `spacing_m` at most.
fn lane_cones(lane: &RoadLane, from: f64, to: f64, spacing_m: f64) -> Vec<[f64; 2]> {
    let half = (lane.width_m / 2.0 - EDGE_INSET_M).max(0.0);
    let gaps = ((to - from) / spacing_m.max(1.0))
        .ceil()
        .clamp(1.0, 10_000.0);
    let step = (to - from) / gaps;
    let mut cones: Vec<[f64; 2]> = lane.at(from).map(|on| on.point).into_iter().collect();
    for k in 0..=gaps as usize {
        let s = from + k as f64 * step;
        for lateral in [half, -half] {
            cones.extend(lane.beside(s, lateral).map(|on| on.point));
        }
    }
    cones
}

/// Lateral offsets (left positive) from `first`'s centreline at `station` of the right and
/// left edges of the lanes running its way.
fn carriageway(road: &Road, first: &RoadLane, station: f64) -> (f64, f64) {
    let half = first.width_m / 2.0;
    let Some(here) = first.at(station) else {
        return (-half, half);
    };
    let same_way = road.lanes.iter().filter_map(|lane| {
        let (s, _) = lane.project(here.point)?;
        let on = lane.at(s)?;
        let turn = (on.bearing_deg - here.bearing_deg + 540.0).rem_euclid(360.0) - 180.0;
        let lateral = first.lateral(on.point)?;
        (turn.abs() < 90.0).then_some((lateral - lane.width_m / 2.0, lateral + lane.width_m / 2.0))
    });
    same_way.fold((-half, half), |(r, l), (lr, ll)| (r.min(lr), l.max(ll)))
}

/// Control points across the carriageway (right edge, middle, left edge) at four stations
/// of `first` evenly from `from` to `to`.
fn control_points(first: &RoadLane, from: f64, to: f64, right: f64, left: f64) -> Vec<[f64; 2]> {
    let stations = (0..4).map(|k| from + (to - from) * f64::from(k) / 3.0);
    let across = [right, 0.5 * (right + left), left];
    stations
        .flat_map(|s| across.map(|lateral| first.beside(s, lateral).map(|on| on.point)))
        .flatten()
        .collect()
}

/// A camera at `centre` aimed at the middle of the points' directions, with the longest focal
/// length (within [`FOCAL_RANGE_PX`]) that keeps them all in the image; `None` if none does.
fn frame(centre: [f64; 3], points: &[[f64; 2]], size: [f64; 2]) -> Option<PinholeCamera> {
    let foot = [centre[0], centre[1]];
    let ahead = points.iter().find(|p| dist(**p, foot) > 0.0)?;
    let reference = bearing(foot, *ahead);
    let angles = points.iter().filter(|p| dist(**p, foot) > 0.0).map(|p| {
        let yaw = (bearing(foot, *p) - reference + 540.0).rem_euclid(360.0) - 180.0;
        let down = centre[2].atan2(dist(*p, foot)).to_degrees();
        (yaw, down)
    });
    let (yaw, down) = angles.fold((Extent::EMPTY, Extent::EMPTY), |(y, d), (a, b)| {
        (y.with(a), d.with(b))
    });
    let fit = |extent: Extent, half_px: f64| FILL * half_px / extent.half().to_radians().tan();
    let focal = fit(yaw, size[0] / 2.0).min(fit(down, size[1] / 2.0));
    let mut focal = focal.clamp(FOCAL_RANGE_PX.0, FOCAL_RANGE_PX.1);
    let bearing_deg = (reference + yaw.mid()).rem_euclid(360.0);
    while focal >= FOCAL_RANGE_PX.0 {
        let camera = PinholeCamera::with_lens(centre, bearing_deg, down.mid(), focal, size);
        if points.iter().all(|p| camera.project(*p).is_some()) {
            return Some(camera);
        }
        focal *= 0.9;
    }
    None
}

/// The range of a set of angles, degrees.
#[derive(Debug, Clone, Copy)]
struct Extent {
    lo: f64,
    hi: f64,
}

impl Extent {
    const EMPTY: Extent = Extent {
        lo: f64::INFINITY,
        hi: f64::NEG_INFINITY,
    };

    fn with(self, v: f64) -> Extent {
        Extent {
            lo: self.lo.min(v),
            hi: self.hi.max(v),
        }
    }

    fn mid(self) -> f64 {
        0.5 * (self.lo + self.hi)
    }

    /// Half the range, at least 0.1°.
    fn half(self) -> f64 {
        (0.5 * (self.hi - self.lo)).max(0.1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geodesy::LatLon;
    use roadside::cones::closures;

    fn road() -> Road {
        let r = LatLon::from_degrees(39.7392, -104.9903).unwrap();
        Road::straight(r, 90.0, 800.0, (2, 0), 3.6, 40.0)
    }

    #[test]
    fn cones_close_the_lane_and_are_in_view() {
        let road = road();
        let scene = zone_scene(&road, &[2], 420.0, 520.0, &Placement::default()).unwrap();
        // 14 stations 100/13 m apart, two edges each, and the taper's centre cone.
        assert_eq!(scene.cones.len(), 29);
        let zones = closures(&road, &scene.cones);
        assert_eq!(zones.len(), 1);
        assert_eq!(zones[0].lane, 2);
        assert!((zones[0].start_m - 420.0).abs() < 1e-9 && (zones[0].end_m - 520.0).abs() < 1e-9);
        assert_eq!(scene.control.len(), 12);
        let cam = scene.camera;
        // 40 m before the zone, 3 m right of lane 2's right edge (north -5.4), 8 m up.
        let c = cam.centre();
        assert!((c[0] - 380.0).abs() < 1e-9 && (c[1] + 8.4).abs() < 1e-9 && c[2] == 8.0);
        assert!(cam.pitch_deg() > 0.0 && cam.bearing_deg() < 90.0);
        assert!(scene.cones.iter().all(|p| cam.project(*p).is_some()));
        assert!(scene.control.iter().all(|p| cam.project(*p).is_some()));
    }

    #[test]
    fn bad_zones_are_refused() {
        let road = road();
        let p = Placement::default();
        assert_eq!(
            zone_scene(&road, &[7], 420.0, 520.0, &p),
            Err(SyntheticError::UnknownLane(7))
        );
        assert_eq!(
            zone_scene(&road, &[2], 520.0, 420.0, &p),
            Err(SyntheticError::BadZone)
        );
        assert_eq!(
            zone_scene(&road, &[], 420.0, 520.0, &p),
            Err(SyntheticError::BadZone)
        );
        // Both lanes closed: cones on both.
        let both = zone_scene(&road, &[1, 2], 420.0, 520.0, &p).unwrap();
        assert_eq!(closures(&road, &both.cones).len(), 2);
    }
}
