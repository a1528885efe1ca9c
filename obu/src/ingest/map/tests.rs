use std::boxed::Box;
use std::vec::Vec;

use j2735::msg::common::SpeedLimitType::{MaxSpeedInConstructionZone, VehicleMaxSpeed};
use j2735::msg::map_data::MapData;

use super::*;
use crate::geo::LatLon;
use crate::ingest::testdata::*;
use crate::ingest::{Ingest, IngestError};
use crate::testutil::{big_stack, decode, vector};
use crate::{Instant, Obu};

fn ingest(obu: &mut Obu, map: &MapData) -> Result<Ingest, IngestError> {
    obu.on_map(Instant::ZERO, map)
}

fn model(obu: &Obu, id: u32) -> &LaneModel {
    obu.maps()
        .get(MapId(id))
        .unwrap_or_else(|| panic!("model {id} stored"))
}

fn lane(m: &LaneModel, id: u8) -> &Lane {
    m.lane(LaneId(id))
        .unwrap_or_else(|| panic!("lane {id} stored"))
}

/// Node positions in whole centimetres and widths in centimetres.
fn cm_nodes(l: &Lane) -> Vec<(i32, i32, i32)> {
    let r = |v: f32| libm::roundf(v * 100.0) as i32;
    l.nodes().map(|(p, w)| (r(p.x), r(p.y), r(w))).collect()
}

#[test]
fn every_node_kind_is_placed() {
    big_stack(|| {
        let far = (LAT + 1500, LON - 2500);
        let list = nodes(&[
            xy(1, 170, -103),
            xy(2, 341, -205),
            xy(3, 682, -410),
            xy(4, 1365, -819),
            xy(5, 2730, -1639),
            xy(6, 10922, -6554),
            xy_latlon(far.0, far.1),
            xy(1, 100, 0),
        ]);
        let map = map_with(102, 1, Some(350), |ls| {
            add(ls, |l| fill_lane(l, 1, true, false, list));
        });
        let mut obu = Box::new(Obu::default());
        let r = ingest(&mut obu, &map);
        assert_eq!(r.map(|r| (r.stored, r.rejected)), Ok((1, 0)));
        let m = model(&obu, 102);
        let got = cm_nodes(lane(m, 1));
        let cumulative = [
            (170, -103),
            (511, -308),
            (1193, -718),
            (2558, -1537),
            (5288, -3176),
            (16210, -9730),
        ];
        for (g, c) in got.iter().zip(cumulative) {
            assert_eq!((g.0, g.1), c, "node-XY offsets add up from the reference");
            assert_eq!(g.2, 352, "laneWidth 350 cm in 4 cm steps");
        }
        let abs = m
            .frame()
            .to_local(LatLon::new(far.0, far.1).unwrap_or_default());
        let last = got[6];
        assert!(
            (last.0 as f32 - abs.x * 100.0).abs() <= 1.0
                && (last.1 as f32 - abs.y * 100.0).abs() <= 1.0
        );
        assert_eq!(
            (got[7].0 - last.0, got[7].1 - last.1),
            (100, 0),
            "offsets continue from a LatLon node"
        );
    });
}

#[test]
fn widths_and_speed_limits() {
    big_stack(|| {
        let list = nodes(&[
            xy(3, 0, 0),
            with_limits(
                with_dwidth(xy(3, 0, 1000), -30),
                limits(&[(MaxSpeedInConstructionZone, 139)]),
            ),
            with_dwidth(xy(3, 0, 1000), -300),
        ]);
        let mut map = map_with(5, 1, Some(366), |ls| {
            add(ls, |l| fill_lane(l, 1, false, true, list));
        });
        if let Some(ix) = map.intersections.as_mut().and_then(|l| l.0.first_mut()) {
            ix.speed_limits = Some(limits(&[
                (VehicleMaxSpeed, 556),
                (MaxSpeedInConstructionZone, 200),
            ]));
        }
        let mut obu = Box::new(Obu::default());
        assert!(ingest(&mut obu, &map).is_ok());
        let l = lane(model(&obu, 5), 1);
        let widths: Vec<i32> = cm_nodes(l).iter().map(|n| n.2).collect();
        assert_eq!(widths, [368, 336, 36], "dWidth adds up: 366, 336, 36");
        let units = |s: SpeedLimits| (s.max.units(), s.construction_max.units());
        assert_eq!(
            units(l.limits),
            (556, 200),
            "the intersection's speedLimits"
        );
        assert_eq!(units(l.limits_at(0)), (556, 200));
        assert_eq!(
            units(l.limits_at(1)),
            (556, 139),
            "a node's speedLimits from that node on"
        );
    });
}

#[test]
fn computed_lanes() {
    big_stack(|| {
        let map = map_with(9, 1, None, |ls| {
            let straight = nodes(&[xy(3, 1000, 0), xy(6, 0, 10000)]);
            add(ls, |l| {
                fill_lane(l, 2, false, true, computed(1, -366, 0, None, None))
            });
            add(ls, |l| fill_lane(l, 1, false, true, straight));
            add(ls, |l| {
                fill_lane(l, 3, false, true, computed(1, 0, 0, Some(7200), None))
            });
            add(ls, |l| {
                fill_lane(
                    l,
                    4,
                    false,
                    true,
                    computed(1, 0, 5000, None, Some((0, 2000))),
                )
            });
            add(ls, |l| {
                fill_lane(l, 5, false, true, computed(42, 0, 0, None, None))
            });
        });
        let mut obu = Box::new(Obu::default());
        assert_eq!(
            ingest(&mut obu, &map),
            Err(IngestError::ReferenceLaneMissing)
        );
        assert_eq!(obu.rejected().get(IngestError::ReferenceLaneMissing), 1);
        let m = model(&obu, 9);
        assert_eq!(m.lanes().len(), 4, "the other lanes are stored");
        let ends = |id| {
            let n = cm_nodes(lane(m, id));
            (n[0].0, n[0].1, n[n.len() - 1].0, n[n.len() - 1].1)
        };
        assert_eq!(ends(1), (1000, 0, 1000, 10000));
        assert_eq!(
            ends(2),
            (634, 0, 634, 10000),
            "offsetXaxis -366 cm, listed before its reference"
        );
        assert_eq!(
            ends(3),
            (1000, 0, 11000, 0),
            "rotateXY 90 degrees clockwise about the first node"
        );
        assert_eq!(
            ends(4),
            (1000, 5000, 1000, 25000),
            "scaleYaxis +100 %, then offsetYaxis"
        );
        assert_eq!(lane(m, 2).max_width(), lane(m, 1).max_width());
    });
}

#[test]
fn lane_attributes_and_connections() {
    big_stack(|| {
        let two = || nodes(&[xy(3, 0, 0), xy(3, 0, 2000)]);
        let map = map_with(11, 1, None, |ls| {
            add(ls, |l| {
                fill_lane(l, 1, true, false, two());
                connect(l, &[2, 3, 9], Some(77));
            });
            add(ls, |l| fill_lane(l, 2, false, true, two()));
            add(ls, |l| fill_lane(l, 3, true, true, two()));
            add(ls, |l| {
                fill_lane(l, 4, false, false, two());
                make_median(l);
            });
        });
        let mut obu = Box::new(Obu::default());
        assert!(ingest(&mut obu, &map).is_ok());
        let m = model(&obu, 11);
        let dir = |id| lane(m, id).direction;
        assert_eq!(
            [dir(1), dir(2), dir(3), dir(4)],
            [
                TravelDirection::Ingress,
                TravelDirection::Egress,
                TravelDirection::Both,
                TravelDirection::None
            ]
        );
        assert_eq!(
            (lane(m, 1).kind, lane(m, 4).kind),
            (LaneKind::Vehicle, LaneKind::Median)
        );
        assert_eq!(
            &lane(m, 1).connections[..],
            &[LaneId(2), LaneId(3)],
            "remote connections are not followed"
        );
    });
}

#[test]
fn road_segments_and_revisions() {
    big_stack(|| {
        let one = |rev| {
            let mut map = map_with(7, rev, None, |ls| {
                add(ls, |l| {
                    fill_lane(l, 1, false, true, nodes(&[xy(3, 0, 0), xy(3, 0, 2000)]))
                });
            });
            add_segment(&mut map, 3301, rev);
            map
        };
        let mut obu = Box::new(Obu::default());
        assert_eq!(ingest(&mut obu, &one(1)).map(|r| r.stored), Ok(2));
        assert_eq!(model(&obu, MapId::new(26, 3301).0).lanes().len(), 1);
        assert_eq!(
            ingest(&mut obu, &one(1)).map(|r| (r.stored, r.unchanged)),
            Ok((0, 2))
        );
        assert_eq!(
            ingest(&mut obu, &one(2)).map(|r| r.stored),
            Ok(2),
            "a new revision replaces"
        );
        assert_eq!(model(&obu, 7).revision, 2);
        assert_eq!(obu.maps().len(), 2);
    });
}

#[test]
fn rejected_parts_are_counted() {
    big_stack(|| {
        let two = || nodes(&[xy(3, 0, 0), xy(3, 0, 2000)]);
        let map = map_with(12, 1, None, |ls| {
            add(ls, |l| fill_lane(l, 1, false, true, two()));
            add(ls, |l| fill_lane(l, 1, false, true, two()));
        });
        let mut obu = Box::new(Obu::default());
        assert_eq!(ingest(&mut obu, &map), Err(IngestError::DuplicateLane));
        assert_eq!(model(&obu, 12).lanes().len(), 1);
        let mut bad = map_with(13, 1, None, |_| {});
        if let Some(ix) = bad.intersections.as_mut().and_then(|l| l.0.first_mut()) {
            ix.ref_point.lat = j2735::msg::common::Latitude::UNAVAILABLE;
        }
        assert_eq!(ingest(&mut obu, &bad), Err(IngestError::InvalidReference));
        assert!(obu.maps().get(MapId(13)).is_none());
        assert_eq!(
            (obu.rejected().total(), obu.counters().maps_rejected),
            (2, 1)
        );
    });
}

#[test]
fn long_lanes_are_thinned() {
    big_stack(|| {
        let mut items = Vec::new();
        items.push(xy(3, 0, 0));
        for i in 0..62 {
            items.push(xy(4, 40 + (i % 3) * 2, 1500));
        }
        let map = map_with(14, 1, None, |ls| {
            add(ls, |l| fill_lane(l, 1, false, true, nodes(&items)));
        });
        let mut obu = Box::new(Obu::default());
        assert_eq!(ingest(&mut obu, &map).map(|r| r.thinned), Ok(1));
        let l = lane(model(&obu, 14), 1);
        assert!(l.node_count() <= MAX_NODES);
        let end = cm_nodes(l).last().copied().unwrap_or_default();
        let x: i32 = (0..62).map(|i| 40 + (i % 3) * 2).sum();
        assert_eq!((end.0, end.1), (x, 62 * 1500), "the ends stay");
        assert!((l.length() - 931.0).abs() < 1.0, "{}", l.length());
    });
}

#[test]
fn oracle_vectors_load() {
    big_stack(|| {
        let load = |names: &[&str]| {
            let mut obu = Box::new(Obu::default());
            for name in names {
                let map = decode::<MapData>(&vector(name));
                let r = obu.on_map(Instant::ZERO, &map);
                assert!(r.is_ok_and(|r| r.rejected == 0), "{name}: {r:?}");
            }
            obu
        };
        let _ = load(&[
            "map_node_offsets_all_kinds",
            "map_road_segments",
            "map_rich",
            "map_lane_types",
        ]);
        let _ = load(&[
            "map_two_intersections",
            "map_nodes_63",
            "map_regional_four_items",
        ]);
        let mut obu = Box::new(Obu::default());
        let map = decode::<MapData>(&vector("map_regional_addgrpb"));
        let r = obu.on_map(Instant::ZERO, &map);
        assert_eq!(
            r,
            Err(IngestError::UnsupportedNode),
            "AddGrpB degree-minute-second nodes"
        );
        let obu = load(&["map_computed_lane_small", "map_work_zone"]);
        let small = model(&obu, 110);
        let (a, b) = (cm_nodes(lane(small, 1)), cm_nodes(lane(small, 2)));
        assert!(
            a.iter()
                .zip(&b)
                .all(|(a, b)| (a.0, a.1 - 366) == (b.0, b.1)),
            "{a:?} {b:?}"
        );
        let wz = model(&obu, 7001);
        assert_eq!(wz.revision, 3);
        assert_eq!(lane(wz, 3).kind, LaneKind::Median);
        let l1 = lane(wz, 1);
        assert_eq!(
            (l1.direction, &l1.connections[..]),
            (TravelDirection::Ingress, &[LaneId(11)][..])
        );
        assert!(
            l1.nodes().last().is_some_and(|(_, w)| w < 0.05),
            "dWidth -30 then -366: tapered to 0"
        );
        assert_eq!(l1.limits.construction_max.units(), 139);
        assert_eq!(lane(wz, 2).limits_at(2).construction_max.units(), 139);
    });
}
