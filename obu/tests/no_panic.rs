//! Property tests: no input panics the core (NaN, infinities, huge values, any ids).

use obu::geo::{LatLon, LocalFrame32, LocalFrame64, Point};
use obu::lane::{LaneId, LaneKind, MapId, TravelDirection};
use obu::zone::{Region, Validity, ZoneInfo, ZoneKey};
use obu::{Fix, Instant, Obu, UtcTime};
use proptest::prelude::*;

fn any_f32() -> impl Strategy<Value = f32> {
    prop_oneof![
        Just(f32::NAN),
        Just(f32::INFINITY),
        Just(f32::NEG_INFINITY),
        Just(f32::MAX),
        Just(f32::MIN),
        -1.0e4f32..1.0e4,
        any::<f32>(),
    ]
}

fn any_latlon() -> impl Strategy<Value = LatLon> {
    (any::<i32>(), any::<i32>())
        .prop_map(|(a, b)| LatLon::new(a % 900_000_001, b % 1_800_000_001).unwrap_or_default())
}

fn any_fix() -> impl Strategy<Value = Fix> {
    (
        any_latlon(),
        any_f32(),
        any_f32(),
        any_f32(),
        any::<u16>(),
        any::<u64>(),
    )
        .prop_map(|(position, acc, speed, course, year, ms)| Fix {
            accuracy_source: Default::default(),
            position,
            accuracy_m: Some(acc),
            speed_mps: Some(speed),
            course_deg: Some(course),
            utc: Some(UtcTime {
                year,
                ms_of_year: ms,
            }),
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn geo_never_panics(origin in any_latlon(), p in any_latlon(), x in any_f32(), y in any_f32(), h in any::<f64>()) {
        let f64f = LocalFrame64::new(origin, h);
        let _ = f64f.to_local(p);
        let _ = f64f.to_wgs84(x as f64, y as f64);
        let f32f = LocalFrame32::new(origin, h);
        let _ = f32f.to_local(p);
        let _ = f32f.to_wgs84(Point::new(x, y));
    }

    #[test]
    fn obu_never_panics(
        nodes in proptest::collection::vec((any_f32(), any_f32(), any_f32()), 0..40),
        zone_nodes in proptest::collection::vec((any_f32(), any_f32()), 0..20),
        fixes in proptest::collection::vec(any_fix(), 1..8),
        lane_id in any::<u8>(),
        reference in any_latlon(),
        width in any_f32(),
        heading in any::<u16>(),
        codes in proptest::collection::vec(any::<u16>(), 0..30),
        text in ".{0,40}",
        start in any::<u32>(),
        duration in any::<u16>(),
        times in proptest::collection::vec(any::<u64>(), 1..8),
    ) {
        let mut obu = Obu::default();
        let _ = obu.update_map(Instant::ZERO, MapId(lane_id as u32), lane_id, reference, width, |m| {
            for dir in [TravelDirection::Ingress, TravelDirection::Egress, TravelDirection::Both] {
                let lane = m.add_lane(LaneId(lane_id.wrapping_add(dir as u8)), dir, LaneKind::Vehicle)?;
                for &(x, y, w) in &nodes {
                    let _ = lane.push_node(Point::new(x, y), w);
                    let _ = lane.push_node_cm(x as i32, y as i32, w as u16);
                }
            }
            Ok::<(), obu::lane::ModelError>(())
        });
        let validity = Validity { start_year: (start % 3000) as u16, start_minute: start, duration_min: duration };
        let _ = obu.update_zone(Instant::ZERO, ZoneKey::default(), lane_id, validity, |z| {
            let mut r = Region::path(reference, width, width);
            r.heading = obu::zone::HeadingSlice(heading);
            for &(x, y) in &zone_nodes {
                let _ = r.push_node(Point::new(x, y));
                let _ = r.push_delta_cm(x as i32, y as i32);
            }
            z.push_region(r)?;
            z.push_region(Region::circle(reference, width, width))?;
            let mut info = ZoneInfo::new(obu::zone::ContentKind::WorkZone);
            codes.iter().for_each(|&c| info.push_itis(c));
            info.push_text(&text);
            z.info = info;
            Ok::<(), obu::lane::ModelError>(())
        });
        for (fix, t) in fixes.iter().zip(times.iter()) {
            let now = Instant::from_millis(*t);
            let _ = obu.on_fix(now, *fix);
            let _ = obu.poll(now);
            let _ = obu.next_deadline();
        }
    }
}
