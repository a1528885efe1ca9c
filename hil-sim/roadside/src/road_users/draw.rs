//! Drawing constructed 3D boxes over a frame (`imageproc` lines): the bottom face B1-B4, the
//! top face B5-B8 and the four vertical edges, in the class's colour, and the position as a
//! cross on the road.

use image::{Rgb, RgbImage};
use imageproc::drawing::draw_line_segment_mut;

use super::boxes::RoadUserBox;
use super::RoadUserClass;

/// The colour a class's boxes are drawn in.
pub fn class_colour(class: RoadUserClass) -> Rgb<u8> {
    Rgb(match class {
        RoadUserClass::Car => [255, 40, 40],
        RoadUserClass::Van => [255, 160, 0],
        RoadUserClass::Bus => [255, 255, 0],
        RoadUserClass::Truck => [0, 220, 255],
        RoadUserClass::Pedestrian => [255, 0, 255],
        RoadUserClass::Cyclist => [0, 255, 80],
        RoadUserClass::Motorcycle => [120, 120, 255],
    })
}

/// The twelve edges of a box by vertex index (B1-B4 = 0-3, B5-B8 = 4-7).
const EDGES: [(usize, usize); 12] = [
    (0, 1),
    (1, 2),
    (2, 3),
    (3, 0),
    (4, 5),
    (5, 6),
    (6, 7),
    (7, 4),
    (0, 4),
    (1, 5),
    (2, 6),
    (3, 7),
];

/// Draws `b` onto `image`, with its position's pixel `at` marked by a cross.
pub fn draw_box(image: &mut RgbImage, b: &RoadUserBox, at: Option<[f64; 2]>) {
    let colour = class_colour(b.class);
    let v = b.vertices_px.map(|p| (p[0] as f32, p[1] as f32));
    for (i, j) in EDGES {
        draw_line_segment_mut(image, v[i], v[j], colour);
    }
    if let Some([x, y]) = at {
        let (x, y) = (x as f32, y as f32);
        draw_line_segment_mut(image, (x - 4.0, y), (x + 4.0, y), colour);
        draw_line_segment_mut(image, (x, y - 4.0), (x, y + 4.0), colour);
    }
}
