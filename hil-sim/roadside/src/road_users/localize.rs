//! One camera's road users in a frame: each detection's box and position, or the reason it
//! has none.
//!
//! A detection is refused when its mask is cut by the image border, or touches the mask of a
//! road user standing nearer the camera (a cut mask gives a wrong box).
//!
//! **Position.** The paper takes the centre of the constructed footprint. Its length comes
//! from where a vertical tangent meets the near long bottom edge: seen along the road from a
//! pole beside it, that ray runs almost parallel to the edge, and one pixel moves the far
//! corner by tens of centimetres at 40 m (a pedestrian's 0.35 m "length" came out 0.16-0.86
//! m). So the length and width are each fused with the class's typical size by inverse
//! variance (the measurement's variance from how far the corner moves for one pixel, the
//! prior's from [`PRIOR_SHARE`] of the typical size), and the position is B1 plus half of each
//! along its edge: a bus keeps its measured length, a pedestrian's comes mostly from the
//! prior. Each position carries its 1-sigma error.

use super::boxes::{construct, BoxRejection, RoadUserBox};
use super::calibrate::{GroundCamera, GroundCameraFault, SceneCalibration, VanishingPoints};
use super::detections::Silhouette;
use super::polygon::{in_front, near_or_overlapping};
use super::tracker::Observation;

/// Masks nearer than this (pixels) count as touching.
const TOUCH_PX: f64 = 2.0;
/// Mask noise assumed for the position error, pixels.
const MASK_SIGMA_PX: f64 = 1.0;
/// Error floor of a position, metres (the box model of a non-box road user).
const SIGMA_FLOOR_M: f64 = 0.05;
/// 1-sigma spread of a class's sizes, as a share of its typical size (cars run 3.6-5.2 m).
pub const PRIOR_SHARE: f64 = 0.12;

/// A localized road user.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Localized {
    /// Index of the detection in the frame's list.
    pub index: usize,
    /// Its box.
    pub road_user: RoadUserBox,
    /// Its position on the road, local metres (see the module's documentation).
    pub position: [f64; 2],
    /// 1-sigma error of the position, metres.
    pub sigma_m: f64,
}

impl Localized {
    /// The tracker's observation of it.
    pub fn observation(&self) -> Observation {
        Observation {
            class: self.road_user.class,
            position: self.position,
            sigma_m: self.sigma_m,
        }
    }
}

/// Detections without a box, by reason.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Rejections {
    /// Cut by the image border.
    pub truncated: u32,
    /// Touching a nearer road user.
    pub occluded: u32,
    /// A vanishing point inside the mask, or tangents that do not meet.
    pub degenerate: u32,
    /// Seen side-on.
    pub side_on: u32,
    /// Implausible size for the class.
    pub implausible: u32,
    /// The box does not cover its mask.
    pub inconsistent: u32,
}

impl Rejections {
    /// Counts one rejection.
    pub fn count(&mut self, r: BoxRejection) {
        let slot = match r {
            BoxRejection::Truncated => &mut self.truncated,
            BoxRejection::Occluded => &mut self.occluded,
            BoxRejection::SideOn => &mut self.side_on,
            BoxRejection::Implausible => &mut self.implausible,
            BoxRejection::Inconsistent { .. } => &mut self.inconsistent,
            _ => &mut self.degenerate,
        };
        *slot += 1;
    }

    /// Adds another count.
    pub fn add(&mut self, o: &Self) {
        self.truncated += o.truncated;
        self.occluded += o.occluded;
        self.degenerate += o.degenerate;
        self.side_on += o.side_on;
        self.implausible += o.implausible;
        self.inconsistent += o.inconsistent;
    }

    /// All rejections.
    pub fn total(&self) -> u32 {
        self.truncated
            + self.occluded
            + self.degenerate
            + self.side_on
            + self.implausible
            + self.inconsistent
    }
}

/// One camera's localizer: its vanishing points and its projection.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Localizer {
    points: VanishingPoints,
    camera: GroundCamera,
}

impl Localizer {
    /// From the camera's vanishing-point calibration and its reference-point homography
    /// (image to local metres, row-major).
    pub fn new(
        cal: &SceneCalibration,
        to_ground: [[f64; 3]; 3],
    ) -> Result<Self, GroundCameraFault> {
        let camera = GroundCamera::new(to_ground, cal.focal_px, cal.principal)?;
        Ok(Self {
            points: cal.points,
            camera,
        })
    }

    /// The camera's projection.
    pub fn camera(&self) -> &GroundCamera {
        &self.camera
    }

    /// The vanishing points.
    pub fn points(&self) -> &VanishingPoints {
        &self.points
    }

    /// The boxes of a frame's detections, and the rejections.
    ///
    /// Of two touching masks, one that may stand behind the other is refused as occluded:
    /// it is behind when a line separates their footprints with the camera on the other's
    /// side (a mask without a box stands where its lowest point meets the road), and may be
    /// when that is not known.
    pub fn frame(&self, detections: &[Silhouette]) -> (Vec<Localized>, Rejections) {
        let built: Vec<Result<RoadUserBox, BoxRejection>> =
            detections.iter().map(|d| self.one(d)).collect();
        // Without the camera's foot (a vertical point at infinity) no order is known: every
        // touching mask may be hidden.
        let foot = self.camera.foot();
        // May detection `j` hide detection `i`? Not when a line between their footprints
        // leaves `j` behind. A detection without a box stands where the lowest point of its
        // mask meets the road. When that is not known, it may.
        let ground_spot = |j: usize| {
            let low = detections[j]
                .hull
                .iter()
                .copied()
                .max_by(|a, b| a[1].total_cmp(&b[1]))?;
            let p = self.camera.to_ground(low)?;
            let r = 0.05;
            Some([
                [p[0] - r, p[1] - r],
                [p[0] + r, p[1] - r],
                [p[0] + r, p[1] + r],
                [p[0] - r, p[1] + r],
            ])
        };
        let before = |j: usize, i: usize| match (&built[j], &built[i]) {
            (Ok(a), Ok(b)) => foot
                .and_then(|f| in_front(&a.footprint, &b.footprint, f))
                .unwrap_or(true),
            (Err(_), Ok(b)) => ground_spot(j)
                .zip(foot)
                .and_then(|(spot, f)| in_front(&b.footprint, &spot, f))
                .is_none_or(|b_in_front| !b_in_front),
            _ => true,
        };
        let mut rejected = Rejections::default();
        let mut boxes = Vec::with_capacity(detections.len());
        for (index, b) in built.iter().enumerate() {
            let hidden = detections.iter().enumerate().any(|(j, o)| {
                j != index
                    && near_or_overlapping(&detections[index].hull, &o.hull, TOUCH_PX)
                    && before(j, index)
            });
            match b {
                _ if hidden => rejected.count(BoxRejection::Occluded),
                Err(r) => rejected.count(*r),
                Ok(b) => {
                    let (position, sigma_m) = self.position(b);
                    boxes.push(Localized {
                        index,
                        road_user: *b,
                        position,
                        sigma_m,
                    });
                }
            }
        }
        (boxes, rejected)
    }

    fn one(&self, d: &Silhouette) -> Result<RoadUserBox, BoxRejection> {
        if d.touches_border {
            return Err(BoxRejection::Truncated);
        }
        if d.parts > 1 {
            return Err(BoxRejection::Occluded);
        }
        construct(d.class, &d.hull, &self.points, &self.camera)
    }

    /// The position (B1 plus half the fused length and width) and its 1-sigma error.
    fn position(&self, b: &RoadUserBox) -> ([f64; 2], f64) {
        let typical = b.class.typical();
        let [b1, b2, _, b4] = b.footprint;
        let (length, sl) = fuse(b.length_m(), b.length_per_px_m, typical.length_m);
        let (width, sw) = fuse(b.width_m(), b.width_per_px_m, typical.width_m);
        let unit = |a: [f64; 2], c: [f64; 2]| {
            let d = (c[0] - a[0]).hypot(c[1] - a[1]);
            [(c[0] - a[0]) / d, (c[1] - a[1]) / d]
        };
        let (ul, uw) = (unit(b1, b2), unit(b1, b4));
        let position = [
            b1[0] + (ul[0] * length + uw[0] * width) / 2.0,
            b1[1] + (ul[1] * length + uw[1] * width) / 2.0,
        ];
        let near = self.pixel_size_m(b.vertices_px[0]) * MASK_SIGMA_PX;
        let sigma =
            (near * near + sl * sl / 4.0 + sw * sw / 4.0 + SIGMA_FLOOR_M * SIGMA_FLOOR_M).sqrt();
        (position, sigma)
    }

    /// Ground size of a pixel at `px` (the larger of its two sides), metres.
    fn pixel_size_m(&self, px: [f64; 2]) -> f64 {
        let step = [[px[0], px[1] + 1.0], [px[0] + 1.0, px[1]]];
        let base = self.camera.to_ground(px);
        step.iter()
            .filter_map(|q| Some((base?, self.camera.to_ground(*q)?)))
            .map(|(a, c)| (a[0] - c[0]).hypot(a[1] - c[1]))
            .fold(0.0, f64::max)
    }
}

/// A size measured with `per_px_m` metres of error per pixel, fused with the class's
/// `typical` size (1-sigma [`PRIOR_SHARE`] of it): the fused size and its 1-sigma error.
fn fuse(measured: f64, per_px_m: f64, typical: f64) -> (f64, f64) {
    let vm = (per_px_m * MASK_SIGMA_PX).max(0.01).powi(2);
    let vp = (PRIOR_SHARE * typical).powi(2);
    if !vm.is_finite() {
        return (typical, vp.sqrt());
    }
    let v = 1.0 / (1.0 / vm + 1.0 / vp);
    ((measured / vm + typical / vp) * v, v.sqrt())
}
