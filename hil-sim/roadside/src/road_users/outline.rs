//! The outline of a raster mask: the convex hull of its boundary points.
//!
//! A detector's mask holds the pixels whose centres fall inside the object, so the object's
//! boundary crosses each row's centre line between the centre of the first pixel in and that
//! of the last pixel out: its best estimate is the pixel's edge, `(left, y + 0.5)`, off by a
//! rounding spread evenly over a pixel. The same holds along each column. The hull of those
//! points rests on their outermost roundings: along an axis-aligned edge it has no bias, along
//! a slanted one it stands out by up to half a pixel (the hull of the pixel squares' corners
//! stands out further). Fitting the box to the points themselves would remove
//! that rounding, but where mask noise moves the silhouette's corners (the bench's noise
//! model) the hull's vertices are those corners and measure the box better: the fit takes
//! the hull, and compares it with the box's outline moved out by the rounding the hull
//! keeps.

use super::polygon::convex_hull;

/// A mask being read pixel by pixel or run by run, over a grid of pixels: the whole image, or
/// a window of it (pixel coordinates are then the window's, and the hull is the image's).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MaskOutline {
    /// The image pixel of the grid's top-left pixel.
    origin: [u32; 2],
    width: u32,
    height: u32,
    /// Per column: first row in and last row in.
    columns: Vec<Option<(u32, u32)>>,
    /// Per row: first column in and last column in.
    rows: Vec<Option<(u32, u32)>>,
    area: u64,
}

fn widen(slot: &mut Option<(u32, u32)>, lo: u32, hi: u32) {
    *slot = Some(slot.map_or((lo, hi), |(a, b)| (a.min(lo), b.max(hi))));
}

impl MaskOutline {
    /// An empty mask of `width` x `height` pixels.
    pub fn new(width: u32, height: u32) -> Self {
        Self::window([0, 0], width, height)
    }

    /// An empty window of `width` x `height` pixels whose top-left pixel is image pixel
    /// `origin` (column, row).
    pub fn window(origin: [u32; 2], width: u32, height: u32) -> Self {
        Self {
            origin,
            width,
            height,
            columns: vec![None; width as usize],
            rows: vec![None; height as usize],
            area: 0,
        }
    }

    /// Adds pixel (column `x`, row `y` of the grid); pixels outside the grid are ignored.
    pub fn add_pixel(&mut self, x: u32, y: u32) {
        if x < self.width && y < self.height {
            widen(&mut self.columns[x as usize], y, y);
            widen(&mut self.rows[y as usize], x, x);
            self.area += 1;
        }
    }

    /// Adds rows `top..bottom` of column `x`.
    pub fn add_column_run(&mut self, x: u32, top: u32, bottom: u32) {
        let bottom = bottom.min(self.height);
        if x >= self.width || top >= bottom {
            return;
        }
        widen(&mut self.columns[x as usize], top, bottom - 1);
        for y in top..bottom {
            widen(&mut self.rows[y as usize], x, x);
        }
        self.area += u64::from(bottom - top);
    }

    /// Adds columns `left..right` of row `y`.
    pub fn add_row_run(&mut self, y: u32, left: u32, right: u32) {
        let right = right.min(self.width);
        if y >= self.height || left >= right {
            return;
        }
        widen(&mut self.rows[y as usize], left, right - 1);
        for x in left..right {
            widen(&mut self.columns[x as usize], y, y);
        }
        self.area += u64::from(right - left);
    }

    /// Pixels in the mask.
    pub fn area(&self) -> u64 {
        self.area
    }

    /// Does the mask reach the grid's border (the image's, for a grid made by [`Self::new`])?
    pub fn touches_border(&self) -> bool {
        let (w, h) = (self.width, self.height);
        let edge_col = |c: usize| self.columns.get(c).is_some_and(Option::is_some);
        let edge_row = |r: usize| self.rows.get(r).is_some_and(Option::is_some);
        w > 0
            && h > 0
            && (edge_col(0) || edge_col(w as usize - 1) || edge_row(0) || edge_row(h as usize - 1))
    }

    /// The convex hull of the boundary points (see the module's documentation).
    pub fn hull(&self) -> Vec<[f64; 2]> {
        let [x0, y0] = self.origin.map(f64::from);
        let mut points = Vec::new();
        for (x, c) in self.columns.iter().enumerate() {
            if let Some((top, bottom)) = c {
                let x = x0 + x as f64 + 0.5;
                points.push([x, y0 + f64::from(*top)]);
                points.push([x, y0 + f64::from(*bottom) + 1.0]);
            }
        }
        for (y, r) in self.rows.iter().enumerate() {
            if let Some((left, right)) = r {
                let y = y0 + y as f64 + 0.5;
                points.push([x0 + f64::from(*left), y]);
                points.push([x0 + f64::from(*right) + 1.0, y]);
            }
        }
        convex_hull(&points)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_outline_of_a_rectangle_is_its_edges() {
        // Pixels 2..5 x 1..3: the rectangle [2, 5] x [1, 3] exactly (its edges' midpoints
        // of every row and column, so the hull has the rectangle's area less the corners).
        let mut m = MaskOutline::new(8, 6);
        for x in 2..5 {
            m.add_column_run(x, 1, 3);
        }
        assert_eq!(m.area(), 6);
        assert!(!m.touches_border());
        let hull = m.hull();
        let xs: Vec<f64> = hull.iter().map(|p| p[0]).collect();
        let ys: Vec<f64> = hull.iter().map(|p| p[1]).collect();
        assert_eq!(xs.iter().copied().fold(f64::INFINITY, f64::min), 2.0);
        assert_eq!(xs.iter().copied().fold(0.0, f64::max), 5.0);
        assert_eq!(ys.iter().copied().fold(f64::INFINITY, f64::min), 1.0);
        assert_eq!(ys.iter().copied().fold(0.0, f64::max), 3.0);
        // Pixel by pixel gives the same; a pixel on the border is seen; outside is ignored.
        let mut p = MaskOutline::new(8, 6);
        (2..5).for_each(|x| (1..3).for_each(|y| p.add_pixel(x, y)));
        assert_eq!(p.hull(), hull);
        p.add_pixel(7, 5);
        p.add_pixel(99, 99);
        assert!(p.touches_border());
        assert_eq!(p.area(), 7);
    }
}
