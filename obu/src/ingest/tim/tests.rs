use std::boxed::Box;

use j2735::msg::common::{RoadRegulatorID, RoadSegmentID, RoadSegmentReferenceID};
use j2735::msg::traveler_information::{DirectionOfUse, DistanceUnits, TravelerInformation};
use j2735::uper::Placeholder;

use super::*;
use crate::ingest::testdata::*;
use crate::ingest::{Ingest, IngestError};
use crate::testutil::{big_stack, decode, vector};
use crate::time::{Duration, UtcTime};
use crate::zone::RegionShape;
use crate::{Fix, Instant, Obu};

fn ingest(obu: &mut Obu, tim: &TravelerInformation) -> Result<Ingest, IngestError> {
    obu.on_tim(Instant::ZERO, tim)
}

fn zone(obu: &Obu, key: ZoneKey) -> &WorkZone {
    obu.zones()
        .get(&key)
        .unwrap_or_else(|| panic!("zone {key} stored"))
}

fn near(p: Point, x: f32, y: f32) -> bool {
    (p.x - x).abs() < 0.02 && (p.y - y).abs() < 0.02
}

#[test]
fn xy_path_with_every_node_kind_and_zoom() {
    big_stack(|| {
        let list = nodes(&[
            xy(1, 100, 0),
            xy(3, 0, 500),
            xy_latlon(LAT + 100, LON),
            xy(2, 50, 0),
        ]);
        let region = xy_region(0, list, Some(1), DirectionOfUse::Forward, &[0]);
        let tim = tim_with(Some(1), 3, &[&|df| add_region(df, region.clone())]);
        let mut obu = Box::new(Obu::default());
        assert_eq!(ingest(&mut obu, &tim).map(|r| r.stored), Ok(1));
        let r = &zone(&obu, ZoneKey::packet([1; 9], 0)).regions[0];
        let n = r.nodes();
        let north = r
            .frame()
            .to_local(LatLon::new(LAT + 100, LON).unwrap_or_default());
        assert_eq!(n.len(), 5);
        assert!(near(n[0], 0.0, 0.0), "the anchor starts the path");
        assert!(
            near(n[1], 2.0, 0.0) && near(n[2], 2.0, 10.0),
            "offsets times 2^scale"
        );
        assert!(near(n[3], north.x, north.y), "node-LatLon is absolute");
        assert!(
            near(n[4], north.x + 1.0, north.y),
            "and offsets continue from it"
        );
        assert!((r.lane_width_m - 3.66).abs() < 1e-4);
    });
}

#[test]
fn ll_path() {
    big_stack(|| {
        let region = ll_region(&[Some((100, 0)), Some((0, 100)), None]);
        let tim = tim_with(Some(1), 3, &[&|df| add_region(df, region.clone())]);
        let mut obu = Box::new(Obu::default());
        assert!(ingest(&mut obu, &tim).is_ok());
        let r = &zone(&obu, ZoneKey::packet([1; 9], 0)).regions[0];
        let east = r
            .frame()
            .to_local(LatLon::new(LAT, LON + 100).unwrap_or_default());
        let ne = r
            .frame()
            .to_local(LatLon::new(LAT + 100, LON + 100).unwrap_or_default());
        let n = r.nodes();
        assert_eq!(n.len(), 4);
        assert!(near(n[1], east.x, east.y) && near(n[2], ne.x, ne.y) && near(n[3], 0.0, 0.0));
        assert_eq!(r.directionality, Directionality::Both, "absent: both ways");
    });
}

#[test]
fn geometry_circle() {
    big_stack(|| {
        let region = circle_region(500, DistanceUnits::Decimeter, &[3, 4]);
        let tim = tim_with(Some(1), 3, &[&|df| add_region(df, region.clone())]);
        let mut obu = Box::new(Obu::default());
        assert!(ingest(&mut obu, &tim).is_ok());
        let r = &zone(&obu, ZoneKey::packet([1; 9], 0)).regions[0];
        assert_eq!(r.shape, RegionShape::Circle { radius_m: 50.0 });
        assert_eq!(
            r.heading,
            HeadingSlice(0b1_1000),
            "bits 3 and 4: 67.5 to 112.5 degrees"
        );
        assert_eq!(r.extent_m, Some(500.0));
        assert!(r.heading.contains(90.0) && !r.heading.contains(270.0));
    });
}

#[test]
fn directionality_and_heading_slice_bits() {
    big_stack(|| {
        let list = || nodes(&[xy(3, -1000, 0)]);
        let dirs = [
            (DirectionOfUse::Forward, Directionality::Forward),
            (DirectionOfUse::Reverse, Directionality::Reverse),
            (DirectionOfUse::Both, Directionality::Both),
            (DirectionOfUse::Unavailable, Directionality::Both),
        ];
        for (i, (j, core)) in dirs.into_iter().enumerate() {
            let region = xy_region(0, list(), None, j, &[0, 11, 12, 15]);
            let tim = tim_with(Some(i as u8), 1, &[&|df| add_region(df, region.clone())]);
            let mut obu = Box::new(Obu::default());
            assert!(ingest(&mut obu, &tim).is_ok());
            let r = &zone(&obu, ZoneKey::packet([i as u8; 9], 0)).regions[0];
            assert_eq!(r.directionality, core);
            assert_eq!(
                r.heading.0,
                1 | 1 << 11 | 1 << 12 | 1 << 15,
                "bit n of the BIT STRING is slice n"
            );
        }
    });
}

#[test]
fn computed_path_needs_its_map() {
    big_stack(|| {
        let mut region = xy_region(
            0,
            computed(1, 366, 0, None, None),
            None,
            DirectionOfUse::Forward,
            &[0],
        );
        region.id = Some(RoadSegmentReferenceID {
            region: RoadRegulatorID::new(26),
            id: ok(RoadSegmentID::new(3301)),
        });
        let tim = tim_with(Some(4), 3, &[&|df| add_region(df, region.clone())]);
        let mut obu = Box::new(Obu::default());
        assert_eq!(
            ingest(&mut obu, &tim),
            Err(IngestError::ReferenceMapMissing)
        );
        assert!(
            obu.zones().is_empty(),
            "dropped: converted again with the next copy"
        );
        let mut map = map_with(7, 1, None, |_| {});
        add_segment(&mut map, 3301, 1);
        assert!(obu.on_map(Instant::ZERO, &map).is_ok());
        assert_eq!(ingest(&mut obu, &tim).map(|r| r.stored), Ok(1));
        let r = &zone(&obu, ZoneKey::packet([4; 9], 0)).regions[0];
        let m = obu
            .maps()
            .get(crate::lane::MapId::new(26, 3301))
            .map(|m| *m.frame());
        let to_region = |x: f32, y: f32| {
            let ll = m
                .and_then(|f| f.to_wgs84(Point::new(x, y)))
                .unwrap_or_default();
            r.frame().to_local(ll)
        };
        let (a, b) = (to_region(3.66, 0.0), to_region(3.66, 20.0));
        assert_eq!(r.nodes().len(), 2);
        assert!(
            near(r.nodes()[0], a.x, a.y) && near(r.nodes()[1], b.x, b.y),
            "{:?}",
            r.nodes()
        );
    });
}

#[test]
fn keys_content_and_capacity() {
    big_stack(|| {
        let path = || {
            xy_region(
                0,
                nodes(&[xy(3, 0, 1000)]),
                None,
                DirectionOfUse::Forward,
                &[0],
            )
        };
        let frame = |df: &mut TravelerDataFrame| {
            work_zone(df, &[1025, 769, 8195, 268, 12569, 8721]);
            add_region(df, GeographicalPath::placeholder());
            for _ in 0..MAX_REGIONS + 1 {
                add_region(df, path());
            }
        };
        let tim = tim_with(None, 3, &[&frame, &|df| add_region(df, path())]);
        let mut obu = Box::new(Obu::default());
        let r = ingest(&mut obu, &tim);
        assert_eq!(
            r,
            Err(IngestError::NoGeometry),
            "a region without description"
        );
        assert_eq!(obu.rejected().get(IngestError::NoGeometry), 1);
        let keys: std::vec::Vec<ZoneKey> = obu.zones().iter().map(|z| z.key).collect();
        assert_eq!(keys.len(), 2);
        assert!(
            keys.iter().all(|k| k.source == KeySource::MsgId),
            "no packetID: keyed by msgId"
        );
        let z = obu
            .zones()
            .iter()
            .next()
            .map(|z| z.info.clone())
            .unwrap_or_default();
        assert!(z.lane_closed && z.side == crate::zone::ClosureSide::Left);
        assert_eq!(
            z.speed_limit,
            crate::lane::Speed::from_kmh(25.0),
            "268, 25, kPH"
        );
        let stored = obu.zones().iter().next().map_or(0, |z| z.regions.len());
        assert_eq!(stored, MAX_REGIONS);
    });
}

#[test]
fn replacement_cancel_and_expiry() {
    big_stack(|| {
        let path = || xy_region(0, nodes(&[xy(3, 0, 1000)]), None, DirectionOfUse::Both, &[]);
        let version = |cnt: u8, start: u32, duration: u16| {
            tim_with(
                Some(9),
                cnt,
                &[&|df| {
                    df.start_time = ok(j2735::msg::common::MinuteOfTheYear::new(start));
                    df.duration_time = ok(j2735::msg::traveler_information::MinutesDuration::new(
                        duration,
                    ));
                    add_region(df, path());
                }],
            )
        };
        let mut obu = Box::new(Obu::default());
        let outcome = |obu: &mut Obu, cnt, start, dur| {
            let r = ingest(obu, &version(cnt, start, dur)).unwrap_or_default();
            (r.stored, r.unchanged, r.stale, r.cancelled)
        };
        assert_eq!(outcome(&mut obu, 1, 1000, 60), (1, 0, 0, 0));
        assert_eq!(
            outcome(&mut obu, 1, 1000, 60),
            (0, 1, 0, 0),
            "same msgCnt and start"
        );
        assert_eq!(
            outcome(&mut obu, 2, 1000, 90),
            (1, 0, 0, 0),
            "newer msgCnt replaces"
        );
        assert_eq!(
            zone(&obu, ZoneKey::packet([9; 9], 0)).validity.duration_min,
            90
        );
        assert_eq!(
            outcome(&mut obu, 3, 900, 60),
            (0, 0, 1, 0),
            "older start: ignored"
        );
        assert_eq!(
            outcome(&mut obu, 4, 1010, 60),
            (1, 0, 0, 0),
            "newer start replaces"
        );
        let key = ZoneKey::packet([9; 9], 0);
        let fix = |minute| Fix {
            utc: Some(UtcTime::from_minute_of_year(2025, minute)),
            ..Fix::default()
        };
        let _ = obu.on_fix(Instant::from_millis(1), fix(1060));
        let _ = obu.poll(Instant::from_millis(2));
        assert!(obu.zones().get(&key).is_some(), "inside its window");
        let _ = obu.on_fix(Instant::from_millis(3), fix(1071));
        let _ = obu.poll(Instant::from_millis(4));
        assert!(
            obu.zones().get(&key).is_none(),
            "expired at start + duration"
        );
        assert_eq!(outcome(&mut obu, 5, 1080, 60), (1, 0, 0, 0));
        assert_eq!(
            outcome(&mut obu, 6, 1080, 0),
            (0, 0, 0, 1),
            "durationTime 0 cancels"
        );
        assert!(obu.zones().is_empty());
        assert_eq!(outcome(&mut obu, 7, 1090, 60), (1, 0, 0, 0));
        let _ = obu.poll(Instant::ZERO + Duration::from_secs(31));
        assert!(obu.zones().is_empty(), "not heard for 30 s");
    });
}

#[test]
fn oracle_vectors_load() {
    big_stack(|| {
        let mut obu = Box::new(Obu::default());
        let map = decode::<j2735::msg::map_data::MapData>(&vector("map_road_segments"));
        assert!(obu.on_map(Instant::ZERO, &map).is_ok());
        let expect_ok = [
            "tim_work_zone_left_lane_closed",
            "tim_work_zone_right_lane_closed_ahead",
            "tim_work_zone_speed_text",
            "tim_geometry_circle",
            "tim_rich",
            "tim_cancel_zero_duration",
        ];
        for name in expect_ok {
            let tim = decode::<TravelerInformation>(&vector(name));
            let r = obu.on_tim(Instant::ZERO, &tim);
            assert!(r.is_ok(), "{name}: {r:?}");
        }
        let expect = [
            ("tim_path_computed_lane", IngestError::ReferenceLaneMissing),
            // scale 15 (zoom 32768) puts its node-XY6 offset 5 000 km from the anchor.
            ("tim_path_xy_all_node_kinds", IngestError::InvalidValue),
            // its node-LL6 offset (times 2) lies 186 km from the anchor.
            ("tim_path_ll_all_node_kinds", IngestError::InvalidValue),
            // a computed shape point set without a region id to find its MAP by.
            ("tim_old_region_variants", IngestError::ReferenceLaneMissing),
        ];
        for (name, e) in expect {
            // A fresh unit each: these TIMs share one msgId (no packetID), so a second
            // one with the same msgCnt and start would only refresh the first.
            let mut fresh = Box::new(Obu::default());
            assert!(fresh.on_map(Instant::ZERO, &map).is_ok());
            let tim = decode::<TravelerInformation>(&vector(name));
            assert_eq!(
                fresh.on_tim(Instant::ZERO, &tim).map(|_| ()),
                Err(e),
                "{name}"
            );
        }
        let mut obu = Box::new(Obu::default());
        let variants = decode::<TravelerInformation>(&vector("tim_directionality_variants"));
        let r = obu.on_tim(Instant::ZERO, &variants).map(|r| r.truncated);
        assert_eq!(
            r,
            Ok(1),
            "a fifth region (without description) is beyond MAX_REGIONS"
        );
        let z = obu
            .zones()
            .iter()
            .find(|z| z.key.source == KeySource::MsgId);
        let got: std::vec::Vec<_> = z
            .map(|z| {
                z.regions
                    .iter()
                    .map(|r| (r.directionality, r.heading.0, r.closed_path))
                    .collect()
            })
            .unwrap_or_default();
        let want = [
            (Directionality::Both, 0b11, false),
            (Directionality::Forward, 0b11 << 4, true),
            (Directionality::Reverse, 0b11 << 8, false),
            (Directionality::Both, 0b11 << 12, true),
        ];
        assert_eq!(got, want, "c000, 0c00, 00c0, 000c: bit 0 is the first bit");
        let minimal = decode::<TravelerInformation>(&vector("tim_minimal"));
        let r = obu
            .on_tim(Instant::ZERO, &minimal)
            .map(|r| (r.cancelled, r.unchanged));
        assert_eq!(
            r,
            Ok((0, 1)),
            "tim_minimal: durationTime 0 of a zone not stored: nothing to cancel or convert"
        );
        let mut obu = Box::new(Obu::default());
        for name in ["tim_work_zone_left_lane_closed", "tim_work_zone_speed_text"] {
            assert!(obu
                .on_tim(Instant::ZERO, &decode::<TravelerInformation>(&vector(name)))
                .is_ok());
        }
        let left = zone(
            &obu,
            ZoneKey::packet([0x5a, 0x0c, 0x0e, 0x11, 0, 0, 0, 0, 0x2a], 0),
        );
        assert!(left.info.lane_closed && left.info.side == crate::zone::ClosureSide::Left);
        assert_eq!(
            left.regions[0].heading.0,
            1 << 11 | 1 << 12,
            "0018: 247.5 to 292.5 degrees"
        );
        assert_eq!(left.regions[0].directionality, Directionality::Forward);
        let speed = zone(
            &obu,
            ZoneKey::packet([0x5a, 0x0c, 0x0e, 0x11, 0, 0, 0, 0, 0x2a], 1),
        );
        assert_eq!(speed.info.speed_limit, crate::lane::Speed::from_mph(25.0));
        let text = zone(
            &obu,
            ZoneKey::packet([0x5a, 0x0c, 0x0e, 0x11, 0, 0, 0, 0, 0x2c], 1),
        );
        assert_eq!(
            text.info.speed_limit,
            crate::lane::Speed::from_mph(25.0),
            "268, \"25\", \"MPH\""
        );
        assert_eq!(text.validity.duration_min, Validity::INDEFINITE);
    });
}

#[test]
fn heading_slice_gates_the_warning() {
    big_stack(|| {
        // A northbound lane 600 m long and a zone from 400 to 500 m along it, usable
        // both ways; only the heading slice differs.
        let lane = nodes(&[xy(3, 0, 0), xy(6, 0, 30_000), xy(6, 0, 30_000)]);
        let map = map_with(21, 1, Some(350), |ls| {
            add(ls, |l| fill_lane(l, 1, false, true, lane))
        });
        let zone_path = || {
            nodes(&[
                xy(3, 0, 2000),
                xy(3, 0, 2000),
                xy(3, 0, 2000),
                xy(3, 0, 2000),
                xy(3, 0, 2000),
            ])
        };
        for (slices, warned) in [(&[15usize, 0][..], true), (&[7, 8][..], false)] {
            let region = xy_region(36_036, zone_path(), None, DirectionOfUse::Both, slices);
            let tim = tim_with(
                Some(2),
                1,
                &[&|df| {
                    work_zone(df, &[1025]);
                    add_region(df, region.clone());
                }],
            );
            let mut obu = Box::new(Obu::default());
            assert!(obu.on_map(Instant::ZERO, &map).is_ok() && ingest(&mut obu, &tim).is_ok());
            let frame = obu
                .maps()
                .iter()
                .next()
                .map(|(_, m)| *m.frame())
                .unwrap_or_default();
            let states: std::vec::Vec<_> = (0..30)
                .map(|k| {
                    let y = 100.0 + 10.0 * k as f32;
                    let fix = Fix {
                        accuracy_source: Default::default(),
                        position: frame.to_wgs84(Point::new(0.0, y)).unwrap_or_default(),
                        speed_mps: Some(10.0),
                        course_deg: Some(0.0),
                        accuracy_m: Some(0.5),
                        utc: Some(UtcTime::from_minute_of_year(2025, 1010)),
                    };
                    obu.on_fix(Instant::from_millis(100 * k), fix).zone_state
                })
                .collect();
            let warning = states.contains(&crate::alert::ZoneState::Warning);
            assert_eq!(
                warning, warned,
                "slices {slices:?} heading north: {states:?}"
            );
        }
    });
}
