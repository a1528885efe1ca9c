//! A worker's place relative to the lanes, in a lane model's local plane.

use super::{IN_PATH_MARGIN_M, NEAR_ROAD_M};
use crate::geo::Point;
use crate::lane::{Lane, LaneKind, LaneModel, LanePosition, TravelDirection};

/// Where a worker stands relative to the vehicle on its own lane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// Metres along the own lane from the vehicle to the worker's projection, in the
    /// direction of travel (negative behind the vehicle).
    pub distance_m: f32,
    /// Metres from the own lane's centreline, positive to the right in the direction of
    /// travel (the HMI's order of [`crate::HmiState::road_lanes`], left to right).
    pub lateral_m: f32,
    /// Within half the lane width plus [`IN_PATH_MARGIN_M`] of the centreline: in the
    /// lane's path (ahead or not).
    pub in_path: bool,
}

/// Places the point `p` on `own`, the lane the vehicle is at `vehicle` on (its position in
/// its direction of travel). `None` for a lane without segments or a non-finite point.
pub fn place(own: &Lane, vehicle: &LanePosition, p: Point) -> Option<Placement> {
    let proj = own.project(p)?;
    let pos = own.position_from(&proj, vehicle.forward);
    let distance_m = pos.station - vehicle.station;
    let lateral_m = -pos.lateral;
    if !(distance_m.is_finite() && lateral_m.is_finite()) {
        return None;
    }
    Some(Placement {
        distance_m,
        lateral_m,
        in_path: lateral_m.abs() <= 0.5 * pos.width + IN_PATH_MARGIN_M,
    })
}

/// True when `p` lies within [`NEAR_ROAD_M`] of a vehicle lane of `model`: of its
/// centreline less than half its width plus that, and no more than that beyond its ends.
pub fn near_road(model: &LaneModel, p: Point) -> bool {
    model
        .lanes()
        .iter()
        .filter(|l| l.kind == LaneKind::Vehicle && l.direction != TravelDirection::None)
        .filter(|l| l.may_contain(p, NEAR_ROAD_M + l.max_width()))
        .any(|l| near_lane(l, p))
}

/// True when `p` lies within [`NEAR_ROAD_M`] of `lane` (see [`near_road`]).
fn near_lane(lane: &Lane, p: Point) -> bool {
    let Some(proj) = lane.project(p) else {
        return false;
    };
    let beyond = lane.position_from(&proj, true).beyond;
    beyond <= NEAR_ROAD_M && proj.lateral.abs() <= 0.5 * proj.width + NEAR_ROAD_M
}
