//! One camera's road users in a frame: each detection's box and position, or the reason it
//! has none.
//!
//! Each detection's box is fitted to its mask ([`super::fit`]): the position, length, width
//! and height whose projected box matches the mask's outline, a size prior deciding only
//! what the view does not measure (the length of a vehicle seen end-on, the depth of a
//! pedestrian walking along the line of sight). That prior is its track's size belief where
//! the caller has tracks ([`Localizer::frame_with`], [`super::size`]): what earlier frames
//! measured of the same road user, from views that showed it. Otherwise it is the class's.
//! Masks it touches and the image
//! border may hide part of it: the fit ignores box corners there, so a partly hidden road
//! user is localized from what is seen, with the larger error that leaves. Each position
//! carries its 1-sigma error from the fit's covariance.

use super::boxes::{construct, BoxRejection, RoadUserBox, MIN_IOU};
use super::calibrate::{GroundCamera, GroundCameraFault, SceneCalibration, VanishingPoints};
use super::detections::Silhouette;
use super::fit::{fit, BoxFit, FitFailure, FitInput};
use super::homog::apply_direction;
use super::noise::{MaskNoise, RMS_AT_ONE_PX};
use super::polygon::{convex_hull, iou, near_or_overlapping, signed_distance_convex};
use super::size::{ClassPriors, Lent, SizeBelief, SizeEvidence, SizeHints};
use super::tracker::Observation;
use crate::ellipse::{floored, worst_sigma, Cov2};

/// Masks nearer than this (pixels) count as touching.
const TOUCH_PX: f64 = 2.0;
/// An outline point this far (pixels) inside another mask's hull lies where that road user
/// would be seen were nothing in front of it: well beyond mask noise and the hull's rounding.
const CARVED_PX: f64 = 4.0;
/// Error floor of a position, metres (the calibration's and the box model's).
const SIGMA_FLOOR_M: f64 = 0.03;
/// A position less certain than this (1-sigma, metres) is not reported.
pub const MAX_SIGMA_M: f64 = 1.0;
/// Largest root mean square distance of the mask's outline to the fitted box's, pixels.
const MAX_RMS_PX: f64 = 3.0;
/// A road user cut by the image border is localized only when its box's outline overlaps
/// its mask at least this much (intersection over union; for a box that fits, the share of
/// it in view).
pub const MIN_SEEN_SHARE: f64 = 0.25;
/// Smallest side of a box, as a share of its class's mean.
const MIN_SHARE: f64 = 0.3;

/// A localized road user.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Localized {
    /// Index of the detection in the frame's list.
    pub index: usize,
    /// Its box.
    pub road_user: RoadUserBox,
    /// Its position on the road, local metres (see the module's documentation).
    pub position: [f64; 2],
    /// 1-sigma error of the position along its worst direction, metres.
    pub sigma_m: f64,
    /// Covariance of the position (east, north), m²: the fit's, scaled by its misfit, never
    /// better than the hidden corners allow, with the calibration's added; mostly along the
    /// line of sight, where a box's depth trades against its size (`sigma_m` is its worst
    /// direction).
    pub covariance_m2: Cov2,
    /// The part of `covariance_m2` that repeats from frame to frame, m²: the calibration's
    /// (in every direction), the size prior's share (the same in every frame; mostly along
    /// the line of sight) and, for a road user cut by the image border, the prior standing
    /// for the end out of view.
    pub floor_covariance_m2: Cov2,
    /// What its mask says of its size, for its track's belief: of every road user not cut
    /// by the image border (the fit's information leaves out what a touching mask may
    /// hide, and a cut end would repeat the same wrong length frame after frame).
    pub size_evidence: Option<SizeEvidence>,
    /// Its mask touches the image border.
    pub road_user_at_border: bool,
    /// Its mask touches another that may hide part of it.
    pub road_user_touching: bool,
    /// The road's direction on the road (unit, east/north): its box's length.
    pub road_axis: [f64; 2],
}

impl Localized {
    /// Seen whole: neither cut by the image border nor touching a mask that may hide part
    /// of it.
    pub fn seen_whole(&self) -> bool {
        !self.road_user_at_border && !self.road_user_touching
    }

    /// The tracker's observation of it.
    pub fn observation(&self) -> Observation {
        Observation {
            class: self.road_user.class,
            position: self.position,
            covariance_m2: self.covariance_m2,
            floor_m2: self.floor_covariance_m2,
            size: self.size_evidence,
            at_border: self.road_user_at_border,
            road_axis: Some(self.road_axis),
        }
    }
}

/// Where a detection's fit starts, and the size belief lent to it there.
type Start = (Result<[f64; 2], BoxRejection>, Option<Lent>);

/// A fitted detection before it becomes a [`Localized`].
struct Placed {
    road_user: RoadUserBox,
    position: [f64; 2],
    covariance_m2: Cov2,
    floor_covariance_m2: Cov2,
    size_evidence: Option<SizeEvidence>,
}

/// Detections without a box, by reason.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Rejections {
    /// Cut by the image border, and too little seen to be placed within [`MAX_SIGMA_M`], or
    /// less than a quarter of its box in view ([`MIN_SEEN_SHARE`]).
    pub truncated: u32,
    /// Touching another road user's mask, and too little seen to be placed within
    /// [`MAX_SIGMA_M`].
    pub occluded: u32,
    /// No box could be fitted: fewer than three hull points, a box leaving the camera's
    /// field, nothing measured, no camera foot.
    pub degenerate: u32,
    /// Seen side-on (kept for callers counting the tangent construction's refusals; the
    /// fitted box is never refused for it).
    pub side_on: u32,
    /// Implausible size for the class.
    pub implausible: u32,
    /// The box's outline misses its mask's (more than 3 px root mean square apart, or, with
    /// nothing hiding it, covering it at an IoU under [`MIN_IOU`]).
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

/// One camera's localizer: its vanishing points, its projection, and the noise of its
/// masks as learnt from its fits ([`Localizer::learn`]). Not `Copy`: what it learnt belongs
/// to one camera's run, and a copy learns apart from it.
#[derive(Debug, Clone, PartialEq)]
pub struct Localizer {
    points: VanishingPoints,
    camera: GroundCamera,
    /// The road's direction on the road (unit, east/north).
    axis: [f64; 2],
    /// `[width, height]` of the camera's image, pixels.
    image_size: [f64; 2],
    /// Its masks' noise.
    noise: MaskNoise,
}

impl Localizer {
    /// From the camera's vanishing-point calibration and its reference-point homography
    /// (image to local metres, row-major).
    pub fn new(
        cal: &SceneCalibration,
        to_ground: [[f64; 3]; 3],
    ) -> Result<Self, GroundCameraFault> {
        let camera = GroundCamera::new(to_ground, cal.focal_px, cal.principal)?;
        let axis =
            apply_direction(&to_ground, cal.points.road).ok_or(GroundCameraFault::Singular)?;
        Ok(Self {
            points: cal.points,
            camera,
            axis,
            image_size: cal.principal.point.map(|v| 2.0 * v),
            noise: MaskNoise::new(),
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

    /// What it learnt of its masks' noise.
    pub fn mask_noise(&self) -> &MaskNoise {
        &self.noise
    }

    /// Learns its masks' noise from a frame's road users ([`super::noise`]): the next
    /// frames' fits weigh the masks' outlines by it. A caller running a camera over a video
    /// passes each frame's road users here.
    pub fn learn(&mut self, found: &[Localized]) {
        let whole = found.iter().filter(|l| l.seen_whole());
        self.noise.take(whole.map(|l| l.road_user.misfit_px));
    }

    /// The boxes of a frame's detections, and the rejections.
    ///
    /// Each detection's box is fitted to its mask ([`fit`]); the masks it touches and the
    /// image border may hide part of it, so box corners there are not checked against its
    /// mask. A touching mask whose outline goes around part of this one's stands behind it
    /// and hides nothing of it (a worker in front of a truck). A detection is refused when
    /// the fit fails, when the box is implausible for its class, when it does not match its
    /// mask, when so little of it is seen that its position is not known within
    /// [`MAX_SIGMA_M`] (then as occluded or truncated), or when it is cut by the image border
    /// with less than a quarter of its box in view ([`MIN_SEEN_SHARE`], as truncated, whether
    /// or not a neighbour hides part of it too).
    pub fn frame(&self, detections: &[Silhouette]) -> (Vec<Localized>, Rejections) {
        self.frame_with(detections, &ClassPriors)
    }

    /// [`Localizer::frame`] with the sizes the tracks know: each detection's fit takes as
    /// its size prior the belief `sizes` gives for where it starts (unless the same track
    /// gives it to another detection of the frame too), or its class's prior.
    pub fn frame_with(
        &self,
        detections: &[Silhouette],
        sizes: &dyn SizeHints,
    ) -> (Vec<Localized>, Rejections) {
        let mut rejected = Rejections::default();
        let mut boxes = Vec::with_capacity(detections.len());
        let touching: Vec<Vec<&[[f64; 2]]>> = (0..detections.len())
            .map(|index| {
                let d = &detections[index];
                detections
                    .iter()
                    .enumerate()
                    .filter(|(j, o)| *j != index && may_hide(&o.hull, &d.hull))
                    .map(|(_, o)| o.hull.as_slice())
                    .collect()
            })
            .collect();
        // Where each fit starts, and the size belief a track lends there.
        let starts: Vec<Option<Start>> = detections
            .iter()
            .zip(&touching)
            .map(|(d, t)| {
                (d.hull.len() >= 3).then(|| {
                    let first = self.start_of(d, t);
                    let lent = first.as_ref().ok().and_then(|&at| sizes.near(d.class, at));
                    (first, lent)
                })
            })
            .collect();
        // A track's belief goes to one detection: lent to two, which one is its road user
        // is not known, and neither takes it.
        let lenders: Vec<u32> = starts
            .iter()
            .flatten()
            .filter_map(|(_, lent)| lent.map(|l| l.lender))
            .collect();
        let shared = |id: u32| lenders.iter().filter(|l| **l == id).count() > 1;
        for (index, (d, start)) in detections.iter().zip(&starts).enumerate() {
            let placed = match start {
                None => Err(BoxRejection::TooFewPoints),
                Some((first, lent)) => {
                    let belief = lent.filter(|l| !shared(l.lender)).map(|l| l.belief);
                    self.one(d, &touching[index], *first, belief)
                }
            };
            match placed {
                Ok(p) => boxes.push(Localized {
                    index,
                    road_user: p.road_user,
                    position: p.position,
                    sigma_m: worst_sigma(&p.covariance_m2),
                    covariance_m2: p.covariance_m2,
                    floor_covariance_m2: p.floor_covariance_m2,
                    size_evidence: p.size_evidence,
                    road_user_at_border: d.touches_border,
                    road_user_touching: !touching[index].is_empty(),
                    road_axis: self.axis,
                }),
                Err(r) => rejected.count(r),
            }
        }
        (boxes, rejected)
    }

    /// One detection's box from `first` with the size belief its track lends (or its
    /// class's prior). A box fitted with its track's belief that is refused for any reason
    /// but too few points is fitted again with its class's prior: the track may have taken
    /// its size from a wrong frame, and the mask comes first.
    fn one(
        &self,
        d: &Silhouette,
        touching: &[&[[f64; 2]]],
        first: Result<[f64; 2], BoxRejection>,
        belief: Option<SizeBelief>,
    ) -> Result<Placed, BoxRejection> {
        let prior = SizeBelief::prior(d.class);
        match (
            self.placed(d, touching, first, belief.unwrap_or(prior)),
            belief,
        ) {
            (Err(e), Some(_)) if e != BoxRejection::TooFewPoints => {
                self.placed(d, touching, first, prior)
            }
            (placed, _) => placed,
        }
    }

    /// Where a detection's fit starts: the centre of its tangent construction where that
    /// works (next to the fit's solution), or the centre from its lowest point
    /// ([`Localizer::start`]).
    fn start_of(&self, d: &Silhouette, touching: &[&[[f64; 2]]]) -> Result<[f64; 2], BoxRejection> {
        touching
            .is_empty()
            .then(|| construct(d.class, &d.hull, &self.points, &self.camera).ok())
            .flatten()
            .map(|b| b.centre)
            .filter(|c| c.iter().all(|v| v.is_finite()))
            .map_or_else(|| self.start(d, false), Ok)
    }

    /// A detection's box fitted from `first` (and, where its foot may be hidden, from its
    /// top) with the size prior `belief`.
    fn placed(
        &self,
        d: &Silhouette,
        touching: &[&[[f64; 2]]],
        first: Result<[f64; 2], BoxRejection>,
        belief: SizeBelief,
    ) -> Result<Placed, BoxRejection> {
        // A mask whose foot may be hidden is also fitted from its top: the highest point
        // taken at the class's mean height. The better fit is kept.
        let noise_px = self.noise.sigma_px();
        let mut starts = vec![first];
        if self.foot_may_be_hidden(d, touching) {
            starts.push(self.start(d, true));
        }
        let mut best: Result<BoxFit, BoxRejection> = Err(BoxRejection::NoIntersection);
        for start in starts {
            let input = FitInput {
                class: d.class,
                hull: &d.hull,
                touching,
                image_size: self.image_size,
                axis: self.axis,
                size: belief,
                outline_sigma_px: noise_px,
                start: match start {
                    Ok(s) => s,
                    Err(e) => {
                        best = best.or(Err(e));
                        continue;
                    }
                },
            };
            let fitted = fit(input, &self.camera).map_err(|f| match f {
                FitFailure::TooFewPoints => BoxRejection::TooFewPoints,
                FitFailure::OffCamera | FitFailure::Singular => BoxRejection::NoIntersection,
            });
            best = match (best, fitted) {
                (Ok(b), Ok(f)) => Ok(if f.cost < b.cost { f } else { b }),
                (Err(_), f) => f,
                (b, Err(_)) => b,
            };
        }
        // A box the mask does not pin down (a sliver beside a nearer road user) is hidden.
        let fitted = best.map_err(|e| match e {
            BoxRejection::NoIntersection if !touching.is_empty() => BoxRejection::Occluded,
            BoxRejection::NoIntersection if d.touches_border => BoxRejection::Truncated,
            e => e,
        })?;
        let e = fitted.extent;
        let (prior, largest) = (d.class.size_prior(), d.class.largest());
        let plausible = |v: f64, mean: f64, hi: f64| (MIN_SHARE * mean..=hi).contains(&v);
        if !(plausible(e.length_m, prior.mean.length_m, largest.length_m)
            && plausible(e.width_m, prior.mean.width_m, largest.width_m)
            && plausible(e.height_m, prior.mean.height_m, largest.height_m))
        {
            return Err(BoxRejection::Implausible);
        }
        let road_user = self.box_of(d, &fitted);
        // The whole box covers a partly hidden mask only in part.
        let whole = touching.is_empty() && !d.touches_border;
        if fitted.rms_px > MAX_RMS_PX || (whole && road_user.iou < MIN_IOU) {
            return Err(BoxRejection::Inconsistent { iou: road_user.iou });
        }
        // Cut by the image border with less than a quarter of its box in view: what is seen
        // may be any part of the road user, and the fit's curvature does not say so (a 5 px
        // sliver of a pedestrian at the border was placed metres off with 13 cm of sigma).
        if d.touches_border && road_user.iou < MIN_SEEN_SHARE {
            return Err(BoxRejection::Truncated);
        }
        // A mask that fits its box worse than its camera's mask noise explains is less
        // certain than the fit's curvature says (a noisier mask, or a wrong local solution):
        // scaled by it.
        let misfit = (fitted.rms_px / (RMS_AT_ONE_PX * noise_px)).max(1.0);
        // Where some corners may be hidden (a touching mask, the border), the box may go on
        // behind them: its centre is known no better than half the spread of the sizes it
        // may have (its track's belief, or its class's), whatever the visible part says.
        let hidden_floor = if fitted.corners_seen < 8 {
            let [l, w, _] = belief.sigma();
            0.5 * l.max(w)
        } else {
            0.0
        };
        // The fit's covariance scaled by the misfit, never better than the hidden floor in
        // any direction, and the calibration's error added in every direction.
        let scaled = fitted
            .covariance
            .map(|row| row.map(|v| v * misfit * misfit));
        let mut covariance_m2 = floored(&scaled, hidden_floor);
        covariance_m2[0][0] += SIGMA_FLOOR_M * SIGMA_FLOOR_M;
        covariance_m2[1][1] += SIGMA_FLOOR_M * SIGMA_FLOOR_M;
        let sigma_m = worst_sigma(&covariance_m2);
        if sigma_m > MAX_SIGMA_M || !sigma_m.is_finite() {
            return Err(if !touching.is_empty() {
                BoxRejection::Occluded
            } else if d.touches_border {
                BoxRejection::Truncated
            } else {
                BoxRejection::NoIntersection
            });
        }
        // Errors that repeat from frame to frame, which no track averages away: the
        // calibration's; the size prior's share of the position's error (the same prior, or
        // the same track's belief, stands in every frame); and, cut by the image
        // border, the same end stays out of view frame after frame, so the prior's share of
        // the error repeats (behind a neighbour, what is hidden changes as traffic moves).
        let border = if d.touches_border { hidden_floor } else { 0.0 };
        let repeated = floored(&fitted.size_covariance, border.max(SIGMA_FLOOR_M));
        let uncut = !d.touches_border;
        Ok(Placed {
            road_user,
            position: fitted.centre,
            covariance_m2,
            floor_covariance_m2: repeated,
            // A mask that fits worse than noise explains says less, as its position does.
            size_evidence: fitted
                .size_evidence
                .filter(|_| uncut)
                .map(|e| e.scaled(1.0 / (misfit * misfit))),
        })
    }

    /// Does the mask's lowest point lie along a touching mask or the image's bottom (so the
    /// road user's foot may be hidden there)?
    fn foot_may_be_hidden(&self, d: &Silhouette, touching: &[&[[f64; 2]]]) -> bool {
        let Some(low) = d.hull.iter().copied().max_by(|a, b| a[1].total_cmp(&b[1])) else {
            return false;
        };
        low[1] >= self.image_size[1] - 2.0 * TOUCH_PX
            || touching
                .iter()
                .any(|o| signed_distance_convex(low, o) < 2.0 * TOUCH_PX)
    }

    /// Where the fit starts: the mask's lowest point on the road taken as the footprint's
    /// corner nearest the camera (or, `from_top`, its highest point at the class's mean
    /// height taken as the top corner farthest from it), the centre half the class's mean
    /// length and width beyond (or before) it.
    fn start(&self, d: &Silhouette, from_top: bool) -> Result<[f64; 2], BoxRejection> {
        let m = d.class.size_prior().mean;
        let by_y = |a: &&[f64; 2], b: &&[f64; 2]| a[1].total_cmp(&b[1]);
        let (px, z, towards) = if from_top {
            (d.hull.iter().min_by(by_y), m.height_m, -1.0)
        } else {
            (d.hull.iter().max_by(by_y), 0.0, 1.0)
        };
        let px = *px.ok_or(BoxRejection::TooFewPoints)?;
        let g = self
            .camera
            .to_plane(px, z)
            .ok_or(BoxRejection::NoIntersection)?;
        let foot = self.camera.foot().ok_or(BoxRejection::NoCameraFoot)?;
        let [ux, uy] = self.axis;
        let (vx, vy) = (-uy, ux);
        let away =
            |sx: f64, sy: f64| towards * ((g[0] - foot[0]) * sx + (g[1] - foot[1]) * sy).signum();
        let (a, b) = (
            away(ux, uy) * m.length_m / 2.0,
            away(vx, vy) * m.width_m / 2.0,
        );
        Ok([g[0] + a * ux + b * vx, g[1] + a * uy + b * vy])
    }

    /// The fitted box as a [`RoadUserBox`]: B1 the footprint corner nearest the camera's
    /// foot, B2 along the road from it, B4 across.
    fn box_of(&self, d: &Silhouette, f: &BoxFit) -> RoadUserBox {
        let [ux, uy] = self.axis;
        let (vx, vy) = (-uy, ux);
        let (hl, hw) = (f.extent.length_m / 2.0, f.extent.width_m / 2.0);
        let [cx, cy] = f.centre;
        let corner = |a: f64, b: f64| {
            [
                cx + a * hl * ux + b * hw * vx,
                cy + a * hl * uy + b * hw * vy,
            ]
        };
        let foot = self.camera.foot().unwrap_or(f.centre);
        let toward = |sx: f64, sy: f64| {
            if (foot[0] - cx) * sx + (foot[1] - cy) * sy >= 0.0 {
                1.0
            } else {
                -1.0
            }
        };
        let (a, b) = (toward(ux, uy), toward(vx, vy));
        let footprint = [corner(a, b), corner(-a, b), corner(-a, -b), corner(a, -b)];
        let mut vertices_px = [[f64::NAN; 2]; 8];
        for (i, p) in footprint.iter().enumerate() {
            for (k, z) in [0.0, f.extent.height_m].into_iter().enumerate() {
                if let Some(px) = self.camera.project([p[0], p[1], z]) {
                    vertices_px[i + 4 * k] = px;
                }
            }
        }
        let outline = convex_hull(&vertices_px);
        RoadUserBox {
            class: d.class,
            footprint,
            height_m: f.extent.height_m,
            centre: f.centre,
            length_per_px_m: 0.0,
            width_per_px_m: 0.0,
            vertices_px,
            iou: iou(&outline, &d.hull),
            misfit_px: f.rms_px,
        }
    }
}

/// May the mask with hull `other` hide part of the road user whose mask has hull `own`?
/// Only if the two touch, and unless `own` was carved out of `other`'s silhouette: masks
/// share no pixel, so where `own`'s outline lies well inside `other`'s hull, `other` is seen
/// around it and stands behind it (a worker in front of a truck), unless `other`'s outline
/// also lies well inside `own`'s (each partly in front: either may hide the other).
fn may_hide(other: &[[f64; 2]], own: &[[f64; 2]]) -> bool {
    let carved = |a: &[[f64; 2]], b: &[[f64; 2]]| {
        a.iter().any(|p| signed_distance_convex(*p, b) < -CARVED_PX)
    };
    // Touching first: most pairs of masks are apart, and that test is the cheap one.
    near_or_overlapping(own, other, TOUCH_PX) && (carved(other, own) || !carved(own, other))
}

#[cfg(test)]
mod tests {
    use super::may_hide;

    fn square(x: f64, y: f64, side: f64) -> Vec<[f64; 2]> {
        vec![[x, y], [x + side, y], [x + side, y + side], [x, y + side]]
    }

    #[test]
    fn only_a_mask_in_front_may_hide() {
        let truck = square(0.0, 0.0, 100.0);
        // Beside it, touching: either may stand in front.
        assert!(may_hide(&truck, &square(100.5, 40.0, 20.0)));
        // Apart: neither hides the other.
        assert!(!may_hide(&truck, &square(110.0, 40.0, 20.0)));
        // Carved out of its outline: the worker stands in front of it.
        let worker = square(40.0, 60.0, 20.0);
        assert!(!may_hide(&truck, &worker));
        // Overlapping the edge by less than mask noise: still touching.
        assert!(may_hide(&truck, &square(97.0, 40.0, 20.0)));
        // Each with a corner well inside the other's outline: either may hide the other.
        let across = square(50.0, 50.0, 100.0);
        assert!(may_hide(&truck, &across));
        assert!(may_hide(&across, &truck));
    }
}
