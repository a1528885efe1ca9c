//! Hand-built models shared by the unit tests.

use j2735::msg::personal_safety_message::{PersonalDeviceUserType, PersonalSafetyMessage};

use crate::geo::{LatLon, Point};
use crate::lane::{
    LaneId, LaneKind, LaneModel, MapId, MapStore, MapUpdate, Speed, TravelDirection,
};
use crate::time::Instant;
use crate::zone::{ContentKind, Directionality, Region, Validity, WorkZone, ZoneInfo, ZoneKey};

/// Reference of the test road.
pub fn reference() -> LatLon {
    LatLon::new(400_000_000, -1_050_000_000).unwrap_or_default()
}

/// Lane centre x of the test road: lanes 1-3 northbound (egress, left to right),
/// lanes 4-5 southbound (ingress), 3.5 m wide, from y = 0 to 1000 m.
pub fn lane_x(id: u8) -> f32 {
    match id {
        1 => -3.5,
        2 => 0.0,
        3 => 3.5,
        4 => -7.0,
        _ => -10.5,
    }
}

/// Fills `m` with the test road.
pub fn fill_road(m: &mut LaneModel) {
    for id in 1..=5u8 {
        let dir = if id <= 3 {
            TravelDirection::Egress
        } else {
            TravelDirection::Ingress
        };
        let Ok(lane) = m.add_lane(LaneId(id), dir, LaneKind::Vehicle) else {
            continue;
        };
        lane.limits.max = Speed::from_kmh(60.0);
        for k in 0..=20 {
            let _ = lane.push_node(Point::new(lane_x(id), k as f32 * 50.0), 3.5);
        }
    }
}

/// The test road as a standalone model.
pub fn road() -> LaneModel {
    let mut m = LaneModel::new();
    m.reset(MapId(7), 1, reference(), 1600.0);
    fill_road(&mut m);
    m
}

/// A store holding the test road.
pub fn store() -> MapStore {
    let mut s = MapStore::new();
    if let MapUpdate::Fill { model, .. } = s.update(
        Instant::ZERO,
        MapId(7),
        1,
        reference(),
        1600.0,
        crate::store::Provenance::Verified,
    ) {
        fill_road(model);
    }
    s
}

/// A WGS84 position of a point of the test road's plane.
pub fn at(p: Point) -> LatLon {
    road().frame().to_wgs84(p).unwrap_or_default()
}

/// Validity used by the tests: 2024, minute 1000, indefinite.
pub fn validity() -> Validity {
    Validity {
        start_year: 2024,
        start_minute: 1000,
        duration_min: Validity::INDEFINITE,
    }
}

/// Fills `z` with a closure of lane 3 from y = 400 to 500 m, 25 mph.
pub fn fill_closure(z: &mut WorkZone) {
    let mut r = Region::path(at(Point::new(3.5, 400.0)), 1600.0, 3.5);
    r.directionality = Directionality::Forward;
    for y in [0.0, 50.0, 100.0] {
        let _ = r.push_node(Point::new(0.0, y));
    }
    let _ = z.push_region(r);
    let mut info = ZoneInfo::new(ContentKind::WorkZone);
    for c in [1025, 771, 8196, 268, 12569, 8720] {
        info.push_itis(c);
    }
    z.info = info;
}

/// The closure as a standalone zone.
pub fn closure() -> WorkZone {
    let mut z = WorkZone::new();
    z.reset(ZoneKey::packet([1; 9], 0), 1, validity());
    fill_closure(&mut z);
    z
}

/// Runs `f` on a thread with room for no-heap J2735 values (a MapData is megabytes).
pub fn big_stack<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    std::thread::Builder::new()
        .stack_size(256 << 20)
        .spawn(f)
        .and_then(|h| {
            h.join()
                .map_err(|_| std::io::Error::other("test thread panicked"))
        })
        .unwrap_or_else(|e| panic!("{e}"))
}

/// The UPER bytes of the codec's oracle vector `name`.
pub fn vector(name: &str) -> std::vec::Vec<u8> {
    test_support::vectors::named(name).bytes()
}

/// Decodes the MessageFrame in `bytes` carrying an `M` into a box.
pub fn decode<M: j2735::frame::Message>(bytes: &[u8]) -> std::boxed::Box<M> {
    let mut m = std::boxed::Box::new(<M as j2735::uper::Placeholder>::placeholder());
    if let Err(e) = j2735::frame::decode_message_into(bytes, &mut *m) {
        panic!("decode: {e:?}");
    }
    m
}

/// A road worker's PSM: id `[0, 0, 0, id]`, at `lat_e7`/`lon_e7`, `secMark` `sec_mark`,
/// accuracy 0.5 m, standing (speed 0), heading unavailable.
pub fn psm_at(id: u8, lat_e7: i32, lon_e7: i32, sec_mark: u16) -> PersonalSafetyMessage {
    use j2735::msg::common::{
        DSecond, Heading, Latitude, Longitude, MsgCount, SemiMajorAxisAccuracy, TemporaryID,
        Velocity,
    };
    let mut psm = <PersonalSafetyMessage as j2735::uper::Placeholder>::placeholder();
    psm.basic_type = PersonalDeviceUserType::APUBLICSAFETYWORKER;
    psm.id = TemporaryID([0, 0, 0, id]);
    psm.sec_mark = DSecond::new(sec_mark).unwrap_or(DSecond::UNAVAILABLE);
    if let Some(c) = MsgCount::new(id % 128) {
        psm.msg_cnt = c;
    }
    psm.position.lat = Latitude::new(lat_e7).unwrap_or(Latitude::UNAVAILABLE);
    psm.position.long = Longitude::new(lon_e7).unwrap_or(Longitude::UNAVAILABLE);
    psm.accuracy.semi_major = SemiMajorAxisAccuracy::new(10).unwrap_or(psm.accuracy.semi_major);
    psm.speed = Velocity::new(0).unwrap_or(Velocity::UNAVAILABLE);
    psm.heading = Heading::UNAVAILABLE;
    psm
}

/// [`psm_at`] at the point `p` of the test road's plane.
pub fn psm(id: u8, p: Point, sec_mark: u16) -> PersonalSafetyMessage {
    let at = at(p);
    psm_at(id, at.lat_e7(), at.lon_e7(), sec_mark)
}
