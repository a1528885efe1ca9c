//! Vanishing points by RANSAC directly on edgelets.
//!
//! A candidate point is where the lines of two random edgelets meet (homogeneous, so it may
//! lie at infinity); its support is the summed strength of the edgelets that point at it
//! within an angle. The best candidate is refined by weighted least squares over its inliers
//! (the point closest to all their lines, in normalised coordinates).
//!
//! The first point ([`dominant`]) is the one with the most support: on a road, the traffic
//! direction (lane markings, curbs, kerbside facades). The other two are searched together
//! ([`orthogonal_pair`]): a candidate second point and the first fix the focal length
//! (principal point at the image centre, square pixels), and the third point follows as the
//! direction orthogonal to both; the pair is scored by the support of both.

use nalgebra::{Matrix3, SymmetricEigen};

use super::edgelets::Edgelet;
use super::homog::{cross, dot, point, towards, unit, H3};
use crate::rng::Prng;

/// How the search runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RansacSettings {
    /// Candidates tried per search.
    pub iterations: u32,
    /// An edgelet supports a point if its direction is within this angle of the point's.
    pub inlier_angle_deg: f64,
    /// Edgelets nearer than this to a candidate (pixels) do not vote for it (no direction).
    pub min_distance_px: f64,
    /// Seed of the candidate sampling (the result is reproducible).
    pub seed: u64,
    /// Focal lengths accepted, as multiples of the image's larger side.
    pub focal_range: (f64, f64),
}

impl Default for RansacSettings {
    /// 4000 candidates, 1.5°, 20 px, seed 1, focal 0.3-5 times the image's larger side.
    fn default() -> Self {
        Self {
            iterations: 4000,
            inlier_angle_deg: 1.5,
            min_distance_px: 20.0,
            seed: 1,
            focal_range: (0.3, 5.0),
        }
    }
}

/// The camera's intrinsics as this search assumes them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Principal {
    /// Principal point, pixels (the image centre).
    pub point: [f64; 2],
    /// Scale of the normalised coordinates, pixels (half the larger side).
    pub scale: f64,
}

impl Principal {
    /// The centre of an image of `size` pixels.
    pub fn centre(size: [u32; 2]) -> Self {
        let [w, h] = size.map(f64::from);
        Self {
            point: [w / 2.0, h / 2.0],
            scale: w.max(h) / 2.0,
        }
    }

    /// A homogeneous pixel point in coordinates relative to the principal point.
    pub fn relative(&self, v: H3) -> H3 {
        [
            v[0] - self.point[0] * v[2],
            v[1] - self.point[1] * v[2],
            v[2],
        ]
    }

    /// Back from [`Principal::relative`].
    pub fn absolute(&self, r: H3) -> H3 {
        [
            r[0] + self.point[0] * r[2],
            r[1] + self.point[1] * r[2],
            r[2],
        ]
    }
}

/// The support of a vanishing point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Support {
    /// Summed strength of its inliers.
    pub score: f64,
    /// Number of inliers.
    pub inliers: usize,
}

/// Does `e` point at `v` (unit homogeneous)?
fn supports(e: &Edgelet, v: H3, sin_tol: f64, min_distance: f64) -> bool {
    let t = towards(e.point, v);
    let len = t[0].hypot(t[1]);
    if len <= min_distance * v[2].abs() {
        return false;
    }
    (e.direction[0] * t[1] - e.direction[1] * t[0]).abs() <= sin_tol * len
}

/// The support of `v` among `edges`.
pub fn support(edges: &[Edgelet], v: H3, s: &RansacSettings) -> Support {
    let sin_tol = s.inlier_angle_deg.to_radians().sin();
    let mut out = Support {
        score: 0.0,
        inliers: 0,
    };
    for e in edges
        .iter()
        .filter(|e| supports(e, v, sin_tol, s.min_distance_px))
    {
        out.score += e.strength;
        out.inliers += 1;
    }
    out
}

/// The edgelets that do not support `v` within `factor` times the inlier angle.
pub fn outliers(edges: &[Edgelet], v: H3, s: &RansacSettings, factor: f64) -> Vec<Edgelet> {
    let sin_tol = (factor * s.inlier_angle_deg).to_radians().sin();
    let keep = |e: &&Edgelet| !supports(e, v, sin_tol, s.min_distance_px);
    edges.iter().filter(keep).copied().collect()
}

/// The homogeneous line of an edgelet.
fn line_of(e: &Edgelet) -> H3 {
    let q = [e.point[0] + e.direction[0], e.point[1] + e.direction[1]];
    cross(point(e.point), point(q))
}

/// The point where the lines of two random edgelets meet (unit norm).
fn candidate(edges: &[Edgelet], rng: &mut Prng) -> Option<H3> {
    let n = edges.len() as u64;
    let a = rng.below(n) as usize;
    let b = rng.below(n) as usize;
    if a == b {
        return None;
    }
    unit(cross(line_of(&edges[a]), line_of(&edges[b])))
}

/// The most supported vanishing point of `edges`, refined; `None` with fewer than two.
pub fn dominant(edges: &[Edgelet], pp: &Principal, s: &RansacSettings) -> Option<(H3, Support)> {
    if edges.len() < 2 {
        return None;
    }
    let mut rng = Prng::new(s.seed);
    let mut best: Option<(H3, Support)> = None;
    for _ in 0..s.iterations {
        let Some(v) = candidate(edges, &mut rng) else {
            continue;
        };
        let sup = support(edges, v, s);
        if best.is_none_or(|(_, b)| sup.score > b.score) {
            best = Some((v, sup));
        }
    }
    let (v, _) = best?;
    let v = refine(edges, v, pp, s);
    Some((v, support(edges, v, s)))
}

/// Least-squares refinement: twice, the point nearest (in normalised coordinates) to the
/// lines of the current inliers, weighted by strength.
pub fn refine(edges: &[Edgelet], mut v: H3, pp: &Principal, s: &RansacSettings) -> H3 {
    let sin_tol = s.inlier_angle_deg.to_radians().sin();
    for _ in 0..2 {
        let mut m = Matrix3::<f64>::zeros();
        let mut used = 0;
        for e in edges
            .iter()
            .filter(|e| supports(e, v, sin_tol, s.min_distance_px))
        {
            let p = [
                (e.point[0] - pp.point[0]) / pp.scale,
                (e.point[1] - pp.point[1]) / pp.scale,
            ];
            let (dx, dy) = (e.direction[0], e.direction[1]);
            // Unit-normal line through p along the edgelet.
            let l = nalgebra::Vector3::new(-dy, dx, p[0] * dy - p[1] * dx);
            m += e.strength * l * l.transpose();
            used += 1;
        }
        if used < 3 {
            break;
        }
        let eig = SymmetricEigen::new(m);
        let k = eig.eigenvalues.imin();
        let r = eig.eigenvectors.column(k);
        let fine = pp.absolute([pp.scale * r[0], pp.scale * r[1], r[2]]);
        match unit(fine) {
            Some(u) => v = u,
            None => break,
        }
    }
    v
}

/// The focal length (pixels) that makes the directions of `a` and `b` orthogonal, `None`
/// if no positive one does (or one point is at infinity).
pub fn focal_of_pair(a: H3, b: H3, pp: &Principal) -> Option<f64> {
    let (ra, rb) = (pp.relative(a), pp.relative(b));
    let zz = ra[2] * rb[2];
    let f2 = -(ra[0] * rb[0] + ra[1] * rb[1]) / zz;
    (f2.is_finite() && f2 > 0.0).then(|| f2.sqrt())
}

/// The camera ray (unit, camera axes x right, y down, z forward) of a vanishing point.
pub fn ray(v: H3, focal: f64, pp: &Principal) -> Option<H3> {
    let r = pp.relative(v);
    unit([r[0] / focal, r[1] / focal, r[2]])
}

/// The vanishing point of a camera ray.
pub fn point_of_ray(r: H3, focal: f64, pp: &Principal) -> Option<H3> {
    unit(pp.absolute([focal * r[0], focal * r[1], r[2]]))
}

/// The third vanishing point orthogonal to `a` and `b` at `focal`.
pub fn third(a: H3, b: H3, focal: f64, pp: &Principal) -> Option<H3> {
    let n = cross(ray(a, focal, pp)?, ray(b, focal, pp)?);
    point_of_ray(unit(n)?, focal, pp)
}

/// The second and third vanishing points orthogonal to `first`, searched together among
/// `edges` (which should no longer hold the first point's inliers); each refined on its own
/// inliers.
pub fn orthogonal_pair(
    edges: &[Edgelet],
    first: H3,
    pp: &Principal,
    s: &RansacSettings,
) -> Option<[(H3, Support); 2]> {
    if edges.len() < 2 {
        return None;
    }
    let (lo, hi) = (
        s.focal_range.0 * pp.scale * 2.0,
        s.focal_range.1 * pp.scale * 2.0,
    );
    let mut rng = Prng::new(s.seed ^ 0x5eed);
    let mut best: Option<(H3, H3, f64)> = None;
    for _ in 0..s.iterations {
        let Some(v2) = candidate(edges, &mut rng) else {
            continue;
        };
        let Some(f) = focal_of_pair(first, v2, pp).filter(|f| (lo..=hi).contains(f)) else {
            continue;
        };
        let Some(v3) = third(first, v2, f, pp) else {
            continue;
        };
        let score = support(edges, v2, s).score + support(edges, v3, s).score;
        if best.is_none_or(|b| score > b.2) {
            best = Some((v2, v3, score));
        }
    }
    let (v2, v3, _) = best?;
    let (v2, v3) = (refine(edges, v2, pp, s), refine(edges, v3, pp, s));
    Some([(v2, support(edges, v2, s)), (v3, support(edges, v3, s))])
}

/// Angle between two vanishing points seen from a camera of focal length `focal`, degrees
/// (0-90: a direction and its opposite are one vanishing point).
pub fn angle_between(a: H3, b: H3, focal: f64, pp: &Principal) -> Option<f64> {
    let c = dot(ray(a, focal, pp)?, ray(b, focal, pp)?).abs().min(1.0);
    Some(c.acos().to_degrees())
}
