//! One `on_fix` against a 64-lane MAP (8 approaches x 8 lanes x 32 nodes, all
//! within reach of the vehicle) with 4 active work zones.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use obu::geo::{LatLon, LocalFrame64, Point};
use obu::lane::{LaneId, LaneKind, LaneModel, MapId, ModelError, TravelDirection};
use obu::zone::{ContentKind, Directionality, Region, Validity, WorkZone, ZoneInfo, ZoneKey};
use obu::{Fix, Instant, Obu};

/// Unit vector and left normal of approach `a` (bearing 45 a degrees).
fn axes(a: usize) -> ((f32, f32), (f32, f32)) {
    let th = (a as f32 * 45.0).to_radians();
    ((th.sin(), th.cos()), (-th.cos(), th.sin()))
}

/// Lane `k` of approach `a`: 4 ingress (k < 4) then 4 egress, 32 nodes, 20 m apart.
fn fill_lane(m: &mut LaneModel, a: usize, k: usize) -> Result<(), ModelError> {
    let ((dx, dy), (nx, ny)) = axes(a);
    let ingress = k < 4;
    let dir = if ingress {
        TravelDirection::Ingress
    } else {
        TravelDirection::Egress
    };
    let offset = if ingress {
        -1.75 - 3.5 * k as f32
    } else {
        1.75 + 3.5 * (k - 4) as f32
    };
    let lane = m.add_lane(LaneId((a * 8 + k + 1) as u8), dir, LaneKind::Vehicle)?;
    for i in 0..32 {
        let s = 15.0 + 20.0 * i as f32;
        lane.push_node(Point::new(dx * s + nx * offset, dy * s + ny * offset), 3.5)?;
    }
    Ok(())
}

fn fill_zone(
    z: &mut WorkZone,
    frame: &LocalFrame64,
    a: usize,
    lane_k: usize,
) -> Result<(), ModelError> {
    let ((dx, dy), (nx, ny)) = axes(a);
    let offset = -1.75 - 3.5 * lane_k as f32;
    let at = |s: f32| frame.to_wgs84((dx * s + nx * offset) as f64, (dy * s + ny * offset) as f64);
    let anchor = at(400.0).ok_or(ModelError::InvalidValue)?;
    let mut r = Region::path(anchor, 0.0, 3.5);
    r.directionality = Directionality::Forward;
    for s in [400.0, 350.0, 300.0] {
        r.push_latlon(at(s).ok_or(ModelError::InvalidValue)?)?;
    }
    z.push_region(r)?;
    let mut info = ZoneInfo::new(ContentKind::WorkZone);
    [1025, 771, 8196, 268, 12569, 8720]
        .into_iter()
        .for_each(|c| info.push_itis(c));
    z.info = info;
    Ok(())
}

fn setup() -> (Obu, Fix) {
    let reference = LatLon::from_degrees(40.5, -105.0).unwrap_or_default();
    let frame = LocalFrame64::new(reference, 0.0);
    let mut obu = Obu::default();
    let filled = obu.update_map(Instant::ZERO, MapId(1), 1, reference, 0.0, |m| {
        (0..8).try_for_each(|a| (0..8).try_for_each(|k| fill_lane(m, a, k)))
    });
    assert_eq!(filled, Ok(true));
    assert_eq!(obu.maps().get(MapId(1)).map(|m| m.lanes().len()), Some(64));
    let validity = Validity {
        start_year: 2024,
        start_minute: 0,
        duration_min: Validity::INDEFINITE,
    };
    for (n, (a, k)) in [(0, 0), (0, 2), (1, 1), (2, 3)].into_iter().enumerate() {
        let key = ZoneKey::packet([n as u8; 9], 0);
        let r = obu.update_zone(Instant::ZERO, key, 1, validity, |z| {
            fill_zone(z, &frame, a, k)
        });
        assert_eq!(r, Ok(true));
    }
    // On approach 0 (north), lane 1 (ingress, southbound), 550 m out: zone 150 m ahead.
    let pos = frame.to_wgs84(1.75, 550.0).unwrap_or_default();
    let fix = Fix {
        speed_mps: Some(15.0),
        course_deg: Some(180.0),
        accuracy_m: Some(0.5),
        ..Fix::at(pos)
    };
    (obu, fix)
}

fn bench(c: &mut Criterion) {
    let (mut obu, fix) = setup();
    let s = obu.on_fix(Instant::from_millis(1), fix);
    assert!(s.lane.is_some() && s.primary.is_some(), "{s:?}");
    let mut t = 1;
    c.bench_function("on_fix 64 lanes, 4 zones", |b| {
        b.iter(|| {
            t += 100;
            black_box(obu.on_fix(Instant::from_millis(t), black_box(fix)))
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
