//! A reference for a frame's localization: the Cramér-Rao bound of a road user's position
//! given its mask.
//!
//! The bench's mask is the convex hull of the eight projected box corners, each moved by
//! Gaussian noise of `noise_px` in x and y. The corners on the silhouette's outline are the
//! mask's vertices; a corner inside it (the top corner nearest the camera, the bottom
//! corner behind the box) leaves no trace in the mask while its noise keeps it inside. So
//! the mask carries the information of the outline corners' noisy coordinates and no more:
//! their Fisher information about (x, y, length, width, height), plus the class's Gaussian
//! size prior as information on the three sides (the Bayesian bound), bounds from below the
//! covariance of an unbiased estimate of the position that knows sizes only through that
//! prior. An ideal estimator at the bound makes errors drawn from that covariance; the
//! benchmark draws one per box it scores and sets their mean and largest beside the
//! localizer's. It is a reference for one frame alone, not a limit for every estimator: the
//! localizer's boxes take their track's size belief as the prior (what earlier frames
//! measured of the same road user), which a one-frame bound does not have, and the largest
//! of the draws is a sample, not a bound. So beside it the bench draws from a second bound,
//! [`position_bound_size_known`], that of an estimator knowing each road user's size
//! exactly: what no size belief, however many frames it rests on, gets below in one frame.

use super::super::street::{corners, RoadUser};
use super::super::synthetic_camera::PinholeCamera;
use roadside::rng::Prng;
use roadside::road_users::polygon::convex_hull;

/// The box's parameters: x, y (centre, metres), length, width, height.
type Params = [f64; 5];

/// The parameters of `u`'s own box.
fn params_of(u: &RoadUser) -> Params {
    let e = u.extent;
    [u.centre[0], u.centre[1], e.length_m, e.width_m, e.height_m]
}

/// The 16 pixel coordinates of the box's corners for `p`, `None` when a corner is behind
/// the camera.
fn corner_pixels(cam: &PinholeCamera, u: &RoadUser, p: &Params) -> Option<[f64; 16]> {
    let mut moved = *u;
    moved.centre = [p[0], p[1]];
    moved.extent.length_m = p[2];
    moved.extent.width_m = p[3];
    moved.extent.height_m = p[4];
    let mut out = [0.0; 16];
    for (k, c) in corners(&moved.solid()).iter().enumerate() {
        let c = cam.to_camera(*c);
        if c[2] <= 0.1 {
            return None;
        }
        let px = cam.pixel_of(c);
        out[2 * k] = px[0];
        out[2 * k + 1] = px[1];
    }
    Some(out)
}

/// The information matrix (5x5) of the corners' noisy pixels and the size prior about the
/// box of `u`.
fn information(cam: &PinholeCamera, u: &RoadUser, noise_px: f64) -> Option<[[f64; 5]; 5]> {
    let mut info = corner_information(cam, u, noise_px)?;
    let s = u.class.size_prior().sigma;
    for (i, sigma) in [(2, s.length_m), (3, s.width_m), (4, s.height_m)] {
        info[i][i] += 1.0 / (sigma * sigma);
    }
    Some(info)
}

/// Which of the box's eight corners (pixels `px`, as [`corner_pixels`] gives them) are on
/// its silhouette's outline: the vertices of their convex hull.
fn on_outline(px: &[f64; 16]) -> [bool; 8] {
    let corners: Vec<[f64; 2]> = px.chunks_exact(2).map(|c| [c[0], c[1]]).collect();
    let hull = convex_hull(&corners);
    std::array::from_fn(|k| hull.contains(&corners[k]))
}

/// The information matrix (5x5) of the outline corners' noisy pixels alone about the box
/// of `u`.
fn corner_information(cam: &PinholeCamera, u: &RoadUser, noise_px: f64) -> Option<[[f64; 5]; 5]> {
    let at = params_of(u);
    let seen = on_outline(&corner_pixels(cam, u, &at)?);
    let mut jac = [[0.0; 5]; 16];
    for j in 0..5 {
        let step = 1e-4;
        let (mut hi, mut lo) = (at, at);
        hi[j] += step;
        lo[j] -= step;
        let (a, b) = (corner_pixels(cam, u, &hi)?, corner_pixels(cam, u, &lo)?);
        for (row, (pa, pb)) in jac.iter_mut().zip(a.iter().zip(&b)) {
            row[j] = (pa - pb) / (2.0 * step);
        }
    }
    let mut info = [[0.0; 5]; 5];
    // Rows 2k and 2k + 1 are corner k's x and y.
    for row in jac
        .iter()
        .enumerate()
        .filter(|(r, _)| seen[r / 2])
        .map(|(_, row)| row)
    {
        for i in 0..5 {
            for j in 0..5 {
                info[i][j] += row[i] * row[j] / (noise_px * noise_px);
            }
        }
    }
    Some(info)
}

/// The inverse of a symmetric positive definite 5x5 matrix (Gauss-Jordan).
fn inverse(mut a: [[f64; 5]; 5]) -> Option<[[f64; 5]; 5]> {
    let mut inv = [[0.0; 5]; 5];
    (0..5).for_each(|i| inv[i][i] = 1.0);
    for c in 0..5 {
        let p = (c..5).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))?;
        if a[p][c].abs() < 1e-15 {
            return None;
        }
        a.swap(c, p);
        inv.swap(c, p);
        let d = a[c][c];
        for k in 0..5 {
            a[c][k] /= d;
            inv[c][k] /= d;
        }
        for r in (0..5).filter(|&r| r != c) {
            let f = a[r][c];
            for k in 0..5 {
                a[r][k] -= f * a[c][k];
                inv[r][k] -= f * inv[c][k];
            }
        }
    }
    Some(inv)
}

/// The bound on the covariance of the position of `u` (east, north; square metres) when its
/// mask's corners carry `noise_px` of noise.
pub fn position_bound(cam: &PinholeCamera, u: &RoadUser, noise_px: f64) -> Option<[[f64; 2]; 2]> {
    let cov = inverse(information(cam, u, noise_px)?)?;
    Some([[cov[0][0], cov[0][1]], [cov[1][0], cov[1][1]]])
}

/// The bound on the covariance of the position of `u` for an estimator that knows its
/// size exactly: the inverse of the corners' information about the position alone. No
/// knowledge of the size, from any number of frames, places it better from one frame.
pub fn position_bound_size_known(
    cam: &PinholeCamera,
    u: &RoadUser,
    noise_px: f64,
) -> Option<[[f64; 2]; 2]> {
    let info = corner_information(cam, u, noise_px)?;
    let [[a, b], [c, d]] = [[info[0][0], info[0][1]], [info[1][0], info[1][1]]];
    let det = a * d - b * c;
    (det.abs() > 1e-15).then(|| [[d / det, -b / det], [-c / det, a / det]])
}

/// One error (metres) of an estimator at the bound `cov`: the length of a draw from it.
pub fn ideal_error(cov: [[f64; 2]; 2], rng: &mut Prng) -> f64 {
    let l00 = cov[0][0].max(0.0).sqrt();
    let l10 = if l00 > 0.0 { cov[1][0] / l00 } else { 0.0 };
    let l11 = (cov[1][1] - l10 * l10).max(0.0).sqrt();
    let (a, b) = (rng.normal(), rng.normal());
    (l00 * a).hypot(l10 * a + l11 * b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::roadside_bench::street::pole_camera;
    use roadside::road_users::RoadUserClass;

    /// The bound grows with range and with noise as the geometry says: twice the noise, up
    /// to twice the position's sigma (all of it where the data decide); a far car is placed
    /// worse than a near one.
    #[test]
    fn the_bound_follows_noise_and_range() {
        let cam = pole_camera();
        let near = RoadUser::standing(1, RoadUserClass::Car, [5.0, 15.0]);
        let far = RoadUser::standing(2, RoadUserClass::Car, [5.0, 40.0]);
        let trace = |c: [[f64; 2]; 2]| (c[0][0] + c[1][1]).sqrt();
        let n1 = trace(position_bound(&cam, &near, 1.0).unwrap());
        let f1 = trace(position_bound(&cam, &far, 1.0).unwrap());
        let f2 = trace(position_bound(&cam, &far, 2.0).unwrap());
        assert!(n1 < f1, "near {n1} far {f1}");
        assert!(f2 > 1.5 * f1 && f2 < 2.0 * f1 + 1e-9, "1 px {f1} 2 px {f2}");
        // Knowing the size places the road user better, and the bound then scales with the
        // noise exactly.
        let k1 = trace(position_bound_size_known(&cam, &far, 1.0).unwrap());
        let k2 = trace(position_bound_size_known(&cam, &far, 2.0).unwrap());
        assert!(k1 < f1, "size known {k1}, prior {f1}");
        assert!((k2 - 2.0 * k1).abs() < 1e-9 * k1.max(1.0), "{k1} {k2}");
        // A box seen from above shows six of its corners: the top one nearest the camera
        // and the bottom one behind are inside its outline and inform nothing.
        let seen = on_outline(&corner_pixels(&cam, &far, &params_of(&far)).unwrap());
        assert_eq!(seen.iter().filter(|s| **s).count(), 6, "{seen:?}");
        // An exact inverse: the information times the bound is the identity.
        let info = information(&cam, &far, 1.0).unwrap();
        let inv = inverse(info).unwrap();
        for (i, row) in info.iter().enumerate() {
            for j in 0..5 {
                let v: f64 = row.iter().zip(&inv).map(|(a, r)| a * r[j]).sum();
                assert!((v - f64::from(u8::from(i == j))).abs() < 1e-6);
            }
        }
    }
}
