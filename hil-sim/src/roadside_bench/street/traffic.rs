//! Moving road users for a sequence of frames: traffic through the open lanes of the street
//! and workers in the closed lane, each with a stable id, as the truth of a video.

use super::render::RoadUser;
use super::world::World;
use roadside::rng::Prng;
use roadside::road_users::class::{Extent, RoadUserClass};

/// The stretch of street the traffic loops over, metres north (a road user leaving its far
/// end comes back at its near end).
pub const LOOP_M: [f64; 2] = [0.0, 72.0];

/// A road user and how it moves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mover {
    /// The road user at time 0.
    pub start: RoadUser,
    /// Its motion.
    pub motion: Motion,
}

/// How a road user moves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Motion {
    /// Drives north along its lane at a constant speed, looping over [`LOOP_M`].
    Drive {
        /// Speed, m/s.
        speed_mps: f64,
    },
    /// Walks east and west between two x positions, slowing down to turn (a sine in time).
    Pace {
        /// West and east turning points, metres.
        between: [f64; 2],
        /// Top speed (midway), m/s.
        speed_mps: f64,
    },
    /// Walks north and south between two stations (metres north), slowing down to turn
    /// (a sine in time), starting north.
    Stroll {
        /// South and north turning points, metres north.
        between: [f64; 2],
        /// Top speed (midway), m/s.
        speed_mps: f64,
    },
    /// Moves along the road (north for a positive speed, south for a negative one) at a
    /// constant speed, looping over `between` (metres north).
    Cruise {
        /// Speed, m/s (negative: south).
        speed_mps: f64,
        /// The stretch looped over, metres north.
        between: [f64; 2],
    },
    /// Stands still.
    Stand,
}

fn sized(class: RoadUserClass, rng: &mut Prng) -> Extent {
    super::road_size(class, rng)
}

/// Traffic through a work zone: lane 1 carries cars and a motorcycle at 12 m/s, lane 2 vans,
/// a truck and a bus at 9 m/s (each lane's vehicles evenly spaced over the loop), and the
/// closed lane holds three workers: one pacing across it and two standing, one by its
/// west edge.
pub fn work_zone_traffic(world: &World, seed: u64) -> Vec<Mover> {
    let mut rng = Prng::new(seed);
    let loop_len = LOOP_M[1] - LOOP_M[0];
    let mut movers = Vec::new();
    let lanes: [(u32, f64, &[RoadUserClass]); 2] = [
        (
            1,
            12.0,
            &[
                RoadUserClass::Car,
                RoadUserClass::Motorcycle,
                RoadUserClass::Car,
            ],
        ),
        (
            2,
            9.0,
            &[RoadUserClass::Van, RoadUserClass::Truck, RoadUserClass::Bus],
        ),
    ];
    for (lane, speed_mps, classes) in lanes {
        let phase = rng.next_f64() * loop_len;
        for (k, &class) in classes.iter().enumerate() {
            let y = LOOP_M[0] + (phase + loop_len * k as f64 / classes.len() as f64) % loop_len;
            let x = world.lane_centre_x(lane) + 0.3 * (rng.next_f64() - 0.5);
            movers.push(mover(
                movers.len(),
                class,
                [x, y],
                sized(class, &mut rng),
                Motion::Drive { speed_mps },
            ));
        }
    }
    let closed = world.lane_centre_x(world.closed.0);
    let half = world.lane_width_m / 2.0;
    let person = |rng: &mut Prng| sized(RoadUserClass::Pedestrian, rng);
    let pace = Motion::Pace {
        between: [closed - half + 0.5, closed + half - 0.5],
        speed_mps: 0.8,
    };
    let workers = [
        ([closed, 32.0], pace),
        ([closed - half + 0.6, 40.0], Motion::Stand),
        ([closed + 0.8, 52.0], Motion::Stand),
    ];
    for (at, motion) in workers {
        let e = person(&mut rng);
        movers.push(mover(
            movers.len(),
            RoadUserClass::Pedestrian,
            at,
            e,
            motion,
        ));
    }
    movers
}

fn mover(
    id: usize,
    class: RoadUserClass,
    centre: [f64; 2],
    extent: Extent,
    motion: Motion,
) -> Mover {
    Mover {
        start: RoadUser {
            id: id as u32,
            class,
            centre,
            extent,
            velocity: [0.0, 0.0],
        },
        motion,
    }
}

/// Where every mover is at time `t_s`, with its velocity.
pub fn users_at(movers: &[Mover], t_s: f64) -> Vec<RoadUser> {
    movers.iter().map(|m| at(m, t_s)).collect()
}

fn at(m: &Mover, t: f64) -> RoadUser {
    let mut u = m.start;
    match m.motion {
        Motion::Drive { speed_mps } => {
            u.centre[1] = looped(u.centre[1], LOOP_M, speed_mps, t);
            u.velocity = [0.0, speed_mps];
        }
        Motion::Cruise { speed_mps, between } => {
            u.centre[1] = looped(u.centre[1], between, speed_mps, t);
            u.velocity = [0.0, speed_mps];
        }
        Motion::Pace { between, speed_mps } => {
            let (x, v) = back_and_forth(u.centre[0], between, speed_mps, t);
            (u.centre[0], u.velocity) = (x, [v, 0.0]);
        }
        Motion::Stroll { between, speed_mps } => {
            let (y, v) = back_and_forth(u.centre[1], between, speed_mps, t);
            (u.centre[1], u.velocity) = (y, [0.0, v]);
        }
        Motion::Stand => {}
    }
    u
}

/// Where a coordinate starting at `start` and moving at `speed_mps` is at `t_s`, looping over
/// `[a, b]` (leaving one end, it comes back at the other).
fn looped(start: f64, [a, b]: [f64; 2], speed_mps: f64, t_s: f64) -> f64 {
    let len = (b - a).max(1e-9);
    a + (start - a + speed_mps * t_s).rem_euclid(len)
}

/// A coordinate going back and forth between `lo` and `hi` from `start` (up first), slowing
/// down to turn: `mid + amp sin(phase + ω t)` with its top speed `speed_mps` midway.
/// Returns the coordinate and its speed at `t_s`.
fn back_and_forth(start: f64, [lo, hi]: [f64; 2], speed_mps: f64, t_s: f64) -> (f64, f64) {
    let (mid, amp) = ((lo + hi) / 2.0, (hi - lo) / 2.0);
    if amp <= 0.0 {
        return (start, 0.0);
    }
    let phase = ((start - mid) / amp).clamp(-1.0, 1.0).asin();
    let a = phase + speed_mps / amp * t_s;
    (mid + amp * a.sin(), speed_mps * a.cos())
}
