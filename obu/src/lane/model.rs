//! One lane model: a MAP intersection or road segment.

use core::fmt;

use heapless::Vec;

use super::{Lane, LaneId, LaneKind, ModelError, TravelDirection};
use crate::capacity::MAX_LANES;
use crate::geo::{LatLon, LocalFrame32};

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

/// Identity of a lane model: J2735 `RoadRegulatorID` (high 16 bits, 0 when absent)
/// and `IntersectionID` or `RoadSegmentID` (low 16 bits).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct MapId(pub u32);

impl MapId {
    /// From a J2735 `IntersectionReferenceID` / `RoadSegmentReferenceID`.
    pub const fn new(region: u16, id: u16) -> Self {
        MapId(((region as u32) << 16) | id as u32)
    }
}

impl fmt::Display for MapId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}.{}", self.0 >> 16, self.0 & 0xffff)
    }
}

/// Lanes of one MAP intersection or road segment, in the local plane of its
/// reference point.
#[derive(Debug, Clone, PartialEq)]
pub struct LaneModel {
    /// Model identity.
    pub id: MapId,
    /// J2735 `MsgCount` revision; a change replaces the stored model.
    pub revision: u8,
    frame: LocalFrame32,
    lanes: Vec<Lane, MAX_LANES, u8>,
}

impl Default for LaneModel {
    fn default() -> Self {
        LaneModel::new()
    }
}

impl LaneModel {
    /// An empty model at (0, 0); usable in `static` items.
    pub const fn new() -> Self {
        LaneModel {
            id: MapId(0),
            revision: 0,
            frame: LocalFrame32::ZERO,
            lanes: Vec::new(),
        }
    }

    /// Clears the model and sets its identity and reference (J2735 `refPoint`, with
    /// elevation in metres, 0 when absent).
    pub fn reset(&mut self, id: MapId, revision: u8, reference: LatLon, elevation_m: f32) {
        self.id = id;
        self.revision = revision;
        self.frame = LocalFrame32::new(reference, elevation_m as f64);
        self.lanes.clear();
    }

    /// The reference position.
    pub fn reference(&self) -> LatLon {
        self.frame.origin()
    }

    /// The local plane of the reference.
    pub fn frame(&self) -> &LocalFrame32 {
        &self.frame
    }

    /// All lanes.
    pub fn lanes(&self) -> &[Lane] {
        &self.lanes
    }

    /// The lane with `id`.
    pub fn lane(&self, id: LaneId) -> Option<&Lane> {
        self.lanes.iter().find(|l| l.id == id)
    }

    /// Index of the lane with `id`.
    pub fn lane_index(&self, id: LaneId) -> Option<usize> {
        self.lanes.iter().position(|l| l.id == id)
    }

    /// The lane with `id`, mutable.
    pub fn lane_mut(&mut self, id: LaneId) -> Option<&mut Lane> {
        self.lanes.iter_mut().find(|l| l.id == id)
    }

    /// Adds an empty lane in place and returns it for filling.
    pub fn add_lane(
        &mut self,
        id: LaneId,
        direction: TravelDirection,
        kind: LaneKind,
    ) -> Result<&mut Lane, ModelError> {
        if self.lane(id).is_some() {
            return Err(ModelError::DuplicateLane);
        }
        self.lanes
            .push(Lane::new(id, direction, kind))
            .map_err(|_| ModelError::CapacityExceeded)?;
        self.lanes.last_mut().ok_or(ModelError::CapacityExceeded)
    }

    /// Removes lanes with fewer than two nodes (nothing to match against).
    pub fn drop_degenerate_lanes(&mut self) {
        self.lanes.retain(|l| l.node_count() >= 2);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geo::Point;

    #[test]
    fn builds_in_place() {
        let mut m = LaneModel::new();
        let origin = LatLon::new(404_744_115, -1_049_690_138).unwrap_or_default();
        m.reset(MapId::new(0, 12), 3, origin, 1500.0);
        assert_eq!(m.reference(), origin);
        let lane = m.add_lane(LaneId(1), TravelDirection::Ingress, LaneKind::Vehicle);
        assert!(lane.is_ok_and(|l| l.push_node(Point::new(0.0, 0.0), 3.6).is_ok()));
        assert_eq!(
            m.add_lane(LaneId(1), TravelDirection::Egress, LaneKind::Vehicle)
                .err(),
            Some(ModelError::DuplicateLane)
        );
        for i in 2..=MAX_LANES as u8 {
            assert!(m
                .add_lane(LaneId(i), TravelDirection::Egress, LaneKind::Vehicle)
                .is_ok());
        }
        assert_eq!(
            m.add_lane(LaneId(200), TravelDirection::Egress, LaneKind::Vehicle)
                .err(),
            Some(ModelError::CapacityExceeded)
        );
        m.drop_degenerate_lanes();
        assert!(m.lanes().is_empty());
        assert_eq!(MapId::new(1, 2).to_string_lossy(), "1.2");
    }

    trait Lossy {
        fn to_string_lossy(&self) -> heapless::String<16>;
    }
    impl<T: fmt::Display> Lossy for T {
        fn to_string_lossy(&self) -> heapless::String<16> {
            let mut s = heapless::String::new();
            let _ = fmt::write(&mut s, format_args!("{self}"));
            s
        }
    }
}
