//! What is known of one road user's size: the class's prior, sharpened by what the frames
//! of its track measured.
//!
//! One frame's mask pins down only some combinations of length, width and height (a
//! vehicle seen end-on shows no length; a pedestrian walking along the line of sight trades
//! depth against height), and the class's prior decides the rest: its spread is the error
//! left in the position. A road user's size does not change between frames, while the view
//! does, so the track adds up each frame's information on the size ([`SizeEvidence`], in
//! information form, the position marginalised out) and the next frame's fit takes the
//! sum with the class's prior as its prior ([`SizeBelief`]). Older observations fade
//! ([`FADE_PER_FRAME`]), so that a wrong frame, or a size that changes with a pedestrian's
//! stride, is forgotten, and the belief never rests on more than a few tens of frames.
//!
//! Plain 3x3 arithmetic on `[length, width, height]`, metres.

// Matrix arithmetic reads as its formulas with indices.
#![allow(clippy::needless_range_loop)]

use super::class::{Extent, RoadUserClass};

/// A symmetric 3x3 matrix.
pub type M3 = [[f64; 3]; 3];

/// Share of the accumulated evidence kept from one observation with evidence to the next:
/// about 20 observations' worth at most (two seconds at 10 frames a second).
pub const FADE_PER_FRAME: f64 = 0.95;
/// Frames of evidence a track needs before its belief is used.
pub const MIN_FRAMES: u32 = 3;
/// A side is never believed known better than this (1-sigma, metres): the masks' own bias.
pub const MIN_SIGMA_M: f64 = 0.02;

/// One frame's information on a road user's size from its mask alone (no prior): the
/// information matrix `S` and vector `S s` of the size `s` the mask says.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SizeEvidence {
    /// Information matrix, 1/m².
    pub information: M3,
    /// Information vector, 1/m.
    pub vector: [f64; 3],
}

impl SizeEvidence {
    /// No information.
    pub const NONE: Self = Self {
        information: [[0.0; 3]; 3],
        vector: [0.0; 3],
    };

    /// Is every number finite?
    pub fn is_finite(&self) -> bool {
        self.vector.iter().all(|v| v.is_finite())
            && self.information.iter().flatten().all(|v| v.is_finite())
    }

    /// This evidence scaled by `k` (fewer effective frames, or a noisier mask).
    pub fn scaled(&self, k: f64) -> Self {
        Self {
            information: self.information.map(|r| r.map(|v| v * k)),
            vector: self.vector.map(|v| v * k),
        }
    }

    /// The sum of two pieces of evidence.
    pub fn plus(&self, o: &Self) -> Self {
        Self {
            information: std::array::from_fn(|i| {
                std::array::from_fn(|j| self.information[i][j] + o.information[i][j])
            }),
            vector: std::array::from_fn(|i| self.vector[i] + o.vector[i]),
        }
    }
}

/// A size belief: mean and information matrix of `[length, width, height]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SizeBelief {
    /// Mean, metres.
    pub mean: [f64; 3],
    /// Information matrix (inverse covariance), 1/m².
    pub information: M3,
}

impl SizeBelief {
    /// The class's prior ([`RoadUserClass::size_prior`]).
    pub fn prior(class: RoadUserClass) -> Self {
        let p = class.size_prior();
        let s = sides(p.sigma);
        let mut information = [[0.0; 3]; 3];
        for k in 0..3 {
            information[k][k] = 1.0 / (s[k] * s[k]);
        }
        Self {
            mean: sides(p.mean),
            information,
        }
    }

    /// The class's prior with the evidence added; `None` when the sum cannot be solved or
    /// its mean is not a size of the class (a side under 0.3 of the class's mean or over its
    /// largest): then the class's prior stands.
    pub fn with(class: RoadUserClass, evidence: &SizeEvidence) -> Option<Self> {
        let prior = Self::prior(class);
        let own = SizeEvidence {
            information: prior.information,
            vector: mat_vec(&prior.information, &prior.mean),
        }
        .plus(evidence);
        // The masks' bias is not averaged away: no side is believed better than MIN_SIGMA_M.
        let mut information = own.information;
        let cap = 1.0 / (MIN_SIGMA_M * MIN_SIGMA_M);
        for k in 0..3 {
            let d = information[k][k];
            if d > cap {
                let f = (cap / d).sqrt();
                for j in 0..3 {
                    information[k][j] *= f;
                    information[j][k] *= f;
                }
            }
        }
        let l = cholesky(&own.information)?;
        let mean = cholesky_solve(&l, &own.vector);
        let (typical, largest) = (sides(class.typical()), sides(class.largest()));
        let plausible = (0..3).all(|k| (0.3 * typical[k]..=largest[k]).contains(&mean[k]));
        plausible.then_some(Self { mean, information })
    }

    /// The mean as an extent.
    pub fn extent(&self) -> Extent {
        let [length_m, width_m, height_m] = self.mean;
        Extent {
            length_m,
            width_m,
            height_m,
        }
    }

    /// 1-sigma of each side (the covariance's diagonal), metres; infinite when the
    /// information matrix is singular.
    pub fn sigma(&self) -> [f64; 3] {
        let Some(l) = cholesky(&self.information) else {
            return [f64::INFINITY; 3];
        };
        std::array::from_fn(|k| {
            let mut e = [0.0; 3];
            e[k] = 1.0;
            cholesky_solve(&l, &e)[k].max(0.0).sqrt()
        })
    }

    /// `U` with `U'U` the information matrix (so `U (s - mean)` are the prior's residuals
    /// in sigmas); `None` when it is not positive definite.
    pub fn root(&self) -> Option<M3> {
        cholesky(&self.information)
            .map(|l| std::array::from_fn(|i| std::array::from_fn(|j| l[j][i])))
    }
}

/// A size belief lent to a detection, and who lends it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lent {
    /// Who lends it (a track's id): one lender's belief goes to one detection of a frame.
    pub lender: u32,
    /// The belief.
    pub belief: SizeBelief,
}

/// What a localizer is told of the road users' sizes: for a detection of a class near a
/// position (local metres), its track's size belief, if one track alone is there.
pub trait SizeHints {
    /// The belief of the one track of `class` near `position`, or `None`.
    fn near(&self, class: RoadUserClass, position: [f64; 2]) -> Option<Lent>;
}

/// No hints: every fit takes its class's prior.
#[derive(Debug, Clone, Copy, Default)]
pub struct ClassPriors;

impl SizeHints for ClassPriors {
    fn near(&self, _: RoadUserClass, _: [f64; 2]) -> Option<Lent> {
        None
    }
}

fn sides(e: Extent) -> [f64; 3] {
    [e.length_m, e.width_m, e.height_m]
}

/// `a x`.
pub fn mat_vec(a: &M3, x: &[f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| (0..3).map(|j| a[i][j] * x[j]).sum())
}

/// Lower-triangular `L` with `L L' = a`, or `None` when `a` is not positive definite.
pub fn cholesky(a: &M3) -> Option<M3> {
    let mut l = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..=i {
            let s: f64 = (0..j).map(|k| l[i][k] * l[j][k]).sum();
            if i == j {
                let d = a[i][i] - s;
                if !(d > 1e-12 && d.is_finite()) {
                    return None;
                }
                l[i][i] = d.sqrt();
            } else {
                l[i][j] = (a[i][j] - s) / l[j][j];
            }
        }
    }
    Some(l)
}

/// Solves `L L' x = b` for the factor of [`cholesky`].
pub fn cholesky_solve(l: &M3, b: &[f64; 3]) -> [f64; 3] {
    let mut y = [0.0; 3];
    for i in 0..3 {
        y[i] = (b[i] - (0..i).map(|k| l[i][k] * y[k]).sum::<f64>()) / l[i][i];
    }
    let mut x = [0.0; 3];
    for i in (0..3).rev() {
        x[i] = (y[i] - (i + 1..3).map(|k| l[k][i] * x[k]).sum::<f64>()) / l[i][i];
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_prior_alone_is_the_class_prior() {
        let b = SizeBelief::with(RoadUserClass::Car, &SizeEvidence::NONE).unwrap();
        let p = RoadUserClass::Car.size_prior();
        assert!((b.mean[0] - p.mean.length_m).abs() < 1e-12);
        assert!((b.sigma()[0] - p.sigma.length_m).abs() < 1e-12);
        assert!((b.sigma()[2] - p.sigma.height_m).abs() < 1e-12);
    }

    #[test]
    fn evidence_on_one_combination_moves_only_what_it_measures() {
        // Twenty frames that each measure length + height = 2.6 m (a pedestrian's depth
        // against height) within 5 cm: the sum is pinned, the difference stays the prior's.
        let row = [1.0, 0.0, 1.0];
        let w = 1.0 / (0.05 * 0.05);
        let one = SizeEvidence {
            information: std::array::from_fn(|i| std::array::from_fn(|j| w * row[i] * row[j])),
            vector: row.map(|r| w * r * 2.6),
        };
        let mut all = SizeEvidence::NONE;
        for _ in 0..20 {
            all = all.plus(&one);
        }
        let b = SizeBelief::with(RoadUserClass::Pedestrian, &all).unwrap();
        // Prior 0.45 + 1.72 = 2.17; the evidence says 2.6; equal prior sigmas split it.
        assert!((b.mean[0] + b.mean[2] - 2.6).abs() < 0.01, "{:?}", b.mean);
        assert!(
            (b.mean[2] - b.mean[0] - (1.72 - 0.45)).abs() < 1e-9,
            "{:?}",
            b.mean
        );
        assert!((b.mean[1] - 0.45).abs() < 1e-12);
    }

    #[test]
    fn cholesky_solves_and_refuses_what_is_not_positive() {
        let a = [[4.0, 2.0, 0.6], [2.0, 5.0, 1.0], [0.6, 1.0, 3.0]];
        let l = cholesky(&a).unwrap();
        let x = cholesky_solve(&l, &[1.0, 2.0, 3.0]);
        let back = mat_vec(&a, &x);
        for (v, b) in back.iter().zip([1.0, 2.0, 3.0]) {
            assert!((v - b).abs() < 1e-12);
        }
        assert!(cholesky(&[[1.0, 2.0, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 1.0]]).is_none());
        assert!(cholesky(&[[f64::NAN, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]).is_none());
    }
}
