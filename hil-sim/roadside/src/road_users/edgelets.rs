//! Edgelets: short straight pieces of image edges, each a point, a direction and a strength,
//! found from the image gradients without any line-segment detection or clustering.
//!
//! The image is cut into square cells. In each cell the Sobel gradients (`imageproc`) of the
//! pixels whose gradient magnitude passes a threshold are summed into a structure tensor;
//! only the ridge pixels of the gradient magnitude count (thin edges). A cell whose tensor has
//! one clear orientation (coherence near 1: one straight edge, not a corner or texture) gives
//! one edgelet at the magnitude-weighted centroid of those pixels, running across the
//! dominant gradient.

use image::GrayImage;
use imageproc::filter::gaussian_blur_f32;
use imageproc::gradients::{horizontal_scharr, vertical_scharr};

/// Gaussian smoothing before the gradients, pixels: a sharp step's Sobel/Scharr direction
/// is biased by up to a degree or two depending on the edge's angle; smoothing removes it.
const BLUR_SIGMA_PX: f32 = 1.0;
/// Pixels this near the border are left out (their blur and gradients are clamped).
const BORDER_PX: u32 = 4;

/// One straight piece of an image edge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Edgelet {
    /// A pixel on the edge.
    pub point: [f64; 2],
    /// Unit direction along the edge (either way).
    pub direction: [f64; 2],
    /// Summed gradient magnitude of the edge's pixels: longer and sharper edges weigh more.
    pub strength: f64,
}

/// How edgelets are found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeletSettings {
    /// Side of a cell, pixels (one edgelet at most per cell).
    pub cell_px: u32,
    /// Smallest Sobel gradient magnitude of an edge pixel (a step of 255 gives 1020).
    pub min_magnitude: f64,
    /// Smallest coherence `(λ1 - λ2) / (λ1 + λ2)` of a cell's structure tensor.
    pub min_coherence: f64,
    /// Fewest edge pixels in a cell.
    pub min_pixels: u32,
}

impl Default for EdgeletSettings {
    /// 8 px cells, magnitude 60 (a step of 15 grey levels), coherence 0.9, 5 pixels.
    fn default() -> Self {
        Self {
            cell_px: 8,
            min_magnitude: 60.0,
            min_coherence: 0.9,
            min_pixels: 5,
        }
    }
}

/// Sums of one cell.
#[derive(Default, Clone, Copy)]
struct Cell {
    jxx: f64,
    jxy: f64,
    jyy: f64,
    weight: f64,
    x: f64,
    y: f64,
    pixels: u32,
}

/// The edgelets of a grey image, cell by cell in row order.
pub fn edgelets(image: &GrayImage, settings: &EdgeletSettings) -> Vec<Edgelet> {
    let (w, h) = image.dimensions();
    let cell = settings.cell_px.max(2);
    if w < 3 || h < 3 {
        return Vec::new();
    }
    let smooth = gaussian_blur_f32(image, BLUR_SIGMA_PX);
    let gx = horizontal_scharr(&smooth);
    let gy = vertical_scharr(&smooth);
    let (cols, rows) = (w.div_ceil(cell) as usize, h.div_ceil(cell) as usize);
    let mut cells = vec![Cell::default(); cols * rows];
    let min2 = settings.min_magnitude * settings.min_magnitude;
    let grad = |x: u32, y: u32| {
        (
            f64::from(gx.get_pixel(x, y)[0]),
            f64::from(gy.get_pixel(x, y)[0]),
        )
    };
    let mag2 = |x: u32, y: u32| {
        let (dx, dy) = grad(x, y);
        dx * dx + dy * dy
    };
    // Pixels near the border have clamped blur and gradients: left out.
    let m = BORDER_PX.min(w / 2).min(h / 2).max(1);
    for y in m..h - m {
        let row = (y / cell) as usize * cols;
        for x in m..w - m {
            let (dx, dy) = grad(x, y);
            let m2 = dx * dx + dy * dy;
            if m2 < min2 {
                continue;
            }
            // Thin edges: a pixel counts only at the ridge of the magnitude across the edge
            // (its neighbours along the gradient, to the nearest of 8 directions, are not
            // stronger), so that a cell's centroid lies on the edge, not on its blurred fringe.
            let (sx, sy) = step_along(dx, dy);
            let ahead = mag2(x.wrapping_add_signed(sx), y.wrapping_add_signed(sy));
            let behind = mag2(x.wrapping_add_signed(-sx), y.wrapping_add_signed(-sy));
            if m2 < ahead || m2 < behind {
                continue;
            }
            let mg = m2.sqrt();
            let c = &mut cells[row + (x / cell) as usize];
            c.jxx += dx * dx;
            c.jxy += dx * dy;
            c.jyy += dy * dy;
            c.weight += mg;
            // Pixel centres are at half-integer coordinates.
            c.x += mg * (f64::from(x) + 0.5);
            c.y += mg * (f64::from(y) + 0.5);
            c.pixels += 1;
        }
    }
    cells
        .iter()
        .filter(|c| c.pixels >= settings.min_pixels)
        .filter_map(|c| cell_edgelet(c, settings.min_coherence))
        .collect()
}

/// The neighbour step (one of 8 directions) nearest to the gradient's direction.
fn step_along(dx: f64, dy: f64) -> (i32, i32) {
    let octant = (dy.atan2(dx) / std::f64::consts::FRAC_PI_4).round() as i32;
    match octant.rem_euclid(8) {
        0 => (1, 0),
        1 => (1, 1),
        2 => (0, 1),
        3 => (-1, 1),
        4 => (-1, 0),
        5 => (-1, -1),
        6 => (0, -1),
        _ => (1, -1),
    }
}

/// The edgelet of a cell whose gradients agree on one orientation.
fn cell_edgelet(c: &Cell, min_coherence: f64) -> Option<Edgelet> {
    let half_trace = (c.jxx + c.jyy) / 2.0;
    let spread = ((c.jxx - c.jyy) / 2.0).hypot(c.jxy);
    if half_trace <= 0.0 || spread / half_trace < min_coherence {
        return None;
    }
    // The dominant gradient points at angle θ; the edge runs across it.
    let theta = 0.5 * (2.0 * c.jxy).atan2(c.jxx - c.jyy);
    let (s, co) = theta.sin_cos();
    Some(Edgelet {
        point: [c.x / c.weight, c.y / c.weight],
        direction: [-s, co],
        strength: c.weight,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::Luma;

    #[test]
    fn a_slanted_step_gives_edgelets_along_it() {
        // Bright below the line y = 0.5 x + 20 (exact coverage is not needed: the step is
        // sampled at pixel centres).
        let img = GrayImage::from_fn(200, 160, |x, y| {
            let above = f64::from(y) + 0.5 < 0.5 * (f64::from(x) + 0.5) + 20.0;
            Luma([if above { 40 } else { 200 }])
        });
        let found = edgelets(&img, &EdgeletSettings::default());
        assert!(found.len() > 15, "{} edgelets", found.len());
        for e in &found {
            // On the line (within a pixel) and along it (within 3°).
            let off = (0.5 * e.point[0] + 20.0 - e.point[1]).abs() / 1.25f64.sqrt();
            assert!(off < 1.0, "{e:?} is {off} px off the edge");
            let along = (e.direction[1] / e.direction[0]).atan().to_degrees();
            assert!((along - 0.5f64.atan().to_degrees()).abs() < 3.0, "{e:?}");
        }
        // A flat image has none.
        assert!(edgelets(&GrayImage::new(64, 64), &EdgeletSettings::default()).is_empty());
        assert!(edgelets(&GrayImage::new(2, 2), &EdgeletSettings::default()).is_empty());
    }
}
