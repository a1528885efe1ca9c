//! How noisy one camera's masks are, learnt from its own fits.
//!
//! A segmentation network's masks stray from the road users' true outlines by an amount
//! that depends on the network, the image and the camera, not on the road user: one
//! camera's masks share it. The box fit ([`super::fit`]) weighs the mask's outline against
//! the size prior by it, so masks twice as noisy as the fit assumes pull the box's sides
//! away from what the prior and the track's belief know, and the position with them. The
//! fit's residual (the root mean square distance of the outline to the fitted box's,
//! [`super::boxes::RoadUserBox::misfit_px`]) measures it: at a noise of 1 px a corner it is
//! [`RMS_AT_ONE_PX`] for a typical mask. [`MaskNoise`] keeps the residuals of a camera's
//! latest fits of road users seen whole (a touching mask or the image border leaves
//! residuals that are not noise; the localizer picks them, [`super::localize::Localizer::learn`])
//! and gives the noise their median stands for.
//!
//! Bounded: a fixed window of the latest fits, no allocation.

/// Root mean square distance of a mask's outline to its fitted box's at a mask noise of
/// 1 px a corner, pixels (the fit's residual has fewer degrees of freedom than the
/// outline's vertices, and a vertex's noise is a corner's spread along an edge).
pub const RMS_AT_ONE_PX: f64 = 0.6;
/// The noise assumed before enough fits were seen, pixels.
pub const DEFAULT_PX: f64 = 1.0;
/// Fits a camera needs before its own noise is used.
pub const MIN_FITS: usize = 32;
/// Fits kept: the latest this many (seconds of dense traffic, minutes of light traffic).
pub const WINDOW: usize = 256;
/// The learnt noise is kept within these bounds, pixels: under half a pixel the outline's
/// own rounding to pixels dominates; at 4 px the median residual (2.4 px) nears the 3 px at
/// which a box is refused as not matching its mask, so the fits that would say more are
/// not there to learn from.
pub const RANGE_PX: (f64, f64) = (0.5, 4.0);

/// The mask noise of one camera, from its latest fits' residuals.
#[derive(Debug, Clone, PartialEq)]
pub struct MaskNoise {
    residuals_px: [f64; WINDOW],
    /// Where the next residual goes.
    next: usize,
    /// Slots in use (at most [`WINDOW`]).
    filled: usize,
    /// Residuals taken (saturating; a count only).
    taken: u64,
    /// The noise the window stands for, pixels (kept with the window).
    sigma_px: f64,
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
            next: 0,
            filled: 0,
            taken: 0,
            sigma_px: DEFAULT_PX,
        }
    }

    /// Takes fits' residuals, pixels (each ignored unless finite and not negative), and
    /// updates the noise.
    pub fn take(&mut self, residuals_px: impl IntoIterator<Item = f64>) {
        for r in residuals_px {
            if r.is_finite() && r >= 0.0 {
                self.residuals_px[self.next] = r;
                self.next = (self.next + 1) % WINDOW;
                self.filled = (self.filled + 1).min(WINDOW);
                self.taken = self.taken.saturating_add(1);
            }
        }
        self.sigma_px = self.window_sigma_px();
    }

    /// Residuals taken so far (saturating).
    pub fn fits(&self) -> u64 {
        self.taken
    }

    /// The mask noise, 1-sigma of a corner, pixels: the median residual of the latest fits
    /// over [`RMS_AT_ONE_PX`], within [`RANGE_PX`]; [`DEFAULT_PX`] before [`MIN_FITS`].
    pub fn sigma_px(&self) -> f64 {
        self.sigma_px
    }

    fn window_sigma_px(&self) -> f64 {
        let n = self.filled;
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
        n.take(std::iter::repeat_n(1.8, MIN_FITS - 1));
        assert_eq!(n.sigma_px(), DEFAULT_PX);
        n.take([1.8]);
        assert!((n.sigma_px() - 3.0).abs() < 1e-12, "{}", n.sigma_px());
    }

    #[test]
    fn the_median_of_the_latest_window_decides_and_outliers_do_not() {
        let mut n = MaskNoise::new();
        // An old, clean stretch is forgotten once a window of noisier fits follows.
        n.take(std::iter::repeat_n(0.6, WINDOW));
        assert!((n.sigma_px() - 1.0).abs() < 1e-12);
        // A tenth of the fits are wrong local solutions far off.
        n.take((0..WINDOW).map(|k| if k % 10 == 0 { 50.0 } else { 1.2 }));
        assert!((n.sigma_px() - 2.0).abs() < 1e-12, "{}", n.sigma_px());
        // And back: a camera whose masks got cleaner learns it within a window.
        n.take(std::iter::repeat_n(0.6, WINDOW / 2 + 1));
        assert!((n.sigma_px() - 1.0).abs() < 1e-12, "{}", n.sigma_px());
        assert_eq!(n.fits(), (2 * WINDOW + WINDOW / 2 + 1) as u64);
    }

    #[test]
    fn hostile_residuals_are_ignored_and_the_noise_stays_in_range() {
        let mut n = MaskNoise::new();
        n.take([f64::NAN, f64::INFINITY, f64::NEG_INFINITY, -1.0]);
        assert_eq!(n.fits(), 0);
        assert_eq!(n.sigma_px(), DEFAULT_PX);
        n.take(std::iter::repeat_n(0.0, MIN_FITS));
        assert_eq!(n.sigma_px(), RANGE_PX.0);
        n.take(std::iter::repeat_n(1e300, WINDOW));
        assert_eq!(n.sigma_px(), RANGE_PX.1);
    }
}
