//! The camera from the scene: three orthogonal vanishing points from one frame's edgelets,
//! the focal length from them, and the full projection (road plane and height) from them
//! with the reference-point homography; the two are cross-checked.

use std::fmt;

use image::GrayImage;

use super::edgelets::{edgelets, EdgeletSettings};
use super::homog::{self, apply, cross, dot, inverse, pixel, point, unit, H3};
use super::vanishing::{
    angle_between, dominant, focal_of_pair, orthogonal_pair, outliers, ray, support, third,
    Principal, RansacSettings, Support,
};

/// Fewest edgelets a calibration needs.
pub const MIN_EDGELETS: usize = 30;
/// Inliers of the first point are taken out within this many times the inlier angle.
const FIRST_POINT_EXCLUSION: f64 = 2.0;

/// The three vanishing points of the road scene (homogeneous pixels, unit norm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VanishingPoints {
    /// Where lines along the road meet (the traffic direction).
    pub road: H3,
    /// Where horizontal lines across the road meet.
    pub across: H3,
    /// Where vertical lines meet.
    pub vertical: H3,
}

/// A camera calibrated from its vanishing points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SceneCalibration {
    /// The points.
    pub points: VanishingPoints,
    /// Support of each (road, across, vertical).
    pub support: [Support; 3],
    /// Focal length, pixels (least squares over the three orthogonality conditions).
    pub focal_px: f64,
    /// Principal point (the image centre) and normalising scale.
    pub principal: Principal,
    /// Edgelets found in the frame.
    pub edgelets: usize,
}

/// Why a frame does not calibrate the camera.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum CalibrationFault {
    /// Too few straight edges in the frame.
    TooFewEdgelets {
        /// Found.
        found: usize,
    },
    /// No vanishing point has support.
    NoDominantPoint,
    /// No pair orthogonal to the first point with a plausible focal length.
    NoOrthogonalPair,
    /// The three points give no positive focal length.
    NoFocalLength,
}

impl fmt::Display for CalibrationFault {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::TooFewEdgelets { found } => {
                write!(f, "{found} edgelets, at least {MIN_EDGELETS} needed")
            }
            Self::NoDominantPoint => f.write_str("no vanishing point has support"),
            Self::NoOrthogonalPair => f.write_str("no orthogonal vanishing points"),
            Self::NoFocalLength => f.write_str("the vanishing points give no focal length"),
        }
    }
}

impl std::error::Error for CalibrationFault {}

/// Calibrates from one frame: edgelets, the dominant point, the orthogonal pair, labels
/// (the vertical point is the one whose camera ray is most vertical in the image; of the
/// other two the road is the better supported) and the focal length.
pub fn calibrate(
    frame: &GrayImage,
    edge: &EdgeletSettings,
    ransac: &RansacSettings,
) -> Result<SceneCalibration, CalibrationFault> {
    let edges = edgelets(frame, edge);
    if edges.len() < MIN_EDGELETS {
        return Err(CalibrationFault::TooFewEdgelets { found: edges.len() });
    }
    let pp = Principal::centre([frame.width(), frame.height()]);
    let (v1, s1) = dominant(&edges, &pp, ransac).ok_or(CalibrationFault::NoDominantPoint)?;
    let rest = outliers(&edges, v1, ransac, FIRST_POINT_EXCLUSION);
    let [(v2, s2), (v3, s3)] =
        orthogonal_pair(&rest, v1, &pp, ransac).ok_or(CalibrationFault::NoOrthogonalPair)?;
    let mut found = [(v1, s1), (v2, s2), (v3, s3)];
    let focal = focal_of_triple([v1, v2, v3], &pp).ok_or(CalibrationFault::NoFocalLength)?;
    let verticality = |v: H3| ray(v, focal, &pp).map_or(0.0, |r| r[1].abs());
    found.sort_by(|a, b| verticality(a.0).total_cmp(&verticality(b.0)));
    let [mut h1, mut h2, vertical] = found;
    if h2.1.score > h1.1.score {
        std::mem::swap(&mut h1, &mut h2);
    }
    // The across point has the fewest edges (stop lines, crossings, side walls): the best
    // supported pair, road and vertical, fixes the focal length, and the across point is
    // the direction orthogonal to both.
    let focal = focal_of_pair(h1.0, vertical.0, &pp).unwrap_or(focal);
    let across = third(h1.0, vertical.0, focal, &pp).unwrap_or(h2.0);
    Ok(SceneCalibration {
        points: VanishingPoints {
            road: h1.0,
            across,
            vertical: vertical.0,
        },
        support: [h1.1, support(&edges, across, ransac), vertical.1],
        focal_px: focal,
        principal: pp,
        edgelets: edges.len(),
    })
}

/// The focal length that best makes the three points pairwise orthogonal (least squares in
/// `f²`); `None` if it is not positive.
pub fn focal_of_triple(v: [H3; 3], pp: &Principal) -> Option<f64> {
    let r = v.map(|p| unit(pp.relative(p)).unwrap_or([0.0; 3]));
    let (mut num, mut den) = (0.0, 0.0);
    for (i, j) in [(0, 1), (0, 2), (1, 2)] {
        let a = r[i][0] * r[j][0] + r[i][1] * r[j][1];
        let b = r[i][2] * r[j][2];
        num -= a * b;
        den += b * b;
    }
    let f2 = num / den;
    (f2.is_finite() && f2 > 0.0).then(|| f2.sqrt())
}

/// The camera over the road plane: the homography to local metres, its inverse and the full
/// 3x4 projection of (east, north, up) metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroundCamera {
    to_ground: [[f64; 3]; 3],
    to_image: [[f64; 3]; 3],
    projection: [[f64; 4]; 3],
    focal_px: f64,
    principal: Principal,
    /// Sign of `w` of `to_ground` for pixels that see the road.
    ground_sign: f64,
}

/// Why a [`GroundCamera`] cannot be made.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum GroundCameraFault {
    /// The homography is singular or not finite.
    Singular,
    /// The homography maps the image mirrored (its up direction points down in the image).
    Mirrored,
}

impl fmt::Display for GroundCameraFault {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Singular => "the homography is singular",
            Self::Mirrored => "the homography is mirrored",
        })
    }
}

impl std::error::Error for GroundCameraFault {}

impl GroundCamera {
    /// From the image-to-road homography (`to_ground`, row-major) and the intrinsics: with
    /// `K` known, the homography's first two columns are the rotated east and north axes and
    /// the third is the translation, so the up axis is their cross product.
    pub fn new(
        to_ground: [[f64; 3]; 3],
        focal_px: f64,
        principal: Principal,
    ) -> Result<Self, GroundCameraFault> {
        let mut g = inverse(&to_ground).ok_or(GroundCameraFault::Singular)?;
        // The bottom centre of the image sees the road, in front of the camera.
        let seen = apply(
            &to_ground,
            point([principal.point[0], 2.0 * principal.point[1]]),
        );
        let ground_sign = if seen[2] < 0.0 { -1.0 } else { 1.0 };
        // `g` maps that road point (w = 1) to the pixel at w = 1 / seen[2]: it must come out
        // in front of the camera (w > 0).
        if seen[2] < 0.0 {
            g = g.map(|row| row.map(|v| -v));
        }
        let col = |c: usize| [g[0][c], g[1][c], g[2][c]];
        let k_inv = |v: H3| {
            let r = principal.relative(v);
            [r[0] / focal_px, r[1] / focal_px, r[2]]
        };
        let (m1, m2, m3) = (k_inv(col(0)), k_inv(col(1)), k_inv(col(2)));
        let lambda = (dot(m1, m1).sqrt() * dot(m2, m2).sqrt()).sqrt();
        if !(lambda.is_finite() && lambda > 0.0) {
            return Err(GroundCameraFault::Singular);
        }
        let up = unit(cross(m1, m2)).ok_or(GroundCameraFault::Singular)?;
        if up[1] > 0.0 {
            return Err(GroundCameraFault::Mirrored);
        }
        let k = |v: H3| principal.absolute([focal_px * v[0], focal_px * v[1], v[2]]);
        let cols = [k(m1), k(m2), k(up.map(|u| u * lambda)), k(m3)];
        let projection = [0, 1, 2].map(|r| [0, 1, 2, 3].map(|c| cols[c][r]));
        Ok(Self {
            to_ground,
            to_image: g,
            projection,
            focal_px,
            principal,
            ground_sign,
        })
    }

    /// The pixel of a point (east, north, up metres); `None` behind the camera.
    pub fn project(&self, p: [f64; 3]) -> Option<[f64; 2]> {
        let x = [p[0], p[1], p[2], 1.0];
        let v = self
            .projection
            .map(|row| (0..4).map(|i| row[i] * x[i]).sum::<f64>());
        if v[2] <= 0.0 {
            return None;
        }
        pixel(v)
    }

    /// The road point of a pixel; `None` at or above the horizon.
    pub fn to_ground(&self, px: [f64; 2]) -> Option<[f64; 2]> {
        let g = apply(&self.to_ground, point(px));
        // Below the horizon: `w` of the sign of the road at the bottom of the image.
        if g[2] * self.ground_sign <= 0.0 {
            return None;
        }
        pixel(g)
    }

    /// The point at height `z_m` (metres above the road) seen at pixel `px`, as (east,
    /// north); `None` when the pixel's ray does not meet that plane in front of the camera.
    pub fn to_plane(&self, px: [f64; 2], z_m: f64) -> Option<[f64; 2]> {
        let p = &self.projection;
        let m = [0, 1, 2].map(|r| [p[r][0], p[r][1], z_m * p[r][2] + p[r][3]]);
        let g = apply(&inverse(&m)?, point(px));
        // In front of the camera: the plane point maps back with w > 0.
        let q = pixel(g)?;
        let w: f64 = (0..3).map(|k| m[2][k] * [q[0], q[1], 1.0][k]).sum();
        (w > 0.0).then_some(q)
    }

    /// The road line of an image line.
    pub fn line_to_ground(&self, line: H3) -> H3 {
        apply(&homog::transpose(&self.to_image), line)
    }

    /// The image line of a road line.
    pub fn line_to_image(&self, line: H3) -> H3 {
        apply(&homog::transpose(&self.to_ground), line)
    }

    /// The road point under the camera (where vertical lines meet on the road).
    pub fn foot(&self) -> Option<[f64; 2]> {
        pixel(apply(&self.to_ground, self.vertical_point()))
    }

    /// The vertical vanishing point this camera implies.
    pub fn vertical_point(&self) -> H3 {
        [0, 1, 2].map(|r| self.projection[r][2])
    }

    /// The vanishing point of a road direction (east, north).
    pub fn point_of_direction(&self, d: [f64; 2]) -> H3 {
        apply(&self.to_image, [d[0], d[1], 0.0])
    }

    /// The height above the road of the point seen at pixel `top` straight above road point
    /// `base` (least squares along the vertical through `base`).
    pub fn height_at(&self, base: [f64; 2], top: [f64; 2]) -> Option<f64> {
        let p0 = [0, 1, 2].map(|r| {
            let row = self.projection[r];
            row[0] * base[0] + row[1] * base[1] + row[3]
        });
        let t = point(top);
        let (c0, c3) = (cross(p0, t), cross(self.vertical_point(), t));
        let z = -dot(c0, c3) / dot(c3, c3);
        z.is_finite().then_some(z)
    }

    /// Focal length used, pixels.
    pub fn focal_px(&self) -> f64 {
        self.focal_px
    }

    /// Principal point used.
    pub fn principal(&self) -> Principal {
        self.principal
    }
}

/// The vanishing-point calibration against the reference-point homography.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CrossCheck {
    /// Angle between the road point and the homography's image of the road direction, degrees.
    pub road_deg: f64,
    /// The same for the across point.
    pub across_deg: f64,
    /// Angle between the vertical point and the one the homography implies at the found focal
    /// length, degrees.
    pub vertical_deg: f64,
    /// The focal length the homography alone implies (orthogonal axes of equal scale), pixels.
    pub homography_focal_px: Option<f64>,
}

/// Cross-checks a calibration with the homography (`to_ground`) and the road's bearing
/// (degrees clockwise from north) where the camera looks.
pub fn cross_check(
    cal: &SceneCalibration,
    to_ground: [[f64; 3]; 3],
    road_bearing_deg: f64,
) -> Result<CrossCheck, GroundCameraFault> {
    let cam = GroundCamera::new(to_ground, cal.focal_px, cal.principal)?;
    let (s, c) = road_bearing_deg.to_radians().sin_cos();
    let (f, pp) = (cal.focal_px, &cal.principal);
    let angle = |a, b| angle_between(a, b, f, pp).unwrap_or(f64::NAN);
    Ok(CrossCheck {
        road_deg: angle(cal.points.road, cam.point_of_direction([s, c])),
        across_deg: angle(cal.points.across, cam.point_of_direction([c, -s])),
        vertical_deg: angle(cal.points.vertical, cam.vertical_point()),
        homography_focal_px: homography_focal(&cam.to_image, pp),
    })
}

/// The focal length that makes the homography's east and north columns orthogonal and of
/// equal length (least squares in `f²`).
fn homography_focal(g: &[[f64; 3]; 3], pp: &Principal) -> Option<f64> {
    let col = |c: usize| pp.relative([g[0][c], g[1][c], g[2][c]]);
    let (a, b) = (col(0), col(1));
    let (ortho_xy, ortho_z) = (a[0] * b[0] + a[1] * b[1], a[2] * b[2]);
    let norm_xy = a[0] * a[0] + a[1] * a[1] - b[0] * b[0] - b[1] * b[1];
    let norm_z = a[2] * a[2] - b[2] * b[2];
    let f2 = -(ortho_xy * ortho_z + norm_xy * norm_z) / (ortho_z * ortho_z + norm_z * norm_z);
    (f2.is_finite() && f2 > 0.0).then(|| f2.sqrt())
}
