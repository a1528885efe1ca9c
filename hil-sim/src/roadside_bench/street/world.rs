//! The static world of the synthetic scene: a straight three-lane road running north with
//! lane markings, a stop line and a crossing, curbs and sidewalks, lamp posts, a closed lane
//! behind cones, and buildings with windows on both sides (the long straight edges the
//! vanishing points are found from). Local metres: x east, y north, z up.

/// A flat convex polygon on the road (z = 0) and its colour.
#[derive(Debug, Clone, PartialEq)]
pub struct Patch {
    /// Corners (x, y), in order.
    pub corners: Vec<[f64; 2]>,
    /// Colour.
    pub colour: [u8; 3],
}

/// An axis-aligned solid box standing on the road.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Solid {
    /// Lowest corner (x, y, z).
    pub min: [f64; 3],
    /// Highest corner.
    pub max: [f64; 3],
    /// Base colour (faces are shaded from it).
    pub colour: [u8; 3],
    /// Windows on its walls (buildings).
    pub windows: bool,
}

/// The static scene.
#[derive(Debug, Clone, PartialEq)]
pub struct World {
    /// Ground patches, drawn in order.
    pub ground: Vec<Patch>,
    /// Solids (buildings, posts, cones).
    pub solids: Vec<Solid>,
    /// Width of one lane, metres; lane 1 is the westmost, from x = 0.
    pub lane_width_m: f64,
    /// Number of lanes.
    pub lanes: u32,
    /// The closed lane (1-based) and its stations `[from, to]` along y.
    pub closed: (u32, [f64; 2]),
}

fn rect(x: [f64; 2], y: [f64; 2], colour: [u8; 3]) -> Patch {
    Patch {
        corners: vec![[x[0], y[0]], [x[1], y[0]], [x[1], y[1]], [x[0], y[1]]],
        colour,
    }
}

fn solid(min: [f64; 3], max: [f64; 3], colour: [u8; 3], windows: bool) -> Solid {
    Solid {
        min,
        max,
        colour,
        windows,
    }
}

const WHITE: [u8; 3] = [235, 235, 230];
const ASPHALT: [u8; 3] = [62, 62, 66];

impl World {
    /// The work-zone street: three 3.5 m lanes from y = -20 m to 400 m, lane 3 closed from
    /// 25 m to 75 m.
    pub fn work_zone() -> Self {
        Self::street(3, 3.5, (3, [25.0, 75.0]))
    }

    /// A street of `lanes` lanes `lane_width_m` wide from y = -20 m to 400 m, lane
    /// `closed.0` (1-based) closed behind cones along its west edge from `closed.1[0]` to
    /// `closed.1[1]` metres north.
    pub fn street(lanes: u32, lane_width_m: f64, closed: (u32, [f64; 2])) -> Self {
        let (lw, lanes) = (lane_width_m, lanes.max(1));
        let right = lw * f64::from(lanes);
        let y = [-20.0, 400.0];
        let mut ground = vec![
            rect([-60.0, 70.0], y, [86, 110, 70]),
            rect([-6.0, -1.3], y, [150, 150, 146]),
            rect([right + 1.3, right + 6.0], y, [150, 150, 146]),
            rect([-1.3, -1.0], y, [196, 196, 190]),
            rect([right + 1.0, right + 1.3], y, [196, 196, 190]),
            rect([-1.0, right + 1.0], y, ASPHALT),
            rect([0.0, 0.15], y, WHITE),
            rect([right - 0.15, right], y, WHITE),
        ];
        for k in 1..lanes {
            let x = lw * f64::from(k);
            let mut y0 = -20.0;
            while y0 < 400.0 {
                ground.push(rect([x - 0.075, x + 0.075], [y0, y0 + 3.0], WHITE));
                y0 += 9.0;
            }
        }
        ground.push(rect([0.0, right], [88.0, 88.5], WHITE));
        let mut x0 = 0.25;
        while x0 + 0.5 < right {
            ground.push(rect([x0, x0 + 0.5], [90.0, 94.0], WHITE));
            x0 += 1.0;
        }
        let mut solids = buildings(-7.0, -1.0);
        solids.extend(buildings(right + 7.0, 1.0));
        for k in 0..14 {
            let yp = -10.0 + 30.0 * f64::from(k);
            for xp in [-1.8, right + 1.8] {
                solids.push(solid(
                    [xp - 0.1, yp - 0.1, 0.0],
                    [xp + 0.1, yp + 0.1, 8.0],
                    [90, 92, 96],
                    false,
                ));
            }
        }
        let xc = lw * f64::from(closed.0.clamp(1, lanes) - 1) + 0.35;
        let mut yc = closed.1[0];
        while yc <= closed.1[1] {
            solids.push(solid(
                [xc - 0.15, yc - 0.15, 0.0],
                [xc + 0.15, yc + 0.15, 0.7],
                [240, 110, 20],
                false,
            ));
            yc += 6.0;
        }
        Self {
            ground,
            solids,
            lane_width_m: lw,
            lanes,
            closed,
        }
    }

    /// East of the centre of lane `lane` (1-based).
    pub fn lane_centre_x(&self, lane: u32) -> f64 {
        self.lane_width_m * (f64::from(lane) - 0.5)
    }

    /// Width of the carriageway, metres.
    pub fn road_width_m(&self) -> f64 {
        self.lane_width_m * f64::from(self.lanes)
    }
}

/// A row of buildings whose road-side walls stand at `x`, extending away from the road in
/// direction `side` (-1 west, +1 east), with gaps between them.
fn buildings(x: f64, side: f64) -> Vec<Solid> {
    let blocks = [
        (-10.0, 14.0, 11.0),
        (18.0, 40.0, 15.0),
        (45.0, 70.0, 9.0),
        (76.0, 105.0, 13.0),
        (110.0, 150.0, 17.0),
        (156.0, 200.0, 10.0),
        (206.0, 260.0, 14.0),
    ];
    let colours = [
        [168, 140, 120],
        [150, 156, 170],
        [182, 170, 146],
        [130, 120, 118],
    ];
    blocks
        .iter()
        .enumerate()
        .map(|(i, &(y0, y1, h))| {
            let depth = 12.0 + 2.0 * (i % 3) as f64;
            let (xa, xb) = if side < 0.0 {
                (x - depth, x)
            } else {
                (x, x + depth)
            };
            solid([xa, y0, 0.0], [xb, y1, h], colours[i % colours.len()], true)
        })
        .collect()
}
