//! A lane map: lane centrelines in a local east/north frame (metres) around a reference
//! point, each in its direction of travel, with width and speed limit.

use geodesy::LatLon;
use geodesy::LocalFrame64;

/// One lane of the map.
#[derive(Debug, Clone, PartialEq)]
pub struct RoadLane {
    /// Lane id (J2735 `LaneID`, 1-255).
    pub id: u8,
    /// Width, metres.
    pub width_m: f64,
    /// Speed limit, km/h.
    pub speed_limit_kmh: f64,
    /// Centreline nodes, east/north metres from the reference, in the direction of travel.
    pub centre: Vec<[f64; 2]>,
}

/// A position on a lane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OnLane {
    /// East/north metres from the reference.
    pub point: [f64; 2],
    /// Bearing of travel there, degrees clockwise from north.
    pub bearing_deg: f64,
}

impl RoadLane {
    /// Length of the centreline, metres.
    pub fn length_m(&self) -> f64 {
        self.centre.windows(2).map(|w| dist(w[0], w[1])).sum()
    }

    /// The point `station` metres along the centreline (clamped to its ends).
    pub fn at(&self, station: f64) -> Option<OnLane> {
        let mut left = station.max(0.0);
        let mut last = None;
        for w in self.centre.windows(2) {
            let len = dist(w[0], w[1]);
            let bearing_deg = bearing(w[0], w[1]);
            last = Some(OnLane {
                point: w[1],
                bearing_deg,
            });
            if len > 0.0 && left <= len {
                let f = left / len;
                return Some(OnLane {
                    point: [
                        w[0][0] + f * (w[1][0] - w[0][0]),
                        w[0][1] + f * (w[1][1] - w[0][1]),
                    ],
                    bearing_deg,
                });
            }
            left -= len;
        }
        last
    }

    /// The point `lateral` metres to the left of the centreline at `station`.
    pub fn beside(&self, station: f64, lateral: f64) -> Option<OnLane> {
        let on = self.at(station)?;
        let b = on.bearing_deg.to_radians();
        // Left of a bearing b (clockwise from north) is the direction (-cos b, sin b).
        Some(OnLane {
            point: [
                on.point[0] - lateral * b.cos(),
                on.point[1] + lateral * b.sin(),
            ],
            ..on
        })
    }

    /// Station of the centreline point nearest to `p`, and the distance to it.
    pub fn project(&self, p: [f64; 2]) -> Option<(f64, f64)> {
        let mut best: Option<(f64, f64)> = None;
        let mut start = 0.0;
        for w in self.centre.windows(2) {
            let (dx, dy) = (w[1][0] - w[0][0], w[1][1] - w[0][1]);
            let len2 = dx * dx + dy * dy;
            let len = len2.sqrt();
            if len2 > 0.0 {
                let t = (((p[0] - w[0][0]) * dx + (p[1] - w[0][1]) * dy) / len2).clamp(0.0, 1.0);
                let d = dist(p, [w[0][0] + t * dx, w[0][1] + t * dy]);
                if best.is_none_or(|b| d < b.1) {
                    best = Some((start + t * len, d));
                }
            }
            start += len;
        }
        best
    }

    /// Signed distance of `p` to the left of the centreline (negative to the right).
    pub fn lateral(&self, p: [f64; 2]) -> Option<f64> {
        let (station, _) = self.project(p)?;
        let on = self.at(station)?;
        let b = on.bearing_deg.to_radians();
        Some(-(p[0] - on.point[0]) * b.cos() + (p[1] - on.point[1]) * b.sin())
    }

    /// The centreline between stations `from` and `to` (both clamped), with its nodes.
    pub fn slice(&self, from: f64, to: f64) -> Vec<[f64; 2]> {
        let mut out = Vec::new();
        let Some(first) = self.at(from) else {
            return out;
        };
        out.push(first.point);
        let mut start = 0.0;
        for w in self.centre.windows(2) {
            start += dist(w[0], w[1]);
            if start > from && start < to {
                out.push(w[1]);
            }
        }
        if let Some(last) = self.at(to) {
            out.push(last.point);
        }
        out
    }
}

/// A lane map around a reference point.
#[derive(Debug, Clone)]
pub struct Road {
    /// Reference point (J2735 `refPoint`).
    pub reference: LatLon,
    /// Lanes.
    pub lanes: Vec<RoadLane>,
    frame: LocalFrame64,
}

impl Road {
    /// A road around `reference` with these lanes.
    pub fn new(reference: LatLon, lanes: Vec<RoadLane>) -> Self {
        Self {
            reference,
            lanes,
            frame: LocalFrame64::new(reference, 0.0),
        }
    }

    /// A straight divided road through the reference point along `bearing_deg`: `forward`
    /// lanes in that direction (ids 1.. from left to right, the leftmost beside the
    /// median) and `backward` lanes the other way (ids after them, also left to right for
    /// their traffic), `width_m` wide, from the reference point to `length_m` ahead.
    pub fn straight(
        reference: LatLon,
        bearing_deg: f64,
        length_m: f64,
        (forward, backward): (u8, u8),
        width_m: f64,
        speed_limit_kmh: f64,
    ) -> Self {
        let b = bearing_deg.to_radians();
        let (ux, uy) = (b.sin(), b.cos());
        let (lx, ly) = (-uy, ux); // left of the forward direction
        Self::divided(
            reference,
            (forward, backward),
            width_m,
            speed_limit_kmh,
            |left_m| {
                let a = [lx * left_m, ly * left_m];
                vec![a, [a[0] + ux * length_m, a[1] + uy * length_m]]
            },
        )
    }

    /// A road along a circular arc: like [`Road::straight`] but the reference lane's
    /// centreline turns with radius `radius_m` (positive: to the right) over `length_m`,
    /// with a node every `node_m` metres; the other lanes run parallel to it.
    #[allow(clippy::too_many_arguments)]
    pub fn arc(
        reference: LatLon,
        bearing_deg: f64,
        radius_m: f64,
        length_m: f64,
        node_m: f64,
        (forward, backward): (u8, u8),
        width_m: f64,
        speed_limit_kmh: f64,
    ) -> Self {
        let b0 = bearing_deg.to_radians();
        let right = radius_m.signum();
        let r = radius_m.abs().max(1.0);
        // The centre of the turn lies `r` to the right (or left) of the reference point.
        let side = b0 + right * std::f64::consts::FRAC_PI_2;
        let centre = [r * side.sin(), r * side.cos()];
        let steps = (length_m / node_m.max(1.0)).ceil().max(1.0) as usize;
        let lane_at = |left_m: f64, k: usize| {
            let turned = b0 + right * (k as f64 * length_m / steps as f64) / r;
            // Radius of this lane: left of a right turn is outside (longer radius).
            let lr = r + right * left_m;
            let from_centre = turned - right * std::f64::consts::FRAC_PI_2;
            [
                centre[0] + lr * from_centre.sin(),
                centre[1] + lr * from_centre.cos(),
            ]
        };
        Self::divided(
            reference,
            (forward, backward),
            width_m,
            speed_limit_kmh,
            |left_m| (0..=steps).map(|k| lane_at(left_m, k)).collect(),
        )
    }

    /// The lanes of a divided road: `forward` lanes (ids 1.., left to right, the first on
    /// the reference line) and, past a median one lane wide, `backward` lanes (ids after
    /// them, left to right for their traffic). `centreline(left_m)` gives the forward
    /// direction's centreline `left_m` metres left of the reference line; backward lanes
    /// run it reversed.
    fn divided(
        reference: LatLon,
        (forward, backward): (u8, u8),
        width_m: f64,
        speed_limit_kmh: f64,
        centreline: impl Fn(f64) -> Vec<[f64; 2]>,
    ) -> Self {
        let median = width_m;
        let forward_lanes = (0..forward).map(|k| (1 + k, -(k as f64) * width_m, false));
        let backward_lanes =
            (0..backward).map(|k| (forward + 1 + k, median + (1 + k) as f64 * width_m, true));
        let lanes = forward_lanes
            .chain(backward_lanes)
            .map(|(id, left_m, reverse)| {
                let mut centre = centreline(left_m);
                if reverse {
                    centre.reverse();
                }
                RoadLane {
                    id,
                    width_m,
                    speed_limit_kmh,
                    centre,
                }
            })
            .collect();
        Self::new(reference, lanes)
    }

    /// The lane with this id.
    pub fn lane(&self, id: u8) -> Option<&RoadLane> {
        self.lanes.iter().find(|l| l.id == id)
    }

    /// WGS84 position of a local point.
    pub fn to_wgs84(&self, p: [f64; 2]) -> Option<LatLon> {
        self.frame.to_wgs84(p[0], p[1])
    }

    /// Local point of a WGS84 position.
    pub fn to_local(&self, p: LatLon) -> [f64; 2] {
        let (e, n) = self.frame.to_local(p);
        [e, n]
    }
}

/// Distance between two points, metres.
pub fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (b[0] - a[0]).hypot(b[1] - a[1])
}

/// Bearing from `a` to `b`, degrees clockwise from north in [0, 360).
pub fn bearing(a: [f64; 2], b: [f64; 2]) -> f64 {
    (b[0] - a[0])
        .atan2(b[1] - a[1])
        .to_degrees()
        .rem_euclid(360.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn road() -> Road {
        let r = LatLon::from_degrees(39.75, -104.99).unwrap();
        Road::straight(r, 90.0, 1000.0, (3, 2), 3.6, 80.0)
    }

    #[test]
    fn straight_road_lanes_left_to_right() {
        let road = road();
        // Eastbound: left is north, so lane 1 is the northernmost of 1-3.
        let north = |id| road.lane(id).unwrap().at(500.0).unwrap().point[1];
        assert!((north(1) - 0.0).abs() < 1e-9);
        assert!((north(2) + 3.6).abs() < 1e-9 && (north(3) + 7.2).abs() < 1e-9);
        // Westbound lanes 4 and 5 lie north of the median; for their traffic (west) left
        // is south, so lane 4 (left) is nearer the median than lane 5.
        assert!(north(4) > 0.0 && north(5) > north(4));
        let w = road.lane(4).unwrap().at(0.0).unwrap();
        assert!((w.bearing_deg - 270.0).abs() < 1e-9 && (w.point[0] - 1000.0).abs() < 1e-9);
        assert!((road.lane(1).unwrap().length_m() - 1000.0).abs() < 1e-9);
    }

    #[test]
    fn stations_beside_and_slices() {
        let lane = RoadLane {
            id: 1,
            width_m: 3.5,
            speed_limit_kmh: 50.0,
            centre: vec![[0.0, 0.0], [0.0, 100.0], [100.0, 100.0]],
        };
        assert_eq!(lane.at(150.0).unwrap().point, [50.0, 100.0]);
        assert!((lane.at(150.0).unwrap().bearing_deg - 90.0).abs() < 1e-9);
        assert_eq!(lane.at(500.0).unwrap().point, [100.0, 100.0]);
        // Heading north, 2 m to the left is west.
        let p = lane.beside(50.0, 2.0).unwrap().point;
        assert!((p[0] + 2.0).abs() < 1e-9 && (p[1] - 50.0).abs() < 1e-9);
        assert_eq!(
            lane.slice(50.0, 150.0),
            vec![[0.0, 50.0], [0.0, 100.0], [50.0, 100.0]]
        );
    }

    #[test]
    fn arcs_are_parallel_and_turn_the_right_way() {
        let r = LatLon::from_degrees(39.75, -104.99).unwrap();
        let road = Road::arc(r, 0.0, 500.0, 400.0, 20.0, (2, 1), 3.6, 60.0);
        let l1 = road.lane(1).unwrap();
        // A right turn from north: heading east of north at the end, 400/500 rad turned.
        let end = l1.at(l1.length_m()).unwrap();
        assert!((end.bearing_deg - (400.0f64 / 500.0).to_degrees()).abs() < 1.5);
        assert!((l1.length_m() - 400.0).abs() < 1.0);
        // Lane 2 is 3.6 m to the right of lane 1 everywhere.
        let l2 = road.lane(2).unwrap();
        for s in [0.0, 100.0, 250.0, 390.0] {
            let p = l2.at(s).unwrap().point;
            assert!((l1.lateral(p).unwrap() + 3.6).abs() < 0.05, "at {s}");
        }
        // Lane 3 runs the other way, left of lane 1 (across the median).
        let l3 = road.lane(3).unwrap();
        let p = l3.at(200.0).unwrap().point;
        assert!(l1.lateral(p).unwrap() > 3.6);
    }

    #[test]
    fn local_frame_round_trip() {
        let road = road();
        let p = road.to_wgs84([1234.5, -678.9]).unwrap();
        let q = road.to_local(p);
        assert!((q[0] - 1234.5).abs() < 0.02 && (q[1] + 678.9).abs() < 0.02);
    }
}
