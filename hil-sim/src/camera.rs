//! The roadside camera's model: image pixels to the road plane (local east/north metres of a
//! [`Road`], and on to latitude/longitude).
//!
//! Two forms, both estimated from ground control points ([`Correspondence`]: a pixel and the
//! surveyed position of the same road point), both behind [`CameraModel`]:
//!
//! - [`Homography`]: one 3x3 plane-to-plane map, estimated by the normalised direct linear
//!   transformation (Hartley normalisation of both point sets, SVD of the 2n x 9 system, least
//!   squares with more than four points).
//! - [`TwoStep`]: the camera paper's form, a perspective homography from the image to a
//!   top-down (bird's-eye) image ([`TopDown`]), then a least-squares affine map from that image
//!   to local metres.
//!
//! Degenerate point sets are refused with a [`ModelError`]; a pixel at or above the horizon
//! maps to `None`. No function here panics on its input.

use std::fmt;

use nalgebra::{DMatrix, Matrix3, Vector3};
use obu::LatLon;
use serde::Deserialize;

use crate::road::{dist, Road};

/// Relative thickness (sqrt of the scatter eigenvalue ratio) below which points are collinear.
const COLLINEAR_TOL: f64 = 1e-3;
/// Second-smallest over largest singular value of the DLT system below which its solution is
/// not unique.
const RANK_TOL: f64 = 1e-9;
/// |det| of the unit-norm normalised homography below which it is singular.
const SINGULAR_TOL: f64 = 1e-9;
/// Fraction of the smallest calibration `w` below which a pixel counts as at the horizon
/// (over a thousand times farther than the farthest control point).
const HORIZON_FRACTION: f64 = 1e-3;
/// Iteration cap of the SVD.
const SVD_MAX_ITER: usize = 10_000;

/// One ground control point: a pixel and the surveyed position of the same road point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Correspondence {
    /// Image position `[u, v]`, pixels (u right, v down).
    pub pixel: [f64; 2],
    /// Position on the road plane.
    pub ground: LatLon,
}

/// Why a calibration file was refused.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum CalibrationError {
    /// The file could not be read.
    Io(String),
    /// Not JSON of the expected shape (serde's message, with line and column).
    Json(String),
    /// `points[index]` is invalid.
    Point {
        /// Index in `points` (0-based).
        index: usize,
        /// What is wrong with it.
        reason: &'static str,
    },
}

impl fmt::Display for CalibrationError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io(e) => write!(f, "calibration file: {e}"),
            Self::Json(e) => write!(f, "calibration JSON: {e}"),
            Self::Point { index, reason } => write!(f, "calibration points[{index}]: {reason}"),
        }
    }
}

impl std::error::Error for CalibrationError {}

#[derive(Deserialize)]
struct RawCalibration {
    points: Vec<RawPoint>,
}

#[derive(Deserialize)]
struct RawPoint {
    pixel: [f64; 2],
    lat: f64,
    lon: f64,
}

/// Parses a calibration file: `{"points": [{"pixel": [u, v], "lat": deg, "lon": deg}, ...]}`.
///
/// Other keys are ignored. The number of points is not checked here (see [`ModelError`]).
pub fn parse_calibration(json: &str) -> Result<Vec<Correspondence>, CalibrationError> {
    let raw: RawCalibration =
        serde_json::from_str(json).map_err(|e| CalibrationError::Json(e.to_string()))?;
    raw.points
        .iter()
        .enumerate()
        .map(|(index, p)| {
            let bad = |reason| CalibrationError::Point { index, reason };
            if !p.pixel.iter().all(|c| c.is_finite()) {
                return Err(bad("pixel is not finite"));
            }
            if !(-90.0..=90.0).contains(&p.lat) || !(-180.0..=180.0).contains(&p.lon) {
                return Err(bad("lat/lon out of range"));
            }
            let ground = LatLon::from_degrees(p.lat, p.lon).ok_or(bad("lat/lon out of range"))?;
            Ok(Correspondence {
                pixel: p.pixel,
                ground,
            })
        })
        .collect()
}

/// Reads and parses a calibration file (see [`parse_calibration`]).
pub fn load_calibration(path: &std::path::Path) -> Result<Vec<Correspondence>, CalibrationError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| CalibrationError::Io(format!("{}: {e}", path.display())))?;
    parse_calibration(&text)
}

/// Which point set of the correspondences an error is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PointSet {
    /// The source points (image pixels).
    Image,
    /// The target points (road plane, or the top-down image).
    Ground,
}

/// Why a camera model cannot be estimated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum ModelError {
    /// Too few correspondences.
    TooFewPoints {
        /// Points given.
        got: usize,
        /// Points needed.
        need: usize,
    },
    /// Correspondence `index` has a non-finite coordinate.
    NonFinite {
        /// Index of the correspondence.
        index: usize,
    },
    /// All points (or three of a minimal set of four) are (nearly) on one line.
    Collinear {
        /// The point set that is collinear.
        set: PointSet,
    },
    /// The points do not fix a unique mapping (e.g. all but one on a line).
    Degenerate,
    /// The estimated homography is singular.
    Singular,
    /// The control points lie on both sides of the horizon: no camera sees them so.
    Horizon,
    /// The top-down view is invalid (scale not positive, bearing not finite, bad quad).
    BadTopDown,
}

impl fmt::Display for ModelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::TooFewPoints { got, need } => {
                write!(f, "{got} correspondences, at least {need} needed")
            }
            Self::NonFinite { index } => write!(f, "correspondence {index} is not finite"),
            Self::Collinear { set } => write!(f, "{set:?} points are (nearly) collinear"),
            Self::Degenerate => f.write_str("the points do not fix a unique mapping"),
            Self::Singular => f.write_str("the estimated homography is singular"),
            Self::Horizon => f.write_str("control points lie on both sides of the horizon"),
            Self::BadTopDown => f.write_str("invalid top-down view"),
        }
    }
}

impl std::error::Error for ModelError {}

/// A plane-to-plane projective map (3x3, up to scale): for the camera, image pixels to road
/// local metres.
#[derive(Debug, Clone, PartialEq)]
pub struct Homography {
    /// Scaled so that the control points have `w > 0`.
    m: Matrix3<f64>,
    /// Smallest `w` over the control points.
    w_min: f64,
    rmse: f64,
}

impl Homography {
    /// Estimates the camera homography from control points; `road` gives the local frame.
    pub fn from_correspondences(
        road: &Road,
        points: &[Correspondence],
    ) -> Result<Self, ModelError> {
        Self::estimate(&local_pairs(road, points))
    }

    /// Estimates the map `from -> to` of point pairs by the normalised DLT (least squares
    /// over more than four pairs).
    pub fn estimate(pairs: &[([f64; 2], [f64; 2])]) -> Result<Self, ModelError> {
        check_pairs(pairs, 4)?;
        let (from, to): (Vec<_>, Vec<_>) = pairs.iter().copied().unzip();
        for (set, pts) in [(PointSet::Image, &from), (PointSet::Ground, &to)] {
            check_spread(set, pts)?;
        }
        let t_from = normaliser(&from).ok_or(ModelError::Collinear {
            set: PointSet::Image,
        })?;
        let t_to = normaliser(&to).ok_or(ModelError::Collinear {
            set: PointSet::Ground,
        })?;
        let nf: Vec<_> = from.iter().map(|p| affine_apply(&t_from, *p)).collect();
        let nt: Vec<_> = to.iter().map(|p| affine_apply(&t_to, *p)).collect();
        let h_norm = solve_dlt(&nf, &nt)?;
        let t_inv = t_to.try_inverse().ok_or(ModelError::Singular)?;
        let m = t_inv * h_norm * t_from;
        Self::finish(m, pairs)
    }

    /// Scales `m` to unit norm with `w > 0` at the control points, and measures the fit.
    fn finish(m: Matrix3<f64>, pairs: &[([f64; 2], [f64; 2])]) -> Result<Self, ModelError> {
        let norm = m.norm();
        if !(norm.is_finite() && norm > 0.0) {
            return Err(ModelError::Singular);
        }
        let mut m = m / norm;
        let ws: Vec<f64> = pairs.iter().map(|(p, _)| w_of(&m, *p)).collect();
        if ws.iter().all(|w| *w < 0.0) {
            m = -m;
        } else if !ws.iter().all(|w| *w > 0.0) {
            return Err(ModelError::Horizon);
        }
        let w_min = ws.iter().map(|w| w.abs()).fold(f64::INFINITY, f64::min);
        let mut h = Self {
            m,
            w_min,
            rmse: 0.0,
        };
        h.rmse = rmse(pairs.iter().map(|(p, q)| h.apply(*p).map(|r| dist(r, *q))))
            .ok_or(ModelError::Horizon)?;
        Ok(h)
    }

    /// Maps a point; `None` at or beyond the horizon (`w` near zero or of the wrong sign) or
    /// for a non-finite input.
    pub fn apply(&self, p: [f64; 2]) -> Option<[f64; 2]> {
        if !(p[0].is_finite() && p[1].is_finite()) {
            return None;
        }
        let v = self.m * Vector3::new(p[0], p[1], 1.0);
        if v.z.is_nan() || v.z <= HORIZON_FRACTION * self.w_min {
            return None;
        }
        let out = [v.x / v.z, v.y / v.z];
        (out[0].is_finite() && out[1].is_finite()).then_some(out)
    }

    /// Root-mean-square reprojection error over the control points, in target units (metres
    /// for the camera homography).
    pub fn rmse(&self) -> f64 {
        self.rmse
    }

    /// The matrix, row-major, unit Frobenius norm.
    pub fn matrix(&self) -> [[f64; 3]; 3] {
        let m = &self.m;
        [0, 1, 2].map(|r| [m[(r, 0)], m[(r, 1)], m[(r, 2)]])
    }
}

/// The top-down (bird's-eye) image of the two-step form: the road plane seen from above,
/// `px_per_m` pixels a metre, with `up_bearing_deg` pointing up (to -y); its top-left corner
/// is that of the control points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TopDown {
    /// Scale, pixels per metre (> 0).
    pub px_per_m: f64,
    /// Bearing (degrees clockwise from north) drawn upwards, e.g. the road's direction.
    pub up_bearing_deg: f64,
    /// The four control points (indices) of the perspective step, e.g. the corners of a road
    /// trapezoid as in the paper; `None` uses all points (least squares).
    pub quad: Option<[usize; 4]>,
}

impl TopDown {
    /// A view of `road` along its first lane, 10 px/m, perspective from all points.
    pub fn along(road: &Road) -> Self {
        let up_bearing_deg = road
            .lanes
            .first()
            .and_then(|l| l.at(0.0))
            .map_or(0.0, |on| on.bearing_deg);
        Self {
            px_per_m: 10.0,
            up_bearing_deg,
            quad: None,
        }
    }

    /// Top-down pixels of local points (before the shift to the top-left corner).
    fn rotate(&self, p: [f64; 2]) -> [f64; 2] {
        let (s, c) = self.up_bearing_deg.to_radians().sin_cos();
        // Up (-y) is the bearing direction (s, c); right (+x) is (c, -s).
        [
            self.px_per_m * (p[0] * c - p[1] * s),
            -self.px_per_m * (p[0] * s + p[1] * c),
        ]
    }

    fn is_valid(&self, n: usize) -> bool {
        let scale_ok = self.px_per_m.is_finite() && self.px_per_m > 0.0;
        let quad_ok = self.quad.is_none_or(|q| {
            q.iter().all(|&i| i < n) && (0..4).all(|a| (a + 1..4).all(|b| q[a] != q[b]))
        });
        scale_ok && self.up_bearing_deg.is_finite() && quad_ok
    }
}

/// The two-step form: perspective to a top-down image, then a least-squares affine map
/// (6 parameters) from it to local metres.
#[derive(Debug, Clone, PartialEq)]
pub struct TwoStep {
    /// Image pixels -> top-down pixels.
    perspective: Homography,
    /// Top-down pixels -> local metres, rows of `[a, b, c]` (`x' = a x + b y + c`).
    affine: [[f64; 3]; 2],
    rmse: f64,
}

impl TwoStep {
    /// Estimates both steps from control points; `road` gives the local frame.
    pub fn from_correspondences(
        road: &Road,
        points: &[Correspondence],
        view: TopDown,
    ) -> Result<Self, ModelError> {
        let pairs = local_pairs(road, points);
        check_pairs(&pairs, 4)?;
        if !view.is_valid(pairs.len()) {
            return Err(ModelError::BadTopDown);
        }
        let rotated: Vec<_> = pairs.iter().map(|(_, g)| view.rotate(*g)).collect();
        let corner = rotated
            .iter()
            .fold([f64::INFINITY; 2], |c, p| [c[0].min(p[0]), c[1].min(p[1])]);
        let top: Vec<_> = pairs
            .iter()
            .zip(&rotated)
            .map(|((px, _), r)| (*px, [r[0] - corner[0], r[1] - corner[1]]))
            .collect();
        let perspective = match view.quad {
            Some(q) => Homography::estimate(&q.map(|i| top[i]))?,
            None => Homography::estimate(&top)?,
        };
        let warped = pairs
            .iter()
            .map(|(px, g)| perspective.apply(*px).map(|t| (t, *g)))
            .collect::<Option<Vec<_>>>()
            .ok_or(ModelError::Horizon)?;
        let affine = fit_affine(&warped)?;
        let mut model = Self {
            perspective,
            affine,
            rmse: 0.0,
        };
        model.rmse = rmse(
            pairs
                .iter()
                .map(|(p, g)| model.to_local(*p).map(|r| dist(r, *g))),
        )
        .ok_or(ModelError::Horizon)?;
        Ok(model)
    }

    /// Local metres of a pixel; `None` at or beyond the horizon.
    pub fn to_local(&self, px: [f64; 2]) -> Option<[f64; 2]> {
        let t = self.perspective.apply(px)?;
        let a = &self.affine;
        Some([0, 1].map(|r| a[r][0] * t[0] + a[r][1] * t[1] + a[r][2]))
    }

    /// Top-down pixels of an image pixel (the first step).
    pub fn to_top_down(&self, px: [f64; 2]) -> Option<[f64; 2]> {
        self.perspective.apply(px)
    }

    /// Root-mean-square error over the control points, metres.
    pub fn rmse_m(&self) -> f64 {
        self.rmse
    }
}

/// A camera model of either form.
#[derive(Debug, Clone, PartialEq)]
pub enum CameraModel {
    /// One homography, image -> local metres.
    Homography(Homography),
    /// Perspective to a top-down image, then affine to local metres.
    TwoStep(TwoStep),
}

impl CameraModel {
    /// The one-homography form from control points.
    pub fn homography(road: &Road, points: &[Correspondence]) -> Result<Self, ModelError> {
        Homography::from_correspondences(road, points).map(Self::Homography)
    }

    /// The two-step form from control points.
    pub fn two_step(
        road: &Road,
        points: &[Correspondence],
        view: TopDown,
    ) -> Result<Self, ModelError> {
        TwoStep::from_correspondences(road, points, view).map(Self::TwoStep)
    }

    /// Local metres (east, north) of a pixel; `None` at or beyond the horizon.
    pub fn to_local(&self, px: [f64; 2]) -> Option<[f64; 2]> {
        match self {
            Self::Homography(h) => h.apply(px),
            Self::TwoStep(t) => t.to_local(px),
        }
    }

    /// WGS84 position of a pixel.
    pub fn to_wgs84(&self, road: &Road, px: [f64; 2]) -> Option<LatLon> {
        road.to_wgs84(self.to_local(px)?)
    }

    /// Root-mean-square error over the control points, metres.
    pub fn rmse_m(&self) -> f64 {
        match self {
            Self::Homography(h) => h.rmse(),
            Self::TwoStep(t) => t.rmse_m(),
        }
    }
}

/// Pixel -> local metre pairs.
fn local_pairs(road: &Road, points: &[Correspondence]) -> Vec<([f64; 2], [f64; 2])> {
    points
        .iter()
        .map(|c| (c.pixel, road.to_local(c.ground)))
        .collect()
}

/// Enough pairs, all finite.
fn check_pairs(pairs: &[([f64; 2], [f64; 2])], need: usize) -> Result<(), ModelError> {
    if pairs.len() < need {
        return Err(ModelError::TooFewPoints {
            got: pairs.len(),
            need,
        });
    }
    match pairs
        .iter()
        .position(|(a, b)| !a.iter().chain(b).all(|c| c.is_finite()))
    {
        Some(index) => Err(ModelError::NonFinite { index }),
        None => Ok(()),
    }
}

/// Refuses a (nearly) collinear set, and for a minimal set (four points) any collinear triple.
fn check_spread(set: PointSet, pts: &[[f64; 2]]) -> Result<(), ModelError> {
    let without = |skip: usize| -> Vec<[f64; 2]> {
        let others = pts.iter().enumerate().filter(|(i, _)| *i != skip);
        others.map(|(_, p)| *p).collect()
    };
    let triple = pts.len() == 4 && (0..4).any(|k| thickness(&without(k)) < COLLINEAR_TOL);
    if triple || thickness(pts) < COLLINEAR_TOL {
        Err(ModelError::Collinear { set })
    } else {
        Ok(())
    }
}

fn centroid(pts: &[[f64; 2]]) -> [f64; 2] {
    let n = pts.len().max(1) as f64;
    let s = pts.iter().fold([0.0; 2], |s, p| [s[0] + p[0], s[1] + p[1]]);
    [s[0] / n, s[1] / n]
}

/// sqrt(smallest / largest eigenvalue) of the scatter matrix: 0 on a line, 1 for a round cloud.
fn thickness(pts: &[[f64; 2]]) -> f64 {
    let c = centroid(pts);
    let (mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0);
    for p in pts {
        let (x, y) = (p[0] - c[0], p[1] - c[1]);
        sxx += x * x;
        syy += y * y;
        sxy += x * y;
    }
    let half = (sxx + syy) / 2.0;
    let disc = (half * half - (sxx * syy - sxy * sxy)).max(0.0).sqrt();
    let (big, small) = (half + disc, (half - disc).max(0.0));
    if big > 0.0 {
        (small / big).sqrt()
    } else {
        0.0
    }
}

/// Hartley normalisation: centroid to the origin, mean distance to sqrt 2.
fn normaliser(pts: &[[f64; 2]]) -> Option<Matrix3<f64>> {
    let c = centroid(pts);
    let mean = pts.iter().map(|p| dist(*p, c)).sum::<f64>() / pts.len().max(1) as f64;
    if !(mean.is_finite() && mean > 0.0) {
        return None;
    }
    let s = std::f64::consts::SQRT_2 / mean;
    Some(Matrix3::new(
        s,
        0.0,
        -s * c[0],
        0.0,
        s,
        -s * c[1],
        0.0,
        0.0,
        1.0,
    ))
}

/// `w` (third homogeneous coordinate) of a point under `m`.
fn w_of(m: &Matrix3<f64>, p: [f64; 2]) -> f64 {
    m[(2, 0)] * p[0] + m[(2, 1)] * p[1] + m[(2, 2)]
}

/// A matrix whose last row is `[0, 0, 1]` applied to a point.
fn affine_apply(m: &Matrix3<f64>, p: [f64; 2]) -> [f64; 2] {
    let v = m * Vector3::new(p[0], p[1], 1.0);
    [v.x, v.y]
}

/// The DLT on normalised points: the null vector of the 2n x 9 system.
fn solve_dlt(from: &[[f64; 2]], to: &[[f64; 2]]) -> Result<Matrix3<f64>, ModelError> {
    // At least 9 rows so that the SVD yields all 9 right singular vectors.
    let rows = (2 * from.len()).max(9);
    let mut a = DMatrix::<f64>::zeros(rows, 9);
    for (i, (p, q)) in from.iter().zip(to).enumerate() {
        let (x, y, u, v) = (p[0], p[1], q[0], q[1]);
        let r0 = [-x, -y, -1.0, 0.0, 0.0, 0.0, u * x, u * y, u];
        let r1 = [0.0, 0.0, 0.0, -x, -y, -1.0, v * x, v * y, v];
        for k in 0..9 {
            a[(2 * i, k)] = r0[k];
            a[(2 * i + 1, k)] = r1[k];
        }
    }
    let svd = a
        .try_svd(false, true, f64::EPSILON, SVD_MAX_ITER)
        .ok_or(ModelError::Degenerate)?;
    let v_t = svd.v_t.as_ref().ok_or(ModelError::Degenerate)?;
    let s = &svd.singular_values;
    // Sorted descending: the last is the solution, the one before must be clearly non-zero.
    let n = s.len();
    if n < 9 || s[n - 2].is_nan() || s[n - 2] <= RANK_TOL * s[0] {
        return Err(ModelError::Degenerate);
    }
    let h = v_t.row(n - 1);
    let m = Matrix3::from_fn(|r, c| h[3 * r + c]);
    let det = m.determinant();
    if det.is_nan() || det.abs() <= SINGULAR_TOL {
        return Err(ModelError::Singular);
    }
    Ok(m)
}

/// Least-squares affine map `from -> to` (normalised source points), rows `[a, b, c]`.
fn fit_affine(pairs: &[([f64; 2], [f64; 2])]) -> Result<[[f64; 3]; 2], ModelError> {
    check_pairs(pairs, 3)?;
    let (from, to): (Vec<_>, Vec<_>) = pairs.iter().copied().unzip();
    for (set, pts) in [(PointSet::Image, &from), (PointSet::Ground, &to)] {
        if thickness(pts) < COLLINEAR_TOL {
            return Err(ModelError::Collinear { set });
        }
    }
    let t = normaliser(&from).ok_or(ModelError::Collinear {
        set: PointSet::Image,
    })?;
    let m = DMatrix::from_fn(pairs.len(), 3, |r, c| {
        let p = affine_apply(&t, from[r]);
        [p[0], p[1], 1.0][c]
    });
    let b = DMatrix::from_fn(pairs.len(), 2, |r, c| to[r][c]);
    let svd = m
        .try_svd(true, true, f64::EPSILON, SVD_MAX_ITER)
        .ok_or(ModelError::Degenerate)?;
    let tol = RANK_TOL * svd.singular_values.max();
    let p = svd.solve(&b, tol).map_err(|_| ModelError::Degenerate)?;
    // x' = P^T (T [x; 1]).
    let rows = [0, 1].map(|k| {
        let row = Vector3::new(p[(0, k)], p[(1, k)], p[(2, k)]).transpose() * t;
        [row[0], row[1], row[2]]
    });
    if rows.iter().flatten().all(|v| v.is_finite()) {
        Ok(rows)
    } else {
        Err(ModelError::Degenerate)
    }
}

/// Root mean square of distances; `None` when one is missing.
fn rmse(errors: impl Iterator<Item = Option<f64>>) -> Option<f64> {
    let (mut sum, mut n) = (0.0, 0usize);
    for e in errors {
        let e = e?;
        sum += e * e;
        n += 1;
    }
    Some((sum / n.max(1) as f64).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A known image -> local homography (w > 0 below v = -833).
    fn truth() -> Matrix3<f64> {
        Matrix3::new(0.05, 0.002, -40.0, 0.001, -0.08, 90.0, 0.0, 0.0012, 1.0)
    }

    fn map(m: &Matrix3<f64>, p: [f64; 2]) -> [f64; 2] {
        let v = m * Vector3::new(p[0], p[1], 1.0);
        [v.x / v.z, v.y / v.z]
    }

    fn road() -> Road {
        let r = LatLon::from_degrees(39.7392, -104.9903).unwrap();
        Road::straight(r, 90.0, 1000.0, (3, 2), 3.6, 80.0)
    }

    /// Exact control points: surveyed positions on the 1e-7 degree grid, pixels from them.
    fn points(road: &Road, n: usize) -> Vec<Correspondence> {
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

    fn close(a: Option<[f64; 2]>, b: [f64; 2], tol: f64) -> bool {
        a.is_some_and(|a| dist(a, b) < tol)
    }

    const PROBES: [[f64; 2]; 5] = [
        [0.0, 0.0],
        [1919.0, 1079.0],
        [960.0, 540.0],
        [200.0, 900.0],
        [1700.0, 100.0],
    ];

    #[test]
    fn known_homography_is_recovered() {
        const GRID: [[f64; 2]; 12] = [
            [150.0, 1000.0],
            [1750.0, 950.0],
            [1200.0, 150.0],
            [400.0, 200.0],
            [960.0, 600.0],
            [100.0, 500.0],
            [1800.0, 450.0],
            [700.0, 900.0],
            [1300.0, 800.0],
            [600.0, 100.0],
            [1500.0, 300.0],
            [300.0, 700.0],
        ];
        let h = truth();
        for n in [4, 5, 12] {
            let pairs = pairs_of(&GRID[..n]);
            let est = Homography::estimate(&pairs).unwrap();
            assert!(est.rmse() < 1e-9, "n {n}: rmse {}", est.rmse());
            for p in PROBES {
                assert!(close(est.apply(p), map(&h, p), 1e-6), "n {n} at {p:?}");
            }
            // Above the horizon (w < 0) and at it.
            assert_eq!(est.apply([500.0, -1000.0]), None);
            assert_eq!(est.apply([500.0, -1.0 / 0.0012]), None);
            assert_eq!(est.apply([f64::NAN, 0.0]), None);
        }
    }

    #[test]
    fn control_points_through_the_road_frame() {
        let road = road();
        let pts = points(&road, 8);
        let model = CameraModel::homography(&road, &pts).unwrap();
        assert!(model.rmse_m() < 1e-6);
        for p in PROBES {
            assert!(close(model.to_local(p), map(&truth(), p), 1e-6), "at {p:?}");
        }
        let ll = model.to_wgs84(&road, pts[3].pixel).unwrap();
        assert_eq!(ll, pts[3].ground);
    }

    #[test]
    fn two_step_reproduces_the_mapping() {
        let road = road();
        let pts = points(&road, 12);
        let all = TopDown::along(&road);
        assert!((all.up_bearing_deg - 90.0).abs() < 1e-9);
        let quad = TopDown {
            quad: Some([0, 3, 8, 11]),
            px_per_m: 25.0,
            ..all
        };
        for view in [all, quad] {
            let model = CameraModel::two_step(&road, &pts, view).unwrap();
            assert!(model.rmse_m() < 1e-6, "{view:?}: {}", model.rmse_m());
            for p in PROBES {
                assert!(
                    close(model.to_local(p), map(&truth(), p), 1e-6),
                    "{view:?} at {p:?}"
                );
            }
        }
        // Top-down: road direction (east) is up, so east of a point is above it.
        let CameraModel::TwoStep(t) = CameraModel::two_step(&road, &pts, all).unwrap() else {
            unreachable!()
        };
        let near = t.to_top_down(pts[0].pixel).unwrap();
        let far = t.to_top_down(pts[11].pixel).unwrap();
        assert!(far[1] < near[1]);
        let bad = TopDown {
            quad: Some([0, 0, 1, 2]),
            ..all
        };
        assert_eq!(
            TwoStep::from_correspondences(&road, &pts, bad),
            Err(ModelError::BadTopDown)
        );
        let bad = TopDown {
            px_per_m: 0.0,
            ..all
        };
        assert_eq!(
            TwoStep::from_correspondences(&road, &pts, bad),
            Err(ModelError::BadTopDown)
        );
    }

    fn pairs_of(pixels: &[[f64; 2]]) -> Vec<([f64; 2], [f64; 2])> {
        pixels.iter().map(|p| (*p, map(&truth(), *p))).collect()
    }

    #[test]
    fn degenerate_sets_are_refused() {
        let three = pairs_of(&[[0.0, 0.0], [100.0, 0.0], [0.0, 100.0]]);
        assert_eq!(
            Homography::estimate(&three),
            Err(ModelError::TooFewPoints { got: 3, need: 4 })
        );
        let line = pairs_of(&[
            [0.0, 0.0],
            [100.0, 100.0],
            [200.0, 200.0],
            [300.0, 300.0],
            [400.0, 400.0],
        ]);
        assert_eq!(
            Homography::estimate(&line),
            Err(ModelError::Collinear {
                set: PointSet::Image
            })
        );
        // Three of a minimal set on a line.
        let tri = pairs_of(&[[0.0, 0.0], [100.0, 100.0], [200.0, 200.0], [500.0, 0.0]]);
        assert_eq!(
            Homography::estimate(&tri),
            Err(ModelError::Collinear {
                set: PointSet::Image
            })
        );
        // Ground collinear although the image is not.
        let ground: Vec<_> = [
            [0.0, 0.0],
            [900.0, 50.0],
            [100.0, 700.0],
            [800.0, 800.0],
            [400.0, 300.0],
        ]
        .iter()
        .enumerate()
        .map(|(k, p)| (*p, [k as f64 * 3.0, 1.0 + k as f64 * 1e-6]))
        .collect();
        assert_eq!(
            Homography::estimate(&ground),
            Err(ModelError::Collinear {
                set: PointSet::Ground
            })
        );
        // All but one on a line: no unique solution.
        let most = pairs_of(&[
            [100.0, 100.0],
            [300.0, 300.0],
            [500.0, 500.0],
            [700.0, 700.0],
            [900.0, 900.0],
            [1500.0, 200.0],
        ]);
        assert_eq!(Homography::estimate(&most), Err(ModelError::Degenerate));
        let mut nan = pairs_of(&[[0.0, 0.0], [100.0, 0.0], [0.0, 100.0], [100.0, 100.0]]);
        nan[2].1[0] = f64::NAN;
        assert_eq!(
            Homography::estimate(&nan),
            Err(ModelError::NonFinite { index: 2 })
        );
        // Control points on both sides of the horizon (v = -833).
        let both = pairs_of(&[
            [0.0, 0.0],
            [900.0, 50.0],
            [100.0, -1500.0],
            [800.0, -1600.0],
            [400.0, 300.0],
        ]);
        assert_eq!(Homography::estimate(&both), Err(ModelError::Horizon));
    }

    #[test]
    fn calibration_files() {
        let json = r#"{"camera": "cam 1", "points": [
            {"pixel": [10.5, 20], "lat": 39.7392, "lon": -104.9903},
            {"pixel": [30, 40], "lat": -45.0, "lon": 170.25, "name": "kerb"}]}"#;
        let pts = parse_calibration(json).unwrap();
        assert_eq!(pts.len(), 2);
        assert_eq!(pts[0].pixel, [10.5, 20.0]);
        assert_eq!(pts[1].ground, LatLon::from_degrees(-45.0, 170.25).unwrap());
        let bad_lat = r#"{"points": [{"pixel": [1, 2], "lat": 1, "lon": 2}, {"pixel": [1, 2], "lat": 91, "lon": 2}]}"#;
        assert_eq!(
            parse_calibration(bad_lat),
            Err(CalibrationError::Point {
                index: 1,
                reason: "lat/lon out of range"
            })
        );
        for bad in [
            "",
            "[]",
            r#"{"points": [{"pixel": [1], "lat": 1, "lon": 2}]}"#,
            r#"{"points": [{"pixel": [1, 2], "lon": 2}]}"#,
            r#"{"points": [{"pixel": [1, 2], "lat": "x", "lon": 2}]}"#,
            r#"{"points": [{"pixel": [1, 2], "lat": 1e999, "lon": 2}]}"#,
        ] {
            let e = parse_calibration(bad).unwrap_err();
            assert!(matches!(e, CalibrationError::Json(_)), "{bad}: {e}");
        }
        let missing =
            parse_calibration(r#"{"points": [{"pixel": [1, 2], "lon": 2}]}"#).unwrap_err();
        assert!(
            missing.to_string().contains("missing field `lat`"),
            "{missing}"
        );
        let io = load_calibration(std::path::Path::new("/nonexistent/cal.json")).unwrap_err();
        assert!(matches!(io, CalibrationError::Io(_)));
    }
}
