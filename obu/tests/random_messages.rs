//! Property test: no random valid MAP, TIM or other MessageFrame (the codec's `_random`
//! values, the same a decoder produces), and no fix after them, panics the core: fixes
//! near the MAP's reference point, anywhere, and with NaN or infinite fields.

mod common;

use j2735::msg::common::Position3D;
use j2735::msg::map_data::{LaneAttributesVehicle, LaneDirection, LaneTypeAttributes};
use j2735::msg::message_frame::{MessageFrame, MessageFrameValue};
use j2735::msg::traveler_information::TravelerInformation;
use j2735::uper::random::{Gen, Random};
use j2735::uper::{Bits, Extensions};
use j2735::{BasicSafetyMessage, MapData};
use obu::geo::LatLon;
use obu::{Fix, Instant, Obu, UtcTime};
use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};

fn any_f32() -> impl Strategy<Value = f32> {
    prop_oneof![
        Just(f32::NAN),
        Just(f32::INFINITY),
        Just(f32::NEG_INFINITY),
        -1.0e3f32..1.0e3,
        any::<f32>(),
    ]
}

/// A fix on a node of a stored lane (`on_lane`: lane and node index, with `d` as
/// centimetres of noise), else `(d_lat, d_lon)` 1e-7 degree from the MAP reference (or
/// anywhere when `anywhere`), with arbitrary speed, course, accuracy and UTC.
#[derive(Debug, Clone)]
struct RawFix {
    d: (i32, i32),
    on_lane: Option<(usize, usize)>,
    anywhere: bool,
    speed: f32,
    course: f32,
    accuracy: f32,
    utc: (u16, u64),
}

fn raw_fix() -> impl Strategy<Value = RawFix> {
    (
        (-5_000i32..5_000, -5_000i32..5_000),
        proptest::option::of((0usize..64, 0usize..32)),
        any::<bool>(),
        (any_f32(), any_f32(), any_f32()),
        (any::<u16>(), any::<u64>()),
    )
        .prop_map(
            |(d, on_lane, anywhere, (speed, course, accuracy), utc)| RawFix {
                d,
                on_lane,
                anywhere,
                speed,
                course,
                accuracy,
                utc,
            },
        )
}

fn fix(raw: &RawFix, reference: LatLon, obu: &Obu) -> Fix {
    let on_lane = raw.on_lane.and_then(|(l, n)| {
        let (_, m) = obu.maps().iter().next()?;
        let lanes = m.lanes();
        let lane = lanes.get(l % lanes.len().max(1))?;
        let (p, _) = lane.nodes().nth(n % lane.node_count().max(1))?;
        let q = obu::geo::Point::new(p.x + raw.d.0 as f32 * 1e-4, p.y + raw.d.1 as f32 * 1e-4);
        let course = lane.locate(q, None).map(|pos| pos.bearing_deg);
        Some((m.frame().to_wgs84(q)?, course))
    });
    if let Some((position, course)) = on_lane {
        // On a lane, driving its way, unless the raw course is not finite.
        let course = course.map(|c| {
            if raw.course.is_finite() {
                c
            } else {
                raw.course
            }
        });
        return Fix {
            accuracy_source: Default::default(),
            position,
            accuracy_m: Some(1.0),
            speed_mps: Some(10.0),
            course_deg: course,
            utc: None,
        };
    }
    let position = if raw.anywhere {
        LatLon::new(raw.d.0.wrapping_mul(18_000), raw.d.1.wrapping_mul(36_000))
    } else {
        LatLon::new(reference.lat_e7() + raw.d.0, reference.lon_e7() + raw.d.1)
    };
    Fix {
        accuracy_source: Default::default(),
        position: position.unwrap_or_default(),
        accuracy_m: Some(raw.accuracy),
        speed_mps: Some(raw.speed),
        course_deg: Some(raw.course),
        utc: Some(UtcTime {
            year: raw.utc.0,
            ms_of_year: raw.utc.1,
        }),
    }
}

/// The first reference point of the MAP.
fn reference(map: &MapData) -> Option<&Position3D> {
    let ix = map
        .intersections
        .iter()
        .flat_map(|l| l.iter())
        .map(|i| &i.ref_point);
    let rs = map
        .road_segments
        .iter()
        .flat_map(|l| l.iter())
        .map(|s| &s.ref_point);
    ix.chain(rs).next()
}

/// Makes every other lane a one-way vehicle lane, so that fixes on them get matched
/// (random lane types and directions rarely allow it).
fn drivable(map: &mut MapData) {
    let ix = map
        .intersections
        .iter_mut()
        .flat_map(|l| l.0.iter_mut())
        .map(|i| &mut i.lane_set.0);
    for lanes in ix {
        for (i, lane) in lanes.iter_mut().enumerate().filter(|(i, _)| i % 2 == 0) {
            let a = &mut lane.lane_attributes;
            a.lane_type = LaneTypeAttributes::Vehicle(LaneAttributesVehicle(
                Bits::zeros(8).unwrap_or(Bits::EMPTY),
            ));
            let mut d = LaneDirection::zeros(2).unwrap_or(a.directional_use);
            d.0.set(i % 4 / 2, true);
            a.directional_use = d;
        }
    }
}

/// Moves every TIM anchor onto `p`, so that zones and lanes meet.
fn anchor_at(tim: &mut TravelerInformation, p: &Position3D) {
    for frame in tim.data_frames.0.iter_mut() {
        for region in frame.regions.0.iter_mut() {
            if region.anchor.is_some() {
                region.anchor = Some(p.clone());
            }
        }
    }
}

fn case(seed: u64, fixes: &[RawFix]) {
    let mut g = Gen::new(seed);
    let mut map = Box::new(MapData::random(&mut g));
    if !seed.is_multiple_of(4) {
        drivable(&mut map);
    }
    let mut tim = Box::new(TravelerInformation::random(&mut g));
    let near = reference(&map).cloned();
    if let Some(p) = &near {
        anchor_at(&mut tim, p);
    }
    let at = near
        .and_then(|p| LatLon::new(p.lat.get(), p.long.get()))
        .unwrap_or_default();
    let mut obu = Box::new(Obu::default());
    let _ = obu.on_map(Instant::ZERO, &map);
    let _ = obu.on_tim(Instant::ZERO, &tim);
    let bsm = Box::new(MessageFrame {
        value: MessageFrameValue::BasicSafetyMessage(BasicSafetyMessage::random(&mut g)),
        extensions: Extensions::new(),
    });
    let _ = obu.on_frame(Instant::ZERO, &bsm);
    for (i, raw) in fixes.iter().enumerate() {
        let now = Instant::from_millis(100 * i as u64);
        let f = fix(raw, at, &obu);
        let _ = obu.on_fix(now, f);
        let _ = obu.poll(now);
        let _ = obu.next_deadline();
    }
    let _ = obu.on_tim(Instant::from_millis(5_000), &tim);
    let _ = obu.on_map(Instant::from_millis(5_000), &map);
    let f = fix(&fixes[0], at, &obu);
    let _ = obu.on_fix(Instant::from_millis(5_100), f);
}

#[test]
fn random_messages_and_fixes_never_panic() {
    common::big_stack(|| {
        let mut runner = TestRunner::new(Config {
            cases: 96,
            failure_persistence: None,
            ..Config::default()
        });
        let strategy = (any::<u64>(), proptest::collection::vec(raw_fix(), 1..16));
        let result = runner.run(&strategy, |(seed, fixes)| {
            case(seed, &fixes);
            Ok(())
        });
        if let Err(e) = result {
            panic!("{e}");
        }
    });
}
