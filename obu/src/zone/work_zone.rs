//! One work zone (a TIM data frame) and its association with MAP lanes.

use heapless::Vec;

use super::{ContentKind, Region, Validity, ZoneInfo, ZoneKey};
use crate::capacity::{MAX_MAPS, MAX_REGIONS, MAX_ZONE_LANES};
use crate::geo::Point;
use crate::lane::{LaneId, MapId, ModelError};

/// A MAP lane a zone region lies on, with the zone's extent on it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ZoneLane {
    /// The lane model.
    pub map: MapId,
    /// The lane.
    pub lane: LaneId,
    /// Index of the region in [`WorkZone::regions`].
    pub region: u8,
    /// Zone start, metres from the lane's entry in its direction of travel.
    pub start: f32,
    /// Zone end, metres from the lane's entry in its direction of travel.
    pub end: f32,
}

/// A path region's first and last node in the plane of one stored map (cached when
/// the zone is associated, so that a fix needs no coordinate conversion).
#[derive(Debug, Clone, Copy, Default)]
pub struct MapEnds {
    /// First node (start in node order).
    pub start: Point,
    /// Last node.
    pub end: Point,
}

/// Bitwise, so that the "not cached" NaN value equals itself.
impl PartialEq for MapEnds {
    fn eq(&self, other: &Self) -> bool {
        let bits = |e: &MapEnds| [e.start.x, e.start.y, e.end.x, e.end.y].map(f32::to_bits);
        bits(self) == bits(other)
    }
}

impl MapEnds {
    /// Not cached (NaN).
    const NONE: MapEnds = MapEnds {
        start: Point::new(f32::NAN, f32::NAN),
        end: Point::new(f32::NAN, f32::NAN),
    };
}

/// A work zone: one TIM data frame.
#[derive(Debug, Clone, PartialEq)]
pub struct WorkZone {
    /// Identity.
    pub key: ZoneKey,
    /// TIM `msgCnt` (0..=127); a change replaces the zone.
    pub msg_cnt: u8,
    /// Validity window.
    pub validity: Validity,
    /// TIM `priority` (0..=7).
    pub priority: u8,
    /// Regions.
    pub regions: Vec<Region, MAX_REGIONS, u8>,
    /// Parsed content.
    pub info: ZoneInfo,
    /// When the signature of the newest message that carried the zone stops being relevant
    /// (its expiry time, or its generation time plus the past window), in whole TAI seconds
    /// since 2004 (`Time64` / 10^6, rounded up; 4 octets a zone on the firmware); 0 for
    /// unsigned data. The zone is shown until the earlier of this and its own window's end.
    pub signed_until_s: u32,
    lanes: Vec<ZoneLane, MAX_ZONE_LANES, u8>,
    /// Region ends per map slot of the [`crate::lane::MapStore`] ([`MapEnds::NONE`]
    /// when not cached: 4 bytes less than an `Option` per entry).
    ends: [[MapEnds; MAX_MAPS]; MAX_REGIONS],
}

impl Default for WorkZone {
    fn default() -> Self {
        WorkZone::new()
    }
}

impl WorkZone {
    /// An empty zone; usable in `static` items.
    pub const fn new() -> Self {
        WorkZone {
            key: ZoneKey::packet([0; 9], 0),
            msg_cnt: 0,
            validity: Validity {
                start_year: 0,
                start_minute: 0,
                duration_min: 0,
            },
            priority: 0,
            regions: Vec::new(),
            info: ZoneInfo::new(ContentKind::WorkZone),
            signed_until_s: 0,
            lanes: Vec::new(),
            ends: [[MapEnds::NONE; MAX_MAPS]; MAX_REGIONS],
        }
    }

    /// Clears the zone and sets identity and validity.
    pub fn reset(&mut self, key: ZoneKey, msg_cnt: u8, validity: Validity) {
        *self = WorkZone {
            key,
            msg_cnt,
            validity,
            ..WorkZone::new()
        };
    }

    /// Adds a region.
    pub fn push_region(&mut self, region: Region) -> Result<(), ModelError> {
        self.regions
            .push(region)
            .map_err(|_| ModelError::CapacityExceeded)
    }

    /// Lanes the regions lie on (filled by [`super::associate`]).
    pub fn lanes(&self) -> &[ZoneLane] {
        &self.lanes
    }

    /// The association for `lane` of `map`, if any.
    pub fn lane(&self, map: MapId, lane: LaneId) -> Option<&ZoneLane> {
        self.lanes.iter().find(|z| z.map == map && z.lane == lane)
    }

    /// Forgets the associations with `map` (or all when `None`).
    pub(crate) fn clear_lanes(&mut self, map: Option<MapId>) {
        self.lanes.retain(|z| map.is_some_and(|m| z.map != m));
    }

    /// The cached ends of region `region` in the plane of map slot `slot`.
    pub fn ends(&self, region: usize, slot: usize) -> Option<MapEnds> {
        let e = *self.ends.get(region)?.get(slot)?;
        e.start.is_finite().then_some(e)
    }

    /// Caches (or clears) the ends of `region` for map slot `slot`.
    pub(crate) fn set_ends(&mut self, region: usize, slot: usize, ends: Option<MapEnds>) {
        if let Some(e) = self.ends.get_mut(region).and_then(|r| r.get_mut(slot)) {
            *e = ends.unwrap_or(MapEnds::NONE);
        }
    }

    /// Clears every cached end.
    pub(crate) fn clear_ends(&mut self) {
        self.ends = [[MapEnds::NONE; MAX_MAPS]; MAX_REGIONS];
    }

    /// Records an association; when full, the entry is dropped (returns false).
    pub(crate) fn add_lane(&mut self, z: ZoneLane) -> bool {
        self.lanes.push(z).is_ok()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geo::LatLon;

    #[test]
    fn builds_and_associates() {
        let mut z = WorkZone::new();
        z.reset(ZoneKey::default(), 3, Validity::default());
        for _ in 0..MAX_REGIONS {
            assert!(z.push_region(Region::path(LatLon::ZERO, 0.0, 3.0)).is_ok());
        }
        let extra = z.push_region(Region::path(LatLon::ZERO, 0.0, 3.0));
        assert_eq!(extra, Err(ModelError::CapacityExceeded));
        let entry = ZoneLane {
            map: MapId(1),
            lane: LaneId(2),
            region: 0,
            start: 1.0,
            end: 2.0,
        };
        assert!(z.add_lane(entry));
        assert!(z.add_lane(ZoneLane {
            map: MapId(2),
            ..entry
        }));
        assert!(z.lane(MapId(1), LaneId(2)).is_some());
        z.clear_lanes(Some(MapId(1)));
        assert!(z.lane(MapId(1), LaneId(2)).is_none() && z.lanes().len() == 1);
        z.clear_lanes(None);
        assert!(z.lanes().is_empty());
    }
}
