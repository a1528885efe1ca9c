//! Tracked workers on the air: every confirmed track of a person inside the work-zone area
//! becomes a J2735 PSM ([`crate::messages::build_psm`]) on each broadcast tick (10 Hz), with a
//! temporary id that stays with the track, its position, accuracy, speed and heading, and
//! its positions of the last seconds as path history.

use std::collections::BTreeMap;

use super::polygon::distance_to_boundary;
use super::tracker::Track;
use crate::clock::Utc;
use crate::messages::{build_psm, Worker, MAX_CRUMBS};
use crate::road::Road;
use j2735::MessageFrame;

/// A crumb of path history is kept every this many seconds.
pub const CRUMB_INTERVAL_S: f64 = 1.0;
/// Workers this near the area's outline (metres) still count as inside.
pub const AREA_MARGIN_M: f64 = 1.0;

/// Is `p` inside `polygon` (even-odd rule)?
fn inside(polygon: &[[f64; 2]], p: [f64; 2]) -> bool {
    let n = polygon.len();
    let mut odd = false;
    for i in 0..n {
        let (a, b) = (polygon[i], polygon[(i + 1) % n]);
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if p[0] < x {
                odd = !odd;
            }
        }
    }
    odd
}

/// The per-track state of the broadcaster.
#[derive(Debug, Clone, Default)]
struct Trail {
    /// Positions of the path history, newest last, with their time.
    crumbs: Vec<([f64; 2], f64)>,
    /// The track's `msgCnt` (J2735 counts per sender, here per temporary id).
    msg_cnt: u8,
}

/// Turns tracks into workers' PSMs.
#[derive(Debug, Clone)]
pub struct WorkerBroadcaster {
    area: Vec<[f64; 2]>,
    salt: u32,
    trails: BTreeMap<u32, Trail>,
    /// PSMs that could not be built (a value out of the standard's range), counted.
    pub failed: u64,
}

impl WorkerBroadcaster {
    /// A broadcaster for the work-zone area `area` (a polygon in local metres); `salt`
    /// scrambles the temporary ids (a new one at each start, so ids do not repeat).
    pub fn new(area: Vec<[f64; 2]>, salt: u32) -> Self {
        Self {
            area,
            salt,
            trails: BTreeMap::new(),
            failed: 0,
        }
    }

    /// The temporary id of track `id`.
    pub fn temporary_id(&self, id: u32) -> [u8; 4] {
        (id.wrapping_mul(0x9e37_79b1) ^ self.salt.rotate_left(13)).to_be_bytes()
    }

    /// Does a track go on the air: a person inside the area (or within [`AREA_MARGIN_M`]).
    pub fn concerns(&self, t: &Track) -> bool {
        t.class.is_person()
            && (inside(&self.area, t.position)
                || distance_to_boundary(t.position, &self.area) <= AREA_MARGIN_M)
    }

    /// The PSMs of one broadcast tick at `time_s` (the tracks' clock) and `now` (UTC):
    /// one per track that [`concerns`](Self::concerns) the zone. Tracks no longer given are
    /// forgotten.
    pub fn tick(
        &mut self,
        tracks: &[Track],
        time_s: f64,
        now: Utc,
        site: &Road,
    ) -> Vec<Box<MessageFrame>> {
        self.trails
            .retain(|id, _| tracks.iter().any(|t| t.id == *id));
        let mut out = Vec::new();
        let concerned: Vec<&Track> = tracks.iter().filter(|t| self.concerns(t)).collect();
        for t in concerned {
            let id = self.temporary_id(t.id);
            let trail = self.trails.entry(t.id).or_default();
            if trail
                .crumbs
                .last()
                .is_none_or(|c| time_s - c.1 >= CRUMB_INTERVAL_S)
            {
                trail.crumbs.push((t.position, time_s));
                if trail.crumbs.len() > MAX_CRUMBS + 1 {
                    trail.crumbs.remove(0);
                }
            }
            let history = trail
                .crumbs
                .iter()
                .rev()
                .filter(|c| time_s - c.1 > 0.0)
                .filter_map(|c| Some((site.to_wgs84(c.0)?, time_s - c.1)))
                .take(MAX_CRUMBS)
                .collect();
            let msg_cnt = trail.msg_cnt;
            trail.msg_cnt = (msg_cnt + 1) % 128;
            let Some(position) = site.to_wgs84(t.position) else {
                self.failed += 1;
                continue;
            };
            let worker = Worker {
                id,
                position,
                accuracy: t.position_ellipse,
                speed_mps: t.speed_mps,
                heading_deg: t.heading_deg,
                history,
            };
            match build_psm(&worker, now, msg_cnt) {
                Ok(frame) => out.push(frame),
                Err(_) => self.failed += 1,
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ellipse::ErrorEllipse;
    use crate::road_users::RoadUserClass;
    use geodesy::LatLon;
    use j2735::MessageFrameValue;

    fn track(id: u32, class: RoadUserClass, position: [f64; 2], speed: f64) -> Track {
        Track {
            id,
            class,
            position,
            velocity: [speed, 0.0],
            speed_mps: speed,
            heading_deg: (speed > 0.0).then_some(90.0),
            position_sigma_m: 0.1,
            position_ellipse: ErrorEllipse::circle(0.1),
            speed_sigma_mps: 0.05,
            heading_sigma_deg: None,
            first_seen_s: 0.0,
            last_seen_s: 0.0,
            hits: 5,
        }
    }

    #[test]
    fn people_in_the_zone_go_out_with_a_stable_id_and_their_trail() {
        let site = Road::new(LatLon::from_degrees(42.0, -83.0).unwrap(), Vec::new());
        // The closed lane: x 7-10.5, y 25-75.
        let area = vec![[7.0, 25.0], [10.5, 25.0], [10.5, 75.0], [7.0, 75.0]];
        let mut b = WorkerBroadcaster::new(area, 0x1234_5678);
        let mut last = Vec::new();
        for k in 0..30 {
            let t = f64::from(k) * 0.1;
            let tracks = [
                track(3, RoadUserClass::Pedestrian, [8.0 + 0.5 * t, 40.0], 0.5),
                // Just outside the lane, within the margin: still on the air.
                track(4, RoadUserClass::Pedestrian, [6.2, 50.0], 0.0),
                // A car in the zone, and a person far from it: not.
                track(5, RoadUserClass::Car, [8.5, 30.0], 0.0),
                track(6, RoadUserClass::Pedestrian, [1.0, 40.0], 0.0),
            ];
            let frames = b.tick(
                &tracks,
                t,
                Utc::from_unix_ms(1_700_000_000_000 + 100 * k as u64),
                &site,
            );
            assert_eq!(frames.len(), 2);
            last = frames;
        }
        let MessageFrameValue::PersonalSafetyMessage(psm) = &last[0].value else {
            panic!("not a PSM");
        };
        assert_eq!(psm.id.0, b.temporary_id(3));
        assert_ne!(b.temporary_id(3), b.temporary_id(4));
        // 8 + 0.5 * 2.9 = 9.45 m east, 40 m north of the origin.
        let want = site.to_wgs84([9.45, 40.0]).unwrap();
        let lat = f64::from(psm.position.lat.get()) / 1e7;
        let lon = f64::from(psm.position.long.get()) / 1e7;
        assert!((lat - want.lat_deg()).abs() < 2e-7 && (lon - want.lon_deg()).abs() < 2e-7);
        // 0.5 m/s in 0.02 m/s units; heading 90° in 0.0125° units.
        assert_eq!(psm.speed.get(), 25);
        assert_eq!(psm.heading.get(), 7200);
        // Crumbs at 0, 1 and 2 s: three in the history at 2.9 s.
        let crumbs = psm
            .path_history
            .as_ref()
            .map_or(0, |h| h.crumb_data.0.len());
        assert_eq!(crumbs, 3);
        // Tracks gone are forgotten.
        assert!(b
            .tick(&[], 3.0, Utc::from_unix_ms(1_700_000_003_000), &site)
            .is_empty());
        assert!(b.trails.is_empty());
    }
}
