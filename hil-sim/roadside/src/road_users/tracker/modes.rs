//! A person either stands or walks: two motion models run side by side and are weighed by
//! how well each predicts the person's boxes (an interacting multiple-model filter).
//!
//! A worker in a closed lane stands for seconds at a time, then walks. One
//! constant-velocity filter tuned for walking (turning at a lane's edge) takes a standing
//! worker's box noise for steps: far from the camera, where a pixel of the feet's row is
//! 15-20 cm along the line of sight, a run of boxes on one side moved a standing worker's
//! track 20-24 cm. The standing model holds the position still (it only drifts, as a
//! person shifting weight does) and averages every box; the walking model is the usual
//! constant velocity. Each frame the two are mixed by the chance of switching, predicted,
//! corrected by the box, and their weights follow the box's likelihood under each; the
//! track is their weighted mixture (mean and spread).

use super::kalman::{self, restart_position, M4};
use crate::ellipse::Cov2;

/// How far a standing person's footprint centre drifts, m/√s (shifting weight, turning):
/// 3 cm per second, a tenth of a slow step.
const STANDING_DRIFT_M_PER_SQRT_S: f64 = 0.03;
/// Mean time a person keeps standing or walking before switching, seconds. Long, so that
/// the weights gather evidence over many frames: far along the line of sight a box's error
/// is as large as a walker's step in a frame, and one frame barely tells the two apart.
/// On the road-user bench 10-20 s give the same tracks; 4 s gives walkers seen along the
/// line of sight some weight of standing (pedestrian means 0.2-0.4 cm higher on the low
/// camera).
const MEAN_SOJOURN_S: f64 = 20.0;
/// A person who starts walking from standing does so at a speed drawn from this 1-sigma per
/// component, m/s (a walk is 1-1.5 m/s): standing turns into walking with the velocity
/// unknown, not zero, so the walking model is ready to follow a worker who walks off.
const STARTING_SPEED_SIGMA_MPS: f64 = 1.0;
/// The standing model's weight stays within `[MIN_WEIGHT, 1 - MIN_WEIGHT]`, so that either
/// model can take over within a few frames.
const MIN_WEIGHT: f64 = 1.0e-3;

/// One motion model's state and covariance.
#[derive(Debug, Clone, PartialEq)]
struct Model {
    x: [f64; 4],
    p: M4,
}

/// A person's two motion models and the weight of standing.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Modes {
    standing: Model,
    walking: Model,
    /// The chance that the person stands, given the boxes so far.
    standing_weight: f64,
}

impl Modes {
    /// Both models at a newborn track's state `(x, p)`, walking taken as all but certain:
    /// standing has to earn its weight, since a young track's speed is not known yet and a
    /// standing model at half the weight holds a walker back (up to 30 cm on the bench's low
    /// camera). Standing has no velocity.
    pub(super) fn new(x: &[f64; 4], p: &M4) -> Self {
        let walking = Model { x: *x, p: *p };
        Self {
            standing: still(walking.clone()),
            walking,
            standing_weight: MIN_WEIGHT,
        }
    }

    /// The chance that the person stands.
    #[cfg(test)]
    pub(super) fn standing_weight(&self) -> f64 {
        self.standing_weight
    }

    /// Mixes the models by the chance of switching over `dt` seconds, then predicts each
    /// (walking with white acceleration of variance `walking_q`); the mixture.
    pub(super) fn predict(&mut self, dt: f64, walking_q: f64) -> ([f64; 4], M4) {
        if dt > 0.0 {
            let switch = (dt / MEAN_SOJOURN_S).min(0.5);
            let w = self.standing_weight;
            // The chance of standing after the step, and of each model before it given it.
            let standing_next = w * (1.0 - switch) + (1.0 - w) * switch;
            let from_standing_if_standing = w * (1.0 - switch) / standing_next;
            let from_standing_if_walking = w * switch / (1.0 - standing_next);
            let starting = starts_walking(self.standing.clone());
            let mut standing = still(mix(
                &self.standing,
                &self.walking,
                from_standing_if_standing,
            ));
            let mut walking = mix(&starting, &self.walking, from_standing_if_walking);
            let drift = STANDING_DRIFT_M_PER_SQRT_S * STANDING_DRIFT_M_PER_SQRT_S * dt;
            standing.p[0][0] += drift;
            standing.p[1][1] += drift;
            kalman::predict(&mut walking.x, &mut walking.p, dt, walking_q);
            (self.standing, self.walking) = (standing, walking);
            self.standing_weight = clamp_weight(standing_next);
        }
        self.mixture()
    }

    /// Corrects both models by a measured `position` with covariance `r` and weighs them by
    /// its likelihood under each; the mixture, `None` (nothing changed) when a model has no
    /// innovation.
    pub(super) fn correct(&mut self, position: [f64; 2], r: &Cov2) -> Option<([f64; 4], M4)> {
        let (mut standing, mut walking) = (self.standing.clone(), self.walking.clone());
        let s = kalman::update(&mut standing.x, &mut standing.p, position, r)?;
        let w = kalman::update(&mut walking.x, &mut walking.p, position, r)?;
        let (ls, lw) = (s.log_likelihood(), w.log_likelihood());
        let top = ls.max(lw);
        let (es, ew) = (
            self.standing_weight * (ls - top).exp(),
            (1.0 - self.standing_weight) * (lw - top).exp(),
        );
        let weight = es / (es + ew);
        if !weight.is_finite() {
            return None;
        }
        (self.standing, self.walking) = (still(standing), walking);
        self.standing_weight = clamp_weight(weight);
        Some(self.mixture())
    }

    /// Restarts each model's position at a measured `position` with covariance `r`, its
    /// velocity kept (a better view re-anchors the track, [`super::views`]).
    pub(super) fn restart_position(&mut self, position: [f64; 2], r: &Cov2) {
        for m in [&mut self.standing, &mut self.walking] {
            restart_position(&mut m.x, &mut m.p, position, r);
        }
    }

    /// The track's state: the two models mixed by their weights.
    pub(super) fn mixture(&self) -> ([f64; 4], M4) {
        let m = mix(&self.standing, &self.walking, self.standing_weight);
        (m.x, m.p)
    }

    /// The smallest squared Mahalanobis distance of a measured `position` with covariance
    /// `r` from either model's prediction: a box belongs to the track if either model
    /// expects it (a worker who walks off is far from where standing holds him, near where
    /// walking may take him).
    pub(super) fn nearest_d2(&self, position: [f64; 2], r: &Cov2) -> Option<f64> {
        [&self.standing, &self.walking]
            .iter()
            .filter_map(|m| kalman::innovation(&m.x, &m.p, position, r))
            .map(|i| i.d2)
            .min_by(f64::total_cmp)
    }
}

/// `a` and `b` mixed with `a`'s share `share`: mean and covariance with the spread of the
/// means.
fn mix(a: &Model, b: &Model, share: f64) -> Model {
    let share = if share.is_finite() {
        share.clamp(0.0, 1.0)
    } else {
        0.5
    };
    let parts = [(share, a), (1.0 - share, b)];
    let x: [f64; 4] = std::array::from_fn(|i| parts.iter().map(|(s, m)| s * m.x[i]).sum());
    let p: M4 = std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            parts
                .iter()
                .map(|(s, m)| s * (m.p[i][j] + (m.x[i] - x[i]) * (m.x[j] - x[j])))
                .sum()
        })
    });
    Model { x, p }
}

/// The standing model `m` as it turns into walking: at its position, its velocity unknown
/// ([`STARTING_SPEED_SIGMA_MPS`] in each direction).
fn starts_walking(mut m: Model) -> Model {
    let v = STARTING_SPEED_SIGMA_MPS * STARTING_SPEED_SIGMA_MPS;
    (m.p[2][2], m.p[3][3]) = (v, v);
    m
}

/// `m` standing still: no velocity, and no uncertainty in it.
fn still(mut m: Model) -> Model {
    m.x[2] = 0.0;
    m.x[3] = 0.0;
    for (i, row) in m.p.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            if i >= 2 || j >= 2 {
                *v = 0.0;
            }
        }
    }
    m
}

fn clamp_weight(w: f64) -> f64 {
    w.clamp(MIN_WEIGHT, 1.0 - MIN_WEIGHT)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Prng;

    /// A person's boxes known to 3 cm across the line of sight (x) and 15 cm along it (y),
    /// as far from a camera on a 12 m mast; the tracker's walking acceleration for people.
    const R: Cov2 = [[0.03 * 0.03, 0.0], [0.0, 0.15 * 0.15]];
    const WALKING_Q: f64 = 0.6 * 0.6;
    const DT: f64 = 0.1;

    /// A newborn person's state at `position`: velocity 0 with 3 m/s per component.
    fn newborn(position: [f64; 2]) -> ([f64; 4], M4) {
        let mut p = [[0.0; 4]; 4];
        (p[0][0], p[1][1], p[2][2], p[3][3]) = (R[0][0], R[1][1], 9.0, 9.0);
        ([position[0], position[1], 0.0, 0.0], p)
    }

    /// Runs both filters (the two models, and one constant-velocity filter) over `frames`
    /// frames of a person at `truth(t)`; per frame after the first second, each one's error
    /// along y (metres), and the two models at the end.
    fn run(truth: impl Fn(f64) -> [f64; 2], frames: usize, seed: u64) -> (Vec<[f64; 2]>, Modes) {
        let mut rng = Prng::new(seed);
        let box_at = |rng: &mut Prng, t: f64| {
            let [x, y] = truth(t);
            [x + 0.03 * rng.normal(), y + 0.15 * rng.normal()]
        };
        let first = box_at(&mut rng, 0.0);
        let (mut x, mut p) = newborn(first);
        let mut modes = Modes::new(&x, &p);
        let mut errors = Vec::new();
        for k in 1..frames {
            let t = k as f64 * DT;
            let b = box_at(&mut rng, t);
            modes.predict(DT, WALKING_Q);
            let (mx, _) = modes.correct(b, &R).expect("finite");
            kalman::predict(&mut x, &mut p, DT, WALKING_Q);
            kalman::update(&mut x, &mut p, b, &R).expect("finite");
            if t >= 1.0 {
                let y = truth(t)[1];
                errors.push([mx[1] - y, x[1] - y]);
            }
        }
        (errors, modes)
    }

    fn rms(errors: &[[f64; 2]], which: usize) -> f64 {
        (errors.iter().map(|e| e[which] * e[which]).sum::<f64>() / errors.len() as f64).sqrt()
    }

    #[test]
    fn a_standing_person_is_averaged_over_many_boxes() {
        let (errors, modes) = run(|_| [11.0, 40.0], 200, 3);
        let (both, walking) = (rms(&errors, 0), rms(&errors, 1));
        // The standing model's steady state: sqrt(drift² dt · 0.15²)^½ ≈ 3.8 cm; one
        // constant-velocity filter for walkers settles near 6.5 cm.
        assert!(both < 0.05, "{both} against {walking}");
        assert!(both < 0.75 * walking, "{both} against {walking}");
        assert!(modes.standing_weight() > 0.9, "{modes:?}");
    }

    #[test]
    fn a_walker_seen_along_the_line_of_sight_is_not_held_back() {
        // 1.2 m/s along y: 12 cm a frame, under one box's error along the line of sight.
        let (errors, modes) = run(|t| [11.0, 30.0 + 1.2 * t], 200, 5);
        let (both, walking) = (rms(&errors, 0), rms(&errors, 1));
        let lag = errors.iter().map(|e| e[0]).sum::<f64>() / errors.len() as f64;
        assert!(both < 1.1 * walking, "{both} against {walking}");
        assert!(lag.abs() < 0.02, "lag {lag}");
        assert!(modes.standing_weight() < 0.1, "{modes:?}");
    }

    #[test]
    fn a_worker_who_starts_walking_is_followed() {
        // Stands for 8 s, then walks at 1 m/s along y.
        let walk_from = 8.0;
        let truth = |t: f64| [11.0, 40.0 + (t - walk_from).max(0.0)];
        let (errors, modes) = run(truth, 140, 9);
        // Errors from 1 s on; the walk starts 70 frames in. From 1 s after it starts, the
        // track keeps up as one walking filter does.
        let walking_part = &errors[80..];
        let (both, walking) = (rms(walking_part, 0), rms(walking_part, 1));
        assert!(both < 1.25 * walking, "{both} against {walking}");
        assert!(modes.standing_weight() < 0.5, "{modes:?}");
    }

    #[test]
    fn non_finite_boxes_change_nothing() {
        let (x, p) = newborn([11.0, 40.0]);
        let mut modes = Modes::new(&x, &p);
        modes.predict(DT, WALKING_Q);
        let before = modes.clone();
        assert!(modes.correct([f64::NAN, 40.0], &R).is_none());
        let huge = [[f64::INFINITY, 0.0], [0.0, 1.0]];
        assert!(modes.correct([11.0, 40.0], &huge).is_none());
        assert_eq!(modes, before);
    }
}
