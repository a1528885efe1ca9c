//! Clipping to the plot rectangle (plotters does not clip).

use super::series::flush;
use super::span::Span;
use super::style::Xy;

/// The parts of a polyline inside the rectangle `x` × `y`.
pub(super) fn clip_polyline(line: &[Xy], x: Span, y: Span) -> Vec<Vec<Xy>> {
    let mut pieces = Vec::new();
    let mut current: Vec<Xy> = Vec::new();
    for pair in line.windows(2) {
        match clip_segment(pair[0], pair[1], x, y) {
            Some((a, b)) => {
                if current.last() != Some(&a) {
                    flush(&mut pieces, &mut current);
                    current.push(a);
                }
                current.push(b);
            }
            None => flush(&mut pieces, &mut current),
        }
    }
    flush(&mut pieces, &mut current);
    pieces
}

/// Liang-Barsky: the part of the segment `a`-`b` inside the rectangle, ends kept exact.
pub(super) fn clip_segment(a: Xy, b: Xy, x: Span, y: Span) -> Option<(Xy, Xy)> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    for (p, q) in [
        (-dx, a.0 - x.lo),
        (dx, x.hi - a.0),
        (-dy, a.1 - y.lo),
        (dy, y.hi - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
            continue;
        }
        let t = q / p;
        if p < 0.0 {
            t0 = t0.max(t);
        } else {
            t1 = t1.min(t);
        }
        if t0 > t1 {
            return None;
        }
    }
    let at = |t: f64| (a.0 + dx * t, a.1 + dy * t);
    let start = if t0 > 0.0 { at(t0) } else { a };
    let end = if t1 < 1.0 { at(t1) } else { b };
    Some((start, end))
}

/// Sutherland-Hodgman: the polygon cut to the rectangle `x` × `y`.
pub(super) fn clip_polygon(poly: &[Xy], x: Span, y: Span) -> Vec<Xy> {
    let halves = [
        (0, x.lo, true),
        (0, x.hi, false),
        (1, y.lo, true),
        (1, y.hi, false),
    ];
    halves
        .iter()
        .fold(poly.to_vec(), |p, &(axis, bound, above)| {
            clip_half(&p, axis, bound, above)
        })
}

fn clip_half(poly: &[Xy], axis: usize, bound: f64, above: bool) -> Vec<Xy> {
    let coord = |p: Xy| if axis == 0 { p.0 } else { p.1 };
    let inside = |p: Xy| {
        if above {
            coord(p) >= bound
        } else {
            coord(p) <= bound
        }
    };
    let cross = |a: Xy, b: Xy| {
        let t = (bound - coord(a)) / (coord(b) - coord(a));
        (a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t)
    };
    let mut out = Vec::with_capacity(poly.len() + 4);
    let Some(&last) = poly.last() else {
        return out;
    };
    let mut prev = last;
    for &cur in poly {
        if inside(cur) != inside(prev) {
            out.push(cross(prev, cur));
        }
        if inside(cur) {
            out.push(cur);
        }
        prev = cur;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clipping() {
        let (x, y) = (Span { lo: 0.0, hi: 10.0 }, Span { lo: 0.0, hi: 10.0 });
        assert_eq!(
            clip_segment((-5.0, 5.0), (5.0, 5.0), x, y),
            Some(((0.0, 5.0), (5.0, 5.0)))
        );
        assert_eq!(clip_segment((-5.0, -5.0), (-1.0, 20.0), x, y), None);
        let line = [
            (-5.0, 5.0),
            (5.0, 5.0),
            (8.0, 5.0),
            (20.0, 5.0),
            (20.0, 6.0),
            (5.0, 6.0),
        ];
        let pieces = clip_polyline(&line, x, y);
        assert_eq!(
            pieces,
            vec![
                vec![(0.0, 5.0), (5.0, 5.0), (8.0, 5.0), (10.0, 5.0)],
                vec![(10.0, 6.0), (5.0, 6.0)]
            ]
        );
        let square = [(-5.0, -5.0), (5.0, -5.0), (5.0, 5.0), (-5.0, 5.0)];
        let cut = clip_polygon(&square, x, y);
        assert_eq!(cut.len(), 4);
        assert!(cut
            .iter()
            .all(|p| (0.0..=5.0).contains(&p.0) && (0.0..=5.0).contains(&p.1)));
        assert!(clip_polygon(&[], x, y).is_empty());
    }
}
