//! How the trajectory figure maps the road: as east/north, or along the road against the
//! lateral offset when the drive is long and narrow.

use super::clip::{clip_polyline, clip_segment};
use super::shapes::{unit, MapShapes};
use super::span::Span;
use super::style::Xy;

/// Ratio of the drive's length to its width above which the trajectory is drawn along the road.
const EXTREME_ASPECT: f64 = 6.0;

/// How map coordinates become plot coordinates: east/north as they are, or rotated into the
/// drive's main direction (along, lateral with left positive) from `origin`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct View {
    pub(super) origin: [f64; 2],
    pub(super) axis: Option<[f64; 2]>,
}

impl View {
    pub(super) const PLAIN: View = View {
        origin: [0.0, 0.0],
        axis: None,
    };

    pub(super) fn map(&self, p: [f64; 2]) -> Xy {
        let Some(u) = self.axis else {
            return (p[0], p[1]);
        };
        let d = [p[0] - self.origin[0], p[1] - self.origin[1]];
        (d[0] * u[0] + d[1] * u[1], d[1] * u[0] - d[0] * u[1])
    }
}

/// The principal direction of `points`, pointing from the first toward the last.
fn main_axis(points: &[[f64; 2]]) -> Option<[f64; 2]> {
    let (first, last) = (points.first()?, points.last()?);
    let n = points.len() as f64;
    let mean = points
        .iter()
        .fold([0.0, 0.0], |m, p| [m[0] + p[0] / n, m[1] + p[1] / n]);
    let (mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0);
    for p in points {
        let (dx, dy) = (p[0] - mean[0], p[1] - mean[1]);
        (sxx, syy, sxy) = (sxx + dx * dx, syy + dy * dy, sxy + dx * dy);
    }
    let angle = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    let u = [angle.cos(), angle.sin()];
    let forward = (last[0] - first[0]) * u[0] + (last[1] - first[1]) * u[1] >= 0.0;
    Some(if forward { u } else { [-u[0], -u[1]] })
}

/// Rotates into the road direction `road` (else the points' main direction) when the points
/// are much longer than wide (`margin` is added to the width on each side).
fn choose_view(points: &[[f64; 2]], road: Option<[f64; 2]>, margin: f64) -> View {
    let (Some(axis), Some(&origin)) = (main_axis(points), points.first()) else {
        return View::PLAIN;
    };
    let axis = road.map_or(axis, |r| {
        let forward = r[0] * axis[0] + r[1] * axis[1] >= 0.0;
        if forward {
            r
        } else {
            [-r[0], -r[1]]
        }
    });
    let view = View {
        origin,
        axis: Some(axis),
    };
    let mapped: Vec<Xy> = points.iter().map(|&p| view.map(p)).collect();
    let along = Span::of(mapped.iter().map(|p| p.0)).map_or(0.0, Span::len);
    let lateral = Span::of(mapped.iter().map(|p| p.1)).map_or(0.0, Span::len);
    if along > EXTREME_ASPECT * (lateral + 2.0 * margin) {
        view
    } else {
        View::PLAIN
    }
}

/// The length-weighted mean direction (undirected) of the lane centreline segments that cross
/// the box `x` × `y`, or of all of them when none does; `None` without lanes.
fn road_axis(shapes: &MapShapes, x: Span, y: Span) -> Option<[f64; 2]> {
    let segments = || shapes.lanes.iter().flat_map(|l| l.1.centre.windows(2));
    let sum = |near: bool| {
        let crossing = |w: &&[[f64; 2]]| !near || clip_segment(pt(w[0]), pt(w[1]), x, y).is_some();
        let doubled = segments().filter(crossing).map(|w| {
            let (dx, dy) = (w[1][0] - w[0][0], w[1][1] - w[0][1]);
            let angle = 2.0 * dy.atan2(dx);
            let len = dx.hypot(dy);
            [len * angle.cos(), len * angle.sin()]
        });
        unit(doubled.fold([0.0, 0.0], |s, v| [s[0] + v[0], s[1] + v[1]]))
    };
    let mean = sum(true).or_else(|| sum(false))?;
    let angle = 0.5 * mean[1].atan2(mean[0]);
    Some([angle.cos(), angle.sin()])
}

fn pt(p: [f64; 2]) -> Xy {
    (p[0], p[1])
}

/// The view, its x/y spans and the axis labels for the trajectory figure.
pub(super) struct Frame {
    pub(super) view: View,
    pub(super) x: Span,
    pub(super) y: Span,
    pub(super) desc: (String, String),
}

/// The frame of the trajectory figure for the track (or the map when there is no track)
/// and a plot of `px` pixels; `None` when there is nothing to fit.
pub(super) fn trajectory_frame(track: &[[f64; 2]], shapes: &MapShapes, px: Xy) -> Option<Frame> {
    let geometry = || shapes.lanes.iter().map(|l| &l.1).chain(&shapes.zones);
    let map_points: Vec<[f64; 2]> = geometry().flat_map(|s| s.band.iter().copied()).collect();
    let fit = if track.is_empty() { &map_points } else { track };
    let bx = Span::of(fit.iter().map(|p| p[0]))?.pad(0.0, 2.0 * shapes.max_width);
    let by = Span::of(fit.iter().map(|p| p[1]))?.pad(0.0, 2.0 * shapes.max_width);
    let view = choose_view(fit, road_axis(shapes, bx, by), shapes.max_width);
    let fitted: Vec<Xy> = fit.iter().map(|&p| view.map(p)).collect();
    let x = Span::of(fitted.iter().map(|p| p.0))?;
    let y = Span::of(fitted.iter().map(|p| p.1))?;
    if view.axis.is_none() {
        let margin = (0.08 * x.len().max(y.len())).max(2.0 * shapes.max_width);
        let (x, y) = equal_scale(x.pad(0.0, margin), y.pad(0.0, margin), px);
        let desc = (
            "east (m; equal scales)".to_string(),
            "north (m)".to_string(),
        );
        return Some(Frame { view, x, y, desc });
    }
    let x = x.pad(0.03, 5.0);
    let y = y.union(road_lateral(shapes, &view, x, y)).pad(0.0, 1.0);
    let desc = road_desc(&view, x, y, px);
    Some(Frame { view, x, y, desc })
}

/// The lateral extent of the lane and zone edges over the along-road span `x`, limited to
/// three lane widths beside the track's lateral span `y` (so a crossing road does not count).
fn road_lateral(shapes: &MapShapes, view: &View, x: Span, y: Span) -> Option<Span> {
    let window = y.pad(0.0, 3.0 * shapes.max_width);
    let geometry = shapes.lanes.iter().map(|l| &l.1).chain(&shapes.zones);
    let edges = geometry.flat_map(|s| s.edges.iter());
    let mapped = edges.map(|e| e.iter().map(|&p| view.map(p)).collect::<Vec<Xy>>());
    let inside = mapped.flat_map(|e| clip_polyline(&e, x, window)).flatten();
    Span::of(inside.map(|p| p.1))
}

/// Grows the shorter side so that a metre has the same length on both axes.
fn equal_scale(x: Span, y: Span, px: Xy) -> (Span, Span) {
    let m_per_px = (x.len() / px.0).max(y.len() / px.1);
    (x.centred(m_per_px * px.0), y.centred(m_per_px * px.1))
}

fn road_desc(view: &View, x: Span, y: Span, px: Xy) -> (String, String) {
    let u = view.axis.unwrap_or([1.0, 0.0]);
    let heading = u[0].atan2(u[1]).to_degrees().rem_euclid(360.0);
    let exaggeration = (x.len() / px.0) / (y.len() / px.1);
    (
        format!("along the road (m from the drive start, heading {heading:03.0}°)"),
        format!("lateral, left + (m; ×{exaggeration:.0} exaggerated)"),
    )
}

#[cfg(test)]
mod tests {
    use super::super::shapes::offset_line;
    use super::super::style::number;
    use super::*;

    #[test]
    fn views_and_offsets() {
        let diagonal: Vec<[f64; 2]> = (0..50)
            .map(|i| [f64::from(i) * 10.0, f64::from(i) * 10.0])
            .collect();
        let view = choose_view(&diagonal, None, 3.5);
        let (along, lateral) = view.map([100.0, 100.0]);
        assert!((along - 100.0 * 2f64.sqrt()).abs() < 1e-9 && lateral.abs() < 1e-9);
        assert_eq!(choose_view(&diagonal[..3], None, 3.5), View::PLAIN);
        let left = offset_line(&[[0.0, 0.0], [10.0, 0.0], [10.0, 10.0]], 1.0);
        assert_eq!(left[0], [0.0, 1.0]);
        assert!((left[1][0] - (10.0 - 0.5f64.sqrt())).abs() < 1e-9);
        assert_eq!(number(-0.2), "-0.2");
        assert_eq!(number(-0.0), "0");
        assert_eq!(number(-250.0), "-250");
    }
}
