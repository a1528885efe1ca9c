//! Datagram loss: the [`LossModel`] (independent or Gilbert-Elliott bursts) and the
//! per-destination [`LossChannel`] state.

use super::config::ConfigError;
use crate::rng::Prng;

/// How datagrams get lost.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum LossModel {
    /// Nothing is lost.
    #[default]
    None,
    /// Each datagram is lost with probability `rate`, independently.
    Independent {
        /// Loss probability, 0-1.
        rate: f64,
    },
    /// Gilbert-Elliott: a two-state Markov channel. Each datagram is lost with the
    /// probability of the current state, then the state changes with the transition
    /// probability. [`LossModel::bursts`] gives the simple form (the good state loses
    /// nothing, the bad state everything).
    GilbertElliott {
        /// Probability of going from good to bad after a datagram.
        to_bad: f64,
        /// Probability of going from bad to good after a datagram (1 / mean burst length).
        to_good: f64,
        /// Loss probability in the good state.
        loss_good: f64,
        /// Loss probability in the bad state.
        loss_bad: f64,
    },
}

impl LossModel {
    /// Independent loss with probability `rate`.
    ///
    /// # Errors
    ///
    /// [`ConfigError::Probability`] when `rate` is not within 0-1.
    pub fn independent(rate: f64) -> Result<Self, ConfigError> {
        let model = Self::Independent { rate };
        model.validate().map(|()| model)
    }

    /// Bursty loss: on average a fraction `rate` of datagrams lost, in bursts of
    /// `mean_burst_len` datagrams on average (a Gilbert-Elliott channel whose bad state
    /// loses everything and good state nothing: `to_good = 1 / mean_burst_len`,
    /// `to_bad = rate * to_good / (1 - rate)`).
    ///
    /// # Errors
    ///
    /// When `rate` is not within 0-1 (1 excluded), `mean_burst_len` is below 1, or the
    /// bursts are too short for the rate (`mean_burst_len < rate / (1 - rate)`).
    pub fn bursts(rate: f64, mean_burst_len: f64) -> Result<Self, ConfigError> {
        if !(0.0..1.0).contains(&rate) {
            return Err(ConfigError::Probability {
                what: "burst loss rate (below 1)",
                value: rate,
            });
        }
        if mean_burst_len.is_nan() || mean_burst_len < 1.0 {
            return Err(ConfigError::BurstLength {
                value: mean_burst_len,
            });
        }
        let to_good = 1.0 / mean_burst_len;
        let to_bad = rate * to_good / (1.0 - rate);
        if to_bad > 1.0 {
            return Err(ConfigError::BurstsTooShort {
                rate,
                mean_burst_len,
            });
        }
        Ok(Self::GilbertElliott {
            to_bad,
            to_good,
            loss_good: 0.0,
            loss_bad: 1.0,
        })
    }

    /// Checks that every probability is within 0-1.
    ///
    /// # Errors
    ///
    /// [`ConfigError::Probability`] naming the first that is not.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let checks: &[(&'static str, f64)] = match *self {
            Self::None => &[],
            Self::Independent { rate } => &[("loss rate", rate)],
            Self::GilbertElliott {
                to_bad,
                to_good,
                loss_good,
                loss_bad,
            } => &[
                ("to_bad", to_bad),
                ("to_good", to_good),
                ("loss_good", loss_good),
                ("loss_bad", loss_bad),
            ],
        };
        probabilities(checks)
    }

    /// The long-run fraction of datagrams lost.
    pub fn mean_loss_rate(&self) -> f64 {
        match *self {
            Self::None => 0.0,
            Self::Independent { rate } => rate,
            Self::GilbertElliott {
                loss_good,
                loss_bad,
                ..
            } => {
                let bad = self.stationary_bad();
                bad * loss_bad + (1.0 - bad) * loss_good
            }
        }
    }

    /// Long-run probability of the bad state (0 for the other models).
    fn stationary_bad(&self) -> f64 {
        match *self {
            Self::GilbertElliott {
                to_bad, to_good, ..
            } if to_bad + to_good > 0.0 => to_bad / (to_bad + to_good),
            _ => 0.0,
        }
    }
}

/// Checks `(name, value)` pairs to be probabilities.
pub(super) fn probabilities(checks: &[(&'static str, f64)]) -> Result<(), ConfigError> {
    match checks.iter().find(|(_, v)| !(0.0..=1.0).contains(v)) {
        Some(&(what, value)) => Err(ConfigError::Probability { what, value }),
        None => Ok(()),
    }
}

/// The loss state of one path (one destination).
#[derive(Clone, Debug, PartialEq)]
pub struct LossChannel {
    model: LossModel,
    bad: bool,
}

impl LossChannel {
    /// A channel of `model`, its state drawn from the long-run distribution.
    pub fn new(model: LossModel, rng: &mut Prng) -> Self {
        let bad = rng.chance(model.stationary_bad());
        Self { model, bad }
    }

    /// Whether the next datagram is lost (and the state moves on).
    pub fn drops(&mut self, rng: &mut Prng) -> bool {
        match self.model {
            LossModel::None => false,
            LossModel::Independent { rate } => rng.chance(rate),
            LossModel::GilbertElliott {
                to_bad,
                to_good,
                loss_good,
                loss_bad,
            } => {
                let lost = rng.chance(if self.bad { loss_bad } else { loss_good });
                let flip = rng.chance(if self.bad { to_good } else { to_bad });
                self.bad ^= flip;
                lost
            }
        }
    }

    /// Whether the channel is in its bad (burst) state.
    pub fn in_burst(&self) -> bool {
        self.bad
    }
}
