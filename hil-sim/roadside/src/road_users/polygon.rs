//! Convex polygons in the image: hulls, areas, intersections and overlap, for checking a
//! constructed box against its mask and for finding masks that touch.

/// The convex hull of `points` (Andrew's monotone chain), counter-clockwise in a y-up frame
/// (clockwise on screen), without collinear or repeated points; non-finite points ignored.
pub fn convex_hull(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut pts: Vec<[f64; 2]> = points
        .iter()
        .copied()
        .filter(|p| p[0].is_finite() && p[1].is_finite())
        .collect();
    pts.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    let mut hull: Vec<[f64; 2]> = Vec::with_capacity(pts.len() + 1);
    for pass in 0..2 {
        let start = hull.len();
        let ordered: Box<dyn Iterator<Item = &[f64; 2]>> = if pass == 0 {
            Box::new(pts.iter())
        } else {
            Box::new(pts.iter().rev())
        };
        for &p in ordered {
            while hull.len() >= start + 2
                && turn(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
            {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

/// Twice the signed area of the triangle `a b c` (positive when counter-clockwise, y up).
fn turn(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Signed area (shoelace; positive counter-clockwise, y up).
pub fn signed_area(poly: &[[f64; 2]]) -> f64 {
    let n = poly.len();
    (0..n)
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum::<f64>()
        / 2.0
}

/// The intersection of two convex polygons of the same orientation (Sutherland-Hodgman:
/// `subject` clipped by each edge of `clip`).
pub fn intersection(subject: &[[f64; 2]], clip: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let sign = signed_area(clip).signum();
    let mut out = subject.to_vec();
    let n = clip.len();
    for i in 0..n {
        let (a, b) = (clip[i], clip[(i + 1) % n]);
        let inside = |p: [f64; 2]| turn(a, b, p) * sign >= 0.0;
        let input = std::mem::take(&mut out);
        let m = input.len();
        for j in 0..m {
            let (p, q) = (input[j], input[(j + 1) % m]);
            let (ip, iq) = (inside(p), inside(q));
            if ip {
                out.push(p);
            }
            if ip != iq {
                let (tp, tq) = (turn(a, b, p), turn(a, b, q));
                let t = tp / (tp - tq);
                out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
            }
        }
        if out.is_empty() {
            break;
        }
    }
    out
}

/// Intersection over union of two convex polygons (0 when either has no area).
pub fn iou(a: &[[f64; 2]], b: &[[f64; 2]]) -> f64 {
    let (aa, ab) = (signed_area(a).abs(), signed_area(b).abs());
    if aa <= 0.0 || ab <= 0.0 {
        return 0.0;
    }
    let b_same: Vec<[f64; 2]> = if signed_area(a).signum() == signed_area(b).signum() {
        b.to_vec()
    } else {
        b.iter().rev().copied().collect()
    };
    let inter = signed_area(&intersection(a, &b_same)).abs();
    let union = aa + ab - inter;
    if union > 0.0 {
        inter / union
    } else {
        0.0
    }
}

/// Do two convex polygons overlap or come within `margin` of each other? (Separating axes:
/// they are apart if some edge normal separates their projections by more than `margin`.)
pub fn near_or_overlapping(a: &[[f64; 2]], b: &[[f64; 2]], margin: f64) -> bool {
    for poly in [a, b] {
        let n = poly.len();
        for i in 0..n {
            let (p, q) = (poly[i], poly[(i + 1) % n]);
            let axis = [q[1] - p[1], p[0] - q[0]];
            let len = axis[0].hypot(axis[1]);
            if len == 0.0 {
                continue;
            }
            let project = |s: &[[f64; 2]]| {
                s.iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                        let d = (v[0] * axis[0] + v[1] * axis[1]) / len;
                        (lo.min(d), hi.max(d))
                    })
            };
            let (a_lo, a_hi) = project(a);
            let (b_lo, b_hi) = project(b);
            if a_lo > b_hi + margin || b_lo > a_hi + margin {
                return false;
            }
        }
    }
    true
}

/// Distance from point `p` to the boundary of polygon `poly`.
pub fn distance_to_boundary(p: [f64; 2], poly: &[[f64; 2]]) -> f64 {
    let n = poly.len();
    (0..n)
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            let ab = [b[0] - a[0], b[1] - a[1]];
            let len2 = ab[0] * ab[0] + ab[1] * ab[1];
            let t = if len2 > 0.0 {
                (((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1]) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (p[0] - a[0] - t * ab[0]).hypot(p[1] - a[1] - t * ab[1])
        })
        .fold(f64::INFINITY, f64::min)
}

/// Signed distance from point `p` to convex polygon `poly` (either orientation): positive
/// outside, negative inside, zero on the boundary; infinite for fewer than three vertices.
pub fn signed_distance_convex(p: [f64; 2], poly: &[[f64; 2]]) -> f64 {
    if poly.len() < 3 {
        return f64::INFINITY;
    }
    let sign = signed_area(poly).signum();
    let n = poly.len();
    let inside = (0..n).all(|i| {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        turn(a, b, p) * sign >= 0.0
    });
    let d = distance_to_boundary(p, poly);
    if inside {
        -d
    } else {
        d
    }
}

/// The larger of the two directed distances between the vertices of each polygon and the
/// boundary of the other (for convex polygons, their Hausdorff distance up to the edges'
/// interiors), pixels.
pub fn vertex_distance(a: &[[f64; 2]], b: &[[f64; 2]]) -> f64 {
    let one_way = |p: &[[f64; 2]], q: &[[f64; 2]]| {
        p.iter()
            .map(|v| distance_to_boundary(*v, q))
            .fold(0.0, f64::max)
    };
    one_way(a, b).max(one_way(b, a))
}

/// Seen from `eye` (a road point under the camera), does footprint `a` stand in front of
/// footprint `b`? Both are parallelograms with the same axes (the edges of `a` from its first
/// corner). A line along an axis that separates them, with the eye on `a`'s side, means that
/// `b` cannot hide `a`. `a` is in front when some axis says so and none says the opposite;
/// when the two axes disagree (side by side as seen from the eye) neither is in front of the
/// other (`Some(false)` both ways, so that an order built from this has no cycle); `None`
/// when no axis separates them (overlapping footprints) or `a` is degenerate.
pub fn in_front(a: &[[f64; 2]; 4], b: &[[f64; 2]; 4], eye: [f64; 2]) -> Option<bool> {
    let mut verdicts = [None; 2];
    for (slot, edge) in verdicts.iter_mut().zip([1, 3]) {
        let d = [a[edge][0] - a[0][0], a[edge][1] - a[0][1]];
        let len = d[0].hypot(d[1]);
        if !(len.is_finite() && len > 0.0) {
            return None;
        }
        let along = |p: [f64; 2]| (p[0] * d[0] + p[1] * d[1]) / len;
        let range = |q: &[[f64; 2]; 4]| {
            q.iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                    (lo.min(along(*p)), hi.max(along(*p)))
                })
        };
        let ((a_lo, a_hi), (b_lo, b_hi), e) = (range(a), range(b), along(eye));
        if a_hi <= b_lo {
            *slot = Some(e < b_lo);
        } else if b_hi <= a_lo {
            *slot = Some(e > b_hi);
        }
    }
    match verdicts {
        [Some(x), Some(y)] => Some(x && y),
        [Some(x), None] | [None, Some(x)] => Some(x),
        [None, None] => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hull_area_and_overlap_of_squares() {
        let pts = [
            [0.0, 0.0],
            [2.0, 0.0],
            [2.0, 2.0],
            [0.0, 2.0],
            [1.0, 1.0],
            [1.0, 0.0],
            [f64::NAN, 5.0],
        ];
        let hull = convex_hull(&pts);
        assert_eq!(hull.len(), 4, "{hull:?}");
        assert!((signed_area(&hull) - 4.0).abs() < 1e-12);
        // A unit-shifted copy overlaps by 1 of 7: IoU 1/7.
        let moved: Vec<_> = hull.iter().map(|p| [p[0] + 1.0, p[1] + 1.0]).collect();
        assert!((iou(&hull, &moved) - 1.0 / 7.0).abs() < 1e-12);
        let reversed: Vec<_> = moved.iter().rev().copied().collect();
        assert!((iou(&hull, &reversed) - 1.0 / 7.0).abs() < 1e-12);
        // 3 apart: separate unless the margin bridges the gap.
        let far: Vec<_> = hull.iter().map(|p| [p[0] + 5.0, p[1]]).collect();
        assert!(!near_or_overlapping(&hull, &far, 2.0));
        assert!(near_or_overlapping(&hull, &far, 3.5));
        assert!(near_or_overlapping(&hull, &moved, 0.0));
        assert_eq!(iou(&hull, &far), 0.0);
    }

    #[test]
    fn the_box_on_the_eyes_side_of_a_gap_is_in_front() {
        let square = |x: f64, y: f64| [[x, y], [x + 1.0, y], [x + 1.0, y + 1.0], [x, y + 1.0]];
        let (a, b) = (square(0.0, 0.0), square(3.0, 0.5));
        // Eye west of both: a (the western one) is in front; east of both: b is.
        assert_eq!(in_front(&a, &b, [-5.0, 0.0]), Some(true));
        assert_eq!(in_front(&b, &a, [-5.0, 0.0]), Some(false));
        assert_eq!(in_front(&a, &b, [9.0, 0.0]), Some(false));
        // Separated along y only.
        let c = square(0.5, 4.0);
        assert_eq!(in_front(&a, &c, [0.0, -10.0]), Some(true));
        // Separated along both axes, the eye on a's side of one and on d's side of the
        // other: side by side as the eye sees them, neither hides the other.
        let d = square(3.0, 4.0);
        assert_eq!(in_front(&a, &d, [-5.0, 10.0]), Some(false));
        assert_eq!(in_front(&d, &a, [-5.0, 10.0]), Some(false));
        // Both axes agree: a is in front.
        assert_eq!(in_front(&a, &d, [-5.0, -5.0]), Some(true));
        assert_eq!(in_front(&d, &a, [-5.0, -5.0]), Some(false));
        // Overlapping footprints: no order.
        assert_eq!(in_front(&a, &square(0.5, 0.5), [-5.0, 0.0]), None);
    }
}
