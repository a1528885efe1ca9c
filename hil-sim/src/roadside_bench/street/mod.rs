//! A synthetic roadside camera scene with known truth, for tests and the benchmark: the
//! work-zone street ([`World`]), a 1920x1080 camera on a 6 m pole beside it, road users of
//! every class as solid boxes of realistic size placed at random ([`random_users`]), frames
//! rendered as pictures with the detector's masks ([`render`]), and the masks as a detector
//! gives them: per road user, the convex hull of its visible pixels ([`masks`]) or a COCO
//! file with RLE masks ([`coco_json`]). Our own drawing and numbers.

mod raster;
mod render;
mod traffic;
mod world;

use serde_json::{json, Value};

pub use render::{
    corners, labels, labels_window, picture, render, silhouette, LabelWindow, Rendered, RoadUser,
};
pub use traffic::{users_at, work_zone_traffic, Motion, Mover, LOOP_M};
pub use world::{Patch, Solid, World};

use super::synthetic_camera::PinholeCamera;
use roadside::rng::Prng;
use roadside::road_users::class::RoadUserClass;
use roadside::road_users::detections::Silhouette;
use roadside::road_users::outline::MaskOutline;

/// Where the scene's camera stands: 6 m up a pole at the back of the west sidewalk, 6 m
/// from the carriageway, looking up the street (bearing 18°, pitched 11° down).
const POLE: ([f64; 3], f64, f64) = ([-6.0, 0.0, 6.0], 18.0, 11.0);

/// The scene's camera: 6 m up a pole at the back of the west sidewalk (bearing 18°, pitched
/// 11° down), 1920x1080, zoomed so that the road from 15 m to the horizon
/// fills the frame (focal length 2800 px, 38° across): a crossing pixel is 1.4 cm wide and
/// 10 cm deep on the road 40 m away.
pub fn pole_camera() -> PinholeCamera {
    let (centre, bearing, pitch) = POLE;
    PinholeCamera::with_lens(centre, bearing, pitch, 2800.0, [1920.0, 1080.0])
}

/// The same camera at half the resolution (960x540, focal 1400 px), for quick tests.
pub fn small_pole_camera() -> PinholeCamera {
    let (centre, bearing, pitch) = POLE;
    PinholeCamera::with_lens(centre, bearing, pitch, 1400.0, [960.0, 540.0])
}

/// A site's two cameras over the street of `world`: [`pole_camera`] (or
/// [`small_pole_camera`] when `small`), and one 6 m up, 7 m right of the carriageway at
/// y = 75 m, looking back down the street (bearing 200°, pitched 11° down).
pub fn site_cameras(world: &World, small: bool) -> [PinholeCamera; 2] {
    let first = if small {
        small_pole_camera()
    } else {
        pole_camera()
    };
    let back = ([world.road_width_m() + 7.0, 75.0, 6.0], 200.0, POLE.2);
    let second =
        PinholeCamera::with_lens(back.0, back.1, back.2, first.focal_px(), first.image_size());
    [first, second]
}

/// A camera's reference points as a surveyor gives them: the corners of the lane markings
/// (every lane edge of `world`'s street, every 5 m from 10 m to 75 m) that it sees at least
/// 20 px inside its frame, each as (pixel picked with 0.5 px of noise, road point in metres).
pub fn marking_points(
    cam: &PinholeCamera,
    world: &World,
    rng: &mut Prng,
) -> Vec<([f64; 2], [f64; 2])> {
    let [w, h] = cam.image_size();
    let mut pairs = Vec::new();
    for k in 0..14 {
        let y = 10.0 + 5.0 * f64::from(k);
        for edge in 0..=world.lanes {
            let ground = [world.lane_width_m * f64::from(edge), y];
            let Some(px) = cam.project(ground) else {
                continue;
            };
            if px[0] > 20.0 && px[1] > 20.0 && px[0] < w - 20.0 && px[1] < h - 20.0 {
                let pixel = [px[0] + 0.5 * rng.normal(), px[1] + 0.5 * rng.normal()];
                pairs.push((pixel, ground));
            }
        }
    }
    pairs
}

/// Distance of a road point from the camera's foot, metres.
pub fn range_m(cam: &PinholeCamera, p: [f64; 2]) -> f64 {
    let c = cam.centre();
    (p[0] - c[0]).hypot(p[1] - c[1])
}

/// Is the whole box of `u` in the image, `margin` pixels inside its border?
pub fn in_view(cam: &PinholeCamera, u: &RoadUser, margin: f64) -> bool {
    let [w, h] = cam.image_size();
    corners(&u.solid()).iter().all(|p| {
        let c = cam.to_camera(*p);
        let q = cam.pixel_of(c);
        c[2] > 1.0 && q[0] >= margin && q[1] >= margin && q[0] <= w - margin && q[1] <= h - margin
    })
}

/// Where a road user of `class` may stand across the street (x range, metres).
fn lateral_range(world: &World, class: RoadUserClass) -> [f64; 2] {
    let road = world.road_width_m();
    match class {
        RoadUserClass::Pedestrian => [-0.8, road + 0.8],
        _ => [
            0.5 * world.lane_width_m - 0.4,
            road - 0.5 * world.lane_width_m + 0.4,
        ],
    }
}

/// `count` road users of classes drawn in turn from `classes`, each fully in view, within
/// `max_range_m` of the camera's foot (and 8 m at least), on the carriageway (people also on
/// the shoulders), footprints at least 0.3 m apart; sizes as on the road ([`road_size`]). Fewer are returned when no free place is found in 200 tries.
pub fn random_users(
    world: &World,
    cam: &PinholeCamera,
    rng: &mut Prng,
    count: usize,
    max_range_m: f64,
    classes: &[RoadUserClass],
) -> Vec<RoadUser> {
    let mut out: Vec<RoadUser> = Vec::with_capacity(count);
    for k in 0..count {
        let Some(&class) = classes.get(k % classes.len().max(1)) else {
            break;
        };
        for _ in 0..200 {
            let extent = road_size(class, rng);
            let [x0, x1] = lateral_range(world, class);
            let x = x0 + (x1 - x0) * rng.next_f64();
            let y = 5.0 + (max_range_m - 5.0) * rng.next_f64();
            let u = RoadUser {
                id: k as u32,
                class,
                centre: [x, y],
                extent,
                velocity: [0.0, 0.0],
            };
            let r = range_m(cam, u.centre);
            if (8.0..=max_range_m).contains(&r) && in_view(cam, &u, 2.0) && apart(&out, &u, 0.3) {
                out.push(u);
                break;
            }
        }
    }
    out
}

/// The sides of a road user of `class` drawn as they vary on the road (uniform over each
/// range, metres): people 0.4-0.6 across either way and 1.55-1.9 tall, cars 4.2-5.0 m long,
/// vans 4.8-5.8, buses 10.5-13.5, trucks 7-10, with their widths and heights. The
/// localizer's size prior comes from road fleets, not from these ranges.
pub fn road_size(class: RoadUserClass, rng: &mut Prng) -> roadside::road_users::class::Extent {
    let ((l0, l1), (w0, w1), (h0, h1)) = match class {
        RoadUserClass::Car => ((4.2, 5.0), (1.7, 1.9), (1.4, 1.65)),
        RoadUserClass::Van => ((4.8, 5.8), (1.9, 2.1), (1.9, 2.6)),
        RoadUserClass::Bus => ((10.5, 13.5), (2.5, 2.55), (3.0, 3.4)),
        RoadUserClass::Truck => ((7.0, 10.0), (2.4, 2.55), (3.0, 4.0)),
        RoadUserClass::Pedestrian => ((0.4, 0.6), (0.4, 0.6), (1.55, 1.9)),
        RoadUserClass::Cyclist => ((1.6, 1.9), (0.5, 0.7), (1.6, 1.85)),
        RoadUserClass::Motorcycle => ((1.9, 2.3), (0.7, 0.9), (1.3, 1.55)),
    };
    let mut pick = |(a, b): (f64, f64)| a + (b - a) * rng.next_f64();
    roadside::road_users::class::Extent {
        length_m: pick((l0, l1)),
        width_m: pick((w0, w1)),
        height_m: pick((h0, h1)),
    }
}

/// Are the footprints of `u` and every one of `others` at least `gap` apart?
fn apart(others: &[RoadUser], u: &RoadUser, gap: f64) -> bool {
    let a = u.solid();
    others.iter().all(|o| {
        let s = o.solid();
        a.min[0] > s.max[0] + gap
            || s.min[0] > a.max[0] + gap
            || a.min[1] > s.max[1] + gap
            || s.min[1] > a.max[1] + gap
    })
}

/// The detector's output for a label buffer of `size` = `[width, height]`: for each road
/// user `k` seen (label `k + 1`)
/// and not in `missed`, its class and the outline of its visible pixels
/// ([`MaskOutline`]). Returns `(k, silhouette)` pairs.
pub fn masks(
    labels: &[u16],
    size: [u32; 2],
    users: &[RoadUser],
    missed: &[bool],
) -> Vec<(usize, Silhouette)> {
    let window = LabelWindow {
        labels: Vec::new(),
        origin: [0, 0],
        size,
    };
    masks_in(labels, &window, size, users, missed)
}

/// [`masks`] of a [`LabelWindow`] of an image of `image` = `[width, height]` pixels (the
/// window's own `labels` are not read: `labels` are, so that [`masks`] needs no copy).
fn masks_in(
    labels: &[u16],
    window: &LabelWindow,
    image: [u32; 2],
    users: &[RoadUser],
    missed: &[bool],
) -> Vec<(usize, Silhouette)> {
    let [w, h] = image;
    let [cw, ch] = window.size;
    let [x0, y0] = window.origin;
    if labels.len() != (cw as usize) * (ch as usize) {
        return Vec::new();
    }
    let n = users.len();
    let mut outlines: Vec<MaskOutline> = (0..n).map(|_| MaskOutline::new(w, h)).collect();
    for (i, &l) in labels.iter().enumerate() {
        if let Some(o) = (l as usize)
            .checked_sub(1)
            .and_then(|k| outlines.get_mut(k))
        {
            o.add_pixel(x0 + i as u32 % cw, y0 + i as u32 / cw);
        }
    }
    outlines
        .iter()
        .enumerate()
        .filter(|(k, o)| o.area() > 0 && !missed.get(*k).copied().unwrap_or(false))
        .map(|(k, o)| {
            let s = Silhouette {
                class: users[k].class,
                score: None,
                hull: o.hull(),
                area_px: o.area() as f64,
                parts: 1,
                touches_border: o.touches_border(),
            };
            (k, s)
        })
        .collect()
}

/// [`masks`] of the window [`labels_window`] rendered, in an image of `image` pixels.
pub fn window_masks(
    window: &LabelWindow,
    image: [u32; 2],
    users: &[RoadUser],
    missed: &[bool],
) -> Vec<(usize, Silhouette)> {
    masks_in(&window.labels, window, image, users, missed)
}

/// One frame of a COCO file: its picture's name and size, the label buffer, the road users
/// it labels and which of them the detector missed.
#[derive(Debug, Clone, Copy)]
pub struct CocoFrame<'a> {
    /// The picture's file name.
    pub file_name: &'a str,
    /// `[width, height]`, pixels.
    pub size: [u32; 2],
    /// Row-major labels (`k + 1` for road user `k`).
    pub labels: &'a [u16],
    /// The road users.
    pub users: &'a [RoadUser],
    /// Missed detections (by index; shorter means not missed).
    pub missed: &'a [bool],
}

/// A COCO dataset file of frames (image ids 0, 1, ...): masks as uncompressed RLE
/// (column-major), classes by name.
pub fn coco_json(frames: &[CocoFrame<'_>]) -> Value {
    let categories: Vec<Value> = RoadUserClass::ALL
        .iter()
        .enumerate()
        .map(|(i, c)| json!({"id": i + 1, "name": c.name()}))
        .collect();
    let mut images = Vec::new();
    let mut annotations = Vec::new();
    for (id, f) in frames.iter().enumerate() {
        let [w, h] = f.size;
        images.push(json!({"id": id, "file_name": f.file_name, "width": w, "height": h}));
        if f.labels.len() != (w as usize) * (h as usize) {
            continue;
        }
        for (k, u) in f.users.iter().enumerate() {
            if f.missed.get(k).copied().unwrap_or(false) {
                continue;
            }
            let counts = rle_counts(f.labels, w, h, (k + 1) as u16);
            if counts.len() <= 1 {
                continue;
            }
            let cat = RoadUserClass::ALL
                .iter()
                .position(|c| *c == u.class)
                .unwrap_or(0)
                + 1;
            annotations.push(json!({
                "id": annotations.len() + 1, "image_id": id, "category_id": cat,
                "segmentation": {"size": [h, w], "counts": counts}, "score": 1.0,
            }));
        }
    }
    json!({"images": images, "annotations": annotations, "categories": categories})
}

/// Column-major run lengths of `value` in a label buffer, starting with a (maybe empty) run
/// of other pixels.
fn rle_counts(labels: &[u16], w: u32, h: u32, value: u16) -> Vec<u32> {
    let mut counts = Vec::new();
    let (mut current, mut run) = (false, 0u32);
    for x in 0..w {
        for y in 0..h {
            let on = labels[(y * w + x) as usize] == value;
            if on != current {
                counts.push(run);
                run = 0;
                current = on;
            }
            run += 1;
        }
    }
    counts.push(run);
    counts
}
