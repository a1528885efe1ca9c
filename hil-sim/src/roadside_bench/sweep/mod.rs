//! The camera sweep: one four-lane street with a work zone, drawn from many installs as a
//! DOT would mount them (poles 5-12 m, 10-40 degrees to the road, roll up to 1.5 degrees,
//! 1280x720 to 1920x1080, wide to tele lenses, sidewalk and road-centre poles, both
//! directions of traffic), with dense two-way traffic, people on the sidewalks and workers
//! in the closed lane, every size drawn as on the road ([`super::street::road_size`]).
//!
//! [`score`] runs the product's road-user pipeline on each install's frames and measures it
//! against the truth; [`bound`] says what no localizer could beat on each frame.

pub mod bound;
pub mod score;

use super::street::{road_size, Motion, Mover, RoadUser, World};
use super::synthetic_camera::PinholeCamera;
use roadside::rng::Prng;
use roadside::road_users::RoadUserClass;

/// Vehicles loop over this stretch of the street, metres north: a vehicle leaving one end
/// comes back at the other, so both ends lie more than 40 m (the scored range) from every
/// install, where a track coasting on after its vehicle left is not scored.
pub const TRAFFIC_LOOP_M: [f64; 2] = [-60.0, 160.0];
/// Vehicles a lane over the loop (one every 27.5 m).
const VEHICLES_A_LANE: usize = 8;

/// One camera install of the sweep.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Install {
    /// Short name.
    pub name: &'static str,
    /// What it is, for the table.
    pub what: &'static str,
    /// The camera.
    pub camera: PinholeCamera,
}

/// The sweep's street: four 3.5 m lanes (1 and 2 southbound, 3 northbound, 4 closed from
/// 25 m to 75 m for the work zone).
pub fn sweep_world() -> World {
    World::street(4, 3.5, (4, [25.0, 75.0]))
}

/// Pitch that aims the optical axis at the road `range_m` ahead of a pole `height_m` high.
fn aim(height_m: f64, range_m: f64) -> f64 {
    height_m.atan2(range_m).to_degrees()
}

/// The installs: the project's own camera, the one a DOT tried it on, and six more.
pub fn installs() -> Vec<Install> {
    let hd = [1920.0, 1080.0];
    let small = [1280.0, 720.0];
    let cam = |c: [f64; 3], bearing: f64, range: f64, f: f64, size: [f64; 2], roll: f64| {
        PinholeCamera::with_lens(c, bearing, aim(c[2], range), f, size).with_roll(roll)
    };
    vec![
        Install {
            name: "own",
            what: "west sidewalk 6 m, 18 deg, 1920x1080 f2800",
            camera: PinholeCamera::with_lens([-6.0, 0.0, 6.0], 18.0, 11.0, 2800.0, hd),
        },
        Install {
            name: "dot",
            what: "west sidewalk 8.5 m, 27 deg, roll 0.7, 1280x720 f1100",
            camera: cam([-4.0, -2.0, 8.5], 27.0, 22.0, 1100.0, small, 0.7),
        },
        Install {
            name: "east5",
            what: "east sidewalk 5 m, 10 deg, 1920x1080 f2400",
            camera: cam([17.0, -8.0, 5.0], 350.0, 30.0, 2400.0, hd, 0.0),
        },
        Install {
            name: "median10",
            what: "road-centre pole 10 m, 15 deg, 1920x1080 f1500",
            camera: cam([7.0, -6.0, 10.0], 15.0, 22.0, 1500.0, hd, 0.0),
        },
        Install {
            name: "mast12",
            what: "west mast 12 m, 40 deg, wide 1280x720 f800",
            camera: cam([-8.0, 5.0, 12.0], 40.0, 20.0, 800.0, small, -0.4),
        },
        Install {
            name: "south7",
            what: "east sidewalk 7 m looking south, 20 deg, roll -1.5, 1920x1080 f2000",
            camera: cam([19.0, 85.0, 7.0], 200.0, 26.0, 2000.0, hd, -1.5),
        },
        Install {
            name: "low5",
            what: "west sidewalk 5 m, 12 deg, tele 1280x720 f1800",
            camera: cam([-3.0, -12.0, 5.0], 12.0, 32.0, 1800.0, small, 0.3),
        },
        Install {
            name: "east9",
            what: "east sidewalk 9 m, 30 deg, roll 1.5, 1920x1080 f1800",
            camera: cam([19.0, 0.0, 9.0], 330.0, 24.0, 1800.0, hd, 1.5),
        },
    ]
}

/// Pairs of installs that watch the zone together (indices into [`installs`]).
pub const PAIRS: [(usize, usize); 2] = [(0, 5), (1, 7)];

fn mover(
    movers: &mut Vec<Mover>,
    class: RoadUserClass,
    at: [f64; 2],
    motion: Motion,
    rng: &mut Prng,
) {
    movers.push(Mover {
        start: RoadUser {
            id: movers.len() as u32,
            class,
            centre: at,
            extent: road_size(class, rng),
            velocity: [0.0, 0.0],
        },
        motion,
    });
}

/// Dense two-way traffic on [`sweep_world`]: eight vehicles a lane in lanes 1-3 (every
/// class, 9-12 m/s, cyclists 4-5 m/s, looping over [`TRAFFIC_LOOP_M`]), people
/// walking up and down both sidewalks, and five workers in the closed lane (two pacing
/// across it, one walking up and down it, two standing).
pub fn sweep_traffic(world: &World, seed: u64) -> Vec<Mover> {
    use RoadUserClass::{Bus, Car, Cyclist, Motorcycle, Pedestrian, Truck, Van};
    let mut rng = Prng::new(seed);
    let mut movers = Vec::new();
    let [a, b] = TRAFFIC_LOOP_M;
    let lanes: [(u32, f64, [RoadUserClass; VEHICLES_A_LANE]); 3] = [
        (1, -11.0, [Car, Car, Van, Car, Bus, Car, Van, Car]),
        (2, -9.0, [Car, Truck, Motorcycle, Van, Car, Car, Truck, Car]),
        (3, 12.0, [Car, Van, Cyclist, Bus, Car, Motorcycle, Car, Van]),
    ];
    for (lane, speed_mps, classes) in lanes {
        let phase = rng.next_f64() * (b - a);
        for (k, class) in classes.into_iter().enumerate() {
            let y = a + (phase + (b - a) * k as f64 / VEHICLES_A_LANE as f64) % (b - a);
            let x = world.lane_centre_x(lane) + 0.4 * (rng.next_f64() - 0.5);
            let speed = if class == Cyclist {
                speed_mps / 2.5
            } else {
                speed_mps
            };
            let motion = Motion::Cruise {
                speed_mps: speed,
                between: TRAFFIC_LOOP_M,
            };
            mover(&mut movers, class, [x, y], motion, &mut rng);
        }
    }
    let road = world.road_width_m();
    // People walk up and down the sidewalks (a looping walker would jump back in view).
    for (x, speed) in [
        (-3.0, 1.3),
        (-4.2, 1.1),
        (road + 3.0, 1.4),
        (road + 4.0, 1.2),
    ] {
        let y = 5.0 + 70.0 * rng.next_f64();
        let motion = Motion::Stroll {
            between: [0.0, 80.0],
            speed_mps: speed,
        };
        mover(&mut movers, Pedestrian, [x, y], motion, &mut rng);
    }
    let closed = world.lane_centre_x(world.closed.0);
    let half = world.lane_width_m / 2.0;
    let across = Motion::Pace {
        between: [closed - half + 0.5, closed + half - 0.5],
        speed_mps: 0.9,
    };
    let along = Motion::Stroll {
        between: [36.0, 54.0],
        speed_mps: 1.0,
    };
    let workers = [
        ([closed, 33.0], across),
        ([closed - 0.6, 58.0], across),
        ([closed + 0.5, 45.0], along),
        ([closed - half + 0.6, 40.0], Motion::Stand),
        ([closed - 0.9, 66.0], Motion::Stand),
    ];
    for (at, motion) in workers {
        mover(&mut movers, Pedestrian, at, motion, &mut rng);
    }
    movers
}
