//! A synthetic roadside camera with known ground truth: a pinhole camera over the road plane
//! that projects surveyed points and cones to pixels, with seeded pixel noise.
//!
//! - [`PinholeCamera`] projects local east/north/up metres of a [`Road`] to pixels (u right,
//!   v down) and gives the detector's box of a cone ([`PinholeCamera::cone_box`]).
//! - [`control_points`] turns surveyed road points into noisy [`Correspondence`]s, and
//!   [`detect`] turns cones into per-frame detections with noise and missed cones.
//! - [`zone_scene`] places cones along the closed lanes of a work zone and a camera beside
//!   the road that sees them ([`ZoneScene`]).
//! - [`capture`] does it all for a zone with the noise of a [`CaptureSpec`], and
//!   [`Capture::write`] (through [`calibration_json`] and [`detections_json`]) writes the
//!   files that [`parse_calibration`](roadside::camera::parse_calibration) and
//!   [`parse_detections_json`](roadside::cones::parse_detections_json) read.
//!
//! Noise comes from the roadside's seeded generator ([`Prng`]), so the same seed gives the same
//! data. No function here panics on its input: a point out of view gives `None` (or an
//! error naming it), a cone out of view is never detected.

mod capture;
mod scene;

use std::fmt;

use roadside::camera::Correspondence;
use roadside::cones::{BoundingBox, Detection, FrameDetections};
use roadside::rng::Prng;
use roadside::road::{dist, Road};

pub use capture::{calibration_json, capture, detections_json, Capture, CaptureSpec};
pub use scene::{zone_scene, Placement, ZoneScene};

/// Height of a traffic cone, metres.
pub const CONE_HEIGHT_M: f64 = 0.7;
/// Half the width of a cone's box at its base, metres.
pub const CONE_HALF_WIDTH_M: f64 = 0.15;

/// Why synthetic data cannot be made.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum SyntheticError {
    /// A closed lane is not on the map.
    UnknownLane(u8),
    /// The zone's stations are not finite, or its end is not after its start.
    BadZone,
    /// Control point `index` is not in the camera's image.
    OutOfView {
        /// Index of the point.
        index: usize,
    },
    /// Control point `index` has no latitude/longitude.
    NoPosition {
        /// Index of the point.
        index: usize,
    },
    /// No camera pose beside the road sees the whole zone.
    NoView,
    /// The noise is negative or not finite, or the miss rate is outside 0-1.
    BadSpec,
}

impl fmt::Display for SyntheticError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::UnknownLane(id) => write!(f, "lane {id} is not on the map"),
            Self::BadZone => f.write_str("the zone must end after it starts"),
            Self::OutOfView { index } => write!(f, "control point {index} is out of view"),
            Self::NoPosition { index } => write!(f, "control point {index} has no lat/lon"),
            Self::NoView => f.write_str("no camera pose beside the road sees the whole zone"),
            Self::BadSpec => f.write_str("noise must be 0 or more and the miss rate in 0-1"),
        }
    }
}

impl std::error::Error for SyntheticError {}

/// A pinhole camera over the road plane, in the road's local east/north/up metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PinholeCamera {
    centre: [f64; 3],
    bearing_deg: f64,
    pitch_deg: f64,
    focal_px: f64,
    size: [f64; 2],
    right: [f64; 3],
    down: [f64; 3],
    forward: [f64; 3],
}

impl PinholeCamera {
    /// Focal length of [`PinholeCamera::new`], pixels.
    pub const DEFAULT_FOCAL_PX: f64 = 1400.0;
    /// Image size of [`PinholeCamera::new`], `[width, height]` pixels.
    pub const DEFAULT_SIZE: [f64; 2] = [1920.0, 1080.0];

    /// A camera at `centre` (east, north, up) looking along `bearing_deg` (clockwise from
    /// north), pitched `pitch_deg` down, 1920x1080 with a focal length of 1400 px.
    pub fn new(centre: [f64; 3], bearing_deg: f64, pitch_deg: f64) -> Self {
        let (f, size) = (Self::DEFAULT_FOCAL_PX, Self::DEFAULT_SIZE);
        Self::with_lens(centre, bearing_deg, pitch_deg, f, size)
    }

    /// Like [`PinholeCamera::new`] with the focal length and image size (pixels) given.
    pub fn with_lens(
        centre: [f64; 3],
        bearing_deg: f64,
        pitch_deg: f64,
        focal_px: f64,
        size: [f64; 2],
    ) -> Self {
        let (sb, cb) = bearing_deg.to_radians().sin_cos();
        let (sp, cp) = pitch_deg.to_radians().sin_cos();
        let forward = [cp * sb, cp * cb, -sp];
        let right = [cb, -sb, 0.0];
        Self {
            centre,
            bearing_deg,
            pitch_deg,
            focal_px,
            size,
            right,
            down: cross(forward, right),
            forward,
        }
    }

    /// The camera turned by `roll_deg` about its optical axis (clockwise as seen from
    /// behind it): a pole mount that is not level.
    pub fn with_roll(mut self, roll_deg: f64) -> Self {
        let (s, c) = roll_deg.to_radians().sin_cos();
        let (r, d) = (self.right, self.down);
        self.right = [0, 1, 2].map(|i| c * r[i] + s * d[i]);
        self.down = [0, 1, 2].map(|i| -s * r[i] + c * d[i]);
        self
    }

    /// The optical centre, east/north/up metres.
    pub fn centre(&self) -> [f64; 3] {
        self.centre
    }

    /// Direction of view, degrees clockwise from north.
    pub fn bearing_deg(&self) -> f64 {
        self.bearing_deg
    }

    /// Pitch below the horizon, degrees.
    pub fn pitch_deg(&self) -> f64 {
        self.pitch_deg
    }

    /// Focal length, pixels.
    pub fn focal_px(&self) -> f64 {
        self.focal_px
    }

    /// Image size, `[width, height]` pixels.
    pub fn image_size(&self) -> [f64; 2] {
        self.size
    }

    /// Pixel of a 3-D point (east, north, up), if in front of the camera and inside the image.
    pub fn project3(&self, p: [f64; 3]) -> Option<[f64; 2]> {
        let r = [
            p[0] - self.centre[0],
            p[1] - self.centre[1],
            p[2] - self.centre[2],
        ];
        let z = dot(r, self.forward);
        let f = self.focal_px;
        let px = [
            self.size[0] / 2.0 + f * dot(r, self.right) / z,
            self.size[1] / 2.0 + f * dot(r, self.down) / z,
        ];
        let inside = px[0] >= 0.0 && px[0] < self.size[0] && px[1] >= 0.0 && px[1] < self.size[1];
        (z > 0.0 && inside).then_some(px)
    }

    /// A point (east, north, up) in camera axes: right, down, forward (metres).
    pub fn to_camera(&self, p: [f64; 3]) -> [f64; 3] {
        let r = [
            p[0] - self.centre[0],
            p[1] - self.centre[1],
            p[2] - self.centre[2],
        ];
        [dot(r, self.right), dot(r, self.down), dot(r, self.forward)]
    }

    /// The pixel of a point in camera axes (`forward` > 0), inside the image or not.
    pub fn pixel_of(&self, c: [f64; 3]) -> [f64; 2] {
        let f = self.focal_px;
        [
            self.size[0] / 2.0 + f * c[0] / c[2],
            self.size[1] / 2.0 + f * c[1] / c[2],
        ]
    }

    /// The vanishing point of a direction (east, north, up), homogeneous pixels.
    pub fn vanishing_point(&self, d: [f64; 3]) -> [f64; 3] {
        let f = self.focal_px;
        let (x, y, z) = (dot(d, self.right), dot(d, self.down), dot(d, self.forward));
        [
            f * x + self.size[0] / 2.0 * z,
            f * y + self.size[1] / 2.0 * z,
            z,
        ]
    }

    /// Pixel of a road point (east, north).
    pub fn project(&self, p: [f64; 2]) -> Option<[f64; 2]> {
        self.project3([p[0], p[1], 0.0])
    }

    /// Ground distance from the foot of the camera, metres.
    pub fn distance(&self, p: [f64; 2]) -> f64 {
        dist(p, [self.centre[0], self.centre[1]])
    }

    /// The detector's box of a cone ([`CONE_HEIGHT_M`] high) standing at `base`, its bottom
    /// centre moved by `noise` pixels; `None` when the cone is not in view.
    pub fn cone_box(&self, base: [f64; 2], noise: [f64; 2]) -> Option<BoundingBox> {
        let b = self.project(base)?;
        let top = self.project3([base[0], base[1], CONE_HEIGHT_M])?;
        let (u, v) = (b[0] + noise[0], b[1] + noise[1]);
        let half = CONE_HALF_WIDTH_M * (b[1] - top[1]) / CONE_HEIGHT_M;
        BoundingBox::new(u - half, top[1], u + half, v)
    }
}

impl fmt::Display for PinholeCamera {
    /// "east 358.0 m, north -11.4 m, 8.0 m up, bearing 87.3°, pitched 6.1° down, focal
    /// 4321 px, 1920x1080".
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [e, n, u] = self.centre;
        write!(
            f,
            "east {e:.1} m, north {n:.1} m, {u:.1} m up, bearing {:.1}°, pitched {:.1}° down, focal {:.0} px, {}x{}",
            self.bearing_deg, self.pitch_deg, self.focal_px, self.size[0], self.size[1]
        )
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Gaussian pixel noise: `sigma_px` times a standard normal on each axis.
pub fn pixel_noise(rng: &mut Prng, sigma_px: f64) -> [f64; 2] {
    [sigma_px * rng.normal(), sigma_px * rng.normal()]
}

/// Control points of surveyed road points `ground` (local metres): their pixels with
/// [`pixel_noise`] of `noise_px`, their positions as latitude/longitude of `road`.
pub fn control_points(
    road: &Road,
    camera: &PinholeCamera,
    ground: &[[f64; 2]],
    rng: &mut Prng,
    noise_px: f64,
) -> Result<Vec<Correspondence>, SyntheticError> {
    let point = |(index, g): (usize, &[f64; 2])| {
        let pixel = camera
            .project(*g)
            .ok_or(SyntheticError::OutOfView { index })?;
        let ground = road
            .to_wgs84(*g)
            .ok_or(SyntheticError::NoPosition { index })?;
        let n = pixel_noise(rng, noise_px);
        Ok(Correspondence {
            pixel: [pixel[0] + n[0], pixel[1] + n[1]],
            ground,
        })
    };
    ground.iter().enumerate().map(point).collect()
}

/// `frames` frames (numbered from 0) of detections of the cones in view: each cone is missed
/// with probability `miss_rate`, else its box's bottom centre carries [`pixel_noise`] of
/// `noise_px`. Cones out of view are never detected.
pub fn detect(
    camera: &PinholeCamera,
    cones: &[[f64; 2]],
    frames: usize,
    noise_px: f64,
    miss_rate: f64,
    rng: &mut Prng,
) -> Vec<FrameDetections> {
    let mut frame = |k: usize| {
        let mut detections = Vec::with_capacity(cones.len());
        for cone in cones {
            if rng.next_f64() < miss_rate {
                continue;
            }
            let noise = pixel_noise(rng, noise_px);
            if let Some(bbox) = camera.cone_box(*cone, noise) {
                detections.push(Detection { bbox, score: None });
            }
        }
        FrameDetections {
            frame: k as u64,
            detections,
        }
    };
    (0..frames).map(&mut frame).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projects_like_a_pinhole() {
        // 8 m up at the origin looking east, 45° down: the road point 8 m east is the centre.
        let cam = PinholeCamera::new([0.0, 0.0, 8.0], 90.0, 45.0);
        let c = cam.project([8.0, 0.0]).unwrap();
        assert!((c[0] - 960.0).abs() < 1e-9 && (c[1] - 540.0).abs() < 1e-9);
        // North of the line of sight is left in the image; behind the camera is not seen.
        assert!(cam.project([8.0, 1.0]).unwrap()[0] < 960.0);
        assert_eq!(cam.project([-8.0, 0.0]), None);
        assert_eq!(cam.project([f64::NAN, 0.0]), None);
        let b = cam.cone_box([8.0, 0.0], [0.0, 0.0]).unwrap();
        assert_eq!(b.bottom_centre(), c);
        assert!(b.y_min < b.y_max && b.x_min < b.x_max);
        assert!((cam.distance([8.0, 6.0]) - 10.0).abs() < 1e-12);
    }
}
