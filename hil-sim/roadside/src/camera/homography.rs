//! The one-homography form: a plane-to-plane projective map estimated by the normalised DLT.

use nalgebra::{DMatrix, Matrix3, Vector3};

use super::fit::{
    affine_apply, check_pairs, check_spread, local_pairs, normaliser, rmse, RANK_TOL, SVD_MAX_ITER,
};
use super::{Correspondence, ModelError, PointSet};
use crate::road::{dist, Road};

/// |det| of the unit-norm normalised homography below which it is singular.
const SINGULAR_TOL: f64 = 1e-9;
/// Fraction of the smallest calibration `w` below which a pixel counts as at the horizon
/// (over a thousand times farther than the farthest control point).
const HORIZON_FRACTION: f64 = 1e-3;

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

/// `w` (third homogeneous coordinate) of a point under `m`.
fn w_of(m: &Matrix3<f64>, p: [f64; 2]) -> f64 {
    m[(2, 0)] * p[0] + m[(2, 1)] * p[1] + m[(2, 2)]
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

#[cfg(test)]
mod tests {
    use super::super::test_support::{close, map, pairs_of, truth, PROBES};
    use super::*;

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
}
