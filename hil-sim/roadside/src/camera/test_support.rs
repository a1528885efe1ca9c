//! Fixtures shared by the unit tests of the camera models.

use geodesy::LatLon;
use nalgebra::{Matrix3, Vector3};

use super::Correspondence;
use crate::road::{dist, Road};

/// A known image -> local homography (w > 0 below v = -833).
pub(super) fn truth() -> Matrix3<f64> {
    Matrix3::new(0.05, 0.002, -40.0, 0.001, -0.08, 90.0, 0.0, 0.0012, 1.0)
}

/// `p` mapped by the homography `m`.
pub(super) fn map(m: &Matrix3<f64>, p: [f64; 2]) -> [f64; 2] {
    let v = m * Vector3::new(p[0], p[1], 1.0);
    [v.x / v.z, v.y / v.z]
}

/// A straight eastbound road with 3 forward and 2 backward lanes.
pub(super) fn road() -> Road {
    let r = LatLon::from_degrees(39.7392, -104.9903).unwrap();
    Road::straight(r, 90.0, 1000.0, (3, 2), 3.6, 80.0)
}

/// Exact control points: surveyed positions on the 1e-7 degree grid, pixels from them.
pub(super) fn points(road: &Road, n: usize) -> Vec<Correspondence> {
    let inv = truth().try_inverse().unwrap();
    (0..n)
        .map(|k| {
            let (a, b) = ((k % 4) as f64, (k / 4) as f64);
            let ground =
                LatLon::from_degrees(39.7391 + 7e-5 * a, -104.9901 + 1e-4 * b + 1.3e-5 * a)
                    .unwrap();
            let pixel = map(&inv, road.to_local(ground));
            Correspondence { pixel, ground }
        })
        .collect()
}

/// True when `a` is within `tol` of `b`.
pub(super) fn close(a: Option<[f64; 2]>, b: [f64; 2], tol: f64) -> bool {
    a.is_some_and(|a| dist(a, b) < tol)
}

/// Pixels at which the estimated models are compared with the truth.
pub(super) const PROBES: [[f64; 2]; 5] = [
    [0.0, 0.0],
    [1919.0, 1079.0],
    [960.0, 540.0],
    [200.0, 900.0],
    [1700.0, 100.0],
];

/// Pixel -> local pairs under the [`truth`].
pub(super) fn pairs_of(pixels: &[[f64; 2]]) -> Vec<([f64; 2], [f64; 2])> {
    pixels.iter().map(|p| (*p, map(&truth(), *p))).collect()
}
