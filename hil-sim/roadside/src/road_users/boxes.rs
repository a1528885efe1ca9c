//! The 3D box of a road user from its silhouette and the three vanishing points, and its
//! place on the road.
//!
//! Every box edge points at one of the vanishing points, so the silhouette (the mask's
//! convex hull) lies between two tangent lines from each point. Seen from a pole above and to
//! one side, the lower tangent from the road point runs along the near long bottom edge, the
//! lower tangent from the across point along the near short bottom edge, and the two
//! tangents from the vertical point along the outermost vertical edges.
//!
//! - **B1-B4, the bottom face:** B1, the near bottom corner, is where the two lower tangents
//!   meet; each vertical tangent meets one lower tangent beyond B1, at B2 (along the road)
//!   and B4 (across it); B3 closes the parallelogram. The construction is made on the road
//!   plane (lines carried by the homography), where "lower" is "nearer the camera's foot"
//!   and "beyond" is "farther from it", so that no image-side case analysis is needed.
//! - **B5-B8, the top face:** the vertical through B2 meets the upper tangent from the across
//!   point (the far short top edge), the vertical through B4 the upper tangent from the road
//!   point; their heights (from the full projection) are averaged, and the top face is the
//!   bottom face raised by it.
//!
//! The footprint's centre is the road user's position. A construction is refused with a
//! [`BoxRejection`] when a vanishing point falls inside the silhouette, when the view is
//! side-on (both vertical tangents meet the same lower tangent), when the box is implausible
//! for its class, or when the box projected back does not cover its own mask.

use std::fmt;

use super::calibrate::{GroundCamera, VanishingPoints};
use super::class::RoadUserClass;
use super::homog::{cross, normal_line, pixel, point, signed_distance, H3};
use super::polygon::{convex_hull, iou, vertex_distance};

/// Smallest intersection over union of the projected box with the mask's hull.
pub const MIN_IOU: f64 = 0.75;
/// Smallest side of a box, as a share of its class's typical size.
const MIN_SHARE: f64 = 0.3;

/// A road user's 3D box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoadUserBox {
    /// The class of the detection.
    pub class: RoadUserClass,
    /// Bottom corners B1-B4, local metres (east, north): near, along the road, far, across.
    pub footprint: [[f64; 2]; 4],
    /// Height, metres.
    pub height_m: f64,
    /// The footprint's centre, local metres.
    pub centre: [f64; 2],
    /// How far B2 (the length) moves when its vertical tangent moves by one pixel, metres
    /// (0 for a fitted box, whose accuracy comes from the fit).
    pub length_per_px_m: f64,
    /// How far B4 (the width) moves when its vertical tangent moves by one pixel, metres
    /// (0 for a fitted box).
    pub width_per_px_m: f64,
    /// The eight vertices B1-B8 in the image (bottom B1-B4, then the top above each).
    pub vertices_px: [[f64; 2]; 8],
    /// Intersection over union of the projected box with the mask's hull.
    pub iou: f64,
    /// How far the box's outline is from the mask's, pixels: for a constructed box the
    /// largest distance between a vertex of one outline and the other; for a fitted box the
    /// root mean square distance of the mask's outline vertices to the box's.
    pub misfit_px: f64,
}

impl RoadUserBox {
    /// Length along the road, metres.
    pub fn length_m(&self) -> f64 {
        side(self.footprint[0], self.footprint[1])
    }

    /// Width across the road, metres.
    pub fn width_m(&self) -> f64 {
        side(self.footprint[0], self.footprint[3])
    }
}

fn side(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// Which vanishing point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Axis {
    /// Along the road.
    Road,
    /// Across the road.
    Across,
    /// Vertical.
    Vertical,
}

/// Why no box is made for a detection (a closed set, counted by the pipeline).
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum BoxRejection {
    /// The hull has fewer than three points.
    TooFewPoints,
    /// The vanishing point lies inside (or on) the silhouette: no tangents.
    PointInside(Axis),
    /// The camera's foot on the road is not defined (vertical point at infinity).
    NoCameraFoot,
    /// Tangent lines do not meet in front of the camera.
    NoIntersection,
    /// Both vertical tangents meet the same lower tangent: the box is seen side-on and its
    /// depth is not observable.
    SideOn,
    /// The box is out of the class's size range (or a side is degenerate).
    Implausible,
    /// The box projected back covers its mask by less than [`MIN_IOU`].
    Inconsistent {
        /// The overlap found.
        iou: f64,
    },
    /// The mask is cut by the image border.
    Truncated,
    /// The mask touches a nearer road user's mask.
    Occluded,
}

impl fmt::Display for BoxRejection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::TooFewPoints => f.write_str("the mask has fewer than three hull points"),
            Self::PointInside(a) => write!(f, "the {a:?} vanishing point is inside the mask"),
            Self::NoCameraFoot => f.write_str("the vertical vanishing point is at infinity"),
            Self::NoIntersection => f.write_str("the tangents do not meet on the road"),
            Self::SideOn => f.write_str("seen side-on: the depth is not observable"),
            Self::Implausible => f.write_str("the box is implausible for its class"),
            Self::Inconsistent { iou } => write!(f, "the box covers its mask at IoU {iou:.2}"),
            Self::Truncated => f.write_str("the mask is cut by the image border"),
            Self::Occluded => f.write_str("the mask touches a nearer road user"),
        }
    }
}

/// The hull vertices where the two tangents from `v` touch the hull, ordered by angle.
fn contacts(v: H3, hull: &[[f64; 2]], axis: Axis) -> Result<[usize; 2], BoxRejection> {
    let mid = centroid(hull);
    // Reference direction from the point towards the hull (or along it, at infinity).
    let (origin, dir) = match pixel(v) {
        Some(c) => (Some(c), [mid[0] - c[0], mid[1] - c[1]]),
        None => (None, [v[0], v[1]]),
    };
    let key = |p: [f64; 2]| match origin {
        // Angle of p seen from the point, relative to the direction of the hull's centre.
        Some(c) => {
            let d = [p[0] - c[0], p[1] - c[1]];
            (dir[0] * d[1] - dir[1] * d[0]).atan2(dir[0] * d[0] + dir[1] * d[1])
        }
        // Offset across the direction, for a point at infinity.
        None => (dir[0] * p[1] - dir[1] * p[0]) / dir[0].hypot(dir[1]),
    };
    let (mut lo, mut hi) = ((f64::INFINITY, 0), (f64::NEG_INFINITY, 0));
    for (i, &p) in hull.iter().enumerate() {
        let k = key(p);
        if k < lo.0 {
            lo = (k, i);
        }
        if k > hi.0 {
            hi = (k, i);
        }
    }
    let inside = origin.is_some() && hi.0 - lo.0 >= std::f64::consts::PI - 1e-9;
    if inside || !(lo.0.is_finite() && hi.0.is_finite()) || lo.0 == hi.0 {
        return Err(BoxRejection::PointInside(axis));
    }
    Ok([lo.1, hi.1])
}

/// The mean of a hull's vertices (inside it).
fn centroid(hull: &[[f64; 2]]) -> [f64; 2] {
    let n = hull.len().max(1) as f64;
    hull.iter()
        .fold([0.0, 0.0], |m, p| [m[0] + p[0] / n, m[1] + p[1] / n])
}

/// The six box edges of a silhouette, two from each vanishing point of `vps` (road, across,
/// vertical), each pair ordered by angle.
///
/// The silhouette of a box is a hexagon whose six edges each point at a vanishing point, so
/// each tangent runs along one edge between two corners. The extreme hull vertex alone is
/// the outermost of the two noisy corners (biased outwards, and by a whole corner's error
/// when one corner strays): each line goes through the mean of both ends instead
/// ([`edge_line`]).
fn edge_lines(hull: &[[f64; 2]], vps: [H3; 3]) -> Result<[[H3; 2]; 3], BoxRejection> {
    let axes = [Axis::Road, Axis::Across, Axis::Vertical];
    let mut touch = [[0; 2]; 3];
    for k in 0..3 {
        touch[k] = contacts(vps[k], hull, axes[k])?;
    }
    let support: [H3; 6] =
        std::array::from_fn(|j| cross(vps[j / 2], point(hull[touch[j / 2][j % 2]])));
    let inner = centroid(hull);
    Ok(std::array::from_fn(|k| {
        [0, 1].map(|s| edge_line(vps[k], hull, touch[k][s], &support, 2 * k + s, inner))
    }))
}

/// The edge along support line `k` of `lines` (from `v`, touching hull vertex `at`): the
/// line from `v` through the midpoint of the edge's two ends. The ends are the hull vertices
/// nearest to where the line leaves the region the other support lines bound (the hexagon
/// of tangents, whose corners are the box's corners as the mask shows them).
fn edge_line(
    v: H3,
    hull: &[[f64; 2]],
    at: usize,
    lines: &[H3; 6],
    k: usize,
    inner: [f64; 2],
) -> H3 {
    let e = hull[at];
    let Some(l) = normal_line(lines[k]) else {
        return lines[k];
    };
    let d = [l[1], -l[0]];
    let (mut t_lo, mut t_hi) = (f64::NEG_INFINITY, f64::INFINITY);
    for (j, o) in lines.iter().enumerate() {
        let Some(o) = normal_line(*o).filter(|_| j != k) else {
            continue;
        };
        // The hull's side of the other line; along this one, f(t) = g0 + t g1 stays >= 0.
        let side = (o[0] * inner[0] + o[1] * inner[1] + o[2]).signum();
        let g0 = side * (o[0] * e[0] + o[1] * e[1] + o[2]);
        let g1 = side * (o[0] * d[0] + o[1] * d[1]);
        if g1.abs() < 1e-9 {
            continue;
        }
        let t = -g0 / g1;
        if g1 > 0.0 {
            t_lo = t_lo.max(t);
        } else {
            t_hi = t_hi.min(t);
        }
    }
    let end = |t: f64| {
        if !t.is_finite() {
            return e;
        }
        let x = [e[0] + t * d[0], e[1] + t * d[1]];
        hull.iter()
            .copied()
            .min_by(|a, b| {
                let da = (a[0] - x[0]).hypot(a[1] - x[1]);
                da.total_cmp(&(b[0] - x[0]).hypot(b[1] - x[1]))
            })
            .unwrap_or(e)
    };
    let (a, b) = (end(t_lo), end(t_hi));
    cross(v, point([(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0]))
}

/// Where two road lines meet.
fn meet(a: H3, b: H3) -> Result<[f64; 2], BoxRejection> {
    pixel(cross(a, b)).ok_or(BoxRejection::NoIntersection)
}

/// Of two road lines from one vanishing point, (lower, upper): the lower is nearer the foot.
fn lower_upper(
    cam: &GroundCamera,
    pair: [H3; 2],
    foot: [f64; 2],
) -> Result<(H3, H3), BoxRejection> {
    let g = pair.map(|l| cam.line_to_ground(l));
    let d = g.map(|l| signed_distance(l, foot).map(f64::abs));
    match d {
        [Some(a), Some(b)] if a <= b => Ok((g[0], pair[1])),
        [Some(_), Some(_)] => Ok((g[1], pair[0])),
        _ => Err(BoxRejection::NoIntersection),
    }
}

/// The box of a detection of `class` whose mask has the convex hull `hull` (image pixels).
pub fn construct(
    class: RoadUserClass,
    hull: &[[f64; 2]],
    vps: &VanishingPoints,
    cam: &GroundCamera,
) -> Result<RoadUserBox, BoxRejection> {
    if hull.len() < 3 {
        return Err(BoxRejection::TooFewPoints);
    }
    let [road, across, vertical] = edge_lines(hull, [vps.road, vps.across, vps.vertical])?;
    let foot = pixel(cross(
        cam.line_to_ground(vertical[0]),
        cam.line_to_ground(vertical[1]),
    ))
    .ok_or(BoxRejection::NoCameraFoot)?;
    let (low_road, up_road) = lower_upper(cam, road, foot)?;
    let (low_across, up_across) = lower_upper(cam, across, foot)?;
    let b1 = meet(low_road, low_across)?;
    let away = [b1[0] - foot[0], b1[1] - foot[1]];
    let beyond = |q: [f64; 2]| (q[0] - b1[0]) * away[0] + (q[1] - b1[1]) * away[1] > 0.0;
    let mut along = None;
    let mut side = None;
    for line in vertical {
        let ray = cam.line_to_ground(line);
        let on_road = meet(ray, low_road).ok().filter(|q| beyond(*q));
        let on_across = meet(ray, low_across).ok().filter(|q| beyond(*q));
        match (on_road, on_across) {
            (Some(q), None) if along.is_none() => along = Some((q, line, low_road)),
            (None, Some(q)) if side.is_none() => side = Some((q, line, low_across)),
            _ => return Err(BoxRejection::SideOn),
        }
    }
    let (along, side) = (
        along.ok_or(BoxRejection::SideOn)?,
        side.ok_or(BoxRejection::SideOn)?,
    );
    let (b2, b4) = (along.0, side.0);
    let length_per_px_m = moved_by_a_pixel(cam, along);
    let width_per_px_m = moved_by_a_pixel(cam, side);
    let b3 = [b2[0] + b4[0] - b1[0], b2[1] + b4[1] - b1[1]];
    let footprint = [b1, b2, b3, b4];
    let height_m = box_height(cam, vps, b2, up_across, b4, up_road)?;
    let mut built = finish(class, footprint, height_m, hull, cam)?;
    built.length_per_px_m = length_per_px_m;
    built.width_per_px_m = width_per_px_m;
    Ok(built)
}

/// How far a far corner moves on its lower line when its vertical tangent (an image line)
/// moves one pixel sideways, metres (infinite if the moved line misses it).
fn moved_by_a_pixel(cam: &GroundCamera, (corner, tangent, lower): ([f64; 2], H3, H3)) -> f64 {
    let moved = normal_line(tangent).map(|l| [l[0], l[1], l[2] - 1.0]);
    moved
        .and_then(|l| meet(cam.line_to_ground(l), lower).ok())
        .map_or(f64::INFINITY, |q| {
            (q[0] - corner[0]).hypot(q[1] - corner[1])
        })
}

/// The mean of the heights seen above B2 (under the far short top edge) and above B4 (under
/// the far long top edge).
fn box_height(
    cam: &GroundCamera,
    vps: &VanishingPoints,
    b2: [f64; 2],
    up_across: H3,
    b4: [f64; 2],
    up_road: H3,
) -> Result<f64, BoxRejection> {
    let mut sum = 0.0;
    for (base, upper) in [(b2, up_across), (b4, up_road)] {
        let px = cam
            .project([base[0], base[1], 0.0])
            .ok_or(BoxRejection::NoIntersection)?;
        let top = pixel(cross(cross(point(px), vps.vertical), upper))
            .ok_or(BoxRejection::NoIntersection)?;
        sum += cam
            .height_at(base, top)
            .ok_or(BoxRejection::NoIntersection)?;
    }
    Ok(sum / 2.0)
}

/// Checks size and reprojection, and builds the box.
fn finish(
    class: RoadUserClass,
    footprint: [[f64; 2]; 4],
    height_m: f64,
    hull: &[[f64; 2]],
    cam: &GroundCamera,
) -> Result<RoadUserBox, BoxRejection> {
    let (min, max) = (class.typical(), class.largest());
    let (length, width) = (
        side(footprint[0], footprint[1]),
        side(footprint[0], footprint[3]),
    );
    let plausible = |v: f64, lo: f64, hi: f64| v.is_finite() && (lo..=hi).contains(&v);
    if !(plausible(length, MIN_SHARE * min.length_m, max.length_m)
        && plausible(width, MIN_SHARE * min.width_m, max.width_m)
        && plausible(height_m, MIN_SHARE * min.height_m, max.height_m))
    {
        return Err(BoxRejection::Implausible);
    }
    let mut vertices_px = [[0.0; 2]; 8];
    for (i, p) in footprint.iter().enumerate() {
        for (k, z) in [0.0, height_m].into_iter().enumerate() {
            vertices_px[i + 4 * k] = cam
                .project([p[0], p[1], z])
                .ok_or(BoxRejection::NoIntersection)?;
        }
    }
    let outline = convex_hull(&vertices_px);
    let overlap = iou(&outline, hull);
    let misfit_px = vertex_distance(&outline, hull);
    if overlap < MIN_IOU {
        return Err(BoxRejection::Inconsistent { iou: overlap });
    }
    let centre = [
        (footprint[0][0] + footprint[2][0]) / 2.0,
        (footprint[0][1] + footprint[2][1]) / 2.0,
    ];
    Ok(RoadUserBox {
        class,
        footprint,
        height_m,
        centre,
        length_per_px_m: 0.0,
        width_per_px_m: 0.0,
        vertices_px,
        iou: overlap,
        misfit_px,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_edge_line_averages_both_ends_even_when_one_corner_strays() {
        // A box seen in parallel projection: edges along a = (40, 5), b = (-15, 10) and
        // c = (0, -60) from (100, 100); the vanishing points are their directions at infinity.
        let (a, b, c) = ([40.0, 5.0], [-15.0, 10.0], [0.0, -60.0]);
        let at = |i: f64, j: f64, k: f64| {
            [
                100.0 + i * a[0] + j * b[0] + k * c[0],
                100.0 + i * a[1] + j * b[1] + k * c[1],
            ]
        };
        let mut corners = Vec::new();
        for k in [0.0, 1.0] {
            for (i, j) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
                corners.push(at(i, j, k));
            }
        }
        // The bottom corner at a + b, (125, 115), strays 4 px down: more than the 3 px within
        // which the old rule took the edge's other end, (85, 110), into account.
        corners[2][1] += 4.0;
        let hull = convex_hull(&corners);
        let vps = [[a[0], a[1], 0.0], [b[0], b[1], 0.0], [c[0], c[1], 0.0]];
        let lines = edge_lines(&hull, vps).unwrap();
        // The lower edge along a runs from (85, 110) to (125, 119): the line along a through
        // their midpoint (105, 114.5).
        let lower = lines[0]
            .iter()
            .copied()
            .find(|l| signed_distance(*l, [125.0, 119.0]).is_some_and(|d| d.abs() < 3.0))
            .unwrap();
        let d = signed_distance(lower, [105.0, 114.5]).unwrap();
        assert!(d.abs() < 1e-9, "{d}");
        // Both ends lie 1.98 px from it (4 px down on a line of slope 5/40), on either side.
        let n = 4.0 * 40.0 / 40.0f64.hypot(5.0) / 2.0;
        for p in [[125.0, 119.0], [85.0, 110.0]] {
            let d = signed_distance(lower, p).unwrap().abs();
            assert!((d - n).abs() < 1e-9, "{p:?}: {d} for {n}");
        }
        // The edge along c (vertical) untouched by the stray corner goes through both ends.
        let right = lines[2]
            .iter()
            .copied()
            .find(|l| signed_distance(*l, [140.0, 105.0]).is_some_and(|d| d.abs() < 1.0))
            .unwrap();
        assert!(signed_distance(right, [140.0, 45.0]).unwrap().abs() < 1e-9);
    }
}
