//! Shared steps of the estimators: checks of the point pairs, Hartley normalisation, the
//! least-squares affine fit and the RMSE.

use nalgebra::{DMatrix, Matrix3, Vector3};

use super::{Correspondence, ModelError, PointSet};
use crate::road::{dist, Road};

/// Relative thickness (sqrt of the scatter eigenvalue ratio) below which points are collinear.
pub(super) const COLLINEAR_TOL: f64 = 1e-3;
/// Second-smallest over largest singular value of the DLT system below which its solution is
/// not unique.
pub(super) const RANK_TOL: f64 = 1e-9;
/// Iteration cap of the SVD.
pub(super) const SVD_MAX_ITER: usize = 10_000;

/// Pixel -> local metre pairs.
pub(super) fn local_pairs(road: &Road, points: &[Correspondence]) -> Vec<([f64; 2], [f64; 2])> {
    points
        .iter()
        .map(|c| (c.pixel, road.to_local(c.ground)))
        .collect()
}

/// Enough pairs, all finite.
pub(super) fn check_pairs(pairs: &[([f64; 2], [f64; 2])], need: usize) -> Result<(), ModelError> {
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
pub(super) fn check_spread(set: PointSet, pts: &[[f64; 2]]) -> Result<(), ModelError> {
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

pub(super) fn centroid(pts: &[[f64; 2]]) -> [f64; 2] {
    let n = pts.len().max(1) as f64;
    let s = pts.iter().fold([0.0; 2], |s, p| [s[0] + p[0], s[1] + p[1]]);
    [s[0] / n, s[1] / n]
}

/// sqrt(smallest / largest eigenvalue) of the scatter matrix: 0 on a line, 1 for a round cloud.
pub(super) fn thickness(pts: &[[f64; 2]]) -> f64 {
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
pub(super) fn normaliser(pts: &[[f64; 2]]) -> Option<Matrix3<f64>> {
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

/// A matrix whose last row is `[0, 0, 1]` applied to a point.
pub(super) fn affine_apply(m: &Matrix3<f64>, p: [f64; 2]) -> [f64; 2] {
    let v = m * Vector3::new(p[0], p[1], 1.0);
    [v.x, v.y]
}

/// Least-squares affine map `from -> to` (normalised source points), rows `[a, b, c]`.
pub(super) fn fit_affine(pairs: &[([f64; 2], [f64; 2])]) -> Result<[[f64; 3]; 2], ModelError> {
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
pub(super) fn rmse(errors: impl Iterator<Item = Option<f64>>) -> Option<f64> {
    let (mut sum, mut n) = (0.0, 0usize);
    for e in errors {
        let e = e?;
        sum += e * e;
        n += 1;
    }
    Some((sum / n.max(1) as f64).sqrt())
}
