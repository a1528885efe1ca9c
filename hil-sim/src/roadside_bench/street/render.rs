//! Drawing the scene: the world and the road users as seen by a pinhole camera (painter's
//! order, near-plane clipping, anti-aliased faces), and the detector's masks: each road
//! user's silhouette with noisy corners, nearer users covering farther ones.

use image::RgbImage;

use super::raster::{fill, label};
use super::world::{Solid, World};
use crate::roadside_bench::synthetic_camera::PinholeCamera;
use roadside::rng::Prng;
use roadside::road_users::class::{Extent, RoadUserClass};
use roadside::road_users::polygon::{convex_hull, in_front};

/// Nearest distance in front of the camera drawn, metres.
const NEAR_M: f64 = 0.5;
const SKY: [u8; 3] = [176, 198, 222];

/// One road user of the scene (its box is aligned with the road: length along y).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoadUser {
    /// Stable id.
    pub id: u32,
    /// Class.
    pub class: RoadUserClass,
    /// Centre of the footprint, local metres.
    pub centre: [f64; 2],
    /// Size.
    pub extent: Extent,
    /// Velocity, m/s (east, north).
    pub velocity: [f64; 2],
}

impl RoadUser {
    /// A road user of `class`'s typical size standing at `centre`.
    pub fn standing(id: u32, class: RoadUserClass, centre: [f64; 2]) -> Self {
        Self {
            id,
            class,
            centre,
            extent: class.typical(),
            velocity: [0.0, 0.0],
        }
    }

    /// The box as a solid.
    pub fn solid(&self) -> Solid {
        let (hl, hw) = (self.extent.length_m / 2.0, self.extent.width_m / 2.0);
        let [x, y] = self.centre;
        Solid {
            min: [x - hw, y - hl, 0.0],
            max: [x + hw, y + hl, self.extent.height_m],
            colour: colour_of(self.class, self.id),
            windows: false,
        }
    }
}

/// The colour a road user is drawn in: per class, varied per id.
fn colour_of(class: RoadUserClass, id: u32) -> [u8; 3] {
    let base: [u8; 3] = match class {
        RoadUserClass::Car => [170, 30, 36],
        RoadUserClass::Van => [226, 226, 220],
        RoadUserClass::Bus => [236, 180, 20],
        RoadUserClass::Truck => [40, 80, 150],
        RoadUserClass::Pedestrian => [250, 120, 0],
        RoadUserClass::Cyclist => [30, 140, 60],
        RoadUserClass::Motorcycle => [20, 20, 24],
    };
    let shift = (id % 5) as i32 * 8 - 16;
    base.map(|c| (i32::from(c) + shift).clamp(0, 255) as u8)
}

/// A rendered frame: the picture and the detector's label buffer.
#[derive(Debug, Clone, PartialEq)]
pub struct Rendered {
    /// The picture.
    pub image: RgbImage,
    /// Row-major labels: `k + 1` where road user `k` (of the rendered list) is seen, else 0.
    pub labels: Vec<u16>,
}

/// The eight corners of a solid.
pub fn corners(s: &Solid) -> [[f64; 3]; 8] {
    let (a, b) = (s.min, s.max);
    [
        [a[0], a[1], a[2]],
        [b[0], a[1], a[2]],
        [b[0], b[1], a[2]],
        [a[0], b[1], a[2]],
        [a[0], a[1], b[2]],
        [b[0], a[1], b[2]],
        [b[0], b[1], b[2]],
        [a[0], b[1], b[2]],
    ]
}

/// Draws a 3-D convex polygon (clipped at the near plane).
fn draw_polygon(img: &mut RgbImage, cam: &PinholeCamera, pts: &[[f64; 3]], colour: [u8; 3]) {
    let c: Vec<[f64; 3]> = pts.iter().map(|p| cam.to_camera(*p)).collect();
    let mut clipped = Vec::with_capacity(c.len() + 2);
    for i in 0..c.len() {
        let (p, q) = (c[i], c[(i + 1) % c.len()]);
        if p[2] >= NEAR_M {
            clipped.push(p);
        }
        if (p[2] >= NEAR_M) != (q[2] >= NEAR_M) {
            let t = (NEAR_M - p[2]) / (q[2] - p[2]);
            clipped.push([0, 1, 2].map(|k| p[k] + t * (q[k] - p[k])));
        }
    }
    let px: Vec<[f64; 2]> = clipped.iter().map(|p| cam.pixel_of(*p)).collect();
    fill(img, &px, colour);
}

fn shade(c: [u8; 3], f: f64) -> [u8; 3] {
    c.map(|v| (f64::from(v) * f).clamp(0.0, 255.0) as u8)
}

/// Draws a solid's faces that face the camera, and windows on buildings.
fn draw_solid(img: &mut RgbImage, cam: &PinholeCamera, s: &Solid) {
    let k = corners(s);
    let eye = cam.centre();
    // (corner indices, outward axis, sign, shade)
    let faces: [([usize; 4], usize, f64, f64); 5] = [
        ([0, 3, 7, 4], 0, -1.0, 0.78),
        ([1, 2, 6, 5], 0, 1.0, 0.66),
        ([0, 1, 5, 4], 1, -1.0, 0.92),
        ([3, 2, 6, 7], 1, 1.0, 0.56),
        ([4, 5, 6, 7], 2, 1.0, 1.12),
    ];
    for (idx, axis, sign, f) in faces {
        let plane = if sign > 0.0 { s.max[axis] } else { s.min[axis] };
        if (eye[axis] - plane) * sign <= 0.0 {
            continue;
        }
        draw_polygon(img, cam, &idx.map(|i| k[i]), shade(s.colour, f));
        if s.windows && axis < 2 {
            draw_windows(img, cam, s, axis, plane + sign * 0.02);
        }
    }
}

/// A grid of windows on the wall at `axis` = `plane`.
fn draw_windows(img: &mut RgbImage, cam: &PinholeCamera, s: &Solid, axis: usize, plane: f64) {
    let along = 1 - axis;
    let (lo, hi) = (s.min[along], s.max[along]);
    let mut z = 1.2;
    while z + 1.5 < s.max[2] - 0.6 {
        let mut u = lo + 1.0;
        while u + 1.2 < hi - 0.6 {
            let quad = [[u, z], [u + 1.2, z], [u + 1.2, z + 1.5], [u, z + 1.5]].map(|[a, h]| {
                let mut p = [0.0; 3];
                p[axis] = plane;
                p[along] = a;
                p[2] = h;
                p
            });
            draw_polygon(img, cam, &quad, [48, 58, 78]);
            u += 3.0;
        }
        z += 3.2;
    }
}

/// The footprint of a solid.
fn footprint(s: &Solid) -> [[f64; 2]; 4] {
    let (a, b) = (s.min, s.max);
    [[a[0], a[1]], [b[0], a[1]], [b[0], b[1]], [a[0], b[1]]]
}

/// The order to paint solids in, back to front: repeatedly the first remaining one that
/// stands in front of no other remaining one (footprints separated by a line: the one on the
/// camera's side is in front). Quadratic per pick; scenes hold a few hundred solids.
fn paint_order(cam: &PinholeCamera, solids: &[Solid]) -> Vec<usize> {
    let eye = [cam.centre()[0], cam.centre()[1]];
    let feet: Vec<[[f64; 2]; 4]> = solids.iter().map(footprint).collect();
    let mut left: Vec<usize> = (0..solids.len()).collect();
    let mut order = Vec::with_capacity(solids.len());
    while !left.is_empty() {
        let pick = left
            .iter()
            .position(|&i| {
                !left
                    .iter()
                    .any(|&j| j != i && in_front(&feet[i], &feet[j], eye) == Some(true))
            })
            .unwrap_or(0);
        order.push(left.remove(pick));
    }
    order
}

/// Renders the world and `users`; the masks' silhouette corners carry Gaussian noise of
/// `mask_noise_px` pixels (from `rng`).
pub fn render(
    world: &World,
    cam: &PinholeCamera,
    users: &[RoadUser],
    mask_noise_px: f64,
    rng: &mut Prng,
) -> Rendered {
    Rendered {
        image: picture(world, cam, users),
        labels: labels(cam, users, mask_noise_px, rng),
    }
}

/// The picture of the world and `users`.
pub fn picture(world: &World, cam: &PinholeCamera, users: &[RoadUser]) -> RgbImage {
    let [w, h] = cam.image_size().map(|v| v as u32);
    let mut image = RgbImage::from_pixel(w, h, image::Rgb(SKY));
    for patch in &world.ground {
        let pts: Vec<[f64; 3]> = patch.corners.iter().map(|p| [p[0], p[1], 0.0]).collect();
        draw_polygon(&mut image, cam, &pts, patch.colour);
    }
    let mut solids: Vec<Solid> = world.solids.clone();
    solids.extend(users.iter().map(RoadUser::solid));
    for i in paint_order(cam, &solids) {
        draw_solid(&mut image, cam, &solids[i]);
    }
    image
}

/// The detector's label buffer (row-major, `k + 1` where road user `k` is seen): each
/// user's silhouette with noisy corners, nearer users drawn over farther ones.
pub fn labels(
    cam: &PinholeCamera,
    users: &[RoadUser],
    mask_noise_px: f64,
    rng: &mut Prng,
) -> Vec<u16> {
    let [w, h] = cam.image_size().map(|v| v as u32);
    let window = labels_window(cam, users, mask_noise_px, rng);
    let mut labels = vec![0u16; (w as usize) * (h as usize)];
    let [x0, y0] = window.origin.map(|v| v as usize);
    let cw = window.size[0] as usize;
    if cw > 0 {
        for (r, row) in window.labels.chunks_exact(cw).enumerate() {
            let at = (y0 + r) * w as usize + x0;
            labels[at..at + cw].copy_from_slice(row);
        }
    }
    labels
}

/// Labels of the part of the image the road users cover: the detector's labels ([`labels`])
/// cut to the smallest window holding every silhouette (plus 2 pixels), so that a frame
/// costs its road users' area, not the image's.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LabelWindow {
    /// Row-major labels of the window.
    pub labels: Vec<u16>,
    /// The window's top-left pixel in the image.
    pub origin: [u32; 2],
    /// `[width, height]` of the window (zero when no road user is in view).
    pub size: [u32; 2],
}

/// [`labels`], cut to the window the silhouettes cover.
pub fn labels_window(
    cam: &PinholeCamera,
    users: &[RoadUser],
    mask_noise_px: f64,
    rng: &mut Prng,
) -> LabelWindow {
    let [w, h] = cam.image_size();
    let solids: Vec<Solid> = users.iter().map(RoadUser::solid).collect();
    let hulls: Vec<(usize, Vec<[f64; 2]>)> = paint_order(cam, &solids)
        .into_iter()
        .filter_map(|i| Some((i, silhouette(cam, &solids[i], mask_noise_px, rng)?)))
        .collect();
    let (mut lo, mut hi) = ([w, h], [0.0f64, 0.0f64]);
    for p in hulls.iter().flat_map(|(_, hull)| hull) {
        if p[0].is_finite() && p[1].is_finite() {
            lo = [lo[0].min(p[0]), lo[1].min(p[1])];
            hi = [hi[0].max(p[0]), hi[1].max(p[1])];
        }
    }
    let x0 = (lo[0] - 2.0).floor().clamp(0.0, w) as u32;
    let y0 = (lo[1] - 2.0).floor().clamp(0.0, h) as u32;
    let x1 = (hi[0] + 2.0).ceil().clamp(0.0, w) as u32;
    let y1 = (hi[1] + 2.0).ceil().clamp(0.0, h) as u32;
    let size = [x1.saturating_sub(x0), y1.saturating_sub(y0)];
    let mut labels = vec![0u16; (size[0] as usize) * (size[1] as usize)];
    let shift = [f64::from(x0), f64::from(y0)];
    for (i, hull) in &hulls {
        let moved: Vec<[f64; 2]> = hull
            .iter()
            .map(|p| [p[0] - shift[0], p[1] - shift[1]])
            .collect();
        label(&mut labels, size[0], &moved, (i + 1) as u16);
    }
    LabelWindow {
        labels,
        origin: [x0, y0],
        size,
    }
}

/// The silhouette of a solid (convex hull of its projected corners, each moved by noise);
/// `None` if a corner is behind the near plane.
pub fn silhouette(
    cam: &PinholeCamera,
    s: &Solid,
    noise_px: f64,
    rng: &mut Prng,
) -> Option<Vec<[f64; 2]>> {
    let mut px = Vec::with_capacity(8);
    for p in corners(s) {
        let c = cam.to_camera(p);
        if c[2] < NEAR_M {
            return None;
        }
        let q = cam.pixel_of(c);
        px.push([
            q[0] + noise_px * rng.normal(),
            q[1] + noise_px * rng.normal(),
        ]);
    }
    Some(convex_hull(&px))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::roadside_bench::street::pole_camera;

    /// The detector's labels drawn straight into a full frame, without windows: the
    /// reference [`labels`] (which cuts a window and copies it back) must equal.
    fn full_frame_labels(cam: &PinholeCamera, users: &[RoadUser], rng: &mut Prng) -> Vec<u16> {
        let [w, h] = cam.image_size().map(|v| v as u32);
        let mut out = vec![0u16; (w * h) as usize];
        let solids: Vec<Solid> = users.iter().map(RoadUser::solid).collect();
        for i in paint_order(cam, &solids) {
            if let Some(hull) = silhouette(cam, &solids[i], 1.0, rng) {
                label(&mut out, w, &hull, (i + 1) as u16);
            }
        }
        out
    }

    #[test]
    fn window_labels_equal_labels_drawn_into_the_full_frame() {
        let cam = pole_camera();
        let [w, h] = cam.image_size();
        // In view, cut by the left edge, cut by the bottom edge, and out of view.
        let users = [
            RoadUser::standing(0, RoadUserClass::Car, [5.25, 40.0]),
            RoadUser::standing(1, RoadUserClass::Pedestrian, [4.0, 42.0]),
            RoadUser::standing(2, RoadUserClass::Truck, [-6.0, 24.0]),
            RoadUser::standing(3, RoadUserClass::Van, [3.0, 12.0]),
            RoadUser::standing(4, RoadUserClass::Car, [60.0, 20.0]),
        ];
        let hulls: Vec<Option<Vec<[f64; 2]>>> = users
            .iter()
            .map(|u| silhouette(&cam, &u.solid(), 0.0, &mut Prng::new(1)))
            .collect();
        let cut = |k: usize| {
            hulls[k].as_ref().is_some_and(|hull| {
                let inside = |p: &[f64; 2]| p[0] >= 0.0 && p[1] >= 0.0 && p[0] < w && p[1] < h;
                hull.iter().any(inside) && !hull.iter().all(inside)
            })
        };
        let outside = hulls[4].as_ref().is_none_or(|hull| {
            hull.iter()
                .all(|p| p[0] < 0.0 || p[0] >= w || p[1] < 0.0 || p[1] >= h)
        });
        assert!(
            cut(2) && cut(3) && outside,
            "the scene tests the image's edges"
        );
        let window = labels(&cam, &users, 1.0, &mut Prng::new(9));
        let full = full_frame_labels(&cam, &users, &mut Prng::new(9));
        assert_eq!(window.len(), full.len());
        let differ = window.iter().zip(&full).filter(|(a, b)| a != b).count();
        assert_eq!(differ, 0, "{differ} pixels differ");
        for k in 1..=4u16 {
            assert!(full.contains(&k), "road user {} is drawn", k - 1);
        }
    }
}
