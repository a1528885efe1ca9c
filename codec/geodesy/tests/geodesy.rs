//! Accuracy of the f64 and f32 local-plane transforms against two independent
//! references written here: a Vincenty inverse geodesic (distance and azimuth, i.e.
//! the azimuthal-equidistant position) and a plain ECEF -> ENU rotation.
//! Run with `--nocapture` to see the figures.

use geodesy::{LatLon, LocalFrame32, LocalFrame64, Point};

const A: f64 = 6_378_137.0;
const F: f64 = 1.0 / 298.257_223_563;

/// Vincenty inverse: (distance m, initial azimuth rad) from p1 to p2 (radians).
fn vincenty(lat1: f64, lon1: f64, lat2: f64, lon2: f64) -> (f64, f64) {
    let b = A * (1.0 - F);
    let l = lon2 - lon1;
    let u1 = ((1.0 - F) * lat1.tan()).atan();
    let u2 = ((1.0 - F) * lat2.tan()).atan();
    let (su1, cu1, su2, cu2) = (u1.sin(), u1.cos(), u2.sin(), u2.cos());
    let mut lam = l;
    let (mut ss, mut cs, mut sig, mut ca2, mut c2sm);
    loop {
        let (sl, cl) = (lam.sin(), lam.cos());
        ss = ((cu2 * sl).powi(2) + (cu1 * su2 - su1 * cu2 * cl).powi(2)).sqrt();
        if ss == 0.0 {
            return (0.0, 0.0);
        }
        cs = su1 * su2 + cu1 * cu2 * cl;
        sig = ss.atan2(cs);
        let sa = cu1 * cu2 * sl / ss;
        ca2 = 1.0 - sa * sa;
        c2sm = if ca2 != 0.0 {
            cs - 2.0 * su1 * su2 / ca2
        } else {
            0.0
        };
        let c = F / 16.0 * ca2 * (4.0 + F * (4.0 - 3.0 * ca2));
        let prev = lam;
        lam =
            l + (1.0 - c) * F * sa * (sig + c * ss * (c2sm + c * cs * (-1.0 + 2.0 * c2sm * c2sm)));
        if (lam - prev).abs() < 1e-13 {
            break;
        }
    }
    let u_sq = ca2 * (A * A - b * b) / (b * b);
    let ka = 1.0 + u_sq / 16384.0 * (4096.0 + u_sq * (-768.0 + u_sq * (320.0 - 175.0 * u_sq)));
    let kb = u_sq / 1024.0 * (256.0 + u_sq * (-128.0 + u_sq * (74.0 - 47.0 * u_sq)));
    let ds = kb
        * ss
        * (c2sm
            + kb / 4.0
                * (cs * (-1.0 + 2.0 * c2sm * c2sm)
                    - kb / 6.0 * c2sm * (-3.0 + 4.0 * ss * ss) * (-3.0 + 4.0 * c2sm * c2sm)));
    let s = b * ka * (sig - ds);
    let (sl, cl) = (lam.sin(), lam.cos());
    let az = (cu2 * sl).atan2(cu1 * su2 - su1 * cu2 * cl);
    (s, az)
}

/// Plain ECEF -> ENU (height 0 for both points).
fn ecef_enu(lat0: f64, lon0: f64, lat: f64, lon: f64) -> (f64, f64) {
    let e2 = F * (2.0 - F);
    let ecef = |la: f64, lo: f64| {
        let n = A / (1.0 - e2 * la.sin().powi(2)).sqrt();
        [
            n * la.cos() * lo.cos(),
            n * la.cos() * lo.sin(),
            n * (1.0 - e2) * la.sin(),
        ]
    };
    let (p0, p) = (ecef(lat0, lon0), ecef(lat, lon));
    let d = [p[0] - p0[0], p[1] - p0[1], p[2] - p0[2]];
    let east = -lon0.sin() * d[0] + lon0.cos() * d[1];
    let north =
        -lat0.sin() * lon0.cos() * d[0] - lat0.sin() * lon0.sin() * d[1] + lat0.cos() * d[2];
    (east, north)
}

struct Stats {
    max64_geo: f64,
    max32_geo: f64,
    max64_ecef: f64,
    max32_ecef: f64,
    max32_round_trip: f64,
}

fn measure(lat0_deg: f64, max_dist: f64, stats: &mut Stats) {
    let origin = LatLon::from_degrees(lat0_deg, -105.0).unwrap_or_default();
    let (f64f, f32f) = (
        LocalFrame64::new(origin, 0.0),
        LocalFrame32::new(origin, 0.0),
    );
    let (la0, lo0) = (origin.lat_deg().to_radians(), origin.lon_deg().to_radians());
    for az_step in 0..24 {
        for &frac in &[0.002, 0.02, 0.2, 0.5, 1.0] {
            let az = (az_step as f64 * 15.0 + 7.0).to_radians();
            let d = max_dist * frac;
            let (e, n) = (d * az.sin(), d * az.cos());
            let Some(p) = f64f.to_wgs84(e, n) else {
                panic!("to_wgs84")
            };
            let (la, lo) = (p.lat_deg().to_radians(), p.lon_deg().to_radians());
            let (s, a) = vincenty(la0, lo0, la, lo);
            let geo = (s * a.sin(), s * a.cos());
            let ecef = ecef_enu(la0, lo0, la, lo);
            let l64 = f64f.to_local(p);
            let l32 = f32f.to_local(p);
            let l32 = (l32.x as f64, l32.y as f64);
            let err =
                |a: (f64, f64), b: (f64, f64)| ((a.0 - b.0).powi(2) + (a.1 - b.1).powi(2)).sqrt();
            stats.max64_geo = stats.max64_geo.max(err(l64, geo));
            stats.max32_geo = stats.max32_geo.max(err(l32, geo));
            stats.max64_ecef = stats.max64_ecef.max(err(l64, ecef));
            stats.max32_ecef = stats.max32_ecef.max(err(l32, ecef));
            let back = f32f
                .to_wgs84(Point::new(l32.0 as f32, l32.1 as f32))
                .unwrap_or_default();
            let rt = f64f.to_local(back);
            stats.max32_round_trip = stats.max32_round_trip.max(err(rt, l64));
        }
    }
}

#[test]
fn local_plane_accuracy_within_5_km() {
    println!("geodesy: max horizontal error over 24 azimuths x 5 distances up to 5 km");
    println!(
        "{:>6} | {:>12} {:>12} | {:>12} {:>12} | {:>12}",
        "lat", "f64 vs geo", "f32 vs geo", "f64 vs ecef", "f32 vs ecef", "f32 rtrip"
    );
    for lat in [0.0, 30.0, 40.5, 60.0, 70.0] {
        let mut s = Stats {
            max64_geo: 0.0,
            max32_geo: 0.0,
            max64_ecef: 0.0,
            max32_ecef: 0.0,
            max32_round_trip: 0.0,
        };
        measure(lat, 5000.0, &mut s);
        println!(
            "{:>6.1} | {:>10.4} m {:>10.4} m | {:>10.6} m {:>10.4} m | {:>10.4} m",
            lat, s.max64_geo, s.max32_geo, s.max64_ecef, s.max32_ecef, s.max32_round_trip
        );
        assert!(s.max64_geo < 0.01, "f64 vs geodesic {}", s.max64_geo);
        assert!(s.max64_ecef < 0.001, "f64 vs ECEF {}", s.max64_ecef);
        assert!(s.max32_geo < 0.05, "f32 vs geodesic {}", s.max32_geo);
        assert!(s.max32_ecef < 0.05, "f32 vs ECEF {}", s.max32_ecef);
        assert!(
            s.max32_round_trip < 0.02,
            "f32 round trip {}",
            s.max32_round_trip
        );
    }
}
