//! Filling convex polygons: anti-aliased into a colour image (exact horizontal coverage over
//! sub-rows) and by the pixel-centre rule into a label buffer (a detector's mask).
//!
//! Hand-written rather than `imageproc::drawing::draw_polygon_mut`, which rounds vertices to
//! whole pixels: the renderer's edges and masks must sit where the geometry puts them, to a
//! fraction of a pixel, or the measured localization error would be the drawing's.

use image::{Rgb, RgbImage};

/// Sub-rows per pixel row of the anti-aliased fill.
const SUB_ROWS: u32 = 4;

/// The x interval of a convex polygon at height `y`, if it crosses it.
fn span(poly: &[[f64; 2]], y: f64) -> Option<(f64, f64)> {
    let n = poly.len();
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        if (a[1] <= y && y < b[1]) || (b[1] <= y && y < a[1]) {
            let x = a[0] + (y - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            lo = lo.min(x);
            hi = hi.max(x);
        }
    }
    (lo <= hi).then_some((lo, hi))
}

/// Rows `[first, last)` of the image a polygon may cover.
fn rows(poly: &[[f64; 2]], height: u32) -> (u32, u32) {
    let (lo, hi) = poly
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
            (l.min(p[1]), h.max(p[1]))
        });
    let first = lo.floor().clamp(0.0, f64::from(height)) as u32;
    let last = (hi.ceil() + 1.0).clamp(0.0, f64::from(height)) as u32;
    (first, last)
}

/// Blends `colour` into `image` over the convex polygon `poly` (pixels), anti-aliased.
pub fn fill(image: &mut RgbImage, poly: &[[f64; 2]], colour: [u8; 3]) {
    if poly.len() < 3 || poly.iter().any(|p| !(p[0].is_finite() && p[1].is_finite())) {
        return;
    }
    let (w, h) = image.dimensions();
    let (first, last) = rows(poly, h);
    let mut cover = vec![0f32; w as usize];
    for y in first..last {
        cover.iter_mut().for_each(|c| *c = 0.0);
        let (mut x_lo, mut x_hi) = (w, 0);
        for s in 0..SUB_ROWS {
            let yy = f64::from(y) + (f64::from(s) + 0.5) / f64::from(SUB_ROWS);
            let Some((l, r)) = span(poly, yy) else {
                continue;
            };
            let (l, r) = (l.max(0.0), r.min(f64::from(w)));
            if l >= r {
                continue;
            }
            let (a, b) = (l.floor() as u32, (r.ceil() as u32).min(w));
            for x in a..b {
                let px = f64::from(x);
                let overlap = (r.min(px + 1.0) - l.max(px)).max(0.0);
                cover[x as usize] += (overlap / f64::from(SUB_ROWS)) as f32;
            }
            x_lo = x_lo.min(a);
            x_hi = x_hi.max(b);
        }
        for x in x_lo..x_hi {
            let c = cover[x as usize].min(1.0);
            if c > 0.0 {
                let p = image.get_pixel_mut(x, y);
                *p = Rgb([0, 1, 2].map(|k| blend(p[k], colour[k], c)));
            }
        }
    }
}

fn blend(old: u8, new: u8, c: f32) -> u8 {
    (f32::from(old) * (1.0 - c) + f32::from(new) * c).round() as u8
}

/// Writes `label` into `labels` (row-major, `width` wide) at every pixel whose centre lies in
/// the convex polygon `poly`.
pub fn label(labels: &mut [u16], width: u32, poly: &[[f64; 2]], value: u16) {
    if poly.len() < 3 || width == 0 || poly.iter().any(|p| !(p[0].is_finite() && p[1].is_finite()))
    {
        return;
    }
    let height = (labels.len() / width as usize) as u32;
    let (first, last) = rows(poly, height);
    for y in first..last {
        let Some((l, r)) = span(poly, f64::from(y) + 0.5) else {
            continue;
        };
        // Centres x + 0.5 in [l, r).
        let a = (l - 0.5).ceil().max(0.0);
        let b = (r - 0.5).ceil().min(f64::from(width));
        if a >= b {
            continue;
        }
        let row = y as usize * width as usize;
        labels[row + a as usize..row + b as usize].fill(value);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coverage_and_centre_rule_are_exact_on_a_known_square() {
        // A square from (1.5, 1.0) to (3.5, 3.0): columns 1 and 3 half covered, 2 fully.
        let sq = [[1.5, 1.0], [3.5, 1.0], [3.5, 3.0], [1.5, 3.0]];
        let mut img = RgbImage::new(5, 4);
        fill(&mut img, &sq, [200, 200, 200]);
        assert_eq!(img.get_pixel(2, 1)[0], 200);
        assert_eq!(img.get_pixel(1, 2)[0], 100);
        assert_eq!(img.get_pixel(3, 2)[0], 100);
        assert_eq!(img.get_pixel(0, 2)[0], 0);
        assert_eq!(img.get_pixel(2, 3)[0], 0);
        // Centres 2.5 and 3.5? 3.5 is on the right edge: excluded; 1.5 on the left: included.
        let mut labels = vec![0u16; 5 * 4];
        label(&mut labels, 5, &sq, 7);
        let row1: Vec<u16> = labels[5..10].to_vec();
        assert_eq!(row1, [0, 7, 7, 0, 0]);
        assert_eq!(labels.iter().filter(|&&v| v == 7).count(), 4);
        // Out of the image or degenerate: nothing, no panic.
        label(
            &mut labels,
            5,
            &[[-9.0, -9.0], [-8.0, -9.0], [-8.0, -8.0]],
            3,
        );
        fill(
            &mut img,
            &[[f64::NAN, 0.0], [1.0, 1.0], [0.0, 1.0]],
            [9, 9, 9],
        );
        assert!(!labels.contains(&3));
    }
}
