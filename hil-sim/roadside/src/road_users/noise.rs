//! How noisy one camera's masks are, learnt from its own fits.
//!
//! A segmentation network's masks stray from the road users' true outlines by an amount
//! that depends on the network, the image and the camera, not on the road user: one
//! camera's masks share it. The box fit ([`super::fit`]) weighs the mask's outline against
//! the size prior by it, so masks twice as noisy as the fit assumes pull the box's sides
//! away from what the prior and the track's belief know, and the position with them. The
//! fit's residual (the root mean square distance of the outline to the fitted box's,
//! [`super::boxes::RoadUserBox::misfit_px`]) measures it: at the assumed noise of 1 px a
//! corner it is [`RMS_AT_ONE_PX`] for a typical mask. [`MaskNoise`] keeps the residuals of
//! a camera's recent fits of road users seen whole (a touching mask or the image border
//! leaves residuals that are not noise) and gives the noise their median stands for.
//!
//! Bounded: a fixed window of the latest fits, no allocation.

use super::localize::Localized;

/// Root mean square distance of a mask's outline to its fitted box's at a mask noise of
/// 1 px a corner, pixels (the fit's residual has fewer degrees of freedom than the
/// outline's vertices, and a vertex's noise is a corner's spread along an edge).
pub const RMS_AT_ONE_PX: f64 = 0.6;
/// The noise assumed before enough fits were seen, pixels.
pub const DEFAULT_PX: f64 = 1.0;
/// Fits a camera needs before its own noise is used.
pub const MIN_FITS: usize = 32;
/// Fits kept: the latest this many (a few seconds of traffic).
pub const WINDOW: usize = 256;
/// The learnt noise is kept within these bounds, pixels: under half a pixel the outline's
/// own rounding dominates, over 4 px no fit stands (a residual over 3 px refuses the box).
pub const RANGE_PX: (f64, f64) = (0.5, 4.0);

/// The mask noise of one camera, from its latest fits' residuals.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaskNoise {
    residuals_px: [f64; WINDOW],
    /// Fits taken (saturating): the next one goes to `taken % WINDOW`.
    taken: usize,
}

impl Default for MaskNoise {
    fn default() -> Self {
        Self::new()
    }
}

impl MaskNoise {
    /// Nothing seen yet: [`DEFAULT_PX`].
    pub const fn new() -> Self {
        Self {
            residuals_px: [0.0; WINDOW],
            taken: 0,
        }
    }

    /// Takes one fit's residual, pixels (ignored unless finite and not negative).
    pub fn take(&mut self, residual_px: f64) {
        if residual_px.is_finite() && residual_px >= 0.0 {
            self.residuals_px[self.taken % WINDOW] = residual_px;
            self.taken = self.taken.saturating_add(1);
        }
    }

    /// Takes the residuals of a frame's road users seen whole (not cut by the image border,
    /// no touching mask).
    pub fn learn(&mut self, found: &[Localized]) {
        for l in found.iter().filter(|l| l.seen_whole()) {
            self.take(l.road_user.misfit_px);
        }
    }

    /// Fits taken so far (saturating).
    pub fn fits(&self) -> usize {
        self.taken
    }

    /// The mask noise, 1-sigma of a corner, pixels: the median residual of the latest fits
    /// over [`RMS_AT_ONE_PX`], within [`RANGE_PX`]; [`DEFAULT_PX`] before [`MIN_FITS`].
    pub fn sigma_px(&self) -> f64 {
        let n = self.taken.min(WINDOW);
        if n < MIN_FITS {
            return DEFAULT_PX;
        }
        let mut window = self.residuals_px;
        let kept = &mut window[..n];
        kept.sort_unstable_by(f64::total_cmp);
        let median = if n % 2 == 1 {
            kept[n / 2]
        } else {
            0.5 * (kept[n / 2 - 1] + kept[n / 2])
        };
        (median / RMS_AT_ONE_PX).clamp(RANGE_PX.0, RANGE_PX.1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_stands_until_enough_fits_are_seen() {
        let mut n = MaskNoise::new();
        for _ in 0..MIN_FITS - 1 {
            n.take(1.8);
        }
        assert_eq!(n.sigma_px(), DEFAULT_PX);
        n.take(1.8);
        assert!((n.sigma_px() - 3.0).abs() < 1e-12, "{}", n.sigma_px());
    }

    #[test]
    fn the_median_of_the_latest_window_decides_and_outliers_do_not() {
        let mut n = MaskNoise::new();
        // An old, clean stretch is forgotten once a window of noisier fits follows.
        for _ in 0..WINDOW {
            n.take(0.6);
        }
        assert!((n.sigma_px() - 1.0).abs() < 1e-12);
        for k in 0..WINDOW {
            // A tenth of the fits are wrong local solutions far off.
            n.take(if k % 10 == 0 { 50.0 } else { 1.2 });
        }
        assert!((n.sigma_px() - 2.0).abs() < 1e-12, "{}", n.sigma_px());
    }

    #[test]
    fn hostile_residuals_are_ignored_and_the_noise_stays_in_range() {
        let mut n = MaskNoise::new();
        for v in [f64::NAN, f64::INFINITY, -1.0] {
            n.take(v);
        }
        assert_eq!(n.fits(), 0);
        for _ in 0..MIN_FITS {
            n.take(0.0);
        }
        assert_eq!(n.sigma_px(), RANGE_PX.0);
        for _ in 0..WINDOW {
            n.take(1e300);
        }
        assert_eq!(n.sigma_px(), RANGE_PX.1);
    }
}
