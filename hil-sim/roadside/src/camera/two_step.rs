//! The two-step form of the paper: perspective to a top-down image, then affine to metres.

use super::fit::{check_pairs, fit_affine, local_pairs, rmse};
use super::{Correspondence, Homography, ModelError};
use crate::road::{dist, Road};

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

#[cfg(test)]
mod tests {
    use super::super::test_support::{close, map, points, road, truth, PROBES};
    use super::super::CameraModel;
    use super::*;

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
}
