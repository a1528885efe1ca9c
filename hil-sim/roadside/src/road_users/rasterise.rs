//! Polygon masks back into pixels.
//!
//! A detector's polygons are traced from its raster mask: along the pixel squares' edges, or
//! through the centres of the boundary pixels (OpenCV's contours, which Detectron2 shifts by
//! half a pixel). The hull of such vertices stands outside (or inside) the object on slanted
//! edges. Filling the polygons again, a pixel in where its centre lies inside or on a
//! polygon (scan lines just above and below each row's centre, and the horizontal edges on
//! it), gives back the detector's mask for either tracing, and the outline of that mask is
//! the one an RLE mask gets ([`MaskOutline`]).

use super::outline::MaskOutline;

/// Largest number of row crossings of one polygon mask's edges (a 1920x1080 mask traced
/// pixel by pixel has a few thousand).
pub const MAX_CROSSINGS: usize = 4_000_000;
/// Largest image side filled when the image size is unknown, in pixels.
const MAX_SIDE: u32 = 16_384;
/// Scan lines run this far above and below each row's centre line, so that a boundary
/// pixel whose centre lies on a horizontal edge is found on one of them.
const EPS_Y: f64 = 1e-6;
/// A pixel whose centre lies this close outside a crossing is in (it lies on the edge).
const EPS_X: f64 = 1e-5;

/// The polygons cross more rows than [`MAX_CROSSINGS`] allows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TooManyCrossings;

/// The first and one-past-last pixel index whose centre lies in `[lo, hi]` (widened by
/// `eps`), clamped to `0..limit`.
fn centres_within(lo: f64, hi: f64, eps: f64, limit: u32) -> (u32, u32) {
    let first = (lo - 0.5 - eps).ceil().max(0.0);
    let end = ((hi - 0.5 + eps).floor() + 1.0).clamp(0.0, f64::from(limit));
    (first.min(end) as u32, end as u32)
}

/// The pixel grid the polygons may cover: `(origin, width, height)`.
fn grid(parts: &[Vec<[f64; 2]>], size: Option<[u32; 2]>) -> ([u32; 2], u32, u32) {
    let [w, h] = size.unwrap_or([MAX_SIDE, MAX_SIDE]);
    let points = parts.iter().flatten();
    let lo = points
        .clone()
        .fold([f64::INFINITY; 2], |m, p| [m[0].min(p[0]), m[1].min(p[1])]);
    let hi = points.fold([f64::NEG_INFINITY; 2], |m, p| {
        [m[0].max(p[0]), m[1].max(p[1])]
    });
    let (x0, x1) = centres_within(lo[0], hi[0], EPS_X, w);
    let (y0, y1) = centres_within(lo[1], hi[1], EPS_Y, h);
    ([x0, y0], x1 - x0, y1 - y0)
}

/// Every edge's crossings of the scan lines of `rows` (grid rows from `top`): (row, line,
/// x) with line 0 just above the row's centre and 1 just below.
fn crossings(part: &[[f64; 2]], top: u32, rows: u32) -> Vec<(u32, u8, f64)> {
    let mut out = Vec::new();
    for (i, &a) in part.iter().enumerate() {
        let b = part[(i + 1) % part.len()];
        if a[1] == b[1] {
            continue;
        }
        let (ylo, yhi) = (a[1].min(b[1]), a[1].max(b[1]));
        for (line, shift) in [(0u8, -EPS_Y), (1, EPS_Y)] {
            // Rows whose line y = top + r + 0.5 + shift lies in [ylo, yhi).
            let base = f64::from(top) + 0.5 + shift;
            let first = (ylo - base).ceil().max(0.0);
            let end = (yhi - base).ceil().clamp(0.0, f64::from(rows));
            for r in first as u32..end.max(first) as u32 {
                let y = base + f64::from(r);
                out.push((r, line, a[0] + (y - a[1]) * (b[0] - a[0]) / (b[1] - a[1])));
            }
        }
    }
    out
}

/// How many crossings `part` has with the scan lines of the whole grid (two per row).
fn crossing_count(part: &[[f64; 2]]) -> f64 {
    part.iter()
        .zip(part.iter().cycle().skip(1))
        .map(|(a, b)| 2.0 * ((a[1] - b[1]).abs() + 1.0))
        .sum()
}

/// The pixel runs `(row, left, right)` on the polygon's horizontal edges that lie on a
/// row's centre line: their centres are on the polygon (a one-row ledge or spike traced
/// through the boundary pixels' centres, which no scan line above or below meets).
fn ledges(part: &[[f64; 2]], origin: [u32; 2], width: u32, rows: u32) -> Vec<(u32, u32, u32)> {
    let [x0, y0] = origin.map(f64::from);
    let mut out = Vec::new();
    for (i, &a) in part.iter().enumerate() {
        let b = part[(i + 1) % part.len()];
        let row = a[1] - y0 - 0.5;
        if a[1] != b[1] || (row - row.round()).abs() > EPS_Y || row.round() < 0.0 {
            continue;
        }
        let row = row.round();
        if row >= f64::from(rows) {
            continue;
        }
        let (left, right) = centres_within(a[0].min(b[0]) - x0, a[0].max(b[0]) - x0, EPS_X, width);
        if left < right {
            out.push((row as u32, left, right));
        }
    }
    out
}

/// The pixel runs `(row, left, right)` inside one polygon (even-odd), on either scan line,
/// and on its horizontal edges ([`ledges`]).
fn runs(part: &[[f64; 2]], origin: [u32; 2], width: u32, rows: u32) -> Vec<(u32, u32, u32)> {
    let mut cross = crossings(part, origin[1], rows);
    cross.sort_by(|p, q| (p.0, p.1).cmp(&(q.0, q.1)).then(p.2.total_cmp(&q.2)));
    let x0 = f64::from(origin[0]);
    let mut out = ledges(part, origin, width, rows);
    for pair in cross.chunk_by(|p, q| (p.0, p.1) == (q.0, q.1)) {
        for span in pair.chunks_exact(2) {
            let (left, right) = centres_within(span[0].2 - x0, span[1].2 - x0, EPS_X, width);
            if left < right {
                out.push((span[0].0, left, right));
            }
        }
    }
    out
}

/// The outline of the pixels of an image of `size` (`[width, height]`, when known) whose
/// centres lie inside or on any of `parts` (each filled even-odd).
pub fn fill(
    parts: &[Vec<[f64; 2]>],
    size: Option<[u32; 2]>,
) -> Result<MaskOutline, TooManyCrossings> {
    if parts.iter().map(|p| crossing_count(p)).sum::<f64>() > MAX_CROSSINGS as f64 {
        return Err(TooManyCrossings);
    }
    let (origin, width, height) = grid(parts, size);
    let mut all: Vec<(u32, u32, u32)> = parts
        .iter()
        .flat_map(|p| runs(p, origin, width, height))
        .collect();
    all.sort_unstable();
    let mut outline = MaskOutline::window(origin, width, height);
    // Merge overlapping runs of a row, so that each pixel is counted once.
    let mut open: Option<(u32, u32, u32)> = None;
    for (row, left, right) in all {
        match &mut open {
            Some((r, _, end)) if *r == row && left <= *end => *end = (*end).max(right),
            _ => {
                if let Some((r, l, e)) = open {
                    outline.add_row_run(r, l, e);
                }
                open = Some((row, left, right));
            }
        }
    }
    if let Some((r, l, e)) = open {
        outline.add_row_run(r, l, e);
    }
    Ok(outline)
}
